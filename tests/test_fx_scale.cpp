// The effects at a reduced resolution (Scene::fx_scale, Config::fx_scale, --fx-scale): every
// effect path and the one medium drawn at 1/2 or 1/4 of the view's resolution and upsampled
// against the game's depth (terrain/src/render/fx_layer.hpp). A campfire behind the edge of the
// game's opaque box, at every scale, alone and inside a mist with either medium method: not a
// trace of fire more than 1 px into the box, and no hole wider than 1 px along its edges; the
// scale and medium are read from scene files and options, and bad values refused by name.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "cellfx/cellfx.hpp"
#include "embedding_support.hpp"
#include "gl/state_guard.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

constexpr int kW = 128, kH = 96;
const glm::vec4 kSky = embedding_test::kSky, kBox = embedding_test::kBox;
// The game's box: edges off every 2- and 4-pixel block boundary (x = 61, y = 23 and 71), so
// that reduced pixels straddle them. The fire stands around the centre: the right and both
// horizontal edges cross it.
constexpr int kBoxRight = 61, kBoxBottom = 23, kBoxTop = 71;
bool in_box(int x, int y) { return x < kBoxRight && y >= kBoxBottom && y < kBoxTop; }
// Pixels from the box's boundary, inside (> 0: 1 is the boundary pixel) or outside (≤ 0).
int depth_into_box(int x, int y) {
    if (!in_box(x, y)) return 0;
    return std::min({kBoxRight - x, y - kBoxBottom + 1, kBoxTop - y});
}

// The game's frame: sky (depth 1) and, with `box`, the box at view depth z (scissored clears).
struct Game {
    GLuint framebuffer = 0, color = 0, depth = 0;
    Game() {
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(color, 1, GL_RGBA32F, kW, kH);
        glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT32F, kW, kH);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth, 0);
    }
    ~Game() {
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
    Game(const Game&) = delete;
    Game& operator=(const Game&) = delete;
    void draw(const fx::Camera& cam, bool box, double z) const {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        const GLfloat sky[4] = {kSky.r, kSky.g, kSky.b, kSky.a}, red[4] = {kBox.r, kBox.g, kBox.b, kBox.a};
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, 1.0f, 0);
        if (!box) return;
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, kBoxBottom, kBoxRight, kBoxTop - kBoxBottom);
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, red);
        const double n = cam.near_distance, f = cam.far_distance;
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, float(f * (z - n) / (z * (f - n))), 0);
    }
    fx::Image read() const {
        fx::Image image(kW, kH);
        glGetTextureImage(color, 0, GL_RGBA, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(glm::vec4)), image.pixels.data());
        return image;
    }
};

// The embedding tests' campfire (flame at the origin, the eye 3 units off), smooth (no
// turbulence: the fire's light varies slowly across a reduced pixel), alone or in a mist box
// around it whose nearest corner is 2.0 units from the eye, so a box at 1.4 is in front of all.
terrain::Scene scene(bool mist) {
    terrain::Scene s = embedding_test::fire_scene(false, R"("turbulence": 0,)");
    if (mist) {
        terrain::EffectSpec m;
        m.name = "mist";
        fx::VolumeParams p;
        p.shape = fx::VolumeShape::Box;
        p.size = {1.4, 1.4, 1.6};
        p.position = {0.0, 0.0, 0.7};
        p.density = 1.0;
        p.density_mode = fx::VolumeDensity::Constant;
        p.cells = 6;
        m.params = p;
        m.transfer_function = fx::TransferFunction::constant({0.35, 0.4, 0.5}, 0.8);
        m.absorb = true;
        m.albedo = 0.6;
        s.effects.push_back(m);
    }
    return s;
}

float excess(const glm::vec4& p) { return glm::length(glm::vec3(p) - glm::vec3(kSky)); }

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

} // namespace

TEST_CASE("A campfire behind the edge of the game's box at every fx scale: no fire on the box, no hole beside it",
          "[gl][fx_scale]") {
    fx_test::gl_context();
    const double box_depth = 1.4;
    struct Case {
        const char* name;
        bool mist;
        fx::MediumMethod method;
    } cases[] = {{"fire", false, fx::MediumMethod::Froxel},
                 {"fire_in_mist_froxel", true, fx::MediumMethod::Froxel},
                 {"fire_in_mist_exact", true, fx::MediumMethod::Exact}};
    for (const Case& c : cases)
        for (double scale : {1.0, 0.5, 0.25}) {
            INFO(c.name << " at fx scale " << scale);
            const terrain::Scene s = scene(c.mist);
            const fx::Camera cam = s.camera;
            cellfx::Config config = cellfx::Config::from_scene(s, kW, kH);
            config.fx_scale = scale;
            config.medium = c.method;
            cellfx::Module fx;
            fx.init(config);
            REQUIRE(fx.fx_scale() == scale);
            Game game;
            fx.update(0.0, cam);
            game.draw(cam, false, 0.0);
            fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
            const fx::Image open = game.read();
            game.draw(cam, true, box_depth);
            fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
            fx_test::require_no_gl_error();
            if (c.mist) CHECK(fx.stats().medium.pixels > 0); // the fire and the mist are one medium
            const fx::Image boxed = game.read();
            const std::string tag = std::string("fx_scale_") + c.name + "_" + std::to_string(int(1.0 / scale));
            fx::write_png(boxed, fx_test::output_path(tag + ".png"));

            // The box: exactly its colour more than 1 px from its boundary (anything else is fire
            // or mist drawn over it); the boundary pixels are reported.
            std::size_t on_box = 0, on_boundary = 0, box_pixels = 0;
            float peak = 0.0f;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    peak = std::max(peak, excess(open.at(x, y)));
                    const int d = depth_into_box(x, y);
                    if (d == 0) continue;
                    ++box_pixels;
                    const bool touched = boxed.at(x, y) != kBox;
                    if (d > 1) on_box += touched;
                    else on_boundary += touched;
                }
            REQUIRE(box_pixels > 1000);
            REQUIRE(peak > 0.3f);
            // Beside the box: where the frame without the box shows the fire (≥ 5% of its peak
            // over the sky), the boxed frame must too — at least half of it (the fire is smooth,
            // and a pixel at an edge takes a neighbour up to 1.5 reduced pixels away). A hole is
            // a run of pixels without it, counted outward from the box's edge: along the right
            // edge per row, along the top and bottom per column.
            const auto hole = [&](int x, int y) {
                const float e = excess(open.at(x, y));
                return e >= 0.05f * peak && excess(boxed.at(x, y)) < 0.5f * e;
            };
            int widest = 0, fire_rows = 0;
            for (int y = kBoxBottom; y < kBoxTop; ++y) {
                if (excess(open.at(kBoxRight + 4, y)) >= 0.05f * peak) ++fire_rows;
                int run = 0;
                for (int x = kBoxRight; x < kW && hole(x, y); ++x) ++run;
                widest = std::max(widest, run);
            }
            for (int x = 0; x < kBoxRight; ++x) {
                int below = 0, above = 0;
                for (int y = kBoxBottom - 1; y >= 0 && hole(x, y); --y) ++below;
                for (int y = kBoxTop; y < kH && hole(x, y); ++y) ++above;
                widest = std::max({widest, below, above});
            }
            // And away from the edges (4 reduced pixels and more) the box changes nothing.
            float far_change = 0.0f;
            const int margin = int(4.0 / scale) + 1;
            for (int y = 0; y < kH; ++y)
                for (int x = 0; x < kW; ++x) {
                    if (in_box(x, y)) continue;
                    const int dx = x >= kBoxRight ? x - kBoxRight : 1 << 20;
                    const int dy = y < kBoxBottom ? kBoxBottom - 1 - y : y >= kBoxTop ? y - kBoxTop : 1 << 20;
                    if (std::min(dx, dy) >= margin) far_change = std::max(far_change, glm::length(boxed.at(x, y) - open.at(x, y)));
                }
            INFO("box pixels touched beyond 1 px: " << on_box << ", on its boundary: " << on_boundary << "; widest hole "
                                                    << widest << " px over " << fire_rows << " rows of fire beside the box; "
                                                    << "change far from the box " << far_change << "; images: "
                                                    << fx_test::output_path(tag + ".png"));
            CHECK(fire_rows > 10); // the fire really crosses the box's edge
            CHECK(on_box == 0);
            CHECK(widest <= 1);
            // Far from the box every reduced pixel the upsample reads was drawn without it; the
            // froxel grid's tiles near the box read the box's depth only at its pixels.
            CHECK(far_change <= 1e-6f);
        }
}

TEST_CASE("fx scale and medium method: from the scene file, the options, run-time setters, bad values refused",
          "[gl][fx_scale]") {
    const std::string dir = fx_test::source_path("content/scenes");
    const auto parse = [&](const std::string& render) {
        return terrain::parse_scene(R"({"effects": [{"type": "campfire", "name": "fire", "transfer_function": "../transfer_functions/fire.json"}],
            "camera": {"eye": [3, -4, 2], "target": [0, 0, 0.5], "up": [0, 0, 1]}, "render": )" + render + "}",
                                    "scale.json", dir);
    };
    CHECK(parse("{}").fx_scale == 1.0);
    CHECK(parse("{}").medium == fx::MediumMethod::Froxel);
    CHECK(parse(R"({"fx_scale": 0.5})").fx_scale == 0.5);
    CHECK(parse(R"({"fx_scale": 0.25, "medium": "exact"})").medium == fx::MediumMethod::Exact);
    CHECK_THROWS_WITH(parse(R"({"fx_scale": 0.3})"), Catch::Contains("scale.json: render.fx_scale") && Catch::Contains("1, 0.5 or 0.25"));
    CHECK_THROWS_WITH(parse(R"({"fx_scale": "half"})"), Catch::Contains("render.fx_scale") && Catch::Contains("number"));
    CHECK_THROWS_WITH(parse(R"({"medium": "voxels"})"), Catch::Contains("render.medium") && Catch::Contains("froxel or exact"));

    fx_test::gl_context();
    cellfx::Config config = cellfx::Config::from_scene(parse("{}"), 64, 48);
    config.fx_scale = 0.3;
    cellfx::Module fx;
    CHECK_THROWS_WITH(fx.init(config), Catch::Contains("fx_scale") && Catch::Contains("1, 0.5 or 0.25"));
    config.fx_scale = 0.25;
    config.medium = fx::MediumMethod::Exact;
    fx.init(config);
    CHECK(fx.fx_scale() == 0.25);
    CHECK(fx.medium_method() == fx::MediumMethod::Exact);
    CHECK_FALSE(fx.try_set_fx_scale(2.0).ok());
    CHECK(fx.fx_scale() == 0.25); // a refused value changes nothing
    fx.set_fx_scale(0.5);
    fx.set_medium_method(fx::MediumMethod::Froxel);
    fx.reload(parse(R"({"fx_scale": 1, "medium": "exact"})")); // the game's choices are kept
    CHECK(fx.fx_scale() == 0.5);
    CHECK(fx.medium_method() == fx::MediumMethod::Froxel);

    const std::string scene = fx_test::source_path("content/scenes/campfire.json");
    for (const auto& [option, message] : {std::pair<std::string, std::string>{"--fx-scale 3", "--fx-scale: '3' must be 1, 0.5 or 0.25"},
                                          {"--medium voxels", "--medium: unknown method 'voxels'"}}) {
        const std::string log = fx_test::output_path("fx_scale_option.log");
        const std::string command = std::string("'") + CELLFX_CLI + "' render '" + scene + "' " + option + " --out '" +
                                    fx_test::output_path("x.png") + "' > '" + log + "' 2>&1";
        INFO(command);
        CHECK(std::system(command.c_str()) != 0);
        CHECK_THAT(read_text(log), Catch::Contains(message));
    }
}
