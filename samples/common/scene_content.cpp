// A scene through cellfx::Module as a sample's content (scene_content.hpp).
#include "scene_content.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "io/input_file.hpp"
#include "terrain/scene_reference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

std::string scene_path(const std::string& name) { return std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + name + ".json"; }

terrain::Scene sample_scene(const SampleOptions& options, const std::string& name) {
    const auto it = options.values.find("scene");
    return terrain::load_scene(it != options.values.end() ? it->second : scene_path(name));
}

std::pair<std::string, std::string> scene_option() {
    return {"--scene FILE", "show this scene file instead (one the panel saved, say)"};
}

namespace {

glm::dvec3 rotate_about(const glm::dvec3& v, const glm::dvec3& axis, double radians) {
    return glm::dvec3(glm::rotate(glm::dmat4(1.0), radians, glm::normalize(axis)) * glm::dvec4(v, 0.0));
}

} // namespace

fx::Camera pan_camera(const fx::Camera& camera, double radians) {
    fx::Camera c = camera;
    c.target = c.eye + rotate_about(c.target - c.eye, c.up, radians);
    return c;
}

fx::Camera orbit_camera(const fx::Camera& camera, double radians) {
    fx::Camera c = camera;
    c.eye = c.target + rotate_about(c.eye - c.target, c.up, radians);
    return c;
}

SceneContent::SceneContent(const terrain::Scene& scene, const SampleOptions& options) {
    // The first frames' size: the window's or the offscreen frame's (a later size re-simulates).
    module_.init(cellfx::Config::from_scene(scene, options.width, options.height));
    module_.set_time(options.start_time);
    if (!scene.source.empty()) {
        const std::vector<char> text = fx::io::read_input_file(scene.source, fx::Limit::JsonBytes, "scene file");
        original_text_.assign(text.begin(), text.end());
    }
}

fx::Camera SceneContent::scripted_camera(double t) const {
    const terrain::Scene& s = module_.scene();
    const fx::Camera camera = s.camera_path ? s.camera_path->at(t, s.camera) : s.camera;
    return camera_script ? camera_script(camera, t) : camera;
}

void SceneContent::update(double dt, const fx::Camera& camera, int width, int height) {
    if (animate) animate(module_, module_.time() + dt);
    width_ = width, height_ = height;
    module_.update(dt, camera);
}

void SceneContent::draw_props(const fx::Camera& camera, int width, int height) {
    if (props) props(camera, width, height, module_.time());
}

void SceneContent::render(unsigned framebuffer, const fx::Viewport& viewport, unsigned depth_texture) {
    module_.render({framebuffer, viewport, depth_texture});
}

std::vector<fx::RenderPath> SceneContent::paths() const { return {std::begin(fx::kRenderPaths), std::end(fx::kRenderPaths)}; }

void SceneContent::set_path(fx::RenderPath path) {
    for (const std::string& name : module_.effect_names()) module_.set_path(name, path);
    path_label_ = fx::render_path_name(path);
}

std::string SceneContent::path_label() const { return path_label_; }

std::vector<std::string> SceneContent::toggle_names() const {
    std::vector<std::string> names = module_.effect_names();
    if (module_.scene().has_terrain()) names.push_back("terrain");
    return names;
}

bool SceneContent::toggled(std::size_t i) const {
    const std::vector<std::string> names = module_.effect_names();
    if (i < names.size()) return module_.enabled(names[i]);
    return module_.terrain_drawn();
}

void SceneContent::toggle(std::size_t i) {
    const std::vector<std::string> names = module_.effect_names();
    if (i < names.size()) module_.set_enabled(names[i], !module_.enabled(names[i]));
    else if (module_.scene().has_terrain()) module_.set_terrain_drawn(!module_.terrain_drawn());
}

std::string SceneContent::stats_line() const { return module_.stats().summary(); }
std::size_t SceneContent::cells_drawn() const { return module_.stats().cells_drawn; }
double SceneContent::update_ms() const { return module_.stats().update_ms; }
double SceneContent::render_ms() const { return module_.stats().render_ms; }
double SceneContent::update_cpu_ms() const { return module_.stats().update_cpu_ms; }
double SceneContent::render_cpu_ms() const { return module_.stats().render_cpu_ms; }

void SceneContent::set_gpu_timing(bool on) { module_.renderer().set_timing(on); }

void SceneContent::gpu_stages(std::vector<StageTime>& out) const {
    out.clear();
    const terrain::FrameStats& s = module_.stats();
    if (s.surface_gpu_ms >= 0.0) out.push_back({"surface", s.surface_gpu_ms});
    for (const terrain::EffectFrameStats& e : s.effects)
        if (e.gpu_ms >= 0.0) out.push_back({e.name, e.gpu_ms});
    if (s.medium.gpu_ms >= 0.0) out.push_back({"medium", s.medium.gpu_ms});
    if (s.composite_gpu_ms >= 0.0) out.push_back({"composite", s.composite_gpu_ms});
}

// ---- the panel's controls -------------------------------------------------------------------

namespace {

const char* const kFxScales[] = {"1", "0.5", "0.25"};

std::vector<std::string> path_names() {
    std::vector<std::string> names;
    for (fx::RenderPath p : fx::kRenderPaths) names.push_back(fx::render_path_name(p));
    return names;
}

fx::RenderPath path_named(const std::string& name) {
    fx::RenderPath path;
    if (!fx::parse_render_path(name, path)) throw fx::Error("path: unknown render path '" + name + "'");
    return path;
}

Control toggle_control(const std::string& name, bool on, const std::string& note = "") {
    Control c;
    c.name = name, c.kind = Control::Kind::Toggle, c.toggle = on, c.note = note;
    return c;
}
Control choice_control(const std::string& name, std::vector<std::string> choices, const std::string& current, const std::string& note = "") {
    Control c;
    c.name = name, c.kind = Control::Kind::Choice, c.choices = std::move(choices), c.choice = current, c.note = note;
    return c;
}
Control number_control(const std::string& name, double value, const fx::ParameterRange& range, const std::string& unit,
               const std::string& note = "") {
    Control c;
    c.name = name, c.kind = Control::Kind::Number, c.number = value, c.range = range, c.unit = unit, c.note = note;
    return c;
}

// One control per parameter of the effect's table that applies to it.
template <class P>
void add_parameter_controls(const P& params, std::vector<Control>& out) {
    for (const fx::Parameter<P>& p : fx::parameter_table<P>()) {
        if (!p.applies_to(params)) continue;
        Control c;
        c.name = p.name, c.range = p.range, c.unit = p.unit, c.note = fx::parameter_cost_name(p.cost);
        switch (p.kind) {
        case fx::ParameterKind::Number: c.kind = Control::Kind::Number; break;
        case fx::ParameterKind::Integer:
        case fx::ParameterKind::Seed: c.kind = Control::Kind::Integer; break;
        case fx::ParameterKind::Vector:
        case fx::ParameterKind::Extents: c.kind = Control::Kind::Vector; break;
        case fx::ParameterKind::Direction: c.kind = Control::Kind::Direction; break;
        }
        if (p.vector) c.vector = fx::parameter_vector(p, params);
        else c.number = fx::parameter_value(p, params);
        out.push_back(std::move(c));
    }
}

// Sets the parameter the control names; false if the table has none of that name.
template <class P>
bool set_parameter(P& params, const Control& c) {
    const fx::Parameter<P>* p = fx::find_parameter<P>(c.name);
    if (!p) return false;
    if (p->vector) *p->vector(params) = c.vector;
    else fx::set_parameter_value(*p, params, c.number);
    return true;
}

std::vector<std::string> volume_shapes(const fx::VolumeParams& p) {
    if (p.shape == fx::VolumeShape::Mesh) return {fx::volume_shape_name(fx::VolumeShape::Mesh)};
    return {fx::volume_shape_name(fx::VolumeShape::Box), fx::volume_shape_name(fx::VolumeShape::Sphere)};
}
std::vector<std::string> volume_densities(const fx::VolumeParams& p) {
    std::vector<std::string> names = {fx::volume_density_name(fx::VolumeDensity::Constant),
                                      fx::volume_density_name(fx::VolumeDensity::Noise)};
    if (p.shape == fx::VolumeShape::Mesh) names.push_back(fx::volume_density_name(fx::VolumeDensity::Field));
    return names;
}

// The extinction scale's range: set_extinction_scale takes any finite value ≥ 0.
constexpr fx::ParameterRange kScale{0.0, fx::kMaxCoordinate, false};

} // namespace

std::vector<ControlGroup> SceneContent::controls() const {
    const terrain::Scene& scene = module_.scene();
    std::vector<ControlGroup> groups;
    ControlGroup all{"scene", "scene", {}};
    std::string common; // the path every effect shares ("" : they differ)
    const std::vector<std::string> names = module_.effect_names();
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string p = fx::render_path_name(module_.path(names[i]));
        common = i == 0 || p == common ? p : "";
        if (common.empty()) break;
    }
    all.controls.push_back(choice_control("path", path_names(), common, "every effect's render path"));
    all.controls.push_back(choice_control("fx_scale", {std::begin(kFxScales), std::end(kFxScales)},
                                  scene.fx_scale == 1.0 ? "1" : scene.fx_scale == 0.5 ? "0.5" : "0.25",
                                  "the effects' resolution: a fraction of the view's"));
    all.controls.push_back(choice_control("medium", {fx::medium_method_name(fx::MediumMethod::Froxel), fx::medium_method_name(fx::MediumMethod::Exact)},
                                  fx::medium_method_name(module_.medium_method()), "how overlapping volumes are integrated"));
    if (scene.has_terrain()) {
        all.controls.push_back(number_control("pixel_error", scene.pixel_error, {0.0, fx::kMaxCoordinate, true}, "px",
                                      "the terrain LOD's screen-space error"));
        all.controls.push_back(toggle_control("terrain", module_.terrain_drawn(), "the terrain surface drawn"));
    }
    groups.push_back(std::move(all));

    for (const std::string& name : names) {
        ControlGroup g{name, name, {}};
        g.controls.push_back(toggle_control("enabled", module_.enabled(name)));
        g.controls.push_back(choice_control("path", path_names(), fx::render_path_name(module_.path(name))));
        if (name == "fog" && scene.fog) {
            g.title = "fog (ground fog)";
            g.controls.push_back(toggle_control("absorb", scene.fog->absorb, "pcp-exact: dims what is behind"));
            g.controls.push_back(number_control("extinction_scale", scene.fog->extinction_scale, kScale, ""));
        } else if (name == "aurora" && scene.aurora) {
            g.title = "aurora";
            g.controls.push_back(number_control("extinction_scale", scene.aurora->extinction_scale, kScale, ""));
        } else {
            const auto spec = std::find_if(scene.effects.begin(), scene.effects.end(), [&](const terrain::EffectSpec& e) { return e.name == name; });
            if (spec == scene.effects.end()) continue;
            g.title = name + " (" + terrain::effect_type_name(spec->params) + ")";
            g.controls.push_back(toggle_control("absorb", spec->absorb, "pcp-exact: dims what is behind"));
            g.controls.push_back(number_control("extinction_scale", spec->extinction_scale, kScale, ""));
            if (const auto* volume = std::get_if<fx::VolumeParams>(&spec->params)) {
                g.controls.push_back(choice_control("shape", volume_shapes(*volume), fx::volume_shape_name(volume->shape), "rebuild"));
                g.controls.push_back(choice_control("density_mode", volume_densities(*volume), fx::volume_density_name(volume->density_mode), "scalars"));
            }
            std::visit([&](const auto& params) { add_parameter_controls(params, g.controls); }, spec->params);
        }
        groups.push_back(std::move(g));
    }
    return groups;
}

void SceneContent::set_control(const std::string& group, const Control& c) {
    const auto unknown = [&] { return fx::Error("no control '" + group + "." + c.name + "' in this sample"); };
    if (group == "scene") {
        if (c.name == "path") set_path(path_named(c.choice));
        else if (c.name == "fx_scale") module_.set_fx_scale(std::stod(c.choice));
        else if (c.name == "medium") {
            fx::MediumMethod method;
            if (!fx::parse_medium_method(c.choice, method)) throw fx::Error("medium: unknown method '" + c.choice + "'");
            module_.set_medium_method(method);
        } else if (c.name == "pixel_error" && module_.scene().has_terrain()) module_.renderer().set_pixel_error(c.number);
        else if (c.name == "terrain" && module_.scene().has_terrain()) module_.set_terrain_drawn(c.toggle);
        else throw unknown();
        return;
    }
    if (!module_.has_effect(group)) throw fx::Error("no effect '" + group + "' in this sample (--set GROUP.NAME=VALUE)");
    if (c.name == "enabled") module_.set_enabled(group, c.toggle);
    else if (c.name == "path") module_.set_path(group, path_named(c.choice));
    else if (c.name == "absorb") module_.set_absorb(group, c.toggle);
    else if (c.name == "extinction_scale") module_.set_extinction_scale(group, c.number);
    else {
        const terrain::Scene& scene = module_.scene();
        const auto spec = std::find_if(scene.effects.begin(), scene.effects.end(), [&](const terrain::EffectSpec& e) { return e.name == group; });
        if (spec == scene.effects.end()) throw unknown(); // fog and aurora: no parameters here
        terrain::EffectParams params = spec->params;
        bool known = std::visit([&](auto& p) { return set_parameter(p, c); }, params);
        if (auto* volume = std::get_if<fx::VolumeParams>(&params); volume && !known) {
            known = true;
            if (c.name == "shape" && c.choice == fx::volume_shape_name(fx::VolumeShape::Box)) volume->shape = fx::VolumeShape::Box;
            else if (c.name == "shape" && c.choice == fx::volume_shape_name(fx::VolumeShape::Sphere)) volume->shape = fx::VolumeShape::Sphere;
            else if (c.name == "density_mode" && c.choice == fx::volume_density_name(fx::VolumeDensity::Constant))
                volume->density_mode = fx::VolumeDensity::Constant;
            else if (c.name == "density_mode" && c.choice == fx::volume_density_name(fx::VolumeDensity::Noise))
                volume->density_mode = fx::VolumeDensity::Noise;
            else if (c.name == "density_mode" && c.choice == fx::volume_density_name(fx::VolumeDensity::Field))
                volume->density_mode = fx::VolumeDensity::Field;
            else known = c.name == "shape" && c.choice == fx::volume_shape_name(volume->shape);
        }
        if (!known) throw unknown();
        module_.set_params(group, params); // checked by the effect (the table's ranges and its own rules)
    }
}

std::optional<std::string> SceneContent::scene_file_text(const std::string& save_dir) const {
    if (original_text_.empty()) return std::nullopt;
    return terrain::updated_scene_json(original_text_, module_.scene(), save_dir);
}

std::optional<ReferenceJob> SceneContent::reference_job(const fx::Camera& camera, int width, int height) {
    // The effects alone, as `cellfx bench accuracy` renders a scene file: the terrain is not part
    // of the reference. render_to_image updates for this camera and size (dt 0), so the
    // volumes captured next are the ones this picture shows.
    terrain::SceneRenderer& r = module_.renderer();
    const bool terrain = r.terrain_drawn();
    if (terrain) r.set_terrain_drawn(false);
    ReferenceJob job;
    try {
        job.frame = r.render_to_image(camera, width, height);
    } catch (...) {
        if (terrain) r.set_terrain_drawn(true);
        throw;
    }
    if (terrain) r.set_terrain_drawn(true);
    job.background = module_.scene().background;
    auto input = std::make_shared<const terrain::SceneReferenceInput>(terrain::capture_scene_reference(r, camera));
    // Back to the frame's own size (the check's may be smaller), as update() left it: nothing
    // advances at dt 0, and the frame's render() finds its size prepared.
    if (width_ > 0 && (width_ != width || height_ != height)) r.update(0.0, camera, width_, height_);
    if (input->passes() == 0) return std::nullopt; // nothing in view to compare
    job.passes = input->passes();
    job.reference = [input, width, height](fx::ScanlineProgress& progress) {
        const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
        // One core left to the window: its frames go on while the reference renders.
        return terrain::render_scene_reference(*input, width, height, cores > 1 ? cores - 1 : 1, &progress);
    };
    std::size_t cells = input->medium_mesh.cell_count();
    for (const terrain::SceneReferenceInput::Layer& l : input->layers) cells += l.mesh.cell_count();
    char what[128];
    std::snprintf(what, sizeof what, "the effects (%zu cells, terrain not drawn) at t = %.2f s", cells, module_.time());
    job.what = what;
    return job;
}

} // namespace cellfx_samples
