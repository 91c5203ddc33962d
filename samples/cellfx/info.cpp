// `cellfx info FILE [Q_FILE]`: what is in a mesh file, and what is wrong with it.
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

int run_info(const std::vector<std::string>& args) {
    if (args.empty() || args.size() > 2 || args[0] == "--help") {
        std::puts("usage: cellfx info FILE [Q_FILE]\n"
                  "  FILE: VTK legacy (.vtk), AVS UCD (.inp) or PLOT3D xyz; Q_FILE: PLOT3D solution");
        return args.empty() || args.size() > 2 ? 2 : 0;
    }
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_mesh(args[0], args.size() > 1 ? args[1] : "", &notes);

    std::printf("file: %s%s%s\n", args[0].c_str(), args.size() > 1 ? " + " : "", args.size() > 1 ? args[1].c_str() : "");
    std::printf("points: %zu\n", mesh.point_count());
    std::map<std::string, std::size_t> by_type;
    for (fx::CellType t : mesh.cell_types) by_type[fx::cell_type_name(t)]++;
    std::printf("cells: %zu", mesh.cell_count());
    const char* sep = " (";
    for (const auto& [name, count] : by_type) {
        std::printf("%s%s %zu", sep, name.c_str(), count);
        sep = ", ";
    }
    std::printf("%s\n", by_type.empty() ? "" : ")");
    std::printf("blocks: %zu\n", mesh.blocks.size());
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const fx::Block& block = mesh.blocks[b];
        std::printf("  [%zu] %s: %u cells", b, block.name.c_str(), block.cell_count);
        if (block.dims[0]) std::printf(", %u x %u x %u nodes", block.dims[0], block.dims[1], block.dims[2]);
        std::printf("\n");
    }
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    if (bounds.empty()) {
        std::printf("bounds: (no cells)\n");
    } else {
        std::printf("bounds: [%g, %g, %g] .. [%g, %g, %g]\n", bounds.lo.x, bounds.lo.y, bounds.lo.z, bounds.hi.x,
                    bounds.hi.y, bounds.hi.z);
    }
    std::printf("scalars: %zu\n", mesh.scalars.size());
    for (const fx::ScalarField& field : mesh.scalars) {
        const fx::ScalarRange r = fx::scalar_range(field);
        std::printf("  %s: [%g, %g]\n", field.name.c_str(), r.lo, r.hi);
    }
    const fx::FaceTopology topo = fx::build_face_topology(mesh);
    std::printf("boundary faces: %zu of %zu", topo.boundary_faces.size(), topo.face_slot_count());
    if (topo.non_manifold_faces) std::printf(" (%zu faces shared by more than two cells)", topo.non_manifold_faces);
    std::printf("\n");
    if (mesh.cell_count()) {
        std::printf("bytes per cell: %.1f (mesh), %.1f (face adjacency)\n",
                    double(mesh.memory_bytes()) / mesh.cell_count(), double(topo.memory_bytes()) / mesh.cell_count());
    }
    for (const std::string& note : notes) std::printf("note: %s\n", note.c_str());

    const std::vector<fx::MeshProblem> problems = fx::validate_mesh(mesh);
    if (problems.empty()) {
        std::printf("validation: no problems\n");
        return 0;
    }
    std::map<std::string, std::size_t> by_kind;
    for (const fx::MeshProblem& p : problems) by_kind[fx::mesh_problem_name(p.kind)]++;
    std::printf("validation: %zu problems", problems.size());
    sep = " (";
    for (const auto& [name, count] : by_kind) {
        std::printf("%s%s %zu", sep, name.c_str(), count);
        sep = ", ";
    }
    std::printf(")\n");
    const std::size_t shown = std::min<std::size_t>(problems.size(), 20);
    for (std::size_t i = 0; i < shown; ++i) std::printf("  %s\n", problems[i].message.c_str());
    if (shown < problems.size()) std::printf("  ... and %zu more\n", problems.size() - shown);
    // Problems are reported, not fatal: the file was read. Exit 0 so scripts can inspect it.
    return 0;
}

} // namespace cellfx_cli
