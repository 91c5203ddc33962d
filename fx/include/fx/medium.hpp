// cellfx — one medium per scene: how volumes that overlap along a ray are integrated together,
// and how lights scatter in them. CPU only (no GL); the GPU compositor
// (medium_compositor.hpp) and the scan-line reference (ScanlineOptions::media) both follow
// the model written here.
//
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (intersecting grids: a ray's crossings of
// all grids sorted in depth, integrated between consecutive ones) and Max 1995 (single
// scattering in the volume density model).
//
// Every volume is a medium along the ray: its transfer function gives colour c(s) and extinction
// σ(s); it emits c·σ per unit length, and — if it absorbs — attenuates by σ. Where volumes
// overlap, their media mix: on a span [a, b] between consecutive boundaries of any volume,
//     τ = Σ_absorbing τ_v,    E = Σ_all E_v + scattered light S,
//     colour = E·(1 − e^(−τ))/τ (E where τ = 0),  alpha = 1 − e^(−τ)
// with E_v = ∫ c_v σ_v, τ_v = ∫ σ_v over the span, composited front to back. This is exact
// when the span's mixture has one colour (any σ profile), and wherever one volume alone has
// constant colour; otherwise spans are cut into pieces of optical depth ≤ kMaxPieceDepth, so the
// error falls with the square of the piece depth.
//
// Scattering (single, no shadowing between the light and the point): an absorbing medium with
// albedo ρ lit by a light L scatters, per unit length, ρ·σ(s)·L(x)·4π·p(cos θ) towards the eye,
// p the Henyey–Greenstein phase function of the light's g (4π·p = 1 for isotropic scattering),
// θ between the light's direction at x and the direction back to the eye. L: a beam (search light, laser) is the light inside its
// own cells with the strength of its falloff scalar; a point light (a fire's glow) is
// strength·r0²/(r0² + r²)·(1 − r²/R²)² within radius R. What is approximate: no attenuation
// between the light and the scattering point (the eye side is exact); the light is not dimmed
// by the volume that carries it.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/segment_color.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {

// Spans are cut into pieces of at most this optical depth (see the header comment).
constexpr double kMaxPieceDepth = 0.25;

// Henyey–Greenstein phase function: (1 − g²) / (4π (1 + g² − 2g·mu)^(3/2)), mu = cos θ, g in
// (−1, 1): 0 isotropic (1/4π), > 0 forward (bright looking into the light).
double henyey_greenstein(double g, double mu);
// The phase relative to isotropic scattering, 4π·henyey_greenstein: 1 for g = 0. Lights scatter
// with it, so a light of colour c lights a unit optical depth of an albedo-1 medium to c·p_rel.
double relative_phase(double g, double mu);

// A light that scatters in the absorbing media it crosses, world frame.
struct MediumLight {
    enum class Kind { None, Beam, Point };
    Kind kind = Kind::None;
    glm::dvec3 color{1.0};      // scattered radiance per unit optical depth at full strength, isotropic
    double phase_g = 0.0;       // Henyey–Greenstein g, (−1, 1)
    glm::dvec3 origin{0.0};     // beam: the lens centre; point: the light's position
    glm::dvec3 axis{0.0, 0.0, 1.0}; // beam: unit direction of travel
    double apex_distance = 0.0; // beam: the rays diverge from origin − axis·apex_distance
                                // (0: parallel to axis)
    double strength_per_scalar = 1.0; // beam: strength = the volume's scalar × this
    double core_radius = 0.5;   // point: r0
    double radius = 10.0;       // point: R, nothing beyond
    // The light's unit direction of travel at x (beam).
    glm::dvec3 direction_at(const glm::dvec3& x) const;
    // A point light's strength at distance² r2 (1 at the light).
    double point_falloff(double r2) const;
};

// How one volume takes part in the medium.
struct MediumVolume {
    TransferFunction tf;   // in the volume's scalar units (not normalized)
    bool absorbs = true;   // false: emission only (adds light, dims nothing)
    double albedo = 0.0;   // absorbing volumes: fraction of the extinction that scatters light
    MediumLight light;     // Beam lights live in this volume's cells; Point lights act everywhere
};

// One volume's part of a span: its scalar at the span's two ends (linear in between).
struct SpanVolume {
    std::size_t volume;
    double s_front, s_back;
};

// A span of a ray: origin + t·dir for t in [t_front, t_back] (dir unit, world frame).
struct RaySpan {
    glm::dvec3 origin{0.0}, dir{0.0, 0.0, 1.0};
    double t_front = 0.0, t_back = 0.0;
};

// The media of a scene's volumes, ready to integrate spans. Immutable once made; integrate_span
// may be called from several threads at once.
class Medium {
public:
    // Throws fx::Error for a volume whose transfer function has no points or is normalized (the
    // medium works in each volume's own scalar units).
    explicit Medium(std::vector<MediumVolume> volumes);
    const std::vector<MediumVolume>& volumes() const { return volumes_; }

    // The colour (premultiplied), alpha and optical depth of a span through the volumes in
    // `inside` (header comment), scattering included: beams of the volumes inside the span,
    // point lights of every volume. This is the reference: a span that is not one volume alone
    // (exact: emission_absorption) is cut into pieces of optical depth ≤ kReferencePieceDepth,
    // and scattering is integrated with adaptive Simpson quadrature to a relative 1e-6. The GPU
    // compositor evaluates the same model more coarsely (docs/effects.md gives the differences).
    SegmentColor integrate_span(const SpanVolume* inside, std::size_t count, const RaySpan& span) const;
    static constexpr double kReferencePieceDepth = 0.02;

private:
    std::vector<MediumVolume> volumes_;
    std::vector<TransferFunction> extinction_; // per volume: colour 1, so emission_integral is ∫σ
    std::vector<std::size_t> point_lights_;    // volumes with a point light
};

// How the GPU integrates volumes that overlap on screen (docs/effects.md, "One medium").
//   Froxel  a grid of screen tiles × exponential depth slices (Wronski 2014): each absorbing
//           volume's exact per-cell segment integrals are added into the slices its cells
//           cross, point lights lit once per froxel, integrated front to back per tile and
//           read per pixel at its scene depth; emission-only volumes (fire, beams) drawn per
//           pixel, dimmed by the grid in front of them. Cost and memory bounded by the grid
//           (≤ 160 × 90 tiles × 64 slices, 27.6 MB), whatever the volumes' depth complexity.
//   Exact   per-pixel lists of ray segments, sorted and integrated exactly (the reference
//           grade: the scan-line reference's model to 1e-4 of peak); cost and memory grow with
//           the segments the region's rays cross (MediumCompositor).
enum class MediumMethod { Froxel, Exact };
const char* medium_method_name(MediumMethod method); // "froxel", "exact"
bool parse_medium_method(std::string_view name, MediumMethod& method); // false for anything else

// What the GPU compositor did in a frame (terrain::FrameStats::medium).
struct MediumStats {
    MediumMethod method = MediumMethod::Exact;
    std::size_t pixels = 0;         // in the region (froxel: the whole view)
    std::size_t segments = 0;       // exact: appended this frame
    std::size_t capacity = 0;       // exact: of the segment pool (segments)
    std::size_t redraws = 0;        // exact: appends repeated after the pool overflowed
    std::size_t volumes = 0;        // appended (exact) or injected and drawn against the grid (froxel)
    std::size_t froxels = 0;        // froxel: tiles across × tiles up × slices
    std::size_t gpu_bytes = 0;      // the method's GPU memory (pool and tables, or grid)
    double cpu_ms = 0.0;            // of the method's calls together
    double gpu_ms = -1.0;           // GL_TIME_ELAPSED of its passes (with timing)
    // exact: appends and resolve; froxel: injection, and lighting + integration + apply
    double append_gpu_ms = -1.0, resolve_gpu_ms = -1.0;
};

} // namespace cellfx::fx
