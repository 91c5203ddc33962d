// Scene files (terrain/scene.hpp): the shipped scenes load and render; errors name the file and
// the key; only what a scene declares is built.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

#include "fx/error.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "gl_fixture.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

const std::string kScenes = "content/scenes";

// A small valid scene (procedural, 33²), as text, with `extra` spliced in before "camera".
std::string small_scene(const std::string& extra = "", const std::string& fog = "") {
    return R"({
      "terrain": {"procedural": {"size": 33, "spacing": 10, "noise": {"amplitude": 30, "frequency": 0.01, "seed": 2}}},
      )" + (fog.empty() ? std::string() : "\"fog\": " + fog + ",") + extra + R"(
      "camera": {"eye": [160, -100, 150], "target": [160, 160, 0], "fov": 50, "near": 1, "far": 5000}
    })";
}
const std::string kFog = R"({"valley": {"level": 5, "max_thickness": 30},
                             "transfer_function": "../transfer_functions/fog.json", "extinction_scale": 0.05})";

terrain::Scene parse(const std::string& text) {
    return terrain::parse_scene(text, "test.json", fx_test::source_path(kScenes));
}

} // namespace

TEST_CASE("The shipped scenes load", "[terrain][scene]") {
    const terrain::Scene fog = terrain::load_scene(fx_test::source_path(kScenes + "/fog_valley.json"));
    CHECK(fog.ground.size == 257);
    CHECK(fog.ground.spacing == 30.0);
    REQUIRE(fog.fog);
    CHECK(fog.fog->path == fx::RenderPath::PcpExact);
    CHECK(fog.fog->absorb);
    CHECK(fog.fog->thickness.max_height() > 50.0f);
    CHECK_FALSE(fog.aurora);
    CHECK(fog.width == 1024);
    CHECK(fog.height == 768);
    const terrain::Scene aurora = terrain::load_scene(fx_test::source_path(kScenes + "/aurora.json"));
    REQUIRE(aurora.aurora);
    CHECK_FALSE(aurora.fog);
    CHECK(aurora.aurora->ceiling == 16000.0);
    CHECK(aurora.aurora->layer.depth.size == 129);
}

TEST_CASE("Scene errors name the file and the key", "[terrain][scene]") {
    CHECK_THROWS_WITH(terrain::load_scene(fx_test::output_path("no_such_scene.json")),
                      Catch::Contains("no_such_scene.json") && Catch::Contains("cannot open"));
    CHECK_THROWS_WITH(parse("{ \"terrain\": "), Catch::StartsWith("test.json: JSON syntax error at byte"));
    CHECK_THROWS_WITH(parse(R"({"camera": {"eye": [0,0,1], "target": [0,1,0]}})"),
                      Catch::Contains("test.json: terrain: is required"));
    CHECK_THROWS_WITH(parse(small_scene("\"lod\": {\"pixel_eror\": 2},")),
                      Catch::Contains("test.json: lod.pixel_eror: unknown key"));
    CHECK_THROWS_WITH(parse(small_scene("\"lod\": {\"pixel_error\": -2},")),
                      Catch::Contains("test.json: lod.pixel_error: must be positive"));
    CHECK_THROWS_WITH(parse(small_scene("\"render\": {\"width\": \"wide\"},")),
                      Catch::Contains("test.json: render.width: expected an integer"));
    CHECK_THROWS_WITH(parse(small_scene("\"effects\": {},")), Catch::Contains("test.json: effects: expected an array"));
    CHECK_THROWS_WITH(parse(small_scene("", R"({"valley": {"level": 5, "max_thickness": 30},
                                                "transfer_function": "../transfer_functions/fog.json", "path": "pcp-exakt"})")),
                      Catch::Contains("test.json: fog.path: unknown render path 'pcp-exakt'"));
    CHECK_THROWS_WITH(parse(small_scene("", R"({"valley": {"level": 5, "max_thickness": 0},
                                                "transfer_function": "../transfer_functions/fog.json"})")),
                      Catch::Contains("test.json: fog.valley.max_thickness: must be positive"));
    CHECK_THROWS_WITH(parse(small_scene("", R"({"valley": {"level": 5, "max_thickness": 3},
                                                "transfer_function": "missing_tf.json"})")),
                      Catch::Contains("test.json: fog.transfer_function:") && Catch::Contains("missing_tf.json"));
    CHECK_THROWS_WITH(parse(small_scene("", R"({"valley": {"level": 5, "max_thickness": 3}, "density": "thick",
                                                "transfer_function": "../transfer_functions/fog.json"})")),
                      Catch::Contains("test.json: fog.density: expected \"layer_height\" or \"noise\""));
    CHECK_THROWS_WITH(parse(R"({"terrain": {"height_map": "../terrain/missing.png"},
                               "camera": {"eye": [0,0,1], "target": [0,1,0]}})"),
                      Catch::Contains("test.json: terrain.height_map:") && Catch::Contains("missing.png"));
    CHECK_THROWS_WITH(parse(R"({"terrain": {"procedural": {"size": 100, "noise": {}}},
                               "camera": {"eye": [0,0,1], "target": [0,1,0]}})"),
                      Catch::Contains("test.json: terrain.procedural.size: must be 2^n + 1"));
    CHECK_THROWS_WITH(parse(R"({"terrain": {"height_map": "../terrain/st_helens_257.png"},
                               "fog": {"thickness_map": {"file": "../terrain/st_helens_257.png", "vertical_offset": -2000},
                                       "transfer_function": "../transfer_functions/fog.json"},
                               "camera": {"eye": [0,0,1], "target": [0,1,0]}})"),
                      Catch::Contains("test.json: fog.thickness_map: the fog map has negative thickness"));
    CHECK_THROWS_WITH(parse(R"({"terrain": {"procedural": {"size": 33, "noise": {}}},
                               "camera": {"eye": [0,0,1], "target": [0,0,1]}})"),
                      Catch::Contains("test.json: camera.target: is the eye position"));
    CHECK_THROWS_WITH(parse(R"({"terrain": {"procedural": {"size": 33, "noise": {"octaves": 40}}},
                               "camera": {"eye": [0,0,1], "target": [0,1,0]}})"),
                      Catch::Contains("test.json: terrain.procedural.noise.octaves: must be in 1..16"));
}

TEST_CASE("A fog map file on the terrain's grid, and noise density", "[terrain][scene]") {
    // St. Helens' own height map, scaled by 0.1, as a fog map (94 .. 254 units thick).
    const terrain::Scene s = parse(R"({"terrain": {"height_map": "../terrain/st_helens_257.png", "spacing": 30},
        "fog": {"thickness_map": {"file": "../terrain/st_helens_257.png", "vertical_scale": 0.1},
                "density": "noise", "density_noise": {"amplitude": 1, "offset": 0.5, "frequency": 0.003},
                "transfer_function": "../transfer_functions/fog.json", "path": "mip"},
        "camera": {"eye": [0, 0, 3000], "target": [3000, 3000, 1500]}})");
    REQUIRE(s.fog);
    CHECK(s.fog->thickness.at(100, 100) == Approx(0.1 * s.ground.at(100, 100)));
    CHECK(s.fog->prisms.density == terrain::LayerDensity::Noise);
    CHECK(s.fog->path == fx::RenderPath::Mip);
    const double v = s.fog->prisms.noise(1234.0, 987.0);
    CHECK(std::isfinite(v));
    CHECK(v == s.fog->prisms.noise(1234.0, 987.0)); // deterministic
}

TEST_CASE("Scenes render and only what they declare is built", "[gl][terrain][scene]") {
    fx_test::gl_context();
    terrain::Scene with_fog = parse(small_scene("", kFog));
    terrain::Scene without = parse(small_scene());
    terrain::SceneRenderer a(with_fog), b(without);
    terrain::FrameStats sa, sb;
    const fx::Image ia = a.render_to_image(with_fog.camera, 96, 72, &sa);
    const fx::Image ib = b.render_to_image(without.camera, 96, 72, &sb);
    fx_test::require_no_gl_error();
    CHECK(sa.fog_prisms.prisms > 0);
    CHECK(a.fog_prisms().cell_count() == sa.fog_prisms.prisms);
    CHECK(sb.fog_prisms.prisms == 0);
    CHECK(b.fog_prisms().cell_count() == 0);
    CHECK(sb.fog.draw_calls == 0); // no fog section: nothing built or drawn for it
    CHECK(sb.aurora.draw_calls == 0);
    // Same terrain LOD either way? No: fog drives refinement, so the fogged one has at least as many.
    CHECK(sa.terrain_lod.triangles >= sb.terrain_lod.triangles);
    // The fog changes the picture (whiter where it lies), nothing is NaN, the frame is opaque.
    std::size_t whiter = 0;
    for (std::size_t i = 0; i < ia.pixels.size(); ++i) {
        REQUIRE(std::isfinite(ia.pixels[i].r));
        CHECK(ia.pixels[i].a == Approx(1.0f));
        if (ia.pixels[i].r > ib.pixels[i].r + 0.02f) ++whiter;
    }
    CHECK(whiter > 50);
    // Every path renders the same scene; a second frame is incremental.
    for (fx::RenderPath path : fx::kRenderPaths) {
        a.set_fog_path(path);
        terrain::FrameStats s;
        fx::Camera moved = with_fog.camera;
        moved.eye.x += 1.0;
        a.render_to_image(moved, 96, 72, &s);
        CHECK_FALSE(s.terrain_lod.full_rebuild);
        CHECK(s.fog.draw_calls > 0);
    }
}

TEST_CASE("The shipped fog valley and aurora render", "[gl][terrain][scene]") {
    fx_test::gl_context();
    for (const char* name : {"fog_valley.json", "aurora.json"}) {
        INFO(name);
        const terrain::Scene scene = terrain::load_scene(fx_test::source_path(kScenes + "/" + name));
        terrain::SceneRenderer renderer(scene);
        terrain::FrameStats stats;
        const fx::Image image = renderer.render_to_image(scene.camera, 128, 96, &stats);
        fx_test::require_no_gl_error();
        CHECK(stats.terrain_lod.triangles > 200); // a 128x96 view needs few
        CHECK(stats.fog_prisms.prisms + stats.aurora_prisms.prisms > 500);
        double light = 0.0;
        for (const glm::vec4& p : image.pixels) {
            REQUIRE(std::isfinite(p.r + p.g + p.b));
            light += p.r + p.g + p.b;
        }
        CHECK(light > 10.0);
    }
}

TEST_CASE("SceneRenderer draws into the host's framebuffer and viewport", "[gl][terrain][scene]") {
    fx_test::gl_context();
    terrain::Scene scene = parse(small_scene("", kFog));
    terrain::SceneRenderer renderer(scene);
    const fx::Image alone = renderer.render_to_image(scene.camera, 64, 48);
    // A host target larger than the viewport, cleared to a marker colour.
    fx::gl::RenderTarget host = fx::gl::RenderTarget::create(100, 80, fx::gl::ColorFormat::RGBA32F, false);
    const glm::vec4 marker(0.25f, 0.5f, 0.75f, 1.0f);
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        host.clear(marker);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, host.framebuffer());
        renderer.render(scene.camera, fx::Viewport{20, 10, 64, 48});
    }
    fx_test::require_no_gl_error();
    const fx::Image frame = host.read();
    fx::Image in_viewport(64, 48);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) in_viewport.at(x, y) = frame.at(20 + x, 10 + y);
    fx_test::check_image("scene_in_viewport", in_viewport, alone,
                         verify::same_picture(1e-5, "the same frame, in the viewport: float rounding of the blend"));
    CHECK(frame.at(5, 5) == marker);      // outside it the host's pixels are untouched
    CHECK(frame.at(90, 70) == marker);
}
