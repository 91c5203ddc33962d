// `cellfx bench render` and `cellfx convert` end to end, as a peer comparison uses them: the
// bench's orbit, transfer function and figures in its JSON, its checks against the scan-line
// reference (and its exit status when a path's picture differs), and a converted mesh read back
// by cellfx's own reader. Timings are not judged (speed is the bench's to print).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <sys/wait.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "harness/synthetic_meshes.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

// Runs the CLI with `arguments`, its output in `log`; returns the exit status.
int run_cli(const std::string& arguments, const std::string& log) {
    const std::string command = std::string("'") + CELLFX_CLI + "' " + arguments + " > '" + log + "' 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

glm::dvec3 vec(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

void require_same_mesh(const fx::CellMesh& a, const fx::CellMesh& b) {
    REQUIRE(a.points == b.points);
    REQUIRE(a.cell_types == b.cell_types);
    REQUIRE(a.cell_offsets == b.cell_offsets);
    REQUIRE(a.connectivity == b.connectivity);
}

} // namespace

TEST_CASE("bench render: every path on the orbit, checked against the scan-line renderer, JSON for peers", "[gl][bench]") {
    const std::string mesh_path = fx_test::source_path("content/meshes/lox_post/post.vtk");
    const std::string out = fx_test::output_path("bench_render");
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    const std::string args = "bench render '" + mesh_path + "' --views 2 --size 64x48 --sort xmpvo,centroid --json '" +
                             out + "/run.json' --images '" + out + "/images'";
    const int status = run_cli(args, out + "/log.txt");
    INFO("cellfx " << args << "\n" << read_text(out + "/log.txt"));
    REQUIRE(status == 0);

    const nlohmann::json j = nlohmann::json::parse(read_text(out + "/run.json"));
    const fx::CellMesh mesh = fx::read_mesh(mesh_path);
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    CHECK(j["passed"] == true);
    CHECK(j["mesh"]["cells"] == 8750);
    CHECK(j["mesh"]["cell_types"]["tetra"] == 8750);
    CHECK(j["mesh"]["field"] == "Pressure");
    CHECK(j["image"]["width"] == 64);
    CHECK(j["image"]["height"] == 48);

    // The default transfer function in field units: the ramp mapped onto the field's range, its
    // largest extinction times the box diagonal 4.
    const nlohmann::json& points = j["transfer_function"]["points"];
    REQUIRE(points.size() == 3);
    const fx::ScalarRange range = fx::scalar_range(*mesh.find_scalar("Pressure"));
    CHECK(points[0][0].get<double>() == Approx(range.lo));
    CHECK(points[2][0].get<double>() == Approx(range.hi));
    CHECK(points[2][4].get<double>() * glm::length(bounds.size()) == Approx(4.0));

    // The orbit as documented: at the box centre, 20° above the plane normal to z, azimuths
    // 180° apart, fov 30°, the bounding sphere just inside the smaller (vertical) dimension.
    const nlohmann::json& views = j["views"];
    REQUIRE(views.size() == 2);
    const double radius = 0.5 * glm::length(bounds.size());
    glm::dvec3 dirs[2];
    for (int k = 0; k < 2; ++k) {
        const glm::dvec3 eye = vec(views[k]["eye"]), target = vec(views[k]["target"]);
        CHECK(glm::length(target - bounds.center()) == Approx(0.0).margin(1e-9));
        CHECK(vec(views[k]["up"]) == glm::dvec3(0, 0, 1));
        CHECK(views[k]["fov_y_degrees"] == 30.0);
        const double d = glm::length(eye - target);
        CHECK(radius / d == Approx(std::sin(glm::radians(15.0))));
        CHECK(std::asin((eye - target).z / d) == Approx(glm::radians(20.0)));
        CHECK(views[k]["near"].get<double>() == Approx(d - 1.01 * radius));
        CHECK(views[k]["far"].get<double>() == Approx(d + 1.01 * radius));
        dirs[k] = glm::normalize(glm::dvec3(eye.x - target.x, eye.y - target.y, 0.0));
    }
    CHECK(dirs[0].x == Approx(1.0)); // azimuth 0 along x
    CHECK(glm::dot(dirs[0], dirs[1]) == Approx(-1.0));

    // Every renderer: figures for both views, and (GPU paths) both frames within tolerance.
    std::map<std::string, nlohmann::json> by_name;
    for (const nlohmann::json& r : j["renderers"]) by_name[r["name"]] = r;
    for (const char* name : {"scanline", "pcp", "pcp-exact", "mip", "absorption (xmpvo)", "absorption (centroid)",
                             "absorption-exact (xmpvo)", "absorption-exact (centroid)"}) {
        INFO(name);
        REQUIRE(by_name.count(name) == 1);
        const nlohmann::json& r = by_name[name];
        REQUIRE(r["ms"].size() == 2);
        const double ms = r["median_ms"];
        CHECK(ms > 0.0);
        CHECK(r["cells_per_second"].get<double>() == Approx(8750.0 / (ms * 1e-3)));
        CHECK(r["bytes_per_cell"].get<double>() > 0.0);
        const bool gpu = std::string(name) != "scanline";
        CHECK(r["gpu_ms"].is_null() == !gpu);
        CHECK(r.contains("check") == gpu);
        if (gpu) {
            CHECK(r["check"]["passed"] == true);
            REQUIRE(r["check"]["frames"].size() == 2);
            for (const nlohmann::json& f : r["check"]["frames"]) CHECK(f["peak"].get<double>() > 0.0);
        }
        std::string file = name;
        for (const char* from : {" (", ")"}) {
            const std::size_t at = file.find(from);
            if (at != std::string::npos) file.replace(at, std::string(from).size(), from[0] == ' ' ? "_" : "");
        }
        CHECK(std::filesystem::exists(out + "/images/" + file + ".png"));
    }
    CHECK(by_name["absorption (centroid)"]["sort"] == "centroid");
    CHECK(by_name["absorption (xmpvo)"]["stages"].contains("sort ms"));
}

TEST_CASE("bench render fails, naming the path, when a path's picture is not the reference's", "[gl][bench]") {
    // A transfer function whose emission peaks sharply inside cells: the scan-line renderer's
    // maximum finds the peak, mip (the maximum of the face values, Roettger & Ertl §2) does
    // not, so mip's frames are far outside its tolerance; pcp-exact integrates it exactly.
    const std::string out = fx_test::output_path("bench_render_fail");
    std::filesystem::create_directories(out);
    {
        std::ofstream tf(out + "/spike.json");
        tf << R"({"normalized": true, "points": [[0, 1, 1, 1, 0.05], [0.47, 1, 1, 1, 0.05], [0.5, 1, 1, 1, 2.0],
                 [0.53, 1, 1, 1, 0.05], [1, 1, 1, 1, 0.05]]})";
    }
    const std::string args = "bench render '" + fx_test::source_path("content/meshes/lox_post/post.vtk") +
                             "' --views 2 --size 64x64 --paths mip,pcp-exact --tf '" + out + "/spike.json' --json '" +
                             out + "/run.json'";
    INFO("cellfx " << args);
    CHECK(run_cli(args, out + "/log.txt") == 1);
    const std::string log = read_text(out + "/log.txt");
    INFO(log);
    CHECK(log.find("outside their tolerance") != std::string::npos);
    CHECK(log.find("mip view") != std::string::npos);
    const nlohmann::json j = nlohmann::json::parse(read_text(out + "/run.json"));
    CHECK(j["passed"] == false);
    for (const nlohmann::json& r : j["renderers"]) {
        if (r["name"] == "mip") CHECK(r["check"]["passed"] == false);
        if (r["name"] == "pcp-exact") CHECK(r["check"]["passed"] == true);
    }
}

TEST_CASE("convert writes the mesh cellfx reads: PLOT3D with one field, and the synthetic duct", "[cli][io]") {
    const std::string out = fx_test::output_path("convert");
    std::filesystem::create_directories(out);
    const std::string xyz = fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin");
    const std::string q = fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin");
    REQUIRE(run_cli("convert '" + xyz + "' '" + q + "' --scalar density --out '" + out + "/fin.vtk'", out + "/log.txt") == 0);
    const fx::CellMesh original = fx::read_mesh(xyz, q);
    const fx::CellMesh back = fx::read_mesh(out + "/fin.vtk");
    require_same_mesh(original, back);
    REQUIRE(back.scalars.size() == 1); // only the field asked for: VTK's readers make it active
    CHECK(back.scalars[0].name == "density");
    CHECK(back.scalars[0].values == original.find_scalar("density")->values);

    REQUIRE(run_cli("convert --synthetic duct --cells 3000 --out '" + out + "/duct.vtk'", out + "/log.txt") == 0);
    const fx::CellMesh duct = fx::read_mesh(out + "/duct.vtk");
    require_same_mesh(fx::make_curved_duct(3000, true), duct);
    CHECK(duct.cell_count() > 2000);
    CHECK(duct.cell_count() < 4500);
    CHECK(duct.find_scalar("temperature"));
    CHECK(fx::validate_mesh(duct).empty()); // positively oriented, nothing degenerate

    REQUIRE(run_cli("convert --synthetic duct-hex --cells 500 --out '" + out + "/duct_hex.vtk'", out + "/log.txt") == 0);
    const fx::CellMesh hexes = fx::read_mesh(out + "/duct_hex.vtk");
    CHECK(hexes.cell_count() > 300);
    CHECK(hexes.cell_count() < 750);
    for (const fx::CellType t : hexes.cell_types) REQUIRE(t == fx::CellType::Hexahedron);
    CHECK(fx::validate_mesh(hexes).empty());

    // The regular box: 5k x 4k x 4k hexahedra, k = round(cbrt(2000 / 80)) = 3; cut into 5 or 6
    // tetrahedra each, k = round(cbrt(2000 / 5.5 / 80)) = 2.
    REQUIRE(run_cli("convert --synthetic box-hex --cells 2000 --out '" + out + "/box_hex.vtk'", out + "/log.txt") == 0);
    const fx::CellMesh box = fx::read_mesh(out + "/box_hex.vtk");
    CHECK(box.cell_count() == 15 * 12 * 12);
    for (const fx::CellType t : box.cell_types) REQUIRE(t == fx::CellType::Hexahedron);
    CHECK(box.find_scalar("temperature"));
    CHECK(fx::validate_mesh(box).empty());
    REQUIRE(run_cli("convert --synthetic box-tet --cells 2000 --out '" + out + "/box_tet.vtk'", out + "/log.txt") == 0);
    const fx::CellMesh box_tets = fx::read_mesh(out + "/box_tet.vtk");
    CHECK(box_tets.cell_count() >= 5 * 10 * 8 * 8);
    CHECK(box_tets.cell_count() <= 6 * 10 * 8 * 8);
    for (const fx::CellType t : box_tets.cell_types) REQUIRE(t == fx::CellType::Tetra);
    CHECK(fx::validate_mesh(box_tets).empty());

    // Bad input: a clear error naming what is wrong.
    CHECK(run_cli("convert '" + xyz + "' '" + q + "' --scalar nope --out '" + out + "/x.vtk'", out + "/log.txt") == 1);
    CHECK(read_text(out + "/log.txt").find("no field 'nope' (the mesh has: density") != std::string::npos);
    CHECK(run_cli("convert --synthetic sphere --out '" + out + "/x.vtk'", out + "/log.txt") == 1);
    CHECK(read_text(out + "/log.txt").find("unknown mesh 'sphere'") != std::string::npos);
}
