// The embedding API (cellfx/cellfx.hpp) in a headless context, as a game uses it: the game's own
// framebuffer with a depth texture attached, an opaque box drawn into it in front of the fire,
// cellfx drawing over that frame. The fire must be hidden behind the box and visible beside it
// (against the scan-line reference), the box untouched, and the game's GL state unchanged.
#include <catch2/catch.hpp>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "embedding_support.hpp"
#include "cellfx_names.hpp"

using effects_test::look;
using namespace embedding_test;

TEST_CASE("camera_from_view inverts Camera::view_matrix", "[embedding]") {
    const fx::Camera cam = look({3, -4, 2}, {0.5, 1, 0.3}, 50.0);
    const fx::Camera back = cellfx::camera_from_view(cam.view_matrix(), 50.0, cam.near_distance, cam.far_distance);
    CHECK(glm::length(back.eye - cam.eye) < 1e-9);
    CHECK(glm::length(back.forward() - cam.forward()) < 1e-12);
    const glm::dmat4 a = cam.view_matrix(), b = back.view_matrix();
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) CHECK(a[c][r] == Approx(b[c][r]).margin(1e-9));
    CHECK_THROWS_WITH(cellfx::camera_from_view(glm::scale(glm::dmat4(1.0), glm::dvec3(1, 1, -1)), 50, 0.1, 10),
                      Catch::Contains("mirrors"));
    CHECK_THROWS_WITH(cellfx::camera_from_view(cam.view_matrix(), 50, 1.0, 0.5), Catch::Contains("near < far"));
}

TEST_CASE("cellfx::Module: lifecycle errors are clear", "[gl][embedding]") {
    fx_test::gl_context();
    cellfx::Module fx;
    CHECK_FALSE(fx.initialized());
    CHECK_THROWS_WITH(fx.update(0.0, look({0, -5, 1}, {0, 0, 0})), Catch::Contains("call init() first"));
    CHECK_THROWS_WITH(fx.init(cellfx::Config{}), Catch::Contains("give a scene file or a scene"));
    CHECK_THROWS_WITH(fx.init(cellfx::Config{fx_test::output_path("missing_scene.json")}),
                      Catch::Contains("missing_scene.json") && Catch::Contains("cannot open"));
    CHECK_FALSE(fx.initialized());
    fx.init(cellfx::Config::from_scene(fire_scene(false), kW, kH));
    CHECK(fx.initialized());
    CHECK_THROWS_WITH(fx.render({0, {0, 0, kW, kH}, 0}), Catch::Contains("call update() before render()"));
    CHECK(fx.effect_names() == std::vector<std::string>{"fire"});
    CHECK(fx.effect<fx::Campfire>("fire") != nullptr);
    CHECK(fx.effect<fx::SearchLight>("fire") == nullptr);
    CHECK_THROWS_WITH(fx.set_enabled("smoke", false), Catch::Contains("no effect named 'smoke'"));
    CHECK_THROWS_WITH(fx.set_terrain_drawn(true), Catch::Contains("no terrain"));
    fx.shutdown();
    CHECK_FALSE(fx.initialized());
}

TEST_CASE("An opaque box of the game's hides the fire behind it, and the fire shows beside it", "[gl][embedding]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(false);
    const fx::Camera cam = scene.camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    // The fire's nearest point is ≥ 2.2 units from the eye along the view: a box at 1.4 is in
    // front of all of it.
    const double box_depth = 1.4;
    for (GLenum format : {GLenum(GL_DEPTH_COMPONENT32F), GLenum(GL_DEPTH24_STENCIL8)}) {
        INFO("depth format 0x" << std::hex << format);
        GameFrame game(format, false);
        fx.update(1.0 / 60.0, cam);
        game.draw(cam, true, box_depth);
        {
            effects_test::HostLeftovers leftovers; // the game's own state, bound and set
            glBindFramebuffer(GL_FRAMEBUFFER, game.framebuffer);
            const std::vector<double> before = effects_test::host_state();
            fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
            fx_test::require_no_gl_error();
            CHECK(effects_test::host_state() == before);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
        }
        const fx::Image frame = game.read();
        fx::write_png(frame, fx_test::output_path("embedding_box.png"));

        // The reference: the same fire mesh, scan-line, emission, over the game's frame.
        std::size_t hidden = 0, beside = 0;
        const fx::Image expected = expected_frame(fx, cam, &hidden, &beside);
        CHECK(hidden > 100); // the box really covers part of the fire ...
        CHECK(beside > 100); // ... and leaves part of it in view
        CHECK(box_error(frame) == 0.0f); // not a trace of fire on the box
        effects_test::check_frame("embedding_box", frame, expected, fx::RenderPath::PcpExact, 20);
    }
}

TEST_CASE("With the terrain drawn by cellfx the game's box still hides terrain and fire", "[gl][embedding]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(true);
    const fx::Camera cam = scene.camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    REQUIRE(fx.terrain_drawn());
    // The game's depth in a DEPTH24_STENCIL8 texture left with a shadow compare mode: cellfx
    // copies it through its own sampler, so neither matters.
    GameFrame game(GL_DEPTH24_STENCIL8, true);
    fx.update(0.0, cam);
    game.draw(cam, false, 0.0);
    fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
    const fx::Image open = game.read();
    game.draw(cam, true, 1.4);
    {
        effects_test::HostLeftovers leftovers;
        const std::vector<double> before = effects_test::host_state();
        fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
        fx_test::require_no_gl_error();
        CHECK(effects_test::host_state() == before);
    }
    const fx::Image boxed = game.read();
    std::size_t terrain_pixels = 0;
    float outside = 0.0f, inside = 0.0f;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            if (in_box(x, y)) {
                inside = std::max(inside, glm::length(boxed.at(x, y) - kBox));
                terrain_pixels += glm::length(open.at(x, y) - kSky) > 0.01f;
            } else {
                outside = std::max(outside, glm::length(boxed.at(x, y) - open.at(x, y)));
            }
        }
    CHECK(terrain_pixels > 500); // without the box, terrain and fire fill its rectangle
    CHECK(inside == 0.0f);       // with it, the box alone
    CHECK(outside == 0.0f);      // beside it, the same frame exactly
}

TEST_CASE("render() into a viewport of the game's framebuffer, resized on the fly", "[gl][embedding]") {
    fx_test::gl_context();
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(fire_scene(false), 40, 30));
    const fx::Camera cam = fire_scene(false).camera;
    GameFrame game(GL_DEPTH_COMPONENT32F, false);
    game.draw(cam, false, 0.0);
    fx.update(0.0, cam); // prepared for 40x30 ...
    const fx::Viewport vp{10, 6, 64, 48};
    fx.render({game.framebuffer, vp, 0}); // ... drawn at 64x48: simulated again for that size
    const fx::Image frame = game.read();
    CHECK(frame.at(5, 3) == kSky);              // outside the viewport: untouched
    CHECK(frame.at(kW - 3, kH - 3) == kSky);
    std::size_t lit = 0;
    for (int y = vp.y; y < vp.y + vp.height; ++y)
        for (int x = vp.x; x < vp.x + vp.width; ++x) lit += frame.at(x, y).r > kSky.r + 0.05f;
    CHECK(lit > 100);
    CHECK(fx.stats().find("fire")->cells_drawn > 0);
}
