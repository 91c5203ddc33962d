// `cellfx convert`: a mesh cellfx reads (or a synthetic one) written as a VTK legacy file, so
// that other tools (VTK, ParaView) see exactly the geometry, orientation and field cellfx draws.
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fx/error.hpp"
#include "scanline/synthetic_meshes.hpp"
#include "fx/vtk_legacy.hpp"
#include "mesh_input.hpp"
#include "options.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

constexpr const char* kUsage =
    "usage: cellfx convert FILE [Q_FILE] --out FILE.vtk [options]\n"
    "       cellfx convert --synthetic NAME --out FILE.vtk [--cells N]\n"
    "  writes a VTK legacy UNSTRUCTURED_GRID (big-endian BINARY; --ascii for text): the cells as\n"
    "  cellfx reads them (IBLANKed PLOT3D cells dropped, AVS UCD cells oriented), points as double\n"
    "  --scalar NAME      write only this point field (VTK readers make it the active scalars);\n"
    "                     default: every field\n"
    "  --synthetic NAME   instead of a file: duct (fx::make_curved_duct cut into tetrahedra, a\n"
    "                     non-convex FEM-like mesh, field \"temperature\") or duct-hex (the same\n"
    "                     duct as hexahedra)\n"
    "  --cells N          synthetic meshes: about N cells (default 1000000)";

} // namespace

int run_convert(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"help", "ascii"});
    if (parsed.has("help") || args.empty()) {
        std::puts(kUsage);
        return args.empty() ? 2 : 0;
    }
    require_known(parsed, {"out", "scalar", "ascii", "synthetic", "cells"});
    const std::string out = output_file_option(parsed, "out", {".vtk"}, true);
    fx::CellMesh mesh;
    std::string source;
    if (parsed.has("synthetic")) {
        if (!parsed.positional.empty()) throw fx::Error("--synthetic takes no input file");
        const std::string name = parsed.get("synthetic");
        const int cells = int_option(parsed, "convert", "cells", 1000000);
        if (name != "duct" && name != "duct-hex") throw fx::Error("--synthetic: unknown mesh '" + name + "' (expected duct or duct-hex)");
        mesh = fx::make_curved_duct(std::size_t(cells), name == "duct");
        source = "synthetic " + name;
    } else {
        if (parsed.has("cells")) throw fx::Error("--cells is an option of --synthetic");
        MeshInput input = read_mesh_input(parsed);
        mesh = std::move(input.mesh);
        source = input.files[0] + (input.files.size() > 1 ? " + " + input.files[1] : "");
    }
    if (parsed.has("scalar")) {
        const fx::ScalarField* field = mesh.find_scalar(parsed.get("scalar"));
        if (!field) throw fx::Error("--scalar: no field '" + parsed.get("scalar") + "'");
        mesh.scalars = {*field};
    }
    fx::write_vtk_legacy(mesh, out, !parsed.has("ascii"));

    std::map<std::string, std::size_t> by_type;
    for (const fx::CellType t : mesh.cell_types) by_type[fx::cell_type_name(t)]++;
    std::string types, fields;
    for (const auto& [name, count] : by_type) types += (types.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    for (const fx::ScalarField& f : mesh.scalars) fields += (fields.empty() ? "" : ", ") + f.name;
    std::printf("wrote %s from %s: %zu points, %zu cells (%s), fields: %s\n", out.c_str(), source.c_str(),
                mesh.point_count(), mesh.cell_count(), types.c_str(), fields.empty() ? "none" : fields.c_str());
    return 0;
}

} // namespace cellfx_cli
