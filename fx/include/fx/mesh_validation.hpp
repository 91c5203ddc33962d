// cellfx — checking a mesh before it is rendered, and fixing cell orientation.
//
// validate_mesh() reports, by cell id, everything that would make a picture silently wrong:
// indices past the point array, non-finite or out-of-range coordinates, non-finite scalars,
// repeated vertices, zero-volume, inverted (negative volume) and twisted (parts of both
// orientations: a bow-tie) cells, and cells that overlap a neighbour (a duplicate, or two
// cells on the same side of the face they share).
//
// One policy for every reader and render path:
// - Readers orient: every reader calls orient_cells() and notes how many cells it flipped
//   (`cellfx info` prints it). Renderers still accept either winding (API-built meshes).
// - Flat cells (zero volume) hold no medium: the scan-line reference leaves them out, the
//   projection paths' thickness through them is zero.
// - Twisted cells have no inside a renderer could agree on: check_renderable() refuses the
//   mesh, naming them; so does a mesh with no cell of positive volume.
// - Overlapping cells within a block: the additive GPU paths (pcp, mip) add their media; the
//   scan-line reference, which needs cells that partition each block, refuses the mesh with a
//   message naming the cells (and the xmpvo sort stops at its sort-pairs budget).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

enum class MeshProblemKind {
    IndexOutOfRange,
    NonFiniteCoordinate,
    CoordinateOutOfRange, // finite, but beyond ±kMaxCoordinate
    NonFiniteScalar,
    RepeatedVertex, // a cell uses the same point twice (degenerate)
    ZeroVolume,
    Inverted,       // negative volume: faces wind inward
    Twisted,        // parts of both orientations: the cell folds over itself (a bow-tie)
    Duplicate,      // the same points as an earlier cell
    Overlapping,    // on the same side of a face it shares with an earlier cell
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

// What a cell is to a renderer. The test is scale-free: volumes are measured in units of the
// cell's own bounding box, so a cell of 1e-20 and one of 1e15 are judged alike.
enum class CellShape : std::uint8_t {
    Positive, // faces wind outward
    Inverted, // faces wind inward (orient_cells() flips it)
    Flat,     // zero volume: below 1e-9 of its bounding box (repeated points, collapsed)
    Twisted,  // the signed volume has parts of both signs beyond 1e-6 of the whole: a bow-tie
    Unusable, // an index out of range or a non-finite coordinate
};
CellShape classify_cell(const CellMesh& mesh, std::size_t cell);

// All problems, in cell order (the overlap checks build the mesh's face topology).
std::vector<MeshProblem> validate_mesh(const CellMesh& mesh);

// The checks every render path runs on a mesh before it draws it. Throws fx::Error, starting
// with `who` ("post.vtk", "scan-line renderer"), when the mesh is over the mesh-points or
// mesh-cells limit, has an index out of range, a non-finite coordinate or one beyond
// ±kMaxCoordinate, a twisted cell, or no cell of positive volume (all flat); messages name
// the first offending cells. Returns every cell's shape (Positive, Inverted or Flat).
std::vector<CellShape> check_renderable(const CellMesh& mesh, const std::string& who);

// Throws fx::Error, starting with `who`, unless `field` has one finite value per point of
// `mesh` (naming the field and the first bad point).
void check_scalar_field(const CellMesh& mesh, const ScalarField& field, const std::string& who);

struct OrientationReport {
    std::size_t flipped = 0;               // inverted cells whose vertex order was mirrored
    std::vector<std::uint32_t> degenerate; // cells left as they are: flat, twisted or unusable
};
// Reorders the vertices of every inverted cell so that its volume becomes positive (tetra:
// swap 1 and 2; pyramid: reverse the base; wedge and hexahedron: swap the two end faces).
OrientationReport orient_cells(CellMesh& mesh);
// The same for one cell: its shape before (CellShape::Inverted: it has been flipped).
CellShape orient_cell(CellMesh& mesh, std::size_t cell);

} // namespace cellfx::fx
