// The embedding API (cellfx/cellfx.hpp): lifecycle and viewport bookkeeping around
// terrain::SceneRenderer, which does the work.
#include "cellfx/cellfx.hpp"

#include <cmath>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace cellfx {

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

struct Module::State {
    terrain::SceneRenderer renderer;
    int width, height;
    fx::Camera camera;
    bool updated = false;
    State(const Scene& scene, int w, int h) : renderer(scene), width(w), height(h) {}
};

Module::Module() = default;
Module::~Module() = default;
Module::Module(Module&&) noexcept = default;
Module& Module::operator=(Module&&) noexcept = default;

void Module::init(const Config& config) {
    state_.reset();
    const int version = epoxy_gl_version();
    if (version < 45)
        throw fx::Error(version == 0 ? "cellfx init: no OpenGL context is current (make the game's context current first)"
                                     : "cellfx init: the current context is OpenGL " + std::to_string(version / 10) + "." +
                                           std::to_string(version % 10) + "; cellfx needs 4.5 core");
    Scene scene;
    if (!config.scene_file.empty()) scene = terrain::load_scene(config.scene_file);
    else if (config.scene) scene = *config.scene;
    else throw fx::Error("cellfx init: give a scene file or a scene");
    if (config.draw_terrain) scene.draw_terrain = *config.draw_terrain;
    if ((config.width > 0) != (config.height > 0) || config.width < 0 || config.height < 0)
        throw fx::Error("cellfx init: give both width and height (or neither)");
    const int w = config.width > 0 ? config.width : scene.width, h = config.height > 0 ? config.height : scene.height;
    state_ = std::make_unique<State>(scene, w, h);
}

void Module::shutdown() { state_.reset(); }
bool Module::initialized() const { return static_cast<bool>(state_); }

Module::State& Module::ready() const {
    if (!state_) throw fx::Error("cellfx: call init() first");
    return *state_;
}

void Module::update(double dt, const fx::Camera& camera) {
    State& s = ready();
    s.renderer.update(dt, camera, s.width, s.height);
    s.camera = camera;
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

const FrameStats& Module::stats() const { return ready().renderer.stats(); }
double Module::time() const { return ready().renderer.time(); }
void Module::set_time(double seconds) { ready().renderer.set_time(seconds); }
fx::Camera Module::scene_camera() const {
    const State& s = ready();
    const Scene& scene = s.renderer.scene();
    return scene.camera_path ? scene.camera_path->at(s.renderer.time(), scene.camera) : scene.camera;
}
const Scene& Module::scene() const { return ready().renderer.scene(); }
std::vector<std::string> Module::effect_names() const { return ready().renderer.effect_names(); }
void Module::set_enabled(const std::string& name, bool enabled) { ready().renderer.set_enabled(name, enabled); }
bool Module::enabled(const std::string& name) const { return ready().renderer.enabled(name); }
void Module::set_path(const std::string& name, fx::RenderPath path) { ready().renderer.set_path(name, path); }
fx::RenderPath Module::path(const std::string& name) const { return ready().renderer.path(name); }
void Module::set_terrain_drawn(bool drawn) { ready().renderer.set_terrain_drawn(drawn); }
bool Module::terrain_drawn() const { return ready().renderer.terrain_drawn(); }
terrain::SceneRenderer& Module::renderer() { return ready().renderer; }

} // namespace cellfx
