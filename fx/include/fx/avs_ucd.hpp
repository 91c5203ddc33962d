// cellfx — AVS UCD (Unstructured Cell Data) ASCII files (".inp").
//
// Layout: leading "#" comment lines; "nnodes ncells nnodedata ncelldata nmodeldata"; nnodes
// lines "id x y z" (ids are arbitrary integers); ncells lines "id material type v...";
// then, when nnodedata > 0, "ncomponents size_1 ... size_n", one "label, unit" line per
// component and nnodes lines "id value...".
//   - Cell types tet, pyr, prism, hex are converted from UCD to VTK vertex order (pyramid: apex
//     first in UCD; hex and prism: UCD lists the two end faces the other way round; tet: third
//     and fourth vertex swapped), as VTK's vtkAVSucdReader and meshio's avsucd module do.
//     pt, line, tri, quad cells are skipped and counted in the notes.
//   - A node-data component of size 1 becomes a scalar field named by its label ("density");
//     one of size k becomes "label_0" ... "label_{k-1}". Cell and model data are skipped (noted).
//   - UCD files mix cell windings, so the reader calls fx::orient_cells(): the notes say how
//     many cells were flipped and list degenerate cells (repeated vertex or zero volume) by
//     file cell id and line number. Degenerate cells stay in the mesh.
// Binary UCD is not read (fx::Error). Every malformed input throws fx::Error naming the file,
// the line and what is wrong; counts are checked against the file size before allocating.
#pragma once

#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

CellMesh read_avs_ucd(const std::string& path, std::vector<std::string>* notes = nullptr);

// Same, from bytes in memory (fuzzers); `name` is used in messages.
CellMesh parse_avs_ucd(const std::vector<char>& bytes, const std::string& name, std::vector<std::string>* notes = nullptr);

} // namespace cellfx::fx
