// The effects' parameter tables (fx/effect_parameters.hpp) are what the library accepts: for
// every Number and Integer parameter of every effect, its range's ends are accepted and a
// value just outside is refused — by the effect's constructor (which checks through the table)
// and by the scene-file parser (which reads every parameter through the table), each naming
// the parameter. So a tool that reads the tables (the samples' panel) offers exactly the values
// cellfx takes. A change costs what the table says; the docs' tables are generated from it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <variant>

#include <glm/vec3.hpp>

#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "terrain/scene.hpp"
#include "io_test_helpers.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

// Raises the effect-cells budget while alive: a range's end (256 cells across a box) must be
// judged by its range, not by the budget that bounds the parameters together.
struct GenerousBudget {
    fx::ResourceLimits saved = fx::resource_limits();
    GenerousBudget() {
        fx::ResourceLimits l = saved;
        l.effect_cells = l.scene_cells = std::uint64_t(1) << 40;
        fx::set_resource_limits(l);
    }
    ~GenerousBudget() { fx::set_resource_limits(saved); }
};

std::string number_json(double v) {
    std::ostringstream out;
    out.precision(17);
    out << v;
    return out.str();
}

// The scene-file entry with `name` (maybe "a.b") set to `value`, for the parameters `params` of
// the type `type` (a volume gets the shape the parameter applies to).
template <class P>
std::string entry_json(const char* type, const P& params, const std::string& name, const std::string& value) {
    std::string entry = std::string(R"({"type": ")") + type + R"(", "transfer_function": "../transfer_functions/fire.json", )";
    if constexpr (std::is_same_v<P, fx::VolumeParams>) {
        entry += std::string(R"("shape": ")") + fx::volume_shape_name(params.shape) + R"(", )";
        entry += std::string(R"("density_mode": ")") + fx::volume_density_name(params.density_mode) + R"(", )";
    }
    const std::size_t dot = name.find('.');
    if (dot == std::string::npos) entry += "\"" + name + "\": " + value + "}";
    else entry += "\"" + name.substr(0, dot) + "\": {\"" + name.substr(dot + 1) + "\": " + value + "}}";
    return R"({"effects": [)" + entry + R"(], "camera": {"eye": [0, -5, 1], "target": [0, 0, 0.7]}})";
}

terrain::Scene parse(const std::string& text) {
    return terrain::parse_scene(text, "fx.json", fx_test::source_path("content/scenes"));
}

// Checks one type's table against its constructor and the parser.
template <class P>
void check_table(const char* type) {
    const GenerousBudget budget;
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        P params{};
        // The parameter in effect: a volume's radius on a sphere, its noise with noise density.
        if constexpr (std::is_same_v<P, fx::VolumeParams>) {
            if (std::string(p.name) == "radius") params.shape = fx::VolumeShape::Sphere;
            if (std::string(p.name).rfind("noise.", 0) == 0) params.density_mode = fx::VolumeDensity::Noise;
        }
        INFO(type << "." << p.name);
        REQUIRE(p.applies_to(params));
        if (p.kind == fx::ParameterKind::Seed) continue; // every value of its type is valid
        if (p.vector) {
            // Vectors: a component beyond ±1e18 is refused (and a zero direction, a negative extent).
            P bad = params;
            *p.vector(bad) = glm::dvec3(2e18, 1.0, 1.0);
            CHECK_THROWS_WITH(terrain::make_effect(bad), Catch::Contains(p.name));
            CHECK_THROWS_WITH(parse(entry_json(type, params, p.name, "[2e18, 1, 1]")), Catch::Contains(p.name));
            if (p.kind != fx::ParameterKind::Vector) {
                *p.vector(bad) = p.kind == fx::ParameterKind::Direction ? glm::dvec3(0.0) : glm::dvec3(1.0, -1.0, 1.0);
                CHECK_THROWS_WITH(terrain::make_effect(bad), Catch::Contains(p.name));
                CHECK_THROWS_WITH(parse(entry_json(type, params, p.name, p.kind == fx::ParameterKind::Direction ? "[0, 0, 0]" : "[1, -1, 1]")),
                                  Catch::Contains(p.name));
            }
            continue;
        }
        const bool integer = p.kind == fx::ParameterKind::Integer;
        const auto step = [&](double bound) { return integer ? 1.0 : std::max(1.0, std::abs(bound) * 1e-3); };
        const double lo_inside = p.range.lo_open ? p.range.lo + step(p.range.lo) : p.range.lo;
        const double lo_outside = p.range.lo_open ? p.range.lo : p.range.lo - step(p.range.lo);
        const double hi_outside = p.range.hi + step(p.range.hi);
        for (double v : {lo_inside, p.range.hi}) {
            INFO("inside: " << v);
            P ok = params;
            fx::set_parameter_value(p, ok, v);
            CHECK(fx::parameter_value(p, ok) == v);
            CHECK_NOTHROW(terrain::make_effect(ok));
            const terrain::Scene scene = parse(entry_json(type, params, p.name, number_json(v)));
            CHECK(fx::parameter_value(p, std::get<P>(scene.effects[0].params)) == v);
        }
        for (double v : {lo_outside, hi_outside}) {
            INFO("outside: " << v);
            P bad = params;
            fx::set_parameter_value(p, bad, v);
            CHECK_THROWS_WITH(terrain::make_effect(bad), Catch::Contains(p.name));
            CHECK_THROWS_WITH(parse(entry_json(type, params, p.name, number_json(v))), Catch::Contains(p.name));
        }
    }
}

} // namespace

TEST_CASE("Effect parameter tables: each range is what the effect and the scene parser accept", "[effects][parameters]") {
    check_table<fx::CampfireParams>("campfire");
    check_table<fx::SearchLightParams>("search_light");
    check_table<fx::LaserConeParams>("laser_cone");
    check_table<fx::VolumeParams>("volume");
}

TEST_CASE("Effect parameter tables: every field once, its key the scene file's", "[effects][parameters]") {
    // Every key a table names is one the parser reads (above); here: no name twice, and the
    // accessors reach distinct fields (setting one leaves the others as they were).
    const auto distinct = [](auto params) {
        using P = decltype(params);
        const auto& table = fx::parameter_table<P>();
        for (std::size_t i = 0; i < table.size(); ++i) {
            for (std::size_t j = i + 1; j < table.size(); ++j) CHECK(std::string(table[i].name) != table[j].name);
            if (!table[i].scalar()) continue;
            P changed = params;
            fx::set_parameter_value(table[i], changed, fx::parameter_value(table[i], params) + 1.0);
            for (std::size_t j = 0; j < table.size(); ++j) {
                INFO(table[i].name << " changed, " << table[j].name << " read");
                if (j == i) CHECK(fx::parameter_value(table[j], changed) == fx::parameter_value(table[j], params) + 1.0);
                else if (table[j].scalar()) CHECK(fx::parameter_value(table[j], changed) == fx::parameter_value(table[j], params));
                else CHECK(fx::parameter_vector(table[j], changed) == fx::parameter_vector(table[j], params));
            }
        }
    };
    distinct(fx::CampfireParams{});
    distinct(fx::SearchLightParams{});
    distinct(fx::LaserConeParams{});
    distinct(fx::VolumeParams{});
    // The checks' messages name the effect, the parameter, the rule and the value.
    fx::CampfireParams p;
    p.cells_across = 1;
    CHECK_THROWS_WITH(fx::Campfire(p), "campfire: cells_across must be in 2..256 (got 1)");
    fx::SearchLightParams beam;
    beam.spread_degrees = 61;
    CHECK_THROWS_WITH(fx::SearchLight(beam), "search_light: spread_degrees must be in [0, 60] (got 61)");
}

namespace {

template <class P>
struct EffectOf;
template <>
struct EffectOf<fx::CampfireParams> { using type = fx::Campfire; };
template <>
struct EffectOf<fx::SearchLightParams> { using type = fx::SearchLight; };
template <>
struct EffectOf<fx::LaserConeParams> { using type = fx::LaserCone; };
template <>
struct EffectOf<fx::VolumeParams> { using type = fx::Volume; };

// Another value of p's field, inside its range.
template <class P>
void change(const fx::Parameter<P>& p, P& params) {
    if (p.vector) {
        glm::dvec3& v = *p.vector(params);
        v = p.kind == fx::ParameterKind::Extents ? 1.25 * v : v + glm::dvec3(0.5, 0.25, -0.125);
        return;
    }
    const double v = fx::parameter_value(p, params);
    const double d = p.kind == fx::ParameterKind::Number ? std::max(0.1 * std::abs(v), 0.05) : 1.0;
    const double w = p.kind != fx::ParameterKind::Seed && v + d > p.range.hi ? v - d : v + d;
    REQUIRE((p.kind == fx::ParameterKind::Seed || p.range.contains(w)));
    fx::set_parameter_value(p, params, w);
}

// For each parameter of the table: changing it alone costs what the table says at the next
// update (the base's bookkeeping follows the table), and that is enough: the mesh and scalars
// are those of an effect made with the new parameters.
template <class P>
void check_costs(const char* type) {
    using E = typename EffectOf<P>::type;
    fx::EffectView view;
    view.camera = fx::Camera::parse("eye=0,-5,1,target=0,0,0.7,up=0,0,1");
    view.time = 0.75;
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        P params{};
        if constexpr (std::is_same_v<P, fx::VolumeParams>) {
            params.cells = 6; // not automatic: a new edge fade or density mode keeps the grid
            if (std::string(p.name) == "radius") params.shape = fx::VolumeShape::Sphere;
            if (std::string(p.name).rfind("noise.", 0) == 0) {
                params.density_mode = fx::VolumeDensity::Noise;
                params.noise.evolve = 0.5; // animated, so a stale time would show
            }
        }
        INFO(type << "." << p.name << " costs " << fx::parameter_cost_name(p.cost));
        E effect(params);
        effect.update(view);
        const fx::EffectCounters before = effect.counters();
        P changed = params;
        change(p, changed);
        CHECK(fx::change_cost(params, changed) == p.cost);
        effect.set_params(changed);
        const fx::EffectChanges c = effect.update(view);
        CHECK(c.mesh == (p.cost == fx::ParameterCost::Rebuild));
        CHECK(c.scalars == (p.cost == fx::ParameterCost::Scalars));
        CHECK(effect.counters().mesh_builds - before.mesh_builds == (p.cost == fx::ParameterCost::Rebuild ? 1u : 0u));
        CHECK(effect.counters().scalar_updates - before.scalar_updates == (p.cost == fx::ParameterCost::Scalars ? 1u : 0u));
        E fresh(changed);
        fresh.update(view);
        CHECK(effect.mesh().points == fresh.mesh().points);
        CHECK(effect.mesh().cell_count() == fresh.mesh().cell_count());
        REQUIRE(effect.mesh().scalars.size() == 1);
        CHECK(effect.mesh().scalars[0].values == fresh.mesh().scalars[0].values);
        CHECK(effect.transform() == fresh.transform());
        // The same parameters again cost nothing.
        effect.set_params(changed);
        const fx::EffectChanges again = effect.update(view);
        CHECK_FALSE(again.any());
    }
}

} // namespace

TEST_CASE("Effect parameter tables: a change costs what the table says, and that is enough", "[effects][parameters]") {
    check_costs<fx::CampfireParams>("campfire");
    check_costs<fx::SearchLightParams>("search_light");
    check_costs<fx::LaserConeParams>("laser_cone");
    check_costs<fx::VolumeParams>("volume");
    // What the volume's table does not describe: a new shape rebuilds, a new density mode on a
    // box re-evaluates, on a mesh (whose field is copied when built) rebuilds.
    fx::VolumeParams box;
    box.cells = 4;
    fx::VolumeParams sphere = box;
    sphere.shape = fx::VolumeShape::Sphere;
    fx::VolumeParams noisy = box;
    noisy.density_mode = fx::VolumeDensity::Noise;
    fx::Volume v(box);
    fx::EffectView view;
    view.camera = fx::Camera::parse("eye=0,-5,1,target=0,0,0.7,up=0,0,1");
    v.update(view);
    v.set_params(noisy);
    fx::EffectChanges c = v.update(view);
    CHECK((c.scalars && !c.mesh));
    v.set_params(sphere);
    c = v.update(view);
    CHECK(c.mesh);
    // Automatic cells follow the density mode: a constant box is one hexahedron, a noisy one 16.
    fx::VolumeParams automatic;
    fx::Volume a(automatic);
    a.update(view);
    CHECK(a.mesh().cell_count() == 1);
    automatic.density_mode = fx::VolumeDensity::Noise;
    a.set_params(automatic);
    CHECK(a.update(view).mesh);
    CHECK(a.mesh().cell_count() == 16 * 16 * 16);
}

TEST_CASE("The scene parser reads every effect parameter through its table", "[effects][parameters][scene]") {
    const auto entry = [](const std::string& type, const std::string& keys) {
        return R"({"effects": [{"type": ")" + type + R"(", "transfer_function": "../transfer_functions/fire.json", )" + keys +
               R"(}], "camera": {"eye": [0, -5, 1], "target": [0, 0, 0.7]}})";
    };
    // Nested keys, every kind, read exactly.
    const terrain::Scene scene = parse(entry("search_light", R"("sweep": {"axis": [1, 0, 0], "amplitude_degrees": 20, "period": 2.5}, "segments": 5)"));
    const auto& beam = std::get<fx::SearchLightParams>(scene.effects[0].params);
    CHECK(beam.sweep.axis == glm::dvec3(1, 0, 0));
    CHECK(beam.sweep.amplitude_degrees == 20.0);
    CHECK(beam.sweep.period == 2.5);
    CHECK(beam.sweep.phase_degrees == fx::SweepMotion{}.phase_degrees); // the default kept
    CHECK(beam.segments == 5);
    const terrain::Scene fire_scene = parse(entry("campfire", R"("seed": 4294967295)"));
    const auto& fire = std::get<fx::CampfireParams>(fire_scene.effects[0].params);
    CHECK(fire.seed == 4294967295u);
    // Errors name the file, the entry and the key.
    CHECK_THROWS_WITH(parse(entry("campfire", R"("seed": -1)")), Catch::Contains("fx.json: effects[0].seed: must be in 0..4294967295"));
    CHECK_THROWS_WITH(parse(entry("campfire", R"("cells_up": 2.5)")), Catch::Contains("fx.json: effects[0].cells_up: expected an integer"));
    CHECK_THROWS_WITH(parse(entry("campfire", R"("height": "tall")")), Catch::Contains("fx.json: effects[0].height: expected a number"));
    CHECK_THROWS_WITH(parse(entry("campfire", R"("base_radius": 0)")),
                      Catch::Contains("fx.json: effects[0].base_radius: must be positive (got 0)"));
    CHECK_THROWS_WITH(parse(entry("search_light", R"("sweep": {"perod": 2})")), Catch::Contains("fx.json: effects[0].sweep.perod: unknown key"));
    CHECK_THROWS_WITH(parse(entry("search_light", R"("sweep": 3)")), Catch::Contains("fx.json: effects[0].sweep: expected an object"));
    CHECK_THROWS_WITH(parse(entry("laser_cone", R"("direction": [0, 0, 0])")),
                      Catch::Contains("fx.json: effects[0].direction: must be finite and non-zero"));
    CHECK_THROWS_WITH(parse(entry("volume", R"("shape": "sphere", "size": [1, 1, 1])")),
                      Catch::Contains("fx.json: effects[0].size: does not apply to a sphere volume with constant density"));
    CHECK_THROWS_WITH(parse(entry("volume", R"("noise": {"frequency": 1}, "density_mode": "constant")")),
                      Catch::Contains("fx.json: effects[0].noise.frequency: does not apply to a box volume with constant density"));
    CHECK_THROWS_WITH(parse(entry("campfire", R"("colour": 1)")), Catch::Contains("fx.json: effects[0].colour: unknown key"));
}

namespace {

std::string text(double v) {
    std::ostringstream out;
    out.precision(10);
    out << v;
    return out.str();
}

template <class P>
std::string range_text(const fx::Parameter<P>& p) {
    const fx::ParameterRange& r = p.range;
    switch (p.kind) {
    case fx::ParameterKind::Seed: return "any 32-bit";
    case fx::ParameterKind::Vector: return "any";
    case fx::ParameterKind::Direction: return "non-zero";
    case fx::ParameterKind::Integer: return text(r.lo) + ".." + text(r.hi);
    case fx::ParameterKind::Number:
    case fx::ParameterKind::Extents: break;
    }
    std::string t;
    if (r.lo == -fx::kMaxCoordinate && r.hi == fx::kMaxCoordinate) t = "any";
    else if (r.hi == fx::kMaxCoordinate) t = std::string(r.lo_open ? "> " : "≥ ") + text(r.lo);
    else t = std::string(r.lo_open ? "(" : "[") + text(r.lo) + ", " + text(r.hi) + "]";
    return p.kind == fx::ParameterKind::Extents ? "each " + t : t;
}

// The docs' table of one parameter type, from its table: what docs/effects.md carries.
template <class P>
std::string markdown_table() {
    const P defaults{};
    std::string out = "| parameter | default | range | unit | what it does | changing it |\n"
                      "| --- | --- | --- | --- | --- | --- |\n";
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        std::string value;
        if (p.vector) {
            const glm::dvec3 v = fx::parameter_vector(p, defaults);
            value = text(v.x) + ", " + text(v.y) + ", " + text(v.z);
        } else {
            value = text(fx::parameter_value(p, defaults));
        }
        const std::string cost = p.cost == fx::ParameterCost::Pose ? "pose only" : fx::parameter_cost_name(p.cost);
        out += "| `" + std::string(p.name) + "` | " + value + " | " + range_text(p) + " | " + (*p.unit ? p.unit : "—") +
               " | " + p.what + " | " + cost + " |\n";
    }
    return out;
}

// Replaces the block after each "<!-- parameters: NAME" marker line, up to the next
// "<!-- end of parameters -->", by `tables[NAME]`; counts the blocks replaced.
std::string with_tables(const std::string& doc, const std::map<std::string, std::string>& tables, int& replaced) {
    const std::string begin = "<!-- parameters: ", end = "<!-- end of parameters -->";
    std::string out;
    std::size_t at = 0;
    replaced = 0;
    for (;;) {
        const std::size_t b = doc.find(begin, at);
        if (b == std::string::npos) break;
        const std::size_t name_end = doc.find_first_of(" \n", b + begin.size());
        const std::size_t line_end = doc.find('\n', b);
        const std::size_t e = doc.find(end, line_end);
        REQUIRE(line_end != std::string::npos);
        REQUIRE(e != std::string::npos);
        const std::string name = doc.substr(b + begin.size(), name_end - b - begin.size());
        INFO("docs/effects.md names the parameter table '" << name << "'");
        REQUIRE(tables.count(name) == 1);
        out += doc.substr(at, line_end + 1 - at) + tables.at(name);
        at = e;
        ++replaced;
    }
    return out + doc.substr(at);
}

} // namespace

TEST_CASE("docs/effects.md's parameter tables are the ones the tables generate", "[effects][parameters][docs]") {
    // The docs' tables come from the description (name, default, range, unit, what, cost), so
    // they cannot drift from what the effects accept and what a change costs. When this fails,
    // the regenerated page is in the test output folder: copy it over docs/effects.md.
    const std::map<std::string, std::string> tables = {{"campfire", markdown_table<fx::CampfireParams>()},
                                                       {"search_light", markdown_table<fx::SearchLightParams>()},
                                                       {"laser_cone", markdown_table<fx::LaserConeParams>()},
                                                       {"volume", markdown_table<fx::VolumeParams>()}};
    const std::string doc = fx_test::read_bytes(fx_test::source_path("docs/effects.md"));
    REQUIRE(!doc.empty());
    int replaced = 0;
    const std::string generated = with_tables(doc, tables, replaced);
    CHECK(replaced == int(tables.size()));
    if (generated != doc) {
        const std::string path = fx_test::output_path("effects.md");
        std::ofstream(path, std::ios::binary | std::ios::trunc) << generated;
        FAIL("docs/effects.md's parameter tables differ from the tables in fx/src/effects/effect_parameters.cpp; "
             "the regenerated page: " << path);
    }
}
