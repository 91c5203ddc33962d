// The six samples (samples/<name>), run as the programs users start: headless for a few
// frames, and one in a real GLFW window under Xvfb (ctest runs "[samples-window]" through
// xvfb-run). Each run's PNGs are read back and checked:
//   - exit status 0, one PNG per frame, the frame not empty (it differs from the background);
//   - frame 0 against an independent render of the same scene and view: terrain::SceneRenderer
//     ::render_to_image (what `cellfx render SCENE.json` does: its own float target, no window,
//     no frame loop) for the scene samples, the scan-line reference (fx::ScanlineRenderer) for
//     fem_viewer; diff PNGs in the test output folder on failure;
//   - animated samples: the last frame differs from the first;
//   - the stats line only covers its panel; bad arguments give exit 2 and a message.
// Pixels are 8-bit (the window's format), so "finite" is checked on the printed statistics
// (no nan/inf), not on the pixels.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
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

// Runs a sample for kFrames frames into a fresh folder under the test output; returns the folder.
std::string run_sample(const std::string& name, const std::string& tag, const std::string& extra, bool headless = true) {
    const std::string dir = fx_test::output_path("samples/" + name + "_" + tag);
    std::filesystem::remove_all(dir);
    const std::string command = sample_binary(name) + (headless ? " --headless" : "") + " --frames " + std::to_string(kFrames) +
                                " --width " + std::to_string(kWidth) + " --height " + std::to_string(kHeight) + " --out " +
                                dir + " " + extra;
    const Run r = run(command);
    INFO(command << "\n" << r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("nan") == std::string::npos);
    CHECK(r.output.find(" inf") == std::string::npos);
    return dir;
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
// scripted cameras start there: their pans and orbits are 0 at t = 0).
fx::Image scene_reference(const std::string& scene_name, bool drone) {
    fx_test::gl_context();
    terrain::SceneRenderer renderer(terrain::load_scene(fx_test::source_path("content/scenes/" + scene_name + ".json")));
    if (drone) renderer.effect("patrol").set_parent_transform(cellfx_samples::drone_parent_transform(0.0));
    renderer.set_time(0.0);
    const terrain::Scene& s = renderer.scene();
    const fx::Camera camera = s.camera_path ? s.camera_path->at(0.0, s.camera) : s.camera;
    return renderer.render_to_image(camera, kWidth, kHeight);
}

// `scene_name`: the sample's scene file (content/scenes/<scene_name>.json), if not its own name.
void check_scene_sample(const std::string& name, std::string scene_name = "") {
    if (scene_name.empty()) scene_name = name;
    const std::string dir = run_sample(name, "headless", "--no-overlay --no-props");
    std::vector<fx::Image> frames;
    for (int f = 0; f < kFrames; ++f) frames.push_back(read_frame(dir, f));
    const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/" + scene_name + ".json"));
    require_not_empty(frames[0], glm::vec3(scene.background));

    const fx::Image expected = quantized(scene_reference(scene_name, name == "searchlight"));
    // Same scene, camera, size and LOD on both sides; the sample composites cellfx's float
    // frame over an 8-bit framebuffer cleared to the (8-bit rounded) background, the reference
    // over the unrounded background in float: 1/255 for the background's rounding, 0.5/255 for
    // the final rounding. Mean: a tenth of a step.
    verify::Tolerance t = verify::same_picture(1.5 / 255.0, "the background's 8-bit rounding and the final rounding");
    t.mean.absolute = 0.1 / 255.0;
    fx_test::check_image("sample_" + name, frames[0], expected, t, rgb());

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
}

TEST_CASE("sample campfire in a GLFW window equals its headless frames", "[samples-window]") {
    // The same frames (fixed steps with --frames) read back from the window's default
    // framebuffer after the draw and before the swap, and from the headless offscreen
    // framebuffer. Both are 8-bit frames of the same GL driver: allow one step of rounding
    // for a window visual whose formats differ (e.g. no alpha bits); mean a tenth of a step.
    const std::string window = run_sample("campfire", "window", "--no-overlay", /*headless=*/false);
    const std::string headless = run_sample("campfire", "window_headless", "--no-overlay");
    for (int f = 0; f < kFrames; ++f) {
        const fx::Image shot = read_frame(window, f), expected = read_frame(headless, f);
        if (f == 0) require_not_empty(shot, glm::vec3(0.015f, 0.02f, 0.045f));
        verify::Tolerance t = verify::same_picture(1.0 / 255.0 + 1e-6, "8-bit frames of one driver: one step of rounding");
        t.mean.absolute = 0.1 / 255.0;
        fx_test::check_image("sample_window_" + std::to_string(f), shot, expected, t, rgb());
    }
}
