// Based on: Max, Williams & Silva 2000, §III (power sort, after Edelsbrunner 1989).
//
// Sorts that give every cell one scalar key per view and order the cells by it: the vertex
// centroid's distance (approximate) and the power distance of the tetrahedron's circumsphere
// (exact for Delaunay tetrahedralisations). Private to the sort module.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/visibility_sort.hpp"

namespace cellfx::fx::sort_detail {

class KeySort {
public:
    enum class Kind { Centroid, Power };
    // Vertex indices must be in range (VisibilitySort checks them first).
    KeySort(const CellMesh& mesh, Kind kind);
    // The same for another mesh (or this one changed), reusing the storage.
    void build(const CellMesh& mesh);

    // Every cell once, largest key (farthest) first; ties by ascending index.
    void sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats& stats) const;
    std::size_t memory_bytes() const;

private:
    Kind kind_;
    glm::dvec3 origin_{0.0};
    std::vector<glm::dvec3> centroids_; // centroid: world-space vertex centroids
    // power: per cell (C, w) with C the sphere centre relative to origin_ and w = |C|² − r²,
    // so that the power distance of e (relative to origin_) is |e|² − 2 C·e + w.
    std::vector<glm::dvec4> spheres_;
    // Per-view scratch, kept so that a steady sort allocates nothing (one sort at a time).
    mutable std::vector<std::pair<double, std::uint32_t>> keyed_;
};

} // namespace cellfx::fx::sort_detail
