// cellfx — volumetric effects in a game's frame: the one header a game includes.
//
// Ground fog over terrain, campfires, search lights, laser cones and aurora, rendered by
// projecting convex cells (Roettger & Ertl 2003) into the game's own OpenGL 4.5 context,
// framebuffer and depth buffer. Link cellfx::cellfx (CMake); everything here is in namespace
// cellfx, with the types it uses from fx:: and terrain:: (their headers say more).
//
// STEP BY STEP
// ============
// 1. Make your OpenGL 4.5 core context current (GLFW, SDL, your engine), then start cellfx
//    with a scene file — terrain, fog, effects, camera (docs/effects.md) — or a scene in code:
//
//        cellfx::Module fx;
//        fx.init({"content/scenes/campfire.json", 1280, 720});   // shaders, LODs; no effect
//                                                                // mesh is built yet
//    or
//        terrain::Scene scene;                                   // no terrain: effects only
//        terrain::EffectSpec fire;
//        fire.name = "fire";
//        fire.params = fx::CampfireParams{};                     // every parameter has a default
//        fire.transfer_function = fx::TransferFunction::read_json("content/transfer_functions/fire.json");
//        scene.effects.push_back(fire);
//        fx.init(cellfx::Config::from_scene(scene, 1280, 720));
//
// 2. Every frame, after moving your camera, let cellfx simulate what this view needs. It skips
//    disabled effects and effects outside the view (no cells, no noise), rebuilds nothing that
//    did not change, and needs no GL:
//
//        fx::Camera camera = cellfx::camera_from_view(view_matrix, fov_y_degrees, near, far);
//        fx.update(dt, camera);
//
// 3. Draw your opaque world with the same camera (camera.projection_matrix(aspect) and
//    camera.view_matrix(), GL's default depth range) into your framebuffer, with a depth
//    *texture* attached (GL_DEPTH_COMPONENT24/32F, GL_TEXTURE_2D).
//
// 4. Let cellfx draw over it. Fog and fire stop at your geometry; the terrain (when the scene
//    draws it) is depth-tested against it. Every GL state cellfx touches is restored:
//
//        fx.render({framebuffer, {0, 0, width, height}, depth_texture});
//
//    (framebuffer 0 is the window; without a depth texture nothing of yours hides the effects.)
//
// 5. Show what it did, switch effects, change render paths, move lights:
//
//        draw_text(fx.stats().summary());        // "t 3.2 s 9.8 ms | fire: simulated pcp-exact 2172 cells, noise 1764 | ..."
//        fx.set_enabled("fire", !fx.enabled("fire"));
//        fx.set_path("fire", fx::RenderPath::Mip);
//        fx.effect<fx::SearchLight>("patrol")->set_parent_transform(truck_world_matrix);
//
// 6. fx.shutdown() — or let the destructor run — while the context is still current.
//
// Threads: one thread, the one whose GL context cellfx was started in. Errors: fx::Error with
// a message naming the file, key or effect; cellfx never aborts.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "fx/camera.hpp"
#include "fx/campfire.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/error.hpp"
#include "fx/laser_cone.hpp"
#include "fx/search_light.hpp"
#include "fx/transfer_function.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"

namespace cellfx {

using terrain::EffectFrameStats;
using terrain::EffectStatus;
using terrain::FrameStats;
using terrain::Scene;
using terrain::Target; // {framebuffer, viewport, depth_texture}: where render() draws

struct Config {
    std::string scene_file;            // a scene file (docs/effects.md), or empty and:
    std::optional<Scene> scene;        // a scene built in code
    int width = 0, height = 0;         // the first frames' viewport size (0: the scene's render size)
    std::optional<bool> draw_terrain;  // override the scene's "terrain.draw"

    Config() = default;
    Config(std::string file, int w = 0, int h = 0) : scene_file(std::move(file)), width(w), height(h) {}
    static Config from_scene(Scene s, int w = 0, int h = 0) {
        Config c;
        c.scene = std::move(s);
        c.width = w, c.height = h;
        return c;
    }
};

// A camera from a game's view matrix (world → eye, right-handed, looking down −z as in
// OpenGL) and its perspective projection's parameters. Throws fx::Error for a matrix that is not
// a rigid motion or parameters out of range (fov in (0, 179), 0 < near < far).
fx::Camera camera_from_view(const glm::dmat4& view, double fov_y_degrees, double near_distance, double far_distance);

class Module {
public:
    Module();
    ~Module(); // shutdown(): the GL context that init() used must be current
    Module(Module&&) noexcept;
    Module& operator=(Module&&) noexcept;
    Module(const Module&) = delete;
    Module& operator=(const Module&) = delete;

    // Loads the scene and builds its GL objects in the current context (an OpenGL 4.5 core
    // context must be current: checked). Calling it again replaces the scene. Throws fx::Error
    // (no or too old a context, a scene file error naming the file and key, a GL failure); the
    // module is then not initialized.
    void init(const Config& config);
    void shutdown(); // releases every GL object cellfx made; the context must be current
    bool initialized() const;

    // Advances the clock by dt seconds and simulates what `camera` sees (no GL calls). The
    // viewport size is the last render()'s (or init's): a render of another size re-simulates
    // for it first. Throws fx::Error for a non-finite dt or camera, or before init().
    void update(double dt, const fx::Camera& camera);
    // Draws the updated frame over the game's (see the header comment); restores GL state.
    void render(const Target& target);
    const FrameStats& stats() const;

    // The scene's clock (seconds since init unless set) and its camera at that time (the camera
    // path when the scene has one, else its camera): for demos and headless runs.
    double time() const;
    void set_time(double seconds);
    fx::Camera scene_camera() const;
    const Scene& scene() const;

    // Effects by name ("fog", "aurora", the names in "effects"). Unknown names throw fx::Error.
    std::vector<std::string> effect_names() const;
    void set_enabled(const std::string& name, bool enabled);
    bool enabled(const std::string& name) const;
    void set_path(const std::string& name, fx::RenderPath path);
    fx::RenderPath path(const std::string& name) const;
    // The live effect, or nullptr if it has another type: effect<fx::SearchLight>("patrol").
    template <class E>
    E* effect(const std::string& name) {
        return dynamic_cast<E*>(&renderer().effect(name));
    }
    void set_terrain_drawn(bool drawn); // throws for a scene without terrain
    bool terrain_drawn() const;

    // Everything else (per-effect transfer functions, GPU timing, LOD error bound).
    terrain::SceneRenderer& renderer();

private:
    struct State;
    std::unique_ptr<State> state_;
    State& ready() const; // throws before init()
};

} // namespace cellfx
