// The embedding API (cellfx/cellfx.hpp) in a headless context, as a game uses it: the game's own
// framebuffer with a depth texture attached, an opaque box drawn into it in front of the fire,
// cellfx drawing over that frame. The fire must be hidden behind the box and visible beside it
// (against the scan-line reference), the box untouched, and the game's GL state unchanged.
#include <catch2/catch.hpp>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "cellfx/cellfx.hpp"
#include "gl/state_guard.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"

using effects_test::look;

namespace {

constexpr int kW = 96, kH = 72;
const glm::vec4 kSky(0.10f, 0.15f, 0.22f, 1.0f);
const glm::vec4 kBox(0.80f, 0.30f, 0.20f, 1.0f);
// The box's screen rectangle: the left half, a band through the middle of the fire.
bool in_box(int x, int y) { return x < kW / 2 && y >= kH / 4 && y < 3 * kH / 4; }

// GL window depth of a point at view depth z (GL's default depth range, perspective).
float window_depth(const fx::Camera& cam, double z) {
    const double n = cam.near_distance, f = cam.far_distance;
    return float(f * (z - n) / (z * (f - n)));
}

// A game's framebuffer: colour + a depth texture, attached. `depth_format` is the game's
// choice; `compare` sets a shadow-sampler compare mode on it (a game may leave one set).
struct GameFrame {
    GLuint framebuffer = 0, color = 0, depth = 0;
    GameFrame(GLenum depth_format, bool compare) {
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glTextureStorage2D(color, 1, GL_RGBA32F, kW, kH);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(depth, 1, depth_format, kW, kH);
        if (compare) glTextureParameteri(depth, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, depth_format == GL_DEPTH24_STENCIL8 ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                                  depth, 0);
        REQUIRE(glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    }
    ~GameFrame() {
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
    // The game's opaque pass: sky everywhere (depth 1), the box's front face at view depth z.
    void draw(const fx::Camera& cam, bool box, double z) const {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        const GLfloat sky[4] = {kSky.r, kSky.g, kSky.b, kSky.a}, red[4] = {kBox.r, kBox.g, kBox.b, kBox.a};
        const GLfloat far = 1.0f, near = window_depth(cam, z);
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, far, 0);
        if (!box) return;
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, kH / 4, kW / 2, kH / 2);
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, red);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, near, 0);
    }
    fx::Image read() const {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        fx::Image image(kW, kH);
        glGetTextureImage(color, 0, GL_RGBA, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(glm::vec4)), image.pixels.data());
        return image;
    }
};

terrain::Scene fire_scene(bool with_terrain) {
    const std::string terrain = R"("terrain": {"procedural": {"size": 33, "spacing": 0.5, "origin": [-8, -8],
                                                  "noise": {"amplitude": 0.2, "frequency": 0.2, "seed": 5}}},)";
    return terrain::parse_scene(R"({)" + (with_terrain ? terrain : std::string()) + R"(
        "effects": [{"type": "campfire", "name": "fire", "position": [0, 0, 0],
                     "transfer_function": "../transfer_functions/fire.json", "extinction_scale": 0.15}],
        "camera": {"eye": [1.6, -2.4, 1.2], "target": [0, 0, 0.6], "fov": 45, "near": 0.05, "far": 100}})",
                                "embedding.json", fx_test::source_path("content/scenes"));
}

} // namespace

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
        const fx::Effect& fire = *fx.effect<fx::Campfire>("fire");
        const fx::CellMesh world = effects_test::world_mesh(fire);
        fx::ScanlineOptions so;
        so.model = fx::OpticalModel::Emission;
        const fx::TransferFunction tf = scene.effects[0].transfer_function.rescaled(0.0, 1.0);
        const fx::Image light = fx::ScanlineRenderer(world).render(cam, kW, kH, world.scalars[0], tf, so);
        fx::Image expected(kW, kH);
        std::size_t hidden = 0, beside = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const glm::vec3 fire_light(light.at(x, y));
                const bool lit = fire_light.r > 0.02f;
                if (in_box(x, y)) {
                    expected.at(x, y) = kBox; // the box is in front of all of the fire
                    hidden += lit;
                } else {
                    expected.at(x, y) = glm::vec4(glm::vec3(kSky) + fire_light, 1.0f);
                    beside += lit;
                }
            }
        CHECK(hidden > 100); // the box really covers part of the fire ...
        CHECK(beside > 100); // ... and leaves part of it in view
        float box_error = 0.0f;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                if (in_box(x, y)) box_error = std::max(box_error, glm::length(frame.at(x, y) - kBox));
        CHECK(box_error == 0.0f); // not a trace of fire on the box
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
