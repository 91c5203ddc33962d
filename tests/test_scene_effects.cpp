// Scenes with effects (terrain/scene.hpp, terrain/scene_renderer.hpp): the format's additions
// and their errors, camera paths, and what SceneRenderer::update simulates — only the effects
// the scene calls for: an effect outside the view costs no cells and no noise samples, a
// disabled one nothing, a static one is not rebuilt, an animated one re-evaluates only when its
// time advanced — and that what it draws after scalar-only and pose-only updates is right.
#include <catch2/catch.hpp>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/error.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using effects_test::look;

namespace {

const std::string kScenes = "content/scenes";

terrain::Scene parse(const std::string& text) {
    return terrain::parse_scene(text, "fx.json", fx_test::source_path(kScenes));
}

// An effects-only scene: `effects` is the JSON array's contents.
std::string effect_scene(const std::string& effects, const std::string& extra = "") {
    return R"({"effects": [)" + effects + "], " + extra +
           R"("camera": {"eye": [0, -5, 1], "target": [0, 0, 0.7], "fov": 45, "near": 0.05, "far": 500}})";
}
const std::string kFire = R"("transfer_function": "../transfer_functions/fire.json", "extinction_scale": 0.05)";
const std::string kBeam = R"("transfer_function": "transfer_functions/searchlight.json", "extinction_scale": 0.1)";

// Draws `renderer`'s updated frame over a black float target and reads it back.
fx::Image draw_over_black(terrain::SceneRenderer& renderer, int w, int h, terrain::FrameStats* stats = nullptr) {
    fx::gl::RenderTarget host = fx::gl::RenderTarget::create(w, h, fx::gl::ColorFormat::RGBA32F, false);
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        host.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    }
    const terrain::FrameStats s = renderer.render(terrain::Target{host.framebuffer(), {0, 0, w, h}, 0});
    if (stats) *stats = s;
    fx_test::require_no_gl_error();
    return host.read();
}

} // namespace

TEST_CASE("The effect scenes load", "[scene][effects]") {
    const terrain::Scene fire = terrain::load_scene(fx_test::source_path(kScenes + "/campfire.json"));
    REQUIRE(fire.effects.size() == 1);
    CHECK(fire.effects[0].name == "fire");
    CHECK(std::string(terrain::effect_type_name(fire.effects[0].params)) == "campfire");
    CHECK(std::get<fx::CampfireParams>(fire.effects[0].params).cells_across == 16);
    CHECK(fire.effects[0].path == fx::RenderPath::PcpExact);
    CHECK(fire.effects[0].enabled);
    CHECK(fire.has_terrain());
    CHECK(fire.draw_terrain);
    REQUIRE(fire.camera_path);
    CHECK(fire.camera_path->loop);
    CHECK(fire.camera_path->duration() == 12.0);

    const terrain::Scene lights = terrain::load_scene(fx_test::source_path(kScenes + "/searchlight.json"));
    REQUIRE(lights.effects.size() == 3);
    const auto& patrol = std::get<fx::SearchLightParams>(lights.effects[2].params);
    CHECK(lights.effects[2].name == "patrol");
    CHECK(patrol.sweep.amplitude_degrees == 35.0);
    CHECK(patrol.slices == 32); // the default

    const terrain::Scene laser = terrain::load_scene(fx_test::source_path(kScenes + "/laser.json"));
    REQUIRE(laser.effects.size() == 4);
    CHECK_FALSE(laser.effects[3].enabled);
    CHECK(std::get<fx::LaserConeParams>(laser.effects[0].params).dust_amount > 0.0);
}

TEST_CASE("Effect entries' errors name the file and the key path", "[scene][effects]") {
    const std::string fire = R"({"type": "campfire", )" + kFire + "}";
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "base_radius": 0, )" + kFire + "}")),
                      Catch::Contains("fx.json: effects[0].base_radius: must be positive"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "bonfire", )" + kFire + "}")),
                      Catch::Contains("fx.json: effects[0].type: unknown effect type 'bonfire'"));
    CHECK_THROWS_WITH(parse(effect_scene(fire + ", " + fire)),
                      Catch::Contains("fx.json: effects[1].name: 'campfire' is already the name of effects[0]"));
    const std::string aurora =
        R"("aurora": {"ceiling": 12000, "size": 9, "spacing": 100, "transfer_function": "transfer_functions/aurora.json"}, )";
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "name": "aurora", )" + kFire + "}", aurora)),
                      Catch::Contains("fx.json: effects[0].name: 'aurora' is reserved"));
    // Without a fog section, "fog" is a name like any other (a fog volume, say).
    CHECK(parse(effect_scene(R"({"type": "campfire", "name": "fog", )" + kFire + "}")).effects[0].name == "fog");
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "colour": 1, )" + kFire + "}")),
                      Catch::Contains("fx.json: effects[0].colour: unknown key"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire"})")),
                      Catch::Contains("fx.json: effects[0].transfer_function: is required"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "cells_across": 1000, )" + kFire + "}")),
                      Catch::Contains("fx.json: effects[0].cells_across: must be in 2..256"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "path": "pcp-fast", )" + kFire + "}")),
                      Catch::Contains("fx.json: effects[0].path: unknown render path 'pcp-fast'"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "search_light", "spread_degrees": 75, )" + kBeam + "}")),
                      Catch::Contains("fx.json: effects[0].spread_degrees: must be in [0, 60]"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "search_light", "sweep": {"period": 0}, )" + kBeam + "}")),
                      Catch::Contains("fx.json: effects[0].sweep.period: must be positive"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "search_light", "direction": [0, 0, 0], )" + kBeam + "}")),
                      Catch::Contains("fx.json: effects[0].direction: must be finite and non-zero (got 0, 0, 0)"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "laser_cone", "dust_amount": 2, )" + kBeam + "}")),
                      Catch::Contains("fx.json: effects[0].dust_amount: must be in [0, 1]"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "ground_fog", )" + kBeam + "}")),
                      Catch::Contains("fx.json: effects[0].type: 'ground_fog' is declared by the scene's \"fog\" section"));
    CHECK_THROWS_WITH(parse(effect_scene(R"({"type": "campfire", "transfer_function": "nope.json"})")),
                      Catch::Contains("fx.json: effects[0].transfer_function:") && Catch::Contains("nope.json"));
    CHECK_THROWS_WITH(parse(R"({"effects": {}, "camera": {"eye": [0, 0, 1], "target": [0, 1, 0]}})"),
                      Catch::Contains("fx.json: effects: expected an array"));
    // Camera paths.
    CHECK_THROWS_WITH(parse(effect_scene(fire, R"("camera_path": {"keys": [{"time": 0, "eye": [0,0,1], "target": [0,1,1]}]},)")),
                      Catch::Contains("fx.json: camera_path.keys: expected an array of at least 2 keys"));
    CHECK_THROWS_WITH(parse(effect_scene(fire, R"("camera_path": {"keys": [{"time": 1, "eye": [0,0,1], "target": [0,1,1]},
                                                                        {"time": 1, "eye": [1,0,1], "target": [0,1,1]}]},)")),
                      Catch::Contains("fx.json: camera_path.keys[1].time: must be later than the previous key's"));
    CHECK_THROWS_WITH(parse(effect_scene(fire, R"("camera_path": {"keys": [{"time": 0, "eye": [0,0,1], "target": [0,0,1]},
                                                                        {"time": 1, "eye": [1,0,1], "target": [0,1,1]}]},)")),
                      Catch::Contains("fx.json: camera_path.keys[0].target: is the eye position"));
    // Terrain: required without effects; the fog needs one.
    CHECK_THROWS_WITH(parse(R"({"camera": {"eye": [0, 0, 1], "target": [0, 1, 0]}})"),
                      Catch::Contains("fx.json: terrain: is required"));
    CHECK_THROWS_WITH(parse(effect_scene(fire, R"("fog": {"valley": {"level": 1, "max_thickness": 2},
                                                        "transfer_function": "../transfer_functions/fog.json"},)")),
                      Catch::Contains("fx.json: fog: needs a terrain"));
    CHECK_THROWS_WITH(parse(effect_scene(fire, R"("surface": {"ramp": [[0.5, [1, 1, 1]], [0.2, [0, 0, 0]]]},)")),
                      Catch::Contains("fx.json: surface.ramp[1]:"));
    // A valid one parses, with the defaults of the C++ parameters.
    const terrain::Scene ok = parse(effect_scene(fire));
    REQUIRE(ok.effects.size() == 1);
    CHECK_FALSE(ok.has_terrain());
    CHECK(std::get<fx::CampfireParams>(ok.effects[0].params).height == fx::CampfireParams{}.height);
}

TEST_CASE("Camera paths pass through their keys, smoothly, and loop", "[scene][effects]") {
    terrain::CameraPath path;
    path.keys = {{0.0, {0, 0, 1}, {0, 10, 0}}, {2.0, {10, 0, 1}, {0, 10, 0}}, {5.0, {10, 10, 3}, {5, 5, 0}},
                 {6.0, {0, 0, 1}, {0, 10, 0}}};
    const fx::Camera base = look({0, 0, 0}, {0, 1, 0}, 33.0);
    for (const terrain::CameraKey& k : path.keys) {
        const fx::Camera c = path.at(k.time, base);
        CHECK(glm::length(c.eye - k.eye) < 1e-12);
        CHECK(glm::length(c.target - k.target) < 1e-12);
        CHECK(c.fov_y_degrees == 33.0); // the rest comes from the base camera
    }
    CHECK(glm::length(path.at(-4.0, base).eye - path.keys.front().eye) < 1e-12); // holds before
    CHECK(glm::length(path.at(9.0, base).eye - path.keys.back().eye) < 1e-12);  // and after
    // Continuous (and with continuous tangents): small steps, small changes, across the keys too.
    double worst = 0.0;
    for (double t = 0.0; t < 6.0; t += 0.001)
        worst = std::max(worst, glm::length(path.at(t + 0.001, base).eye - path.at(t, base).eye));
    CHECK(worst < 0.05); // speed ≤ ~10 units/s at the fastest
    path.loop = true;
    CHECK(glm::length(path.at(7.5, base).eye - path.at(1.5, base).eye) < 1e-9);
    CHECK(glm::length(path.at(-4.5, base).eye - path.at(1.5, base).eye) < 1e-9);
}

TEST_CASE("update simulates only the effects the scene calls for", "[gl][scene][effects]") {
    fx_test::gl_context();
    // In view: "near" (a fire) and "beam" (a static search light). Behind the camera: "behind".
    // Switched off: "off".
    const terrain::Scene scene = parse(effect_scene(
        R"({"type": "campfire", "name": "near", "position": [0, 0, 0], )" + kFire + R"(},
           {"type": "campfire", "name": "behind", "position": [0, -60, 0], )" + kFire + R"(},
           {"type": "campfire", "name": "off", "enabled": false, "position": [1, 1, 0], )" + kFire + R"(},
           {"type": "search_light", "name": "beam", "position": [-1, 2, 0], "direction": [1, 0, 1], "range": 5, )" + kBeam + "}"));
    terrain::SceneRenderer renderer(scene);
    const fx::Camera cam = scene.camera;
    const int w = 80, h = 60;
    auto counters = [&](const char* name) { return renderer.effect(name).counters(); };
    renderer.update(1.0 / 30.0, cam, w, h);
    const std::size_t active = dynamic_cast<fx::Campfire&>(renderer.effect("near")).active_nodes();
    terrain::FrameStats s;
    draw_over_black(renderer, w, h, &s);
    const terrain::EffectFrameStats* near = s.find("near");
    REQUIRE(near);
    CHECK(near->status == terrain::EffectStatus::Simulated);
    CHECK(near->cells > 0);
    CHECK(near->cells_built == near->cells);
    CHECK(near->cells_drawn == near->cells);
    CHECK(near->noise_samples == active);
    CHECK(s.find("behind")->status == terrain::EffectStatus::OutOfView);
    CHECK(s.find("off")->status == terrain::EffectStatus::Disabled);
    CHECK(s.find("beam")->status == terrain::EffectStatus::Simulated);
    CHECK(s.noise_samples == active); // only the fire in view sampled noise
    for (const char* skipped : {"behind", "off"}) {
        INFO(skipped);
        const terrain::EffectFrameStats* e = s.find(skipped);
        CHECK(e->cells == 0);
        CHECK(e->cells_built == 0);
        CHECK(e->cells_drawn == 0);
        CHECK(e->noise_samples == 0);
        CHECK(counters(skipped).updates == 0); // never even asked
        CHECK(counters(skipped).noise_samples == 0);
        CHECK(counters(skipped).mesh_builds == 0);
    }

    // More frames, the camera still: the fire re-samples its own grid once per frame, the static
    // beam is neither rebuilt nor re-evaluated, the skipped effects stay free.
    for (int f = 0; f < 4; ++f) {
        renderer.update(1.0 / 30.0, cam, w, h);
        draw_over_black(renderer, w, h, &s);
        CHECK(s.find("near")->status == terrain::EffectStatus::Simulated);
        CHECK(s.find("near")->noise_samples == active);
        CHECK(s.find("near")->cells_built == 0);
        CHECK(s.find("near")->cells_drawn > 0);
        CHECK(s.find("beam")->status == terrain::EffectStatus::Unchanged);
        CHECK(s.find("beam")->cells_built == 0);
        CHECK(s.find("beam")->cells_drawn > 0);
    }
    CHECK(counters("near").mesh_builds == 1);
    CHECK(counters("near").scalar_updates == 4);
    CHECK(counters("near").noise_samples == 5 * active);
    CHECK(counters("beam").mesh_builds == 1);
    CHECK(counters("beam").scalar_updates == 0);
    CHECK(counters("behind").updates == 0);
    CHECK(counters("off").updates == 0);

    // No time passes: nothing to re-evaluate.
    renderer.update(0.0, cam, w, h);
    CHECK(renderer.stats().find("near")->status == terrain::EffectStatus::Unchanged);
    CHECK(renderer.stats().noise_samples == 0);

    // The beam rides on something that moves: a pose change, no rebuild.
    renderer.effect("beam").set_parent_transform(glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, 0.0, 0.0)));
    renderer.update(0.0, cam, w, h);
    CHECK(renderer.stats().find("beam")->status == terrain::EffectStatus::Moved);
    CHECK(counters("beam").mesh_builds == 1);

    // Turn round: "behind" comes into view and costs its own grid's samples once; "near" leaves.
    fx::Camera back = cam;
    back.target = {0, -60, 0.7};
    renderer.update(1.0 / 30.0, back, w, h);
    s = renderer.stats();
    CHECK(s.find("behind")->status == terrain::EffectStatus::Simulated);
    CHECK(s.find("behind")->noise_samples == dynamic_cast<fx::Campfire&>(renderer.effect("behind")).active_nodes());
    CHECK(s.find("near")->status == terrain::EffectStatus::OutOfView);
    CHECK(s.find("near")->noise_samples == 0);
    CHECK(counters("near").noise_samples == 5 * active);

    // Switched on, "off" runs too; switched off, "near" would not even when in view.
    renderer.set_enabled("off", true);
    renderer.set_enabled("near", false);
    renderer.update(1.0 / 30.0, cam, w, h);
    CHECK(renderer.stats().find("off")->status == terrain::EffectStatus::Simulated);
    CHECK(renderer.stats().find("near")->status == terrain::EffectStatus::Disabled);
    CHECK(counters("near").noise_samples == 5 * active);
    const std::string line = renderer.stats().summary();
    CHECK_THAT(line, Catch::Contains("near: disabled") && Catch::Contains("off: simulated"));
    CHECK_THROWS_WITH(renderer.set_enabled("nope", true), Catch::Contains("no effect named 'nope'"));
}

TEST_CASE("The ground fog is not refined for a camera that only turns, nor rebuilt for one that stands still", "[gl][scene][effects]") {
    fx_test::gl_context();
    const std::string terrain_fog = R"(
      "terrain": {"procedural": {"size": 65, "spacing": 10, "noise": {"amplitude": 40, "frequency": 0.004, "seed": 2}}, "draw": false},
      "fog": {"valley": {"level": 5, "max_thickness": 30, "radius": 100},
              "transfer_function": "../transfer_functions/fog.json", "extinction_scale": 0.02},)";
    const terrain::Scene scene = parse(R"({)" + terrain_fog + R"(
      "camera": {"eye": [320, -200, 200], "target": [320, 320, 0], "fov": 50, "near": 1, "far": 5000}})");
    terrain::SceneRenderer renderer(scene);
    const int w = 64, h = 48;
    renderer.update(0.0, scene.camera, w, h);
    CHECK(renderer.stats().find("fog")->status == terrain::EffectStatus::Simulated);
    CHECK(renderer.stats().terrain_lod.triangles > 0);
    const std::uint64_t builds = renderer.effect("fog").counters().mesh_builds;
    renderer.update(0.1, scene.camera, w, h);
    CHECK(renderer.stats().find("fog")->status == terrain::EffectStatus::Unchanged);
    CHECK(renderer.effect("fog").counters().mesh_builds == builds);
    // Turning: the LOD as it was (no refinement), and so the prisms (they are not culled to the
    // view on the CPU: the renderer draws those in view).
    fx::Camera turned = scene.camera;
    turned.target = {250, 300, 20};
    renderer.update(0.1, turned, w, h);
    CHECK(renderer.stats().find("fog")->status == terrain::EffectStatus::Unchanged);
    CHECK(renderer.effect("fog").counters().mesh_builds == builds);
    CHECK(renderer.stats().terrain_lod.triangles == 0);
    CHECK(renderer.stats().lod_ms == 0.0);
    // Looking away from the terrain (which cellfx does not draw here): no LOD work at all.
    fx::Camera away = scene.camera;
    away.target = {320, -2000, 200};
    renderer.update(0.1, away, w, h);
    CHECK(renderer.stats().find("fog")->status == terrain::EffectStatus::OutOfView);
    CHECK(renderer.stats().terrain_lod.triangles == 0);
    CHECK(renderer.stats().lod_ms == 0.0);
}

TEST_CASE("What the scene draws after scalar-only and pose-only updates matches the reference", "[gl][scene][effects]") {
    fx_test::gl_context();
    const int w = 96, h = 96;
    SECTION("a campfire advanced in time (set_scalars)") {
        const terrain::Scene scene = parse(effect_scene(R"({"type": "campfire", "name": "fire", )" + kFire + "}"));
        terrain::SceneRenderer renderer(scene);
        const fx::Camera cam = look({1.6, -2.4, 1.3}, {0, 0, 0.6}, 45.0);
        renderer.update(0.0, cam, w, h);
        draw_over_black(renderer, w, h);
        renderer.update(0.4, cam, w, h);
        terrain::FrameStats s;
        const fx::Image frame = draw_over_black(renderer, w, h, &s);
        REQUIRE(s.find("fire")->status == terrain::EffectStatus::Simulated);
        REQUIRE(renderer.effect("fire").counters().mesh_builds == 1); // the second frame uploaded scalars only
        const fx::CellMesh world = effects_test::world_mesh(renderer.effect("fire"));
        fx::TransferFunction tf = terrain::drawn_transfer_function(scene.effects[0].transfer_function, scene.effects[0].extinction_scale, {0.0f, 1.0f});
        fx::ScanlineOptions so;
        so.model = fx::OpticalModel::Emission;
        fx::Image expected = fx::ScanlineRenderer(world).render(cam, w, h, world.scalars[0], tf, so);
        fx::composite_over(expected, glm::vec3(0.0f));
        effects_test::check_frame("scene_campfire_scalars", frame, expected, fx::RenderPath::PcpExact, 20);
    }
    SECTION("a search light moved by its parent (no upload)") {
        const terrain::Scene scene = parse(effect_scene(
            R"({"type": "search_light", "name": "beam", "position": [0, 0, 0], "direction": [1, 1, 1], "range": 6, "spread_degrees": 10, )" +
            kBeam + "}"));
        terrain::SceneRenderer renderer(scene);
        const fx::Camera cam = look({2.0, -4.0, 2.0}, {1.5, 1.5, 1.5}, 50.0);
        renderer.update(0.0, cam, w, h);
        draw_over_black(renderer, w, h);
        renderer.effect("beam").set_parent_transform(
            glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.4, 0.3, -0.2)), 0.3, glm::dvec3(0, 0, 1)));
        renderer.update(0.0, cam, w, h);
        terrain::FrameStats s;
        const fx::Image frame = draw_over_black(renderer, w, h, &s);
        REQUIRE(s.find("beam")->status == terrain::EffectStatus::Moved);
        const fx::CellMesh world = effects_test::world_mesh(renderer.effect("beam"));
        const fx::TransferFunction tf = terrain::drawn_transfer_function(scene.effects[0].transfer_function, scene.effects[0].extinction_scale, {0.0f, 1.0f});
        fx::ScanlineOptions so;
        so.model = fx::OpticalModel::Emission;
        fx::Image expected = fx::ScanlineRenderer(world).render(cam, w, h, world.scalars[0], tf, so);
        fx::composite_over(expected, glm::vec3(0.0f));
        effects_test::check_frame("scene_search_light_moved", frame, expected, fx::RenderPath::PcpExact, 8);
    }
}
