#include <catch2/catch.hpp>

#include <chrono>
#include <random>

#include <glm/geometric.hpp>

#include "fx/avs_ucd.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "io_test_helpers.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using Catch::Matchers::Contains;

namespace {

// Every UCD cell type, written the AVS way: hex nodes 1-4 are the top face counter-clockwise
// seen from above (outside), pyramid apex first, tet base wound counter-clockwise seen from
// outside, prism top triangle first. Node ids are arbitrary and unordered.
const char* kAllTypes =
    "# AVS UCD test file\n"
    "# all cell types\n"
    "9 9 4 1 0\n"
    "101 0 0 1\n"
    "102 1 0 1\n"
    "103 1 1 1\n"
    "104 0 1 1\n"
    "108 0 1 0\n"
    "107 1 1 0\n"
    "106 1 0 0\n"
    "105 0 0 0\n"
    "109 0.5 0.5 2\n"
    "7 1 hex 101 102 103 104 105 106 107 108\n"
    "8 1 pyr 109 101 102 103 104\n"
    "9 1 tet 101 104 102 109\n"
    "3 2 prism 101 102 104 105 106 108\n"
    "10 1 tri 101 102 103\n"
    "11 1 quad 101 102 103 104\n"
    "12 2 line 101 105\n"
    "13 2 pt 101\n"
    "14 2 tri 105 106 107\n"
    "2 1 3\n"
    "temperature, K\n"
    "velocity, m/s\n"
    "109 9 0 0 9\n"
    "101 1 1 0 0\n"
    "102 2 0 2 0\n"
    "103 3 3 3 3\n"
    "104 4 4 0 0\n"
    "105 5 0 5 0\n"
    "106 6 0 0 6\n"
    "107 7 7 0 0\n"
    "108 8 0 8 0\n"
    "1 1\n"
    "material, none\n";

std::string write_ucd(const std::string& name, const std::string& text) { return fx_test::write_temp_file(name, text); }

glm::dvec3 corner(const fx::CellMesh& mesh, std::size_t cell, int k) { return mesh.points[mesh.cell_vertices(cell)[k]]; }

} // namespace

TEST_CASE("UCD: every cell type, arbitrary node ids, node data components", "[io][ucd]") {
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_avs_ucd(write_ucd("all_types.inp", kAllTypes), &notes);
    REQUIRE(mesh.point_count() == 9);
    REQUIRE(mesh.cell_count() == 4);
    CHECK(mesh.cell_types[0] == fx::CellType::Hexahedron);
    CHECK(mesh.cell_types[1] == fx::CellType::Pyramid);
    CHECK(mesh.cell_types[2] == fx::CellType::Tetra);
    CHECK(mesh.cell_types[3] == fx::CellType::Wedge);
    CHECK(fx_test::notes_contain(notes, "skipped 3 2-D cells"));
    CHECK(fx_test::notes_contain(notes, "skipped 1 1-D cells"));
    CHECK(fx_test::notes_contain(notes, "skipped 1 0-D cells"));
    CHECK(fx_test::notes_contain(notes, "skipped cell data"));
    // Hex: UCD lists the top face first; in VTK order vertex k+4 sits right above vertex k.
    for (int k = 0; k < 4; ++k) {
        CHECK(corner(mesh, 0, k).z == 0.0);
        CHECK(corner(mesh, 0, k + 4) == corner(mesh, 0, k) + glm::dvec3(0, 0, 1));
    }
    // Pyramid: the apex (first in UCD) is VTK vertex 4.
    CHECK(corner(mesh, 1, 4) == glm::dvec3(0.5, 0.5, 2));
    // Prism: vertex k+3 is the other end of the vertical edge from vertex k.
    for (int k = 0; k < 3; ++k) CHECK(glm::length(corner(mesh, 3, k + 3) - corner(mesh, 3, k)) == 1.0);
    // Cells written in the AVS convention need no flipping (hex, pyramid, tet); after
    // orient_cells every cell has positive volume.
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) CHECK(fx::cell_signed_volume(mesh, c) > 0.0);
    CHECK(fx::cell_signed_volume(mesh, 0) == Approx(1.0));
    // Node data, by node id (the data lines are in another order than the nodes).
    const fx::ScalarField* t = mesh.find_scalar("temperature");
    REQUIRE(t);
    CHECK(t->values[0] == 1.0f); // node 101
    CHECK(t->values[4] == 8.0f); // node 108 is the fifth node line
    REQUIRE(mesh.find_scalar("velocity_0"));
    REQUIRE(mesh.find_scalar("velocity_2"));
    CHECK(mesh.find_scalar("velocity_2")->values[8] == 9.0f); // node 109
}

TEST_CASE("A missing shared data file fails the test that reads it, naming the file", "[io]") {
    // Never a silent skip: tests that read ../shared/data throw when a file is absent (and run
    // as the ctest entry shared_data, listed as not run when the folder was missing at configure).
    CHECK_THROWS_WITH(fx_test::shared_data_path("spx/no_such_file.inp"),
                      Catch::Contains("spx/no_such_file.inp is missing") && Catch::Contains("../shared/data"));
}

TEST_CASE("UCD SPX: 2,896 nodes, 12,936 tets, degenerate cell and mixed winding reported", "[io][ucd][shared-data]") {
    // spx.inp has no stated licence: read from the shared data, never shipped in content/.
    const std::string path = fx_test::shared_data_path("spx/spx.inp");
    std::vector<std::string> notes;
    const auto start = std::chrono::steady_clock::now();
    const fx::CellMesh mesh = fx::read_avs_ucd(path, &notes);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    WARN("spx.inp read in " << ms << " ms");
    CHECK(mesh.point_count() == 2896);
    CHECK(mesh.cell_count() == 12936);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    CHECK(b.lo.x == Approx(4.06).margin(0.01));
    CHECK(b.hi.x == Approx(10.0).margin(0.01));
    CHECK(b.lo.z == Approx(-8.67).margin(0.01));
    CHECK(b.hi.z == Approx(0.725).margin(0.01));
    const fx::ScalarField* density = mesh.find_scalar("density");
    REQUIRE(density);
    CHECK(fx::scalar_range(*density).lo == Approx(0.2));
    CHECK(fx::scalar_range(*density).hi == Approx(1.0));
    // Cell id 1 ("1 1 tet 1 1 2 21") repeats node 1; it is on line 2 + 2896 nodes = 2898.
    CHECK(fx_test::notes_contain(notes, "degenerate cell: id 1 (line 2898)"));
    // The data README counts 11 tets wound against the other 12,924 (in VTK order), so after
    // the UCD-to-VTK reorder exactly those 11 are flipped.
    CHECK(fx_test::notes_contain(notes, "flipped 11 of 12,936 cells"));
    std::size_t non_positive = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) non_positive += !(fx::cell_signed_volume(mesh, c) > 0.0);
    CHECK(non_positive == 1); // only the degenerate cell
}

TEST_CASE("UCD bad input: errors name the file, the line and the problem", "[io][ucd]") {
    const std::string base = kAllTypes;
    auto message_for = [](const std::string& name, const std::string& text) {
        const std::string path = write_ucd(name, text);
        const std::string m = fx_test::error_message([&] { fx::read_avs_ucd(path); });
        CHECK_THAT(m, Contains(path));
        return m;
    };
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = base;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    SECTION("unknown cell type") {
        CHECK_THAT(message_for("type.inp", replaced("8 1 pyr", "8 1 pyramid5")), Contains("line 14") && Contains("cell id 8") && Contains("pyramid5"));
    }
    SECTION("undefined node id") {
        CHECK_THAT(message_for("node.inp", replaced("9 1 tet 101 104 102 109", "9 1 tet 101 104 102 110")),
                   Contains("line 15") && Contains("node id 110 is not defined"));
    }
    SECTION("NaN coordinate") {
        CHECK_THAT(message_for("nan.inp", replaced("103 1 1 1", "103 1 nan 1")), Contains("line 6") && Contains("node id 103") && Contains("non-finite"));
    }
    SECTION("duplicate node id") {
        CHECK_THAT(message_for("dup.inp", replaced("107 1 1 0", "101 1 1 0")), Contains("line 9") && Contains("defined twice"));
    }
    SECTION("node data sizes do not add up") {
        CHECK_THAT(message_for("sizes.inp", replaced("2 1 3\n", "2 1 2\n")), Contains("line 22") && Contains("add up to 3"));
    }
    SECTION("more cells announced than present") {
        CHECK_THAT(message_for("count.inp", replaced("9 9 4 1 0", "9 99 4 1 0")), Contains("line"));
    }
    SECTION("hostile node count") {
        CHECK_THAT(message_for("huge.inp", replaced("9 9 4 1 0", "900000000000 9 4 1 0")), Contains("line 3") && Contains("number of nodes"));
    }
    SECTION("binary UCD") {
        CHECK_THAT(message_for("binary.inp", std::string(1, '\x07') + "binary"), Contains("byte 0") && Contains("binary"));
    }
}

TEST_CASE("UCD truncated at every offset: parses or throws fx::Error with a line", "[io][ucd]") {
    const std::string text = kAllTypes;
    const std::vector<std::size_t> cuts = fx_test::cut_points(text.size(), text.size(), 0);
    const std::size_t errors = fx_test::sweep_truncations("cut.inp", text, cuts, [](const std::string& p) { fx::read_avs_ucd(p); });
    CHECK(errors > text.size() * 9 / 10);
    std::mt19937 rng(7);
    for (int trial = 0; trial < 300; ++trial) {
        std::string bytes = text;
        for (int k = 0; k < 3; ++k) bytes[rng() % bytes.size()] = "0123456789 -.\n#aex"[rng() % 18];
        try {
            fx::parse_avs_ucd(std::vector<char>(bytes.begin(), bytes.end()), "corrupt.inp");
        } catch (const fx::Error& e) {
            CHECK_THAT(std::string(e.what()), Contains("corrupt.inp: "));
        }
    }
}

TEST_CASE("read_mesh picks the reader by content", "[io][ucd][vtk][plot3d]") {
    std::vector<std::string> notes;
    const fx::CellMesh ucd = fx::read_mesh(write_ucd("sniff.dat", kAllTypes), "", &notes);
    CHECK(ucd.cell_count() == 4);
    CHECK(fx_test::notes_contain(notes, "format: AVS UCD"));

    notes.clear();
    const fx::CellMesh vtk = fx::read_mesh(fx_test::source_path("content/meshes/lox_post/post.vtk"), "", &notes);
    CHECK(vtk.cell_count() == 8750);
    CHECK(fx_test::notes_contain(notes, "format: VTK legacy"));

    notes.clear();
    const fx::CellMesh p3d = fx::read_mesh(fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin"),
                                           fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin"), &notes);
    CHECK(p3d.cell_count() == 37479);
    CHECK(p3d.find_scalar("density"));
    CHECK(fx_test::notes_contain(notes, "format: PLOT3D"));
    CHECK(fx_test::notes_contain(notes, "big-endian"));

    const std::string q = fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin");
    CHECK_THAT(fx_test::error_message([&] { fx::read_mesh(fx_test::source_path("content/meshes/lox_post/post.vtk"), q); }),
               Contains(q) && Contains("PLOT3D"));
    CHECK_THAT(fx_test::error_message([] { fx::read_mesh("/nonexistent/mesh.vtk"); }), Contains("/nonexistent/mesh.vtk: cannot open"));

    CHECK(fx::sniff_mesh_format("# vtk DataFile Version 2.0\n", 27) == fx::MeshFileFormat::VtkLegacy);
    CHECK(fx::sniff_mesh_format("# c\n1 2 3 4 5\n", 14) == fx::MeshFileFormat::AvsUcd);
    CHECK(fx::sniff_mesh_format("\0\0\0\x28", 4) == fx::MeshFileFormat::Plot3d);
}
