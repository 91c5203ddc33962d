// A scene through cellfx::Module as a sample's content (scene_content.hpp).
#include "scene_content.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/error.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

std::string scene_path(const std::string& name) { return std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + name + ".json"; }

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

} // namespace cellfx_samples
