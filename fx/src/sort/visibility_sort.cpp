// Based on: Max, Williams & Silva 2000, §III (visibility sorting).
#include "fx/visibility_sort.hpp"

#include <algorithm>
#include <chrono>
#include <numeric>

#include <glm/geometric.hpp>

#include "fx/error.hpp"

namespace fx {

const char* sort_method_name(SortMethod method) {
    switch (method) {
    case SortMethod::Centroid: return "centroid";
    }
    return "unknown";
}

bool parse_sort_method(std::string_view name, SortMethod& method) {
    if (name == "centroid") method = SortMethod::Centroid;
    else return false;
    return true;
}

VisibilitySort::VisibilitySort(const CellMesh& mesh, SortMethod method) : mesh_(mesh), method_(method) {
    centroids_.resize(mesh.cell_count());
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* v = mesh.cell_vertices(c);
        const int n = cell_vertex_count(mesh.cell_types[c]);
        glm::dvec3 sum(0.0);
        for (int i = 0; i < n; ++i) {
            if (v[i] >= mesh.point_count())
                throw Error("visibility sort: cell " + std::to_string(c) + ": vertex index out of range");
            sum += mesh.points[v[i]];
        }
        centroids_[c] = sum / double(n);
    }
}

void VisibilitySort::sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats* stats) const {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t n = mesh_.cell_count();
    // Key: squared distance from the eye (perspective) or depth along the view (orthographic);
    // larger keys are farther and come first.
    std::vector<std::pair<double, std::uint32_t>> keyed(n);
    const glm::dvec3 forward = camera.forward();
    for (std::size_t c = 0; c < n; ++c) {
        const glm::dvec3 d = centroids_[c] - camera.eye;
        const double key = camera.orthographic() ? glm::dot(d, forward) : glm::dot(d, d);
        keyed[c] = {key, static_cast<std::uint32_t>(c)};
    }
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
        return a.first > b.first || (a.first == b.first && a.second < b.second);
    });
    back_to_front.resize(n);
    for (std::size_t i = 0; i < n; ++i) back_to_front[i] = keyed[i].second;
    if (stats) {
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        stats->cells = n;
        stats->cycles = 0;
    }
}

std::size_t VisibilitySort::memory_bytes() const { return centroids_.capacity() * sizeof(glm::dvec3); }

} // namespace fx
