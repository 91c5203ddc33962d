// The fog_valley sample: content/scenes/fog_valley.json (terrain, valley fog drawn with
// pcp-exact and absorbing), the view panning slowly across the crater.
#include <cmath>

#include "fx/error.hpp"
#include "scene_content.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

SampleInfo fog_valley_sample() {
    SampleInfo info;
    info.usage.name = "fog_valley";
    info.usage.summary = "Valley fog on Mount St. Helens over continuous-LOD terrain (content/scenes/fog_valley.json).";
    info.usage.options = {scene_option()};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> {
        auto content = std::make_unique<SceneContent>(sample_scene(options, "fog_valley"), options);
        // ±12° of pan over 40 s: the fog is static, the LOD follows the view.
        content->camera_script = [](const fx::Camera& c, double t) { return pan_camera(c, 0.21 * std::sin(2.0 * M_PI * t / 40.0)); };
        return content;
    };
    return info;
}

} // namespace cellfx_samples
