// The scene-file loader (format: terrain/scene.hpp and docs/terrain.md). The one place that
// reads scene JSON, and writes it back updated (updated_scene_json, at the end).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <variant>

#include <nlohmann/json.hpp>

#include "fx/cell_mesh.hpp"
#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "fx/medium.hpp"
#include "fx/mesh_io.hpp"
#include "fx/resource_limits.hpp"
#include "io/input_file.hpp"
#include "io/json_input.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"

namespace cellfx::terrain {

namespace {

using nlohmann::json;

// A JSON object at a key path ("fog.valley"), with typed getters that name the file and the key
// in errors, and a check that every key was understood.
class Section {
public:
    Section(const json& value, std::string path, const std::string& source) : j_(value), path_(std::move(path)), source_(source) {
        if (!j_.is_object()) throw error("", "expected an object");
    }

    fx::Error error(const std::string& key, const std::string& what) const {
        std::string where = path_;
        if (!key.empty()) where += (where.empty() ? "" : ".") + key;
        return fx::Error(source_ + ": " + (where.empty() ? "" : where + ": ") + what);
    }
    bool has(const std::string& key) const { return j_.contains(key); }
    // The value at a key the section must have (a missing one is an error naming it, not
    // nlohmann's out_of_range escaping the reader).
    const json& at(const std::string& key) {
        if (!has(key)) throw error(key, "is required");
        used_.insert(key);
        return j_.at(key);
    }

    double number(const std::string& key, std::optional<double> fallback = std::nullopt) {
        if (!has(key)) {
            if (!fallback) throw error(key, "is required");
            return *fallback;
        }
        const json& v = at(key);
        if (!v.is_number()) throw error(key, "expected a number");
        return bounded(key, v.get<double>());
    }
    double positive(const std::string& key, std::optional<double> fallback = std::nullopt) {
        const double d = number(key, fallback);
        if (!(d > 0.0)) throw error(key, "must be positive");
        return d;
    }
    long integer(const std::string& key, long fallback, long lo, long hi) {
        if (!has(key)) return fallback;
        const json& v = at(key);
        if (!v.is_number_integer()) throw error(key, "expected an integer");
        const long i = v.get<long>();
        if (i < lo || i > hi) throw error(key, "must be in " + std::to_string(lo) + ".." + std::to_string(hi));
        return i;
    }
    bool boolean(const std::string& key, bool fallback) {
        if (!has(key)) return fallback;
        const json& v = at(key);
        if (!v.is_boolean()) throw error(key, "expected true or false");
        return v.get<bool>();
    }
    std::string string(const std::string& key, std::optional<std::string> fallback = std::nullopt) {
        if (!has(key)) {
            if (!fallback) throw error(key, "is required");
            return *fallback;
        }
        const json& v = at(key);
        if (!v.is_string()) throw error(key, "expected a string");
        return v.get<std::string>();
    }
    template <int N>
    glm::vec<N, double> vector(const std::string& key, std::optional<glm::vec<N, double>> fallback = std::nullopt) {
        if (!has(key)) {
            if (!fallback) throw error(key, "is required");
            return *fallback;
        }
        const json& v = at(key);
        if (!v.is_array() || v.size() != std::size_t(N)) throw error(key, "expected an array of " + std::to_string(N) + " numbers");
        glm::vec<N, double> out;
        for (int k = 0; k < N; ++k) {
            if (!v[k].is_number()) throw error(key, "expected an array of " + std::to_string(N) + " finite numbers");
            out[k] = bounded(key, v[k].get<double>());
        }
        return out;
    }
    Section object(const std::string& key) {
        if (!has(key)) throw error(key, "is required");
        return Section(at(key), child(key), source_);
    }
    std::string child(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    // Rejects keys nobody asked for (a typo is an error, not silently ignored).
    void finish(std::initializer_list<const char*> optional_keys = {}) const {
        for (auto it = j_.begin(); it != j_.end(); ++it) {
            if (used_.count(it.key())) continue;
            bool known = false;
            for (const char* k : optional_keys) known = known || it.key() == k;
            if (!known) throw error(it.key(), "unknown key");
        }
    }
    void use(const std::string& key) { used_.insert(key); }
    const std::string& source() const { return source_; }

private:
    // Every number a scene holds is finite and within ±kMaxCoordinate: coordinates, sizes and
    // rates beyond it only overflow the float arithmetic of the render paths.
    double bounded(const std::string& key, double d) const {
        if (!std::isfinite(d)) throw error(key, "is not finite");
        if (std::abs(d) > fx::kMaxCoordinate) {
            std::ostringstream text;
            text << d;
            throw error(key, "is " + text.str() + ", beyond ±1e18: cellfx renders coordinates and sizes up to 1e18");
        }
        return d;
    }

    const json& j_;
    std::string path_;
    const std::string& source_;
    std::set<std::string> used_;
};

// A number as a user wrote it: "60", "0.5", "1e-06".
std::string fx_format(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

// An effect's own constructor checks its parameters (cross-parameter rules included).
void validate_effect_params(const fx::CampfireParams& p) { fx::Campfire check(p); }
void validate_effect_params(const fx::SearchLightParams& p) { fx::SearchLight check(p); }
void validate_effect_params(const fx::LaserConeParams& p) { fx::LaserCone check(p); }
void validate_effect_params(const fx::VolumeParams& p) { fx::Volume check(p); }

// The files a scene names: resolved against its folder; a transfer function named by many
// effects is read once.
struct SceneFiles {
    std::string base_dir;
    std::map<std::string, fx::TransferFunction> transfer_functions; // by resolved path

    std::string resolve(const std::string& file) const {
        const std::filesystem::path p(file);
        return p.is_absolute() || base_dir.empty() ? file : (std::filesystem::path(base_dir) / p).lexically_normal().string();
    }
    const fx::TransferFunction& transfer_function(const std::string& path) {
        const auto found = transfer_functions.find(path);
        if (found != transfer_functions.end()) return found->second;
        return transfer_functions.emplace(path, fx::TransferFunction::read_json(path)).first->second;
    }
};

NoiseSpec parse_noise(Section s) {
    NoiseSpec n;
    n.amplitude = s.number("amplitude", 1.0);
    n.offset = s.number("offset", 0.0);
    n.frequency = s.positive("frequency", 1.0);
    n.octaves = int(s.integer("octaves", 4, 1, 16));
    n.lacunarity = s.positive("lacunarity", 2.0);
    n.gain = s.positive("gain", 0.5);
    n.seed = std::uint32_t(s.integer("seed", 1, 0, 0xffffffffL));
    s.finish();
    return n;
}

fx::RenderPath parse_path(Section& s, const std::string& key, fx::RenderPath fallback) {
    if (!s.has(key)) return fallback;
    const std::string name = s.string(key);
    fx::RenderPath path;
    if (!fx::parse_render_path(name, path)) {
        std::string names;
        for (fx::RenderPath p : fx::kRenderPaths) names += std::string(names.empty() ? "" : ", ") + fx::render_path_name(p);
        throw s.error(key, "unknown render path '" + name + "' (expected " + names + ")");
    }
    return path;
}

// A transfer function given by file name or inline ({"points": [[s, r, g, b, sigma], ...]}).
fx::TransferFunction load_transfer_function(Section& s, SceneFiles& files) {
    if (s.has("transfer_function") && s.at("transfer_function").is_object()) {
        // Errors name the key path as the source: "fx.json: effects[0].transfer_function: points[1]: ...".
        return fx::TransferFunction::parse_json(s.at("transfer_function").dump(), s.source() + ": " + s.child("transfer_function"));
    }
    const std::string file = files.resolve(s.string("transfer_function"));
    try {
        return files.transfer_function(file);
    } catch (const fx::Error& e) {
        throw s.error("transfer_function", e.what());
    }
}

// The scale of `tf`'s extinction; the scaled function must still be one cellfx integrates.
double parse_extinction_scale(Section& s, const fx::TransferFunction& tf) {
    const double k = s.number("extinction_scale", 1.0);
    if (k < 0.0) throw s.error("extinction_scale", "must not be negative");
    try {
        tf.scaled_extinction(k);
    } catch (const fx::Error& e) {
        throw s.error("extinction_scale", e.what());
    }
    return k;
}

HeightField load_height_map(Section& s, const std::string& key, Section& options_from, const SceneFiles& files,
                            double spacing, glm::dvec2 origin) {
    HeightFieldOptions options;
    options.spacing = spacing;
    options.origin = origin;
    options.vertical_scale = options_from.number("vertical_scale", 1.0);
    if (options.vertical_scale == 0.0) throw options_from.error("vertical_scale", "must not be zero");
    options.vertical_offset = options_from.number("vertical_offset", 0.0);
    options.pad = options_from.boolean("pad", false);
    const std::string file = files.resolve(s.string(key));
    try {
        return read_height_field_png(file, options);
    } catch (const fx::Error& e) {
        throw s.error(key, e.what());
    }
}

HeightField parse_terrain(Section s, const SceneFiles& files, bool& draw) {
    HeightField ground;
    draw = s.boolean("draw", true);
    if (s.has("height_map") == s.has("procedural"))
        throw s.error("", "give either height_map or procedural");
    if (s.has("height_map")) {
        const double spacing = s.positive("spacing", 1.0);
        const glm::dvec2 origin = s.vector<2>("origin", glm::dvec2(0.0));
        ground = load_height_map(s, "height_map", s, files, spacing, origin);
    } else {
        Section p = s.object("procedural");
        const long size = p.integer("size", 257, 3, 16385);
        if (!is_lod_size(int(size))) throw p.error("size", "must be 2^n + 1 (e.g. 257, 1025)");
        const double spacing = p.positive("spacing", 1.0);
        const glm::dvec2 origin = p.vector<2>("origin", glm::dvec2(0.0));
        const NoiseSpec noise = parse_noise(p.object("noise"));
        p.finish();
        try {
            ground = make_height_field(int(size), spacing, make_noise_generator(noise), origin);
        } catch (const fx::Error& e) {
            throw p.error("", e.what());
        }
    }
    s.finish();
    return ground;
}

FogSpec parse_fog(Section s, const HeightField& ground, SceneFiles& files) {
    FogSpec fog;
    if (s.has("thickness_map") == s.has("valley")) throw s.error("", "give either thickness_map or valley");
    if (s.has("thickness_map")) {
        Section m = s.object("thickness_map");
        fog.thickness = load_height_map(m, "file", m, files, ground.spacing, ground.origin);
        m.finish();
        try {
            require_same_grid(ground, fog.thickness, "the fog map");
        } catch (const fx::Error& e) {
            throw s.error("thickness_map", e.what());
        }
        for (float t : fog.thickness.heights)
            if (t < 0.0f) throw s.error("thickness_map", "the fog map has negative thickness (check vertical_offset)");
    } else {
        Section v = s.object("valley");
        const double level = v.number("level");
        const double max_thickness = v.positive("max_thickness");
        const double radius = v.number("radius", 0.0);
        if (radius < 0.0) throw v.error("radius", "must not be negative");
        HeightGenerator modulation;
        if (v.has("noise")) modulation = make_noise_generator(parse_noise(v.object("noise")));
        v.finish();
        fog.thickness = make_valley_fog_map(ground, level, max_thickness, modulation, radius);
    }
    const std::string density = s.string("density", std::string("layer_height"));
    if (density == "layer_height") {
        fog.prisms.density = LayerDensity::LayerHeight;
    } else if (density == "noise") {
        fog.prisms.density = LayerDensity::Noise;
        if (!s.has("density_noise")) throw s.error("density_noise", "is required with density \"noise\"");
        fog.prisms.noise = make_noise_generator(parse_noise(s.object("density_noise")));
    } else {
        throw s.error("density", "expected \"layer_height\" or \"noise\", got \"" + density + "\"");
    }
    fog.prisms.density_scale = s.positive("density_scale", 1.0);
    fog.transfer_function = load_transfer_function(s, files);
    fog.extinction_scale = parse_extinction_scale(s, fog.transfer_function);
    fog.path = parse_path(s, "path", fx::RenderPath::PcpExact);
    fog.absorb = s.boolean("absorb", true);
    fog.albedo = s.number("albedo", fog.albedo);
    if (fog.albedo < 0.0 || fog.albedo > 1.0) throw s.error("albedo", "must be in [0, 1]");
    fog.enabled = s.boolean("enabled", true);
    s.finish();
    return fog;
}

AuroraSpec parse_aurora(Section s, SceneFiles& files) {
    AuroraSpec a;
    a.ceiling = s.number("ceiling");
    const long size = s.integer("size", 129, 3, 16385);
    if (!is_lod_size(int(size))) throw s.error("size", "must be 2^n + 1 (e.g. 129, 257)");
    const double spacing = s.positive("spacing");
    const glm::dvec2 origin = s.vector<2>("origin", glm::dvec2(0.0));
    AuroraCurtains c;
    if (s.has("curtains")) {
        Section k = s.object("curtains");
        c.count = int(k.integer("count", c.count, 1, 64));
        c.max_depth = k.positive("max_depth", c.max_depth);
        c.width = k.positive("width", c.width);
        c.wander = k.number("wander", c.wander);
        c.cutoff = k.number("cutoff", c.cutoff);
        if (c.cutoff < 0.0 || c.cutoff >= 1.0) throw k.error("cutoff", "must be in [0, 1)");
        c.seed = std::uint32_t(k.integer("seed", c.seed, 0, 0xffffffffL));
        k.finish();
    }
    try {
        a.layer = make_aurora_layer(make_aurora_depth(int(size), spacing, origin, c), a.ceiling);
    } catch (const fx::Error& e) {
        throw s.error("", e.what());
    }
    a.transfer_function = load_transfer_function(s, files);
    a.extinction_scale = parse_extinction_scale(s, a.transfer_function);
    a.path = parse_path(s, "path", fx::RenderPath::Mip);
    a.pixel_error = s.positive("pixel_error", 4.0);
    a.enabled = s.boolean("enabled", true);
    s.finish();
    return a;
}

double non_negative(Section& s, const std::string& key, double fallback) {
    const double d = s.number(key, fallback);
    if (d < 0.0) throw s.error(key, "must not be negative");
    return d;
}

double in_range(Section& s, const std::string& key, double fallback, double lo, double hi) {
    const double d = s.number(key, fallback);
    if (d < lo || d > hi) throw s.error(key, "must be in [" + fx_format(lo) + ", " + fx_format(hi) + "]");
    return d;
}

// Reads the parameters of P's table (fx/effect_parameters.hpp) that the entry gives, over the
// defaults in `params`: key "a.b" is key b of the object a (whose other keys are refused as
// unknown). Each value is checked against the table's kind and range, errors naming the key; a
// key for a parameter that does not apply to these parameters (a sphere's size) is refused
// with `does_not_apply`.
template <class P>
void parse_params(Section& s, P& params, const std::string& does_not_apply) {
    std::map<std::string, Section> objects; // "sweep", "noise": read once each
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        const std::string name = p.name;
        const std::size_t dot = name.find('.');
        Section* in = &s;
        std::string key = name;
        if (dot != std::string::npos) {
            const std::string parent = name.substr(0, dot);
            if (!s.has(parent)) continue;
            auto found = objects.find(parent);
            if (found == objects.end()) found = objects.emplace(parent, s.object(parent)).first;
            in = &found->second;
            key = name.substr(dot + 1);
        }
        if (!in->has(key)) continue;
        if (!p.applies_to(params)) throw in->error(key, does_not_apply);
        std::string problem;
        if (p.vector) {
            const glm::dvec3 v = in->vector<3>(key);
            problem = fx::parameter_problem(p.kind, p.range, v);
            *p.vector(params) = v;
        } else if (p.kind == fx::ParameterKind::Number) {
            const double v = in->number(key);
            problem = fx::parameter_problem(p.kind, p.range, v);
            *p.number(params) = v;
        } else {
            // Integers and seeds: whole numbers (a seed any std::uint32_t), read exactly.
            const json& v = in->at(key);
            if (!v.is_number_integer()) throw in->error(key, "expected an integer");
            const bool seed = p.kind == fx::ParameterKind::Seed;
            const double lo = seed ? 0.0 : p.range.lo, hi = seed ? 4294967295.0 : p.range.hi;
            const bool negative = v.is_number_unsigned() ? false : v.get<std::int64_t>() < 0;
            const double d = negative ? double(v.get<std::int64_t>()) : double(v.get<std::uint64_t>());
            if (d < lo || d > hi) problem = "must be in " + std::to_string(std::int64_t(lo)) + ".." + std::to_string(std::int64_t(hi)) + " (got " + v.dump() + ")";
            else fx::set_parameter_value(p, params, d);
        }
        if (!problem.empty()) throw in->error(key, problem);
    }
    for (const auto& object : objects) object.second.finish();
}

fx::CampfireParams parse_campfire(Section& s) {
    fx::CampfireParams p;
    parse_params(s, p, "");
    return p;
}

fx::SearchLightParams parse_search_light(Section& s) {
    fx::SearchLightParams p;
    parse_params(s, p, "");
    return p;
}

fx::LaserConeParams parse_laser_cone(Section& s) {
    fx::LaserConeParams p;
    parse_params(s, p, "");
    return p;
}

// A volume's shape, mesh and density mode (not in its table) come first: they decide which of
// its table's parameters apply.
fx::VolumeParams parse_volume(Section& s, const SceneFiles& files) {
    fx::VolumeParams p;
    const std::string shape = s.string("shape", std::string("box"));
    if (shape == "box") p.shape = fx::VolumeShape::Box;
    else if (shape == "sphere") p.shape = fx::VolumeShape::Sphere;
    else if (shape == "mesh") p.shape = fx::VolumeShape::Mesh;
    else throw s.error("shape", "unknown shape '" + shape + "' (expected box, sphere, mesh)");
    if (p.shape == fx::VolumeShape::Mesh) {
        const std::string file = files.resolve(s.string("mesh"));
        const std::string q_file = s.has("q_file") ? files.resolve(s.string("q_file")) : std::string();
        try {
            p.mesh = std::make_shared<const fx::CellMesh>(fx::read_mesh(file, q_file));
        } catch (const fx::Error& e) {
            throw s.error("mesh", e.what());
        }
        p.field = s.string("field", std::string());
    }
    // The density's kind: as given, else noise when a "noise" object is, else a mesh's field.
    p.density_mode = s.has("noise") ? fx::VolumeDensity::Noise
                     : p.shape == fx::VolumeShape::Mesh ? fx::VolumeDensity::Field
                                                        : fx::VolumeDensity::Constant;
    if (s.has("density_mode")) {
        const std::string mode = s.string("density_mode");
        if (mode == "constant") p.density_mode = fx::VolumeDensity::Constant;
        else if (mode == "noise") p.density_mode = fx::VolumeDensity::Noise;
        else if (mode == "field") p.density_mode = fx::VolumeDensity::Field;
        else throw s.error("density_mode", "unknown density '" + mode + "' (expected constant, noise, field)");
    }
    parse_params(s, p, std::string("does not apply to a ") + fx::volume_shape_name(p.shape) + " volume with " +
                           fx::volume_density_name(p.density_mode) + " density");
    return p;
}

LightSpec parse_light(Section l) {
    LightSpec light;
    light.color = l.vector<3>("color", light.color);
    if (light.color.r < 0.0 || light.color.g < 0.0 || light.color.b < 0.0) throw l.error("color", "must not be negative");
    light.strength = non_negative(l, "strength", light.strength);
    light.phase_g = in_range(l, "g", light.phase_g, -0.99, 0.99);
    light.radius = non_negative(l, "radius", light.radius);
    l.finish();
    return light;
}

EffectSpec parse_effect(Section s, SceneFiles& files) {
    EffectSpec e;
    const std::string type = s.string("type");
    if (type == "campfire") e.params = parse_campfire(s);
    else if (type == "search_light") e.params = parse_search_light(s);
    else if (type == "laser_cone") e.params = parse_laser_cone(s);
    else if (type == "volume") e.params = parse_volume(s, files);
    else if (type == "ground_fog" || type == "aurora")
        throw s.error("type", "'" + type + "' is declared by the scene's \"" + (type == "aurora" ? "aurora" : "fog") +
                                  "\" section, not in effects");
    else throw s.error("type", "unknown effect type '" + type + "' (expected campfire, search_light, laser_cone, volume)");
    e.name = s.string("name", type);
    if (e.name.empty()) throw s.error("name", "must not be empty");
    e.enabled = s.boolean("enabled", true);
    e.path = parse_path(s, "path", fx::RenderPath::PcpExact);
    e.absorb = s.boolean("absorb", type == "volume"); // volumes absorb unless told otherwise
    e.albedo = in_range(s, "albedo", type == "volume" ? 0.9 : 0.0, 0.0, 1.0);
    if (s.has("light")) {
        if (type == "volume") throw s.error("light", "a volume sheds no light (campfires, search lights and laser cones do)");
        e.light = parse_light(s.object("light"));
    }
    e.transfer_function = load_transfer_function(s, files);
    e.extinction_scale = parse_extinction_scale(s, e.transfer_function);
    s.finish();
    // The effect's own checks (cross-parameter rules), named by the entry.
    try {
        std::visit([](const auto& params) { validate_effect_params(params); }, e.params);
    } catch (const fx::Error& err) {
        throw s.error("", err.what());
    }
    return e;
}

// `taken`: the names of the scene's own sections ("fog", "aurora") when it declares them.
std::vector<EffectSpec> parse_effects(Section& root, SceneFiles& files, const std::vector<std::string>& taken) {
    const json& list = root.at("effects");
    if (!list.is_array()) throw root.error("effects", "expected an array of effects");
    fx::check_limit(fx::Limit::Effects, list.size(), root.source() + ": effects");
    std::vector<EffectSpec> effects;
    std::map<std::string, std::size_t> index_of; // name → entry: a linear search was quadratic
    std::uint64_t cells = 0;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string where = "effects[" + std::to_string(i) + "]";
        EffectSpec e = parse_effect(Section(list[i], where, root.source()), files);
        if (std::find(taken.begin(), taken.end(), e.name) != taken.end())
            throw fx::Error(root.source() + ": " + where + ".name: '" + e.name + "' is reserved for the scene's " + e.name +
                            " section");
        const auto [it, fresh] = index_of.emplace(e.name, i);
        if (!fresh)
            throw fx::Error(root.source() + ": " + where + ".name: '" + e.name + "' is already the name of effects[" +
                            std::to_string(it->second) + "] (give each effect its own \"name\")");
        cells += std::visit([](const auto& params) { return fx::max_cells(params); }, e.params);
        fx::check_limit(fx::Limit::SceneCells, cells, root.source() + ": effects[0.." + std::to_string(i) + "] together");
        effects.push_back(std::move(e));
    }
    return effects;
}

CameraPath parse_camera_path(Section s, const fx::Camera& base) {
    CameraPath path;
    path.loop = s.boolean("loop", false);
    const json& keys = s.at("keys");
    if (!keys.is_array() || keys.size() < 2) throw s.error("keys", "expected an array of at least 2 keys");
    for (std::size_t i = 0; i < keys.size(); ++i) {
        Section k(keys[i], s.child("keys[" + std::to_string(i) + "]"), s.source());
        CameraKey key;
        key.time = k.number("time");
        key.eye = k.vector<3>("eye");
        key.target = k.vector<3>("target");
        if (key.eye == key.target) throw k.error("target", "is the eye position");
        fx::Camera at_key = base; // the scene camera's up, fov, near and far from this key
        at_key.eye = key.eye;
        at_key.target = key.target;
        at_key.validate(s.source() + ": " + s.child("keys[" + std::to_string(i) + "]"));
        if (!path.keys.empty() && !(key.time > path.keys.back().time))
            throw k.error("time", "must be later than the previous key's");
        k.finish();
        path.keys.push_back(key);
    }
    s.finish();
    return path;
}

fx::Camera parse_camera(Section s) {
    fx::Camera cam;
    cam.eye = s.vector<3>("eye");
    cam.target = s.vector<3>("target");
    cam.up = s.vector<3>("up", glm::dvec3(0.0, 0.0, 1.0));
    if (s.has("ortho")) {
        cam.ortho_height = s.positive("ortho");
    } else {
        cam.fov_y_degrees = s.positive("fov", 50.0);
        if (cam.fov_y_degrees >= 179.0) throw s.error("fov", "must be below 179 degrees");
    }
    cam.near_distance = s.positive("near", 1.0);
    cam.far_distance = s.positive("far", 1.0e5);
    if (!(cam.far_distance > cam.near_distance)) throw s.error("far", "must be beyond near");
    if (cam.eye == cam.target) throw s.error("target", "is the eye position");
    s.finish();
    cam.validate(s.source() + ": camera");
    return cam;
}

} // namespace

Scene parse_scene(std::string_view text, const std::string& source, const std::string& base_dir) {
    const json doc = fx::io::parse_json_input(text, source);
    Section root(doc, "", source);
    SceneFiles files{base_dir, {}};
    Scene scene;
    scene.source = source;
    scene.description = root.string("description", std::string());
    if (root.has("terrain")) {
        scene.ground = parse_terrain(root.object("terrain"), files, scene.draw_terrain);
    } else if (!root.has("effects")) {
        throw root.error("terrain", "is required (a scene without effects needs a terrain)");
    }
    if (root.has("lod")) {
        Section l = root.object("lod");
        scene.pixel_error = l.positive("pixel_error", scene.pixel_error);
        scene.lod.min_resolution = l.number("min_resolution", scene.lod.min_resolution);
        if (!(scene.lod.min_resolution > 1.0)) throw l.error("min_resolution", "must be greater than 1");
        scene.triangle_budget = std::size_t(l.integer("triangle_budget", 0, 0, 1L << 40));
        scene.lod.geomorph = l.boolean("geomorph", true);
        scene.lod.morph_steps = int(l.integer("morph_steps", scene.lod.morph_steps, 0, 4096));
        l.finish();
    }
    if (root.has("fog")) {
        if (!scene.has_terrain()) throw root.error("fog", "needs a terrain (the fog map lies on its grid)");
        scene.fog = parse_fog(root.object("fog"), scene.ground, files);
    }
    if (root.has("aurora")) scene.aurora = parse_aurora(root.object("aurora"), files);
    if (root.has("effects")) {
        std::vector<std::string> taken;
        if (scene.fog) taken.push_back("fog");
        if (scene.aurora) taken.push_back("aurora");
        scene.effects = parse_effects(root, files, taken);
    }
    scene.camera = parse_camera(root.object("camera"));
    if (root.has("camera_path")) scene.camera_path = parse_camera_path(root.object("camera_path"), scene.camera);
    if (root.has("render")) {
        Section r = root.object("render");
        scene.width = int(r.integer("width", scene.width, 1, 16384));
        scene.height = int(r.integer("height", scene.height, 1, 16384));
        scene.background = r.vector<3>("background", scene.background);
        for (int k = 0; k < 3; ++k)
            if (!(scene.background[k] >= 0.0 && scene.background[k] <= 1.0))
                throw r.error("background", "colour components must be in [0, 1]");
        scene.fx_scale = r.number("fx_scale", scene.fx_scale);
        if (!valid_fx_scale(scene.fx_scale))
            throw r.error("fx_scale", "must be 1, 0.5 or 0.25 (the effects' resolution: full, half, quarter), got " +
                                          std::to_string(scene.fx_scale));
        if (r.has("medium") && !fx::parse_medium_method(r.string("medium"), scene.medium))
            throw r.error("medium", "unknown method '" + r.string("medium") + "' (expected froxel or exact)");
        fx::check_limit(fx::Limit::ImagePixels, std::uint64_t(scene.width) * std::uint64_t(scene.height),
                        source + ": render: a " + std::to_string(scene.width) + "x" + std::to_string(scene.height) + " image");
        r.finish();
    }
    if (root.has("surface")) {
        Section s = root.object("surface");
        scene.surface.sun_direction = s.vector<3>("sun", scene.surface.sun_direction);
        if (glm::dvec3(0.0) == scene.surface.sun_direction) throw s.error("sun", "must not be zero");
        scene.surface.ambient = s.number("ambient", scene.surface.ambient);
        if (scene.surface.ambient < 0.0 || scene.surface.ambient > 1.0) throw s.error("ambient", "must be in [0, 1]");
        if (s.has("ramp")) {
            // [[fraction, [r, g, b]], ...]: colour by height fraction, 1 to 8 stops, fractions rising.
            const json& ramp = s.at("ramp");
            const std::string bad = "expected 1 to 8 stops [fraction, [r, g, b]] with fractions in [0, 1], not decreasing";
            if (!ramp.is_array() || ramp.empty() || ramp.size() > 8) throw s.error("ramp", bad);
            scene.surface.ramp.clear();
            for (std::size_t k = 0; k < ramp.size(); ++k) {
                const json& stop = ramp[k];
                const std::string key = "ramp[" + std::to_string(k) + "]";
                if (!stop.is_array() || stop.size() != 2 || !stop[0].is_number() || !stop[1].is_array() || stop[1].size() != 3)
                    throw s.error(key, bad);
                const double f = stop[0].get<double>();
                glm::dvec3 c;
                for (int i = 0; i < 3; ++i) {
                    if (!stop[1][i].is_number() || !std::isfinite(stop[1][i].get<double>()) || stop[1][i].get<double>() < 0.0)
                        throw s.error(key, "colour components must be finite and ≥ 0");
                    c[i] = stop[1][i].get<double>();
                }
                if (!(f >= 0.0 && f <= 1.0) || (!scene.surface.ramp.empty() && f < scene.surface.ramp.back().first))
                    throw s.error(key, bad);
                scene.surface.ramp.emplace_back(f, c);
            }
        }
        s.finish();
    }
    root.finish();
    return scene;
}

Scene load_scene(const std::string& path) {
    const std::vector<char> text = fx::io::read_input_file(path, fx::Limit::JsonBytes, "scene file", [&](std::string_view head) {
        fx::io::check_json_encoding(head, path);
    });
    return parse_scene(std::string_view(text.data(), text.size()), path, std::filesystem::path(path).parent_path().string());
}

// ---- writing a scene back: the original file with the values changed at run time ----------------

namespace {

using ordered_json = nlohmann::ordered_json;

// `file`, a name relative to the folder `from` (as the parser resolves it), seen from `to`.
std::string rebased(const std::string& file, const std::string& from, const std::string& to) {
    namespace fs = std::filesystem;
    if (fs::path(file).is_absolute()) return file;
    const fs::path absolute = fs::absolute(fs::path(from.empty() ? "." : from) / file).lexically_normal();
    const fs::path relative = absolute.lexically_relative(fs::absolute(to.empty() ? "." : to).lexically_normal());
    return relative.empty() ? absolute.string() : relative.generic_string();
}

void rebase(ordered_json& object, const char* key, const std::string& from, const std::string& to) {
    if (object.is_object() && object.contains(key) && object[key].is_string())
        object[key] = rebased(object[key].get<std::string>(), from, to);
}

// Writes `key` when the file has it or the value is not the default (defaults stay left out).
template <class T>
void write(ordered_json& object, const char* key, const T& value, const T& default_value) {
    if (object.contains(key) || !(value == default_value)) object[key] = value;
}

ordered_json vector_json(const glm::dvec3& v) { return ordered_json::array({v.x, v.y, v.z}); }

// The parameters of one effect entry, by its type's table (fx/effect_parameters.hpp): keys
// "a.b" are key b of the object a. A parameter that does not apply (a volume's size once it is
// a sphere) is taken out.
template <class P>
void write_params(ordered_json& entry, const P& params) {
    const P defaults{};
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        const std::string name = p.name;
        const std::size_t dot = name.find('.');
        const std::string parent = dot == std::string::npos ? "" : name.substr(0, dot);
        const std::string key = name.substr(dot == std::string::npos ? 0 : dot + 1);
        if (!parent.empty() && entry.contains(parent) && !entry[parent].is_object()) entry.erase(parent);
        ordered_json& object = parent.empty() ? entry : entry[parent];
        const bool present = object.contains(key);
        if (!p.applies_to(params)) {
            if (present) object.erase(key);
        } else if (p.vector) {
            const glm::dvec3 v = fx::parameter_vector(p, params);
            if (present || v != fx::parameter_vector(p, defaults)) object[key] = vector_json(v);
        } else {
            const double v = fx::parameter_value(p, params);
            if (present || v != fx::parameter_value(p, defaults)) {
                if (p.kind == fx::ParameterKind::Number) object[key] = v;
                else object[key] = std::int64_t(v); // integers and seeds, exact
            }
        }
        if (!parent.empty() && object.is_object() && object.empty()) entry.erase(parent);
        else if (!parent.empty() && object.is_null()) entry.erase(parent);
    }
}

void write_effect(ordered_json& entry, const EffectSpec& e, const std::string& where) {
    const std::string type = effect_type_name(e.params);
    if (entry.value("type", std::string()) != type) {
        // Another type (set_params with another kind of effect): only the keys every effect has stay.
        ordered_json kept = ordered_json::object();
        for (const char* key : {"name", "enabled", "path", "absorb", "albedo", "light", "transfer_function", "extinction_scale"})
            if (entry.contains(key)) kept[key] = entry[key];
        entry = std::move(kept);
        entry["type"] = type;
    }
    write(entry, "enabled", e.enabled, true);
    write(entry, "path", std::string(fx::render_path_name(e.path)), std::string(fx::render_path_name(fx::RenderPath::PcpExact)));
    write(entry, "absorb", e.absorb, type == "volume");
    write(entry, "extinction_scale", e.extinction_scale, 1.0);
    if (const auto* volume = std::get_if<fx::VolumeParams>(&e.params)) {
        if (volume->shape == fx::VolumeShape::Mesh && !entry.contains("mesh"))
            throw fx::Error(where + ": a volume whose mesh was built in code has no file to name");
        if (volume->shape != fx::VolumeShape::Mesh) entry["shape"] = fx::volume_shape_name(volume->shape);
        // Always said: the parser would otherwise infer it from whether a "noise" object is there.
        entry["density_mode"] = fx::volume_density_name(volume->density_mode);
    }
    std::visit([&](const auto& params) { write_params(entry, params); }, e.params);
}

} // namespace

std::string updated_scene_json(std::string_view original, const Scene& scene, const std::string& save_dir) {
    if (scene.source.empty()) throw fx::Error("scene: a scene built in code has no file to update");
    const std::string& source = scene.source;
    ordered_json doc;
    try {
        doc = ordered_json::parse(original.begin(), original.end());
    } catch (const nlohmann::json::exception& e) {
        throw fx::Error(source + ": not a scene's JSON: " + e.what());
    }
    if (!doc.is_object()) throw fx::Error(source + ": not a scene's JSON: expected an object");
    const std::string from = std::filesystem::path(source).parent_path().string();

    // Files, named for the new folder.
    if (doc.contains("terrain")) rebase(doc["terrain"], "height_map", from, save_dir);
    if (doc.contains("fog") && doc["fog"].contains("thickness_map")) rebase(doc["fog"]["thickness_map"], "file", from, save_dir);
    for (const char* section : {"fog", "aurora"})
        if (doc.contains(section)) rebase(doc[section], "transfer_function", from, save_dir);
    if (doc.contains("effects") && doc["effects"].is_array())
        for (ordered_json& entry : doc["effects"])
            for (const char* key : {"transfer_function", "mesh", "q_file"}) rebase(entry, key, from, save_dir);

    // The run-time choices.
    const std::string pcp_exact = fx::render_path_name(fx::RenderPath::PcpExact);
    if (scene.fog && doc.contains("fog")) {
        ordered_json& f = doc["fog"];
        write(f, "enabled", scene.fog->enabled, true);
        write(f, "path", std::string(fx::render_path_name(scene.fog->path)), pcp_exact);
        write(f, "absorb", scene.fog->absorb, true);
        write(f, "extinction_scale", scene.fog->extinction_scale, 1.0);
    }
    if (scene.aurora && doc.contains("aurora")) {
        ordered_json& a = doc["aurora"];
        write(a, "enabled", scene.aurora->enabled, true);
        write(a, "path", std::string(fx::render_path_name(scene.aurora->path)), std::string(fx::render_path_name(fx::RenderPath::Mip)));
        write(a, "extinction_scale", scene.aurora->extinction_scale, 1.0);
    }
    ordered_json effects = ordered_json::array();
    const ordered_json written = doc.value("effects", ordered_json::array());
    for (std::size_t i = 0; i < scene.effects.size(); ++i) {
        const EffectSpec& e = scene.effects[i];
        const ordered_json* found = nullptr;
        for (const ordered_json& entry : written)
            if (entry.is_object() && entry.value("name", entry.value("type", std::string())) == e.name) found = &entry;
        if (!found)
            throw fx::Error(source + ": effect '" + e.name + "' is not declared in the file (an effect added at run time cannot be saved)");
        ordered_json entry = *found;
        write_effect(entry, e, source + ": effect '" + e.name + "'");
        effects.push_back(std::move(entry)); // effects removed at run time are left out
    }
    if (doc.contains("effects") || !effects.empty()) doc["effects"] = std::move(effects);
    if (scene.has_terrain() && (doc.contains("lod") || scene.pixel_error != Scene().pixel_error)) doc["lod"]["pixel_error"] = scene.pixel_error;
    if (doc.contains("render") || scene.fx_scale != 1.0 || scene.medium != fx::MediumMethod::Froxel) {
        ordered_json& r = doc["render"];
        write(r, "fx_scale", scene.fx_scale, 1.0);
        write(r, "medium", std::string(fx::medium_method_name(scene.medium)), std::string(fx::medium_method_name(fx::MediumMethod::Froxel)));
    }
    return doc.dump(2) + "\n";
}

} // namespace cellfx::terrain
