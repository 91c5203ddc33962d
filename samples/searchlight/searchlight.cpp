// The searchlight sample: content/scenes/searchlight.json (three sweeping search lights over
// hills at night) with its "patrol" light attached to a drone (drone.hpp) that the sample draws
// itself: the light follows its parent transform every frame (no mesh rebuilt), and the drone's
// body sits in the depth buffer cellfx draws against.
#include <memory>

#include "fx/search_light.hpp"
#include "sample_gl.hpp"
#include "scene_content.hpp"
#include "searchlight/drone.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

SampleInfo searchlight_sample() {
    SampleInfo info;
    info.usage.name = "searchlight";
    info.usage.summary = "Search lights at night; the patrol light rides a drone circling the hill (content/scenes/searchlight.json).";
    info.usage.options = {scene_option()};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> {
        auto content = std::make_unique<SceneContent>(sample_scene(options, "searchlight"), options);
        content->animate = [](cellfx::Module& module, double t) {
            if (module.has_effect("patrol")) module.set_parent_transform("patrol", drone_parent_transform(t));
        };
        auto boxes = std::make_shared<BoxRenderer>();
        const glm::dvec3 sun = content->module().scene().surface.sun_direction;
        content->props = [boxes, sun](const fx::Camera& camera, int w, int h, double t) {
            boxes->draw(camera, w, h, drone_body_transform(t), glm::vec3(0.45f, 0.47f, 0.5f), sun, 0.35f);
        };
        return content;
    };
    return info;
}

} // namespace cellfx_samples
