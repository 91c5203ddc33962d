// cellfx — volumetric effects: a designer's parameters in, a cell mesh with per-vertex scalars out.
//
// An Effect builds an fx::CellMesh with one per-point scalar field (scalar_name()) in its own
// local frame, and places it in the world with a rigid transform (transform(): rotation and
// translation, no scale). Effects are CPU-only (no GL): render one with
//     fx::CellRenderer renderer(effect.mesh(), effect.scalar_name(), tf);
//     renderer.render(fx::camera_in_frame(camera, effect.transform()), viewport, path);
// — the camera is moved into the effect's frame instead of the mesh into the world, so moving an
// effect uploads nothing (a rigid motion leaves lengths, and so every integral, unchanged; the
// view-space depth of every point is the same, so a scene depth buffer still applies).
//
// Per frame the owner (terrain::SceneRenderer does this for scenes) asks, in this order:
//   world_bounds(time)  cheap, from the parameters and the pose alone — no mesh is built — for
//                       the frustum test (bounds_in_view); an effect outside the view is not
//                       updated at all, so it costs no cells and no noise samples;
//   update(view)        brings mesh() up to date for the view and the scene time, doing only
//                       what changed, and reports it (EffectChanges): the mesh was rebuilt
//                       (new points or cells: CellRenderer::set_mesh), only its scalars were
//                       re-evaluated (same cells: CellRenderer::set_scalars), or only its pose
//                       moved (nothing to upload). A static effect returns no change after its
//                       first update; an animated one re-evaluates only when its time advanced.
// counters() accumulate over the effect's life (builds, scalar updates, cells built, noise
// samples): the evidence that work was, or was not, done.
//
// Ownership: an Effect owns its mesh and scratch; mesh() stays valid until the next update()
// or parameter change. Not thread-safe: one caller at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/medium.hpp"

namespace cellfx::fx {

// What a frame asks of an effect.
struct EffectView {
    Camera camera;           // world space
    int viewport_width = 1;  // pixels: the frustum's aspect, level-of-detail effects' resolution
    int viewport_height = 1;
    double time = 0.0;       // seconds on the scene's clock (animated effects sample it)
};

// What update() changed since the previous update().
struct EffectChanges {
    bool mesh = false;    // points or cells are new: upload them (Effect::mesh_changes says which)
    bool scalars = false; // same points and cells, new scalar values
    bool pose = false;    // transform() changed: nothing to upload, the camera moves instead
    bool any() const { return mesh || scalars || pose; }
};

// Cumulative work of one effect (never reset).
struct EffectCounters {
    std::uint64_t updates = 0;        // update() calls
    std::uint64_t mesh_builds = 0;    // meshes built (points, cells and scalars)
    std::uint64_t scalar_updates = 0; // scalars re-evaluated on an unchanged mesh
    std::uint64_t cells_built = 0;    // cells of the meshes built, summed over builds
    std::uint64_t noise_samples = 0;  // noise values evaluated by this effect
};

class Effect {
public:
    virtual ~Effect() = default;
    Effect(const Effect&) = delete;
    Effect& operator=(const Effect&) = delete;

    // "campfire", "search_light", "laser_cone", "ground_fog", "aurora" (the scene file's type).
    // Each concrete effect also has it as `static constexpr const char* kTypeName`: the type tag
    // by which cellfx::Module::effect<E>() finds an effect's type without RTTI.
    virtual const char* type_name() const = 0;
    // True if time alone changes the mesh, its scalars or its pose.
    virtual bool animated() const { return false; }
    // The range of scalars the effect's parameters can produce: normalized transfer functions
    // are mapped onto it once, so colours do not shift as the frame's scalars vary.
    virtual ScalarRange scalar_range() const = 0;
    const std::string& scalar_name() const { return scalar_name_; }

    // The light the effect sheds on the absorbing media around it (fx/medium.hpp), in its local
    // frame with colour 1 and phase g 0 — a search light's or laser's beam (its cells, its
    // falloff scalar), a campfire's glow (a point light); Kind::None for the others.
    virtual MediumLight medium_light() const { return {}; }

    // Brings mesh() up to date for `view` (see the header comment). Throws fx::Error for a
    // non-finite time or camera, or parameters the effect cannot build.
    EffectChanges update(const EffectView& view);
    const CellMesh& mesh() const { return mesh_; }
    // Which points and cells of mesh() changed since the last clear_mesh_changes() (whole for
    // effects that rebuild their mesh whole; the terrain's fog and aurora follow their LOD and
    // list only what it changed): what CellRenderer::update_mesh takes. The uploader clears it.
    const MeshChanges& mesh_changes() const { return mesh_changes_; }
    void clear_mesh_changes() { mesh_changes_.clear(); }
    const EffectCounters& counters() const { return counters_; }

    // Placement: world_from_local = rigid(parent · pose(time)). The parent is the object the
    // effect is attached to (identity until set), given again whenever that object moves; the
    // pose is the effect's own placement in the parent's frame (position, direction, animation).
    // A parent with scale moves the effect's origin accordingly but does not resize it (sizes
    // are the parameters', in world units). Throws fx::Error for a matrix that is not finite,
    // is singular, mirrors, or has a projective row.
    void set_parent_transform(const glm::dmat4& parent);
    const glm::dmat4& parent_transform() const { return parent_; }
    glm::dmat4 transform_at(double time) const;
    // The transform mesh() is drawn with: transform_at(time of the last update()).
    const glm::dmat4& transform() const { return transform_; }
    // World-space bounds at `time` (the box of the transformed local bounds); empty when the
    // effect would draw nothing.
    Bounds world_bounds(double time) const;

protected:
    explicit Effect(std::string scalar_name);
    // The subclass's part of update(): rebuild or re-evaluate what the view and time require;
    // report mesh/scalars changes (pose is tracked here). May assume a finite view.
    virtual EffectChanges simulate(const EffectView& view) = 0;
    // Bounds of everything the mesh can occupy, local frame, from the parameters alone.
    virtual Bounds local_bounds() const = 0;
    // The pose in the parent's frame at `time` (rigid). Identity unless overridden.
    virtual glm::dmat4 pose_at(double time) const;

    // For subclasses: record a build or a scalar update in the counters. A build of part of the
    // mesh counts the cells it built.
    void count_build() { ++counters_.mesh_builds, counters_.cells_built += mesh_.cell_count(); }
    void count_partial_build(std::size_t cells) { ++counters_.mesh_builds, counters_.cells_built += cells; }
    void count_scalar_update() { ++counters_.scalar_updates; }
    void count_noise(std::size_t samples) { counters_.noise_samples += samples; }

    CellMesh mesh_;
    // What changed in mesh_ since it was last taken: a subclass that rebuilds only part of its
    // mesh lists the points and cells here; update() marks it whole after any other mesh change.
    MeshChanges mesh_changes_;
    bool lists_mesh_changes_ = false; // set by such a subclass

private:
    std::string scalar_name_;
    EffectCounters counters_;
    glm::dmat4 parent_{1.0};
    glm::dmat4 transform_{1.0};
    bool placed_ = false; // transform_ set by a first update()
};

// The rigid part of a transform: its translation and the orthonormalised (Gram–Schmidt, x first)
// rotation of its linear part. Throws fx::Error (naming `what`) for a matrix that is not
// finite, has a zero or dependent column, mirrors (negative determinant), or has a bottom row
// other than (0, 0, 0, 1). Allocates nothing unless it throws.
glm::dmat4 rigid_part(const glm::dmat4& m, std::string_view what);

// A rigid transform placing local +z along `direction` at `position` (x and y chosen from a
// fixed reference so that they change continuously except where direction crosses ±z). Throws
// fx::Error for a zero or non-finite direction or position.
glm::dmat4 frame_along(const glm::dvec3& position, const glm::dvec3& direction);

// The camera seen from a local frame: the same picture of a mesh given in that frame as
// `camera` gives of the mesh moved by `world_from_local` (rigid: rotation and translation).
Camera camera_in_frame(const Camera& camera, const glm::dmat4& world_from_local);

// The view volume of `camera` with this aspect (width / height) as six half-spaces (GL's
// clip-space inequalities −w ≤ x ≤ w, ... carried back through the view-projection), in world
// coordinates relative to the eye: a box 2 units across 1e17 from the world's origin is
// tested as precisely as one at the origin.
struct Frustum {
    glm::dvec3 origin{0.0}; // the camera's eye
    glm::dvec4 planes[6];   // (n, d): n·(p − origin) + d ≥ 0 inside
    Frustum(const Camera& camera, double aspect);
    // False when the box lies entirely outside one of the planes; true otherwise (conservative:
    // a box beside a frustum corner may pass). False for empty bounds.
    bool intersects(const Bounds& box) const;
};

// Frustum(camera, aspect).intersects(bounds).
bool bounds_in_view(const Bounds& bounds, const Camera& camera, double aspect);

// For an effect's parameter checks: a position or length cellfx can render (finite, every
// component within ±kMaxCoordinate, cell_mesh.hpp).
bool renderable_coordinates(const glm::dvec3& v);
bool renderable_length(double length); // finite, > 0 and at most kMaxCoordinate
// Throws fx::Error("<what> needs N cells, over the effect-cells limit ...") when an effect's
// parameters could build more cells than the resource budget allows (resource_limits.hpp).
void check_effect_cells(std::uint64_t cells, const std::string& what);

// The box of `bounds` moved by `m` (its 8 corners transformed).
Bounds transform_bounds(const Bounds& bounds, const glm::dmat4& m);

} // namespace cellfx::fx
