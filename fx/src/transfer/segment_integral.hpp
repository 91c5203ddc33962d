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

#include <algorithm>
#include <cmath>
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

// A scalar's place in a transfer function, looked up once per ray crossing and read by the two
// segments that share the crossing (the scan-line renderer's pixel walk), so that a segment
// does not search the transfer function's points again: s, the value there (c, σ) and the
// interval a segment leaving s downwards (`down`) or upwards (`up`) starts in. Interval j lies
// between points j−1 and j (0 and n are the held ends). Inside an interval down == up; on a
// point i, down = i and up = i + 1, the value is the point's; on a step (several points at s)
// the value depends on the side a segment comes from: down = up = kOnStep.
struct TransferSample {
    static constexpr std::size_t kOnStep = ~std::size_t(0);
    double s = 0.0;
    glm::dvec3 c{0.0};
    double sigma = 0.0;
    std::size_t down = kOnStep, up = kOnStep;
};

// `hint`: an interval to try first (a neighbouring crossing's), or kOnStep. Inline: it runs
// once per crossing.
inline TransferSample transfer_sample(const TransferFunction& tf, double s, std::size_t hint = TransferSample::kOnStep) {
    TransferSample out;
    out.s = s;
    const TransferPoint* p = tf.points().data();
    const std::size_t n = tf.points().size();
    if (n == 0) return out;
    std::size_t j = hint;
    if (!(hint <= n && (hint == 0 || p[hint - 1].s < s) && (hint == n || s < p[hint].s))) {
        // upper_bound: past every point at s, as emission_absorption() searches upwards.
        j = static_cast<std::size_t>(
            std::upper_bound(p, p + n, s, [](double v, const TransferPoint& q) { return v < q.s; }) - p);
        if (j > 0 && p[j - 1].s == s) { // on point j − 1
            if (j > 1 && p[j - 2].s == s) return out; // a step
            out.down = j - 1;
            out.up = j;
            out.c = p[j - 1].color;
            out.sigma = p[j - 1].sigma;
            return out;
        }
    }
    out.down = out.up = j;
    if (j == 0 || j == n) { // the held ends
        out.c = p[j == 0 ? 0 : n - 1].color;
        out.sigma = p[j == 0 ? 0 : n - 1].sigma;
        return out;
    }
    // on_interval() in segment_integral.cpp, the same expressions (s is never p[j].s here).
    const TransferPoint& a = p[j - 1];
    const TransferPoint& b = p[j];
    const double t = (s - a.s) / (b.s - a.s);
    out.c = a.color + t * (b.color - a.color);
    out.sigma = a.sigma + t * (b.sigma - a.sigma);
    return out;
}

namespace detail {
// Power series below this optical depth per piece (segment_integral.cpp).
constexpr double kSeriesMax = 0.5;
// The weights of a piece's front and back colours (segment_integral.cpp's file comment) for
// optical thickness rates a, b ≥ 0 with a + b > 0.
struct PieceWeights {
    double w0, w1;
};
PieceWeights piece_weights(double a, double b);
// piece_weights() of two pieces, bit for bit, faster than two calls (two series side by side).
void piece_weights_2(const double a[2], const double b[2], PieceWeights out[2]);

// A segment of one piece: front colour c0 and optical thickness rate a = l·σ₀, back c1 and b,
// a + b > 0, with its weights w = piece_weights(a, b).
inline SegmentColor one_piece_with(double a, double b, const glm::dvec3& c0, const glm::dvec3& c1,
                                   const PieceWeights& w) {
    SegmentColor out;
    out.optical_depth = 0.5 * a + 0.5 * b;
    out.color = w.w0 * c0 + w.w1 * c1;
    // The weights sum to 1 − e^{−τ}. Where the series gives them (τ ≤ kSeriesMax, a and b not
    // clamped) they carry no significant cancellation, so their sum is alpha to a few ulp
    // (tested against expm1) and costs no exponential; elsewhere 1 − J and J − e^{−τ} may have
    // cancelled and expm1 gives alpha.
    out.alpha = out.optical_depth <= kSeriesMax ? w.w0 + w.w1 : -std::expm1(-out.optical_depth);
    return out;
}

// The same for any a, b ≥ 0. Inline, as the functions below: the scan-line renderer
// integrates one segment per crossing.
inline SegmentColor one_piece(double a, double b, const glm::dvec3& c0, const glm::dvec3& c1) {
    const double depth = 0.5 * a + 0.5 * b;
    if (!(depth > 0.0)) {
        SegmentColor out;
        out.optical_depth = depth;
        out.alpha = -std::expm1(-depth);
        return out;
    }
    return one_piece_with(a, b, c0, c1, piece_weights(a, b));
}
} // namespace detail

// Whether emission_absorption(tf, front, back, length) below is one piece with optical depth
// > 0, i.e. one_piece_with(a, b, front.c, back.c, piece_weights(a, b)); then a = l·σ_front and
// b = l·σ_back. A caller with many segments can so compute their weights two at a time
// (piece_weights_2).
//
// Why the samples' values are emission_absorption(tf, front.s, back.s, length)'s: for s_front ==
// s_back (a region of constant field, often on a point of the transfer function: the field's end
// values are its first and last points) value_at() gives the sample's value: inside an interval
// by the same expression, on a point i by interval i + 1 at t = 0, i.e. the point's value (but
// for the sign of a zero written as −0). Otherwise the interval emission_absorption() finds for
// s_front is front.up going up and front.down going down; the segment is one piece when s_back
// lies in it, ends included, i.e. back.down (up) or back.up (down) is that interval.
// on_interval() then gives at either end the value the sample holds: inside the interval by the
// same expression, at an end point that point's value (exactly: s == b.s, or t = 0).
inline bool one_piece_rates(const TransferSample& front, const TransferSample& back, double length, double& a,
                            double& b) {
    if (front.s == back.s || !(length > 0.0)) return false;
    const bool up = front.s < back.s;
    const std::size_t j = up ? front.up : front.down;
    if (j == TransferSample::kOnStep || (up ? back.down : back.up) != j) return false;
    a = length * front.sigma;
    b = length * back.sigma;
    return 0.5 * a + 0.5 * b > 0.0;
}

// emission_absorption(tf, front.s, back.s, length), bit for bit, from the ends' samples: a
// segment inside one interval (nearly every segment of a fine mesh, ends on a point included)
// reads the values the samples hold; any other goes through the function above.
inline SegmentColor emission_absorption(const TransferFunction& tf, const TransferSample& front,
                                        const TransferSample& back, double length) {
    double a, b;
    if (one_piece_rates(front, back, length, a, b))
        return detail::one_piece_with(a, b, front.c, back.c, detail::piece_weights(a, b));
    SegmentColor out;
    if (front.s == back.s && front.down != TransferSample::kOnStep) {
        if (!(length > 0.0)) return out;
        out.optical_depth = length * front.sigma;
        out.alpha = -std::expm1(-out.optical_depth);
        out.color = front.c * out.alpha;
        return out;
    }
    const bool up = front.s < back.s;
    const std::size_t j = up ? front.up : front.down;
    if (j == TransferSample::kOnStep || (up ? back.down : back.up) != j)
        return emission_absorption(tf, front.s, back.s, length);
    if (!(length > 0.0)) return out;
    return detail::one_piece(length * front.sigma, length * back.sigma, front.c, back.c); // τ = 0
}

// Front-to-back "over": `front` in front of `back`. Uses the alphas (colour and alpha add with
// weight 1 − front.alpha); optical depths add. Inline: the scan-line renderer composites once
// per segment.
inline SegmentColor composite(const SegmentColor& front, const SegmentColor& back) {
    const double through = 1.0 - front.alpha;
    SegmentColor out;
    out.color = front.color + through * back.color;
    out.alpha = front.alpha + through * back.alpha; // no 1 − (1−α)(1−β): exact for tiny alphas
    out.optical_depth = front.optical_depth + back.optical_depth;
    return out;
}

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
