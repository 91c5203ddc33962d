// cellfx — one medium on the GPU: several volumes (fog, fire, smoke, beams) integrated together
// along each pixel's ray in depth order, where they overlap on screen.
//
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 — each pixel's crossings of every grid,
// sorted in depth and integrated between consecutive ones — done per pixel on the GPU with an
// A-buffer of ray segments (Carpenter 1984; per-pixel linked lists as in order-independent
// transparency). The optical model is fx/medium.hpp's.
//
// Per frame, inside one rectangle of the viewport (the region where volumes overlap; the
// caller draws everything else with the ordinary paths):
//   begin()    the view, the region and every volume's medium (transfer function, absorbs,
//              albedo, light); uploads tables only for volumes whose medium changed;
//   append()   per volume: its CellRenderer's mesh drawn once (back faces, the renderer's own
//              buffers), each fragment computing its ray's exact segment inside the cell
//              (entry through the cell's planes, clamped to the near plane and the scene depth:
//              shaders/cell_segment.glsl) and appending (t_in, t_out, s_in, s_out, volume) to
//              its pixel's list;
//   resolve()  per pixel of the region: the segments sorted by entry, swept in depth order, every
//              span between consecutive boundaries integrated through the media inside it
//              (emission tables, fx/medium.hpp's mixing and scattering), composited over the
//              `behind` image (the frame without the volumes) and written — replacing what the
//              ordinary paths drew there.
// The segment pool grows to what a frame needs: resolve() reads back the count (4 bytes; a
// GPU sync), and a frame that overflowed is appended again with a pool twice as large.
//
// Limits: at most kMaxVolumes volumes; a pixel's segments are sorted in a local array of
// kSortedSegments (longer lists are walked by repeated selection — slower, still exact); at
// most kActiveSegments segments overlap at one depth (more are left out and counted).
//
// Ownership: owns its programs, buffers and tables (move-only; destroy with the context
// current). Keeps no reference to the renderers between calls. Preconditions: GL 4.5 context
// current for every call; every GL state it changes is restored (gl::StateGuard).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/medium.hpp"

namespace fx {

struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0; // in the viewport's pixels
    bool empty() const { return width <= 0 || height <= 0; }
};

// The pixel rectangle (in a width × height view of `camera`) that covers the box, a pixel wider
// on each side; the whole view when the box reaches behind the near plane; empty when it is
// outside the view.
PixelRect screen_rect(const Bounds& bounds, const Camera& camera, int width, int height);

struct MediumStats {
    std::size_t pixels = 0;         // in the region
    std::size_t segments = 0;       // appended this frame
    std::size_t capacity = 0;       // of the segment pool (segments)
    std::size_t redraws = 0;        // appends repeated after the pool overflowed
    std::size_t volumes = 0;        // appended this frame
    double cpu_ms = 0.0;            // of append() and resolve() together
    double gpu_ms = -1.0;           // GL_TIME_ELAPSED of appends and resolve (with timing)
    double append_gpu_ms = -1.0, resolve_gpu_ms = -1.0; // its two parts
};

class MediumCompositor {
public:
    static constexpr int kMaxVolumes = 32;
    static constexpr int kSortedSegments = 128;
    static constexpr int kActiveSegments = 16;

    MediumCompositor(); // GL context current; compiles the programs
    ~MediumCompositor();
    MediumCompositor(MediumCompositor&&) noexcept;
    MediumCompositor& operator=(MediumCompositor&&) noexcept;

    // Starts a frame. `camera` is the world camera; `viewport` the target's (the caller's bound
    // draw framebuffer: append and resolve draw into it); `region` a rectangle of it; `volumes`
    // index the volumes append() names. Throws fx::Error for more than kMaxVolumes volumes, a
    // region outside the viewport or a medium without transfer function points.
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

} // namespace fx
