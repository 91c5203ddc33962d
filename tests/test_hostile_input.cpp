// The hostile-input suite: what a careless user or an attacker gives cellfx — meshes, PLOT3D,
// UCD, transfer functions, scenes, height maps, devices, pipes, command-line options — each run
// as the programs users start (the `cellfx` command, the fem_viewer sample; a library call in a
// forked child where no command reaches it) under an address-space limit and a time limit.
// Every case must end one of two ways:
//   refused:  exit 1, a message naming the file (or option) and the place, and what is wrong;
//   accepted: exit 0 and the right picture, compared with an independent render.
// Never a signal, a hang past the time limit, or exit 0 with a wrong picture. The inputs are
// generated here, into the test output folder (docs/robustness.md, "Hostile input").
#include <catch2/catch.hpp>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <sys/stat.h>
#include <fcntl.h>
#include <unistd.h>

#include "fx/cell_mesh.hpp"
#include "fx/camera.hpp"
#include "fx/error.hpp"
#include "fx/image.hpp"
#include "fx/plot3d.hpp"
#include "fx/resource_limits.hpp"
#include "fx/visibility_sort.hpp"
#include "fx/vtk_legacy.hpp"
#include "image_check.hpp"
#include "mesh_builders.hpp"
#include "process_runner.hpp"
#include "terrain/scene.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

using fx_test::RunLimits;
using fx_test::RunResult;

// CPU cases: far more than any of them needs (the budgets stop every input long before), far
// less than an unbounded one would take. GL cases: Mesa's llvmpipe maps ~1 GiB of its own.
const RunLimits kCpu{std::uint64_t(2) << 30, 60.0};
const RunLimits kGl{std::uint64_t(6) << 30, 60.0};

std::string dir() {
    static const std::string d = [] {
        const std::string p = fx_test::output_path("hostile");
        std::filesystem::create_directories(p);
        return p;
    }();
    return d;
}
std::string file(const std::string& name) { return dir() + "/" + name; }

// "10" rather than "10.000000": the form `cellfx limits` prints.
std::string format_double(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

std::string write(const std::string& name, const std::string& text) {
    const std::string path = file(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// A scene text with every "TF" replaced by the shipped fire transfer function's path.
std::string write_scene(const std::string& name, std::string text) {
    const std::string tf = fx_test::source_path("content/transfer_functions/fire.json");
    for (std::size_t at; (at = text.find("\"TF\"")) != std::string::npos;) text.replace(at, 4, "\"" + tf + "\"");
    return write(name, text);
}

RunResult run_cellfx(std::vector<std::string> args, const RunLimits& limits = kCpu) {
    args.insert(args.begin(), CELLFX_CLI);
    return fx_test::run_program(args, limits);
}

// Refused: exit 1 within the limits, and the message names every one of `names`.
void require_refused(const RunResult& r, const std::vector<std::string>& names) {
    INFO(r.describe());
    REQUIRE_FALSE(r.timed_out);
    REQUIRE(r.signal == 0);
    REQUIRE(r.exit_code == 1);
    for (const std::string& n : names) CHECK_THAT(r.output, Catch::Contains(n));
}

void require_accepted(const RunResult& r) {
    INFO(r.describe());
    REQUIRE_FALSE(r.timed_out);
    REQUIRE(r.signal == 0);
    REQUIRE(r.exit_code == 0);
}

// The largest per-channel difference of two PFM renders (both must exist and match in size);
// infinite where the first holds a NaN or Inf.
double max_difference(const std::string& a, const std::string& b) {
    verify::Options rgb;
    rgb.channels = 3;
    const verify::Difference d = verify::measure(fx::read_pfm(a), fx::read_pfm(b), rgb);
    return d.nonfinite ? HUGE_VAL : d.worst.delta;
}

// Mean of all channels: a render that shows nothing is 0.
double mean_value(const std::string& pfm) {
    const fx::Image x = fx::read_pfm(pfm);
    double sum = 0.0;
    for (const glm::vec4& p : x.pixels) sum += p.r + p.g + p.b;
    return sum / (3.0 * double(x.pixels.size()));
}

bool all_finite(const std::string& pfm) {
    const fx::Image x = fx::read_pfm(pfm);
    for (const glm::vec4& p : x.pixels)
        if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) return false;
    return true;
}

// A mesh with a point field "s" (its x coordinate + 1, never constant) written as VTK.
std::string write_vtk(const std::string& name, fx::CellMesh mesh) {
    fx::ScalarField s{"s", {}};
    for (const glm::dvec3& p : mesh.points) s.values.push_back(float(p.x + 1.0));
    mesh.scalars = {s};
    const std::string path = file(name);
    fx::write_vtk_legacy(mesh, path, false);
    return path;
}

fx::CellMesh one_tet() {
    fx::CellMesh m;
    m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::uint32_t t[4] = {0, 1, 2, 3};
    m.add_cell(fx::CellType::Tetra, t);
    return m;
}

// `copies` tetrahedra on the same four points (what a mesh concatenated with itself gives).
fx::CellMesh copies_of_a_tet(std::size_t copies) {
    fx::CellMesh m = one_tet();
    const std::uint32_t t[4] = {0, 1, 2, 3};
    for (std::size_t i = 1; i < copies; ++i) m.add_cell(fx::CellType::Tetra, t);
    return m;
}

// Hexahedra that overlap without sharing points: the unit cube and one shifted by `shift`.
fx::CellMesh overlapping_hexes(double shift) {
    fx::CellMesh a = fx_test::hex_box(1, 1, 1), m = a;
    for (const glm::dvec3& p : a.points) m.points.push_back(p + glm::dvec3(shift, 0.3 * shift, 0.0));
    std::uint32_t v[8];
    for (int i = 0; i < 8; ++i) v[i] = a.cell_vertices(0)[i] + 8;
    m.add_cell(fx::CellType::Hexahedron, v);
    return m;
}

std::vector<std::string> scanline(const std::string& mesh, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"render", mesh, "--path", "scanline", "--size", "48x40", "--threads", "2", "--out", out};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

// A scene of effects only (no terrain), with `effects` as the array's text.
std::string effects_scene(const std::string& name, const std::string& effects, const std::string& camera = "") {
    return write_scene(name, "{\"effects\": [" + effects + "],\n \"camera\": " +
                                 (camera.empty() ? std::string("{\"eye\": [3, -4, 2], \"target\": [0, 0, 0.5], \"up\": [0, 0, 1]}") : camera) +
                                 ",\n \"render\": {\"width\": 64, \"height\": 48}}");
}
std::string campfire(const std::string& extra) {
    return "{\"type\": \"campfire\", \"name\": \"fire\", \"transfer_function\": \"TF\"" + extra + "}";
}

} // namespace

TEST_CASE("hostile input: crashes (thousands of effects, a tetrahedron copied 200,000 times)", "[hostile]") {
    SECTION("3,000 laser cones: refused before any is built, naming the effects limit") {
        std::string list;
        for (int i = 0; i < 3000; ++i)
            list += std::string(i ? "," : "") + "{\"type\": \"laser_cone\", \"name\": \"l" + std::to_string(i) +
                    "\", \"transfer_function\": \"TF\"}";
        const std::string scene = effects_scene("lasers.json", list);
        require_refused(run_cellfx({"render", scene, "--out", file("lasers.png")}), {"lasers.json", "effects", "3,000", "effects limit of 256"});
    }
    SECTION("200,000 copies of one tetrahedron: the reference names the duplicates; info lists them") {
        const std::string mesh = write_vtk("tet_200k.vtk", copies_of_a_tet(200000));
        require_refused(run_cellfx(scanline(mesh, file("tet_200k.pfm"))),
                        {"tet_200k.vtk", "cell 1 has the same points as cell 0", "more pairs"});
        const RunResult info = run_cellfx({"info", mesh});
        require_accepted(info);
        CHECK_THAT(info.output, Catch::Contains("duplicate") && Catch::Contains("cell 1: cell 1 has the same points as cell 0"));
    }
}

TEST_CASE("hostile input: overlapping cells within a grid are refused by the reference, named", "[hostile]") {
    for (const std::size_t copies : {2u, 3u, 10u}) {
        DYNAMIC_SECTION(copies << " identical tetrahedra") {
            const std::string mesh = write_vtk("tets_" + std::to_string(copies) + ".vtk", copies_of_a_tet(copies));
            require_refused(run_cellfx(scanline(mesh, file("tets.pfm"))), {mesh, "cell 1 has the same points as cell 0"});
        }
    }
    SECTION("two hexahedra overlapping without sharing points: found along the rays, cells and pixel named") {
        const std::string mesh = write_vtk("hexes_overlap.vtk", overlapping_hexes(0.5));
        const RunResult r = run_cellfx(scanline(mesh, file("hexes_overlap.pfm")));
        require_refused(r, {"hexes_overlap.vtk", "block 0", "overlap", "cell 0", "cell 1", "pixel (", "inside both at once"});
    }
    SECTION("touching hexahedra with their own points (a seam, not an overlap) render") {
        const std::string mesh = write_vtk("hexes_touching.vtk", overlapping_hexes(1.0));
        require_accepted(run_cellfx(scanline(mesh, file("hexes_touching.pfm"))));
        CHECK(mean_value(file("hexes_touching.pfm")) > 0.0);
    }
    SECTION("overlapping grids (separate blocks) add their media: two coincident blocks = one at twice the density") {
        fx::Plot3dBlock b;
        b.dims = {2, 2, 2};
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) b.points.push_back(glm::dvec3(i, j, k));
        // A homogeneous medium: where grids overlap the reference adds media exactly for those
        // (docs/scanline.md, "Overlapping grids").
        for (std::vector<double>& q : b.q) q.assign(8, 0.8);
        fx::Plot3dFormat f;
        f.multi_block = true;
        fx::write_plot3d({b, b}, f, file("two.xyz"), file("two.q"));
        fx::write_plot3d({b}, f, file("one.xyz"), file("one.q"));
        const std::string tf = write("homogeneous.json", R"({"points": [[0.8, 0.9, 0.5, 0.2, 1.5]]})");
        const std::vector<std::string> view = {"--camera", "eye=3,-2,2.5,target=0.5,0.5,0.5,up=0,0,1,fov=40", "--tf", tf};
        auto args = scanline(file("two.xyz"), file("two.pfm"), view);
        args.insert(args.begin() + 2, file("two.q"));
        require_accepted(run_cellfx(args));
        args = scanline(file("one.xyz"), file("one.pfm"), view);
        args.insert(args.begin() + 2, file("one.q"));
        args.insert(args.end(), {"--density", "2"});
        require_accepted(run_cellfx(args));
        CHECK(mean_value(file("one.pfm")) > 0.01);
        CHECK(max_difference(file("two.pfm"), file("one.pfm")) < 1e-5); // float image, one medium at 2σ
    }
}

TEST_CASE("hostile input: inverted cells, one policy for every reader", "[hostile]") {
    fx::CellMesh box = fx_test::hex_box(2, 2, 2);
    const std::string good = write_vtk("box.vtk", box);
    for (std::size_t c = 0; c < box.cell_count(); ++c) {
        std::uint32_t* v = box.cell_vertices(c);
        std::swap_ranges(v, v + 4, v + 4);
    }
    const std::string bad = write_vtk("box_inverted.vtk", box);
    SECTION("VTK: info reports the flipped cells; the scan-line picture is the oriented mesh's") {
        const RunResult info = run_cellfx({"info", bad});
        require_accepted(info);
        CHECK_THAT(info.output, Catch::Contains("orientation: flipped 8 of 8 cells"));
        CHECK_THAT(info.output, Catch::Contains("validation: no problems"));
        require_accepted(run_cellfx(scanline(good, file("box.pfm"))));
        require_accepted(run_cellfx(scanline(bad, file("box_inverted.pfm"))));
        CHECK(mean_value(file("box.pfm")) > 0.01);
        CHECK(max_difference(file("box.pfm"), file("box_inverted.pfm")) == 0.0);
    }
    SECTION("PLOT3D with a left-handed (i, j, k): flipped and rendered like the right-handed grid") {
        fx::Plot3dBlock right, left;
        right.dims = left.dims = {3, 3, 3};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i) {
                    right.points.push_back(glm::dvec3(i, j, k) * 0.5);
                    left.points.push_back(glm::dvec3(2 - i, j, k) * 0.5);
                }
        const fx::Plot3dFormat f;
        fx::write_plot3d({right}, f, file("right.xyz"));
        fx::write_plot3d({left}, f, file("left.xyz"));
        const RunResult info = run_cellfx({"info", file("left.xyz")});
        require_accepted(info);
        CHECK_THAT(info.output, Catch::Contains("orientation: flipped 8 of 8 cells"));
        // PLOT3D without a q file has no field: the cells themselves are what is checked here.
        CHECK_THAT(info.output, Catch::Contains("validation: no problems"));
    }
    SECTION("a GPU path draws the inverted file like the oriented one") {
        require_accepted(run_cellfx({"render", good, "--path", "pcp-exact", "--size", "48x40", "--out", file("box_gl.pfm")}, kGl));
        require_accepted(run_cellfx({"render", bad, "--path", "pcp-exact", "--size", "48x40", "--out", file("box_gl_inv.pfm")}, kGl));
        CHECK(mean_value(file("box_gl.pfm")) > 0.0);
        CHECK(max_difference(file("box_gl.pfm"), file("box_gl_inv.pfm")) == 0.0);
    }
}

TEST_CASE("hostile input: scale, a unit cube at 10^K with extinction at 10^-K gives one picture (scan-line)", "[hostile]") {
    auto cube = [](double scale) {
        fx::CellMesh m = fx_test::hex_box(2, 2, 2);
        fx::ScalarField s{"s", {}};
        for (glm::dvec3& p : m.points) {
            s.values.push_back(float(0.2 + p.x + 0.5 * p.z));
            p *= scale;
        }
        m.scalars = {s};
        return m;
    };
    auto render = [&](int k) {
        const std::string name = "cube_e" + std::to_string(k);
        fx::write_vtk_legacy(cube(std::pow(10.0, k)), file(name + ".vtk"), true);
        char density[32];
        std::snprintf(density, sizeof density, "%.17g", std::pow(10.0, -k));
        return run_cellfx(scanline(file(name + ".vtk"), file(name + ".pfm"), {"--density", density}));
    };
    require_accepted(render(0));
    CHECK(mean_value(file("cube_e0.pfm")) > 0.01);
    for (const int k : {-30, -15, -12, -6, 6, 12, 15, 17}) {
        INFO("10^" << k);
        require_accepted(render(k));
        // Double positions, float screen depths relative to the mesh: the same picture to float
        // rounding of the integrals (1e-4 absorbs the 1e-7 relative depths at any scale).
        CHECK(max_difference(file("cube_e0.pfm"), file("cube_e" + std::to_string(k) + ".pfm")) < 1e-4);
    }
    SECTION("past the range: coordinates of 1e19 and extinction of 4e32 are refused, naming why") {
        require_refused(render(19), {"cube_e19.vtk", "beyond ±1e+18"});
        require_refused(render(-33), {"--density", "is over 1e+32"});
    }
}

TEST_CASE("hostile input: settings that used to give a silent wrong picture", "[hostile]") {
    const std::string mesh = write_vtk("box_settings.vtk", fx_test::hex_box(2, 2, 2));
    SECTION("camera up: parallel, zero and 1e-300 in a scene, 1e-300 on the command line") {
        auto scene_with_camera = [&](const std::string& name, const std::string& camera) {
            return effects_scene(name, campfire(""), camera);
        };
        require_refused(run_cellfx({"render", scene_with_camera("up_parallel.json", R"({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 0, 1]})"),
                                "--out", file("x.png")}),
                        {"up_parallel.json", "camera", "parallel to the view direction"});
        require_refused(run_cellfx({"render", scene_with_camera("up_zero.json", R"({"eye": [3, 0, 1], "target": [0, 0, 0], "up": [0, 0, 0]})"),
                                "--out", file("x.png")}),
                        {"up_zero.json", "camera", "up is zero"});
        const std::string view = "eye=3,-2,2.5,target=0.5,0.5,0.5,fov=40,up=0,0,";
        require_accepted(run_cellfx(scanline(mesh, file("up_1.pfm"), {"--camera", view + "1"})));
        require_accepted(run_cellfx(scanline(mesh, file("up_tiny.pfm"), {"--camera", view + "1e-300"})));
        CHECK(mean_value(file("up_1.pfm")) > 0.001);
        CHECK(max_difference(file("up_1.pfm"), file("up_tiny.pfm")) == 0.0);
        // Every GPU path takes the frame Camera::basis builds in double: the same picture with an
        // up of 1e-300 or 1e300 as with 1 (pcp drew garbage, pcp-exact nothing, absorption-exact
        // 4x too bright with 1e-300, as they normalised the raw up in place).
        for (const char* path : {"pcp", "pcp-exact", "mip", "absorption", "absorption-exact"}) {
            INFO(path);
            const std::string one = file(std::string("up_1_") + path + ".pfm");
            require_accepted(run_cellfx({"render", mesh, "--path", path, "--size", "48x40", "--camera", view + "1", "--out", one}, kGl));
            CHECK(mean_value(one) > 0.001);
            for (const char* scale : {"1e-300", "1e300"}) {
                const std::string scaled = file(std::string("up_") + scale + "_" + path + ".pfm");
                require_accepted(
                    run_cellfx({"render", mesh, "--path", path, "--size", "48x40", "--camera", view + scale, "--out", scaled}, kGl));
                CHECK(max_difference(one, scaled) == 0.0);
            }
        }
        // A scene: its campfire in the one medium and its frustum culling see the same frame.
        const auto fire = [&](const std::string& name, const std::string& up) {
            const std::string scene = scene_with_camera(name + ".json", R"({"eye": [3, -4, 2], "target": [0, 0, 0.5], "up": )" + up + "}");
            require_accepted(run_cellfx({"render", scene, "--out", file(name + ".pfm")}, kGl));
            return file(name + ".pfm");
        };
        const std::string fire_1 = fire("up_fire_1", "[0, 0, 1]");
        CHECK(mean_value(fire_1) > 0.001);
        CHECK(max_difference(fire_1, fire("up_fire_tiny", "[0, 0, 1e-300]")) == 0.0);
    }
    SECTION("a camera-path key straight above its target") {
        const std::string scene = effects_scene("path_above.json", campfire(""),
                                                R"({"eye": [3, -4, 2], "target": [0, 0, 0.5], "up": [0, 0, 1]},
 "camera_path": {"keys": [{"time": 0, "eye": [3, -4, 2], "target": [0, 0, 0.5]},
                          {"time": 2, "eye": [0, 0, 9], "target": [0, 0, 0.5]}]})");
        require_refused(run_cellfx({"render", scene, "--out", file("x.png")}), {"path_above.json", "camera_path.keys[1]", "parallel"});
    }
    SECTION("--near beyond the far plane, ortho=-5, backgrounds outside [0, 1]") {
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--camera", "eye=3,3,3,far=10", "--near", "50"})),
                        {"--near 50", "not in front of far 10"});
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--camera", "eye=3,3,3,ortho=-5"})), {"ortho=-5", "positive"});
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--background", "5,5,5"})), {"--background", "[0, 1]"});
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--background", "-1,-1,-1"})), {"--background", "[0, 1]"});
    }
    SECTION("one medium of volumes whose field runs far past the transfer function") {
        // The field (2e17·x + 1) leaves the table's [0, 1] at once: the medium's held end value
        // times a run of 2e17 in s used to overflow its sum into Inf, then NaN.
        fx::CellMesh box = fx_test::hex_box(2, 2, 2);
        for (glm::dvec3& p : box.points) p *= 0.5;
        fx::ScalarField f{"f", {}};
        for (const glm::dvec3& p : box.points) f.values.push_back(float(1.0 + 2e17 * p.x));
        box.scalars = {f};
        const std::string mesh_path = file("far_field.vtk");
        fx::write_vtk_legacy(box, mesh_path, false);
        const std::string tf = R"({"points": [[0, 1, 0.5, 0.2, 1e30], [1, 1, 0.5, 0.2, 1e31]]})";
        const std::string scene = write("far_field.json", R"({"effects": [
  {"type": "volume", "name": "a", "shape": "mesh", "mesh": ")" + mesh_path + R"(", "transfer_function": )" + tf + R"(, "path": "absorption-exact"},
  {"type": "volume", "name": "b", "shape": "mesh", "mesh": ")" + mesh_path + R"(", "position": [0.3, 0.2, 0.1], "transfer_function": )" + tf + R"(, "path": "absorption-exact"}],
 "camera": {"eye": [3, -2, 2.5], "target": [0.6, 0.5, 0.5], "up": [0, 0, 1]}, "render": {"width": 48, "height": 40}})");
        require_accepted(run_cellfx({"render", scene, "--medium", "exact", "--out", file("far_field_gl.pfm")}, kGl));
        require_accepted(run_cellfx({"render", scene, "--path", "scanline", "--threads", "2", "--out", file("far_field_ref.pfm")}));
        CHECK(all_finite(file("far_field_gl.pfm")));
        CHECK(mean_value(file("far_field_ref.pfm")) > 0.1);
        CHECK(max_difference(file("far_field_gl.pfm"), file("far_field_ref.pfm")) < 1e-4);
        // The froxel grid (the default) adds the same runs of s into its slices: finite too, and
        // the same picture away from the volumes' silhouettes, which its tiles blur.
        require_accepted(run_cellfx({"render", scene, "--medium", "froxel", "--out", file("far_field_froxel.pfm")}, kGl));
        CHECK(all_finite(file("far_field_froxel.pfm")));
        CHECK(mean_value(file("far_field_froxel.pfm")) > 0.1);
    }
    SECTION("a scene 1e17 from the world's origin: the picture it has at the origin, reference included") {
        // Offsets of 1e17 (exact in double, as are the positions below) move a fog box and a
        // campfire 2 units across: the scan-line reference used to collapse them in world
        // coordinates ("all 1 cells have zero volume"); it now works relative to the eye.
        auto scene_at = [&](const std::string& name, const std::string& x, const std::string& eye_x) {
            return write_scene(name, R"({"effects": [
  {"type": "volume", "shape": "box", "size": [2, 2, 2], "position": [)" + x + R"(, 0, 0], "albedo": 0.5, "path": "absorption-exact",
   "transfer_function": {"points": [[0, 1, 0.5, 0.2, 0], [1, 1, 0.5, 0.2, 2]]}},
  {"type": "campfire", "position": [)" + x + R"(, -1.5, 0], "transfer_function": "TF"}],
 "camera": {"eye": [)" + eye_x + R"(, -10, 6], "target": [)" + x + R"(, 0, 0.5], "up": [0, 0, 1]}, "render": {"width": 48, "height": 40}})");
        };
        const std::string here = scene_at("scene_here.json", "0", "16"), far = scene_at("scene_far.json", "1e17", "100000000000000016");
        for (const std::string& path : {std::string("scanline"), std::string("gpu")}) {
            INFO(path);
            std::vector<std::string> a = {"render", here, "--out", file("scene_here.pfm")}, b = {"render", far, "--out", file("scene_far.pfm")};
            if (path == "scanline")
                for (auto* v : {&a, &b}) v->insert(v->end(), {"--path", "scanline", "--threads", "2"});
            require_accepted(run_cellfx(a, kGl));
            require_accepted(run_cellfx(b, kGl));
            CHECK(mean_value(file("scene_here.pfm")) > 0.01);
            CHECK(max_difference(file("scene_here.pfm"), file("scene_far.pfm")) < 1e-5);
        }
    }
    SECTION("a view too narrow for float, a far plane through the mesh") {
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--camera", "eye=3,3,3,target=0.3,0.3,0.3,up=0,0,1,ortho=1e-30"})),
                        {"ortho height 1e-30", "narrower than 1e-6"});
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--camera", "eye=3,3,3,target=0.3,0.3,0.3,fov=1e-9"})),
                        {"fov 1e-09", "narrower than 1e-6"});
        // A far plane through the mesh cuts no cells on any path: an orthographic view's GPU paths
        // rasterise with far moved past the mesh (the sorted paths used to draw nothing here).
        const std::string ortho = "eye=3,3,3,target=0.5,0.5,0.5,up=0,0,1,ortho=3";
        require_accepted(run_cellfx(scanline(mesh, file("ortho_ref.pfm"), {"--camera", ortho})));
        CHECK(mean_value(file("ortho_ref.pfm")) > 0.001);
        for (const char* path : {"absorption-exact", "pcp-exact", "mip", "pcp"}) {
            INFO(path);
            for (const char* far : {",far=100", ",far=4.5"}) {
                require_accepted(run_cellfx({"render", mesh, "--path", path, "--camera", ortho + far, "--size", "48x40",
                                             "--out", file(std::string("ortho_") + (far[5] == '1' ? "far" : "cut") + ".pfm")},
                                            kGl));
            }
            CHECK(max_difference(file("ortho_far.pfm"), file("ortho_cut.pfm")) == 0.0);
            if (std::string(path) == "absorption-exact") CHECK(max_difference(file("ortho_cut.pfm"), file("ortho_ref.pfm")) < 1e-3);
        }
        // A box 1e5 across seen from 2e5 away: without far= the camera reaches it, and with a far
        // plane through it (or just beyond it, where n/f below float's resolution used to clip
        // back faces in front of it) every perspective path draws it all, as the reference does.
        fx::CellMesh wide = fx_test::hex_box(2, 2, 2);
        for (glm::dvec3& p : wide.points) p *= 5e4;
        const std::string wide_mesh = write_vtk("wide_box.vtk", wide);
        const std::string view = "eye=2e5,-1.2e5,1.5e5,target=5e4,5e4,5e4,up=0,0,1,fov=40";
        const std::string tf = write("wide_tf.json", R"({"points": [[0, 1, 0.5, 0.2, 1e-5], [1, 0.2, 0.5, 1, 3e-5]], "normalized": true})");
        require_accepted(run_cellfx(scanline(wide_mesh, file("wide_scanline.pfm"), {"--camera", view, "--tf", tf})));
        CHECK(mean_value(file("wide_scanline.pfm")) > 0.01);
        for (const char* far : {"", ",far=3.1e5", ",far=2e5"}) {
            INFO("camera " << view << far);
            require_accepted(run_cellfx({"render", wide_mesh, "--path", "absorption-exact", "--camera", view + far, "--tf", tf,
                                         "--size", "48x40", "--out", file("wide_gl.pfm")},
                                        kGl));
            CHECK(max_difference(file("wide_scanline.pfm"), file("wide_gl.pfm")) < 1e-3);
        }
    }
    SECTION("extinction: 1e300 refused, 1e31 (inside the bound) stays finite on every CPU model") {
        const std::string huge = write("sigma_huge.json", R"({"points": [[0, 1, 0.5, 0.2, 1], [1, 1, 0.5, 0.2, 1e300]]})");
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--tf", huge})), {"sigma_huge.json", "points[1]", "sigma", "1e+32"});
        const std::string big = write("sigma_big.json", R"({"points": [[0, 1, 0.5, 0.2, 1], [1, 1, 0.5, 0.2, 1e31]], "normalized": true})");
        for (const char* model : {"absorption", "emission", "max"}) {
            INFO(model);
            const std::string out = file(std::string("sigma_big_") + model + ".pfm");
            require_accepted(run_cellfx(scanline(mesh, out, {"--tf", big, "--model", model})));
            CHECK(all_finite(out));
            CHECK(mean_value(out) > 0.0);
        }
        // 1e31 per unit over 1e17 units: light past a float's range saturates, never Inf.
        fx::CellMesh huge_box = fx_test::hex_box(1, 1, 1);
        for (glm::dvec3& p : huge_box.points) p *= 1e17;
        const std::string out = file("sigma_big_far.pfm");
        require_accepted(run_cellfx(scanline(write_vtk("huge_box.vtk", huge_box), out, {"--tf", big, "--model", "emission"})));
        CHECK(all_finite(out));
    }
    SECTION("extinction 1e31 over a box of 1e17 on every GPU path: finite, and the reference's picture") {
        // One colour, so the fog model is exact too. Over the box's field (1 to 2e17 + 1) it holds
        // its last value, 1e31 per unit: c·σ over the table's range [0, 1] fits a float.
        const std::string big = write("sigma_held.json", R"({"points": [[0, 1, 0.5, 0.2, 1e30], [1, 1, 0.5, 0.2, 1e31]]})");
        fx::CellMesh huge_box = fx_test::hex_box(2, 1, 1);
        for (glm::dvec3& p : huge_box.points) p *= 1e17;
        const std::string mesh_far = write_vtk("huge_box2.vtk", huge_box);
        const std::string camera = "eye=3e17,-2e17,2.5e17,target=1e17,0.5e17,0.5e17,up=0,0,1,fov=40,near=1e16,far=1e18";
        auto render = [&](const std::string& path, const std::string& name, std::vector<std::string> extra = {}) {
            const std::string out = file("sigma_far_" + name + ".pfm");
            std::vector<std::string> args = {"render", mesh_far, "--path", path, "--tf", big, "--camera", camera,
                                             "--size", "48x40", "--threads", "2", "--out", out};
            args.insert(args.end(), extra.begin(), extra.end());
            require_accepted(run_cellfx(args, path == "scanline" ? kCpu : kGl));
            INFO(out);
            CHECK(all_finite(out));
            return out;
        };
        const std::string absorption = render("scanline", "scanline_absorption");
        const std::string emission = render("scanline", "scanline_emission", {"--model", "emission"});
        REQUIRE(mean_value(absorption) > 0.05);
        // Past a float's range emitted light saturates at its largest value, as the reference's.
        CHECK(max_difference(render("pcp-exact", "pcp_exact"), emission) == 0.0);
        // A segment 1e17 long at 1e31 per unit is opaque: the front's colour. The fog model keeps
        // emission over optical depth finite; the exact sorted path interpolates τ along the
        // length exactly (a silhouette's short segments stay opaque).
        CHECK(max_difference(render("pcp-exact", "fog", {"--fog"}), absorption) < 2e-3);
        CHECK(max_difference(render("absorption-exact", "absorption_exact"), absorption) < 2e-3);
        CHECK(max_difference(render("absorption", "absorption"), absorption) < 2e-2); // classic: interpolated opacity
        CHECK(mean_value(render("mip", "mip")) > 0.0);
        // The 8-bit classic path: the same picture as the box at unit size, whose light saturates
        // alike (it used to draw nothing at 1e17: Inf vertex colours interpolated to NaN).
        const std::string unit_out = file("sigma_unit_pcp.pfm");
        require_accepted(run_cellfx({"render", write_vtk("unit_box2.vtk", fx_test::hex_box(2, 1, 1)), "--path", "pcp", "--tf", big,
                                     "--camera", "eye=3,-2,2.5,target=1,0.5,0.5,up=0,0,1,fov=40,near=0.1,far=10", "--size",
                                     "48x40", "--out", unit_out},
                                    kGl));
        CHECK(mean_value(unit_out) > 0.05);
        CHECK(max_difference(render("pcp", "pcp"), unit_out) <= 2.0 / 255.0);
        // Mapped onto the field's range instead, c·σ integrated over 2e17 would pass a float's
        // range in the GPU paths' tables: refused, saying so; the scan-line renderer draws it.
        const std::string spread = write("sigma_spread.json", R"({"points": [[0, 1, 0.5, 0.2, 1e30], [1, 1, 0.5, 0.2, 1e31]], "normalized": true})");
        require_refused(run_cellfx({"render", mesh_far, "--path", "pcp-exact", "--tf", spread, "--size", "48x40", "--out", file("x.pfm")}, kGl),
                        {"transfer function", "scalar range", "float tables"});
        require_accepted(run_cellfx(scanline(mesh_far, file("sigma_spread_scanline.pfm"), {"--tf", spread})));
    }
    SECTION("a bow-tie hexahedron and a mesh of flat cells: refused by every path, info says why") {
        fx::CellMesh bow = fx_test::hex_box(1, 1, 1);
        std::uint32_t* h = bow.cell_vertices(0);
        std::swap(h[4], h[6]); // the top face turned half a turn: two halves of opposite sign
        const std::string bowtie = write_vtk("bowtie.vtk", bow);
        require_refused(run_cellfx(scanline(bowtie, file("x.pfm"))), {"bowtie.vtk", "cell 0", "folds over itself"});
        require_refused(run_cellfx({"render", bowtie, "--path", "pcp", "--out", file("x.png")}), {"bowtie.vtk", "folds over itself"});
        const RunResult info = run_cellfx({"info", bowtie});
        require_accepted(info);
        CHECK_THAT(info.output, Catch::Contains("twisted"));
        fx::CellMesh flat = fx_test::hex_box(2, 1, 1);
        for (glm::dvec3& p : flat.points) p.z = 0.0;
        require_refused(run_cellfx(scanline(write_vtk("flat.vtk", flat), file("x.pfm"))), {"flat.vtk", "all 2 cells have zero volume"});
    }
    SECTION("effect and terrain parameters of 1e300, named by their key") {
        require_refused(run_cellfx({"render", effects_scene("fire_huge.json", campfire(", \"base_radius\": 1e300")), "--out", file("x.png")}),
                        {"fire_huge.json", "effects[0].base_radius", "beyond ±1e18"});
        require_refused(run_cellfx({"render",
                                effects_scene("light_huge.json", R"({"type": "search_light", "transfer_function": "TF", "range": 1e300})"),
                                "--out", file("x.png")}),
                        {"light_huge.json", "effects[0].range", "beyond ±1e18"});
        const std::string terrain = write("terrain_huge.json", R"({"terrain": {"procedural": {"size": 65, "spacing": 1e300,
            "noise": {"amplitude": 1}}}, "camera": {"eye": [0, -10, 5], "target": [0, 0, 0]}})");
        require_refused(run_cellfx({"render", terrain, "--out", file("x.png")}), {"terrain_huge.json", "terrain.procedural.spacing", "1e+300"});
        const std::string spread = write("terrain_wide.json", R"({"terrain": {"procedural": {"size": 4097, "spacing": 1e15,
            "noise": {"amplitude": 1}}}, "camera": {"eye": [0, -10, 5], "target": [0, 0, 0]}})");
        require_refused(run_cellfx({"render", spread, "--out", file("x.png")}), {"terrain_wide.json", "terrain", "grid reaches"});
    }
}

TEST_CASE("hostile input: what used to hang", "[hostile]") {
    SECTION("xmpvo on 20,000 identical tetrahedra: the sort-pairs budget stops it with a message") {
        const RunResult r = fx_test::run_limited(
            [] {
                const fx::CellMesh mesh = copies_of_a_tet(20000);
                const fx::VisibilitySort sort(mesh, fx::SortMethod::Xmpvo);
                std::vector<std::uint32_t> order;
                try {
                    sort.sort(fx::Camera::parse("eye=2,1.5,1.2,target=0.25,0.25,0.25,up=0,0,1"), order);
                } catch (const fx::Error& e) {
                    std::printf("%s\n", e.what());
                    return 1;
                }
                return 0;
            },
            kCpu);
        require_refused(r, {"visibility sort (xmpvo)", "sort-pairs limit", "overlap"});
    }
    SECTION("200,000 effects (limit raised): the unique-name check is no longer quadratic") {
        const RunResult r = fx_test::run_limited(
            [] {
                std::string text = "{\"effects\": [";
                for (int i = 0; i < 200000; ++i)
                    text += std::string(i ? "," : "") + "{\"type\": \"laser_cone\", \"name\": \"l" + std::to_string(i) +
                            "\", \"enabled\": false, \"slices\": 1, \"transfer_function\": \"fire.json\"}";
                text += "], \"camera\": {\"eye\": [3, -4, 2], \"target\": [0, 0, 0]}}";
                fx::ResourceLimits limits = fx::resource_limits();
                limits.effects = 200000;
                limits.scene_cells = std::uint64_t(1) << 40;
                fx::set_resource_limits(limits);
                const terrain::Scene scene =
                    terrain::parse_scene(text, "many.json", fx_test::source_path("content/transfer_functions"));
                return scene.effects.size() == 200000 ? 0 : 2;
            },
            kCpu);
        require_accepted(r);
    }
    SECTION("a named pipe nobody writes to, as a mesh, a transfer function and a scene") {
        const std::string fifo = file("pipe.vtk");
        std::filesystem::remove(fifo);
        REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
        const std::vector<std::string> wait = {"--limit", "input-wait=1"};
        auto with_wait = [&](std::vector<std::string> args) {
            args.insert(args.end(), wait.begin(), wait.end());
            return args;
        };
        const std::string mesh = write_vtk("pipe_box.vtk", fx_test::hex_box(1, 1, 1));
        require_refused(run_cellfx(with_wait(scanline(fifo, file("x.pfm")))), {"pipe.vtk", "nothing arrived from this pipe for 1 s", "input-wait"});
        require_refused(run_cellfx(with_wait(scanline(mesh, file("x.pfm"), {"--tf", fifo}))), {"pipe.vtk", "nothing arrived"});
        const std::string scene_fifo = file("pipe.json");
        std::filesystem::remove(scene_fifo);
        REQUIRE(mkfifo(scene_fifo.c_str(), 0600) == 0);
        require_refused(run_cellfx(with_wait({"render", scene_fifo, "--out", file("x.png")})), {"pipe.json", "nothing arrived"});
    }
    SECTION("a pipe with a writer is read (process substitution works)") {
        const std::string fifo = file("pipe_fed.vtk");
        std::filesystem::remove(fifo);
        REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
        const std::string mesh = write_vtk("pipe_source.vtk", fx_test::hex_box(2, 2, 2));
        std::ifstream in(mesh, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::signal(SIGPIPE, SIG_IGN); // a reader that went away is an EPIPE, not this test's death
        std::thread writer([&] {
            const int fd = ::open(fifo.c_str(), O_WRONLY); // waits until cellfx opens it
            for (std::size_t at = 0; fd >= 0 && at < bytes.size();) {
                const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
                if (n <= 0) break;
                at += std::size_t(n);
            }
            if (fd >= 0) ::close(fd);
        });
        const RunResult r = run_cellfx(scanline(fifo, file("pipe_fed.pfm")));
        const int unblock = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK); // in case cellfx never opened it
        writer.join();
        if (unblock >= 0) ::close(unblock);
        require_accepted(r);
        require_accepted(run_cellfx(scanline(mesh, file("pipe_source.pfm"))));
        CHECK(max_difference(file("pipe_fed.pfm"), file("pipe_source.pfm")) == 0.0);
    }
}

TEST_CASE("hostile input: unbounded memory — devices, effect resolutions, image sizes", "[hostile]") {
    const std::string mesh = write_vtk("box_memory.vtk", fx_test::hex_box(1, 1, 1));
    SECTION("/dev/zero and /dev/urandom as inputs: refused from their first bytes, or at the byte budget") {
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--tf", "/dev/zero"})), {"/dev/zero", "NUL", "not UTF-8 JSON"});
        require_refused(run_cellfx({"render", "/dev/zero", "--out", file("x.png")}), {"/dev/zero", "byte 0", "four zero bytes"});
        require_refused(run_cellfx({"render", "/dev/urandom", "--out", file("x.png"), "--limit", "file-bytes=1000000"}),
                        {"/dev/urandom", "file-bytes limit of 1,000,000", "not a regular file"});
        const std::string zero_json = file("zero.json");
        std::filesystem::remove(zero_json);
        std::filesystem::create_symlink("/dev/zero", zero_json);
        require_refused(run_cellfx({"render", zero_json, "--out", file("x.png")}), {"zero.json", "NUL"});
        require_refused(run_cellfx({"render", effects_scene("tf_zero.json", R"({"type": "laser_cone", "transfer_function": "/dev/zero"})"),
                                "--out", file("x.png")}),
                        {"tf_zero.json", "effects[0].transfer_function", "/dev/zero", "NUL"});
        const std::string hm = write("heightmap_zero.json", R"({"terrain": {"height_map": "/dev/zero"},
            "camera": {"eye": [0, -10, 5], "target": [0, 0, 0]}})");
        require_refused(run_cellfx({"render", hm, "--out", file("x.png")}), {"heightmap_zero.json", "terrain.height_map", "not a PNG file"});
    }
    SECTION("effect resolutions within their documented ranges but over the effect-cells budget") {
        require_refused(run_cellfx({"render", effects_scene("fire_256.json", campfire(", \"cells_across\": 256, \"cells_up\": 256")),
                                "--out", file("x.png")}),
                        {"fire_256.json", "effects[0]", "16,777,216 cells", "effect-cells limit"});
        require_refused(run_cellfx({"render",
                                effects_scene("light_big.json", R"({"type": "search_light", "transfer_function": "TF",
                                    "segments": 256, "rings": 64, "slices": 1024})"),
                                "--out", file("x.png")}),
                        {"light_big.json", "effects[0]", "effect-cells limit"});
    }
    SECTION("image sizes: the image-pixels budget, then the scan-line frame budget") {
        require_refused(run_cellfx({"render", mesh, "--size", "16384x16384", "--out", file("x.pfm")}), {"--size 16384x16384", "image-pixels limit"});
        require_refused(run_cellfx({"render", mesh, "--path", "pcp", "--size", "16384x16384", "--out", file("x.png")}), {"image-pixels limit"});
        require_refused(run_cellfx({"render", mesh, "--size", "16384x16384", "--out", file("x.pfm"), "--limit", "image-pixels=300000000"}),
                        {"box_memory.vtk", "16384x16384 frame", "frame-bytes limit"});
        const std::string scene = write_scene("scene_huge.json", R"({"effects": [{"type": "laser_cone", "transfer_function": "TF"}],
            "camera": {"eye": [3, -4, 2], "target": [0, 0, 0]}, "render": {"width": 16384, "height": 16384}})");
        require_refused(run_cellfx({"render", scene, "--out", file("x.png")}), {"scene_huge.json", "render", "image-pixels limit"});
    }
    SECTION("scan-line workers out of memory: an error naming the budget or the memory, never an abort") {
        // 4,000 layers seen face on: 2,000 pixels a line × 4,001 crossings = 8 M fragments
        // (640 MB) for one scan line of one worker.
        const std::string deep = write_vtk("deep.vtk", fx_test::hex_box(1, 1, 4000));
        const std::vector<std::string> view = {"--size", "2000x8", "--camera", "eye=0.5,0.5,3,target=0.5,0.5,0.5,up=0,1,0,ortho=0.01"};
        std::vector<std::string> args = {"render", deep, "--path", "scanline", "--threads", "2", "--out", file("deep.pfm")};
        args.insert(args.end(), view.begin(), view.end());
        auto with = [&](std::vector<std::string> extra) {
            std::vector<std::string> a = args;
            a.insert(a.end(), extra.begin(), extra.end());
            return a;
        };
        require_refused(run_cellfx(with({"--limit", "frame-bytes=100000000"})), {"deep.vtk", "scan line", "frame-bytes limit"});
        if (fx_test::kAddressSpaceLimited) // the allocation failure needs the 400 MB address-space limit
            require_refused(run_cellfx(with({"--limit", "frame-bytes=100000000000"}), {std::uint64_t(400) << 20, 60.0}),
                            {"deep.vtk", "out of memory"});
    }
    SECTION("counts: a header claiming 40 million points in a small file, and a file over a lowered budget") {
        const std::string claim = write("claims_points.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                                                             "POINTS 40000000 float\n0 0 0\n");
        require_refused(run_cellfx({"info", claim}), {"claims_points.vtk", "truncated POINTS", "120000000 values"});
        require_refused(run_cellfx({"info", mesh, "--limit", "mesh-points=7"}),
                        {"box_memory.vtk", "line 5", "POINTS needs 8 points", "mesh-points limit of 7"});
    }
}

TEST_CASE("hostile input: messages that say what to fix", "[hostile]") {
    fx::CellMesh tet = one_tet();
    SECTION("a constant field renders (a normalized function's low end); all-NaN and all-Inf fields are named") {
        tet.scalars = {{"c", std::vector<float>(4, 7.0f)}};
        fx::write_vtk_legacy(tet, file("constant.vtk"), false);
        require_accepted(run_cellfx(scanline(file("constant.vtk"), file("constant.pfm"), {"--camera", "eye=2,1.5,1.2,target=0.25,0.25,0.25"})));
        // The same as the function's first point everywhere: a constant function at s = 7.
        const std::string flat_tf = write("constant_tf.json", R"({"points": [[7, 0.1, 0.25, 0.9, 0.02]]})");
        require_accepted(run_cellfx(scanline(file("constant.vtk"), file("constant_ref.pfm"),
                                         {"--camera", "eye=2,1.5,1.2,target=0.25,0.25,0.25", "--tf", flat_tf})));
        CHECK(mean_value(file("constant.pfm")) > 0.0);
        CHECK(max_difference(file("constant.pfm"), file("constant_ref.pfm")) == 0.0);
        for (const float bad : {std::nanf(""), INFINITY}) {
            tet.scalars = {{"p", std::vector<float>(4, bad)}};
            fx::write_vtk_legacy(tet, file("bad_field.vtk"), true);
            require_refused(run_cellfx(scanline(file("bad_field.vtk"), file("x.pfm"))),
                            {"bad_field.vtk", "field 'p' is", "at point 0", "and 3 more points"});
        }
    }
    SECTION("a key given twice in one JSON object is named, not one of the two silently kept") {
        const std::string mesh = write_vtk("dup_box.vtk", fx_test::hex_box(1, 1, 1));
        const std::string tf = write("dup_tf.json", R"({"points": [[0, 1, 0.5, 0.2, 1], [1, 1, 0.5, 0.2, 1]], "points": [[0, 0, 0, 0, 0]]})");
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--tf", tf})), {"dup_tf.json", "\"points\" appears twice"});
        const std::string scene = write_scene("dup_scene.json", R"({"effects": [{"type": "laser_cone", "transfer_function": "TF", "slices": 4, "slices": 64}],
 "camera": {"eye": [3, -4, 2], "target": [0, 0, 0]}})");
        require_refused(run_cellfx({"render", scene, "--out", file("x.png")}), {"dup_scene.json", "\"slices\" appears twice"});
    }
    SECTION("coordinates of 1e300 are named as such, not blamed on the camera") {
        fx::CellMesh far = one_tet();
        for (glm::dvec3& p : far.points) p *= 1e300;
        require_refused(run_cellfx(scanline(write_vtk("far.vtk", far), file("x.pfm"))), {"far.vtk", "point 1", "beyond ±1e+18"});
    }
    SECTION("files that used to fall through to the PLOT3D reader") {
        const std::string ucd = write("negative.inp", "# a UCD file\n-4 1 0 0 0\n");
        require_refused(run_cellfx({"info", ucd}), {"negative.inp", "line 2", "number of nodes is negative"});
        const std::string json_mesh = write("scene.txt", "{\"effects\": []}\n");
        require_refused(run_cellfx({"info", json_mesh}), {"scene.txt", "it is text", "looks like JSON"});
        const std::string upper = write_scene("SCENE.JSON", R"({"effects": [{"type": "laser_cone", "transfer_function": "TF"}]})");
        require_refused(run_cellfx({"render", upper, "--out", file("x.png")}), {"SCENE.JSON", "camera", "is required"});
    }
    SECTION("truncated PLOT3D and a lying record marker: what the header says and what the file holds") {
        fx::Plot3dBlock b;
        b.dims = {4, 3, 2};
        for (int i = 0; i < 24; ++i) b.points.push_back(glm::dvec3(i % 4, (i / 4) % 3, i / 12));
        fx::Plot3dFormat f;
        f.record_markers = true;
        fx::write_plot3d({b}, f, file("grid.xyz"));
        std::ifstream in(file("grid.xyz"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        write("truncated.xyz", bytes.substr(0, 100));
        require_refused(run_cellfx({"info", file("truncated.xyz")}), {"truncated.xyz", "4 x 3 x 2", "truncated"});
        std::string lying = bytes;
        lying[23] = char(lying[23] + 16); // the coordinates' opening marker (big-endian, low byte)
        write("lying.xyz", lying);
        // Named at the marker's byte as the file's fault, not as "not a PLOT3D grid file".
        const RunResult r = run_cellfx({"info", file("lying.xyz")});
        require_refused(r, {"lying.xyz: byte 20: a damaged or lying record marker", "says 304 bytes, but the record holds 288",
                            "every other record marker agrees"});
        CHECK_THAT(r.output, !Catch::Contains("not a PLOT3D grid file"));
    }
    SECTION("a q file of NaN or Inf is blamed on the q file, not the grid") {
        fx::Plot3dBlock b;
        b.dims = {3, 3, 2};
        for (int i = 0; i < 18; ++i) b.points.push_back(glm::dvec3(i % 3, (i / 3) % 3, i / 9));
        for (const double bad : {std::nan(""), HUGE_VAL}) {
            for (std::vector<double>& q : b.q) q.assign(18, bad);
            const std::string q = file(std::isnan(bad) ? "all_nan.q" : "all_inf.q");
            fx::write_plot3d({b}, fx::Plot3dFormat{}, file("q_grid.xyz"), q);
            std::vector<std::string> args = scanline(file("q_grid.xyz"), file("x.pfm"), {"--camera", "eye=4,3,3,target=1,1,0.5"});
            args.insert(args.begin() + 2, q); // render GRID Q ...
            const RunResult r = run_cellfx(args);
            require_refused(r, {q + ": field 'density' is", "at point 0 (and 17 more points)"});
            CHECK_THAT(r.output, !Catch::Contains("q_grid.xyz: field"));
        }
    }
    SECTION("a scene file with a second file, convert --out naming a folder, 1e999 in a scene") {
        const std::string scene = effects_scene("alone.json", campfire(""));
        require_refused(run_cellfx({"render", scene, file("extra.q"), "--out", file("x.png")}),
                        {"alone.json: a scene file is rendered alone", "extra.q"});
        const std::string mesh = write_vtk("convert_me.vtk", fx_test::hex_box(1, 1, 1));
        std::filesystem::create_directories(file("a_folder.vtk"));
        require_refused(run_cellfx({"convert", mesh, "--out", file("a_folder.vtk")}), {"--out", "a_folder.vtk: is a folder, not a file"});
        require_refused(run_cellfx({"convert", mesh, "--out", dir()}), {"--out", "is a folder, not a file"});
        require_refused(run_cellfx({"convert", mesh, "--out", file("mesh.txt")}), {"--out", "mesh.txt", "FILE.vtk"});
        const std::string huge = effects_scene("e999.json", campfire(", \"base_radius\": 1e999"));
        require_refused(run_cellfx({"render", huge, "--out", file("x.png")}),
                        {"e999.json: byte", "(at effects[0].base_radius)", "the number 1e999 is beyond the range of a double"});
    }
    SECTION("vertical_scale and an aurora ceiling of 1e300, named by key") {
        const std::string st_helens = fx_test::source_path("content/terrain/st_helens_257.png");
        const std::string scale = write("vertical.json", "{\"terrain\": {\"height_map\": \"" + st_helens +
                                                             "\", \"vertical_scale\": 1e300}, \"camera\": {\"eye\": [0, -10, 5], \"target\": [0, 0, 0]}}");
        require_refused(run_cellfx({"render", scale, "--out", file("x.png")}), {"vertical.json", "terrain.vertical_scale", "1e+300"});
        const std::string scale15 = write("vertical15.json", "{\"terrain\": {\"height_map\": \"" + st_helens +
                                                                 "\", \"vertical_scale\": 1e15}, \"camera\": {\"eye\": [0, -10, 5], \"target\": [0, 0, 0]}}");
        require_refused(run_cellfx({"render", scale15, "--out", file("x.png")}), {"vertical15.json", "terrain.height_map", "heights reach", "vertical_scale"});
        const std::string aurora = write_scene("ceiling.json", R"({"aurora": {"ceiling": 1e300, "spacing": 10, "transfer_function": "TF"},
            "effects": [], "camera": {"eye": [0, -10, 5], "target": [0, 0, 0]}})");
        require_refused(run_cellfx({"render", aurora, "--out", file("x.png")}), {"ceiling.json", "aurora.ceiling", "1e+300"});
    }
    SECTION("a folder named like a scene, UTF-16 text, an empty file, a missing file, an unknown limit") {
        std::filesystem::create_directories(file("folder.json"));
        require_refused(run_cellfx({"render", file("folder.json"), "--out", file("x.png")}), {"folder.json", "is a folder, not a scene file"});
        const std::string utf16 = write("utf16.json", std::string("\xFF\xFE{\0}\0", 6));
        require_refused(run_cellfx({"render", utf16, "--out", file("x.png")}), {"utf16.json", "UTF-16"});
        const std::string mesh = write_vtk("box_messages.vtk", fx_test::hex_box(1, 1, 1));
        require_refused(run_cellfx(scanline(mesh, file("x.pfm"), {"--tf", utf16})), {"utf16.json", "UTF-16"});
        require_refused(run_cellfx({"info", write("empty.vtk", "")}), {"empty.vtk", "empty file"});
        require_refused(run_cellfx({"info", file("no_such_file.vtk")}), {"no_such_file.vtk", "cannot open the mesh file"});
        require_refused(run_cellfx({"info", mesh, "--limit", "cells=5"}), {"unknown limit 'cells'", "mesh-cells"});
    }
}

TEST_CASE("hostile input: outputs that cannot be written are errors naming the file, nothing half written", "[hostile]") {
    // Every file cellfx writes goes through io::OutputFile (tests/test_output_file.cpp has the
    // library's cases). Here the commands: exit 1 and the file and reason named, where they
    // used to print "wrote ..." and exit 0 for a small PNG to a full disk. The failures are
    // ones that fail for root too: /dev/full, /sys, a file where a folder belongs, a file-size
    // limit part way through.
    const std::string mesh = write_vtk("out_box.vtk", fx_test::hex_box(2, 2, 2));
    const std::string out = file("outputs");
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
    const auto link_to_full = [&](const std::string& name) {
        std::filesystem::create_symlink("/dev/full", out + "/" + name);
        return out + "/" + name;
    };
    SECTION("a full disk: render's PNG and PFM, convert's VTK, bench render's JSON") {
        for (const char* name : {"full.png", "full.pfm"}) {
            const RunResult r = run_cellfx(scanline(mesh, link_to_full(name)));
            require_refused(r, {std::string(name) + ": cannot write: No space left on device"});
            CHECK_THAT(r.output, !Catch::Contains("wrote"));
        }
        require_refused(run_cellfx({"convert", mesh, "--out", link_to_full("full.vtk")}),
                        {"full.vtk: cannot write: No space left on device"});
        require_refused(run_cellfx({"bench", "render", mesh, "--paths", "pcp-exact", "--views", "1", "--size", "16x16",
                                    "--json", link_to_full("full.json")},
                                   kGl),
                        {"full.json: cannot write: No space left on device"});
    }
    SECTION("folders that take no file: refused before the frame is rendered") {
        write("plain.txt", "a file, not a folder\n");
        const RunResult r = run_cellfx(scanline(mesh, file("plain.txt") + "/frame.png"));
        require_refused(r, {"--out", "plain.txt/frame.png: cannot create a file in the folder", "Not a directory"});
        // No frame was rendered: none of render's timings (a bare "scan" would also match a
        // checkout whose path holds the word, as the message names the file).
        CHECK_THAT(r.output, !Catch::Contains("wrote") && !Catch::Contains("y-buckets") && !Catch::Contains("crossings"));
        require_refused(run_cellfx(scanline(mesh, "/sys/cellfx_frame.png")),
                        {"--out /sys/cellfx_frame.png: cannot create a file in the folder '/sys'"});
        require_refused(run_cellfx(scanline(mesh, out + "/missing/frame.png")), {"frame.png", "No such file or directory"});
        require_refused(run_cellfx({"bench", "accuracy", "--quick", "--out", "/sys/cellfx_accuracy"}),
                        {"/sys/cellfx_accuracy: cannot create the folder"});
        require_refused(run_cellfx({"bench", "accuracy", "--quick", "--out", file("plain.txt")}),
                        {"plain.txt: cannot create the folder"});
    }
    SECTION("a disk that fills part way: the last good file stays, no temporary is left") {
        write("outputs/keep.pfm", "the last good frame\n");
        RunLimits limited = kCpu;
        limited.file_size = 64 << 10; // the 256 x 256 PFM needs 768 KiB
        const RunResult r = run_cellfx(scanline(mesh, out + "/keep.pfm", {"--size", "256x256"}), limited);
        require_refused(r, {"keep.pfm: cannot write: File too large"});
        std::ifstream in(out + "/keep.pfm");
        CHECK(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()) == "the last good frame\n");
        std::vector<std::string> left;
        for (const auto& e : std::filesystem::directory_iterator(out)) left.push_back(e.path().filename().string());
        CHECK(left == std::vector<std::string>{"keep.pfm"});
    }
}

TEST_CASE("hostile input: every numeric option is bounded before anything is allocated", "[hostile]") {
    // `cellfx limits` lists every numeric option of every subcommand with its range; each is
    // tried here just past its range, under the 2 GiB and 60 s limits, and must be refused by
    // name before the command reads or builds anything. `bench sort --views 1000000000` and
    // `--cells 1000000000` grew to 3.8-6.5 GB before an out-of-memory message.
    const RunResult listed = run_cellfx({"limits"});
    require_accepted(listed);
    const std::string mesh = write_vtk("options_box.vtk", fx_test::hex_box(1, 1, 1));
    const std::string scene = effects_scene("options_scene.json", campfire(""));
    std::istringstream lines(listed.output.substr(listed.output.find("option ranges")));
    std::string line;
    std::getline(lines, line);
    int tried = 0;
    while (std::getline(lines, line)) {
        // "  bench sort --views            2 .. 360   views sorted per mesh"
        std::istringstream words(line);
        std::vector<std::string> command;
        std::string word;
        while (words >> word && word.rfind("--", 0) != 0) command.push_back(word);
        REQUIRE_FALSE(command.empty());
        const std::string option = word;
        std::string range;
        std::getline(words, range);
        // A value just past the range's top ("1 .. 256": 257); a Number's top times ten; the
        // composite ones their own way.
        std::string value;
        if (option == "--size" && range.find("a side") != std::string::npos) value = "16385x1"; // WxH
        else if (option == "--background") value = "2,0,0";
        else if (option == "--camera") value = "eye=1e19,0,0";
        else {
            const std::size_t dots = range.find(" .. ");
            if (dots != std::string::npos) {
                std::istringstream after(range.substr(dots + 4)); // "256 each   thread counts to time"
                std::string top, next;
                after >> top >> next;
                top.erase(std::remove(top.begin(), top.end(), ','), top.end());
                value = std::to_string(std::stoll(top) + 1);
                if (next == "each") value = "1," + value; // a list: its second item
            } else {
                const std::string top = range.substr(range.find(',') + 2, range.find(']') - range.find(',') - 2);
                value = format_double(std::stod(top) * 10.0);
            }
        }
        std::vector<std::string> args = command;
        if (command[0] == "render") {
            const bool scene_option = option == "--time" || option == "--pixel-error";
            args.push_back(scene_option ? scene : mesh);
            args.insert(args.end(), {"--out", file("x.png")});
        } else if (command[0] == "convert") {
            args.insert(args.end(), {"--synthetic", "duct", "--out", file("x.vtk")});
        } else if (command.size() > 1 && command[1] == "render") {
            args.push_back(mesh);
        }
        args.insert(args.end(), {option, value});
        INFO(line);
        std::string shown;
        for (const std::string& a : args) shown += a + " ";
        INFO(shown);
        const RunResult r = run_cellfx(args);
        require_refused(r, {option});
        CHECK_THAT(r.output, Catch::Contains("outside") || Catch::Contains("beyond") || Catch::Contains("over the"));
        ++tried;
    }
    CHECK(tried >= 30);
    // Within the range, over the budget: named by the limit, raised by --limit.
    require_refused(run_cellfx({"bench", "sort", "--cells", "1000000000"}), {"bench sort --cells 1000000000", "mesh-cells limit"});
    require_refused(run_cellfx({"bench", "sort", "--views", "1000000000"}), {"bench sort --views", "outside 2 .. 360"});
    require_refused(run_cellfx({"bench", "terrain", "--sizes", "8193"}), {"--sizes 8193", "height-samples limit"});
}

TEST_CASE("hostile input: the fem_viewer sample reads files through the same budgets", "[hostile]") {
    const std::string viewer = std::string(CELLFX_SAMPLE_DIR) + "/fem_viewer";
    const RunResult zero = fx_test::run_program({viewer, "--headless", "--frames", "1", "/dev/zero"}, kGl);
    require_refused(zero, {"/dev/zero", "four zero bytes"});
    fx::CellMesh bow = fx_test::hex_box(1, 1, 1);
    std::swap(bow.cell_vertices(0)[4], bow.cell_vertices(0)[6]);
    const RunResult bowtie = fx_test::run_program({viewer, "--headless", "--frames", "1", write_vtk("viewer_bowtie.vtk", bow)}, kGl);
    require_refused(bowtie, {"viewer_bowtie.vtk", "folds over itself"});
}
