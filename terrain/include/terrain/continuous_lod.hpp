// cellfx terrain — continuous level of detail for a height field, with geomorphing.
//
// Based on: Röttger, Heidrich, Slusallek & Seidel 1998, "Real-Time Generation of Continuous
// Levels of Detail for Height Fields" (quadtree refinement, d2 roughness, triangle fans,
// geomorphing), used by Roettger & Ertl 2003 §5 for ground fog. Details in docs/terrain.md.
//
// The field's (2^n + 1)² samples form a quadtree of square nodes; a node of size d (world
// units) is centred on a sample and is split when
//     f = l / (d · C · max(c · d2, 1)) < 1,
// l the distance from the eye to the node's centre, C the minimum resolution, d2 the node's
// roughness (largest height error of its edge midpoints and centre, divided by d, over the
// ground and — when a layer is given — the layer's top surface, so fog drives refinement where
// its surface varies), and c = k / (τ·C) from the screen-space error bound τ in pixels
// (k = viewport height / (2 tan(fov/2)), so a split happens where the node's height error would
// show as more than τ pixels). d2 is propagated bottom-up: every node's d2 is at least
// K = C / (2(C − 1)) times that of each finer node it borders, so f grows towards the root.
// Neighbouring leaves then differ by at most one level; the refinement guarantees it exactly by
// using f_eff(N) = max(f(N), f_eff of N's parent and of the parent's neighbours N touches),
// which equals f wherever the K bound holds (LodStats::constrained counts where it did not).
// Each leaf is a triangle fan around its centre through its corners and those edge midpoints
// whose same-size neighbour is split: no cracks, no T-junctions.
//
// Geomorphing: a vertex introduced by splitting node N sits at
//     (1 − b)·(average of the two vertices it bisects) + b·(its true height),
// b = clamp(2(1 − f_eff(N)), 0, 1) (an edge midpoint takes the larger b of its two nodes);
// at b = 0 the split changes nothing on screen, so refining never pops. The layer thickness is
// blended the same way.
//
// Per-frame cost follows what changes: f_eff(N) can change by at most |Δeye| / T_N per unit of
// eye travel (T_N = d·C·max(c·d2, 1), the smallest along its constraint chain thanks to the
// K propagation), so each node is re-examined only after the eye has travelled far enough for it
// to cross a threshold (1: split/merge, ½: morphing starts); nodes that are morphing are updated
// every frame. Changing the error bound, the view's scale or (through the triangle budget) c
// rebuilds from the root, which costs the size of the output.
//
// Ownership: ContinuousLod owns copies of its fields and all LOD state (52 bytes per
// sample). Not thread-safe; one update() at a time.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "terrain/height_field.hpp"
#include "terrain/lod_settings.hpp"

namespace cellfx::terrain {

// What one update() changed, for consumers that follow the mesh as it changes (fog prisms, the
// surface's buffers) instead of extracting it whole. Fans live in slots 0 .. fan_count() − 1;
// a slot listed in `fans` holds a fan it did not hold before the update (rebuilt, new, or
// another fan moved into it), and slots from fan_count() up to fans_before are gone. The same
// changes by the fan's node (its centre sample) in `fan_nodes`: nodes whose fan is new, rebuilt
// differently or gone (fan_of() says which) — a fan that only moved to another slot is not
// among them. Vertices are samples (j·size + i) whose morphed height or thickness changed, with
// their new height and thickness (vertex_position().z and vertex_thickness()) side by side: a
// consumer reads them in order instead of looking each vertex up again.
struct LodChanges {
    bool full = true; // rebuilt from the root (or before the first update): take everything anew
    std::size_t fans_before = 0;
    std::vector<std::uint32_t> fans;
    std::vector<std::uint32_t> fan_nodes;
    std::vector<std::uint32_t> vertices;
    std::vector<float> vertex_heights, vertex_thicknesses;
};

// One leaf's triangle fan: its centre sample and its ring (corners and the edge midpoints its
// finer neighbours need), counter-clockwise from above; triangle k is (centre, ring[k],
// ring[(k + 1) % count]), as extract() makes it.
struct LodFan {
    std::uint32_t center = 0;
    std::uint32_t count = 0;
    std::uint32_t ring[8] = {};
};

// What refinement depends on each frame.
struct LodView {
    glm::dvec3 eye{0.0};
    // Pixels per world unit at unit distance: viewport height / (2·tan(fov_y / 2)).
    double projection_scale = 1000.0;
    // Screen-space error bound τ: a node is split when its height error would cover more than
    // this many pixels. > 0.
    double pixel_error = 2.0;
    // At most this many triangles (0: no limit). When the bound gives more, c is lowered until
    // it fits (a rebuild per adjustment); below half the budget it is raised again towards the
    // bound. The C term alone sets a floor (LodStats::over_budget then says so).
    std::size_t triangle_budget = 0;

    // From a camera and the viewport height in pixels. An orthographic camera is treated as a
    // perspective one at its eye with the scale it has at its target distance.
    static LodView from_camera(const fx::Camera& camera, int viewport_height, double pixel_error,
                               std::size_t triangle_budget = 0);
};

struct LodStats {
    std::size_t triangles = 0;       // in the LOD mesh after the update
    std::size_t live_nodes = 0;      // nodes whose parent is split (the active quadtree)
    std::size_t nodes_examined = 0;  // nodes whose split state and blend were recomputed
    std::size_t nodes_woken = 0;     // of which: woken because the eye moved far enough
    std::size_t nodes_evaluated = 0; // f computed (the examined nodes and their constraint chains)
    std::size_t splits = 0, merges = 0;
    std::size_t morphing_nodes = 0;  // split nodes with 0 < b < 1
    std::size_t vertices_morphed = 0;// vertex heights recomputed
    std::size_t vertices_changed = 0;// vertices whose morphed height or thickness changed
    std::size_t fans_rebuilt = 0;
    std::size_t constrained = 0;     // evaluated nodes whose f_eff came from a coarser node
    bool full_rebuild = false;       // the update started from the root
    int budget_adjustments = 0;      // rebuilds made to meet the triangle budget
    double error_scale = 1.0;        // c used / c of the error bound (< 1 when the budget binds)
    bool over_budget = false;        // still over the budget with c = 0
    double milliseconds = 0.0;       // wall time of the update
};

// The LOD mesh as plain arrays (for prisms, drawing and tests).
struct LodMesh {
    std::vector<std::uint32_t> grid_index;  // per vertex: j·size + i of its sample
    std::vector<glm::dvec3> positions;      // geomorphed ground position
    std::vector<float> thickness;           // geomorphed layer thickness (zeros without a layer)
    std::vector<std::array<std::uint32_t, 3>> triangles; // vertex ids, counter-clockwise from above
    void clear() { grid_index.clear(), positions.clear(), thickness.clear(), triangles.clear(); }
};

class ContinuousLod {
public:
    // Precomputes d2 (O(samples)). `layer_thickness`, when given, must be on the ground's grid
    // and non-negative (the fog map, Roettger & Ertl §5). Throws fx::Error for a field that is
    // not 2^n + 1, a layer on another grid or with negative or non-finite values, or settings
    // out of range (C must be > 1 and finite).
    explicit ContinuousLod(HeightField ground, const LodSettings& settings = {});
    ContinuousLod(HeightField ground, HeightField layer_thickness, const LodSettings& settings = {});
    ~ContinuousLod();
    ContinuousLod(ContinuousLod&&) noexcept;
    ContinuousLod& operator=(ContinuousLod&&) noexcept;

    // Refines for the view. Throws fx::Error for a non-finite eye or a non-positive scale or
    // error bound.
    LodStats update(const LodView& view);
    // Discards all state: the next update() starts from the root.
    void reset();

    // What the last update() changed (LodChanges; `full` before the first and after reset()).
    const LodChanges& changes() const;
    // The fans, by slot, and the vertices as morphed (samples j·size + i).
    std::size_t fan_count() const;
    LodFan fan(std::size_t slot) const;
    bool fan_of(std::uint32_t node, LodFan& out) const; // false: the node draws no fan
    glm::dvec3 vertex_position(std::uint32_t sample) const;
    float vertex_thickness(std::uint32_t sample) const; // 0 without a layer

    // The current mesh (empty before the first update).
    void extract(LodMesh& out) const;
    LodMesh mesh() const;
    std::size_t triangle_count() const;
    // 2·(size − 1)²: every sample used.
    std::size_t full_resolution_triangles() const;

    const HeightField& ground() const;
    const HeightField* layer() const; // nullptr without a layer
    const LodSettings& settings() const;
    std::size_t memory_bytes() const;

    // Inspection, for tests and tools. A node is named by its centre sample (i, j); samples that
    // are no node's centre return false / 0.
    bool is_node_center(int i, int j) const;
    bool is_split(int i, int j) const;
    double roughness(int i, int j) const;       // d2 after propagation
    float morphed_height(int i, int j) const;   // as last computed (meaningful for used vertices)
    float morphed_thickness(int i, int j) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::terrain
