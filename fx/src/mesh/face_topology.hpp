// cellfx — which cell faces touch, and which lie on the boundary.
//
// Faces are matched by their vertex index sets (not by coordinates), so two cells are
// neighbours exactly when they share a face's vertex indices; blocks with separate points
// (PLOT3D zones) never match each other. A quad shared with two triangles of a
// tetrahedralised neighbour does not match: both sides count as boundary.
//
// Face slots: the faces of cell c are slots first_face[c] .. first_face[c+1]-1, in the order
// of cell_faces(type). Built once per mesh topology; O(F) in the number of faces (faces are
// grouped by their smallest vertex, then matched within each group).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/mesh_validation.hpp"

namespace cellfx::fx {

struct FaceTopology {
    static constexpr std::uint32_t kBoundary = 0xFFFFFFFFu;

    std::vector<std::uint32_t> first_face;     // cell_count + 1 entries
    std::vector<std::uint32_t> neighbour;      // per slot: neighbour's face slot, or kBoundary
    std::vector<std::uint32_t> slot_cell;      // per slot: the cell it belongs to
    std::vector<std::uint32_t> boundary_faces; // slots with no neighbour, ascending
    std::size_t non_manifold_faces = 0;        // vertex sets shared by more than two cells
    // The slots of those faces (left as boundary above), grouped: the g-th such face is
    // non_manifold_slots[non_manifold_first[g] .. non_manifold_first[g + 1]).
    std::vector<std::uint32_t> non_manifold_slots;
    std::vector<std::uint32_t> non_manifold_first{0};

    std::size_t face_slot_count() const { return neighbour.size(); }
    std::size_t memory_bytes() const;
};

FaceTopology build_face_topology(const CellMesh& mesh);

// The working storage of a build, kept by callers that rebuild the topology of a mesh replaced
// every frame (terrain prisms).
struct FaceTopologyScratch {
    struct Key {
        std::array<std::uint32_t, 4> v; // the face's vertices, sorted, 0xFFFFFFFF-padded
        std::uint32_t slot;
    };
    std::vector<Key> keys, grouped;
    std::vector<std::uint32_t> bucket_start, fill;
};
// The same into `out`, reusing its storage and the scratch's: no allocation once sizes have
// been seen.
void build_face_topology(const CellMesh& mesh, FaceTopology& out, FaceTopologyScratch& scratch);

// Two cells of one block that overlap: `cell` lies on the same side of a face it shares with
// `other` (other < cell), or has the same points (duplicate). Found from the face topology
// (faces matched by point ids), so cells that overlap without sharing points are not listed;
// the scan-line renderer finds those along its rays.
struct CellOverlap {
    std::uint32_t other, cell;
    bool duplicate;
};
std::vector<CellOverlap> find_overlapping_cells(const CellMesh& mesh, const FaceTopology& topology,
                                                const std::vector<CellShape>& shapes);
// "cell 5 has the same points as cell 2" / "cells 2 and 5 lie on the same side of their shared face".
std::string describe_overlap(const CellOverlap& overlap);

} // namespace cellfx::fx
