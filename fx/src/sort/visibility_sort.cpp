// Based on: Max, Williams & Silva 2000, §III (visibility sorting).
//
// The method switch: key sorts (centroid, power) in key_sort.cpp, the face-graph topological
// sort (mpvo) in face_graph.cpp, and its exterior edges (xmpvo) in exterior_faces.cpp.
#include "fx/visibility_sort.hpp"

#include <chrono>
#include <mutex>
#include <string>

#include "exterior_faces.hpp"
#include "face_graph.hpp"
#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "key_sort.hpp"

namespace cellfx::fx {
namespace {

void check_vertex_indices(const CellMesh& mesh) {
    if (mesh.cell_offsets.size() != mesh.cell_count() + 1) {
        throw Error("visibility sort: mesh has " + std::to_string(mesh.cell_count()) + " cells but " +
                    std::to_string(mesh.cell_offsets.size()) + " cell offsets");
    }
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* v = mesh.cell_vertices(c);
        for (int i = 0; i < cell_vertex_count(mesh.cell_types[c]); ++i) {
            if (v[i] >= mesh.point_count()) {
                throw Error("visibility sort: cell " + std::to_string(c) + ": vertex " + std::to_string(i) +
                            " is point " + std::to_string(v[i]) + " but the mesh has " +
                            std::to_string(mesh.point_count()) + " points");
            }
        }
    }
}

} // namespace

const char* sort_method_name(SortMethod method) {
    switch (method) {
    case SortMethod::Centroid: return "centroid";
    case SortMethod::Mpvo: return "mpvo";
    case SortMethod::Xmpvo: return "xmpvo";
    case SortMethod::Power: return "power";
    }
    return "unknown";
}

bool parse_sort_method(std::string_view name, SortMethod& method) {
    for (SortMethod m : all_sort_methods()) {
        if (name == sort_method_name(m)) {
            method = m;
            return true;
        }
    }
    return false;
}

const std::vector<SortMethod>& all_sort_methods() {
    static const std::vector<SortMethod> methods = {SortMethod::Centroid, SortMethod::Mpvo, SortMethod::Xmpvo,
                                                    SortMethod::Power};
    return methods;
}

// The per-view state the sorts reuse (theirs is in KeySort, FaceGraph and ExteriorFaces), and
// the lock that gives one sort at a time its use.
struct sort_detail::Scratch {
    std::mutex turn;
    ExteriorEdges exterior_edges; // xmpvo: this view's edges
    // mpvo, xmpvo: the face topology of the last rebuild() and its working storage, kept for the
    // next one (the constructor's is dropped: a mesh sorted as it is does not pay for it).
    FaceTopology topology;
    FaceTopologyScratch topology_scratch;
};

VisibilitySort::VisibilitySort(const CellMesh& mesh, SortMethod method)
    : method_(method), scratch_(std::make_shared<sort_detail::Scratch>()) {
    const auto t0 = std::chrono::steady_clock::now();
    check_vertex_indices(mesh);
    switch (method) {
    case SortMethod::Centroid:
        keys_ = std::make_shared<sort_detail::KeySort>(mesh, sort_detail::KeySort::Kind::Centroid);
        break;
    case SortMethod::Power:
        keys_ = std::make_shared<sort_detail::KeySort>(mesh, sort_detail::KeySort::Kind::Power);
        break;
    case SortMethod::Mpvo:
    case SortMethod::Xmpvo: {
        const FaceTopology topology = build_face_topology(mesh);
        graph_ = std::make_shared<sort_detail::FaceGraph>(mesh, topology);
        if (method == SortMethod::Xmpvo) exterior_ = std::make_shared<sort_detail::ExteriorFaces>(mesh, topology);
        break;
    }
    }
    setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void VisibilitySort::rebuild(const CellMesh& mesh) {
    check_vertex_indices(mesh);
    const bool graph = method_ == SortMethod::Mpvo || method_ == SortMethod::Xmpvo;
    if (graph && mesh.cell_count() >= sort_detail::FaceGraph::kMaxCells) {
        *this = VisibilitySort(mesh, method_); // throws the constructor's error
        return;
    }
    const auto unshared = [](const auto& p) { return !p || p.use_count() == 1; };
    if (!unshared(keys_) || !unshared(graph_) || !unshared(exterior_) || !unshared(scratch_)) {
        *this = VisibilitySort(mesh, method_); // a copy keeps the old state
        return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    if (keys_) {
        keys_->build(mesh);
    } else {
        build_face_topology(mesh, scratch_->topology, scratch_->topology_scratch);
        graph_->build(mesh, scratch_->topology);
        if (exterior_) exterior_->build(mesh, scratch_->topology);
    }
    setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void VisibilitySort::sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats* stats) const {
    const std::lock_guard<std::mutex> turn(scratch_->turn);
    const auto t0 = std::chrono::steady_clock::now();
    SortStats s;
    if (keys_) {
        keys_->sort(camera, back_to_front, s);
    } else {
        if (exterior_) exterior_->edges(camera, scratch_->exterior_edges, s);
        graph_->sort(camera, exterior_ ? &scratch_->exterior_edges : nullptr, back_to_front, s);
    }
    s.cells = back_to_front.size();
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (stats) *stats = s;
}

std::size_t VisibilitySort::memory_bytes() const {
    std::size_t bytes = 0;
    if (keys_) bytes += keys_->memory_bytes();
    if (graph_) bytes += graph_->memory_bytes();
    if (exterior_) bytes += exterior_->memory_bytes();
    const FaceTopologyScratch& kept = scratch_->topology_scratch;
    bytes += scratch_->topology.memory_bytes() +
             (kept.keys.capacity() + kept.grouped.capacity()) * sizeof(FaceTopologyScratch::Key) +
             (kept.bucket_start.capacity() + kept.fill.capacity()) * sizeof(std::uint32_t);
    return bytes;
}

std::size_t VisibilitySort::boundary_triangle_count() const { return exterior_ ? exterior_->triangle_count() : 0; }

} // namespace cellfx::fx
