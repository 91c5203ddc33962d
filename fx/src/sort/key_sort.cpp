// Based on: Max, Williams & Silva 2000, §III (power sort, after Edelsbrunner 1989).
//
// Power distance: for a sphere (c, r) and eye e, π = |e − c|² − r². For two tetrahedra sharing
// a face both circumspheres pass through the face's three vertices, so π_A − π_B (linear in e)
// vanishes exactly on the face's plane: ordering by π agrees with the face's MPVO edge
// whenever the face is locally Delaunay (neither opposite vertex inside the other sphere).
// Hence exactness on Delaunay meshes, and a good approximation on others.
#include "key_sort.hpp"
#include "frame_storage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

namespace cellfx::fx::sort_detail {
namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

glm::dvec3 vertex_centroid(const CellMesh& mesh, std::size_t c) {
    const std::uint32_t* v = mesh.cell_vertices(c);
    const int n = cell_vertex_count(mesh.cell_types[c]);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) sum += mesh.points[v[i]];
    return sum / double(n);
}

// (C, w) relative to `origin` for cell c: the circumsphere of a tetrahedron, or for other
// cells (and flat tetrahedra) the sphere about the vertex centroid through the farthest vertex.
glm::dvec4 power_sphere(const CellMesh& mesh, std::size_t c, const glm::dvec3& origin) {
    const std::uint32_t* v = mesh.cell_vertices(c);
    if (mesh.cell_types[c] == CellType::Tetra) {
        const glm::dvec3 a = mesh.points[v[0]];
        const glm::dvec3 u = mesh.points[v[1]] - a, s = mesh.points[v[2]] - a, w = mesh.points[v[3]] - a;
        const double den = 2.0 * glm::dot(u, glm::cross(s, w));
        const glm::dvec3 num = glm::dot(u, u) * glm::cross(s, w) + glm::dot(s, s) * glm::cross(w, u) +
                               glm::dot(w, w) * glm::cross(u, s);
        const glm::dvec3 centre = a + num / den;
        if (den != 0.0 && std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z)) {
            const glm::dvec3 C = centre - origin, A = a - origin;
            // |C|² − r² with r = |A − C|, written without forming r.
            return glm::dvec4(C, 2.0 * glm::dot(C, A) - glm::dot(A, A));
        }
    }
    const glm::dvec3 centre = vertex_centroid(mesh, c);
    double r2 = 0.0;
    for (int i = 0; i < cell_vertex_count(mesh.cell_types[c]); ++i) {
        const glm::dvec3 d = mesh.points[v[i]] - centre;
        r2 = std::max(r2, glm::dot(d, d));
    }
    const glm::dvec3 C = centre - origin;
    return glm::dvec4(C, glm::dot(C, C) - r2);
}

} // namespace

KeySort::KeySort(const CellMesh& mesh, Kind kind) : kind_(kind) { build(mesh); }

void KeySort::build(const CellMesh& mesh) {
    const std::size_t n = mesh.cell_count();
    if (kind_ == Kind::Centroid) {
        resize_kept(centroids_, n);
        for (std::size_t c = 0; c < n; ++c) centroids_[c] = vertex_centroid(mesh, c);
        return;
    }
    const Bounds bounds = mesh_bounds(mesh);
    origin_ = bounds.empty() ? glm::dvec3(0.0) : bounds.center();
    resize_kept(spheres_, n);
    for (std::size_t c = 0; c < n; ++c) spheres_[c] = power_sphere(mesh, c, origin_);
}

void KeySort::sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats& stats) const {
    auto t0 = clock_type::now();
    const std::size_t n = kind_ == Kind::Centroid ? centroids_.size() : spheres_.size();
    // Larger keys are farther and come first.
    std::vector<std::pair<double, std::uint32_t>>& keyed = keyed_;
    resize_kept(keyed, n);
    const glm::dvec3 forward = camera.forward();
    const bool ortho = camera.orthographic();
    if (kind_ == Kind::Centroid) {
        // Squared distance from the eye (perspective) or depth along the view (orthographic).
        for (std::size_t c = 0; c < n; ++c) {
            const glm::dvec3 d = centroids_[c] - camera.eye;
            keyed[c] = {ortho ? glm::dot(d, forward) : glm::dot(d, d), static_cast<std::uint32_t>(c)};
        }
    } else {
        // π − |e|² = w − 2 C·e. An orthographic eye is at infinity behind the view: the limit
        // order is by the depth of the centre along the view direction.
        const glm::dvec3 e = camera.eye - origin_;
        for (std::size_t c = 0; c < n; ++c) {
            const glm::dvec4& s = spheres_[c];
            const glm::dvec3 C(s);
            keyed[c] = {ortho ? glm::dot(C, forward) : s.w - 2.0 * glm::dot(C, e), static_cast<std::uint32_t>(c)};
        }
    }
    stats.seconds_keys = seconds_since(t0);
    t0 = clock_type::now();
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    resize_kept(back_to_front, n);
    for (std::size_t i = 0; i < n; ++i) back_to_front[i] = keyed[i].second;
    stats.seconds_order = seconds_since(t0);
    stats.cycles = 0;
    stats.working_bytes = keyed.capacity() * sizeof(keyed[0]);
}

std::size_t KeySort::memory_bytes() const {
    return centroids_.capacity() * sizeof(glm::dvec3) + spheres_.capacity() * sizeof(glm::dvec4);
}

} // namespace cellfx::fx::sort_detail
