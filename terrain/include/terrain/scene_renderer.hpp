// cellfx terrain — the per-frame owner of a Scene: simulates only the effects the scene calls for
// and draws them, with the terrain, into the game's frame. (Games include cellfx/cellfx.hpp,
// which wraps this class; tools and tests use it directly.)
//
// Effects: the scene's fog ("fog", terrain::GroundFog) and aurora ("aurora", terrain::Aurora)
// and each entry of scene.effects (fx::Campfire, fx::SearchLight, fx::LaserCone, by its name),
// all behind fx::Effect (fx/effect.hpp). Per frame:
//   update(dt, camera, width, height)
//     1. the scene clock advances by dt;
//     2. the terrain LOD is refined (once, shared by surface and fog) if the surface is drawn
//        or the fog is simulated — not at all otherwise;
//     3. per effect: disabled → skipped, nothing built; world bounds outside the camera's
//        frustum → skipped, nothing built or sampled; otherwise fx::Effect::update(), which does
//        only what changed (a static effect nothing after its first frame, a campfire re-samples
//        its own grid's noise only when its time advanced, a moving search light only moves).
//   render(target)
//     4. the game's depth, in whatever convention Target::depth describes, turned into cellfx's
//        own (DepthConvention); the terrain surface (if the scene draws it), depth-tested
//        against it;
//     5. per simulated effect: what update() changed is uploaded (mesh: CellRenderer::set_mesh,
//        scalars only: set_scalars, pose only: nothing — the camera is moved into the effect's
//        frame), then drawn with its render path, stopped by the scene depth (the game's depth
//        and the terrain's), in the order fog, aurora, then the other effects far to near;
//     6. composited over the game's frame inside target.viewport.
// FrameStats reports it all per effect: simulated or skipped and why, cells built, cells drawn,
// noise samples, milliseconds per stage.
//
// Ownership: owns the effects, LODs, meshes and GL objects (move-only; destroy it while its
// context is current). Preconditions: a GL 4.5 core context current for the constructor and
// every call that draws. Every GL state it changes is restored: one fx::gl::StateGuard per
// frame around everything render() draws (it binds texture units 0–3 only; the guard saves every
// target of units 0–7).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/image.hpp"
#include "fx/medium.hpp"
#include "fx/parallel_for.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/surface_renderer.hpp"

namespace cellfx::terrain {

// What update() did with an effect this frame.
enum class EffectStatus {
    Simulated, // its mesh or scalars were rebuilt
    Moved,     // only its pose changed (nothing rebuilt or uploaded)
    Unchanged, // up to date already: drawn as it was
    Disabled,  // skipped: switched off (scene file or set_enabled)
    OutOfView, // skipped: its bounds lie outside the camera's frustum
};
const char* effect_status_name(EffectStatus status); // "simulated", "moved", "unchanged", "disabled", "out of view"
inline bool effect_skipped(EffectStatus s) { return s == EffectStatus::Disabled || s == EffectStatus::OutOfView; }

struct EffectFrameStats {
    std::string name, type;              // "fire", "campfire"
    EffectStatus status = EffectStatus::Disabled;
    fx::RenderPath path = fx::RenderPath::PcpExact;
    std::size_t cells = 0;         // in the effect's current mesh (0 if never built)
    std::size_t cells_built = 0;   // cells of meshes built this frame (0 unless rebuilt)
    std::size_t cells_drawn = 0;   // cells the render path drew this frame
    std::size_t noise_samples = 0; // noise values the effect evaluated this frame
    double simulate_ms = 0.0;      // fx::Effect::update (CPU)
    double upload_ms = 0.0;        // set_mesh / set_scalars (CPU, incl. driver copies)
    double draw_ms = 0.0;          // the render path's CPU time
    double gpu_ms = -1.0;          // GL_TIME_ELAPSED of its draw; −1 unless timing is on
    bool in_medium = false;        // integrated with the others where they overlap (FrameStats::medium)
    fx::CellRenderStats render;    // the render path's own figures
};

struct FrameStats {
    // Per effect, in the scene's order: "fog", "aurora" (when declared), then scene.effects.
    std::vector<EffectFrameStats> effects;
    double time = 0.0;        // scene clock at this frame (s)
    double update_ms = 0.0;   // update(): LOD and effect simulation
    double render_ms = 0.0;   // render(): uploads, GL commands (to glFinish when timed)
    // CPU time the calling thread spent in update() and render(): cellfx's own work and the GL
    // driver's work on that thread, not the time spent waiting for the GPU (thread CPU clock).
    double update_cpu_ms = 0.0, render_cpu_ms = 0.0;
    double gpu_ms = -1.0;     // GPU time of the whole render when timing is on (sum of the stages)
    double surface_gpu_ms = -1.0, composite_gpu_ms = -1.0;
    std::size_t cells_drawn = 0;   // all effects
    std::size_t noise_samples = 0; // all effects
    // One medium: the region where volumes overlapped and were integrated together (pixels 0
    // when none did), its segments and time (GPU time included in gpu_ms).
    fx::MediumStats medium;

    // The terrain's stages (as before effects existed).
    LodStats terrain_lod, aurora_lod;             // refinements done this frame (zero if none)
    LayerPrismStats fog_prisms, aurora_prisms;    // of the prisms drawn
    SurfaceStats surface;
    fx::CellRenderStats fog, aurora;              // their draws (zero when not drawn)
    double lod_ms = 0.0;     // LOD refinement (terrain and aurora)
    double mesh_ms = 0.0;    // LOD extraction and prism building
    double upload_ms = 0.0;  // set_mesh / set_scalars of all effects
    double draw_ms = 0.0;    // GL commands of the frame, to glFinish when timed
    double frame_ms = 0.0;   // update + render

    const EffectFrameStats* find(std::string_view name) const; // nullptr if absent
    // One line for an on-screen display: "t 3.2s  12.4 ms  fire: simulated 2172 cells ...".
    std::string summary() const;
};

// How the game wrote its depth texture: every common set-up.
//   standard    GL's defaults: near → 0, far → 1, GL_LESS, cleared to 1 (with the default clip
//               control, or glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) and a projection that
//               maps near → 0: the same window depth, more precision);
//   reversed    reversed-Z: near → 1, far → 0 — glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), a
//               reversed projection, GL_GREATER (or GEQUAL), cleared to 0.
// The projection's own planes may differ from the camera given to update() (0: the camera's), and
// its far plane may be infinite (an infinite reversed-Z projection: depth = near / z). Any GL
// depth format of a GL_TEXTURE_2D, or a GL_TEXTURE_2D_MULTISAMPLE (resolved to the nearest of
// its samples, so nothing behind the game's geometry shows on its edge pixels). GL's default
// depth range [0, 1] is assumed. cellfx turns it into its own depth once per frame
// (DepthNormalizer) and draws under GL's default clip control whatever the game has set.
// render() looks at the GL state it is called under: a depth test of GL_GREATER / GL_GEQUAL with
// glClipControl's GL_ZERO_TO_ONE is reversed-Z, and without `reversed` it throws, saying what to
// set (read the wrong way round, the game's depth would hide almost every effect). Any other
// state is taken at this struct's word.
struct DepthConvention {
    bool reversed = false;
    double near_distance = 0.0; // 0: the camera's
    double far_distance = 0.0;  // 0: the camera's; may be infinite (perspective)
};

// Where render() draws: the game's framebuffer, the viewport in it, and its depth.
struct Target {
    Target() = default;
    Target(unsigned int framebuffer_name, const fx::Viewport& pixels, unsigned int depth_texture_name = 0,
           const DepthConvention& depth_convention = {})
        : framebuffer(framebuffer_name), viewport(pixels), depth_texture(depth_texture_name), depth(depth_convention) {}

    unsigned int framebuffer = 0;   // GL framebuffer name (0: the default framebuffer)
    fx::Viewport viewport;          // pixels of that framebuffer to draw over
    // The game's depth (a GL_TEXTURE_2D or GL_TEXTURE_2D_MULTISAMPLE name, 0: none), written with
    // the camera given to update() (its view; its projection as `depth` says): texel
    // (viewport.x + i, viewport.y + j) for pixel (i, j). Fog and fire stop at it; the terrain
    // surface is depth-tested against it. It may be attached to `framebuffer` (cellfx reads it
    // only while drawing into its own targets) and is not written. A texture cellfx cannot read
    // (not 2D, not a depth format, smaller than the viewport) makes render() throw, naming it.
    unsigned int depth_texture = 0;
    DepthConvention depth;
};

class SceneRenderer {
public:
    // Builds the effects (no meshes yet: those are built when first in view), LODs and GL
    // objects; `scene` is copied. Throws fx::Error (GL failures, effects that cannot be built).
    explicit SceneRenderer(const Scene& scene);
    ~SceneRenderer();
    SceneRenderer(SceneRenderer&&) noexcept;
    SceneRenderer& operator=(SceneRenderer&&) noexcept;

    // --- the game loop --------------------------------------------------------------------
    // Advances the clock by dt (seconds, finite; 0 re-simulates nothing that depends on time)
    // and simulates what the view of `camera` at width × height pixels needs (header comment).
    // Needs no GL. Throws fx::Error for a non-finite dt or camera, or an empty size.
    void update(double dt, const fx::Camera& camera, int width, int height);
    // Draws the last update()'s frame over the game's frame (header comment). Throws fx::Error
    // before the first update() or for a viewport of another size than update() was given.
    const FrameStats& render(const Target& target);
    // The last frame's statistics (update part only until render()).
    const FrameStats& stats() const;

    // --- whole frames (tools, tests): update(0, camera) and an opaque frame with the scene's
    // background ---------------------------------------------------------------------------
    // Into `viewport` of the bound draw framebuffer. `finish` waits for the GPU (glFinish) so
    // that draw_ms and frame_ms measure the frame.
    const FrameStats& render(const fx::Camera& camera, const fx::Viewport& viewport, bool finish = false);
    // The same frame read back: premultiplied RGBA floats, alpha 1, bottom row first.
    fx::Image render_to_image(const fx::Camera& camera, int width, int height, FrameStats* stats = nullptr);
    // The scene depth of the last whole frame (the terrain's and the game's, as the effects were
    // stopped by it): window depth of the camera's standard projection in r, bottom row first;
    // empty before the first one. For tools (where depth edges lie).
    fx::Image depth_image() const;

    // --- control ---------------------------------------------------------------------------
    std::vector<std::string> effect_names() const; // "fog", "aurora", then scene.effects
    bool has_effect(const std::string& name) const;
    // These throw fx::Error naming an unknown effect.
    void set_enabled(const std::string& name, bool enabled);
    bool enabled(const std::string& name) const;
    void set_path(const std::string& name, fx::RenderPath path);
    fx::RenderPath path(const std::string& name) const;
    // The live effect (move a search light with set_pose, attach it with set_parent_transform).
    fx::Effect& effect(const std::string& name);
    fx::Effect* find_effect(const std::string& name) noexcept; // nullptr for an unknown name

    // --- effects at run time: each change costs what it changes (a colour re-uploads the
    // tables, a shape rebuilds that effect's mesh at the next update) and keeps scene() equal to
    // what is drawn. Each throws fx::Error naming the effect and what is wrong, and then
    // changes nothing. ---------------------------------------------------------------------
    // Adds an effect (built when first in view). Its name must be new (not "fog" or "aurora").
    void add_effect(const EffectSpec& spec);
    // Removes an effect of scene.effects with its GL objects (the context must be current).
    void remove_effect(const std::string& name);
    // New parameters for an effect of scene.effects; another type (a campfire's name given
    // search light parameters) replaces the effect, keeping its parent transform.
    void set_params(const std::string& name, const EffectParams& params);
    // Replaces an effect's transfer function (normalized ones mapped onto its scalar_range()).
    void set_transfer_function(const std::string& name, const fx::TransferFunction& tf);
    // Multiplies the transfer function's extinction (≥ 0, finite).
    void set_extinction_scale(const std::string& name, double scale);
    // pcp-exact: the effect also dims what is behind it (not for the aurora).
    void set_absorb(const std::string& name, bool absorb);

    // Whether cellfx draws the terrain surface (scene.draw_terrain to start with).
    void set_terrain_drawn(bool drawn);
    bool terrain_drawn() const;
    // The background of the opaque frames (render(camera, viewport), render_to_image).
    void set_background(const glm::dvec3& rgb);
    // GPU timing of every stage (GL_TIME_ELAPSED queries, waiting for each result: for
    // benchmarks, not games; none of the host's timer queries may be active then).
    void set_timing(bool timing);
    bool timing() const;
    // The host's job system for the CPU work of update() (effects simulated side by side) and
    // of render() (the classic absorption path's projection, the exact one's per-frame lists).
    // None (the default): update() on the calling thread, render()'s work on cellfx's own
    // persistent pool (fx::default_parallel_for()).
    void set_parallel_for(const fx::ParallelFor& parallel_for);
    double time() const;
    void set_time(double seconds); // the clock, e.g. for a camera path; throws for non-finite

    // The effects' resolution, a fraction of the view's: 1, 0.5 or 0.25 (scene.fx_scale to start
    // with; docs/effects.md, "Resolution"). Throws fx::Error for another value.
    void set_fx_scale(double scale);
    double fx_scale() const;
    // How volumes that overlap on screen are integrated (scene.medium to start with): the
    // bounded froxel grid or the exact per-pixel segment lists (fx/medium.hpp).
    void set_medium_method(fx::MediumMethod method);
    fx::MediumMethod medium_method() const;

    // Overrides of the scene's choices (tools, benchmarks).
    void set_fog_path(fx::RenderPath path);    // no-op without fog
    void set_aurora_path(fx::RenderPath path); // no-op without aurora
    void set_pixel_error(double pixels);

    // The effects the last update() simulated (enabled, in view) that have cells, in the
    // scene's order, each with its medium as the renderer integrates it (transfer function in scalar
    // units, absorbing or not, albedo, light in the world) and its path: what the scan-line
    // reference of the frame renders (terrain/scene_reference.hpp).
    struct DrawnVolume {
        std::string name;
        const fx::Effect* effect = nullptr; // mesh() and transform() of that update
        fx::RenderPath path = fx::RenderPath::PcpExact;
        bool in_medium = false;            // pcp-exact, absorption, absorption-exact: one medium
        fx::MediumVolume medium;
    };
    std::vector<DrawnVolume> drawn_volumes() const;

    const Scene& scene() const;
    const ContinuousLod& terrain_lod() const; // throws fx::Error for a scene without terrain
    // The last frame's meshes (empty before the first frame or without that layer).
    const LodMesh& terrain_mesh() const;
    const fx::CellMesh& fog_prisms() const;
    const fx::CellMesh& aurora_prisms() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::terrain
