// cellfx terrain — the terrain surface drawn shaded under the fog, sharing depth with it.
//
// Draws a terrain LOD as opaque triangles coloured by height (a ramp over the field's height
// range) and lit by a sun (Lambert + ambient), with normals from the full-resolution field (so
// shading does not change as the LOD refines). The GPU holds a height per sample of the field
// (as the LOD morphed it) and the fans' triangles by fan slot; drawing a TerrainLod frame after
// frame uploads only the vertices and fans its last refinement changed (gl::ScatterPass), and
// everything when it missed a refinement or the LOD was rebuilt. Depth is tested (GL_LESS)
// and written, with no polygon offset: fog prisms share the ground's vertices, so a render path
// clamping to this depth (fx::CellRenderOptions::scene_depth) ends their rays at the ground to
// within a depth-buffer step, and an offset (which grows with the slope) would let fog behind a
// ridge show through at its silhouette.
//
// Ownership: owns its programs, buffers and the normal texture (move-only; destroy it while its
// context is current). Preconditions: a GL 4.5 core context current for every call; draw()
// draws into the framebuffer bound to GL_DRAW_FRAMEBUFFER, which needs a depth attachment for
// the depth test. Every GL state it changes is restored (fx::gl::StateGuard).
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/height_field.hpp"
#include "terrain/surface_style.hpp"
#include "terrain/terrain_lod.hpp"

namespace cellfx::terrain {

struct SurfaceStats {
    std::size_t triangles = 0;
    double cpu_ms = 0.0;          // upload and draw calls
    std::size_t vertices_uploaded = 0, fans_uploaded = 0; // this frame (a TerrainLod drawn)
    bool whole = false;           // everything uploaded (a new LOD version it could not follow)
};

class SurfaceRenderer {
public:
    // Uploads the field's gradients (a float texture of size²·8 bytes) and compiles the shaders.
    // Throws fx::Error for an empty field or a GL failure (shader errors name file:line).
    explicit SurfaceRenderer(const HeightField& ground);
    ~SurfaceRenderer();
    SurfaceRenderer(SurfaceRenderer&&) noexcept;
    SurfaceRenderer& operator=(SurfaceRenderer&&) noexcept;

    // Draws `lod` (of this field) with `camera` into `viewport` of the bound draw framebuffer.
    // Throws fx::Error for an empty viewport, more than 8 ramp stops, or a LOD of another field.
    SurfaceStats draw(const TerrainLod& lod, const fx::Camera& camera, const fx::Viewport& viewport,
                      const SurfaceStyle& style = {});
    // The same for an extracted mesh (ContinuousLod::extract), uploaded whole.
    SurfaceStats draw(const LodMesh& mesh, const fx::Camera& camera, const fx::Viewport& viewport,
                      const SurfaceStyle& style = {});

    std::size_t gpu_bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::terrain
