// Based on: Max, Williams & Silva 2000, §III (MPVO: topological sort of the face-adjacency
// graph, after Williams 1992).
//
// The per-mesh graph of shared faces and their planes, and the per-view topological sort,
// which also takes the exterior edges XMPVO adds. Private to the sort module.
//
// Memory (per tetrahedron of a mesh with few boundary faces): 16 bytes of packed neighbours
// (4 per face slot: neighbour cell << 3 | its slot), 32 bytes of planes (one float plane per
// shared face, ≈ 2 per tetrahedron), plus per view 2 bytes of state per cell. Mixed-type
// meshes add 4 bytes per cell for the first slot of each cell.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "mesh/face_topology.hpp"
#include "fx/visibility_sort.hpp"

namespace cellfx::fx::sort_detail {

// Per view: extra directed edges "source is drawn before target" between cells that share no
// face (XMPVO). Built by ExteriorEdges::build(); empty for MPVO.
struct ExteriorEdges {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_source; // (source, target), sorted
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_target; // (target, source), sorted
    std::vector<std::uint32_t> targets;      // distinct targets, ascending
    std::vector<std::uint32_t> target_first; // targets.size() + 1: ranges of by_target
    // Takes (source, target) pairs (duplicates allowed, no self pairs; sorted in place) and
    // builds the indices, reusing their storage.
    void build(std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);
    std::size_t memory_bytes() const;
};

class FaceGraph {
public:
    static constexpr std::uint32_t kBoundary = 0xFFFFFFFFu;
    static constexpr std::size_t kMaxCells = std::size_t(1) << 29;

    // Throws fx::Error for more than kMaxCells cells. Vertex indices must be in range.
    FaceGraph(const CellMesh& mesh, const FaceTopology& topology);
    // The same for another mesh (or this one changed), reusing the storage: no allocation for a
    // mesh no larger than one built before. Throws like the constructor (the graph is then empty).
    void build(const CellMesh& mesh, const FaceTopology& topology);

    // The topological sort for this view; `exterior` may be null. Not to be called from two
    // threads at once (it reuses scratch). Fills stats' seconds_keys,
    // seconds_order, face_edges, cycles and working_bytes (adding to what is there).
    void sort(const Camera& camera, const ExteriorEdges* exterior, std::vector<std::uint32_t>& back_to_front,
              SortStats& stats) const;
    std::size_t memory_bytes() const;

private:
    std::uint32_t first_slot(std::uint32_t cell) const { return stride_ ? cell * stride_ : first_slot_[cell]; }

    std::uint32_t cells_ = 0;
    std::uint32_t stride_ = 0;             // faces per cell when all cells have the same type
    std::vector<std::uint32_t> first_slot_; // otherwise cell_count + 1 slot offsets
    std::vector<std::uint32_t> neighbour_;  // per slot: neighbour << 3 | neighbour's slot, or kBoundary
    // One plane per shared face, stored in the order the per-view pass meets the faces (by
    // the cell with the smaller index, in slot order), relative to origin_ and outward from
    // that cell: (n, d) with n·(x − origin_) + d > 0 outside.
    std::vector<glm::vec4> planes_;
    glm::dvec3 origin_{0.0};
    // Per-view scratch, kept so that a steady sort allocates nothing (one sort at a time).
    mutable std::vector<std::uint16_t> state_;
    mutable std::vector<std::uint32_t> remaining_;
    mutable std::vector<std::uint32_t> path_; // a cycle's walk
};

} // namespace cellfx::fx::sort_detail
