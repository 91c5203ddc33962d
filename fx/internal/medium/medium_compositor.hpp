// cellfx — one medium on the GPU: several volumes (fog, fire, smoke, beams) integrated together
// along each pixel's ray in depth order, where they overlap on screen.
//
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 — each pixel's crossings of every grid,
// sorted in depth and integrated between consecutive ones — done per pixel on the GPU with an
// A-buffer of ray segments (Carpenter 1984; per-pixel linked lists as in order-independent
// transparency). The optical model is fx/medium.hpp's.
//
// Per frame, inside one rectangle of the viewport (the region where volumes overlap; the
// caller draws everything with the ordinary paths, and this replaces what they drew where the
// volumes other than the bulk one cover):
//   begin()    the view, the region, every volume's medium (transfer function, absorbs, albedo,
//              light) and which one is the bulk (the ground fog: one colour, many segments);
//              tables are uploaded only for volumes whose medium changed;
//   append()   names a volume's CellRenderer (its own buffers are drawn: nothing is uploaded);
//   resolve()  draws the appends: each volume's back faces once, every fragment computing its
//              ray's exact segment in the cell (cell_segment.glsl: entry through the cell's
//              planes, near plane, scene depth) and pushing (t_in, t_out, s_in, s_out, volume)
//              onto its pixel's list — the other volumes first, marking a mask where they cover
//              (and a rectangle over each point light's reach), the bulk only inside the mask.
//              Then per masked pixel: the other volumes' segments sorted by entry, the bulk's
//              integrated into the bins between their boundaries (and the point lights' chords,
//              and its own segment ends among them), the bins swept front to back through the
//              media inside them (fx/medium.hpp: mixing, pieces, single scattering), composited
//              over `behind` and written.
// The segment pool grows to what a frame needs: resolve() reads back the count (4 bytes; a GPU
// sync), and a frame that overflowed is appended again with a pool 25% larger than it needed.
//
// Limits: at most kMaxVolumes volumes and 8 point lights; a pixel's non-bulk segments are sorted
// in a local array of kSortedSegments (longer lists are walked by repeated selection, the bulk's
// segments among them — slower, still exact); at most kActiveSegments segments overlap at one
// depth (more are left out).
//
// Ownership: owns its programs, buffers, tables and mask (move-only; destroy with the context
// current). Keeps pointers to the appended renderers until resolve() returns. Preconditions:
// GL 4.5 context current for every call; every GL state it changes is restored (gl::StateGuard:
// it uses texture units 0–2 and storage binding 3).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/medium.hpp"

namespace cellfx::fx {

struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0; // in the viewport's pixels
    bool empty() const { return width <= 0 || height <= 0; }
};

// The pixel rectangle (in a width × height view of `camera`) that covers the box, a pixel wider
// on each side; the whole view when the box reaches behind the near plane; empty when it is
// outside the view.
PixelRect screen_rect(const Bounds& bounds, const Camera& camera, int width, int height);

class MediumCompositor {
public:
    static constexpr int kMaxVolumes = 32;
    static constexpr int kSortedSegments = 96;
    static constexpr int kActiveSegments = 16;

    MediumCompositor(); // GL context current; compiles the programs
    ~MediumCompositor();
    MediumCompositor(MediumCompositor&&) noexcept;
    MediumCompositor& operator=(MediumCompositor&&) noexcept;

    // Starts a frame. `camera` is the world camera; `viewport` the target's (resolve() writes
    // into the draw framebuffer bound then); `region` a rectangle of it; `volumes` index the
    // volumes append() names; `bulk_volume` the one binned rather than sorted (−1: none). Throws
    // fx::Error for more than kMaxVolumes volumes, a region outside the viewport, a bulk index
    // out of range or a medium whose transfer function has no points or is normalized.
    void begin(const Camera& camera, const Viewport& viewport, const PixelRect& region,
               const std::vector<MediumVolume>& volumes, int bulk_volume = -1, bool timing = false);
    // Adds the segments of `renderer`'s mesh as volume `volume`; `local_camera` is the camera in
    // the mesh's frame (fx::camera_in_frame), `scene_depth` as CellRenderOptions::scene_depth.
    // Drawn by resolve(): the renderer must stay alive and unchanged until then.
    void append(CellRenderer& renderer, const Camera& local_camera, std::size_t volume, unsigned scene_depth = 0);
    // Appends every volume (the others first, marking the mask where they cover; the bulk volume
    // inside it), integrates the masked pixels of the region and writes them into the bound draw
    // framebuffer (blending off): premultiplied volumes over `behind` (an RGBA texture,
    // premultiplied, texel (viewport.x + i, viewport.y + j) for pixel (i, j)). Pixels outside
    // the mask are left as they were.
    MediumStats resolve(unsigned behind_texture);

    std::size_t gpu_bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::fx
