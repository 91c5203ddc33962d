// cellfx — visibility orders of cells for back-to-front compositing (the Absorption path).
//
// Based on: Max, Williams & Silva 2000, §III (visibility sorting).
//
// A VisibilitySort is built once per mesh (topology and geometry: what each method needs,
// such as face adjacency or face planes, is computed in the constructor); sort() then gives,
// per view, every cell index exactly once, farthest first, so that compositing in that order
// with "over" is correct wherever the method is exact.
//
//   centroid  cells by the distance of their vertex centroid from the eye (along the view
//             direction for orthographic cameras). Approximate: the fastest, and the floor the
//             exact sorts are measured against.
//
// Ownership and preconditions: the sort keeps a reference to the mesh, which must outlive it
// and must not change. The mesh passed validate_mesh(). sort() is const and may be called
// from several threads at once with their own output vectors.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"

namespace fx {

enum class SortMethod {
    Centroid,
};
const char* sort_method_name(SortMethod method); // "centroid", ...
// Parses a name given by sort_method_name(); false for anything else.
bool parse_sort_method(std::string_view name, SortMethod& method);

struct SortStats {
    double seconds = 0.0;     // time of this sort() call
    std::size_t cells = 0;    // cells ordered
    std::size_t cycles = 0;   // visibility cycles found and broken (exact methods); 0 for centroid
};

class VisibilitySort {
public:
    // Builds what the method needs per mesh. Throws fx::Error for a mesh it cannot sort.
    VisibilitySort(const CellMesh& mesh, SortMethod method);

    SortMethod method() const { return method_; }
    // Every cell exactly once, back to front (farthest first), for this camera.
    void sort(const Camera& camera, std::vector<std::uint32_t>& back_to_front, SortStats* stats = nullptr) const;
    // Bytes of the per-mesh state (not counting the mesh).
    std::size_t memory_bytes() const;

private:
    const CellMesh& mesh_;
    SortMethod method_;
    std::vector<glm::dvec3> centroids_; // per cell
};

} // namespace fx
