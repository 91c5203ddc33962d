// cellfx — a search light: a cone of prisms with quadratic falloff along the beam and across it,
// attachable to a moving object.
//
// Based on: Roettger & Ertl 2003, Figure 2 and Table 4 ("a search light with quadratic intensity
// attenuation", 16×4×32 nodes, rendered by PCP).
//
// The beam runs along local +z from a lens of radius lens_radius; its radius grows as
// R(z) = lens_radius + z·tan(spread). The mesh: `slices` slabs along the beam, each cut into
// wedges around the axis and hexahedra in rings − 1 outer rings of `segments` cells (all convex:
// every side face lies in a plane through the cone's apex). The scalar "intensity" at a node:
//     I(z, ρ) = intensity · (1 − z/range)² · (1 − (ρ/R(z))²)
// quadratic along the beam (full at the lens, 0 at the range) and across it (full on the axis,
// 0 at the rim); scalar_range() is [0, intensity].
//
// Moving it is cheap: the mesh is built in the beam's own frame once per shape, and
// position, direction, sweep and the parent transform only change transform() — update()
// then reports a pose change and uploads nothing (see effect.hpp). Changing `intensity`
// re-evaluates the scalars only; changing range, spread, lens_radius or the resolution rebuilds.
//
//     fx::SearchLightParams beam;
//     beam.position = {0, 0, 3};       // on the truck's roof, in the truck's frame
//     beam.direction = {1, 0, 0.2};    // ahead, a little up
//     fx::SearchLight light(beam);
//     every frame: light.set_parent_transform(truck.world_matrix()); // the light rides on it
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "fx/parametric_effect.hpp"

namespace cellfx::fx {

// A periodic swing of the beam: direction rotated about `axis` (parent frame) by
// amplitude·sin(2π·t/period + phase).
struct SweepMotion {
    glm::dvec3 axis{0.0, 0.0, 1.0};
    double amplitude_degrees = 0.0; // 0: no sweep; in [0, 180]
    double period = 8.0;            // seconds; > 0
    double phase_degrees = 0.0;
};

struct SearchLightParams {
    glm::dvec3 position{0.0};            // lens centre, parent frame (m)
    glm::dvec3 direction{0.0, 0.0, 1.0}; // beam axis, parent frame (any length > 0)
    double range = 60.0;                 // m, where the beam has faded to 0; > 0
    double spread_degrees = 6.0;         // half-angle of the cone, [0, 60]
    double lens_radius = 0.35;           // m; > 0
    double intensity = 1.0;              // scalar on the axis at the lens; ≥ 0
    int segments = 16;                   // cells around the axis, 3..256
    int rings = 4;                       // cells from the axis to the rim, 1..64
    int slices = 32;                     // cells along the beam, 1..1024
    SweepMotion sweep;
};

// The cells these parameters build (segments · rings · slices), known before building:
// what the effect-cells budget checks.
std::uint64_t max_cells(const SearchLightParams& params);

class SearchLight final : public ParametricEffect {
public:
    // Throws fx::Error naming the parameter that is out of range.
    explicit SearchLight(const SearchLightParams& params = {});

    static constexpr const char* kTypeName = "search_light"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    bool animated() const override { return params_.sweep.amplitude_degrees != 0.0; }
    ScalarRange scalar_range() const override { return {0.0f, float(params_.intensity)}; }

    const SearchLightParams& params() const { return params_; }
    // Changes the parameters (see the header comment, and fx/effect_parameters.hpp, for what
    // each change costs). Throws like the constructor and keeps the old ones.
    void set_params(const SearchLightParams& params);
    // Moves the lens and turns the beam in the parent's frame: costs no rebuild.
    void set_pose(const glm::dvec3& position, const glm::dvec3& direction);

    // The beam axis in the parent's frame at `time` (the sweep applied), unit length.
    glm::dvec3 direction_at(double time) const;

    // Its beam: light where its cells are, strength intensity/params().intensity, the rays
    // diverging from the cone's apex behind the lens.
    MediumLight medium_light() const override;

private:
    Bounds local_bounds() const override;
    glm::dmat4 pose_at(double time) const override;

    void build_mesh() override;
    void evaluate_scalars(double time) override; // the sweep moves the pose, never the scalars

    SearchLightParams params_;
    std::vector<double> along_, across_; // per point, from the cone builder
};

} // namespace cellfx::fx
