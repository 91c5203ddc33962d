// cellfx — VTK legacy files (".vtk", "# vtk DataFile Version x.y"), ASCII and BINARY.
//
// Reading: datasets UNSTRUCTURED_GRID and STRUCTURED_GRID; POINTS float or double (any numeric
// type); CELLS in the classic layout and in the version 5 OFFSETS/CONNECTIVITY layout.
// BINARY data is big-endian, as VTK writes it.
//   - Cell types 10 tetra, 12 hexahedron, 13 wedge, 14 pyramid are kept; 11 voxel is reordered
//     into a hexahedron; the 0-D/1-D/2-D types 1-9 are skipped and counted in the notes; any
//     other type id (quadratic cells, 0, 99, ...) is an error naming the file, cell and type.
//   - STRUCTURED_GRID (DIMENSIONS + POINTS) becomes one block of hexahedra (i fastest, VTK
//     vertex order) with Block::dims set.
//   - POINT_DATA: SCALARS with one component keep their name; with k components they become
//     "name_0" ... "name_{k-1}". VECTORS become "name_magnitude". FIELD arrays with one
//     component keep their name, others become "name_magnitude". NORMALS, TENSORS,
//     TEXTURE_COORDINATES, COLOR_SCALARS, ids and lookup tables are skipped (noted).
//   - CELL_DATA and dataset-level FIELD data are skipped (noted).
// Every malformed input throws fx::Error naming the file and the line (text) or byte offset
// (binary data) and what is wrong; sizes are checked against the file before allocating.
//
// Writing: UNSTRUCTURED_GRID with all cells and all point scalar fields (float), ASCII or
// big-endian BINARY; read_vtk_legacy() reads it back exactly (coordinates as double).
#pragma once

#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

// Reads a VTK legacy file. `notes`, when given, receives human-readable lines about what was
// skipped or converted ("skipped 3 2-D cells (types 5, 9)").
CellMesh read_vtk_legacy(const std::string& path, std::vector<std::string>* notes = nullptr);

// Same, from bytes already in memory (fuzzers, archives); `name` is used in messages.
CellMesh parse_vtk_legacy(const std::vector<char>& bytes, const std::string& name,
                          std::vector<std::string>* notes = nullptr);

// Writes `mesh` as an UNSTRUCTURED_GRID with every scalar field as POINT_DATA SCALARS.
// Precondition: every field has point_count() values. Throws fx::Error if the file cannot be
// written or the mesh is inconsistent.
void write_vtk_legacy(const CellMesh& mesh, const std::string& path, bool binary);

} // namespace cellfx::fx
