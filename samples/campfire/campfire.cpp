// The campfire sample: content/scenes/campfire.json (animated 4-D noise on a hexahedral grid,
// fire transfer function, emission only, stopped by the ground), the camera on the scene's
// path around the fire.
#include "scene_content.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

SampleInfo campfire_sample() {
    SampleInfo info;
    info.usage.name = "campfire";
    info.usage.summary = "A campfire of animated 4-D noise on rough ground, the camera circling it (content/scenes/campfire.json).";
    info.usage.options = {scene_option()};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> {
        return std::make_unique<SceneContent>(sample_scene(options, "campfire"), options);
    };
    return info;
}

} // namespace cellfx_samples
