// cellfx terrain — renders a Scene: continuous-LOD terrain, its ground fog as prisms, an aurora.
//
// Per frame (render()):
//   1. the LODs refine for the camera (terrain + fog layer: the fog map drives refinement too;
//      the aurora on its own grid), incrementally (continuous_lod.hpp);
//   2. the fog and aurora prisms are rebuilt from the LOD meshes (fog_layer.hpp) and handed to
//      their fx::CellRenderer (set_mesh: no program relinking);
//   3. into an internal RGBA32F + depth target: the background, the terrain surface (shaded,
//      writing depth), the fog with the scene's render path and the terrain's depth as
//      scene_depth (fog stops at the ground, pcp-exact with absorb dims the terrain behind it),
//      then the aurora (emission, added, also stopped by the terrain);
//   4. the target is copied over the host's viewport (render()) or read back (render_to_image()).
// Only what the scene declares is built, updated and drawn: no fog or aurora section, no LOD,
// prisms or cell renderer for it.
//
// Ownership: owns its LODs, meshes and GL objects (move-only; destroy it while its context is
// current). Preconditions: a GL 4.5 core context current for every call, including the
// constructor. Every GL state it changes is restored.
#pragma once

#include <memory>

#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/image.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/surface_renderer.hpp"

namespace terrain {

struct FrameStats {
    LodStats terrain_lod, aurora_lod;
    LayerPrismStats fog_prisms, aurora_prisms;
    SurfaceStats surface;
    fx::CellRenderStats fog, aurora;
    double lod_ms = 0.0;     // both LOD updates
    double mesh_ms = 0.0;    // LOD extraction and prism building
    double upload_ms = 0.0;  // set_mesh of the cell renderers (projector geometry, buffers)
    double draw_ms = 0.0;    // GL commands of the frame, to glFinish when timed
    double frame_ms = 0.0;   // the whole render call
};

class SceneRenderer {
public:
    // Builds the LODs (d2 precomputation) and GL objects; `scene` is copied. Throws fx::Error
    // (GL failures, a scene whose fog or aurora cannot be rendered).
    explicit SceneRenderer(const Scene& scene);
    ~SceneRenderer();
    SceneRenderer(SceneRenderer&&) noexcept;
    SceneRenderer& operator=(SceneRenderer&&) noexcept;

    // Updates and draws one frame into `viewport` of the bound draw framebuffer (opaque).
    // `finish` waits for the GPU (glFinish) so that draw_ms and frame_ms measure the frame.
    FrameStats render(const fx::Camera& camera, const fx::Viewport& viewport, bool finish = false);
    // The same frame read back: premultiplied RGBA floats, alpha 1, bottom row first.
    fx::Image render_to_image(const fx::Camera& camera, int width, int height, FrameStats* stats = nullptr);

    // Overrides of the scene's choices (the bench compares paths, tools vary the error bound).
    void set_fog_path(fx::RenderPath path);
    void set_aurora_path(fx::RenderPath path);
    void set_pixel_error(double pixels);

    const Scene& scene() const;
    const ContinuousLod& terrain_lod() const;
    // The last frame's meshes (empty before the first frame or without that layer).
    const LodMesh& terrain_mesh() const;
    const fx::CellMesh& fog_prisms() const;
    const fx::CellMesh& aurora_prisms() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace terrain
