// cellfx — exact integrals of a transfer function along one ray segment.
//
// Based on: Williams & Max 1992 (volume density optical model) and Max, Williams & Silva
// 2000 §II. A segment of length `length` (world units) has scalar s_front at the end nearer
// the eye and s_back at the far end, linear in between. The segment is split where s crosses
// a breakpoint of the transfer function; on each piece colour and sigma are linear along the
// ray, and the integrals below are evaluated in closed form (no quadrature).
//
// These functions are the one source of truth: the CPU scan-line reference calls them per
// pixel, and the GPU paths' lookup tables are built from them. Private to cellfx (not
// installed): a user reaches them through fx::ScanlineRenderer and fx::Medium.
//
// Conventions shared by all of them: s_front > s_back is fine (the ray runs down the scalar);
// a breakpoint step is crossed with the value on the side the ray comes from; scalars outside
// the control points see the held end values; with s_front == s_back the value at s is the one
// from above (TransferFunction::color/sigma). length <= 0 (or NaN) is an empty segment.
// Scalars must be finite. No allocation; safe to call from many threads at once.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp> // PreintegrationTable::rgba

#include "fx/segment_color.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {

// Emission only: ∫₀ˡ c(s(t))·σ(s(t)) dt. Exact for l → 0 (→ 0) and s_front == s_back.
glm::dvec3 emission_integral(const TransferFunction& tf, double s_front, double s_back, double length);

// Maximum intensity: the per-channel maximum of the emission c(s)·σ(s) over the scalar
// interval between s_front and s_back (breakpoints inside it included: both sides of a step
// inside the interval count; at an end of the interval, only the side inside it).
glm::dvec3 segment_maximum(const TransferFunction& tf, double s_front, double s_back);

// Emission–absorption (volume density model), front to back:
//   colour = ∫₀ˡ c(t)σ(t)·exp(−∫₀ᵗ σ) dt   (premultiplied),   alpha = 1 − exp(−τ),   τ = ∫₀ˡ σ.
// Stable for huge extinction (exp underflow → alpha 1, colour finite), tiny extinction
// (1 − e^(−x) without cancellation) and l → 0.
// SegmentColor: fx/segment_color.hpp.
SegmentColor emission_absorption(const TransferFunction& tf, double s_front, double s_back, double length);

// Front-to-back "over": `front` in front of `back`. Uses the alphas (colour and alpha add with
// weight 1 − front.alpha); optical depths add.
SegmentColor composite(const SegmentColor& front, const SegmentColor& back);

// ∫ from the first control point's s to s of c(u)·σ(u) du (per unit scalar). The emission of
// a segment is then length·(E(s_b) − E(s_f))/(s_b − s_f), which is what a GPU emission table
// stores. Below the first point E is negative and linear (held end value); above the last it
// grows linearly with the last emission.
glm::dvec3 cumulative_emission(const TransferFunction& tf, double s);

// Lookup tables for the GPU paths (no GL here; the render paths upload them).
// Both tables cover the control points' range [first s, last s] (a unit range centred on the
// point when all share one s), sample i at s_lo + i·(s_hi − s_lo)/(count − 1). They throw
// fx::Error for fewer than 2 samples along any axis, a non-positive or non-finite max_length,
// or a transfer function without points.
struct EmissionTable {
    double s_lo = 0.0, s_hi = 1.0;      // table covers [s_lo, s_hi] in `size` samples
    std::vector<glm::vec3> cumulative;  // E(s) at each sample
};
EmissionTable build_emission_table(const TransferFunction& tf, std::size_t size);

// The GPU paths' emission tables as texels (shaders/project.glsl, medium_resolve.frag): row 0
// (texels [0, size)) the cumulative emission E(s) (rgb) and extinction ∫σ ds (a) from
// build_emission_table, row 1 (texels [size, 2·size)) the point values c·σ (rgb) and σ (a) at
// the same samples. `texels` is resized to 2·size; the table's range is returned in s_lo, s_hi.
void build_emission_rows(const TransferFunction& tf, std::size_t size, std::vector<glm::vec4>& texels, double& s_lo,
                         double& s_hi);

// Throws fx::Error, naming the scalar range, where the GPU paths' float sums over tf's
// emission tables would overflow (E or T over the range, or a point's c·σ times the samples):
// refused rather than drawn as Inf. build_emission_rows calls it; so must any other builder.
void require_float_emission_tables(const TransferFunction& tf, const EmissionTable& emission,
                                   const EmissionTable& extinction);

// Pre-integration table over (s_front, s_back, length), for the exact absorption path: entry
// [(il * n_s + ib) * n_s + if] describes emission_absorption(s_f, s_b, l) with s_f, s_b on n_s
// samples of [s_lo, s_hi] and l on n_l samples of [0, max_length] as
//   a   = the segment's mean extinction σ̄ = τ / l (the same for every l),
//   rgb = M = σ̄·colour / alpha: at l = 0 its limit, the mean emission ∫c·σ ds / Δs; for a
//         thin medium (τ → 0) M stays that mean, for a dense one colour / alpha tends to the
//         front's colour.
// A reader interpolates these and forms τ = σ̄·l, alpha = 1 − e^−τ, colour = M·alpha / σ̄
// (= M·l for τ → 0). τ is linear in l, so its interpolation along l is exact and a short
// segment through dense matter stays as opaque as it is: colour and alpha themselves rise
// within the first length sample when σ is large, and interpolating them linearly there
// would lose it. M ≤ (largest colour)·σ̄ at every sample, so the interpolated colour / alpha
// stays a colour of the transfer function's.
struct PreintegrationTable {
    double s_lo = 0.0, s_hi = 1.0, max_length = 1.0;
    std::size_t n_s = 0, n_l = 0;
    std::vector<glm::vec4> entries; // M, σ̄
};
PreintegrationTable build_preintegration_table(const TransferFunction& tf, std::size_t n_s, std::size_t n_l,
                                               double max_length);

} // namespace cellfx::fx
