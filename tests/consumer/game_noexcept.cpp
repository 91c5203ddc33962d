// The consumer game built with -fno-exceptions -fno-rtti: cellfx's try_ forms and Status, the
// effect<E>() type tag, effects added, tuned and removed at run time, a bad reload refused while
// the scene keeps running. Exit 0 when all holds.
#include "game_support.hpp"

namespace {

bool frame_ok(cellfx::Module& fx, const game::Frame& frame, const cellfx::fx::Camera& camera) {
    frame.clear();
    const cellfx::Status updated = fx.try_update(1.0 / 60.0, camera);
    const cellfx::Status rendered = fx.try_render({frame.framebuffer, {0, 0, game::kWidth, game::kHeight}, frame.depth});
    if (!updated || !rendered) std::fprintf(stderr, "%s%s\n", updated.message().c_str(), rendered.message().c_str());
    return updated && rendered;
}

} // namespace

int main() {
    const game::Context context; // the game's own (cellfx installs none)
    if (!context.ok()) return game::fail("no GL context");
    game::Frame frame;
    if (!frame.complete()) return game::fail("the game's framebuffer is incomplete");
    cellfx::Module fx;
    if (cellfx::Status s = fx.try_init(cellfx::Config::from_scene(game::campfire_scene(), game::kWidth, game::kHeight)); !s)
        return game::fail(s.message().c_str());
    cellfx::fx::Camera camera;
    if (cellfx::Status s = cellfx::try_camera_from_view(game::view_matrix(), 45.0, 0.05, 100.0, camera); !s)
        return game::fail(s.message().c_str());
    if (cellfx::try_camera_from_view(game::view_matrix(), 45.0, 1.0, 0.5, camera))
        return game::fail("try_camera_from_view accepted near > far");
    const game::GameState state;
    if (!frame_ok(fx, frame, camera)) return game::fail("a frame failed");
    const int before = frame.fire_pixels();

    // The type tag instead of dynamic_cast.
    if (fx.effect<cellfx::fx::Campfire>("fire") == nullptr || fx.effect<cellfx::fx::SearchLight>("fire") != nullptr)
        return game::fail("effect<E>() did not tell a campfire from a search light");
    // A bad reload is refused and names the file; the fire keeps burning.
    const cellfx::Status bad = fx.try_reload("no_such_scene.json");
    if (bad || bad.message().find("no_such_scene.json") == std::string::npos) return game::fail("a bad reload was not refused");
    // Effects at run time: a second fire, brighter; the first one's extinction changed, then removed.
    cellfx::EffectSpec second = fx.scene().effects[0];
    second.name = "second";
    cellfx::fx::CampfireParams p;
    p.position = {0.6, 0.3, 0.0};
    second.params = p;
    if (cellfx::Status s = fx.try_add_effect(second); !s) return game::fail(s.message().c_str());
    if (fx.try_add_effect(second)) return game::fail("an effect was added twice");
    if (cellfx::Status s = fx.try_set_extinction_scale("fire", 0.4); !s) return game::fail(s.message().c_str());
    if (fx.try_set_extinction_scale("fire", -1.0)) return game::fail("a negative extinction scale was taken");
    if (fx.try_set_enabled("smoke", false)) return game::fail("an unknown effect was switched");
    if (!frame_ok(fx, frame, camera)) return game::fail("a frame failed");
    const int two = frame.fire_pixels();
    if (cellfx::Status s = fx.try_remove_effect("second"); !s) return game::fail(s.message().c_str());
    if (!frame_ok(fx, frame, camera)) return game::fail("a frame failed");
    if (!state.intact()) return game::fail("cellfx changed the game's GL state");
    if (before < 100 || two <= before) return game::fail("the fires are not in the frame");
    std::printf("cellfx consumer game without exceptions or RTTI: %d fire pixels, %d with a second fire; refused: %s\n",
                before, two, bad.message().c_str());
    return 0;
}
