// Input of the samples' frame loop without a window: FlightCamera's mouse look and flight, and
// the key bindings — the same FrameLoop calls run_sample's GLFW callbacks make (key codes are
// the loop's own, independent of GLFW), checked on the campfire sample's content headless —
// and the panel's keys (R, Ctrl+S, Tab) and the view's controls.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "frame_loop.hpp"
#include "gl_fixture.hpp"
#include "panel.hpp"
#include "terrain/scene.hpp"
#include "sample.hpp"
#include "sample_gl.hpp"
#include "cellfx_names.hpp"

namespace {

using cellfx_samples::FlightCamera;
using cellfx_samples::FrameLoop;

void check_near(const glm::dvec3& actual, const glm::dvec3& expected, double tolerance = 1e-9) {
    INFO("actual (" << actual.x << ", " << actual.y << ", " << actual.z << "), expected (" << expected.x << ", "
                    << expected.y << ", " << expected.z << ")");
    CHECK(glm::length(actual - expected) <= tolerance);
}

// The view direction's heading: its part across `up`, normalised.
glm::dvec3 heading(const fx::Camera& camera) {
    const glm::dvec3 f = camera.forward(), up = glm::normalize(camera.up);
    return glm::normalize(f - glm::dot(f, up) * up);
}

} // namespace

TEST_CASE("sample flight camera: mouse look turns about up, pitch stops short of the poles, flight moves the eye",
          "[samples]") {
    fx::Camera start;
    start.eye = {0, 0, 0};
    start.target = {0, 10, 0};
    start.up = {0, 0, 1};
    FlightCamera flight(start);
    check_near(flight.camera().forward(), {0, 1, 0});

    flight.look(M_PI / 2, 0.0); // positive yaw turns left: from +y to −x seen from above
    check_near(flight.camera().forward(), {-1, 0, 0});
    check_near(flight.camera().up, {0, 0, 1});
    CHECK(glm::length(flight.camera().target - flight.camera().eye) == Approx(10.0)); // the target stays as far

    flight.look(0.0, 10.0); // far past straight up: stops at 89°
    CHECK(flight.camera().forward().z == Approx(std::sin(glm::radians(89.0))));
    flight.look(0.0, -20.0);
    CHECK(flight.camera().forward().z == Approx(-std::sin(glm::radians(89.0))));
    flight.look(0.0, glm::radians(89.0)); // level again, heading kept
    check_near(flight.camera().forward(), {-1, 0, 0}, 1e-9);

    flight.move(2.0, 0.0, 0.0); // forward
    check_near(flight.camera().eye, {-2, 0, 0});
    flight.move(0.0, 1.0, 0.0); // right of −x, with z up, is +y
    check_near(flight.camera().eye, {-2, 1, 0});
    flight.move(0.0, 0.0, 3.0); // up
    check_near(flight.camera().eye, {-2, 1, 3});
    check_near(flight.camera().target - flight.camera().eye, {-10, 0, 0});
}

TEST_CASE("sample keys: 1-5 pick the path, F-keys toggle effects, P pauses, mouse and WASD fly, C returns, Esc quits",
          "[samples][gl]") {
    fx_test::gl_context();
    constexpr int w = 64, h = 48;
    constexpr double dt = 0.1;
    cellfx_samples::SampleOptions options;
    options.headless = true;
    options.width = w, options.height = h;
    options.overlay = false;
    const std::unique_ptr<cellfx_samples::SampleContent> content = cellfx_samples::find_sample("campfire").make(options);
    {
        const cellfx_samples::OffscreenFramebuffer target(w, h);
        FrameLoop loop(*content, options, "campfire");
        const auto frame = [&] { loop.frame(target.id(), w, h, dt); };

        frame(); // the first frame shows the start time
        const double t0 = content->time();
        frame();
        CHECK(content->time() == Approx(t0 + dt));

        // Paths: key n picks the n-th path offered; a key past the list changes nothing.
        const std::vector<fx::RenderPath> paths = content->paths();
        REQUIRE(paths.size() >= 2);
        CHECK(loop.key('2'));
        CHECK(content->path_label() == fx::render_path_name(paths[1]));
        CHECK(loop.key('9'));
        CHECK(content->path_label() == fx::render_path_name(paths[1]));
        CHECK(loop.help().find(std::string("1 ") + fx::render_path_name(paths[0])) != std::string::npos);
        frame();

        // Toggles: F1 switches the first one off and on again; the label says what is off.
        const std::vector<std::string> toggles = content->toggle_names();
        REQUIRE(!toggles.empty());
        CHECK(content->toggled(0));
        loop.key(cellfx_samples::kKeyF1);
        CHECK_FALSE(content->toggled(0));
        CHECK(loop.label().find("off: " + toggles[0]) != std::string::npos);
        frame();
        loop.key(cellfx_samples::kKeyF1);
        CHECK(content->toggled(0));
        CHECK(loop.help().find("F1 " + toggles[0]) != std::string::npos);

        // P: the clock stands still while paused.
        loop.key('P');
        const double paused_at = content->time();
        frame();
        CHECK(content->time() == paused_at);
        CHECK(loop.label().find("paused") != std::string::npos);

        // Mouse look leaves the scene camera for a free one, turned by the drag's yaw.
        CHECK_FALSE(loop.free_camera());
        const fx::Camera scripted = loop.camera();
        loop.look(0.2, 0.0);
        frame();
        CHECK(loop.free_camera());
        CHECK(std::acos(std::clamp(glm::dot(heading(loop.camera()), heading(scripted)), -1.0, 1.0)) == Approx(0.2));

        // WASD: along the view, a third of the scene camera's viewing distance per second; shift 5×.
        const double distance = glm::length(scripted.target - scripted.eye); // clock paused: the same camera
        glm::dvec3 eye = loop.camera().eye;
        loop.fly(1.0, 0.0, 0.0, 0.5, false);
        frame();
        const glm::dvec3 step = loop.camera().eye - eye;
        CHECK(glm::length(step) == Approx(0.5 * distance / 3.0));
        CHECK(glm::dot(glm::normalize(step), loop.camera().forward()) == Approx(1.0));
        eye = loop.camera().eye;
        loop.fly(1.0, 0.0, 0.0, 0.5, true);
        CHECK(glm::length(loop.camera().eye - eye) == Approx(0.0)); // the loop's camera moves at the next frame
        frame();
        CHECK(glm::length(loop.camera().eye - eye) == Approx(5.0 * glm::length(step)));

        // C: back on the scene's camera; P again: the clock runs; Esc: quit.
        loop.key('C');
        CHECK_FALSE(loop.free_camera());
        loop.key('P');
        frame();
        CHECK(content->time() == Approx(paused_at + dt));
        check_near(loop.camera().eye, content->scripted_camera(content->time()).eye, 1e-9);
        CHECK_FALSE(loop.key(cellfx_samples::kKeyEscape));
        fx_test::require_no_gl_error();
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
}

TEST_CASE("sample panel keys and controls: R checks the accuracy in the background, Ctrl+S saves, the view's controls",
          "[samples][gl]") {
    fx_test::gl_context();
    constexpr int w = 64, h = 48;
    cellfx_samples::SampleOptions options;
    options.headless = true;
    options.width = w, options.height = h;
    options.overlay = false;
    options.save = fx_test::output_path("sample_input_saved.json");
    std::filesystem::remove(options.save);
    const std::unique_ptr<cellfx_samples::SampleContent> content = cellfx_samples::find_sample("campfire").make(options);
    const cellfx_samples::OffscreenFramebuffer target(w, h);
    FrameLoop loop(*content, options, "campfire");
    loop.set_panel(cellfx_samples::make_panel(nullptr)); // nullptr without ImGui: the keys work the same
    const auto frame = [&] { loop.frame(target.id(), w, h, 0.1); };
    frame();

    // R: the next frame starts the check (at the panel's size, or full size without one); the
    // frames go on while it runs; its result is the frame's error against the reference.
    CHECK(loop.key('R'));
    frame(); // starts it
    frame(); // and goes on, whether it is done or not
    loop.wait_for_accuracy();
    REQUIRE(loop.accuracy_results() == 1);
    const cellfx_samples::AccuracyResult& r = *loop.accuracy_result();
    const int expected_width = loop.has_panel() ? w / 2 : w; // the panel's default: half size
    CHECK(r.width == expected_width);
    CHECK(r.finite);
    CHECK(r.peak > 0.0);
    CHECK(r.max_abs >= r.rmse);
    CHECK(r.worst_percent() < 10.0); // pcp-exact against the reference: a few % at the worst pixel

    // The view's controls, as --set and the panel set them.
    loop.apply_setting("view.time=2.5");
    CHECK(content->time() == 2.5);
    loop.apply_setting("view.pause=true");
    frame();
    CHECK(content->time() == 2.5);
    loop.apply_setting("view.pause=false");
    loop.apply_setting("view.time_scale=2");
    frame();
    CHECK(content->time() == Approx(2.7));
    loop.apply_setting("fire.enabled=false");
    CHECK_FALSE(content->toggled(0));
    CHECK_THROWS_WITH(loop.apply_setting("view.time_scale=-1"), Catch::Contains("time_scale must be in [0, 100]"));

    // Ctrl+S: the tuned scene, which reads back with the fire off.
    loop.key(cellfx_samples::kKeySave);
    REQUIRE(std::filesystem::exists(options.save));
    const terrain::Scene saved = terrain::load_scene(options.save);
    REQUIRE(saved.effects.size() == 1);
    CHECK_FALSE(saved.effects[0].enabled);
    CHECK(loop.message().find("saved the tuned scene") != std::string::npos);

    // Tab hides and shows the panel.
    if (loop.has_panel()) {
        CHECK(loop.panel_shown());
        loop.key(cellfx_samples::kKeyTab);
        CHECK_FALSE(loop.panel_shown());
        loop.key(cellfx_samples::kKeyTab);
        CHECK(loop.panel_shown());
    }
}
