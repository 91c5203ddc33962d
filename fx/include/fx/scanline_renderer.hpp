// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2–§3, §5
//
// cellfx — the CPU scan-line volume renderer: the exact per-pixel reference every GPU path is
// tested against.
//
// Every cell face becomes triangles (quads split by triangulate_face(), smallest-vertex
// diagonal); a face shared by two cells of one block is emitted once. A face with no
// neighbour in its own block is a "grid surface" of that block. A triangle is stored as one
// 32-bit code (cell, face, half, surface flag); its points come from the mesh. Per frame the
// points go to screen space with depth kept in pixel units (§5), the triangles are sorted
// into one Y-bucket array (§2.1, built in two passes by all threads with per-thread counts
// and offsets, §3 Figure 7; inside a bucket by the number of lines they cover), and every
// scan line keeps an active list, builds X-buckets — each pixel's crossings, in depth order
// (§2.2) — and walks them. Between consecutive crossings the colour is integrated exactly
// with cellfx's segment integrals (fx/src/transfer/segment_integral.hpp: emission_absorption,
// emission_integral, segment_maximum).
// docs/scanline.md describes the algorithm, its rules, memory and speed.
//
// Rules that make the picture right rather than roughly right:
// - Coverage: pixel (x, y) is the point (x + 0.5, y + 0.5). A triangle covers it when
//   y_bottom ≤ y_c < y_top and x_left ≤ x_c < x_right (half-open on both axes), with edge x
//   values from the §2.3 formula evaluated with each edge's endpoints in a fixed order (lower
//   y first) and exact at the endpoints. Two triangles sharing an edge therefore never both
//   cover, and never both miss, a pixel centre on that edge; a ray through a shared vertex
//   crosses each surface exactly once.
// - Inside/outside is toggled per grid (block) at that grid's surface triangles (§2.4 Fig. 6),
//   so non-convex grids (a ray leaving and re-entering) and intersecting grids work.
// - Overlapping grids: where a ray is inside several grids at once, each grid's segment
//   contributes its own emission and extinction over the shared span, i.e. the media add:
//   optical depth τ = Σ τ_g, emitted light Σ (per-grid emission). Emission model: the span's
//   emission is the sum of the grids' emission_integral(). Maximum: the largest of the grids'
//   segment_maximum(). Emission–absorption: alpha = 1 − e^(−Σ τ_g) and colour
//   = alpha · Σ_g (colour_g / alpha_g · τ_g) / Σ τ_g, where (colour_g, alpha_g, τ_g) is
//   emission_absorption() of grid g alone over the span. This is exact when each grid's
//   medium is homogeneous over the span (a mixture of two media), reduces to the single-grid
//   integral where only one grid is present, and does not depend on the order of the grids.
// - Perspective (§5): screen depth z_s = f·(1 − z_r / z_e) in pixels (f the focal length in
//   pixels, z_e the eye-space depth, z_r a reference depth near the mesh) is linear over a
//   projected triangle; the eye-depth difference of two crossings is recovered exactly with
//   the paper's formula Δz_e = f·z_r·(z_s2 − z_s1) / ((f − z_s1)(f − z_s2)) and divided by
//   cos θ (θ between the pixel ray and the view axis) to give the length along the ray.
//   Scalars are interpolated perspective-correctly (s/z_e is linear on screen), so a field
//   linear in world space integrates exactly. Orthographic: z_s is eye depth in pixels.
// - Near plane: nothing behind camera.near_distance is drawn. Triangles crossing the near
//   plane are clipped (never projected through the eye); every cell cut by the plane adds its
//   cross-section ("cap") as virtual grid-surface triangles at the near depth carrying the
//   interpolated scalar, so a camera inside a grid renders what lies in front of it. The far
//   plane is ignored: the reference integrates to the end of the mesh.
// - Clip box: an optional world-space box acts as the paper's virtual clipping polygon: its
//   12 triangles (and its near-plane cap) toggle "inside the clip region" at each pixel, and
//   colour is accumulated only inside it. Triangles whose pixels cannot see the box are
//   dropped during the Y-bucket build.
// - Output: premultiplied RGBA floats, bottom row first. Emission-absorption writes
//   alpha = 1 − e^(−τ); the Emission and Maximum models neither absorb nor occlude, so they
//   write alpha = 0 (composite_over() then adds them to the background).
//
// - Cells that overlap within a grid: the reference refuses them rather than guess. The
//   constructor refuses cells that share a face on the same side (duplicates included,
//   find_overlapping_cells()); render() counts, along every pixel's ray, how many cells of
//   each grid the ray is inside (+1 entering a cell through a surface, −1 leaving) and throws
//   fx::Error naming the cells and the pixel where that count reaches 2 (or −1) over more
//   than rounding's worth of depth. Every picture it returns is therefore exact; a mesh whose
//   overlapping parts are separate blocks renders with their media added.
// - Flat (zero-volume) cells hold no medium and are skipped; twisted cells and meshes with
//   no cell of volume are refused (check_renderable(), mesh_validation.hpp).
//
// Ownership and preconditions: the renderer keeps a reference to the mesh, which must
// outlive it and must not change (points may not move, cells not be added) while it is
// used. The mesh must pass check_renderable() and have at most 2^27 cells (the constructor
// throws fx::Error otherwise); cells may have either winding (each cell's orientation is
// taken into account). render() is const and may be called from several threads at once,
// each call with `options.threads` workers. The renderer keeps one set of per-frame buffers
// (screen points, Y-buckets, worker lists) between calls so that a frame does not allocate
// and clear them again; a call that finds them in use by another allocates its own. Frames
// do not depend on the thread count or on how lines are shared out: equal depths are
// ordered by triangle code.
//
//     fx::ScanlineRenderer renderer(mesh);                       // once per mesh
//     fx::ScanlineOptions options;                               // EmissionAbsorption, all cores
//     fx::ScanlineStats stats;
//     fx::Image frame = renderer.render(camera, 512, 512, *mesh.find_scalar("density"),
//                                       tf, options, &stats);    // per frame
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/image.hpp"
#include "fx/medium.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {

namespace scanline {
struct FrameBuffers;
}

enum class OpticalModel {
    Emission,           // ∫ c·σ ds, additive
    Maximum,            // maximum of c·σ along the ray
    EmissionAbsorption, // volume density model, front to back
};

// A long frame watched and stopped from another thread (a tool's progress bar): render() adds
// each scan line to `lines_done` as a worker finishes it (height lines a frame), and once
// `cancel` is true its workers take no more lines and it returns early, the lines not drawn
// left empty (the caller that cancelled discards the frame). Shared by every render() given it.
struct ScanlineProgress {
    std::atomic<std::uint64_t> lines_done{0};
    std::atomic<bool> cancel{false};
};

struct ScanlineOptions {
    OpticalModel model = OpticalModel::EmissionAbsorption;
    unsigned threads = 0;           // 0: std::thread::hardware_concurrency()
    std::optional<Bounds> clip_box; // world-space box; colour only inside it
    // Consecutive scan lines a worker takes from the shared counter at once. 0: chunks of a
    // share of the work left (estimated from the Y-bucket counts), large first, shrinking.
    int lines_per_task = 0;
    // Intersecting grids of different media (a scene's volumes): one fx::MediumVolume per block,
    // in block order. Each grid is then integrated with its own transfer function (in its own
    // scalar units; render()'s `tf` is not used), absorbing or emitting only, lights scattering
    // in the absorbing ones, every span through Medium::integrate_span. EmissionAbsorption
    // model only. Not owned; must outlive render().
    const Medium* medium = nullptr;
    // Progress and cancellation (above); not owned, must outlive render(). nullptr: none.
    ScanlineProgress* progress = nullptr;
};

// Bytes in use during one frame, by the components of §4.3.
struct ScanlineMemory {
    std::size_t mesh = 0;               // the CellMesh itself (not owned, for comparison)
    std::size_t triangles = 0;          // face triangles (per mesh) and per-frame extra ones
    std::size_t transformed_points = 0; // screen-space vertices
    std::size_t y_buckets = 0;          // Y-bucket array, per-line start/end, per-thread counts
    std::size_t bucket_clip_info = 0;   // one short per triangle
    std::size_t active_lists = 0;       // active Y lists and pixel lists, peak, all threads
    std::size_t x_buckets = 0;          // X-bucket entries and indices, peak, all threads
    std::size_t frame_buffer = 0;       // the output image
    std::size_t renderer_total() const {
        return triangles + transformed_points + y_buckets + bucket_clip_info + active_lists + x_buckets +
               frame_buffer;
    }
};

struct ScanlineStats {
    ScanlineMemory memory;
    unsigned threads = 0;
    double seconds_transform = 0.0; // points to screen space
    double seconds_y_buckets = 0.0; // near-plane clipping, caps, clip box, both bucket passes
    double seconds_scan = 0.0;      // active lists, X-buckets, pixels
    double seconds_total = 0.0;
    std::size_t triangles_total = 0;    // mesh triangles
    std::size_t triangles_surface = 0;  // of which grid surfaces
    std::size_t triangles_active = 0;   // in the Y-buckets (the paper's "active polygons")
    std::size_t triangles_near_clipped = 0; // mesh triangles cut by the near plane
    std::size_t cap_triangles = 0;      // near-plane cross-sections of cells (and clip box)
    std::size_t crossings = 0;          // (pixel, triangle) crossings walked
    std::size_t lost_segments = 0;      // "inside" a grid with no crossing after: broken mesh
};

class ScanlineRenderer {
public:
    // Builds the triangle table (face topology is computed here and discarded). Throws
    // fx::Error for non-finite points, indices out of range or more than 2^27 cells.
    explicit ScanlineRenderer(const CellMesh& mesh);
    ~ScanlineRenderer();
    // Copies share the mesh and copy the triangle table, not the per-frame buffers.
    ScanlineRenderer(const ScanlineRenderer& other);
    ScanlineRenderer(ScanlineRenderer&& other) noexcept;
    ScanlineRenderer& operator=(const ScanlineRenderer&) = delete; // the mesh reference is fixed

    // Renders one frame. `field` has one value per mesh point (finite); a normalized transfer
    // function is first mapped onto the field's range. width, height in [1, 65534] and within
    // the image-pixels limit; the frame's buffers within the frame-bytes limit
    // (resource_limits.hpp). Throws fx::Error on bad arguments, overlapping cells (above) and
    // when memory runs out (on any worker thread).
    Image render(const Camera& camera, int width, int height, const ScalarField& field,
                 const TransferFunction& tf, const ScanlineOptions& options = {},
                 ScanlineStats* stats = nullptr) const;

    std::size_t triangle_count() const { return codes_.size(); }
    std::size_t surface_triangle_count() const { return surface_triangles_; }
    std::size_t grid_count() const { return blocks_.size(); }
    std::size_t memory_bytes() const; // the per-mesh triangle table

private:
    Image render_frame(const Camera& camera, int width, int height, const ScalarField& field,
                       const TransferFunction& tf, const ScanlineOptions& options, ScanlineStats* stats) const;

    const CellMesh& mesh_;
    // One 32-bit code per triangle, in cell order: cell << 5 | face << 2 | half << 1 |
    // grid surface (the paper's sequential identifier; its points come from the mesh).
    std::vector<std::uint32_t> codes_;
    struct CellRange {
        std::uint32_t begin = 0, end = 0; // cells of one block (grid)
    };
    std::vector<CellRange> blocks_;
    std::size_t surface_triangles_ = 0;
    std::vector<std::uint8_t> cell_flags_; // per cell: inverted, flat (scanline_renderer.cpp)
    Bounds bounds_; // of the mesh, for the depth reference
    // Per-frame buffers kept for the next render() (none while a render() holds them).
    mutable std::mutex spare_mutex_;
    mutable std::unique_ptr<scanline::FrameBuffers> spare_;
};

} // namespace cellfx::fx
