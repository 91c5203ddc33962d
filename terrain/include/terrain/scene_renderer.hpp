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
//     4. the terrain surface (if the scene draws it), depth-tested against the game's depth;
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
// every call that draws. Every GL state it changes is restored (fx::gl::StateGuard; it binds
// texture units 0–3 only, which the guard saves).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/image.hpp"
#include "fx/medium_compositor.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/surface_renderer.hpp"

namespace terrain {

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

// Where render() draws: the game's framebuffer, the viewport in it, and its depth.
struct Target {
    unsigned int framebuffer = 0;   // GL framebuffer name (0: the default framebuffer)
    fx::Viewport viewport;          // pixels of that framebuffer to draw over
    // The game's depth (a GL_TEXTURE_2D name, 0: none): window depth in [0, 1] written with the
    // camera given to update() — its projection_matrix(viewport aspect), GL's default depth
    // range and clip control — texel (viewport.x + i, viewport.y + j) for pixel (i, j); compare
    // mode NONE when the scene does not draw the terrain (then it is sampled directly). Fog and
    // fire stop at it; the terrain surface is depth-tested against it. It may be attached to
    // `framebuffer` (cellfx reads it only while drawing into its own targets) and is not written.
    unsigned int depth_texture = 0;
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
    FrameStats render(const Target& target);
    // The last frame's statistics (update part only until render()).
    const FrameStats& stats() const;

    // --- whole frames (tools, tests): update(0, camera) and an opaque frame with the scene's
    // background ---------------------------------------------------------------------------
    // Into `viewport` of the bound draw framebuffer. `finish` waits for the GPU (glFinish) so
    // that draw_ms and frame_ms measure the frame.
    FrameStats render(const fx::Camera& camera, const fx::Viewport& viewport, bool finish = false);
    // The same frame read back: premultiplied RGBA floats, alpha 1, bottom row first.
    fx::Image render_to_image(const fx::Camera& camera, int width, int height, FrameStats* stats = nullptr);

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
    // Replaces an effect's transfer function (normalized ones mapped onto its scalar_range()).
    void set_transfer_function(const std::string& name, const fx::TransferFunction& tf);

    // Whether cellfx draws the terrain surface (scene.draw_terrain to start with).
    void set_terrain_drawn(bool drawn);
    bool terrain_drawn() const;
    // The background of the opaque frames (render(camera, viewport), render_to_image).
    void set_background(const glm::dvec3& rgb);
    // GPU timing of every stage (GL_TIME_ELAPSED queries, waiting for each result: for
    // benchmarks, not games; none of the host's timer queries may be active then).
    void set_timing(bool timing);
    double time() const;
    void set_time(double seconds); // the clock, e.g. for a camera path; throws for non-finite

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

} // namespace terrain
