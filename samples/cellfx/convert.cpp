// `cellfx convert`: a mesh cellfx reads (or a synthetic one) written as a VTK legacy file, so
// that other tools (VTK, ParaView) see exactly the geometry, orientation and field cellfx draws.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "commands.hpp"
#include "fx/error.hpp"
#include "mesh/tetrahedralize.hpp"
#include "harness/synthetic_meshes.hpp"
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
    "                     non-convex FEM-like mesh, field \"temperature\"), duct-hex (the same\n"
    "                     duct as hexahedra), box-hex (a regular grid of hexahedra filling a\n"
    "                     1.25 x 1 x 1 box, 5k x 4k x 4k cells, field \"temperature\") or box-tet\n"
    "                     (the same box's hexahedra cut into tetrahedra, 5 or 6 each)\n"
    "  --cells N          synthetic meshes: about N cells (default 1000000)";

// A regular box of 5k × 4k × 4k hexahedra over [0, 1.25] × [0, 1] × [0, 1] (k from the wanted
// count, at least 1; 40,960 cells for k = 8), or those hexahedra cut into consistent tetrahedra,
// with the duct's kind of smooth field: two waves and a hot spot.
fx::CellMesh make_box(std::size_t cells, bool tetrahedra) {
    const double hexes = std::max(1.0, double(cells) / (tetrahedra ? 5.5 : 1.0));
    const std::uint32_t k = std::max<std::uint32_t>(1, std::uint32_t(std::lround(std::cbrt(hexes / 80.0))));
    fx::CellMesh mesh;
    fx::append_curvilinear_block(mesh, "box", {5 * k + 1, 4 * k + 1, 4 * k + 1},
                                 [](double u, double v, double w) { return glm::dvec3(1.25 * u, v, w); });
    fx::set_scalar_field(mesh, "temperature", [](const glm::dvec3& p) {
        const glm::dvec3 hot(0.8, 0.35, 0.6);
        return 0.35 + 0.25 * std::sin(6.0 * p.x + 1.0) * std::cos(5.0 * p.y) + 0.3 * p.z +
               0.45 * std::exp(-glm::dot(p - hot, p - hot) / 0.03);
    });
    return tetrahedra ? fx::tetrahedralize(mesh) : mesh;
}

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
        if (name == "duct" || name == "duct-hex") mesh = fx::make_curved_duct(std::size_t(cells), name == "duct");
        else if (name == "box-hex" || name == "box-tet") mesh = make_box(std::size_t(cells), name == "box-tet");
        else throw fx::Error("--synthetic: unknown mesh '" + name + "' (expected duct, duct-hex, box-hex or box-tet)");
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
