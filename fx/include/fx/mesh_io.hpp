// cellfx — one entry point for every mesh file cellfx reads.
//
// read_mesh() picks the reader by content, not by file name:
//   - "# vtk DataFile" on the first line          → VTK legacy (vtk_legacy.hpp)
//   - "#" comment lines, then five integers       → AVS UCD ASCII (avs_ucd.hpp)
//   - anything else                               → PLOT3D binary grid (plot3d.hpp), with q_path
//                                                    as its solution file when given
// `notes`, when given, receives human-readable lines about the detected format and about what
// was skipped, converted or repaired. Throws fx::Error (naming the file and the place) for
// unreadable or malformed files, and for a q_path given with a file that is not PLOT3D.
// This is what `cellfx info FILE [Q_FILE]` and `cellfx render` call.
#pragma once

#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

enum class MeshFileFormat { VtkLegacy, AvsUcd, Plot3d };
const char* mesh_file_format_name(MeshFileFormat format); // "VTK legacy", "AVS UCD", "PLOT3D"

// Format of the bytes at the start of a file (at most the first few KiB are looked at).
MeshFileFormat sniff_mesh_format(const char* data, std::size_t size);

CellMesh read_mesh(const std::string& path, const std::string& q_path = "", std::vector<std::string>* notes = nullptr);

} // namespace cellfx::fx
