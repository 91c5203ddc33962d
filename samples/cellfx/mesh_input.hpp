// What `cellfx render`, `cellfx convert` and `cellfx bench render` read from the command line
// about a mesh: FILE [Q_FILE], the field to draw (--scalar) and the transfer function (--tf,
// --density), resolved to field units.
#pragma once

#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/transfer_function.hpp"
#include "options.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

struct MeshInput {
    std::vector<std::string> files; // FILE [Q_FILE] as given
    fx::CellMesh mesh;
    std::string field;              // the field to render: --scalar, or the mesh's first
    double load_ms = 0.0;           // reading the files
    const fx::ScalarField& scalar() const { return *mesh.find_scalar(field); }
};

// Reads parsed.positional (FILE [Q_FILE]) with fx::read_mesh and picks --scalar NAME (default:
// the first field). Throws fx::Error for a wrong number of files, a mesh without cells or
// fields, or an unknown field (naming the fields the mesh has).
MeshInput read_mesh_input(const ParsedArgs& parsed);

// `cellfx render`'s default: a blue-to-red ramp whose extinction grows with the scalar
// (normalized: mapped onto the field's range).
fx::TransferFunction default_transfer_function();

// --tf FILE (or `fallback`), mapped onto the field's range when normalized, its extinction
// multiplied by --density K (`command`'s documented range). The result is in field units
// (normalized() is false).
fx::TransferFunction transfer_function_option(const ParsedArgs& parsed, const char* command, const fx::ScalarField& field,
                                              const fx::TransferFunction& fallback);

} // namespace cellfx_cli
