// Writing a tuned scene back (terrain::updated_scene_json): the scene file with what changed at
// run time reads back as the scene that was drawn — every effect parameter (by the tables of
// fx/effect_parameters.hpp), on/off, path, absorb, extinction scale, the LOD's pixel error, the
// resolution and the medium — from another folder too (file names rewritten), with the keys the
// author wrote kept and defaults left out.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <variant>

#include <nlohmann/json.hpp>

#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "terrain/scene.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    REQUIRE(in);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string scene_file(const std::string& name) { return fx_test::source_path("content/scenes/" + name + ".json"); }

// The scene `text` read as if it were a file in `folder`.
terrain::Scene reparse(const std::string& text, const std::string& folder) {
    return terrain::parse_scene(text, folder + "/saved.json", folder);
}

template <class P>
void check_same_params(const P& a, const P& b) {
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        INFO(p.name);
        if (!p.applies_to(b)) continue; // a sphere's box size: not drawn, not written
        if (p.vector) CHECK(fx::parameter_vector(p, a) == fx::parameter_vector(p, b));
        else CHECK(fx::parameter_value(p, a) == fx::parameter_value(p, b));
    }
    if constexpr (std::is_same_v<P, fx::VolumeParams>) {
        CHECK(a.shape == b.shape);
        CHECK(a.density_mode == b.density_mode);
    }
}

// What the writer writes, read back, equals what was drawn.
void check_same_scene(const terrain::Scene& saved, const terrain::Scene& drawn) {
    REQUIRE(saved.effects.size() == drawn.effects.size());
    for (std::size_t i = 0; i < drawn.effects.size(); ++i) {
        const terrain::EffectSpec &a = saved.effects[i], &b = drawn.effects[i];
        INFO("effect " << b.name);
        CHECK(a.name == b.name);
        CHECK(a.enabled == b.enabled);
        CHECK(a.path == b.path);
        CHECK(a.absorb == b.absorb);
        CHECK(a.extinction_scale == b.extinction_scale);
        REQUIRE(a.params.index() == b.params.index());
        std::visit([&](const auto& p) { check_same_params(p, std::get<std::decay_t<decltype(p)>>(b.params)); }, a.params);
    }
    REQUIRE(saved.fog.has_value() == drawn.fog.has_value());
    if (drawn.fog) {
        CHECK(saved.fog->enabled == drawn.fog->enabled);
        CHECK(saved.fog->path == drawn.fog->path);
        CHECK(saved.fog->absorb == drawn.fog->absorb);
        CHECK(saved.fog->extinction_scale == drawn.fog->extinction_scale);
        CHECK(saved.fog->thickness.heights == drawn.fog->thickness.heights);
    }
    REQUIRE(saved.aurora.has_value() == drawn.aurora.has_value());
    if (drawn.aurora) {
        CHECK(saved.aurora->enabled == drawn.aurora->enabled);
        CHECK(saved.aurora->path == drawn.aurora->path);
        CHECK(saved.aurora->extinction_scale == drawn.aurora->extinction_scale);
    }
    CHECK(saved.ground.heights == drawn.ground.heights);
    CHECK(saved.pixel_error == drawn.pixel_error);
    CHECK(saved.fx_scale == drawn.fx_scale);
    CHECK(saved.medium == drawn.medium);
    CHECK(saved.camera.eye == drawn.camera.eye);
}

} // namespace

TEST_CASE("A scene saved unchanged reads back the same, with the author's keys and no new defaults", "[scene][writer]") {
    for (const char* name : {"campfire", "searchlight", "laser", "fog_valley", "fog_valley_night", "aurora"}) {
        INFO(name);
        const std::string path = scene_file(name);
        const std::string original = read_text(path);
        const terrain::Scene scene = terrain::load_scene(path);
        const std::string folder = std::filesystem::path(path).parent_path().string();
        const std::string saved = terrain::updated_scene_json(original, scene, folder);
        check_same_scene(reparse(saved, folder), scene);
        // Every key of the result was in the file, but a volume's density_mode, which is always
        // written (the parser infers it from the keys otherwise); every value equal.
        const nlohmann::json a = nlohmann::json::parse(original), b = nlohmann::json::parse(saved);
        for (const auto& [key, value] : b.items()) {
            INFO(key);
            REQUIRE(a.contains(key));
            if (key != "effects") CHECK(value == a[key]);
        }
        for (std::size_t i = 0; i < b.value("effects", nlohmann::json::array()).size(); ++i)
            for (const auto& [key, value] : b["effects"][i].items()) {
                INFO("effects[" << i << "]." << key);
                if (key == "density_mode") continue;
                REQUIRE(a["effects"][i].contains(key));
                CHECK(value == a["effects"][i][key]);
            }
    }
}

TEST_CASE("A tuned scene saved in another folder reads back as it was drawn", "[scene][writer]") {
    const std::string path = scene_file("fog_valley_night");
    terrain::Scene scene = terrain::load_scene(path);
    // Changes a panel makes: parameters of every type, toggles, paths, scales, the quality.
    for (terrain::EffectSpec& e : scene.effects) {
        if (auto* fire = std::get_if<fx::CampfireParams>(&e.params)) {
            fire->base_radius = 0.8, fire->cells_up = 24, fire->seed = 7, fire->position.x += 0.25;
            e.extinction_scale = 0.37;
        } else if (auto* smoke = std::get_if<fx::VolumeParams>(&e.params)) {
            smoke->shape = fx::VolumeShape::Sphere, smoke->radius = 3.5, smoke->noise.octaves = 3, smoke->noise.drift.z = -0.5;
            e.enabled = false;
        } else if (auto* beam = std::get_if<fx::SearchLightParams>(&e.params)) {
            beam->sweep.period = 11.0, beam->spread_degrees = 9.5, beam->direction = {0.2, 1.0, -0.3};
            e.path = fx::RenderPath::Mip;
        }
    }
    scene.fog->extinction_scale *= 1.5;
    scene.fog->absorb = false;
    scene.fog->path = fx::RenderPath::AbsorptionExact;
    scene.pixel_error = 3.25;
    scene.fx_scale = 0.5;
    scene.medium = fx::MediumMethod::Exact;

    const std::string folder = fx_test::output_path("scene_writer/elsewhere");
    std::filesystem::create_directories(folder);
    const std::string saved = terrain::updated_scene_json(read_text(path), scene, folder);
    std::ofstream(folder + "/tuned.json") << saved;
    // load_scene from the new folder: the height map, fog noise and transfer functions found there.
    check_same_scene(terrain::load_scene(folder + "/tuned.json"), scene);
    // The sphere has no size; the file says so rather than leaving the box's.
    const nlohmann::json j = nlohmann::json::parse(saved);
    for (const nlohmann::json& e : j["effects"])
        if (e["name"] == "smoke") {
            CHECK_FALSE(e.contains("size"));
            CHECK(e["shape"] == "sphere");
        }
}

TEST_CASE("A saved effect of another type, and what cannot be saved", "[scene][writer]") {
    const std::string path = scene_file("campfire");
    const std::string original = read_text(path);
    const std::string folder = std::filesystem::path(path).parent_path().string();
    terrain::Scene scene = terrain::load_scene(path);
    fx::SearchLightParams beam;
    beam.range = 12.0, beam.direction = {0.0, 1.0, 0.5};
    scene.effects[0].params = beam; // set_params with another type replaces the effect
    check_same_scene(reparse(terrain::updated_scene_json(original, scene, folder), folder), scene);

    terrain::Scene added = terrain::load_scene(path);
    added.effects.push_back(added.effects[0]);
    added.effects.back().name = "second";
    CHECK_THROWS_WITH(terrain::updated_scene_json(original, added, folder),
                      Catch::Contains("campfire.json") && Catch::Contains("'second' is not declared in the file"));
    terrain::Scene removed = terrain::load_scene(path);
    removed.effects.clear();
    CHECK(reparse(terrain::updated_scene_json(original, removed, folder), folder).effects.empty());
    terrain::Scene in_code = terrain::load_scene(path);
    in_code.source.clear();
    CHECK_THROWS_WITH(terrain::updated_scene_json(original, in_code, folder), Catch::Contains("built in code"));
    CHECK_THROWS_WITH(terrain::updated_scene_json("{ not json", scene, folder), Catch::Contains("campfire.json: not a scene's JSON"));
}
