#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <random>

#include "fx/cell_mesh.hpp"
#include "fx/vtk_legacy.hpp"
#include "io_test_helpers.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using Catch::Matchers::Contains;

namespace {

std::string cells_path(const std::string& name) { return fx_test::source_path("content/meshes/vtk_cells/" + name); }

std::size_t count_type(const fx::CellMesh& mesh, fx::CellType type) {
    return static_cast<std::size_t>(std::count(mesh.cell_types.begin(), mesh.cell_types.end(), type));
}

// A small mesh with every cell type and two fields, for round trips.
fx::CellMesh mixed_mesh() {
    fx::CellMesh mesh;
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) mesh.points.push_back({i + 0.125 * k, j - 1e-7 * i, k * 1.5 + 1e6});
    mesh.points.push_back({0.5, 0.5, 1e6 + 4.0});
    const std::uint32_t hex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    const std::uint32_t wedge[6] = {4, 6, 5, 8, 10, 9};
    const std::uint32_t tet[4] = {8, 9, 10, 12};
    const std::uint32_t pyr[5] = {8, 9, 11, 10, 12};
    mesh.add_cell(fx::CellType::Hexahedron, hex);
    mesh.add_cell(fx::CellType::Wedge, wedge);
    mesh.add_cell(fx::CellType::Tetra, tet);
    mesh.add_cell(fx::CellType::Pyramid, pyr);
    fx::ScalarField a{"density", {}}, b{"my field", {}};
    for (std::size_t p = 0; p < mesh.points.size(); ++p) {
        a.values.push_back(0.1f * float(p) + 1.0f / 3.0f);
        b.values.push_back(-float(p) * 1e-3f);
    }
    mesh.scalars = {a, b};
    return mesh;
}

void require_same_mesh(const fx::CellMesh& a, const fx::CellMesh& b) {
    REQUIRE(a.points.size() == b.points.size());
    for (std::size_t i = 0; i < a.points.size(); ++i) REQUIRE(a.points[i] == b.points[i]);
    REQUIRE(a.cell_types == b.cell_types);
    REQUIRE(a.cell_offsets == b.cell_offsets);
    REQUIRE(a.connectivity == b.connectivity);
    REQUIRE(a.scalars.size() == b.scalars.size());
    for (std::size_t f = 0; f < a.scalars.size(); ++f) {
        CHECK(a.scalars[f].name == b.scalars[f].name);
        REQUIRE(a.scalars[f].values == b.scalars[f].values);
    }
}

const char* kTinyHeader = "# vtk DataFile Version 3.0\ntiny\nASCII\nDATASET UNSTRUCTURED_GRID\n";

} // namespace

TEST_CASE("VTK single-cell files give one cell of each type", "[io][vtk]") {
    struct Case {
        const char* file;
        fx::CellType type;
    };
    for (const Case& c : {Case{"Tetra.vtk", fx::CellType::Tetra}, Case{"Pyramid.vtk", fx::CellType::Pyramid},
                          Case{"Wedge.vtk", fx::CellType::Wedge}, Case{"Hexahedron.vtk", fx::CellType::Hexahedron},
                          Case{"Voxel.vtk", fx::CellType::Hexahedron}}) {
        CAPTURE(c.file);
        const fx::CellMesh mesh = fx::read_vtk_legacy(cells_path(c.file));
        REQUIRE(mesh.cell_count() == 1);
        CHECK(mesh.cell_types[0] == c.type);
        CHECK(mesh.point_count() == std::size_t(fx::cell_vertex_count(c.type)));
    }
}

TEST_CASE("VTK voxel is reordered into the hexahedron's corner order", "[io][vtk]") {
    std::vector<std::string> notes;
    const fx::CellMesh voxel = fx::read_vtk_legacy(cells_path("Voxel.vtk"), &notes);
    const fx::CellMesh hex = fx::read_vtk_legacy(cells_path("Hexahedron.vtk"));
    // Both files describe the unit cube; after reordering, corner k is the same point.
    for (int k = 0; k < 8; ++k) {
        CAPTURE(k);
        CHECK(voxel.points[voxel.cell_vertices(0)[k]] == hex.points[hex.cell_vertices(0)[k]]);
    }
    CHECK(fx_test::notes_contain(notes, "1 voxels"));
}

TEST_CASE("VTK uGridEx: volume cells kept, lower-dimensional cells skipped and counted", "[io][vtk]") {
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_vtk_legacy(cells_path("uGridEx.vtk"), &notes);
    CHECK(mesh.point_count() == 27);
    CHECK(mesh.cell_count() == 4);
    CHECK(count_type(mesh, fx::CellType::Hexahedron) == 2);
    CHECK(count_type(mesh, fx::CellType::Tetra) == 2);
    CHECK(fx_test::notes_contain(notes, "skipped 5 2-D cells (types 5, 6, 7, 9)"));
    CHECK(fx_test::notes_contain(notes, "skipped 2 1-D cells (type 3)"));
    CHECK(fx_test::notes_contain(notes, "skipped 1 0-D cells (type 1)"));
    const fx::ScalarField* s = mesh.find_scalar("scalars");
    REQUIRE(s);
    CHECK(s->values[26] == 26.0f);
    const fx::ScalarField* v = mesh.find_scalar("vectors_magnitude");
    REQUIRE(v);
    CHECK(v->values[1] == Approx(std::sqrt(2.0)));
    CHECK(v->values[2] == Approx(2.0));
}

TEST_CASE("VTK VTKCellTypes: cell data and lookup tables are skipped", "[io][vtk]") {
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_vtk_legacy(cells_path("VTKCellTypes.vtk"), &notes);
    CHECK(mesh.cell_count() == 3); // hexahedron, voxel, tetra
    CHECK(count_type(mesh, fx::CellType::Hexahedron) == 2);
    CHECK(count_type(mesh, fx::CellType::Tetra) == 1);
    CHECK(fx_test::notes_contain(notes, "CELL_DATA"));
    CHECK(fx_test::notes_contain(notes, "skipped 5 2-D cells (types 5, 6, 7, 8, 9)"));
    CHECK(fx_test::notes_contain(notes, "skipped 2 1-D cells (types 3, 4)"));
    REQUIRE(mesh.scalars.size() == 2); // "scalars" and "vectors_magnitude"; the cell scalars are skipped
    CHECK(mesh.scalars[0].values.size() == 27);
}

TEST_CASE("VTK tetraMesh: 160 tets, empty CELL_DATA, int scalars", "[io][vtk]") {
    const fx::CellMesh mesh = fx::read_vtk_legacy(cells_path("tetraMesh.vtk"));
    CHECK(mesh.point_count() == 55);
    CHECK(mesh.cell_count() == 160);
    CHECK(count_type(mesh, fx::CellType::Tetra) == 160);
    const fx::ScalarField* s = mesh.find_scalar("scalars");
    REQUIRE(s);
    const fx::ScalarRange r = fx::scalar_range(*s);
    CHECK(r.lo == 0.0f);
    CHECK(r.hi == 4.0f);
}

TEST_CASE("VTK hexa.vtk: 10,648 hexahedra on the unit-ish cube", "[io][vtk]") {
    const auto start = std::chrono::steady_clock::now();
    const fx::CellMesh mesh = fx::read_vtk_legacy(fx_test::source_path("content/meshes/hexa_grid/hexa.vtk"));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    WARN("hexa.vtk (931 kB ASCII) read in " << ms << " ms");
    CHECK(mesh.point_count() == 12167);
    CHECK(mesh.cell_count() == 10648);
    CHECK(count_type(mesh, fx::CellType::Hexahedron) == 10648);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    CHECK(b.lo.x == Approx(0.0));
    CHECK(b.hi.x == Approx(0.9565).epsilon(1e-3));
    const fx::ScalarField* s = mesh.find_scalar("scalars");
    REQUIRE(s);
    CHECK(s->values[0] == Approx(17.32).epsilon(1e-3));
}

TEST_CASE("VTK binary post.vtk: 2,288 points, 8,750 tets, Pressure", "[io][vtk]") {
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_vtk_legacy(fx_test::source_path("content/meshes/lox_post/post.vtk"), &notes);
    CHECK(mesh.point_count() == 2288);
    CHECK(mesh.cell_count() == 8750);
    CHECK(count_type(mesh, fx::CellType::Tetra) == 8750);
    REQUIRE(mesh.find_scalar("Pressure"));
    CHECK(fx_test::notes_contain(notes, "\"Properties\""));
    const fx::Bounds b = fx::mesh_bounds(mesh);
    CHECK(b.lo.x >= -15.01);
    CHECK(b.hi.x <= 15.01);
}

TEST_CASE("VTK binary CylinderLinear.vtk: double points, FIELD vectors as magnitude", "[io][vtk]") {
    const fx::CellMesh mesh = fx::read_vtk_legacy(fx_test::source_path("content/meshes/cylinder_tets/CylinderLinear.vtk"));
    CHECK(mesh.point_count() == 465);
    CHECK(mesh.cell_count() == 1522);
    const fx::ScalarField* magnitude = mesh.find_scalar("velocity_magnitude");
    const fx::ScalarField* norm = mesh.find_scalar("vel_norm");
    REQUIRE(magnitude);
    REQUIRE(norm);
    // The file's own vel_norm is an independent check of the magnitude we compute.
    for (std::size_t i = 0; i < mesh.point_count(); ++i) REQUIRE(magnitude->values[i] == Approx(norm->values[i]).margin(1e-5));
}

TEST_CASE("VTK write/read round trip, ASCII and binary", "[io][vtk]") {
    const fx::CellMesh mesh = mixed_mesh();
    for (bool binary : {false, true}) {
        CAPTURE(binary);
        const std::string path = fx_test::output_path(binary ? "io_roundtrip_binary.vtk" : "io_roundtrip_ascii.vtk");
        fx::write_vtk_legacy(mesh, path, binary);
        const fx::CellMesh back = fx::read_vtk_legacy(path);
        require_same_mesh(mesh, back);
        CHECK(back.scalars[1].name == "my field"); // spaces survive percent-encoding
    }
    // A real file through both encodings.
    const fx::CellMesh post = fx::read_vtk_legacy(fx_test::source_path("content/meshes/lox_post/post.vtk"));
    for (bool binary : {false, true}) {
        const std::string path = fx_test::output_path("io_post_copy.vtk");
        fx::write_vtk_legacy(post, path, binary);
        require_same_mesh(post, fx::read_vtk_legacy(path));
    }
}

TEST_CASE("VTK version 5 OFFSETS/CONNECTIVITY layout", "[io][vtk]") {
    const std::string text = std::string("# vtk DataFile Version 5.1\nv5\nASCII\nDATASET UNSTRUCTURED_GRID\n") +
                             "POINTS 5 float\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\n" +
                             "CELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n0 1 2 3 1 2 3\n" +
                             "CELL_TYPES 2\n10\n5\n";
    std::vector<std::string> notes;
    const fx::CellMesh mesh = fx::read_vtk_legacy(fx_test::write_temp_file("v5.vtk", text), &notes);
    REQUIRE(mesh.cell_count() == 1);
    CHECK(mesh.cell_types[0] == fx::CellType::Tetra);
    CHECK(fx_test::notes_contain(notes, "skipped 1 2-D cells (type 5)"));
}

TEST_CASE("VTK STRUCTURED_GRID becomes a block of hexahedra", "[io][vtk]") {
    std::string text = "# vtk DataFile Version 3.0\nsg\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 3 2 2\nPOINTS 12 double\n";
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) text += std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(k) + "\n";
    text += "POINT_DATA 12\nSCALARS t double 3\nLOOKUP_TABLE default\n";
    for (int p = 0; p < 12; ++p) text += std::to_string(p) + " " + std::to_string(-p) + " 7\n";
    const fx::CellMesh mesh = fx::read_vtk_legacy(fx_test::write_temp_file("sg.vtk", text));
    REQUIRE(mesh.cell_count() == 2);
    REQUIRE(mesh.blocks.size() == 1);
    CHECK(mesh.blocks[0].dims == std::array<std::uint32_t, 3>{3, 2, 2});
    const std::uint32_t* v = mesh.cell_vertices(1);
    CHECK(mesh.points[v[0]] == glm::dvec3(1, 0, 0));
    CHECK(mesh.points[v[6]] == glm::dvec3(2, 1, 1));
    // Multi-component scalars are stored per component.
    REQUIRE(mesh.find_scalar("t_0"));
    REQUIRE(mesh.find_scalar("t_1"));
    REQUIRE(mesh.find_scalar("t_2"));
    CHECK(mesh.find_scalar("t_1")->values[5] == -5.0f);
}

TEST_CASE("VTK bad input: errors name the file, the place and the problem", "[io][vtk]") {
    const std::string cells_ok = "CELLS 1 5\n4 0 1 2 3\n";
    const std::string points_ok = "POINTS 4 float\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    auto message_for = [](const std::string& name, const std::string& text) {
        const std::string path = fx_test::write_temp_file(name, text);
        const std::string message = fx_test::error_message([&] { fx::read_vtk_legacy(path); });
        CHECK_THAT(message, Contains(path));
        return message;
    };

    SECTION("unknown cell type 99") {
        const std::string m = message_for("bad_type.vtk", kTinyHeader + points_ok + cells_ok + "CELL_TYPES 1\n99\n");
        CHECK_THAT(m, Contains("line 13") && Contains("cell 0") && Contains("99"));
    }
    SECTION("quadratic cell type") {
        const std::string m = message_for("quadratic.vtk", kTinyHeader + points_ok + cells_ok + "CELL_TYPES 1\n24\n");
        CHECK_THAT(m, Contains("cell 0") && Contains("24"));
    }
    SECTION("NaN coordinate") {
        const std::string m = message_for("nan.vtk", kTinyHeader + std::string("POINTS 4 float\n0 0 0\n1 0 0\n0 nan 0\n0 0 1\n") +
                                                         cells_ok + "CELL_TYPES 1\n10\n");
        CHECK_THAT(m, Contains("line 8") && Contains("point 2") && Contains("non-finite"));
    }
    SECTION("vertex index out of range") {
        const std::string m = message_for("range.vtk", kTinyHeader + points_ok + "CELLS 1 5\n4 0 1 2 4\n" + "CELL_TYPES 1\n10\n");
        CHECK_THAT(m, Contains("line 11") && Contains("cell 0") && Contains("point 4"));
    }
    SECTION("negative vertex index") {
        const std::string m = message_for("negative.vtk", kTinyHeader + points_ok + "CELLS 1 5\n4 0 -1 2 3\n" + "CELL_TYPES 1\n10\n");
        CHECK_THAT(m, Contains("cell 0") && Contains("point -1"));
    }
    SECTION("cell list size does not add up") {
        const std::string m = message_for("size.vtk", kTinyHeader + points_ok + "CELLS 1 6\n4 0 1 2 3\n" + "CELL_TYPES 1\n10\n");
        CHECK_THAT(m, Contains("line"));
    }
    SECTION("CELL_TYPES count differs from CELLS") {
        const std::string m = message_for("count.vtk", kTinyHeader + points_ok + cells_ok + "CELL_TYPES 2\n10\n10\n");
        CHECK_THAT(m, Contains("CELL_TYPES lists 2 cells but CELLS has 1"));
    }
    SECTION("wrong vertex count for the type") {
        const std::string m = message_for("arity.vtk", kTinyHeader + points_ok + cells_ok + "CELL_TYPES 1\n12\n");
        CHECK_THAT(m, Contains("line 11") && Contains("has 4 vertices, expected 8"));
    }
    SECTION("POINT_DATA count differs from POINTS") {
        const std::string m = message_for("pd.vtk", kTinyHeader + points_ok + cells_ok + "CELL_TYPES 1\n10\nPOINT_DATA 5\n");
        CHECK_THAT(m, Contains("line 14") && Contains("POINT_DATA 5"));
    }
    SECTION("unknown keyword") {
        const std::string m = message_for("kw.vtk", kTinyHeader + points_ok + "BANANAS 3\n");
        CHECK_THAT(m, Contains("line 10") && Contains("BANANAS"));
    }
    SECTION("hostile point count is refused before allocating") {
        const std::string m = message_for("huge.vtk", kTinyHeader + std::string("POINTS 4000000000000 float\n0 0 0\n"));
        CHECK_THAT(m, Contains("line 6") && Contains("POINTS"));
    }
    SECTION("negative structured dims") {
        const std::string m = message_for("dims.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS 3 -2 2\n");
        CHECK_THAT(m, Contains("line 5") && Contains("-2"));
    }
    SECTION("structured dims that do not match the points") {
        const std::string m = message_for("dims2.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_GRID\n"
                                                       "DIMENSIONS 2 2 2\nPOINTS 2 float\n0 0 0 1 1 1\n");
        CHECK_THAT(m, Contains("2 x 2 x 2") && Contains("2 points"));
    }
    SECTION("unsupported dataset") {
        const std::string m = message_for("poly.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n");
        CHECK_THAT(m, Contains("line 4") && Contains("POLYDATA"));
    }
    SECTION("binary truncated inside POINTS names the byte offset") {
        const std::string full = fx_test::read_bytes(fx_test::source_path("content/meshes/lox_post/post.vtk"));
        const std::string m = message_for("post_cut.vtk", full.substr(0, 1000));
        CHECK_THAT(m, Contains("byte") && Contains("truncated POINTS"));
    }
}

TEST_CASE("VTK truncated at every offset: parses or throws fx::Error with a location", "[io][vtk]") {
    const std::string ascii = fx_test::read_bytes(cells_path("uGridEx.vtk"));
    const std::size_t ascii_errors = fx_test::sweep_truncations("cut_ascii.vtk", ascii, fx_test::cut_points(ascii.size(), ascii.size(), 0),
                                                                [](const std::string& p) { fx::read_vtk_legacy(p); });
    CHECK(ascii_errors > ascii.size() / 2);
    const std::string binary = fx_test::read_bytes(fx_test::source_path("content/meshes/cylinder_tets/CylinderLinear.vtk"));
    fx_test::sweep_truncations("cut_binary.vtk", binary, fx_test::cut_points(binary.size(), 300, 300),
                               [](const std::string& p) { fx::read_vtk_legacy(p); });
}

TEST_CASE("VTK corrupted bytes never crash", "[io][vtk]") {
    // A cheap stand-in for the fuzzer: random byte changes in a binary and an ASCII file.
    std::mt19937 rng(1234);
    for (const std::string file : {"content/meshes/vtk_cells/uGridEx.vtk", "content/meshes/cylinder_tets/CylinderLinear.vtk"}) {
        const std::string original = fx_test::read_bytes(fx_test::source_path(file));
        for (int trial = 0; trial < 150; ++trial) {
            std::string bytes = original;
            for (int k = 0; k < 4; ++k) {
                bytes[rng() % bytes.size()] = static_cast<char>(rng() % 256);
            }
            const std::vector<char> data(bytes.begin(), bytes.end());
            try {
                fx::parse_vtk_legacy(data, "corrupt.vtk");
            } catch (const fx::Error& e) {
                CHECK_THAT(std::string(e.what()), Contains("corrupt.vtk: "));
            }
        }
    }
}
