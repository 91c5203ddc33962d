// cellfx — a campfire: animated noise on a hexahedral grid, shaped by a tapering flame envelope.
//
// Based on: Roettger & Ertl 2003, §3 and Figure 2 ("a campfire generated with 3D Perlin noise",
// 16×16×16 nodes; "hexahedra with zero emission were discarded"), with time as a fourth noise
// axis (fx::Noise simplex4) so the flames change shape as they rise.
//
// The scalar "temperature" T ∈ [0, 1] at a grid node (x, y, z) — local frame, z up from the
// centre of the fire's base, metres — at time t:
//     r(z)  = base_radius · (1 − z/height)^taper             flame radius, tapering to the tip
//     E     = max(0, 1 − (ρ/r(z))²) · (1 − z/height)         envelope: ρ = √(x² + y²); 0 above the tip
//     n     = fBm of simplex4 at (x, y, (z − rise_speed·t) / noise_stretch,
//             flicker_rate·t / noise_frequency) (noise_octaves, noise_frequency, seed) ∈ [−1, 1]
//     T     = clamp(intensity · E · (1 + turbulence · n), 0, 1)
// The noise field rises through the envelope at rise_speed (rising flicker), its features
// noise_stretch times taller than wide (tongues), while its 4th axis advances at flicker_rate
// lattice cells per second (the shapes boil). Where turbulence·n < −1 the flame has gaps. Map T with a fire
// transfer function (content/transfer_functions/fire.json); scalar_range() is [0, 1].
//
// Cost: the grid's cells whose eight nodes all have E = 0 are never built (the envelope does not
// move), so the mesh is built once per parameter set. update() re-samples the noise — once per
// node with E > 0 (active_nodes()), one fill_points4 batch — only when the time has advanced
// since the last sample; otherwise it does nothing. counters().noise_samples counts them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/parametric_effect.hpp"

namespace cellfx::fx {

struct CampfireParams {
    glm::dvec3 position{0.0};     // centre of the base in the parent's frame (world units, m)
    double base_radius = 0.45;    // m, flame radius at the base; > 0
    double height = 1.4;          // m, tip above the base; > 0
    double taper = 0.7;           // 0: a column, 1: a cone, > 1: a spike; ≥ 0
    int cells_across = 16;        // hexahedra along x and along y (2..256)
    int cells_up = 20;            // hexahedra along z (1..256)
    double intensity = 1.4;       // envelope gain; > 1 saturates the core at T = 1; ≥ 0
    double turbulence = 4.0;      // how strongly the noise breaks the envelope up; ≥ 0
    double noise_frequency = 3.0; // cycles per metre of the first octave (across); > 0
    double noise_stretch = 2.5;   // vertical elongation of the noise features; > 0
    int noise_octaves = 3;        // 1..8
    double rise_speed = 1.1;      // m/s the flicker rises; finite
    double flicker_rate = 0.9;    // noise cells per second along the time axis; finite
    std::uint32_t seed = 1;
};

// The most cells these parameters build (cells_across² · cells_up; cells outside the flame
// are never built), known before anything is built: what the effect-cells budget checks.
std::uint64_t max_cells(const CampfireParams& params);

class Campfire final : public ParametricEffect {
public:
    // Throws fx::Error naming the parameter that is out of range.
    explicit Campfire(const CampfireParams& params = {});

    static constexpr const char* kTypeName = "campfire"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    bool animated() const override { return params_.rise_speed != 0.0 || params_.flicker_rate != 0.0; }
    ScalarRange scalar_range() const override { return {0.0f, 1.0f}; }

    const CampfireParams& params() const { return params_; }
    // Changes the parameters; the next update() rebuilds the mesh if the shape or grid changed,
    // re-samples the scalars if the flame's look changed, and only moves it for a new position
    // (each parameter's cost: fx/effect_parameters.hpp). Throws like the constructor (and keeps
    // the old ones).
    void set_params(const CampfireParams& params);

    // Grid nodes inside the envelope (E > 0): the noise samples one update costs.
    std::size_t active_nodes() const { return active_.size(); }
    // sampled_time(): the time of the scalars in mesh() (NaN before the first update).

    // The temperature formula at one point and time, without the grid (for tests and tools).
    double temperature_at(const glm::dvec3& local, double time) const;

    // Its glow: a point light at 35% of its height, core radius base_radius, reaching 6 × height.
    MediumLight medium_light() const override;

private:
    Bounds local_bounds() const override;
    glm::dmat4 pose_at(double time) const override;
    // Time is one of the noise's axes only when the fire moves; a still fire samples once.
    bool scalars_follow_time() const override { return animated(); }

    void build_mesh() override;
    void evaluate_scalars(double time) override;

    CampfireParams params_;
    std::vector<std::uint32_t> active_;   // mesh points with E > 0
    std::vector<double> envelope_;        // E at those points
    std::vector<glm::dvec4> noise_points_; // scratch: noise coordinates
    std::vector<float> noise_values_;      // scratch
};

} // namespace cellfx::fx
