// The embedding API (cellfx/cellfx.hpp): lifecycle, the game's world frame, reloads that keep
// the game's choices, and the non-throwing forms, around terrain::SceneRenderer, which does the
// work.
#include "cellfx/cellfx.hpp"

#include <cmath>
#include <exception>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace cellfx {

namespace {

// Runs f; its exception, if any, as a Status. Never throws (an allocation failure while copying
// the message gives a failed Status without one).
template <class F>
Status attempt(F&& f) noexcept {
    try {
        f();
        return Status();
    } catch (const std::exception& e) {
        try {
            return Status::error(e.what());
        } catch (...) {
            return Status::error(std::string());
        }
    } catch (...) {
        return Status::error(std::string());
    }
}

// Scene coordinates (z up) from the game's world: the identity, or (x, y, z) → (x, −z, y).
glm::dmat4 scene_from_world(WorldUp up) {
    if (up == WorldUp::Z) return glm::dmat4(1.0);
    glm::dmat4 m(1.0);
    m[1] = glm::dvec4(0.0, 0.0, 1.0, 0.0);  // world y → scene z
    m[2] = glm::dvec4(0.0, -1.0, 0.0, 0.0); // world z → scene −y
    return m;
}

fx::Camera transformed(const fx::Camera& c, const glm::dmat4& m) {
    fx::Camera t = c;
    t.eye = glm::dvec3(m * glm::dvec4(c.eye, 1.0));
    t.target = glm::dvec3(m * glm::dvec4(c.target, 1.0));
    t.up = glm::dvec3(m * glm::dvec4(c.up, 0.0));
    return t;
}

std::string gl_version_problem() {
    const int version = epoxy_gl_version();
    if (version >= 45) return {};
    return version == 0 ? "no OpenGL context is current (make the game's context current first)"
                        : "the current context is OpenGL " + std::to_string(version / 10) + "." +
                              std::to_string(version % 10) + "; cellfx needs 4.5 core";
}

} // namespace

fx::Camera camera_from_view(const glm::dmat4& view, double fov_y_degrees, double near_distance, double far_distance) {
    if (!(fov_y_degrees > 0.0 && fov_y_degrees < 179.0)) throw fx::Error("camera_from_view: fov must be in (0, 179) degrees");
    if (!(near_distance > 0.0) || !(far_distance > near_distance) || !std::isfinite(far_distance))
        throw fx::Error("camera_from_view: need 0 < near < far, both finite");
    const glm::dmat4 world_from_eye = fx::rigid_part(glm::inverse(view), "camera_from_view: the view matrix");
    fx::Camera cam;
    cam.eye = glm::dvec3(world_from_eye[3]);
    cam.target = cam.eye - glm::dvec3(world_from_eye[2]); // the eye looks down its −z
    cam.up = glm::dvec3(world_from_eye[1]);
    cam.fov_y_degrees = fov_y_degrees;
    cam.near_distance = near_distance;
    cam.far_distance = far_distance;
    return cam;
}

Status try_camera_from_view(const glm::dmat4& view, double fov_y_degrees, double near_distance, double far_distance,
                            fx::Camera& camera) noexcept {
    return attempt([&] { camera = camera_from_view(view, fov_y_degrees, near_distance, far_distance); });
}

struct Module::State {
    // The game's choices, kept when the scene is reloaded.
    struct Choice {
        std::string name;
        std::optional<fx::RenderPath> path;
        std::optional<bool> enabled;
    };

    terrain::SceneRenderer renderer;
    int width, height;
    fx::Camera camera; // scene coordinates
    bool updated = false;
    glm::dmat4 scene_from_world{1.0}, world_from_scene{1.0};
    std::optional<bool> draw_terrain; // Config's override of the scene file
    std::optional<bool> terrain_choice;
    std::optional<double> fx_scale;          // Config's or set_fx_scale's, kept across reloads
    std::optional<fx::MediumMethod> medium;  // the same
    std::vector<Choice> choices;

    State(const Scene& scene, int w, int h) : renderer(scene), width(w), height(h) {}

    Choice& choice(const std::string& name) {
        for (Choice& c : choices)
            if (c.name == name) return c;
        choices.push_back({name, std::nullopt, std::nullopt});
        return choices.back();
    }
};

Module::Module() = default;
Module::~Module() = default;
Module::Module(Module&&) noexcept = default;
Module& Module::operator=(Module&&) noexcept = default;

void Module::init(const Config& config) {
    if (const std::string problem = gl_version_problem(); !problem.empty()) throw fx::Error("cellfx init: " + problem);
    Scene scene;
    if (!config.scene_file.empty()) scene = terrain::load_scene(config.scene_file);
    else if (config.scene) scene = *config.scene;
    else throw fx::Error("cellfx init: give a scene file or a scene");
    if (config.draw_terrain) scene.draw_terrain = *config.draw_terrain;
    if (config.fx_scale && !terrain::valid_fx_scale(*config.fx_scale))
        throw fx::Error("cellfx init: Config::fx_scale " + std::to_string(*config.fx_scale) + ": must be 1, 0.5 or 0.25");
    if (config.fx_scale) scene.fx_scale = *config.fx_scale;
    if (config.medium) scene.medium = *config.medium;
    if ((config.width > 0) != (config.height > 0) || config.width < 0 || config.height < 0)
        throw fx::Error("cellfx init: give both width and height (or neither)");
    const int w = config.width > 0 ? config.width : scene.width, h = config.height > 0 ? config.height : scene.height;
    auto state = std::make_unique<State>(scene, w, h);
    state->scene_from_world = scene_from_world(config.world_up);
    state->world_from_scene = glm::inverse(state->scene_from_world);
    state->draw_terrain = config.draw_terrain;
    state->fx_scale = config.fx_scale;
    state->medium = config.medium;
    state->renderer.set_parallel_for(config.parallel_for);
    state_ = std::move(state);
}

void Module::shutdown() noexcept { state_.reset(); }
bool Module::initialized() const noexcept { return static_cast<bool>(state_); }

Module::State& Module::ready() const {
    if (!state_) throw fx::Error("cellfx: call init() first");
    return *state_;
}

void Module::update(double dt, const fx::Camera& camera) {
    State& s = ready();
    const fx::Camera scene_camera = transformed(camera, s.scene_from_world);
    s.renderer.update(dt, scene_camera, s.width, s.height);
    s.camera = scene_camera;
    s.updated = true;
}

void Module::render(const Target& target) {
    State& s = ready();
    if (!s.updated) throw fx::Error("cellfx: call update() before render()");
    if (target.viewport.width <= 0 || target.viewport.height <= 0) throw fx::Error("cellfx render: empty viewport");
    if (target.viewport.width != s.width || target.viewport.height != s.height) {
        // The window was resized: simulate this frame again for the new size (no time passes).
        s.width = target.viewport.width;
        s.height = target.viewport.height;
        s.renderer.update(0.0, s.camera, s.width, s.height);
    }
    s.renderer.render(target);
}

const FrameStats& Module::stats() const noexcept {
    static const FrameStats none;
    return state_ ? state_->renderer.stats() : none;
}
double Module::time() const noexcept { return state_ ? state_->renderer.time() : 0.0; }
void Module::set_time(double seconds) { ready().renderer.set_time(seconds); }
fx::Camera Module::scene_camera() const {
    const State& s = ready();
    const Scene& scene = s.renderer.scene();
    const fx::Camera c = scene.camera_path ? scene.camera_path->at(s.renderer.time(), scene.camera) : scene.camera;
    return transformed(c, s.world_from_scene);
}
const Scene& Module::scene() const noexcept {
    static const Scene none;
    return state_ ? state_->renderer.scene() : none;
}

void Module::reload(const std::string& scene_file) { reload(terrain::load_scene(scene_file)); }

void Module::reload(const Scene& new_scene) {
    State& s = ready();
    Scene scene = new_scene;
    if (s.draw_terrain) scene.draw_terrain = *s.draw_terrain;
    if (s.fx_scale) scene.fx_scale = *s.fx_scale;
    if (s.medium) scene.medium = *s.medium;
    terrain::SceneRenderer fresh(scene);
    terrain::SceneRenderer& old = s.renderer;
    fresh.set_time(old.time());
    fresh.set_timing(old.timing());
    for (const std::string& name : fresh.effect_names()) {
        if (const fx::Effect* before = old.find_effect(name))
            fresh.effect(name).set_parent_transform(before->parent_transform());
    }
    for (const State::Choice& c : s.choices) {
        if (!fresh.has_effect(c.name)) continue;
        if (c.path) fresh.set_path(c.name, *c.path);
        if (c.enabled) fresh.set_enabled(c.name, *c.enabled);
    }
    if (s.terrain_choice && scene.has_terrain()) fresh.set_terrain_drawn(*s.terrain_choice);
    // The frame update() prepared is prepared again, so that render() may follow directly.
    if (s.updated) fresh.update(0.0, s.camera, s.width, s.height);
    // Everything is built: swap (the old scene's GL objects go now).
    s.renderer = std::move(fresh);
}

std::vector<std::string> Module::effect_names() const { return ready().renderer.effect_names(); }
bool Module::has_effect(const std::string& name) const noexcept { return state_ && state_->renderer.has_effect(name); }
void Module::add_effect(const EffectSpec& spec) { ready().renderer.add_effect(spec); }
void Module::remove_effect(const std::string& name) { ready().renderer.remove_effect(name); }
void Module::set_enabled(const std::string& name, bool enabled) {
    State& s = ready();
    s.renderer.set_enabled(name, enabled);
    s.choice(name).enabled = enabled;
}
bool Module::enabled(const std::string& name) const { return ready().renderer.enabled(name); }
void Module::set_path(const std::string& name, fx::RenderPath path) {
    State& s = ready();
    s.renderer.set_path(name, path);
    s.choice(name).path = path;
}
fx::RenderPath Module::path(const std::string& name) const { return ready().renderer.path(name); }
void Module::set_params(const std::string& name, const EffectParams& params) { ready().renderer.set_params(name, params); }
void Module::set_transfer_function(const std::string& name, const fx::TransferFunction& tf) {
    ready().renderer.set_transfer_function(name, tf);
}
void Module::set_extinction_scale(const std::string& name, double scale) { ready().renderer.set_extinction_scale(name, scale); }
void Module::set_absorb(const std::string& name, bool absorb) { ready().renderer.set_absorb(name, absorb); }
void Module::set_parent_transform(const std::string& name, const glm::dmat4& world_from_object) {
    State& s = ready();
    // The object's own frame has the game's up axis too: the effect's z follows the object's up.
    s.renderer.effect(name).set_parent_transform(s.scene_from_world * world_from_object * s.world_from_scene);
}
fx::Effect* Module::find_effect(const std::string& name) noexcept {
    return state_ ? state_->renderer.find_effect(name) : nullptr;
}
void Module::set_terrain_drawn(bool drawn) {
    State& s = ready();
    s.renderer.set_terrain_drawn(drawn);
    s.terrain_choice = drawn;
}
bool Module::terrain_drawn() const noexcept { return state_ && state_->renderer.terrain_drawn(); }
void Module::set_fx_scale(double scale) {
    State& s = ready();
    s.renderer.set_fx_scale(scale);
    s.fx_scale = scale;
}
double Module::fx_scale() const noexcept { return state_ ? state_->renderer.fx_scale() : 1.0; }
void Module::set_medium_method(fx::MediumMethod method) {
    State& s = ready();
    s.renderer.set_medium_method(method);
    s.medium = method;
}
fx::MediumMethod Module::medium_method() const noexcept {
    return state_ ? state_->renderer.medium_method() : fx::MediumMethod::Froxel;
}
terrain::SceneRenderer& Module::renderer() { return ready().renderer; }

// The non-throwing forms.
Status Module::try_init(const Config& config) noexcept { return attempt([&] { init(config); }); }
Status Module::try_update(double dt, const fx::Camera& camera) noexcept { return attempt([&] { update(dt, camera); }); }
Status Module::try_render(const Target& target) noexcept { return attempt([&] { render(target); }); }
Status Module::try_set_time(double seconds) noexcept { return attempt([&] { set_time(seconds); }); }
Status Module::try_reload(const std::string& scene_file) noexcept { return attempt([&] { reload(scene_file); }); }
Status Module::try_reload(const Scene& scene) noexcept { return attempt([&] { reload(scene); }); }
Status Module::try_add_effect(const EffectSpec& spec) noexcept { return attempt([&] { add_effect(spec); }); }
Status Module::try_remove_effect(const std::string& name) noexcept { return attempt([&] { remove_effect(name); }); }
Status Module::try_set_enabled(const std::string& name, bool enabled) noexcept {
    return attempt([&] { set_enabled(name, enabled); });
}
Status Module::try_set_path(const std::string& name, fx::RenderPath path) noexcept {
    return attempt([&] { set_path(name, path); });
}
Status Module::try_set_params(const std::string& name, const EffectParams& params) noexcept {
    return attempt([&] { set_params(name, params); });
}
Status Module::try_set_transfer_function(const std::string& name, const fx::TransferFunction& tf) noexcept {
    return attempt([&] { set_transfer_function(name, tf); });
}
Status Module::try_set_extinction_scale(const std::string& name, double scale) noexcept {
    return attempt([&] { set_extinction_scale(name, scale); });
}
Status Module::try_set_absorb(const std::string& name, bool absorb) noexcept {
    return attempt([&] { set_absorb(name, absorb); });
}
Status Module::try_set_parent_transform(const std::string& name, const glm::dmat4& world_from_object) noexcept {
    return attempt([&] { set_parent_transform(name, world_from_object); });
}
Status Module::try_set_terrain_drawn(bool drawn) noexcept { return attempt([&] { set_terrain_drawn(drawn); }); }
Status Module::try_set_fx_scale(double scale) noexcept { return attempt([&] { set_fx_scale(scale); }); }

} // namespace cellfx
