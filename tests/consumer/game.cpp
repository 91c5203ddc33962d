// A game that takes cellfx from its build (subproject, FetchContent, installed package or
// pkg-config) and runs headless: a campfire built in code drawn over the game's own frame for a
// few frames, the fire visible and the game's GL state as it was. Exit 0 when all holds.
#include "game_support.hpp"

int main() {
    try {
        const game::Context context; // the game's own (cellfx installs none)
        if (!context.ok()) return game::fail("no GL context");
        game::Frame frame;
        if (!frame.complete()) return game::fail("the game's framebuffer is incomplete");
        // The game's own terrain::Scene and fx::Error (game_support.hpp) beside cellfx's names.
        const terrain::Scene world;
        const fx::Error none;
        if (world.tiles != 64 || none.what != nullptr) return game::fail("the game's own terrain and fx");
        cellfx::Module fx;
        fx.init(cellfx::Config::from_scene(game::campfire_scene(), game::kWidth, game::kHeight));
        const cellfx::fx::Camera camera = cellfx::camera_from_view(game::view_matrix(), 45.0, 0.05, 100.0);
        const game::GameState state;
        for (int i = 0; i < 3; ++i) {
            frame.clear();
            fx.update(1.0 / 60.0, camera);
            fx.render({frame.framebuffer, {0, 0, game::kWidth, game::kHeight}, frame.depth});
        }
        if (!state.intact()) return game::fail("cellfx changed the game's GL state");
        if (fx.effect<cellfx::fx::Campfire>("fire") == nullptr) return game::fail("effect<cellfx::fx::Campfire>(\"fire\") found nothing");
        const int lit = frame.fire_pixels();
        if (lit < 100) return game::fail("the fire is not in the frame");
        if (glGetError() != GL_NO_ERROR) return game::fail("a GL error");
        std::printf("cellfx consumer game: %d fire pixels of %d; %s\n", lit, game::kWidth * game::kHeight,
                    fx.stats().summary().c_str());
        return 0;
    } catch (const std::exception& e) {
        return game::fail(e.what());
    }
}
