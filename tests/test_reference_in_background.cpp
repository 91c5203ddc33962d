// The scan-line reference of a scene's frame rendered away from the renderer (a tool's
// background thread): the captured volumes are copies (the renderer may change and draw on while
// they render), the frame they give is the reference of the frame captured, and a
// fx::ScanlineProgress counts every line and stops the render when cancelled.
#include <catch2/catch.hpp>

#include <thread>
#include <variant>

#include "fx/scanline_renderer.hpp"
#include "gl_fixture.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_reference.hpp"
#include "terrain/scene_renderer.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

constexpr int kW = 96, kH = 72;

fx::Camera scene_camera(const terrain::Scene& s, double t) { return s.camera_path ? s.camera_path->at(t, s.camera) : s.camera; }

} // namespace

TEST_CASE("A captured frame's reference is the renderer's, and stays so while the renderer changes", "[gl][scene][reference]") {
    fx_test::gl_context();
    terrain::SceneRenderer r(terrain::load_scene(fx_test::source_path("content/scenes/fog_valley_night.json")));
    r.set_terrain_drawn(false);
    r.set_time(1.0);
    const fx::Camera camera = scene_camera(r.scene(), 1.0);
    r.update(0.0, camera, kW, kH);
    const terrain::SceneReferenceInput input = terrain::capture_scene_reference(r, camera);
    CHECK(input.passes() >= 1);
    const fx::Image direct = terrain::render_scene_reference(r, camera, kW, kH);

    // The renderer moves on: a bigger fire, later, another path for the beam.
    fx::CampfireParams fire = std::get<fx::CampfireParams>(r.scene().effects[0].params);
    fire.base_radius *= 1.6;
    r.set_params("fire", fire);
    r.set_path("beam", fx::RenderPath::Mip);
    r.update(0.5, camera, kW, kH);
    const fx::Image moved = terrain::render_scene_reference(r, camera, kW, kH);

    // On another thread, from the copy: the first frame's reference, to the bit.
    fx::Image from_copy;
    std::thread worker([&] { from_copy = terrain::render_scene_reference(input, kW, kH, 1); });
    worker.join();
    fx_test::check_image("reference_from_copy", from_copy, direct, verify::same_picture(0.0, "the same volumes, the same renderer: to the bit"));
    const verify::Difference changed = verify::measure(moved, direct);
    INFO("the renderer's own reference after the change differs by " << changed.worst.delta);
    CHECK(changed.worst.delta > 0.01);
}

TEST_CASE("Scan-line progress counts every line of every pass, and a cancel stops the render", "[gl][scene][reference]") {
    fx_test::gl_context();
    terrain::SceneRenderer r(terrain::load_scene(fx_test::source_path("content/scenes/fog_valley_night.json")));
    r.set_terrain_drawn(false);
    const fx::Camera camera = scene_camera(r.scene(), 0.0);
    r.set_path("beam", fx::RenderPath::Pcp); // one pass of its own besides the medium
    r.update(0.0, camera, kW, kH);
    const terrain::SceneReferenceInput input = terrain::capture_scene_reference(r, camera);
    REQUIRE(input.passes() == 2);

    fx::ScanlineProgress progress;
    terrain::render_scene_reference(input, kW, kH, 2, &progress);
    CHECK(progress.lines_done == std::uint64_t(kH) * 2);

    fx::ScanlineProgress cancelled;
    cancelled.cancel = true;
    const fx::Image partial = terrain::render_scene_reference(input, kW, kH, 2, &cancelled);
    // Only the lines with nothing to draw count; none was drawn.
    CHECK(cancelled.lines_done < std::uint64_t(kH) * 2);
    for (const glm::vec4& p : partial.pixels) REQUIRE(p == glm::vec4(0.0f));
}
