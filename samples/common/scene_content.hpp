// cellfx samples — a scene file's effects through the embedding API (cellfx::Module), as a
// sample's content: render paths for every effect at once, one toggle per effect (and the
// terrain), the module's frame statistics, and the tuning panel's controls — every effect's
// parameters (fx/effect_parameters.hpp: the ranges the library checks), on/off, path, absorb,
// extinction scale, the resolution, the medium, the LOD's pixel error — each set through the
// cellfx::Module call a game would make, the tuned scene saved back as a scene file, and the
// frame's effects against the scan-line reference.
#pragma once

#include <functional>
#include <string>

#include "cellfx/cellfx.hpp"
#include "sample.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

class SceneContent : public SampleContent {
public:
    // Loads the scene (init in the current context) and sets the clock to options.start_time.
    SceneContent(const terrain::Scene& scene, const SampleOptions& options);

    // Called before each update with the new scene time: moves what the sample animates
    // itself (a light on a vehicle).
    std::function<void(cellfx::Module&, double time)> animate;
    // Draws the sample's own geometry at the current time (see SampleContent::draw_props).
    std::function<void(const fx::Camera&, int, int, double time)> props;
    // The scripted camera at time t from the scene's (its camera path or camera); default: as is.
    std::function<fx::Camera(const fx::Camera& scene_camera, double time)> camera_script;

    cellfx::Module& module() { return module_; }

    int default_width() const override { return module_.scene().width; }
    int default_height() const override { return module_.scene().height; }
    glm::vec3 background() const override { return glm::vec3(module_.scene().background); }
    fx::Camera scripted_camera(double t) const override;
    double time() const override { return module_.time(); }
    void set_time(double seconds) override { module_.set_time(seconds); }
    void update(double dt, const fx::Camera& camera, int width, int height) override;
    void draw_props(const fx::Camera& camera, int width, int height) override;
    void render(unsigned framebuffer, const fx::Viewport& viewport, unsigned depth_texture) override;

    std::vector<fx::RenderPath> paths() const override;
    void set_path(fx::RenderPath path) override;
    std::string path_label() const override;
    std::vector<std::string> toggle_names() const override;
    bool toggled(std::size_t i) const override;
    void toggle(std::size_t i) override;

    std::string stats_line() const override;
    std::size_t cells_drawn() const override;
    double update_ms() const override;
    double render_ms() const override;
    double update_cpu_ms() const override;
    double render_cpu_ms() const override;
    void set_gpu_timing(bool on) override;
    void gpu_stages(std::vector<StageTime>& out) const override;

    std::vector<ControlGroup> controls() const override;
    void set_control(const std::string& group, const Control& value) override;
    std::optional<std::string> scene_file_text(const std::string& save_dir) const override;
    std::optional<ReferenceJob> reference_job(const fx::Camera& camera, int width, int height) override;

private:
    cellfx::Module module_;
    std::string original_text_; // the scene file as read (what scene_file_text updates)
    std::string path_label_ = "as in the scene";
    int width_ = 0, height_ = 0;
};

// `camera` turned about its up axis by `radians`: the view swings around the eye (pan) or the
// eye circles the target (orbit).
fx::Camera pan_camera(const fx::Camera& camera, double radians);
fx::Camera orbit_camera(const fx::Camera& camera, double radians);

// The shipped scene content/scenes/<name>.json (source tree this build came from).
std::string scene_path(const std::string& name);
// The scene a scene sample shows: --scene FILE, or the shipped content/scenes/<name>.json.
terrain::Scene sample_scene(const SampleOptions& options, const std::string& name);
// The --scene option the scene samples declare.
std::pair<std::string, std::string> scene_option();

} // namespace cellfx_samples
