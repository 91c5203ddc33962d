// cellfx terrain — fog maps and the prisms stacked on a LOD mesh (Roettger & Ertl 2003, §5).
//
// A fog map is a second height field: the fog layer's thickness above the ground (a
// HeightField on the ground's grid, ≥ 0). Every LOD triangle becomes a vertical prism — an
// fx::CellType::Wedge whose three vertical edges run from the (geomorphed) ground up by the
// (geomorphed) thickness at its corners — and the prisms form an fx::CellMesh with one
// per-point scalar field for the render paths (fx::CellRenderer: pcp, pcp-exact with fog, mip;
// fx::ScanlineRenderer as the reference). Only prisms with non-zero thickness are emitted.
// Adjacent prisms share their points, so shared side faces are one face to every renderer.
//
// Wedge vertex order is VTK's with positive orientation (cell_mesh.hpp): vertices 0, 1, 2 the
// bottom triangle (wound so that face faces down), 3, 4, 5 above them. Side faces are planar
// (two vertical edges), so the cells are convex; validate_mesh() passes.
//
// Density per point (the scalar, named options.scalar_name):
//   LayerHeight   0 at the ground, scale·thickness at the top: the paper's MIP set-up (§5),
//                 denser where the layer is deeper;
//   Noise         scale·max(noise(x, y), 0) at both ends: 2-D noise, constant up a column;
//   LowerBorder   scale at the bottom, falling linearly to 0 at fade_height above it (aurora:
//                 brightest where the particles stop). Linear in height, like LayerHeight, so a
//                 side face's density does not depend on how its quad is cut into triangles.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/effect.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/height_field.hpp"
#include "terrain/layer_prism_options.hpp"
#include "terrain/terrain_lod.hpp"

namespace cellfx::terrain {

struct LayerPrismStats {
    std::size_t triangles = 0;   // LOD triangles looked at
    std::size_t prisms = 0;      // wedges emitted
    std::size_t empty = 0;       // triangles with no thickness (no prism)
    std::size_t culled = 0;      // triangles whose prism lies outside the view (not built)
    std::size_t points = 0;
};

// Builds the prism mesh over `mesh` (ContinuousLod::extract of a LOD built with a layer).
// A triangle gets a prism when its corners' thicknesses sum to more than 1e-6 of its longest
// edge (thinner ones are flat to every renderer and to validate_mesh). Throws fx::Error for
// LayerDensity::Noise without a generator or a non-finite density.
fx::CellMesh build_layer_prisms(const LodMesh& mesh, const LayerPrismOptions& options = {},
                                LayerPrismStats* stats = nullptr);

// The same, frame after frame without allocating: builds into `out` reusing its storage and the
// builder's scratch (no allocation once both have grown to the meshes' size). With `view`, only
// the prisms whose box meets that view volume are built (a conservative test: everything the
// camera sees is there; LayerPrismStats::culled counts the others).
class LayerPrismBuilder {
public:
    void build(const LodMesh& mesh, const LayerPrismOptions& options, fx::CellMesh& out, LayerPrismStats* stats = nullptr,
               const fx::Frustum* view = nullptr);

private:
    std::vector<std::uint32_t> bottom_; // LOD vertex → its bottom point in `out`
};

// The prisms of a TerrainLod followed as it refines: built from its fans once, then after each
// refinement only the fans it rebuilt (by node: LodChanges::fan_nodes) and the vertices it moved are
// written again, into the same mesh — prisms of a rebuilt fan replaced, a removed prism's place
// taken by the last one, a moved vertex's two points rewritten — and listed in an
// fx::MeshChanges for fx::CellRenderer::update_mesh. A LOD version it did not follow (skipped
// frames, a rebuild from the root) is built whole.
//
// Which prisms: build_layer_prisms' (a triangle whose corners' thicknesses sum to more than a
// millionth of its longest edge), decided when its fan is built; a fan is built again when a
// vertex of it gains or loses its thickness (ContinuousLod lists it), so the mesh holds the
// prisms build_layer_prisms would make of the extracted LOD — up to triangles thinner than a
// millionth of the field's size throughout, whose edges alone changed — with the same points, in
// another order. Points come in pairs (bottom, top) per LOD vertex that carries a prism, reused
// when freed; the mesh may hold unused pairs.
//
// Not view-culled: every prism of the LOD is in the mesh (CellRenderer::set_culling draws those in
// view). Ownership: owns its bookkeeping (a few bytes per sample of the field, kept between
// frames: a steady refinement allocates nothing).
class LayerPrismTracker {
public:
    // Brings `out` up to date with `lod` (built with a layer) and adds what changed to `changes`
    // (which the caller clears once it has used them). Returns true if `out` changed. Throws
    // like build_layer_prisms.
    bool update(const TerrainLod& lod, const LayerPrismOptions& options, fx::CellMesh& out, fx::MeshChanges& changes,
                LayerPrismStats* stats = nullptr);
    // Forgets what it built: the next update() builds whole.
    void reset() { built_ = nullptr; }

private:
    void build_whole(const ContinuousLod& lod, const LayerPrismOptions& options, fx::CellMesh& out, fx::MeshChanges& changes);
    // The pair's points: the bottom at `p`, the top `t` above it.
    void set_points(const LayerPrismOptions& options, std::uint32_t pair, const glm::dvec3& p, double t, fx::CellMesh& out,
                    fx::MeshChanges& changes);
    std::uint32_t acquire_pair(const ContinuousLod& lod, const LayerPrismOptions& options, std::uint32_t sample,
                               fx::CellMesh& out, fx::MeshChanges& changes);
    void release_pair(std::uint32_t sample);
    void add_fan(const ContinuousLod& lod, const LayerPrismOptions& options, const LodFan& fan, fx::CellMesh& out,
                 fx::MeshChanges& changes);
    void remove_fan(std::uint32_t node, fx::CellMesh& out, fx::MeshChanges& changes);
    void cell_changed(std::uint32_t cell, fx::MeshChanges& changes);

    const TerrainLod* built_ = nullptr; // the LOD and version `out` holds
    std::uint64_t version_ = 0;
    std::vector<std::uint32_t> sample_pair_;  // per sample: its point pair, or none
    std::vector<std::uint32_t> pair_sample_, pair_refs_, free_pairs_;
    // The prisms of a fan, by its node: node → group of up to 8 cells (groups reused when freed).
    struct Group {
        std::array<std::uint32_t, 8> cells{};
        std::uint32_t count = 0;
    };
    std::vector<std::uint32_t> node_group_;   // per sample: its fan's group, or none
    std::vector<Group> groups_;
    std::vector<std::uint32_t> free_groups_;
    std::vector<std::uint32_t> cell_owner_;   // per cell: group · 8 + its place in the group
    std::vector<std::uint32_t> cell_listed_;  // per cell: the update that last listed it
    std::vector<std::uint32_t> pair_listed_;  // per pair: the same for its points
    std::uint32_t update_count_ = 0;
};

// A valley fog map: the fog fills the ground up to `level` (+ `modulation(x, y)` when given,
// e.g. 2-D noise), thickness = clamp(level + modulation − ground, 0, max_thickness). With
// `radius` > 0 the level is relative to the ground averaged over a square of ±radius world
// units (a box filter), so fog collects in every hollow — crater floors, valley bottoms — at
// its own height. Throws fx::Error for non-finite parameters, a negative max_thickness or radius.
HeightField make_valley_fog_map(const HeightField& ground, double level, double max_thickness,
                                const HeightGenerator& modulation = {}, double radius = 0.0);

} // namespace cellfx::terrain
