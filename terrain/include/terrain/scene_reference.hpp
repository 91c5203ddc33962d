// cellfx terrain — the scan-line reference of a scene's frame: every volume the scene renderer
// draws, rendered exactly on the CPU (fx::ScanlineRenderer) as intersecting grids.
//
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 — several grids in one scan-line pass,
// inside/outside toggled per grid, integrated between consecutive crossings.
//
// The effects of the renderer's last update() (SceneRenderer::drawn_volumes) are moved into the
// world and become the blocks of one mesh. Those drawn with a path of the emission–absorption
// model (pcp-exact, absorption, absorption-exact) are one medium: each grid with its own
// transfer function, absorbing or not, lights scattering (ScanlineOptions::medium, fx/medium.hpp).
// Effects drawn with pcp (emission) or mip (maximum) are rendered with those models and added
// over it, as the renderer adds them. Not part of the reference: the terrain surface and scene
// depth (compare with the terrain not drawn).
#pragma once

#include "fx/camera.hpp"
#include "fx/image.hpp"
#include "terrain/scene_renderer.hpp"

namespace cellfx::terrain {

// Premultiplied RGBA, bottom row first: colour and alpha = 1 − transmittance of the volumes
// (composite it over the background with fx::composite_over). `threads` 0: all cores. The
// renderer's last update() must have been for this camera and size (render_to_image does one).
fx::Image render_scene_reference(const SceneRenderer& renderer, const fx::Camera& camera, int width, int height,
                                 unsigned threads = 0);

} // namespace cellfx::terrain
