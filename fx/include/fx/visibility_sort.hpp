// cellfx — visibility orders of cells for back-to-front compositing (the Absorption path).
//
// Based on: Max, Williams & Silva 2000, §III (visibility sorting); Williams 1992 (MPVO);
// Silva, Mitchell & Williams 1998 (XMPVO); Edelsbrunner 1989 (power sort).
//
// A VisibilitySort is built once per mesh (topology and geometry: what each method needs,
// such as face adjacency or face planes, is computed in the constructor); sort() then gives,
// per view, every cell index exactly once, farthest first, so that compositing in that order
// with "over" is correct wherever the method is exact. docs/visibility_sort.md has the
// proofs and measured speeds.
//
//   centroid  cells by the distance of their vertex centroid from the eye (along the view
//             direction for orthographic cameras). Approximate: the fastest key sort, and the
//             floor the exact sorts are measured against.
//   mpvo      topological sort of the face-adjacency graph (Williams' MPVO). Each shared face
//             is an edge directed by the side of its plane the eye is on; adjacency and
//             planes are built once, per view only the directions are evaluated. O(n).
//             Exact for CONVEX meshes of convex cells with planar faces (when acyclic).
//   xmpvo     mpvo plus, per view, the edges MPVO misses on non-convex meshes and meshes with
//             holes or several pieces: wherever a viewing ray leaves the mesh through a
//             boundary face of cell B and re-enters through a boundary face of cell A, A is
//             drawn before B. Those pairs are found exactly by projecting the boundary faces
//             and intersecting the projections. Exact for any mesh of convex cells with planar
//             faces whose visibility relation is acyclic. O(n + b + k) for b boundary faces
//             and k overlapping pairs of them.
//   power     cells by the power distance |eye − c|² − r² of each tetrahedron's circumsphere
//             (centre c, radius r). Exact for Delaunay tetrahedralisations (Edelsbrunner), and
//             a good approximate sort for other tetrahedral meshes. Cells that are not
//             tetrahedra use the sphere about their vertex centroid through their farthest
//             vertex (approximate).
//
// Exactness is for the part of each cell in front of the camera's near plane (what the
// render paths draw). Cycles — possible with non-Delaunay meshes, non-planar faces or
// intersecting grids — are detected and broken, never looped on: one cell of the cycle is
// emitted early and SortStats::cycles counts it. Every call emits every cell exactly once.
//
// Ownership and preconditions: the sort keeps a reference to the mesh, which must outlive it
// and must not change (neither topology nor points) until rebuild() is called for it. The mesh
// passed validate_mesh(); cells may wind either way (planes are oriented from the cell's own
// centroid). sort() is const and may be called from several threads at once with their own
// output vectors. Copies share the per-mesh state.
//
//     fx::VisibilitySort sorter(mesh, fx::SortMethod::Xmpvo);   // once per mesh
//     std::vector<std::uint32_t> order;
//     sorter.sort(camera, order);                                // per view: farthest first
//     sorter.rebuild(mesh);                                      // after the mesh changed
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/sort_method.hpp"

namespace cellfx::fx {

struct SortStats {
    double seconds = 0.0;     // time of this sort() call
    std::size_t cells = 0;    // cells ordered
    std::size_t cycles = 0;   // visibility cycles found and broken (exact methods); 0 for centroid

    // Per-view detail. Keys: centroid/power keys, or the face-edge directions (and for xmpvo
    // the exterior edges). Order: the std::sort of the keys, or the topological traversal.
    double seconds_keys = 0.0;
    double seconds_order = 0.0;
    std::size_t face_edges = 0;             // mpvo/xmpvo: shared faces that gave a directed edge
    std::size_t exterior_faces = 0;         // xmpvo: boundary triangles in front of the near plane
    std::size_t exterior_pairs = 0;         // xmpvo: projected boundary-face pairs intersected exactly
    std::size_t exterior_edges = 0;         // xmpvo: distinct edges added between boundary cells
    std::size_t working_bytes = 0;          // peak working memory of this call, not counting back_to_front
};

namespace sort_detail {
class FaceGraph;
class ExteriorFaces;
struct Scratch;
class KeySort;
} // namespace sort_detail

class VisibilitySort {
public:
    // Builds what the method needs per mesh. Throws fx::Error for a mesh it cannot sort (a
    // vertex index out of range, more than 2^29 cells for the graph methods).
    VisibilitySort(const CellMesh& mesh, SortMethod method);

    // Rebuilds the per-mesh state for `mesh` (this one changed, or another), reusing its storage:
    // for a mesh no larger than one seen before nothing is allocated (meshes replaced every
    // frame: terrain prisms), once a first rebuild has kept the face topology's working storage
    // (mpvo, xmpvo). The sort then refers to `mesh`. A copy sharing the old state keeps it (this
    // object then builds anew). Throws like the constructor, before changing anything.
    void rebuild(const CellMesh& mesh);

    SortMethod method() const { return method_; }
    // Every cell exactly once, back to front (farthest first), for this camera. Reuses scratch
    // kept with the per-mesh state, so that a steady sort allocates nothing. Safe from several
    // threads at once: sorts on one object (or its copies, which share that state) take turns.
    void sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats* stats = nullptr) const;
    // Bytes of the per-mesh state (not counting the mesh).
    std::size_t memory_bytes() const;
    // Seconds the constructor spent building the per-mesh state.
    double setup_seconds() const { return setup_seconds_; }
    // xmpvo: boundary triangles (quads split by the smallest-vertex diagonal); else 0.
    std::size_t boundary_triangle_count() const;

private:
    SortMethod method_;
    double setup_seconds_ = 0.0;
    std::shared_ptr<sort_detail::KeySort> keys_;           // centroid, power
    std::shared_ptr<sort_detail::FaceGraph> graph_;        // mpvo, xmpvo
    std::shared_ptr<sort_detail::ExteriorFaces> exterior_; // xmpvo
    std::shared_ptr<sort_detail::Scratch> scratch_;        // one sort's turn, xmpvo's edges, rebuild()'s topology
};

} // namespace cellfx::fx
