// The night_valley sample: content/scenes/fog_valley_night.json — valley fog at night on
// St. Helens' crater floor, a campfire inside it lighting the fog and the smoke that drifts over
// it, a search light sweeping through; fog, fire, smoke and beam integrated as one medium where
// they overlap. The camera flies the scene's path round the fire.
#include "scene_content.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

SampleInfo night_valley_sample() {
    SampleInfo info;
    info.usage.name = "night_valley";
    info.usage.summary = "Valley fog at night: a campfire in the fog, smoke drifting over it, a search light sweeping "
                         "through, one medium (content/scenes/fog_valley_night.json).";
    info.usage.options = {scene_option()};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> {
        return std::make_unique<SceneContent>(sample_scene(options, "fog_valley_night"), options);
    };
    return info;
}

} // namespace cellfx_samples
