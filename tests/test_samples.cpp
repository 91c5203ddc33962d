// The six samples (samples/<name>), run as the programs users start: headless for a few
// frames, and one in a real GLFW window under Xvfb (ctest runs "[samples-window]" through
// xvfb-run). Each run's PNGs are read back and checked:
//   - exit status 0, one PNG per frame, the frame not empty (it differs from the background);
//   - frame 0 against an independent render of the same scene and view: terrain::SceneRenderer
//     ::render_to_image (what `cellfx render SCENE.json` does: its own float target, no window,
//     no frame loop) for the scene samples, the scan-line reference (fx::ScanlineRenderer) for
//     fem_viewer; diff PNGs in the test output folder on failure;
//   - animated samples: the last frame differs from the first;
//   - the stats line only covers its panel; bad arguments give exit 2 and a message;
//   - the tuning panel (samples/common/panel.hpp): a control set through its code path (--set)
//     changes the frame as the same cellfx::Module call does in SceneRenderer's own frame; the
//     scene it saves renders the same frame in the sample and in `cellfx render`; its accuracy
//     check reports `cellfx bench accuracy`'s figures for the same frame; in a real window it
//     draws where it is and nowhere else, and its check runs while the frames go on.
// Pixels are 8-bit (the window's format), so "finite" is checked on the printed statistics
// (no nan/inf), not on the pixels.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <sstream>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/search_light.hpp"
#include "cellfx_names.hpp"
#include "gl_fixture.hpp"
#include "searchlight/drone.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace {

constexpr int kWidth = 160, kHeight = 120, kFrames = 3;

struct Run {
    int status = -1;
    std::string output; // stdout and stderr
};

Run run(const std::string& command) {
    Run r;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::array<char, 4096> buffer;
    for (std::size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) r.output.append(buffer.data(), n);
    const int status = pclose(pipe);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

std::string sample_binary(const std::string& name) { return std::string(CELLFX_SAMPLE_BIN_DIR) + "/" + name; }

struct SampleRun {
    std::string dir;    // the frames
    std::string output; // what the program printed
};

// Runs a sample for `frames` frames into a fresh folder under the test output.
SampleRun run_sample_logged(const std::string& name, const std::string& tag, const std::string& extra, bool headless = true,
                            int width = kWidth, int height = kHeight, int frames = kFrames) {
    const std::string dir = fx_test::output_path("samples/" + name + "_" + tag);
    std::filesystem::remove_all(dir);
    const std::string command = sample_binary(name) + (headless ? " --headless" : "") + " --frames " + std::to_string(frames) +
                                " --width " + std::to_string(width) + " --height " + std::to_string(height) + " --out " +
                                dir + " " + extra;
    const Run r = run(command);
    INFO(command << "\n" << r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("nan") == std::string::npos);
    CHECK(r.output.find(" inf") == std::string::npos);
    return {dir, r.output};
}

// Runs a sample for kFrames frames into a fresh folder under the test output; returns the folder.
std::string run_sample(const std::string& name, const std::string& tag, const std::string& extra, bool headless = true) {
    return run_sample_logged(name, tag, extra, headless).dir;
}

fx::Image read_frame(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%04d.png", frame);
    const std::string path = dir + name;
    INFO(path);
    REQUIRE(std::filesystem::exists(path));
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &n, 4);
    REQUIRE(data != nullptr);
    fx::Image image(w, h);
    for (int y = 0; y < h; ++y) // PNG rows top-down, fx::Image bottom row first
        for (int x = 0; x < w; ++x) {
            const unsigned char* p = data + 4 * (std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x));
            image.at(x, y) = glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
        }
    stbi_image_free(data);
    return image;
}

// The reference as the 8-bit window would hold it: clamped to [0, 1], alpha 1, rounded.
fx::Image quantized(const fx::Image& image) {
    fx::Image q = image;
    for (glm::vec4& p : q.pixels) p = glm::vec4(glm::round(glm::clamp(glm::vec3(p), 0.0f, 1.0f) * 255.0f) / 255.0f, 1.0f);
    return q;
}

// The colour channels (the frames are opaque).
verify::Options rgb() {
    verify::Options o;
    o.channels = 3;
    return o;
}

// Pixels that differ by more than `threshold` in some colour channel.
std::size_t differing_pixels(const fx::Image& a, const fx::Image& b, float threshold) {
    verify::Tolerance t;
    t.pixel.absolute = threshold;
    return verify::measure(a, b, t, rgb()).beyond;
}

// The frame shows something: at least 2% of its pixels are not the background colour.
void require_not_empty(const fx::Image& frame, const glm::vec3& background) {
    const fx::Image bg(frame.width, frame.height, glm::vec4(background, 1.0f));
    const std::size_t n = differing_pixels(frame, bg, 4.0f / 255.0f);
    INFO(n << " of " << frame.pixels.size() << " pixels differ from the background");
    REQUIRE(n > frame.pixels.size() / 50);
}

// terrain::SceneRenderer's own frame of the scene at time 0 from the scene camera (the samples'
// scripted cameras start there: their pans and orbits are 0 at t = 0). `change` (optional)
// changes the renderer first, as the sample's panel would through cellfx::Module.
fx::Image scene_reference(const std::string& scene_name, bool drone,
                          const std::function<void(terrain::SceneRenderer&)>& change = nullptr) {
    fx_test::gl_context();
    terrain::SceneRenderer renderer(terrain::load_scene(fx_test::source_path("content/scenes/" + scene_name + ".json")));
    if (change) change(renderer);
    if (drone) renderer.effect("patrol").set_parent_transform(cellfx_samples::drone_parent_transform(0.0));
    renderer.set_time(0.0);
    const terrain::Scene& s = renderer.scene();
    const fx::Camera camera = s.camera_path ? s.camera_path->at(0.0, s.camera) : s.camera;
    return renderer.render_to_image(camera, kWidth, kHeight);
}

// A sample's 8-bit frame against SceneRenderer's float frame of the same scene, camera, size and
// LOD (quantized): the sample composites cellfx's float frame over an 8-bit framebuffer cleared
// to the (8-bit rounded) background, the reference over the unrounded background in float: 1/255
// for the background's rounding, 0.5/255 for the final rounding. Mean: a tenth of a step.
void check_same_frame(const fx::Image& frame, const fx::Image& expected, const std::string& label) {
    verify::Tolerance t = verify::same_picture(1.5 / 255.0, "the background's 8-bit rounding and the final rounding");
    t.mean.absolute = 0.1 / 255.0;
    fx_test::check_image(label, frame, expected, t, rgb());
}

// `scene_name`: the sample's scene file (content/scenes/<scene_name>.json), if not its own name.
void check_scene_sample(const std::string& name, std::string scene_name = "") {
    if (scene_name.empty()) scene_name = name;
    const std::string dir = run_sample(name, "headless", "--no-overlay --no-props");
    std::vector<fx::Image> frames;
    for (int f = 0; f < kFrames; ++f) frames.push_back(read_frame(dir, f));
    const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/" + scene_name + ".json"));
    require_not_empty(frames[0], glm::vec3(scene.background));

    check_same_frame(frames[0], quantized(scene_reference(scene_name, name == "searchlight")), "sample_" + name);

    // Animated: time (and the scripted camera) move the picture between frame 0 and the last.
    const std::size_t changed = differing_pixels(frames[0], frames[kFrames - 1], 1.5f / 255.0f);
    INFO(changed << " pixels changed between frame 0 and frame " << kFrames - 1);
    CHECK(changed > 0);
}

} // namespace

TEST_CASE("sample fog_valley runs headless and matches SceneRenderer's frame", "[samples]") { check_scene_sample("fog_valley"); }
TEST_CASE("sample campfire runs headless and matches SceneRenderer's frame", "[samples]") { check_scene_sample("campfire"); }
TEST_CASE("sample searchlight runs headless and matches SceneRenderer's frame", "[samples]") { check_scene_sample("searchlight"); }
TEST_CASE("sample aurora runs headless and matches SceneRenderer's frame", "[samples]") { check_scene_sample("aurora"); }
TEST_CASE("sample night_valley runs headless and matches SceneRenderer's frame", "[samples]") {
    check_scene_sample("night_valley", "fog_valley_night");
}

TEST_CASE("sample fem_viewer runs headless and matches the scan-line reference", "[samples]") {
    const std::string dir = run_sample("fem_viewer", "headless", "--no-overlay");
    const fx::Image frame = read_frame(dir, 0);
    const glm::vec3 background(0.06f, 0.065f, 0.08f); // fem_viewer's
    require_not_empty(frame, background);

    // The sample's defaults: the blunt fin, density, cool_warm mapped onto its range,
    // absorption-exact, the README's view from 1.3× as far (near/far far from the mesh: they cut nothing).
    const fx::CellMesh mesh = fx::read_mesh(fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin"),
                                            fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin"));
    const fx::ScalarField& field = *mesh.find_scalar("density");
    const fx::ScalarRange r = fx::scalar_range(field);
    const fx::TransferFunction tf =
        fx::TransferFunction::read_json(fx_test::source_path("content/transfer_functions/cool_warm.json")).rescaled(r.lo, r.hi);
    const fx::Camera camera = fx::Camera::parse("eye=3.56,-22.06,19.96,target=3.3,4.2,2.8,up=0,0,1,fov=40");
    fx::ScanlineOptions so;
    so.model = fx::OpticalModel::EmissionAbsorption;
    fx::Image reference = fx::ScanlineRenderer(mesh).render(camera, kWidth, kHeight, field, tf, so);
    fx::composite_over(reference, glm::round(background * 255.0f) / 255.0f); // over the 8-bit cleared frame
    const fx::Image expected = quantized(reference);

    // absorption-exact's stated tolerance against the scan-line reference
    // (testing/verify/tolerances.cpp), plus one 8-bit step per pixel for the window's format (the
    // composite over the 8-bit background, then rounding) and half a step on the mean.
    verify::Tolerance t = verify::stated(verify::Path::AbsorptionExact);
    t.pixel.absolute += 1.0 / 255.0, t.mean.absolute += 0.5 / 255.0;
    t.why += "; the 8-bit window: one step";
    fx_test::check_frame("sample_fem_viewer", frame, expected, t, rgb());

    const std::size_t changed = differing_pixels(frame, read_frame(dir, kFrames - 1), 1.5f / 255.0f);
    INFO(changed << " pixels changed (the camera orbits)");
    CHECK(changed > 0);
}

TEST_CASE("sample stats line and props: drawn where they belong", "[samples]") {
    // The stats panel covers the top-left corner only: the frame with it equals the frame
    // without it below the panel (two lines of 12 px and margins: 30 px).
    const fx::Image plain = read_frame(run_sample("searchlight", "plain", "--no-overlay --no-props"), 0);
    const fx::Image with_text = read_frame(run_sample("searchlight", "text", "--no-props"), 0);
    std::size_t text_pixels = 0, outside = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const bool differs = glm::any(glm::greaterThan(glm::abs(glm::vec3(plain.at(x, y)) - glm::vec3(with_text.at(x, y))),
                                                            glm::vec3(1.5f / 255.0f)));
            if (!differs) continue;
            if (kHeight - 1 - y < 30) ++text_pixels; // rows from the top
            else ++outside;
        }
    CHECK(text_pixels > 200);
    CHECK(outside == 0);
    // The drone (searchlight's props) is drawn and hides part of the night: a few pixels, not
    // the frame.
    const fx::Image with_drone = read_frame(run_sample("searchlight", "drone", "--no-overlay"), 0);
    const std::size_t drone = differing_pixels(plain, with_drone, 4.0f / 255.0f);
    INFO(drone << " pixels show the drone");
    CHECK(drone > 0);
    CHECK(drone < plain.pixels.size() / 20);
}

TEST_CASE("samples reject bad arguments with a message", "[samples]") {
    const struct {
        std::string args, message;
        int status;
    } cases[] = {
        {"--headless", "--headless needs --frames N", 2},
        {"--headless --frames 0", "--frames: expected a whole number", 2},
        {"--headless --frames 1 --path foo", "unknown render path 'foo'", 2},
        {"--headless --frames 1 --width 64", "--width and --height go together", 2},
        {"--bogus", "unknown option '--bogus'", 2},
        {"extra", "unexpected argument 'extra'", 2},
        {"--headless --frames 1 --width 32 --height 24 --disable nosuch", "no effect 'nosuch'", 1},
    };
    for (const auto& c : cases) {
        const Run r = run(sample_binary("campfire") + " " + c.args);
        INFO("campfire " << c.args << "\n" << r.output);
        CHECK(r.status == c.status);
        CHECK(r.output.find(c.message) != std::string::npos);
    }
    const Run missing = run(sample_binary("fem_viewer") + " --headless --frames 1 /nonexistent/mesh.vtk");
    INFO(missing.output);
    CHECK(missing.status == 1);
    CHECK(missing.output.find("/nonexistent/mesh.vtk") != std::string::npos);
    const Run scalar = run(sample_binary("fem_viewer") + " --headless --frames 1 --scalar nosuch");
    INFO(scalar.output);
    CHECK(scalar.status == 1);
    CHECK(scalar.output.find("no field 'nosuch'") != std::string::npos);
    const Run save = run(sample_binary("fem_viewer") + " --headless --frames 1 --save " + fx_test::output_path("never.json"));
    INFO(save.output);
    CHECK(save.status == 1);
    CHECK(save.output.find("--save: this sample shows no scene file") != std::string::npos);
    CHECK(save.output.find("frame 0") == std::string::npos); // refused before any frame
    const std::string nowhere = fx_test::output_path("no_such_folder/tuned.json");
    const Run unwritable = run(sample_binary("campfire") + " --headless --frames 1 --save " + nowhere);
    INFO(unwritable.output);
    CHECK(unwritable.status == 1);
    CHECK(unwritable.output.find("--save " + nowhere) != std::string::npos);
    CHECK(unwritable.output.find("frame 0") == std::string::npos); // before the tuning it would lose
}

TEST_CASE("sample campfire in a GLFW window equals its headless frames", "[samples-window]") {
    // The same frames (fixed steps with --frames) read back from the window's default
    // framebuffer after the draw and before the swap, and from the headless offscreen
    // framebuffer. Both are 8-bit frames of the same GL driver: allow one step of rounding
    // for a window visual whose formats differ (e.g. no alpha bits); mean a tenth of a step.
    const std::string window = run_sample("campfire", "window", "--no-overlay --no-panel", /*headless=*/false);
    const std::string headless = run_sample("campfire", "window_headless", "--no-overlay");
    for (int f = 0; f < kFrames; ++f) {
        const fx::Image shot = read_frame(window, f), expected = read_frame(headless, f);
        if (f == 0) require_not_empty(shot, glm::vec3(0.015f, 0.02f, 0.045f));
        verify::Tolerance t = verify::same_picture(1.0 / 255.0 + 1e-6, "8-bit frames of one driver: one step of rounding");
        t.mean.absolute = 0.1 / 255.0;
        fx_test::check_image("sample_window_" + std::to_string(f), shot, expected, t, rgb());
    }
}

// ---- the tuning panel ---------------------------------------------------------------------------

namespace {

// The changes the panel tests make to the campfire, on the command line (--set goes through the
// panel's code path: FrameLoop::set_control, then cellfx::Module::set_params / set_path ...) and
// on a SceneRenderer (what the same Module calls do).
const char* const kFireSettings = "--set fire.base_radius=0.9 --set fire.intensity=2.2 --set fire.extinction_scale=0.35";
void change_fire(terrain::SceneRenderer& r) {
    fx::CampfireParams p = std::get<fx::CampfireParams>(r.scene().effects[0].params);
    p.base_radius = 0.9, p.intensity = 2.2;
    r.set_params("fire", p);
    r.set_extinction_scale("fire", 0.35);
}

// The figures of an "accuracy: mean ... (rmse R, max M) ..." line.
struct Figures {
    double rmse = -1.0, max_abs = -1.0, peak = -1.0;
};
Figures accuracy_figures(const std::string& output) {
    static const std::regex line(R"(accuracy: mean \S+ worst \S+ of peak ([0-9.e+-]+) \(rmse ([0-9.e+-]+), max ([0-9.e+-]+)\))");
    std::smatch m;
    Figures f;
    if (std::regex_search(output, m, line)) f = {std::stod(m[2]), std::stod(m[3]), std::stod(m[1])};
    return f;
}

// The rows of a `cellfx bench accuracy` CSV by flavour, for one scene.
std::map<std::string, std::map<std::string, std::string>> bench_rows(const std::string& csv, const std::string& scene) {
    std::ifstream in(csv);
    REQUIRE(in);
    std::string line;
    std::getline(in, line);
    std::vector<std::string> header;
    std::stringstream hs(line);
    for (std::string h; std::getline(hs, h, ',');) header.push_back(h);
    std::map<std::string, std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        std::map<std::string, std::string> row;
        std::stringstream ls(line);
        std::size_t i = 0;
        for (std::string cell; std::getline(ls, cell, ',') && i < header.size(); ++i) row[header[i]] = cell;
        if (row["scene"] == scene) rows[row["flavour"]] = row;
    }
    return rows;
}

} // namespace

TEST_CASE("sample campfire: a control set through the panel's code path changes the frame as cellfx::Module does", "[samples]") {
    const std::string dir = run_sample("campfire", "set", std::string("--no-overlay --no-props ") + kFireSettings);
    const fx::Image frame = read_frame(dir, 0);
    check_same_frame(frame, quantized(scene_reference("campfire", false, change_fire)), "sample_campfire_set");
    // And the change shows: a wider, brighter fire than the shipped one.
    const fx::Image plain = read_frame(run_sample("campfire", "unset", "--no-overlay --no-props"), 0);
    const std::size_t changed = differing_pixels(frame, plain, 4.0f / 255.0f);
    INFO(changed << " pixels changed");
    CHECK(changed > frame.pixels.size() / 50);
    // Refused values name the control and its range; unknown ones list what there is.
    const struct {
        std::string set, message;
    } cases[] = {
        {"fire.base_radius=-1", "base_radius must be positive"},
        {"fire.cells_across=300", "cells_across must be in 2..256"},
        {"fire.bogus=1", "no control 'bogus' in fire (it has: enabled, path, absorb, extinction_scale, position, base_radius"},
        {"smoke.enabled=false", "no group 'smoke' (this sample has: scene, fire, view)"},
        {"fire.path=pcp-fast", "expected one of pcp, pcp-exact"},
    };
    for (const auto& c : cases) {
        const Run r = run(sample_binary("campfire") + " --headless --frames 1 --width 32 --height 24 --set " + c.set);
        INFO(c.set << "\n" << r.output);
        CHECK(r.status == 1);
        CHECK(r.output.find(c.message) != std::string::npos);
    }
}

TEST_CASE("sample campfire: the tuned scene it saves renders the same frame in the sample and in cellfx render", "[samples]") {
    const std::string folder = fx_test::output_path("samples/saved_scene");
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const std::string file = folder + "/tuned_campfire.json";
    const std::string tuned = run_sample("campfire", "save", std::string("--no-overlay --no-props --save ") + file + " " + kFireSettings);
    REQUIRE(std::filesystem::exists(file));
    // The sample with the saved scene draws the frames the tuned one drew.
    const std::string reloaded = run_sample("campfire", "reloaded", "--no-overlay --no-props --scene " + file);
    for (int f = 0; f < kFrames; ++f) {
        // The same program, scene and GL: the same bytes.
        const verify::Tolerance t = verify::same_picture(0.0, "the same program, scene and GL: the same bytes");
        fx_test::check_image("sample_campfire_reloaded_" + std::to_string(f), read_frame(reloaded, f), read_frame(tuned, f), t, rgb());
    }
    // `cellfx render` reads it too: SceneRenderer's frame of it is the sample's.
    const std::string png = folder + "/render.png";
    const Run r = run(std::string(CELLFX_CLI) + " render " + file + " --time 0 --size " + std::to_string(kWidth) + "x" +
                      std::to_string(kHeight) + " --out " + png);
    INFO(r.output);
    REQUIRE(r.status == 0);
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(png.c_str(), &w, &h, &n, 4);
    REQUIRE(data != nullptr);
    fx::Image rendered(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const unsigned char* p = data + 4 * (std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x));
            rendered.at(x, y) = glm::vec4(p[0], p[1], p[2], 255.0f) / 255.0f;
        }
    stbi_image_free(data);
    check_same_frame(read_frame(tuned, 0), rendered, "sample_campfire_saved_render");
}

TEST_CASE("sample night_valley: the accuracy check reports cellfx bench accuracy's figures for the same frame", "[samples]") {
    // The same scene, camera (the camera path at t = 0), time, size (bench accuracy --quick:
    // 64x48), path (pcp-exact for every effect), medium (exact) and resolution; terrain not drawn.
    const std::string out = fx_test::output_path("samples/accuracy_bench");
    std::filesystem::remove_all(out);
    const Run bench = run(std::string(CELLFX_CLI) + " bench accuracy --quick --scenes night-valley --out " + out);
    INFO(bench.output);
    REQUIRE(bench.status == 0);
    const auto rows = bench_rows(out + "/accuracy.csv", "night-valley");
    // The exact medium (errors of 1e-5: the path's own) and the scene's froxel medium (1e-2).
    for (const auto& [flavour, medium] : {std::pair<std::string, std::string>{"pcp-exact", "exact"}, {"pcp-exact froxel", "froxel"}}) {
        INFO(flavour);
        REQUIRE(rows.count(flavour));
        const auto& row = rows.at(flavour);
        REQUIRE(row.at("width") == "64");
        const double rmse = std::stod(row.at("rmse_1spp")), max_abs = std::stod(row.at("max_abs_1spp"));
        const SampleRun sample = run_sample_logged("night_valley", "accuracy_" + medium,
                                                   "--no-overlay --path pcp-exact --set scene.medium=" + medium +
                                                       " --set scene.fx_scale=1 --accuracy",
                                                   true, 64, 48, 1);
        INFO(sample.output);
        const Figures f = accuracy_figures(sample.output);
        REQUIRE(f.rmse >= 0.0);
        // Both compare SceneRenderer::render_to_image with render_scene_reference at one sample
        // per pixel on the pictures as displayed: the same numbers but for the printing (6
        // significant digits on both sides) and the GPU's float rounding between two processes'
        // frames: 1e-3 of the figure.
        WARN(flavour << ": sample rmse " << f.rmse << ", max " << f.max_abs << "; bench accuracy rmse " << rmse << ", max " << max_abs);
        CHECK(f.rmse == Approx(rmse).epsilon(1e-3).margin(1e-7));
        CHECK(f.max_abs == Approx(max_abs).epsilon(1e-3).margin(1e-7));
    }
}

TEST_CASE("sample fem_viewer: the accuracy check of its mesh, however soon the reference is done", "[samples]") {
    // One frame: the check starts in it, and at 96x72 the blunt fin's reference is done in a
    // fraction of a second, often before the run looks for it: the run takes it in either way.
    const SampleRun run = run_sample_logged("fem_viewer", "accuracy", "--no-overlay --accuracy", true, 96, 72, 1);
    INFO(run.output);
    const Figures f = accuracy_figures(run.output);
    REQUIRE(f.rmse >= 0.0);
    REQUIRE(f.peak > 0.0);
    // absorption-exact (fem_viewer's path) against fx::ScanlineRenderer of the same mesh, field
    // and transfer function, float against float. Its stated tolerance (verify::stated: 0.5% of
    // peak per pixel, mean 0.05%) lets edge pixels that the rasteriser and the reference assign
    // differently go beyond; from the printed figures alone, the worst pixel (maybe such an
    // edge) within a tenth of peak and the RMSE, which weighs those pixels more than a mean,
    // within 0.5% of peak. Measured: worst 0.15%, RMSE 0.003% of peak.
    WARN("fem_viewer: rmse " << f.rmse << ", max " << f.max_abs << ", peak " << f.peak);
    CHECK(f.max_abs <= 0.1 * f.peak);
    CHECK(f.rmse <= 0.005 * f.peak);
}

#if CELLFX_SAMPLES_PANEL // built with Dear ImGui (samples/CMakeLists.txt)
TEST_CASE("sample panel: drawn headless over the right of the frame, and absent without --panel", "[samples]") {
    // 320 wide: the panel takes min(400, 0.45 × 320) = 144 pixels at the right.
    const fx::Image plain = read_frame(run_sample_logged("campfire", "panel_off", "--no-overlay", true, 320, 240).dir, 2);
    const fx::Image panel = read_frame(run_sample_logged("campfire", "panel_on", "--no-overlay --panel", true, 320, 240).dir, 2);
    std::size_t inside = 0, outside = 0;
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x) {
            const bool differs = glm::any(glm::greaterThan(glm::abs(glm::vec3(plain.at(x, y)) - glm::vec3(panel.at(x, y))), glm::vec3(1.5f / 255.0f)));
            (x >= 320 - 144 ? inside : outside) += differs ? 1 : 0;
        }
    INFO(inside << " pixels differ in the panel, " << outside << " outside it");
    CHECK(inside > 144 * 240 / 4);
    CHECK(outside == 0);
}

TEST_CASE("sample panel in a GLFW window: drawn where it is, and its accuracy check runs while the frames go on", "[samples-window]") {
    const fx::Image plain = read_frame(run_sample_logged("campfire", "window_panel_off", "--no-overlay --no-panel", false, 320, 240).dir, 2);
    const fx::Image panel = read_frame(run_sample_logged("campfire", "window_panel_on", "--no-overlay", false, 320, 240).dir, 2);
    std::size_t inside = 0, outside = 0;
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x) {
            const bool differs = glm::any(glm::greaterThan(glm::abs(glm::vec3(plain.at(x, y)) - glm::vec3(panel.at(x, y))), glm::vec3(1.5f / 255.0f)));
            (x >= 320 - 144 ? inside : outside) += differs ? 1 : 0;
        }
    INFO(inside << " pixels differ in the panel (shown by default in a window), " << outside << " outside it");
    CHECK(inside > 144 * 240 / 4);
    CHECK(outside == 0);

    // The night valley's reference takes seconds: the window draws frames meanwhile, each line
    // saying how far the check is, and the last frame shows its result.
    const SampleRun run = run_sample_logged("night_valley", "window_accuracy", "--no-overlay --accuracy", false, 320, 240, 6);
    INFO(run.output);
    const std::size_t result = run.output.find("accuracy: mean");
    REQUIRE(result != std::string::npos);
    const std::size_t while_running = run.output.find("| accuracy check ");
    CHECK(while_running < result);
    CHECK(accuracy_figures(run.output).rmse > 0.0);
}
#endif // CELLFX_SAMPLES_PANEL

TEST_CASE("sample campfire in a GLFW window: a control set, the scene saved and the accuracy as headless", "[samples-window]") {
    // --set through the panel's code path in the window: its frames are the headless ones, and
    // the scene it saves is the same file.
    const std::string folder = fx_test::output_path("samples/window_saved");
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const std::string window = run_sample("campfire", "window_set",
                                          std::string("--no-overlay --no-panel --save ") + folder + "/window.json " + kFireSettings, false);
    const std::string headless = run_sample("campfire", "window_set_headless",
                                            std::string("--no-overlay --no-panel --save ") + folder + "/headless.json " + kFireSettings);
    for (int f = 0; f < kFrames; ++f) {
        verify::Tolerance t = verify::same_picture(1.0 / 255.0 + 1e-6, "8-bit frames of one driver: one step of rounding");
        t.mean.absolute = 0.1 / 255.0; // as the window test above
        fx_test::check_image("sample_window_set_" + std::to_string(f), read_frame(window, f), read_frame(headless, f), t, rgb());
    }
    const auto text = [](const std::string& path) {
        std::ifstream in(path);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    };
    CHECK(!text(folder + "/window.json").empty());
    CHECK(text(folder + "/window.json") == text(folder + "/headless.json"));
    // The accuracy check in the window reports what it reports headless (which the test above
    // holds to cellfx bench accuracy's figures).
    const std::string args = "--no-overlay --no-panel --path pcp-exact --set scene.medium=froxel --accuracy";
    const Figures in_window = accuracy_figures(run_sample_logged("night_valley", "window_check", args, false, 64, 48, 1).output);
    const Figures offscreen = accuracy_figures(run_sample_logged("night_valley", "window_check_headless", args, true, 64, 48, 1).output);
    REQUIRE(in_window.rmse > 0.0);
    CHECK(in_window.rmse == Approx(offscreen.rmse).epsilon(1e-3));
    CHECK(in_window.max_abs == Approx(offscreen.max_abs).epsilon(1e-3));
}
