// cellfx — volumetric effects in a game's frame: the one header a game includes.
//
// Ground fog over terrain, campfires, search lights, laser cones and aurora, rendered by
// projecting convex cells (Roettger & Ertl 2003) into the game's own OpenGL 4.5 context,
// framebuffer and depth buffer. Link cellfx::cellfx (CMake: add_subdirectory, FetchContent or
// find_package(cellfx); or pkg-config cellfx); everything here is in namespace cellfx, with the
// types it uses from cellfx::fx and cellfx::terrain (their headers say more).
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
//        cellfx::Scene scene;                                    // no terrain: effects only
//        cellfx::EffectSpec fire;
//        fire.name = "fire";
//        fire.params = fx::CampfireParams{};                     // every parameter has a default
//        fire.transfer_function = fx::TransferFunction::read_json("content/transfer_functions/fire.json");
//        fire.extinction_scale = 0.2;
//        scene.effects.push_back(fire);
//        cellfx::Config config = cellfx::Config::from_scene(scene, 1280, 720);
//        config.world_up = cellfx::WorldUp::Y;                   // a y-up engine (default: z up)
//        fx.init(config);
//
// 2. Every frame, after moving your camera, let cellfx simulate what this view needs. It skips
//    disabled effects and effects outside the view (no cells, no noise), rebuilds nothing that
//    did not change, allocates nothing in a steady frame, and needs no GL:
//
//        fx::Camera camera = cellfx::camera_from_view(view_matrix, fov_y_degrees, near, far);
//        fx.update(dt, camera);
//
// 3. Draw your opaque world with the same camera into your framebuffer, with a depth *texture*
//    attached (GL_TEXTURE_2D or GL_TEXTURE_2D_MULTISAMPLE, any depth format), in your depth
//    convention: standard, or reversed-Z (cellfx::DepthConvention says which).
//
// 4. Let cellfx draw over it. Fog and fire stop at your geometry; the terrain (when the scene
//    draws it) is depth-tested against it. Every GL state cellfx touches is restored, once:
//
//        fx.render({framebuffer, {0, 0, width, height}, depth_texture});
//        // reversed-Z: target.depth.reversed = true (and its planes if not the camera's)
//
//    (framebuffer 0 is the window; without a depth texture nothing of yours hides the effects.)
//
// 5. Show what it did; add, remove, switch and tune effects; move lights; reload the scene:
//
//        draw_text(fx.stats().summary());        // "t 3.2 s 9.8 ms | fire: simulated pcp-exact 2172 cells, noise 1764 | ..."
//        fx.set_enabled("fire", !fx.enabled("fire"));
//        fx.set_path("fire", fx::RenderPath::Mip);
//        fx.set_extinction_scale("fire", 0.3);
//        fx.set_parent_transform("patrol", truck_world_matrix);
//        fx.effect<fx::SearchLight>("patrol")->set_pose(lens, direction);
//        if (cellfx::Status s = fx.try_reload("content/scenes/campfire.json"); !s) log(s.message());
//
// 6. fx.shutdown() — or let the destructor run — while the context is still current.
//
// Threads: one thread, the one whose GL context cellfx was started in (Config::parallel_for lends
// cellfx the game's job system for the CPU work it can split). Errors: every call that can fail
// has two forms — one that throws fx::Error with a message naming the file, key or effect, and a
// try_ form that returns a cellfx::Status with the same message and never throws (games built
// with -fno-exceptions use those; nothing here needs RTTI). A failed call changes nothing;
// cellfx never aborts.
#pragma once

#include <cstring>
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
#include "fx/medium.hpp"
#include "fx/parallel_for.hpp"
#include "fx/search_light.hpp"
#include "fx/transfer_function.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"

namespace cellfx {

using terrain::DepthConvention; // how the game's depth texture was written (standard, reversed-Z)
using terrain::EffectFrameStats;
using terrain::EffectParams; // fx::CampfireParams, fx::SearchLightParams or fx::LaserConeParams
using terrain::EffectSpec;   // one effect: name, parameters, colour, extinction scale, path
using terrain::EffectStatus;
using terrain::FrameStats;
using terrain::Scene;
using terrain::Target; // {framebuffer, viewport, depth_texture, depth}: where render() draws

// The outcome of a call that can fail: ok, or the error the throwing form would have thrown.
class Status {
public:
    Status() = default; // ok
    static Status error(std::string message) {
        Status s;
        s.failed_ = true;
        s.message_ = std::move(message);
        return s;
    }
    bool ok() const noexcept { return !failed_; }
    explicit operator bool() const noexcept { return !failed_; }
    const std::string& message() const noexcept { return message_; } // "" when ok

private:
    bool failed_ = false;
    std::string message_;
};

// The game's up axis. cellfx's scenes (files, terrain, effect parameters) are z-up; a y-up game
// gives its cameras and parent transforms in its own frame and sees fire rise along its +y:
// world (x, y, z) is scene (x, −z, y).
enum class WorldUp { Z, Y };

struct Config {
    std::string scene_file;            // a scene file (docs/effects.md), or empty and:
    std::optional<Scene> scene;        // a scene built in code
    int width = 0, height = 0;         // the first frames' viewport size (0: the scene's render size)
    std::optional<bool> draw_terrain;  // override the scene's "terrain.draw"
    // Override the scene's "render.fx_scale": every effect and the one medium at 1, 0.5 or 0.25
    // of the viewport's resolution, upsampled against the game's depth (edges stay sharp).
    std::optional<double> fx_scale;
    // Override the scene's "render.medium": froxel (bounded cost and memory, the default) or
    // exact (per-pixel segment lists: the reference grade) where volumes overlap.
    std::optional<fx::MediumMethod> medium;
    WorldUp world_up = WorldUp::Z;
    fx::ParallelFor parallel_for;      // the host's job system (none: update() on the calling thread, the
                                       // render paths' CPU work on cellfx's own pool, started once)

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
// a rigid motion or parameters out of range (fov in (0, 179), 0 < near < far, far finite: give
// an infinite reversed-Z projection's planes in Target::depth and a finite far here).
fx::Camera camera_from_view(const glm::dmat4& view, double fov_y_degrees, double near_distance, double far_distance);
Status try_camera_from_view(const glm::dmat4& view, double fov_y_degrees, double near_distance, double far_distance,
                            fx::Camera& camera) noexcept;

class Module {
public:
    Module();
    ~Module(); // shutdown(): the GL context that init() used must be current
    Module(Module&&) noexcept;
    Module& operator=(Module&&) noexcept;
    Module(const Module&) = delete;
    Module& operator=(const Module&) = delete;

    // --- lifecycle ---------------------------------------------------------------------------
    // Loads the scene and builds its GL objects in the current context (an OpenGL 4.5 core
    // context must be current: checked). Throws fx::Error (no or too old a context, a scene file
    // error naming the file and key, a GL failure); an initialized module is then left as it
    // was. To change the scene of a running module keep its clock and choices: reload().
    void init(const Config& config);
    Status try_init(const Config& config) noexcept;
    void shutdown() noexcept; // releases every GL object cellfx made; the context must be current
    bool initialized() const noexcept;

    // --- every frame -----------------------------------------------------------------------
    // Advances the clock by dt seconds and simulates what `camera` (the game's world frame)
    // sees; no GL calls. The viewport size is the last render()'s (or init's): a render of
    // another size re-simulates for it first. Throws fx::Error for a non-finite dt or camera,
    // or before init().
    void update(double dt, const fx::Camera& camera);
    Status try_update(double dt, const fx::Camera& camera) noexcept;
    // Draws the updated frame over the game's (see the header comment); restores GL state.
    // Throws for a depth texture it cannot read (naming it) or before update().
    void render(const Target& target);
    Status try_render(const Target& target) noexcept;
    const FrameStats& stats() const noexcept; // the last frame's (empty before the first)

    // The scene's clock (seconds since init unless set) and its camera at that time in the
    // game's frame (the camera path when the scene has one): for demos and headless runs.
    double time() const noexcept;
    void set_time(double seconds); // throws for a non-finite time
    Status try_set_time(double seconds) noexcept;
    fx::Camera scene_camera() const;
    // The scene as it is drawn now: run-time changes (effects added, parameters, colours, paths)
    // included. An empty scene before init().
    const Scene& scene() const noexcept;

    // --- the scene at run time ---------------------------------------------------------------
    // Parses the file (or takes the scene) first and swaps only if everything is built: a bad
    // file leaves the running scene untouched and the error names file and key. Kept across the
    // swap: the clock, the parent transforms of effects of the same name, the render paths and
    // enabled states the game chose (set_path, set_enabled), set_terrain_drawn's choice.
    void reload(const std::string& scene_file);
    Status try_reload(const std::string& scene_file) noexcept;
    void reload(const Scene& scene);
    Status try_reload(const Scene& scene) noexcept;

    // Effects by name ("fog", "aurora", the names in scene().effects). The setters throw
    // fx::Error for an unknown name or a bad value and then change nothing; each costs what it
    // changes (docs/effects.md).
    std::vector<std::string> effect_names() const;
    bool has_effect(const std::string& name) const noexcept;
    void add_effect(const EffectSpec& spec); // a new name; built when first in view
    Status try_add_effect(const EffectSpec& spec) noexcept;
    void remove_effect(const std::string& name); // an entry of scene().effects (fog, aurora: set_enabled)
    Status try_remove_effect(const std::string& name) noexcept;
    void set_enabled(const std::string& name, bool enabled);
    Status try_set_enabled(const std::string& name, bool enabled) noexcept;
    bool enabled(const std::string& name) const;
    void set_path(const std::string& name, fx::RenderPath path);
    Status try_set_path(const std::string& name, fx::RenderPath path) noexcept;
    fx::RenderPath path(const std::string& name) const;
    // Every parameter of an entry of scene().effects (another type replaces the effect).
    void set_params(const std::string& name, const EffectParams& params);
    Status try_set_params(const std::string& name, const EffectParams& params) noexcept;
    // Colour and extinction: the transfer function as read (normalized ones mapped onto the
    // effect's scalar range) and the factor on its extinction.
    void set_transfer_function(const std::string& name, const fx::TransferFunction& tf);
    Status try_set_transfer_function(const std::string& name, const fx::TransferFunction& tf) noexcept;
    void set_extinction_scale(const std::string& name, double scale);
    Status try_set_extinction_scale(const std::string& name, double scale) noexcept;
    void set_absorb(const std::string& name, bool absorb); // pcp-exact: dims what is behind it
    Status try_set_absorb(const std::string& name, bool absorb) noexcept;
    // Attaches an effect to a game object: `world_from_object` in the game's world frame (its up
    // axis as Config::world_up says), given again whenever the object moves; costs no rebuild.
    void set_parent_transform(const std::string& name, const glm::dmat4& world_from_object);
    Status try_set_parent_transform(const std::string& name, const glm::dmat4& world_from_object) noexcept;
    // The live effect, or nullptr for an unknown name or another type: effect<fx::SearchLight>
    // ("patrol"), effect<terrain::GroundFog>("fog"). By the type's kTypeName tag (no RTTI).
    // Its own setters (set_pose, set_params) work in scene coordinates (z up).
    template <class E>
    E* effect(const std::string& name) noexcept {
        fx::Effect* e = find_effect(name);
        return e && std::strcmp(e->type_name(), E::kTypeName) == 0 ? static_cast<E*>(e) : nullptr;
    }
    void set_terrain_drawn(bool drawn); // throws for a scene without terrain
    Status try_set_terrain_drawn(bool drawn) noexcept;
    bool terrain_drawn() const noexcept;
    // Quality at run time, kept across reload(): the effects' resolution (1, 0.5 or 0.25; throws
    // for another value) and how overlapping volumes are integrated (Config's fields).
    void set_fx_scale(double scale);
    Status try_set_fx_scale(double scale) noexcept;
    double fx_scale() const noexcept;
    void set_medium_method(fx::MediumMethod method);
    fx::MediumMethod medium_method() const noexcept;

    // Tools and benchmarks: GPU timing, LOD error bound, background of whole frames.
    terrain::SceneRenderer& renderer();

private:
    struct State;
    std::unique_ptr<State> state_;
    State& ready() const; // throws before init()
    fx::Effect* find_effect(const std::string& name) noexcept;
};

} // namespace cellfx
