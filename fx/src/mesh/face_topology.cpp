#include "fx/face_topology.hpp"

#include <algorithm>
#include <array>

namespace fx {
namespace {

// A face's vertex set, sorted, padded with 0xFFFFFFFF for triangles, plus its slot.
struct FaceKey {
    std::array<std::uint32_t, 4> v;
    std::uint32_t slot;
};

bool same_vertices(const FaceKey& a, const FaceKey& b) { return a.v == b.v; }

} // namespace

std::size_t FaceTopology::memory_bytes() const {
    return (first_face.capacity() + neighbour.capacity() + slot_cell.capacity() + boundary_faces.capacity()) *
           sizeof(std::uint32_t);
}

FaceTopology build_face_topology(const CellMesh& mesh) {
    FaceTopology topo;
    const std::size_t cells = mesh.cell_count();
    topo.first_face.resize(cells + 1);
    std::uint32_t slots = 0;
    for (std::size_t c = 0; c < cells; ++c) {
        topo.first_face[c] = slots;
        slots += static_cast<std::uint32_t>(cell_face_count(mesh.cell_types[c]));
    }
    topo.first_face[cells] = slots;
    topo.neighbour.assign(slots, FaceTopology::kBoundary);
    topo.slot_cell.resize(slots);

    std::vector<FaceKey> keys(slots);
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
        }
    }
    std::sort(keys.begin(), keys.end(), [](const FaceKey& a, const FaceKey& b) {
        return a.v != b.v ? a.v < b.v : a.slot < b.slot;
    });

    for (std::size_t i = 0; i < keys.size();) {
        std::size_t j = i + 1;
        while (j < keys.size() && same_vertices(keys[i], keys[j])) ++j;
        if (j - i == 2) {
            topo.neighbour[keys[i].slot] = keys[i + 1].slot;
            topo.neighbour[keys[i + 1].slot] = keys[i].slot;
        } else if (j - i > 2) {
            // More than two cells on one face: the mesh is not a manifold there. Leave those
            // faces as boundary so nothing is hidden, and count the occurrence.
            ++topo.non_manifold_faces;
        }
        i = j;
    }
    for (std::uint32_t s = 0; s < slots; ++s) {
        if (topo.neighbour[s] == FaceTopology::kBoundary) topo.boundary_faces.push_back(s);
    }
    return topo;
}

} // namespace fx
