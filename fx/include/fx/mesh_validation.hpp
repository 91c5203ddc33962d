// cellfx — checking a mesh before it is rendered, and fixing cell orientation.
//
// validate_mesh() reports, by cell id, everything that would make a picture silently wrong:
// indices past the point array, non-finite coordinates or scalars, repeated vertices,
// zero-volume, inverted (negative volume) and twisted (corners of both orientations) cells.
// Readers call orient_cells() for formats with mixed winding (AVS UCD).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace fx {

enum class MeshProblemKind {
    IndexOutOfRange,
    NonFiniteCoordinate,
    NonFiniteScalar,
    RepeatedVertex, // a cell uses the same point twice (degenerate)
    ZeroVolume,
    Inverted,       // negative volume: faces wind inward
    Twisted,        // corner volumes of both signs: the cell folds over itself
};
const char* mesh_problem_name(MeshProblemKind kind);

struct MeshProblem {
    MeshProblemKind kind;
    std::uint32_t cell;
    std::string message; // "cell 17: vertex 3 is point 900 but the mesh has 800 points"
};

// Signed volume by the divergence theorem over the cell's faces (quads split through their
// centroid, so non-planar quads count symmetrically). Positive for correctly wound cells.
// Vertices must be in range.
double cell_signed_volume(const CellMesh& mesh, std::size_t cell);

// All problems, in cell order. A cell's volume is "zero" below 1e-9 of the cube of its own
// bounding-box diagonal, so the test does not depend on the mesh's scale or position.
std::vector<MeshProblem> validate_mesh(const CellMesh& mesh);

struct OrientationReport {
    std::size_t flipped = 0;                 // inverted cells whose vertex order was mirrored
    std::vector<std::uint32_t> degenerate;   // cells left as they are: zero volume or repeated vertex
};
// Reorders the vertices of every inverted cell so that its volume becomes positive (tetra:
// swap 1 and 2; pyramid: reverse the base; wedge and hexahedron: swap the two end faces).
OrientationReport orient_cells(CellMesh& mesh);

} // namespace fx
