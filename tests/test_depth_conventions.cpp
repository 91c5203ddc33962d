// Every common depth set-up a game draws with works, or is refused with a message naming what is
// wrong: standard depth (GL's clip control or GL_ZERO_TO_ONE), reversed-Z (GL_ZERO_TO_ONE,
// GL_GREATER, cleared to 0) with finite and infinite far planes, the game's projection planes
// differing from the camera's, DEPTH_COMPONENT24 / 32F / DEPTH24_STENCIL8 and 4x multisampled
// depth. The game draws a box in front of part of the campfire as real geometry through its own
// projection, clip control and depth test (left set when cellfx renders); the frame must show the
// box untouched and beside it the fire as the scan-line reference draws it. And a y-up game
// (Config::world_up) sees the very frame a z-up game sees.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "embedding_support.hpp"
#include "cellfx_names.hpp"

using namespace embedding_test;

namespace {

constexpr double kBoxDepth = 1.4; // in front of all of the fire (its nearest point is ≥ 2.2 away)

double aspect() { return double(kW) / kH; }

// glm's projections, D3D-style depth (near → 0, far → 1 in clip z / w).
glm::dmat4 zero_to_one(const fx::Camera& c, double n, double f) {
    return glm::perspectiveRH_ZO(glm::radians(c.fov_y_degrees), aspect(), n, f);
}
// The same reversed: clip z' = w − z, so near → 1 and far → 0.
glm::dmat4 reversed(glm::dmat4 p) {
    for (int col = 0; col < 4; ++col) p[col][2] = p[col][3] - p[col][2];
    return p;
}
// Reversed-Z with an infinite far plane: depth = near / z.
glm::dmat4 reversed_infinite(const fx::Camera& c, double n) {
    const double t = std::tan(glm::radians(c.fov_y_degrees) / 2.0);
    glm::dmat4 p(0.0);
    p[0][0] = 1.0 / (aspect() * t);
    p[1][1] = 1.0 / t;
    p[2][3] = -1.0;
    p[3][2] = n;
    return p;
}

struct Case {
    const char* name;
    GameProjection projection;
};

std::vector<Case> conventions(const fx::Camera& cam) {
    const double n = cam.near_distance, f = cam.far_distance, inf = std::numeric_limits<double>::infinity();
    const double rad = glm::radians(cam.fov_y_degrees);
    std::vector<Case> cases;
    cases.push_back({"standard", standard_projection(cam)});
    cases.push_back({"standard, GL_ZERO_TO_ONE", {zero_to_one(cam, n, f), GL_ZERO_TO_ONE, GL_LESS, 1.0f, {}}});
    cases.push_back({"reversed-Z", {reversed(zero_to_one(cam, n, f)), GL_ZERO_TO_ONE, GL_GREATER, 0.0f, {true, 0.0, 0.0}}});
    cases.push_back({"reversed-Z, infinite far plane",
                     {reversed_infinite(cam, n), GL_ZERO_TO_ONE, GL_GREATER, 0.0f, {true, n, inf}}});
    cases.push_back({"standard, the game's own planes 0.2 .. 500",
                     {glm::perspective(rad, aspect(), 0.2, 500.0), GL_NEGATIVE_ONE_TO_ONE, GL_LESS, 1.0f, {false, 0.2, 500.0}}});
    cases.push_back({"standard, infinite far plane",
                     {glm::infinitePerspective(rad, aspect(), n), GL_NEGATIVE_ONE_TO_ONE, GL_LESS, 1.0f, {false, n, inf}}});
    return cases;
}

void restore_gl_defaults() {
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
}

} // namespace

TEST_CASE("Every common depth set-up hides the fire behind the game's box, exactly as standard depth does",
          "[gl][embedding][depth]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(false);
    const fx::Camera cam = scene.camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    fx.update(0.0, cam);
    const fx::Image expected = expected_frame(fx, cam);
    for (const Case& c : conventions(cam)) {
        for (GLenum format : {GLenum(GL_DEPTH_COMPONENT24), GLenum(GL_DEPTH_COMPONENT32F), GLenum(GL_DEPTH24_STENCIL8)}) {
            for (int samples : {1, 4}) {
                INFO(c.name << ", depth format 0x" << std::hex << format << std::dec << ", " << samples << " sample(s)");
                GameFrame game(format, false, samples);
                game.draw_geometry(cam, c.projection, kBoxDepth);
                fx.update(0.0, cam);
                fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth, c.projection.convention});
                restore_gl_defaults();
                fx_test::require_no_gl_error();
                const fx::Image frame = game.read();
                // The box pixels are the game's alone: the normalized depth puts it in front of the
                // whole fire, in every convention (no trace of fire, not one bit).
                CHECK(box_error(frame) == 0.0f);
                effects_test::check_frame("depth_convention", frame, expected, fx::RenderPath::PcpExact, 20);
            }
        }
    }
}

TEST_CASE("With cellfx's terrain, reversed-Z multisampled depth gives the standard-depth frame", "[gl][embedding][depth]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(true);
    const fx::Camera cam = scene.camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    REQUIRE(fx.terrain_drawn());
    auto frame = [&](const GameProjection& p, GLenum format, int samples) {
        GameFrame game(format, false, samples);
        game.draw_geometry(cam, p, kBoxDepth);
        fx.update(0.0, cam);
        fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth, p.convention});
        restore_gl_defaults();
        fx_test::require_no_gl_error();
        return game.read();
    };
    // The standard frame (itself tested against the scan-line reference above and in
    // test_embedding.cpp) and the reversed-Z one: the box hides terrain and fire alike, and the
    // terrain and fire beside it are depth-tested against the game's depth the same way.
    const fx::Image standard = frame(standard_projection(cam), GL_DEPTH_COMPONENT32F, 1);
    const Case reversed_z = conventions(cam)[2];
    const fx::Image reversed_ms = frame(reversed_z.projection, GL_DEPTH_COMPONENT32F, 4);
    CHECK(box_error(standard) == 0.0f);
    CHECK(box_error(reversed_ms) == 0.0f);
    fx_test::check_image("depth_terrain_reversed", reversed_ms, standard,
                         verify::same_picture(1e-6, "the same draws, the box's normalized depth differing by float rounding only"));
    std::size_t terrain_pixels = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) terrain_pixels += !in_box(x, y) && glm::length(standard.at(x, y) - kSky) > 0.01f;
    CHECK(terrain_pixels > 500);
}

TEST_CASE("A depth texture cellfx cannot read is refused, naming it, and the next frame works", "[gl][embedding][depth]") {
    fx_test::gl_context();
    const fx::Camera cam = fire_scene(false).camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(fire_scene(false), kW, kH));
    GameFrame game(GL_DEPTH_COMPONENT32F, false);
    game.draw(cam, false, 0.0);
    GLuint color = 0, array = 0, small = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA8, kW, kH);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
    glTextureStorage3D(array, 1, GL_DEPTH_COMPONENT32F, kW, kH, 2);
    glCreateTextures(GL_TEXTURE_2D, 1, &small);
    glTextureStorage2D(small, 1, GL_DEPTH_COMPONENT24, kW / 2, kH);
    fx.update(0.0, cam);
    const fx::Viewport all{0, 0, kW, kH};
    CHECK_THROWS_WITH(fx.render({game.framebuffer, all, color}),
                      Catch::Contains("depth_texture " + std::to_string(color)) && Catch::Contains("not a depth format"));
    CHECK_THROWS_WITH(fx.render({game.framebuffer, all, array}), Catch::Contains("GL_TEXTURE_2D_ARRAY"));
    CHECK_THROWS_WITH(fx.render({game.framebuffer, all, small}), Catch::Contains("48x72, too small for the viewport 96x72"));
    CHECK_THROWS_WITH(fx.render({game.framebuffer, all, 987654}), Catch::Contains("987654 is not a texture"));
    const cellfx::Status s = fx.try_render({game.framebuffer, all, game.depth, {true, 10.0, 5.0}});
    CHECK_FALSE(s.ok());
    CHECK_THAT(s.message(), Catch::Contains("far plane (5.000000) must lie beyond the near plane (10.000000)"));
    fx_test::require_no_gl_error();
    // The module is still good: the next frame draws the fire.
    fx.render({game.framebuffer, all, game.depth});
    std::size_t lit = 0;
    for (const glm::vec4& p : game.read().pixels) lit += p.r > kSky.r + 0.1f;
    CHECK(lit > 100);
    glDeleteTextures(1, &color);
    glDeleteTextures(1, &array);
    glDeleteTextures(1, &small);
}

TEST_CASE("A y-up game sees the frame a z-up game sees, and attaches effects in its own frame", "[gl][embedding][depth]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(false);
    // World (x, y, z) of a y-up game is scene (x, −z, y): the same camera in the game's frame.
    auto to_y_up = [](const glm::dvec3& v) { return glm::dvec3(v.x, v.z, -v.y); };
    fx::Camera cam_y = scene.camera;
    cam_y.eye = to_y_up(cam_y.eye), cam_y.target = to_y_up(cam_y.target), cam_y.up = to_y_up(cam_y.up);
    cellfx::Module z_up, y_up;
    z_up.init(cellfx::Config::from_scene(scene, kW, kH));
    cellfx::Config config = cellfx::Config::from_scene(scene, kW, kH);
    config.world_up = cellfx::WorldUp::Y;
    y_up.init(config);
    // An object turned 30° about its up axis and moved: z-up about z, y-up about y.
    const glm::dmat4 object_z = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0.2, 0.0)), 0.5, glm::dvec3(0, 0, 1));
    const glm::dmat4 object_y = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0.0, -0.2)), 0.5, glm::dvec3(0, 1, 0));
    z_up.set_parent_transform("fire", object_z);
    y_up.set_parent_transform("fire", object_y);
    auto frame = [](cellfx::Module& fx, const fx::Camera& cam) {
        GameFrame game(GL_DEPTH_COMPONENT32F, false);
        game.draw(cam, true, kBoxDepth); // the box's depth depends on near, far and z only
        fx.update(0.0, cam);
        fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
        return game.read();
    };
    const fx::Image z_frame = frame(z_up, scene.camera), y_frame = frame(y_up, cam_y);
    // The rotation between the frames is exact in floating point (a permutation and a sign):
    // the same bits.
    fx_test::check_image("world_up_y", y_frame, z_frame, verify::same_picture(0.0, "an exact rotation: the same bits"));
    CHECK(y_up.effect<fx::Campfire>("fire")->transform() == z_up.effect<fx::Campfire>("fire")->transform());
    const fx::Camera back = y_up.scene_camera();
    CHECK(back.eye == cam_y.eye);
    CHECK(back.up == cam_y.up);
    // And the z-up frame, the fire moved by its parent, against the scan-line reference.
    CHECK(box_error(z_frame) == 0.0f);
    effects_test::check_frame("world_up_z", z_frame, expected_frame(z_up, scene.camera), fx::RenderPath::PcpExact, 20);
}

TEST_CASE("A game's reversed-Z state that target.depth does not declare is refused, saying what to set",
          "[gl][embedding][depth]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(false);
    const fx::Camera cam = scene.camera;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    const fx::Image expected = [&] {
        fx.update(0.0, cam);
        return expected_frame(fx, cam);
    }();
    const GameProjection reversed_z = conventions(cam)[2].projection;
    REQUIRE(reversed_z.convention.reversed);

    // A game drawing reversed-Z (GL_GREATER, GL_ZERO_TO_ONE, cleared to 0), its state left set,
    // that forgets target.depth.reversed: read as standard depth its depth would hide almost the
    // whole fire. Refused before any GL state changes, and the game's frame is untouched.
    GameFrame game(GL_DEPTH_COMPONENT32F, false);
    game.draw_geometry(cam, reversed_z, kBoxDepth);
    const fx::Image before = game.read();
    fx.update(0.0, cam);
    const cellfx::Target forgot{game.framebuffer, {0, 0, kW, kH}, game.depth};
    CHECK_THROWS_WITH(fx.render(forgot), Catch::Contains("the game draws reversed-Z (glDepthFunc GL_GREATER, "
                                                         "glClipControl GL_ZERO_TO_ONE)") &&
                                             Catch::Contains("set target.depth.reversed = true"));
    const cellfx::Status s = fx.try_render(forgot);
    CHECK_FALSE(s);
    CHECK_THAT(s.message(), Catch::Contains("target.depth.reversed"));
    GLint func = 0, clip = 0;
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip);
    CHECK(func == GL_GREATER); // the game's state as it was
    CHECK(clip == GL_ZERO_TO_ONE);
    fx_test::check_image("depth_refused_untouched", game.read(), before, verify::same_picture(0.0, "nothing drawn"));

    // Declared, the same state draws the standard frame.
    fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth, reversed_z.convention});
    restore_gl_defaults();
    fx_test::require_no_gl_error();
    const fx::Image frame = game.read();
    CHECK(box_error(frame) == 0.0f);
    effects_test::check_frame("depth_declared", frame, expected, fx::RenderPath::PcpExact, 20);

    // A reversed-Z game that resets its depth test and clip control to GL's defaults before
    // render(): the state tells nothing, the declared convention is taken, the frame is right.
    game.draw_geometry(cam, reversed_z, kBoxDepth);
    restore_gl_defaults();
    fx.update(0.0, cam);
    fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth, reversed_z.convention});
    fx_test::require_no_gl_error();
    CHECK(box_error(game.read()) == 0.0f);
    effects_test::check_frame("depth_declared_reset", game.read(), expected, fx::RenderPath::PcpExact, 20);
}
