// cellfx — a laser cone: a narrow, bright beam, optionally made visible in places by dust.
//
// Based on: Roettger & Ertl 2003, Figure 2 ("a laser cone"), built like the search light
// (search_light.hpp: wedges around the axis, hexahedra in outer rings, planar faces) but thin,
// long and without the quadratic fade: the scalar "intensity" at a node is
//     I = intensity · (1 − (ρ/R(z))²) · fade(z) · dust(p, t)
//     R(z)    = radius + z·tan(divergence)
//     fade(z) = min(1, (1 − z/range) / end_fade)      (end_fade = 0: no fade, a hard end)
//     dust    = 1 − dust_amount + dust_amount · min(1, 2·turbulence(p − dust_drift·t))
// with turbulence the fx::Noise turbulence fractal (dust_octaves, dust_frequency, seed) ∈ [0, 1]
// at the node's local position p. scalar_range() is [0, intensity].
//
// Costs: the mesh is built once per shape; position, direction and the parent transform only
// move it (no rebuild, see effect.hpp). Dust is sampled at every node when the mesh is built and
// again only when its time matters (dust_amount > 0 and a non-zero drift) and has advanced; a
// laser without dust, or with still dust, samples no noise after its first update. The dust
// lives in the beam's frame, so it moves with the beam.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/parametric_effect.hpp"

namespace cellfx::fx {

struct LaserConeParams {
    glm::dvec3 position{0.0};            // emitter, parent frame (m)
    glm::dvec3 direction{1.0, 0.0, 0.0}; // beam axis, parent frame (any length > 0)
    double range = 150.0;                // m; > 0
    double radius = 0.04;                // m at the emitter; > 0
    double divergence_degrees = 0.12;    // half-angle, [0, 10]
    double intensity = 1.0;              // scalar on the axis; ≥ 0
    double end_fade = 0.15;              // fraction of the range over which it fades out, [0, 1]
    int segments = 8;                    // cells around the axis, 3..64
    int slices = 96;                     // cells along the beam, 1..4096
    double dust_amount = 0.0;            // 0: a clean beam, 1: visible only in the dust; [0, 1]
    double dust_frequency = 0.6;         // cycles per metre; > 0
    int dust_octaves = 2;                // 1..8
    glm::dvec3 dust_drift{0.0};          // m/s in the beam's frame (z along the beam)
    std::uint32_t seed = 1;
};

// The cells these parameters build (segments · slices), known before building: what the
// effect-cells budget checks.
std::uint64_t max_cells(const LaserConeParams& params);

class LaserCone final : public ParametricEffect {
public:
    // Throws fx::Error naming the parameter that is out of range.
    explicit LaserCone(const LaserConeParams& params = {});

    static constexpr const char* kTypeName = "laser_cone"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    bool animated() const override { return dusty() && params_.dust_drift != glm::dvec3(0.0); }
    ScalarRange scalar_range() const override { return {0.0f, float(params_.intensity)}; }

    const LaserConeParams& params() const { return params_; }
    // Changes the parameters: range, radius, divergence or resolution rebuild the mesh; the
    // others re-evaluate the scalars; position and direction cost nothing (each parameter's
    // cost: fx/effect_parameters.hpp). Throws like the constructor and keeps the old ones.
    void set_params(const LaserConeParams& params);
    void set_pose(const glm::dvec3& position, const glm::dvec3& direction);

    // Its beam, like a search light's (fx/search_light.hpp).
    MediumLight medium_light() const override;

private:
    bool dusty() const { return params_.dust_amount > 0.0; }
    Bounds local_bounds() const override;
    glm::dmat4 pose_at(double time) const override;
    bool scalars_follow_time() const override { return animated(); }

    void build_mesh() override;
    void evaluate_scalars(double time) override;

    LaserConeParams params_;
    std::vector<double> along_, across_;
    std::vector<glm::dvec3> dust_points_;
    std::vector<float> dust_;
};

} // namespace cellfx::fx
