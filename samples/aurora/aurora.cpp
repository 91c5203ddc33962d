// The aurora sample: content/scenes/aurora.json (curtains of prisms under a ceiling over the
// terrain, MIP), the view sweeping slowly along the sky.
#include <cmath>

#include "scene_content.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

SampleInfo aurora_sample() {
    SampleInfo info;
    info.usage.name = "aurora";
    info.usage.summary = "Aurora curtains over the mountains, drawn with MIP (content/scenes/aurora.json).";
    info.usage.options = {scene_option()};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> {
        auto content = std::make_unique<SceneContent>(sample_scene(options, "aurora"), options);
        // ±17° of pan over 60 s along the curtains.
        content->camera_script = [](const fx::Camera& c, double t) { return pan_camera(c, 0.3 * std::sin(2.0 * M_PI * t / 60.0)); };
        return content;
    };
    return info;
}

} // namespace cellfx_samples
