// Based on: Max, Williams & Silva 2000, §III (XMPVO, after Silva, Mitchell & Williams 1998).
//
// The boundary faces of a mesh and, per view, the exterior edges that make MPVO exact on
// non-convex meshes: wherever a viewing ray leaves the mesh through a boundary face g of cell
// B and later meets a boundary face f of cell A that faces the eye, with g nearer, A must be
// drawn before B. Private to the sort module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "face_graph.hpp"
#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "mesh/face_topology.hpp"
#include "fx/visibility_sort.hpp"

namespace cellfx::fx::sort_detail {

// A boundary triangle projected for one view, clipped to the near plane.
struct ExteriorProjection {
    double x[4], y[4];
    int count;
    double lo_x, lo_y, hi_x, hi_y;
    double depth_lo, depth_hi; // view depth range of the clipped triangle
    double area;
    std::uint32_t triangle; // index into ExteriorFaces' triangles
    std::uint32_t cell;
    bool big; // covers too many tiles: tested outside the tiles
};

class ExteriorFaces {
public:
    // Keeps a reference to the mesh (its points are read per view).
    ExteriorFaces(const CellMesh& mesh, const FaceTopology& topology);
    // The same for another mesh (or this one changed), reusing the storage.
    void build(const CellMesh& mesh, const FaceTopology& topology);

    // The exterior edges for this view. Fills stats' exterior_* counters and adds to
    // seconds_keys and working_bytes. Not to be called from two threads at once (it reuses
    // scratch, so that a steady sort allocates nothing).
    void edges(const Camera& camera, ExteriorEdges& out, SortStats& stats) const;

    std::size_t triangle_count() const { return triangles_.size(); }
    std::size_t memory_bytes() const { return triangles_.capacity() * sizeof(Triangle); }

private:
    struct Triangle {
        std::uint32_t v[3]; // outward winding (counter-clockwise seen from outside the cell)
        std::uint32_t cell;
    };
    const CellMesh* mesh_ = nullptr;
    std::vector<Triangle> triangles_;
    // Per-view scratch.
    mutable std::vector<ExteriorProjection> front_, back_;
    mutable std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;
    mutable std::vector<double> extent_;
    mutable std::vector<std::uint32_t> tile_first_[2], tile_items_[2], big_front_, big_back_, cursor_;
};

} // namespace cellfx::fx::sort_detail
