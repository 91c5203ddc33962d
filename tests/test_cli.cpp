// Every subcommand of the `cellfx` command, run as a user runs it (under time and memory limits,
// tests/process_runner.hpp): info, render, convert, limits, and each benchmark in a quick
// configuration — small meshes and images, one or two frames — that still verifies what it
// times, with the rows it prints checked. `bench accuracy --quick`, `bench render` and
// `convert` have their own suites (test_bench_accuracy.cpp, test_bench_render.cpp); here they
// run once more in their smallest form so that this file names every subcommand.
// tests/CMakeLists.txt checks that this suite is built (the `cli_suites` test).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fx/image.hpp"
#include "image_check.hpp"
#include "process_runner.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

fx_test::RunResult run_cellfx(std::vector<std::string> args, double seconds = 120.0) {
    args.insert(args.begin(), CELLFX_CLI);
    fx_test::RunLimits limits;
    limits.address_space = std::uint64_t(8) << 30; // GL drivers map a lot of address space
    limits.seconds = seconds;
    return fx_test::run_program(args, limits);
}

// Exit 0, and the output holds every one of `lines` (each a piece of a line it prints).
void require_ran(const fx_test::RunResult& r, const std::vector<std::string>& lines) {
    INFO(r.describe());
    REQUIRE_FALSE(r.timed_out);
    REQUIRE(r.signal == 0);
    REQUIRE(r.exit_code == 0);
    for (const std::string& l : lines) CHECK_THAT(r.output, Catch::Contains(l));
}

std::string out_dir(const std::string& name) {
    const std::string dir = fx_test::output_path("cli_" + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

const std::string kFin = fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin");
const std::string kFinQ = fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin");

} // namespace

TEST_CASE("cellfx: usage, unknown commands and the resource limits", "[cli]") {
    const fx_test::RunResult none = run_cellfx({});
    CHECK(none.exit_code == 2);
    CHECK_THAT(none.output, Catch::Contains("usage: cellfx <command>"));
    require_ran(run_cellfx({"--help"}), {"info FILE", "render FILE", "convert FILE", "bench NAME", "limits"});
    const fx_test::RunResult unknown = run_cellfx({"frobnicate"});
    CHECK(unknown.exit_code == 2);
    CHECK_THAT(unknown.output, Catch::Contains("unknown command 'frobnicate'"));
    require_ran(run_cellfx({"limits"}), {"resource limits", "mesh-cells      16,777,216", "effects         256"});
    // --limit changes what `limits` prints and what every command accepts.
    require_ran(run_cellfx({"limits", "--limit", "effects=12"}), {"effects         12 "});
    const fx_test::RunResult bad = run_cellfx({"limits", "--limit", "nonsense=3"});
    CHECK(bad.exit_code == 1);
    CHECK_THAT(bad.output, Catch::Contains("nonsense"));
    require_ran(run_cellfx({"bench", "--help"}), {"scanline", "pcp", "sort", "terrain", "absorption", "effects", "flicker",
                                              "render", "accuracy", "noise"});
    const fx_test::RunResult no_bench = run_cellfx({"bench", "nosuch"});
    CHECK(no_bench.exit_code == 1);
    CHECK_THAT(no_bench.output, Catch::Contains("unknown benchmark 'nosuch'"));
}

TEST_CASE("cellfx info, render and convert", "[cli]") {
    require_ran(run_cellfx({"info", kFin, kFinQ}), {"37479", "hexahedron", "density"});
    const std::string dir = out_dir("render");
    require_ran(run_cellfx({"render", kFin, kFinQ, "--path", "scanline", "--size", "48x32", "--out", dir + "/fin.pfm"}), {});
    CHECK(std::filesystem::file_size(dir + "/fin.pfm") > 48 * 32 * 12);
    require_ran(run_cellfx({"render", fx_test::source_path("content/scenes/campfire.json"), "--size", "48x32", "--out",
                        dir + "/campfire.png"}),
                {});
    CHECK(std::filesystem::exists(dir + "/campfire.png"));
    require_ran(run_cellfx({"convert", "--synthetic", "duct", "--cells", "500", "--out", dir + "/duct.vtk"}), {});
    require_ran(run_cellfx({"info", dir + "/duct.vtk"}), {"tetra"});
}

TEST_CASE("cellfx render --path auto: the pick and why, its picture, bad options", "[cli][auto]") {
    const std::string dir = out_dir("auto");
    const fx_test::RunResult r =
        run_cellfx({"render", kFin, kFinQ, "--path", "auto", "--size", "64x40", "--out", dir + "/auto.pfm"});
    require_ran(r, {"auto picked ", "predicted for 64x40", "<= accuracy 0.001", "(auto)"});
    // "wrote DIR/auto.pfm (64x40, path NAME (auto), ...": the picked path, which must be one
    // that meets the default accuracy for the default (emission-absorption) model.
    const std::string marker = "64x40, path ";
    const std::size_t at = r.output.find(marker);
    REQUIRE(at != std::string::npos);
    const std::string picked = r.output.substr(at + marker.size(), r.output.find(' ', at + marker.size()) - at - marker.size());
    INFO(r.output);
    REQUIRE((picked == "scanline" || picked == "absorption-exact"));
    // Its picture passes that path's stated check against the scan-line reference.
    require_ran(run_cellfx({"render", kFin, kFinQ, "--path", "scanline", "--size", "64x40", "--out", dir + "/ref.pfm"}), {});
    const fx::Image actual = fx::read_pfm(dir + "/auto.pfm"), expected = fx::read_pfm(dir + "/ref.pfm");
    fx_test::check_frame("cli_auto_" + picked, actual, expected,
                         picked == "scanline" ? verify::same_picture(0.0, "the reference itself")
                                              : verify::stated(verify::Path::AbsorptionExact));
    // Another model changes the candidates: emission is drawn by scanline or pcp-exact.
    const fx_test::RunResult emission = run_cellfx(
        {"render", kFin, kFinQ, "--path", "auto", "--model", "emission", "--size", "32x20", "--out", dir + "/e.pfm"});
    require_ran(emission, {"auto picked "});
    CHECK((emission.output.find("path scanline (auto)") != std::string::npos ||
           emission.output.find("path pcp-exact (auto)") != std::string::npos));

    // A mesh the scan-line renderer refuses (one cell twice) leaves it out, and says why.
    {
        const std::string dup = dir + "/dup.vtk";
        std::ofstream(dup) << "# vtk DataFile Version 3.0\none tetrahedron twice\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                              "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\nCELLS 2 10\n4 0 1 2 3\n4 0 1 2 3\n"
                              "CELL_TYPES 2\n10\n10\nPOINT_DATA 4\nSCALARS s double 1\nLOOKUP_TABLE default\n0 0.3 0.6 1\n";
        require_ran(run_cellfx({"render", dup, "--path", "auto", "--size", "16x16", "--out", dir + "/dup.pfm"}),
                    {"auto picked absorption-exact", "scanline left out: scan-line renderer: cell 1 has the same points as cell 0"});
    }

    // Bad input: named by the option, exit 1, nothing rendered.
    const auto refused = [&](std::vector<std::string> extra, const std::string& message) {
        std::vector<std::string> args = {"render", kFin, kFinQ, "--size", "32x20", "--out", dir + "/bad.pfm"};
        args.insert(args.end(), extra.begin(), extra.end());
        const fx_test::RunResult bad = run_cellfx(args);
        INFO(bad.describe());
        CHECK(bad.exit_code == 1);
        CHECK_THAT(bad.output, Catch::Contains(message));
    };
    refused({"--path", "automatic"}, "--path: unknown render path 'automatic'");
    refused({"--path", "auto", "--accuracy", "2"}, "--accuracy");
    refused({"--path", "auto", "--accuracy", "0"}, "--accuracy");
    refused({"--path", "auto", "--accuracy", "nan"}, "--accuracy");
    refused({"--path", "scanline", "--accuracy", "0.01"}, "--accuracy is an option of --path auto");
    refused({"--path", "auto", "--accuracy", "1e-6"}, "--accuracy: no render path meets accuracy 1e-06");
    refused({"--path", "auto", "--fog"}, "--fog is an option of --path pcp-exact");
    CHECK_FALSE(std::filesystem::exists(dir + "/bad.pfm"));
    const fx_test::RunResult scene = run_cellfx({"render", fx_test::source_path("content/scenes/campfire.json"), "--path",
                                                 "auto", "--size", "32x20", "--out", dir + "/scene.png"});
    CHECK(scene.exit_code == 1);
    CHECK_THAT(scene.output, Catch::Contains("--path auto: renders a mesh"));
}

TEST_CASE("cellfx bench scanline, pcp and sort, quick", "[cli][bench]") {
    require_ran(run_cellfx({"bench", "scanline", "--size", "64x48", "--repeat", "1", "--scale", "0.1", "--threads", "1,2"}),
                {"grids 9", "1 thread", "2 threads", "speed-up 2 threads", "renderer total"});
    require_ran(run_cellfx({"bench", "pcp", "--sizes", "48", "--repeat", "1", "--grid", "6"}),
                {"blunt fin: 37479 cells", "hex grid 6^3: 216 cells", "reference (peak", "mean |err|", "non-empty (max"});
    require_ran(run_cellfx({"bench", "sort", "--cells", "3000", "--views", "2", "--repeat", "1"}),
                {"grid:", "jittered grid:", "C-shape:", "centroid", "mpvo", "xmpvo", "power",
                 "verified: every order is a permutation"});
}

TEST_CASE("cellfx bench terrain and absorption, quick", "[cli][bench]") {
    require_ran(run_cellfx({"bench", "terrain", "--sizes", "65", "--lod-frames", "3", "--views", "1", "--frames", "1",
                        "--size", "96x72"}),
                {"65x65 height field", "full resolution: 8192 triangles", "pixels changed", "96x72", "pcp-exact",
                 "absorption-exact"});
    require_ran(run_cellfx({"bench", "absorption", "--size", "48x48", "--frames", "1", "--cells", "3000", "--scenes", "box",
                        "--sort", "xmpvo"}),
                {"tet box", "xmpvo    absorption ", "xmpvo    absorption-exact", "Verified: finite"});
}

TEST_CASE("cellfx bench effects, flicker and noise, quick", "[cli][bench]") {
    const std::string dir = out_dir("bench_effects");
    require_ran(run_cellfx({"bench", "effects", "--scenes", "campfire", "--paths", "pcp-exact", "--frames", "1", "--size",
                        "80x60", "--samples", "campfire", "--fx-scale", "1", "--gl-calls", "--json", dir + "/effects.json"}),
                {"campfire     fire", "samples:", "CPU per frame in a game", "GL state", "teleport",
                 "GL calls per steady frame, campfire", "glDrawArrays", "wrote"});
    CHECK(std::filesystem::file_size(dir + "/effects.json") > 100);
    require_ran(run_cellfx({"bench", "flicker", "--frames", "3", "--size", "80x60", "--fx-scale", "1,0.5"}),
                {"flicker: frame-to-frame change", "80x60, 3 frames", "edge px %"});
    require_ran(run_cellfx({"bench", "noise", "--rounds", "1", "--size", "16"}),
                {"perlin2", "simplex4", "fbm3 4 octaves"});
}

TEST_CASE("cellfx bench render and accuracy, smallest", "[cli][bench]") {
    const std::string dir = out_dir("bench_accuracy");
    require_ran(run_cellfx({"bench", "render", fx_test::source_path("content/meshes/vtk_cells/tetraMesh.vtk"), "--views", "2",
                        "--size", "48x48", "--paths", "pcp-exact,mip"}),
                {"pcp-exact", "mip", " ok "});
    require_ran(run_cellfx({"bench", "accuracy", "--quick", "--scenes", "campfire", "--frames", "1", "--out", dir}, 300.0),
                {"campfire"});
    CHECK(std::filesystem::exists(dir + "/accuracy.csv"));
}
