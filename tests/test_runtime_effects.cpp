// Effects managed at run time through cellfx::Module, without re-initialising and without the
// renderer() escape hatch: added and removed, every parameter changed (shape, type, colour,
// extinction scale, absorb), and a scene file reloaded in one step that parses first and swaps
// only on success, keeping the clock, parent transforms and the game's path choices. Each changed
// module must draw exactly (bit for bit) the frame of a module started with the changed scene,
// which is itself the frame the embedding tests check against the scan-line reference.
#include <catch2/catch.hpp>

#include <atomic>
#include <fstream>
#include <thread>

#include <glm/gtc/matrix_transform.hpp>

#include "embedding_support.hpp"
#include "cellfx_names.hpp"

using namespace embedding_test;

namespace {

// A scene file of the campfire and a search light named "patrol", with `fire_keys` added to the
// fire, in the test output folder (the shipped transfer functions by absolute path).
std::string write_scene(const std::string& name, const std::string& fire_keys, bool valid = true) {
    const std::string path = fx_test::output_path(name);
    std::ofstream(path) << R"({
  "effects": [
    {"type": "campfire", "name": "fire", )" << fire_keys << R"("transfer_function": ")"
                        << fx_test::source_path("content/transfer_functions/fire.json") << R"(", "extinction_scale": 0.15},
    {"type": "search_light", "name": "patrol", "position": [-1.0, 1.0, 0.2], "direction": [1, -0.2, 0.4], "range": 4,
     "transfer_function": ")" << fx_test::source_path("content/scenes/transfer_functions/searchlight.json") << R"(",
     "extinction_scale": 0.5)" << (valid ? "" : R"(, "brightness": 3)") << R"(}
  ],
  "camera": {"eye": [1.6, -2.4, 1.2], "target": [0, 0, 0.6], "fov": 45, "near": 0.05, "far": 100}
})";
    return path;
}

// The module's frame over the game's sky (no depth: nothing of the game's in front).
fx::Image frame(cellfx::Module& fx) {
    GameFrame game(GL_DEPTH_COMPONENT32F, false);
    game.draw(fx.scene_camera(), false, 0.0);
    fx.update(0.0, fx.scene_camera());
    fx.render({game.framebuffer, {0, 0, kW, kH}, game.depth});
    fx_test::require_no_gl_error();
    return game.read();
}

void check_same(const std::string& name, const fx::Image& actual, const fx::Image& expected) {
    fx_test::check_image(name, actual, expected, verify::same_picture(0.0, "the same effects in the same state"));
}

std::size_t lit_pixels(const fx::Image& image) {
    std::size_t lit = 0;
    for (const glm::vec4& p : image.pixels) lit += glm::length(glm::vec3(p) - glm::vec3(kSky)) > 0.05f;
    return lit;
}

cellfx::Module started(const terrain::Scene& scene) {
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    return fx;
}

} // namespace

TEST_CASE("Effects added, changed and removed at run time draw what a module started with them draws",
          "[gl][embedding][runtime]") {
    fx_test::gl_context();
    const terrain::Scene fire_only = fire_scene(false);
    cellfx::Module fx = started(fire_only);
    const fx::Image first = frame(fx);

    // Add a search light.
    terrain::EffectSpec beam;
    beam.name = "beam";
    fx::SearchLightParams p;
    p.position = {-1.0, 1.0, 0.2};
    p.direction = {1.0, -0.2, 0.4};
    p.range = 4.0;
    beam.params = p;
    beam.transfer_function = fx::TransferFunction::read_json(fx_test::source_path("content/scenes/transfer_functions/searchlight.json"));
    beam.extinction_scale = 0.5;
    fx.add_effect(beam);
    REQUIRE(fx.has_effect("beam"));
    terrain::Scene both = fire_only;
    both.effects.push_back(beam);
    cellfx::Module reference = started(both);
    const fx::Image with_beam = frame(fx);
    check_same("runtime_add", with_beam, frame(reference));
    CHECK(lit_pixels(with_beam) > lit_pixels(first));
    CHECK(fx.stats().find("beam")->cells_drawn > 0);
    CHECK(fx.scene().effects.size() == 2);

    // Every parameter: the fire's shape, the beam's colour and extinction, absorb, the path.
    fx::CampfireParams tall = std::get<fx::CampfireParams>(fire_only.effects[0].params);
    tall.height = 2.0;
    tall.base_radius = 0.3;
    fx.set_params("fire", tall);
    const fx::TransferFunction green = fx::TransferFunction::constant({0.2, 1.0, 0.3}, 0.8);
    fx.set_transfer_function("beam", green);
    fx.set_extinction_scale("beam", 0.25);
    fx.set_absorb("fire", true);
    both.effects[0].params = tall;
    both.effects[0].absorb = true;
    both.effects[1].transfer_function = green;
    both.effects[1].extinction_scale = 0.25;
    cellfx::Module reference2 = started(both);
    check_same("runtime_params", frame(fx), frame(reference2));
    CHECK(std::get<fx::CampfireParams>(fx.scene().effects[0].params).height == 2.0); // scene() shows what is drawn
    CHECK(fx.scene().effects[1].extinction_scale == 0.25);

    // Another type under the same name keeps the effect's parent transform.
    const glm::dmat4 moved = glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, 0.1, 0.0));
    fx.set_parent_transform("fire", moved);
    fx::LaserConeParams laser;
    laser.position = {0.0, 0.0, 0.3};
    laser.direction = {0.0, 1.0, 0.2};
    laser.range = 3.0;
    laser.radius = 0.05;
    fx.set_params("fire", laser);
    REQUIRE(fx.effect<fx::LaserCone>("fire") != nullptr);
    CHECK(fx.effect<fx::Campfire>("fire") == nullptr);
    CHECK(fx.effect<fx::LaserCone>("fire")->parent_transform() == moved);
    both.effects[0].params = laser;
    cellfx::Module reference3 = started(both);
    reference3.set_parent_transform("fire", moved);
    check_same("runtime_type", frame(fx), frame(reference3));

    // Remove it again: the beam alone.
    fx.remove_effect("fire");
    CHECK_FALSE(fx.has_effect("fire"));
    both.effects.erase(both.effects.begin());
    cellfx::Module reference4 = started(both);
    check_same("runtime_remove", frame(fx), frame(reference4));
    CHECK(fx.stats().effects.size() == 1);
}

TEST_CASE("Run-time changes refuse bad values with a message and change nothing", "[gl][embedding][runtime]") {
    fx_test::gl_context();
    cellfx::Module fx = started(fire_scene(false));
    const fx::Image before = frame(fx);
    terrain::EffectSpec copy = fx.scene().effects[0];
    CHECK_THROWS_WITH(fx.add_effect(copy), Catch::Contains("already an effect named 'fire'"));
    copy.name = "fog";
    CHECK_THROWS_WITH(fx.add_effect(copy), Catch::Contains("'fog' names the scene's own fog section"));
    copy.name = "bad";
    fx::CampfireParams broken;
    broken.base_radius = -1.0;
    copy.params = broken;
    CHECK_THROWS_WITH(fx.add_effect(copy), Catch::Contains("add_effect 'bad'") && Catch::Contains("base_radius"));
    CHECK_THROWS_WITH(fx.set_params("fire", broken), Catch::Contains("set_params 'fire'") && Catch::Contains("base_radius"));
    CHECK_THROWS_WITH(fx.set_extinction_scale("fire", -0.5), Catch::Contains("must be finite and ≥ 0"));
    CHECK_THROWS_WITH(fx.remove_effect("smoke"), Catch::Contains("no effect named 'smoke'"));
    const cellfx::Status s = fx.try_set_path("smoke", fx::RenderPath::Mip);
    CHECK_FALSE(s);
    CHECK_THAT(s.message(), Catch::Contains("no effect named 'smoke'"));
    CHECK(fx.effect_names() == std::vector<std::string>{"fire"});
    check_same("runtime_refused", frame(fx), before);
}

TEST_CASE("A reload parses first, swaps on success, and keeps the clock, parent transforms and path choices",
          "[gl][embedding][runtime]") {
    fx_test::gl_context();
    const std::string file = write_scene("runtime_reload.json", "");
    cellfx::Module fx;
    fx.init(cellfx::Config(file, kW, kH));
    const glm::dmat4 truck = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, 0.0, 0.1)), 0.4, glm::dvec3(0, 0, 1));
    fx.set_time(2.5);
    fx.set_parent_transform("patrol", truck);
    fx.set_path("fire", fx::RenderPath::Mip);
    const fx::Image running = frame(fx);

    // A typo: refused, naming file and key; the running scene is untouched.
    const std::string bad = write_scene("runtime_reload_bad.json", R"("height": 1.8, )", false);
    CHECK_THROWS_WITH(fx.reload(bad), Catch::Contains("runtime_reload_bad.json") && Catch::Contains("effects[1].brightness"));
    const cellfx::Status s = fx.try_reload(bad);
    CHECK_FALSE(s);
    CHECK_THAT(s.message(), Catch::Contains("runtime_reload_bad.json"));
    CHECK(fx.time() == 2.5);
    check_same("reload_refused", frame(fx), running);
    CHECK(fx.path("fire") == fx::RenderPath::Mip);

    // The fixed file: the new fire, at the same time, the light still on its truck, the fire
    // still drawn with the game's choice of path.
    const std::string fixed = write_scene("runtime_reload_fixed.json", R"("height": 1.8, )");
    fx.update(0.0, fx.scene_camera());
    fx.reload(fixed); // between update() and render(): the frame is prepared again
    CHECK(fx.time() == 2.5);
    CHECK(std::get<fx::CampfireParams>(fx.scene().effects[0].params).height == 1.8);
    CHECK(fx.effect<fx::SearchLight>("patrol")->parent_transform() == truck);
    CHECK(fx.path("fire") == fx::RenderPath::Mip);
    CHECK(fx.path("patrol") == fx::RenderPath::PcpExact); // the file's, never overridden
    cellfx::Module reference;
    reference.init(cellfx::Config(fixed, kW, kH));
    reference.set_time(2.5);
    reference.set_parent_transform("patrol", truck);
    reference.set_path("fire", fx::RenderPath::Mip);
    const fx::Image reloaded = frame(fx);
    check_same("reload_fixed", reloaded, frame(reference));
    CHECK(verify::measure(reloaded, running).worst.delta > 0.01); // and it is the new fire
}

TEST_CASE("Config::parallel_for runs the effects' simulation on the host's job system, frames unchanged",
          "[gl][embedding][runtime]") {
    fx_test::gl_context();
    // The host's job system: two threads, the odd tasks on the second.
    struct Jobs {
        std::atomic<int> calls{0}, tasks{0};
    } jobs;
    fx::ParallelFor parallel;
    parallel.host_context = &jobs;
    parallel.run = [](void* host, std::size_t count, fx::ParallelFor::Task task, void* context) {
        Jobs& j = *static_cast<Jobs*>(host);
        ++j.calls;
        std::thread other([&] {
            for (std::size_t i = 1; i < count; i += 2) task(context, i), ++j.tasks;
        });
        for (std::size_t i = 0; i < count; i += 2) task(context, i), ++j.tasks;
        other.join();
    };
    const std::string file = write_scene("runtime_parallel.json", "");
    cellfx::Module serial;
    serial.init(cellfx::Config(file, kW, kH));
    cellfx::Config config(file, kW, kH);
    config.parallel_for = parallel;
    cellfx::Module host_jobs;
    host_jobs.init(config);
    for (double t : {0.5, 0.8}) {
        serial.set_time(t);
        host_jobs.set_time(t);
        check_same("parallel_for", frame(host_jobs), frame(serial));
    }
    CHECK(jobs.calls == 2);
    CHECK(jobs.tasks == 4); // the fire and the search light, every frame
    CHECK(host_jobs.stats().find("patrol")->status != terrain::EffectStatus::OutOfView);
}

namespace {

// What `f` throws, "" when it does not throw.
template <class F> std::string thrown(F&& f) {
    try {
        f();
    } catch (const std::exception& e) {
        return e.what();
    }
    return "";
}

// A refused try_ form: a failed Status carrying the throwing form's message, which names `what`.
void check_refused(const cellfx::Status& s, const std::string& thrown_message, const std::string& what) {
    INFO("expected a refusal naming '" << what << "'");
    CHECK_FALSE(s);
    CHECK_FALSE(s.ok());
    CHECK(s.message() == thrown_message);
    CHECK_THAT(s.message(), Catch::Contains(what));
}

} // namespace

TEST_CASE("Every try_ form does what its throwing form does, and refuses what it refuses with its message",
          "[gl][embedding][runtime]") {
    fx_test::gl_context();
    // Before init(): every call is refused, naming what to do first.
    {
        cellfx::Module idle;
        check_refused(idle.try_update(0.0, fx::Camera{}), thrown([&] { idle.update(0.0, fx::Camera{}); }), "init");
        check_refused(idle.try_set_time(1.0), thrown([&] { idle.set_time(1.0); }), "init");
        check_refused(idle.try_set_terrain_drawn(false), thrown([&] { idle.set_terrain_drawn(false); }), "init");
        CHECK_THAT(thrown([&] { idle.renderer(); }), Catch::Contains("init"));
    }

    // The same changes through the throwing forms (`thrower`) and the try_ forms (`tried`): the
    // same frames, bit for bit, and each change visible.
    const terrain::Scene scene = fire_scene(true);
    cellfx::Module thrower = started(scene), tried = started(scene);
    const fx::Image first = frame(thrower);
    check_same("try_start", frame(tried), first);

    fx::CampfireParams tall = std::get<fx::CampfireParams>(scene.effects[0].params);
    tall.height = 2.0;
    const fx::TransferFunction green = fx::TransferFunction::constant({0.2, 1.0, 0.3}, 0.8);
    const glm::dmat4 moved = glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, 0.1, 0.0));
    thrower.set_time(1.5);
    thrower.set_params("fire", tall);
    thrower.set_transfer_function("fire", green);
    thrower.set_absorb("fire", true);
    thrower.set_parent_transform("fire", moved);
    thrower.set_terrain_drawn(false);
    CHECK(tried.try_set_time(1.5));
    CHECK(tried.try_set_params("fire", tall));
    CHECK(tried.try_set_transfer_function("fire", green));
    CHECK(tried.try_set_absorb("fire", true));
    CHECK(tried.try_set_parent_transform("fire", moved));
    CHECK(tried.try_set_terrain_drawn(false));
    CHECK(tried.time() == 1.5);
    CHECK(std::get<fx::CampfireParams>(tried.scene().effects[0].params).height == 2.0);
    CHECK(tried.scene().effects[0].absorb);
    CHECK(tried.effect<fx::Campfire>("fire")->parent_transform() == moved);
    CHECK_FALSE(tried.terrain_drawn());
    const fx::Image changed = frame(tried);
    check_same("try_changed", changed, frame(thrower));
    CHECK(verify::measure(changed, first).worst.delta > 0.05); // the changes show
    CHECK(lit_pixels(changed) > 100);                          // the fire, without the terrain

    // Refusals: the same message as the throwing form, and nothing changed.
    fx::CampfireParams broken = tall;
    broken.base_radius = -1.0;
    check_refused(tried.try_set_time(NAN), thrown([&] { thrower.set_time(NAN); }), "time");
    check_refused(tried.try_set_params("fire", broken), thrown([&] { thrower.set_params("fire", broken); }), "base_radius");
    check_refused(tried.try_set_transfer_function("smoke", green),
                  thrown([&] { thrower.set_transfer_function("smoke", green); }), "smoke");
    check_refused(tried.try_set_absorb("smoke", true), thrown([&] { thrower.set_absorb("smoke", true); }), "smoke");
    check_refused(tried.try_set_parent_transform("smoke", moved),
                  thrown([&] { thrower.set_parent_transform("smoke", moved); }), "smoke");
    CHECK(tried.time() == 1.5);
    check_same("try_refused", frame(tried), changed);

    // enabled() follows set_enabled; renderer(), the escape hatch, holds the module's effects.
    CHECK(tried.enabled("fire"));
    CHECK(tried.try_set_enabled("fire", false));
    CHECK_FALSE(tried.enabled("fire"));
    CHECK_THAT(thrown([&] { tried.enabled("smoke"); }), Catch::Contains("smoke"));
    CHECK(tried.renderer().find_effect("fire") == static_cast<fx::Effect*>(tried.effect<fx::Campfire>("fire")));
    CHECK(tried.renderer().find_effect("smoke") == nullptr);

    // A scene without terrain refuses to draw one.
    cellfx::Module bare = started(fire_scene(false));
    check_refused(bare.try_set_terrain_drawn(true), thrown([&] { bare.set_terrain_drawn(true); }), "terrain");
}
