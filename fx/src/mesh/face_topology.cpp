#include "mesh/face_topology.hpp"

#include <algorithm>
#include <array>

#include "frame_storage.hpp"

namespace cellfx::fx {
namespace {

// A face's vertex set, sorted, padded with 0xFFFFFFFF for triangles, plus its slot.
using FaceKey = FaceTopologyScratch::Key;

bool same_vertices(const FaceKey& a, const FaceKey& b) { return a.v == b.v; }

} // namespace

std::size_t FaceTopology::memory_bytes() const {
    return (first_face.capacity() + neighbour.capacity() + slot_cell.capacity() + boundary_faces.capacity() +
            non_manifold_slots.capacity() + non_manifold_first.capacity()) *
           sizeof(std::uint32_t);
}

FaceTopology build_face_topology(const CellMesh& mesh) {
    FaceTopology topo;
    FaceTopologyScratch scratch;
    build_face_topology(mesh, topo, scratch);
    return topo;
}

void build_face_topology(const CellMesh& mesh, FaceTopology& topo, FaceTopologyScratch& scratch) {
    const std::size_t cells = mesh.cell_count();
    topo.boundary_faces.clear();
    topo.non_manifold_faces = 0;
    topo.non_manifold_slots.clear();
    assign_kept(topo.non_manifold_first, 1, 0u);
    resize_kept(topo.first_face, cells + 1);
    std::uint32_t slots = 0;
    for (std::size_t c = 0; c < cells; ++c) {
        topo.first_face[c] = slots;
        slots += static_cast<std::uint32_t>(cell_face_count(mesh.cell_types[c]));
    }
    topo.first_face[cells] = slots;
    assign_kept(topo.neighbour, slots, FaceTopology::kBoundary);
    resize_kept(topo.slot_cell, slots);

    // Every face's sorted vertex set, then the slots grouped by their smallest vertex (a
    // counting sort: O(F)), so that only the few faces around one point are compared.
    std::vector<FaceKey>& keys = scratch.keys;
    std::vector<std::uint32_t>& bucket_start = scratch.bucket_start;
    resize_kept(keys, slots);
    assign_kept(bucket_start, mesh.point_count() + 2, 0u);
    for (std::size_t c = 0; c < cells; ++c) {
        const CellType type = mesh.cell_types[c];
        const CellFace* faces = cell_faces(type);
        const std::uint32_t* cv = mesh.cell_vertices(c);
        for (int f = 0; f < cell_face_count(type); ++f) {
            const std::uint32_t slot = topo.first_face[c] + static_cast<std::uint32_t>(f);
            FaceKey& key = keys[slot];
            key.v = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu};
            for (int i = 0; i < faces[f].count; ++i) key.v[i] = cv[faces[f].v[i]];
            std::sort(key.v.begin(), key.v.begin() + faces[f].count);
            key.slot = slot;
            topo.slot_cell[slot] = static_cast<std::uint32_t>(c);
            // Indices past the points (an invalid mesh) share the last bucket.
            ++bucket_start[std::min<std::size_t>(key.v[0], mesh.point_count()) + 1];
        }
    }
    for (std::size_t b = 1; b < bucket_start.size(); ++b) bucket_start[b] += bucket_start[b - 1];
    std::vector<FaceKey>& grouped = scratch.grouped;
    resize_kept(grouped, slots);
    {
        std::vector<std::uint32_t>& fill = scratch.fill;
        assign_range_kept(fill, bucket_start.begin(), bucket_start.end() - 1);
        for (const FaceKey& key : keys) grouped[fill[std::min<std::size_t>(key.v[0], mesh.point_count())]++] = key;
    }
    const auto before = [](const FaceKey& a, const FaceKey& b) { return a.v != b.v ? a.v < b.v : a.slot < b.slot; };
    for (std::size_t b = 0; b + 1 < bucket_start.size(); ++b)
        std::sort(grouped.begin() + bucket_start[b], grouped.begin() + bucket_start[b + 1], before);

    for (std::size_t i = 0; i < grouped.size();) {
        std::size_t j = i + 1;
        while (j < grouped.size() && same_vertices(grouped[i], grouped[j])) ++j;
        if (j - i == 2) {
            topo.neighbour[grouped[i].slot] = grouped[i + 1].slot;
            topo.neighbour[grouped[i + 1].slot] = grouped[i].slot;
        } else if (j - i > 2) {
            // More than two cells on one face: the mesh is not a manifold there. Leave those
            // faces as boundary so nothing is hidden, and count the occurrence.
            ++topo.non_manifold_faces;
            for (std::size_t k = i; k < j; ++k) topo.non_manifold_slots.push_back(grouped[k].slot);
            topo.non_manifold_first.push_back(static_cast<std::uint32_t>(topo.non_manifold_slots.size()));
        }
        i = j;
    }
    for (std::uint32_t s = 0; s < slots; ++s) {
        if (topo.neighbour[s] == FaceTopology::kBoundary) topo.boundary_faces.push_back(s);
    }
}

} // namespace cellfx::fx
