// cellfx — a generic volume: a box, a sphere or any cell mesh filled with a density that is
// constant, animated noise, or the mesh's own field. Smoke, dust, mist in a doorway, a glowing
// cloud — the fog volumes game engines offer, as cells like every other effect.
//
// The scalar "density" d at a mesh point p (local frame) at time t:
//     constant  d = density · edge(p)
//     noise     d = density · clamp(coverage + contrast · n, 0, 1) · edge(p)
//               n = fBm of simplex4 at (p − drift·t, evolve·t / frequency) (octaves, frequency,
//               seed) ∈ [−1, 1] — the field moves with the wind and boils as time passes
//     field     d = density · f(p), f the mesh's own point field
//     edge(p)   1, or with edge_fade > 0 a linear fall to 0 over that fraction of the half extent
//               (box: distance to the nearest face; sphere: to the surface) — a soft rim
// A transfer function maps d to colour and extinction (emission = colour·σ): colour 0 makes an
// absorbing-only volume (smoke), a scene's "absorb": false an emissive-only one (glow).
// scalar_range() is [0, density] ([min(0, density·f_lo), density·f_hi] for a field), so a
// normalized transfer function maps the volume's full density onto its last point.
//
// Shapes, local frame (placed by position and rotation, rigid):
//     box     size = full extents, centred on the origin: a grid of hexahedra, `cells` across its
//             largest extent (a single hexahedron for constant density without an edge fade)
//     sphere  radius around the origin: an icosphere (the polyhedron inscribed in the sphere)
//             cut into shells — tetrahedra around the centre, wedges outside them; every face
//             is planar, every cell convex
//     mesh    a cell mesh (any format fx::read_mesh reads) in its own coordinates; its cells
//             are oriented positively (fx::orient_cells) once
//
// Cost: the mesh is built once per shape. A constant or field volume never changes after that
// (moving it is a pose: nothing uploaded); a noise volume re-samples once per point, in one
// fill_points4 batch, only when its time advanced and it drifts or evolves.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/parametric_effect.hpp"

namespace cellfx::fx {

enum class VolumeShape { Box, Sphere, Mesh };
enum class VolumeDensity { Constant, Noise, Field };
const char* volume_shape_name(VolumeShape shape);     // "box", "sphere", "mesh"
const char* volume_density_name(VolumeDensity density); // "constant", "noise", "field"

struct VolumeNoise {
    double frequency = 0.5; // cycles per metre of the first octave; > 0
    int octaves = 4;        // 1..8
    double coverage = 0.5;  // density where the noise is 0, as a fraction of `density`; [0, 1]
    double contrast = 0.8;  // how far the noise moves it; ≥ 0
    glm::dvec3 drift{0.0};  // m/s in the volume's frame: the field moves with the wind
    double evolve = 0.0;    // noise cells per second along the time axis: the shapes change
    std::uint32_t seed = 1;
};

struct VolumeParams {
    VolumeShape shape = VolumeShape::Box;
    glm::dvec3 position{0.0};          // parent frame: centre of the box or sphere, origin of a mesh
    glm::dvec3 rotation_degrees{0.0};  // about x, then y, then z (parent frame)
    glm::dvec3 size{1.0, 1.0, 1.0};    // box: full extents (m); each > 0
    double radius = 0.5;               // sphere (m); > 0
    std::shared_ptr<const CellMesh> mesh; // shape mesh: its cells and points (local frame)
    std::string field;                 // shape mesh: the point field (density "field"); "" = the first
    int cells = 0;                     // box and sphere: cells across the largest extent, 0 = automatic
                                       // (1 for a constant box, 16 otherwise); 1..256
    VolumeDensity density_mode = VolumeDensity::Constant;
    double density = 1.0;              // ≥ 0, see the header comment
    double edge_fade = 0.0;            // box and sphere; [0, 1]
    VolumeNoise noise;
};

// The cells these parameters build, known before building: what the effect-cells budget checks.
std::uint64_t max_cells(const VolumeParams& params);

class Volume final : public ParametricEffect {
public:
    // Throws fx::Error naming the parameter that is wrong (a mesh without cells, a field it
    // lacks, a density "field" on a box, ...).
    explicit Volume(const VolumeParams& params = {});

    static constexpr const char* kTypeName = "volume"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    bool animated() const override;
    ScalarRange scalar_range() const override;

    const VolumeParams& params() const { return params_; }
    // Changes the parameters: the shape, its size or resolution rebuild the mesh; the density
    // re-evaluates the scalars; position and rotation only move it (each parameter's cost:
    // fx/effect_parameters.hpp; a new shape, mesh or field rebuilds, a new density mode
    // re-evaluates). Throws like the constructor and keeps the old ones.
    void set_params(const VolumeParams& params);

    // The density formula at one local point and time, without the mesh (tests and tools; not
    // for the field density, which lives on the mesh's points).
    double density_at(const glm::dvec3& local, double time) const;

private:
    Bounds local_bounds() const override;
    glm::dmat4 pose_at(double time) const override;
    bool scalars_follow_time() const override { return animated(); }

    void build_mesh() override;
    void evaluate_scalars(double time) override;

    VolumeParams params_;
    ScalarRange field_range_;      // shape mesh: the field's range
    std::vector<float> field_;     // shape mesh: the field at its points
    std::vector<glm::dvec4> noise_points_; // scratch
    std::vector<float> noise_values_;      // scratch
};

} // namespace cellfx::fx
