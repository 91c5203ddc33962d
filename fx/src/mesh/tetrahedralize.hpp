// cellfx — consistent subdivision of cells into tetrahedra.
//
// Based on: Max, Williams & Silva 2000, §IV (after Nielson & Sung 1997). Every quadrilateral
// face is cut by the diagonal that starts at its smallest global vertex index, a decision that
// involves only the face's four vertices, so the two cells sharing a face always agree and no
// adjacency is needed. Pyramids give 2 tetrahedra, wedges 3, hexahedra 5 (when no chosen
// diagonal touches the vertex opposite the smallest) or 6 (cut into two wedges first).
//
// Output tetrahedra keep the parent's orientation: a positively oriented cell (see
// cell_mesh.hpp) gives positively oriented tetrahedra. The decision is combinatorial (made on
// the reference cell), so it holds for curved cells too.
#pragma once

#include <cstdint>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

constexpr int kMaxCellTetrahedra = 6;

// Writes the tetrahedra of one cell as global vertex indices into out; returns their count
// (1, 2, 3, 5 or 6). `vertices` holds cell_vertex_count(type) distinct indices.
int subdivide_cell(CellType type, const std::uint32_t* vertices, std::uint32_t out[kMaxCellTetrahedra][4]);

// The whole mesh as tetrahedra: same points and scalars, blocks kept (their cell ranges
// remapped). If parent_cell is given it receives, per output tetrahedron, its source cell.
CellMesh tetrahedralize(const CellMesh& mesh, std::vector<std::uint32_t>* parent_cell = nullptr);

} // namespace cellfx::fx
