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

#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/image.hpp"
#include "fx/medium.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "terrain/scene_renderer.hpp"

namespace cellfx::terrain {

// The volumes of a frame, copied out of the renderer: everything the reference needs and
// nothing of the renderer's, so a tool can render it on another thread while the renderer goes
// on drawing frames. Meshes are in the world relative to the camera's eye (an effect 2 units
// across at 1e17 from the origin keeps its shape), as the reference renders them.
struct SceneReferenceInput {
    fx::Camera camera;                   // the view, its eye at the origin
    fx::CellMesh medium_mesh;            // one block per grid of the one medium
    std::vector<fx::MediumVolume> media; // one per block of medium_mesh
    struct Layer {                       // a pcp (emission) or mip (maximum) effect, added over it
        fx::CellMesh mesh;
        fx::OpticalModel model = fx::OpticalModel::Emission;
        fx::TransferFunction tf;
    };
    std::vector<Layer> layers;
    // Scan-line frames render_scene_reference() makes (one per layer, one for the medium): a
    // progress bar counts height × passes() lines.
    int passes() const { return int(layers.size()) + (medium_mesh.cell_count() > 0 ? 1 : 0); }
};

// The volumes of the renderer's last update(), seen by `camera` (the camera of that update).
SceneReferenceInput capture_scene_reference(const SceneRenderer& renderer, const fx::Camera& camera);

// Premultiplied RGBA, bottom row first: colour and alpha = 1 − transmittance of the volumes
// (composite it over the background with fx::composite_over). `threads` 0: all cores. Needs no
// GL. `progress` (optional) counts the lines of every pass and stops it when cancelled (the
// frame is then incomplete).
fx::Image render_scene_reference(const SceneReferenceInput& input, int width, int height, unsigned threads = 0,
                                 fx::ScanlineProgress* progress = nullptr);

// Both at once. The renderer's last update() must have been for this camera and size
// (render_to_image does one).
fx::Image render_scene_reference(const SceneRenderer& renderer, const fx::Camera& camera, int width, int height,
                                 unsigned threads = 0);

} // namespace cellfx::terrain
