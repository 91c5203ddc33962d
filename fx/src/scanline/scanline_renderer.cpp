// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2–§3, §5
//
// The scan-line renderer: triangle codes from cell faces (once per mesh), then per frame
//   1. points to screen space with pixel-unit depth (§2, §5), threads over points;
//   2. near-plane clipping, caps and the clip box's virtual polygons (few, serial);
//   3. the Y-bucket array in two passes with per-thread counts and offsets (§3, Figure 7),
//      culling triangles off screen, outside the clip box's screen rectangle, or covering no
//      scan line / pixel column (at pixel centres); bucket_clip_info keeps each triangle's
//      bucket (or "dropped") and span class (lines covered) between the passes; a bucket
//      lists its triangles by span class, longest first;
//   4. scan lines handed to workers in chunks through one atomic counter (no lock); each
//      worker keeps its own active Y list of multi-line triangles, reading exactly the
//      still-active prefix of the buckets of lines it skipped; one-line triangles are cut
//      straight from their bucket. A line cuts its triangles nearest (centroid) first. Each line's crossings become fragments, counting-sorted
//      into per-pixel X-buckets, each sorted by depth (§2.2);
//   5. per pixel, the crossings in depth order toggle inside/outside per grid at surface
//      triangles and the clip flag at clip polygons (§2.4 Figure 6); colour is integrated
//      between consecutive crossings with segment_integral.hpp.
#include "fx/scanline_renderer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/resource_limits.hpp"
#include "transfer/segment_integral.hpp"
#include "scanline/scanline_fragments.hpp"
#include "scanline/scanline_frame.hpp"

namespace cellfx::fx {
namespace scanline {

// A vertex as the scan converter uses it: q is the scalar times w (perspective-correct).
struct SVertex {
    double x, y, z, q;
};

// A triangle with its vertices sorted bottom to top, ready to be cut by scan lines.
struct ScanTriangle {
    ScreenPoint v[3];
    float key; // sum of its points' depths (3× the centroid's): the order a scan line cuts triangles in
    std::uint32_t id;
    std::uint32_t grid : 30;
    std::uint32_t toggles : 1;
    std::uint32_t enters : 1; // a ray crossing it enters its cell (front-facing outward winding)
};

// Table 1 of the paper: a triangle active over several scan lines, with its last line.
// Triangles that cover one scan line never enter this list; they are cut straight from
// their Y-bucket.
struct ActiveTriangle {
    ScanTriangle tri;
    std::int32_t last_row;
};

// Nearer triangles first. A scan line cuts its triangles in this order, so that each pixel's
// crossings arrive nearly in depth order and its sort (sort_by_depth) has little to move. Any
// order gives the same frame: the sort orders crossings by (depth, code).
inline bool nearer(const ScanTriangle& a, const ScanTriangle& b) { return a.key < b.key; }

// A fragment before the per-pixel counting sort.
struct PixelFragment {
    Fragment f;
    std::int32_t x; // pixel column
};

struct Crossing {
    double z, s;
    double inv_w; // 1 / w(z)
    std::uint32_t grid;
    std::uint32_t id;
    bool toggles, enters;
};

constexpr std::size_t kNoCrossing = ~std::size_t(0);

// A grid's segment through the current pixel, from its crossing a to its next crossing b.
struct GridSegment {
    std::size_t a = 0, b = kNoCrossing;
    double z_a = 0.0, s_a = 0.0, ds = 0.0;
    double scale = 0.0; // w(z_b) / (z_b − z_a), 0 for an empty segment
};

// A one-piece segment of a pixel's ray waiting for the next one, so that their colour weights
// are computed together.
struct PendingSegment {
    double a, b; // optical thickness rates at the front and back
    glm::dvec3 c0, c1;
};

// Counts, along one pixel's ray, how many cells of one grid the ray is inside: +1 where it
// enters a cell through a grid surface, −1 where it leaves. In a grid whose cells do not
// overlap the count stays 0 or 1 and equals the inside/outside parity; 2 or more (or −1) over
// more than rounding's worth of depth means overlapping cells (or a surface that is not
// closed), which parity would silently get wrong.
struct SurfaceWalk {
    int count = 0;
    int bad_from = -1;              // crossing where the count left {0, 1}; −1 if it has not
    int bad_count = 0;              // the count it left for
    std::uint32_t bad_id = 0;       // code of that crossing
    std::uint32_t last = ~0u;       // code of the grid's crossing before it (~0u: none)
    bool last_entered = false;      // ... and whether that one entered a cell through a surface
};

// Bytes held by a vector (capacity, not size).
template <class T>
std::size_t bytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}

// Per-thread buffers, kept between frames. Aligned to a cache line: the vectors' sizes
// change with every fragment, and neighbouring workers' must not share a line.
struct alignas(64) WorkerBuffers {
    std::vector<ActiveTriangle> active; // in nearer() order
    std::vector<ActiveTriangle> merged; // the next line's active list while it is merged
    std::vector<ScanTriangle> one_line; // a line's one-line triangles, in nearer() order
    std::vector<PixelFragment> fragments;
    std::vector<Fragment> sorted; // fragments by pixel, each pixel's X-bucket in depth order
    std::vector<Fragment> scratch; // merge buffer of sort_by_depth()
    std::vector<std::uint32_t> runs;
    std::vector<std::uint32_t> xcount; // X-bucket starts per pixel (counting sort)
    std::vector<Crossing> cross;
    std::vector<int> next_same;
    std::vector<std::uint8_t> inside;
    std::vector<int> seen;
    std::vector<GridSegment> segment; // per grid
    std::vector<std::uint32_t> inside_list;
    std::vector<SpanVolume> span_volumes; // per-grid media: the grids over one span
    std::vector<SurfaceWalk> walks; // per grid
    std::vector<SegmentColor> held_back; // segments behind a pending one, waiting with it

    std::size_t active_bytes() const {
        return bytes(active) + bytes(merged) + bytes(one_line) + bytes(cross) + bytes(next_same) + bytes(inside) + bytes(seen) + bytes(segment) +
               bytes(inside_list) + bytes(span_volumes) + bytes(walks) +
               bytes(held_back);
    }
    std::size_t x_bytes() const {
        return bytes(fragments) + bytes(sorted) + bytes(scratch) + bytes(runs) + bytes(xcount);
    }
};

// The per-frame buffers, kept by the renderer between frames so that a frame neither
// allocates nor clears its large arrays again (ScanlineRenderer::spare_).
struct FrameBuffers {
    std::vector<ScreenPoint> points;
    std::vector<std::uint16_t> clip_info;  // bucket_clip_info: Y-bucket of each mesh triangle,
    std::vector<std::uint64_t> span_class; // ... and its span class, 4 bits (16 per word)
    std::vector<std::uint32_t> counts, offsets, bucket_start, class_begin, y_buckets;
    std::vector<WorkerBuffers> workers;
};

} // namespace scanline

namespace {

using scanline::ActiveTriangle;
using scanline::nearer;
using scanline::Crossing;
using scanline::DepthMap;
using scanline::ExtraTriangle;
using scanline::Fragment;
using scanline::FrameBuffers;
using scanline::FrameGeometry;
using scanline::GridSegment;
using scanline::kNoCrossing;
using scanline::PixelFragment;
using scanline::ScanTriangle;
using scanline::ScreenPoint;
using scanline::SVertex;
using scanline::SurfaceWalk;
using scanline::Vertex;
using scanline::WorkerBuffers;
using scanline::bytes;

constexpr std::uint16_t kDropped = 0xFFFF;
// Per-cell flags kept by the renderer (ScanlineRenderer::cell_flags_).
constexpr std::uint8_t kInvertedCell = 1; // faces wind inward: a crossing's facing is reversed
constexpr std::uint8_t kFlatCell = 2;     // zero volume: holds no medium, not drawn
// Bytes a fragment holds during a scan line: its PixelFragment, its sorted copy, the merge buffer.
constexpr std::size_t kFragmentBytes = sizeof(PixelFragment) + 2 * sizeof(Fragment);

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs fn(thread_index) for every index in [0, threads) on that many threads (the caller is
// thread 0) and waits. An exception on any thread (std::bad_alloc included) is rethrown here,
// on the caller's, after all have finished; shares whose thread could not be started run on
// the caller.
template <class Fn>
void run_threads(unsigned threads, const Fn& fn) {
    std::vector<std::exception_ptr> errors(threads);
    auto guarded = [&](unsigned t) {
        try {
            fn(t);
        } catch (...) {
            errors[t] = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    unsigned started = 1;
    try {
        pool.reserve(threads - 1);
        for (; started < threads; ++started) pool.emplace_back(guarded, started);
    } catch (...) { // no memory or no threads left: the caller does the rest
    }
    guarded(0u);
    for (unsigned t = started; t < threads; ++t) guarded(t);
    for (std::thread& th : pool) th.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

// Smallest pixel index whose centre (i + 0.5) is ≥ v, and largest whose centre is < v.
// v is clamped first so that far off-screen values cannot overflow an int (NaN counts as far
// off). ceil() by truncation and one exact comparison: std::ceil is a library call on
// baseline x86-64, and this runs for every triangle on every scan line.
inline int first_center_at_or_after(double v) {
    double w = v - 0.5;
    if (!(w > -1.0e9)) w = -1.0e9;
    if (!(w < 1.0e9)) w = 1.0e9;
    const int i = static_cast<int>(w); // towards zero
    return static_cast<double>(i) < w ? i + 1 : i;
}
inline int last_center_before(double v) { return first_center_at_or_after(v) - 1; }

// §2.3: x = x1/(y1−y0)·(y−y0) + x0/(y1−y0)·(y1−y), exact at both endpoints. Callers pass an
// edge's endpoints in a fixed order (lower y first), so two triangles sharing an edge get
// the same value for the same y.
// `inv` is 1/(t1 − t0), computed once per edge or span with the same expression everywhere.
inline double interpolate(double a0, double a1, double t0, double t1, double inv, double t) {
    if (t == t0) return a0;
    if (t == t1) return a1;
    return a1 * inv * (t - t0) + a0 * inv * (t1 - t);
}

// Pixel rectangle (inclusive) that can be drawn into.
struct Rect {
    int row_lo, row_hi, col_lo, col_hi;
};

// The scan lines a triangle covers at pixel centres: its Y-bucket `first` and its last line.
// first == -1 when it is dropped: off screen, outside `r`, or covering no scan line or no
// pixel column.
struct Rows {
    int first, last;
};
Rows rows_of(const double x[3], const double y[3], const Rect& r) {
    const double ylo = std::min({y[0], y[1], y[2]}), yhi = std::max({y[0], y[1], y[2]});
    const int r0 = std::max(first_center_at_or_after(ylo), r.row_lo);
    const int r1 = std::min(last_center_before(yhi), r.row_hi);
    if (r0 > r1) return {-1, -1};
    const double xlo = std::min({x[0], x[1], x[2]}), xhi = std::max({x[0], x[1], x[2]});
    const int c0 = std::max(first_center_at_or_after(xlo), r.col_lo);
    const int c1 = std::min(last_center_before(xhi), r.col_hi);
    if (c0 > c1) return {-1, -1};
    return {r0, r1};
}

// Sorts a triangle's three screen points bottom to top; every use of a triangle's edges
// relies on this one order.
inline void sort_bottom_to_top(ScreenPoint v[3]) {
    if (v[1].y < v[0].y) std::swap(v[0], v[1]);
    if (v[2].y < v[1].y) std::swap(v[1], v[2]);
    if (v[1].y < v[0].y) std::swap(v[0], v[1]);
}

// Where scan line yc cuts triangle v (sorted bottom to top): Figure 3's two edges, the long
// one v0→v2 and the short one below or above the middle vertex, their x by §2.3, and the
// pixel columns [first, last] whose centres lie in [x_left, x_right) (none if first > last).
struct LineSpan {
    double xa, xb;       // x on the long and on the short edge
    double inv_a, inv_b; // 1/(Δy) of those edges
    int first, last;
};
inline LineSpan line_span(const ScreenPoint v[3], double yc, const Rect& r) {
    LineSpan s;
    s.inv_a = 1.0 / (double(v[2].y) - double(v[0].y));
    s.xa = interpolate(v[0].x, v[2].x, v[0].y, v[2].y, s.inv_a, yc);
    const ScreenPoint& p = yc < v[1].y ? v[0] : v[1];
    const ScreenPoint& q = yc < v[1].y ? v[1] : v[2];
    s.inv_b = 1.0 / (double(q.y) - double(p.y));
    s.xb = interpolate(p.x, q.x, p.y, q.y, s.inv_b, yc);
    s.first = std::max(first_center_at_or_after(std::min(s.xa, s.xb)), r.col_lo);
    s.last = std::min(last_center_before(std::max(s.xa, s.xb)), r.col_hi);
    return s;
}

// Y-bucket parts: span class c holds triangles covering exactly c scan lines (1 ≤ c < 15),
// class 15 those covering 15 or more.
constexpr int kSpanClasses = 16;
int span_class(const Rows& r) { return std::min(r.last - r.first + 1, kSpanClasses - 1); }

// Triangle codes. A mesh triangle is cell << 5 | face << 2 | half << 1 | surface: half h of
// triangulate_face() on face `face` of cell `cell`. A per-frame extra triangle (near-plane
// piece, cap, clip-box polygon) is index << 5 | 7 << 2 | toggles. Codes are unique and the
// same whichever thread meets them, so they break depth ties.
constexpr std::uint32_t kExtraFace = 7;
constexpr std::size_t kMaxCells = std::size_t(1) << 27;
constexpr std::uint32_t mesh_code(std::size_t cell, int face, int half, bool surface) {
    return static_cast<std::uint32_t>(cell << 5) | static_cast<std::uint32_t>(face) << 2 |
           static_cast<std::uint32_t>(half) << 1 | (surface ? 1u : 0u);
}
constexpr std::uint32_t extra_code(std::size_t index, bool toggles) {
    return static_cast<std::uint32_t>(index << 5) | kExtraFace << 2 | (toggles ? 1u : 0u);
}
constexpr bool is_extra(std::uint32_t code) { return ((code >> 2) & 7) == kExtraFace; }
constexpr std::uint32_t code_index(std::uint32_t code) { return code >> 5; } // cell or extra index
constexpr bool code_toggles(std::uint32_t code) { return (code & 1) != 0; }

// The point ids of mesh triangles, in triangulate_face()'s order. The two halves of a quad
// have neighbouring codes and usually come one after the other, so the face's
// triangulation is kept for the next call.
class TriangleDecoder {
public:
    explicit TriangleDecoder(const CellMesh& mesh) : mesh_(mesh) {}
    const std::uint32_t* operator()(std::uint32_t code) {
        const std::uint32_t face = code >> 2; // cell and face
        if (face != face_) {
            const std::uint32_t cell = code_index(code);
            triangulate_face(cell_faces(mesh_.cell_types[cell])[face & 7], mesh_.cell_vertices(cell), tri_);
            face_ = face;
        }
        return tri_[(code >> 1) & 1];
    }

private:
    const CellMesh& mesh_;
    std::uint32_t face_ = ~std::uint32_t(0); // no cell has this index (at most 2^27 cells)
    std::uint32_t tri_[2][3];
};

// Everything one frame needs, shared read-only by the workers.
struct FrameContext {
    const FrameGeometry* geo;
    const CellMesh* mesh;
    std::vector<std::uint32_t> block_begin, block_end; // cells of each grid
    const std::uint32_t* y_buckets; // triangle codes
    // Bucket b is y_buckets[bucket_start[b] .. bucket_start[b + 1]), its span classes from 15
    // down to 1; class c starts at class_begin[16 b + c] and ends where class c − 1 starts
    // (class_begin[16 b] is the end of the bucket).
    const std::uint32_t* bucket_start; // height + 1 entries
    const std::uint32_t* class_begin;  // 16 · height entries
    std::size_t max_active;            // most triangles active on one line (never exceeded)
    Rect rect;
    int width, height;
    std::uint32_t grid_count; // blocks + 1 (the clip box)
    std::uint32_t clip_grid;
    bool clip;
    const std::uint8_t* cell_flags; // kInvertedCell, kFlatCell per cell
    // Depth difference (pixel units) below which crossings count as one place when the walk
    // looks for overlapping cells: rounding of coincident faces, not overlap.
    double z_tolerance;
    std::size_t max_fragments; // per worker and scan line: the frame-bytes budget's share
    unsigned workers;
    OpticalModel model;
    const TransferFunction* tf;
    const Medium* medium; // per-grid media (ScanlineOptions::medium), or null
    const Camera* camera;
    Image* image;
};

// Forced inline for the few small functions run once per crossing, which GCC leaves as calls.
#if defined(__GNUC__) || defined(__clang__)
#define SCANLINE_INLINE inline __attribute__((always_inline))
#else
#define SCANLINE_INLINE inline
#endif

inline void prefetch(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

class Worker {
public:
    Worker(const FrameContext& ctx, WorkerBuffers& buffers) : ctx_(ctx), b_(buffers), decode_(*ctx.mesh) {
        b_.active.clear();
        b_.active.reserve(ctx.max_active);
        b_.merged.reserve(ctx.max_active);
        b_.xcount.assign(static_cast<std::size_t>(ctx.width) + 1, 0);
        b_.inside.assign(ctx.grid_count, 0);
        b_.segment.assign(ctx.grid_count, GridSegment{});
        b_.seen.assign(ctx.grid_count, -1);
        b_.walks.assign(ctx.grid_count, SurfaceWalk{});
        cursor_ = 0;
    }

    void process_line(int y);

    std::size_t crossings = 0;
    std::size_t lost = 0;

private:
    // Fetches triangle `code` with its vertices sorted bottom to top. Codes ascend along a
    // bucket's span class, so the grid is found by moving a cursor.
    void fetch(std::uint32_t code, ScanTriangle& t);
    // Appends the triangles of y_buckets[begin, end) still active on line y.
    void load_active(std::uint32_t begin, std::uint32_t end, int y);
    // Prefetches what fetch() will read for the bucket entries ahead of `i` in [i, end).
    void prefetch_ahead(const std::uint32_t* codes, std::uint32_t i, std::uint32_t end) const;
    SVertex vertex(const ScreenPoint& p) const; // with q = s·w
    void update_active(int y);
    // Cuts t with scan line yc: appends one fragment per covered pixel.
    void add_fragments(const ScanTriangle& t, double yc);
    // Walks pixel (x, y)'s crossings in depth order (§2.4 Figure 6).
    void shade_pixel(int x, int y, const Fragment* frags, std::size_t n);
    // Counts the crossing (depth z, code id) in the grid's walk; throws fx::Error when the ray
    // has been inside two cells of the grid at once (or fewer than none) over more than
    // rounding's worth of depth. `z_of(k)` gives the depth of crossing k.
    template <class DepthOf>
    void walk_surface(SurfaceWalk& w, std::uint32_t grid, std::size_t k, bool toggles, bool enters, std::uint32_t id,
                      const DepthOf& z_of, int x, int y) const;
    [[noreturn]] void report_overlap(const SurfaceWalk& w, std::uint32_t grid, int x, int y) const;

    const FrameContext& ctx_;
    WorkerBuffers& b_;
    int current_line_ = -1;
    std::size_t cursor_ = 0; // block of the last fetched mesh triangle
    TriangleDecoder decode_;
};

SVertex Worker::vertex(const ScreenPoint& p) const {
    const double z = p.z;
    return SVertex{p.x, p.y, z, static_cast<double>(p.s) * ctx_.geo->depth.w(z)};
}

void Worker::prefetch_ahead(const std::uint32_t* codes, std::uint32_t i, std::uint32_t end) const {
    // Three stages along the bucket: the cell's connectivity offset far ahead, its point ids
    // nearer, the face's points nearest (each stage reads what the previous one fetched).
    // Most triangles are used once per frame, so their loads would otherwise wait on memory
    // one after another.
    constexpr std::uint32_t kFar = 24, kMid = 12, kNear = 6;
    const CellMesh& mesh = *ctx_.mesh;
    if (i + kFar < end && !is_extra(codes[i + kFar])) {
        const std::uint32_t cell = code_index(codes[i + kFar]);
        prefetch(&mesh.cell_offsets[cell]);
        prefetch(&mesh.cell_types[cell]);
    }
    if (i + kMid < end && !is_extra(codes[i + kMid])) prefetch(mesh.cell_vertices(code_index(codes[i + kMid])));
    if (i + kNear < end && !is_extra(codes[i + kNear])) {
        const std::uint32_t code = codes[i + kNear];
        const std::uint32_t cell = code_index(code);
        const CellFace& face = cell_faces(mesh.cell_types[cell])[(code >> 2) & 7];
        const std::uint32_t* cv = mesh.cell_vertices(cell);
        const ScreenPoint* points = ctx_.geo->points.data();
        for (int k = 0; k < face.count; ++k) prefetch(points + cv[face.v[k]]);
    }
}

// True when the triangle winds counter-clockwise on screen (y up): its outward side faces
// the eye, so a ray crossing it enters the cell.
inline bool counter_clockwise(const ScreenPoint v[3]) {
    const double area = (double(v[1].x) - v[0].x) * (double(v[2].y) - v[0].y) -
                        (double(v[1].y) - v[0].y) * (double(v[2].x) - v[0].x);
    return area > 0.0;
}

void Worker::fetch(std::uint32_t code, ScanTriangle& t) {
    const FrameGeometry& geo = *ctx_.geo;
    t.id = code;
    t.toggles = code_toggles(code);
    if (!is_extra(code)) {
        const std::uint32_t* ids = decode_(code);
        for (int i = 0; i < 3; ++i) t.v[i] = geo.points[ids[i]];
        const std::uint32_t cell = code_index(code);
        if (cell < ctx_.block_begin[cursor_]) cursor_ = 0;
        while (cell >= ctx_.block_end[cursor_]) ++cursor_;
        t.grid = static_cast<std::uint32_t>(cursor_);
        t.enters = counter_clockwise(t.v) != ((ctx_.cell_flags[cell] & kInvertedCell) != 0);
    } else {
        const ExtraTriangle& e = geo.extra_triangles[code_index(code)];
        for (int i = 0; i < 3; ++i) t.v[i] = geo.extra_vertices[e.v[i]];
        t.grid = e.grid;
        t.enters = e.facing == scanline::Facing::Enters || counter_clockwise(t.v) != (e.facing == scanline::Facing::Reversed);
    }
    sort_bottom_to_top(t.v);
    t.key = t.v[0].z + t.v[1].z + t.v[2].z;
}

void Worker::load_active(std::uint32_t begin, std::uint32_t end, int y) {
    const std::uint32_t* ids = ctx_.y_buckets;
    cursor_ = 0;
    for (std::uint32_t i = begin; i < end; ++i) {
        prefetch_ahead(ids, i, end);
        ActiveTriangle a;
        fetch(ids[i], a.tri);
        a.last_row = std::min(last_center_before(a.tri.v[2].y), ctx_.rect.row_hi);
        if (a.last_row >= y) b_.active.push_back(a);
    }
}

void Worker::update_active(int y) {
    // Remove finished triangles, keeping the nearer() order.
    std::vector<ActiveTriangle>& active = b_.active;
    active.erase(std::remove_if(active.begin(), active.end(), [y](const ActiveTriangle& a) { return a.last_row < y; }),
                 active.end());
    const std::size_t kept = active.size();
    // Buckets of lines skipped since this worker's last line (taken by other workers) and of
    // line y itself. A triangle of bucket b covers lines b .. b + span − 1, so only the span
    // classes ≥ y − b + 1 (a prefix of the bucket) are still active on line y: exactly those
    // are read, class 15 (15 lines or more) with a check. Bucket y's one-line class is cut
    // directly by process_line().
    for (int b = current_line_ + 1; b <= y; ++b) {
        const int need = std::max(y - b + 1, 2);
        const std::size_t cls = static_cast<std::size_t>(std::min(need, kSpanClasses - 1));
        const std::uint32_t* begin = ctx_.class_begin + static_cast<std::size_t>(b) * kSpanClasses;
        load_active(ctx_.bucket_start[b], begin[cls - 1], y);
    }
    current_line_ = y;
    if (active.size() > kept) { // the new ones sorted, then merged into the kept ones
        const auto by_depth = [](const ActiveTriangle& a, const ActiveTriangle& c) { return nearer(a.tri, c.tri); };
        std::sort(active.begin() + static_cast<std::ptrdiff_t>(kept), active.end(), by_depth);
        std::vector<ActiveTriangle>& merged = b_.merged;
        merged.resize(active.size());
        std::merge(active.begin(), active.begin() + static_cast<std::ptrdiff_t>(kept),
                   active.begin() + static_cast<std::ptrdiff_t>(kept), active.end(), merged.begin(), by_depth);
        active.swap(merged);
    }
}

void Worker::add_fragments(const ScanTriangle& t, double yc) {
    const LineSpan span = line_span(t.v, yc, ctx_.rect);
    const int first = span.first, last = span.last;
    if (first > last) return; // no pixel centre in [x_l, x_r): most triangle lines end here
    const ScreenPoint& v0 = t.v[0];
    const ScreenPoint& v2 = t.v[2];
    const ScreenPoint& p = yc < t.v[1].y ? t.v[0] : t.v[1];
    const ScreenPoint& q = yc < t.v[1].y ? t.v[1] : t.v[2];
    const double xa = span.xa, xb = span.xb, inv_a = span.inv_a, inv_b = span.inv_b;
    const double xl = std::min(xa, xb), xr = std::max(xa, xb);
    const SVertex s0 = vertex(v0), s2 = vertex(v2), sp = vertex(p), sq = vertex(q);
    const double za = interpolate(s0.z, s2.z, s0.y, s2.y, inv_a, yc);
    const double qa = interpolate(s0.q, s2.q, s0.y, s2.y, inv_a, yc);
    const double zb = interpolate(sp.z, sq.z, sp.y, sq.y, inv_b, yc);
    const double qb = interpolate(sp.q, sq.q, sp.y, sq.y, inv_b, yc);
    const bool a_left = xa <= xb;
    const double zl = a_left ? za : zb, zr = a_left ? zb : za;
    const double ql = a_left ? qa : qb, qr = a_left ? qb : qa;
    const double inv_width = 1.0 / (xr - xl);
    if (b_.fragments.size() + static_cast<std::size_t>(last - first + 1) > ctx_.max_fragments) {
        throw Error("scan-line renderer: " + over_limit(Limit::FrameBytes, (b_.fragments.size() + std::size_t(last - first + 1)) *
                                                                            kFragmentBytes * ctx_.workers,
                                                        "scan line " + std::to_string(static_cast<int>(yc)) + "'s " +
                                                            with_commas(b_.fragments.size()) + " crossings"));
    }
    PixelFragment pf;
    pf.f.id = t.id;
    pf.f.grid = t.grid;
    pf.f.toggles = t.toggles;
    pf.f.enters = t.enters;
    // interpolate() at the pixel centres xc: xl ≤ xc < xr, and only the first centre can be
    // xl, so the others take its general expression directly (the same values).
    const double zr_w = zr * inv_width, zl_w = zl * inv_width, qr_w = qr * inv_width, ql_w = ql * inv_width;
    for (int x = first; x <= last; ++x) {
        const double xc = x + 0.5;
        if (x == first && xc == xl) {
            pf.f.z = zl;
            pf.f.q = ql;
        } else {
            pf.f.z = zr_w * (xc - xl) + zl_w * (xr - xc);
            pf.f.q = qr_w * (xc - xl) + ql_w * (xr - xc);
        }
        pf.x = x;
        b_.fragments.push_back(pf);
        ++b_.xcount[x + 1];
    }
}

void Worker::process_line(int y) {
    update_active(y);
    const double yc = y + 0.5;
    std::vector<PixelFragment>& frags = b_.fragments;
    std::vector<std::uint32_t>& xcount = b_.xcount;
    frags.clear();
    std::fill(xcount.begin(), xcount.end(), 0u);
    // X-buckets (§2.2): every crossing of a triangle with a pixel ray on this line, the
    // active list and the line's one-line triangles merged in nearer() order.
    const std::uint32_t* ids = ctx_.y_buckets;
    const std::uint32_t* classes = ctx_.class_begin + static_cast<std::size_t>(y) * kSpanClasses;
    const std::uint32_t one_line_end = classes[0];
    std::vector<ScanTriangle>& one = b_.one_line;
    one.resize(one_line_end - classes[1]);
    cursor_ = 0;
    for (std::uint32_t i = classes[1]; i < one_line_end; ++i) {
        prefetch_ahead(ids, i, one_line_end);
        fetch(ids[i], one[i - classes[1]]);
    }
    std::sort(one.begin(), one.end(), nearer);
    const std::vector<ActiveTriangle>& active = b_.active;
    std::size_t i = 0, j = 0;
    for (; i < active.size() && j < one.size();) {
        if (nearer(one[j], active[i].tri)) add_fragments(one[j++], yc);
        else add_fragments(active[i++].tri, yc);
    }
    for (; i < active.size(); ++i) add_fragments(active[i].tri, yc);
    for (; j < one.size(); ++j) add_fragments(one[j], yc);
    if (frags.empty()) return;
    // Counting sort by pixel; then each pixel's X-bucket in depth order, ties by id, so that
    // equal depths order the same way whichever thread renders the line.
    const int width = ctx_.width;
    for (int x = 0; x < width; ++x) xcount[x + 1] += xcount[x];
    std::vector<Fragment>& sorted = b_.sorted;
    sorted.resize(frags.size());
    // A running cursor per pixel: afterwards xcount[x] is the end of pixel x's bucket, i.e.
    // the start of pixel x + 1's.
    for (const PixelFragment& pf : frags) sorted[xcount[pf.x]++] = pf.f;
    std::uint32_t begin = 0;
    for (int x = 0; x < width; ++x) {
        const std::uint32_t stop = xcount[x];
        if (stop == begin) continue;
        Fragment* k = sorted.data() + begin;
        const std::size_t n = stop - begin;
        scanline::sort_by_depth(k, n, b_.scratch, b_.runs);
        shade_pixel(x, y, k, n);
        begin = stop;
    }
}

void Worker::shade_pixel(int x, int y, const Fragment* frags, std::size_t n) {
    const DepthMap& dm = ctx_.geo->depth;
    std::vector<Crossing>& cross = b_.cross;
    std::vector<int>& next_same = b_.next_same;
    std::vector<int>& seen = b_.seen;
    std::vector<std::uint8_t>& inside = b_.inside;
    std::vector<std::uint32_t>& inside_list = b_.inside_list;
    crossings += n;
    const double inv_cos = dm.inv_cos(x + 0.5, y + 0.5);
    const TransferFunction& tf = *ctx_.tf;
    SegmentColor acc;
    glm::dvec3 sum(0.0);
    // Per-grid media: the pixel's ray in the world, a span from screen depth z over `length`.
    RaySpan ray;
    if (ctx_.medium) {
        const Ray r = ctx_.camera->pixel_ray(x + 0.5, y + 0.5, ctx_.width, ctx_.height);
        ray.origin = r.origin, ray.dir = r.direction;
    }
    auto span_at = [&](double z, double length) {
        ray.t_front = dm.eye_depth(z) * inv_cos;
        ray.t_back = ray.t_front + length;
        return ray;
    };
    // One medium between front scalar sf and back scalar sb over `length`, grid `grid` from
    // screen depth z on.
    auto integrate = [&](double sf, double sb, double length, std::uint32_t grid, double z) {
        if (ctx_.medium) {
            const SpanVolume v{grid, sf, sb};
            acc = composite(acc, ctx_.medium->integrate_span(&v, 1, span_at(z, length)));
            return;
        }
        switch (ctx_.model) {
        case OpticalModel::EmissionAbsorption: acc = composite(acc, emission_absorption(tf, sf, sb, length)); break;
        case OpticalModel::Emission: sum += emission_integral(tf, sf, sb, length); break;
        case OpticalModel::Maximum: sum = glm::max(sum, segment_maximum(tf, sf, sb)); break;
        }
    };
    auto write = [&]() {
        glm::vec4& out = ctx_.image->at(x, y);
        if (ctx_.model == OpticalModel::EmissionAbsorption) {
            out = glm::vec4(glm::vec3(acc.color), static_cast<float>(acc.alpha));
        } else {
            // Emitted light has no upper bound (extinction up to 1e32 over a mesh of 1e18):
            // the float image saturates at its largest value rather than turning infinite.
            out = glm::vec4(glm::vec3(glm::min(sum, glm::dvec3(std::numeric_limits<float>::max()))), 0.0f);
        }
    };
    auto scalar = [&](const Fragment& f) { return f.q * (1.0 / dm.w(f.z)); }; // as Crossing::s

    bool one_grid = !ctx_.clip;
    if (ctx_.grid_count > 2) // more than one block (and the clip box's grid)
        for (std::size_t k = 1; k < n && one_grid; ++k) one_grid = frags[k].grid == frags[0].grid;
    if (one_grid) {
        // The common case, the general walk below reduced to one grid: every segment runs
        // from a crossing of the grid to the next one.
        bool in = false;
        double s_front = scalar(frags[0]);
        SurfaceWalk walk;
        const auto z_of = [frags](std::size_t k) { return frags[k].z; };
        if (!ctx_.medium && ctx_.model == OpticalModel::EmissionAbsorption) {
            // Each crossing's place in the transfer function is looked up once, for both
            // segments that share it (the same colours as integrate() gives). The colour
            // weights of one-piece segments, most of the work, are computed two segments at a
            // time (piece_weights_2: two independent series side by side): a one-piece segment
            // waits for the next, and the segments between them (rare) wait with it, so that
            // colours are still composited in depth order.
            TransferSample samples[2]; // the segment's front and back, taking turns
            int front = 0;
            bool have_front = false;
            scanline::PendingSegment pending{};
            bool waiting = false;
            std::vector<SegmentColor>& held_back = b_.held_back;
            held_back.clear();
            auto release = [&](const SegmentColor& first, const SegmentColor* second) {
                acc = composite(acc, first);
                for (const SegmentColor& c : held_back) acc = composite(acc, c);
                held_back.clear();
                if (second) acc = composite(acc, *second);
                waiting = false;
            };
            for (std::size_t k = 0; k < n; ++k) {
                walk_surface(walk, frags[0].grid, k, frags[k].toggles, frags[k].enters, frags[k].id, z_of, x, y);
                if (k + 1 == n) break;
                const double s_back = scalar(frags[k + 1]);
                if (frags[k].toggles) in = !in;
                bool have_back = false;
                if (in) {
                    const double length = dm.eye_delta(frags[k].z, frags[k + 1].z) * inv_cos;
                    if (length > 0.0) {
                        TransferSample& f = samples[front];
                        TransferSample& b = samples[front ^ 1];
                        if (!have_front) f = transfer_sample(tf, s_front, f.up);
                        b = transfer_sample(tf, s_back, f.up);
                        have_back = true;
                        double ra, rb;
                        if (!one_piece_rates(f, b, length, ra, rb)) {
                            const SegmentColor c = emission_absorption(tf, f, b, length);
                            if (waiting) held_back.push_back(c);
                            else acc = composite(acc, c);
                        } else if (!waiting) {
                            pending = scanline::PendingSegment{ra, rb, f.c, b.c};
                            waiting = true;
                        } else {
                            const double a2[2] = {pending.a, ra}, b2[2] = {pending.b, rb};
                            detail::PieceWeights w[2];
                            detail::piece_weights_2(a2, b2, w);
                            const SegmentColor second = detail::one_piece_with(ra, rb, f.c, b.c, w[1]);
                            release(detail::one_piece_with(pending.a, pending.b, pending.c0, pending.c1, w[0]), &second);
                        }
                    }
                }
                if (have_back) front ^= 1;
                have_front = have_back;
                s_front = s_back;
            }
            if (waiting) {
                release(detail::one_piece_with(pending.a, pending.b, pending.c0, pending.c1,
                                               detail::piece_weights(pending.a, pending.b)),
                        nullptr);
            }
            write();
            return;
        }
        for (std::size_t k = 0; k < n; ++k) {
            walk_surface(walk, frags[0].grid, k, frags[k].toggles, frags[k].enters, frags[k].id, z_of, x, y);
            if (k + 1 == n) break;
            const double s_back = scalar(frags[k + 1]);
            if (frags[k].toggles) in = !in;
            if (in) {
                const double length = dm.eye_delta(frags[k].z, frags[k + 1].z) * inv_cos;
                if (length > 0.0) integrate(s_front, s_back, length, frags[k].grid, frags[k].z);
            }
            s_front = s_back;
        }
        write();
        return;
    }

    cross.resize(n);
    next_same.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Fragment& f = frags[k];
        const double inv_w = 1.0 / dm.w(f.z);
        cross[k] = Crossing{f.z, f.q * inv_w, inv_w, f.grid, f.id, f.toggles != 0, f.enters != 0};
    }
    // Next crossing of the same grid, for segments that other grids' crossings split.
    for (std::size_t k = n; k-- > 0;) {
        const std::uint32_t g = cross[k].grid;
        next_same[k] = seen[g];
        seen[g] = static_cast<int>(k);
    }
    for (std::size_t k = 0; k < n; ++k) seen[cross[k].grid] = -1;

    bool clip_in = !ctx_.clip;
    inside_list.clear();

    // Each grid's current segment, from its crossing a to its next crossing b. Inside it the
    // scalar is linear in eye depth: at crossing j, s = s_a + (s_b − s_a)·u with
    // u = Δz_e(a→j)/Δz_e(a→b) = (z_j − z_a)·w(z_b) / ((z_b − z_a)·w(z_j)) (§5's depth map;
    // w = 1 for orthographic views), exact at a and b.
    std::vector<GridSegment>& segment = b_.segment;
    auto scalar_at = [&](const GridSegment& g, std::size_t j) {
        if (j == g.a) return g.s_a;
        if (j == g.b) return cross[j].s;
        return g.s_a + g.ds * ((cross[j].z - g.z_a) * g.scale * cross[j].inv_w);
    };

    std::vector<SurfaceWalk>& walks = b_.walks;
    const auto z_of = [&cross](std::size_t k) { return cross[k].z; };
    for (std::size_t k = 0; k < n; ++k) {
        const Crossing& c = cross[k];
        if (c.grid != ctx_.clip_grid) walk_surface(walks[c.grid], c.grid, k, c.toggles, c.enters, c.id, z_of, x, y);
        if (c.toggles) {
            if (c.grid == ctx_.clip_grid) {
                clip_in = !clip_in;
            } else if (inside[c.grid]) {
                inside[c.grid] = 0;
                inside_list.erase(std::find(inside_list.begin(), inside_list.end(), c.grid));
            } else {
                inside[c.grid] = 1;
                inside_list.push_back(c.grid);
            }
        }
        {
            GridSegment& g = segment[c.grid];
            const int b = next_same[k];
            g.a = k;
            g.b = b < 0 ? kNoCrossing : static_cast<std::size_t>(b);
            g.z_a = c.z;
            g.s_a = c.s;
            if (b >= 0) {
                const Crossing& e = cross[static_cast<std::size_t>(b)];
                g.ds = e.s - c.s;
                g.scale = e.z > c.z ? 1.0 / ((e.z - c.z) * e.inv_w) : 0.0;
            }
        }
        if (k + 1 == n || !clip_in || inside_list.empty()) continue;
        const double length = dm.eye_delta(c.z, cross[k + 1].z) * inv_cos;
        if (!(length > 0.0)) continue;

        if (inside_list.size() == 1) {
            const GridSegment& g = segment[inside_list[0]];
            if (g.b == kNoCrossing) { ++lost; continue; }
            integrate(scalar_at(g, k), scalar_at(g, k + 1), length, inside_list[0], c.z);
            continue;
        }
        if (ctx_.medium) { // several media over this span: fx/medium.hpp mixes them
            std::vector<SpanVolume>& spans = b_.span_volumes;
            spans.clear();
            for (std::uint32_t gi : inside_list) {
                const GridSegment& g = segment[gi];
                if (g.b == kNoCrossing) { ++lost; continue; }
                spans.push_back(SpanVolume{gi, scalar_at(g, k), scalar_at(g, k + 1)});
            }
            acc = composite(acc, ctx_.medium->integrate_span(spans.data(), spans.size(), span_at(c.z, length)));
            continue;
        }
        // Several grids over this span: their media add (see the header).
        double tau = 0.0;
        glm::dvec3 weighted(0.0);
        for (std::uint32_t gi : inside_list) {
            const GridSegment& g = segment[gi];
            if (g.b == kNoCrossing) { ++lost; continue; }
            const double sf = scalar_at(g, k), sb = scalar_at(g, k + 1);
            switch (ctx_.model) {
            case OpticalModel::EmissionAbsorption: {
                const SegmentColor seg = emission_absorption(tf, sf, sb, length);
                tau += seg.optical_depth;
                if (seg.alpha > 0.0) weighted += seg.color * (seg.optical_depth / seg.alpha);
                break;
            }
            case OpticalModel::Emission: sum += emission_integral(tf, sf, sb, length); break;
            case OpticalModel::Maximum: sum = glm::max(sum, segment_maximum(tf, sf, sb)); break;
            }
        }
        if (ctx_.model == OpticalModel::EmissionAbsorption && tau > 0.0) {
            SegmentColor mixed;
            mixed.optical_depth = tau;
            mixed.alpha = -std::expm1(-tau);
            mixed.color = weighted * (mixed.alpha / tau);
            acc = composite(acc, mixed);
        }
    }
    for (std::uint32_t g : inside_list) inside[g] = 0;
    for (std::size_t k = 0; k < n; ++k) walks[cross[k].grid] = SurfaceWalk{};
    write();
}

template <class DepthOf>
SCANLINE_INLINE void Worker::walk_surface(SurfaceWalk& w, std::uint32_t grid, std::size_t k, bool toggles, bool enters, std::uint32_t id,
                          const DepthOf& z_of, int x, int y) const {
    if (w.bad_from >= 0) {
        // Inside two cells (or fewer than none) from crossing bad_from to this one: more than
        // rounding (coincident faces of neighbouring cells with their own points) is overlap.
        const double za = z_of(static_cast<std::size_t>(w.bad_from)), zb = z_of(k);
        if (zb - za > 1e-5 * (std::abs(za) + std::abs(zb)) + ctx_.z_tolerance) report_overlap(w, grid, x, y);
    }
    if (toggles) {
        w.count += enters ? 1 : -1;
        if (w.count == 0 || w.count == 1) {
            w.bad_from = -1;
        } else if (w.bad_from < 0) {
            w.bad_from = static_cast<int>(k);
            w.bad_count = w.count;
            w.bad_id = id;
        }
    }
    if (w.bad_from < 0) {
        w.last = id;
        w.last_entered = toggles && enters;
    }
}

void Worker::report_overlap(const SurfaceWalk& w, std::uint32_t grid, int x, int y) const {
    auto name = [](std::uint32_t id) {
        return is_extra(id) ? std::string("a cell cut by the near plane") : "cell " + std::to_string(code_index(id));
    };
    const std::string pixel = "the ray through pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
    std::string what;
    if (w.bad_count > 1 && w.last != ~0u) {
        what = w.last_entered ? name(w.bad_id) + " and " + name(w.last) + " overlap (" + pixel + " is inside both at once)"
                              : name(w.bad_id) + " overlaps " + name(w.last) + " or a neighbour of it (" + pixel +
                                    " is inside two cells at once)";
    } else if (w.bad_count > 1) {
        what = name(w.bad_id) + " overlaps another cell (" + pixel + " is inside two cells at once)";
    } else {
        what = pixel + " leaves " + name(w.bad_id) + " without having entered it: the block's surface is not closed "
                       "there, or its cells overlap";
    }
    throw Error("scan-line renderer: block " + std::to_string(grid) + ": " + what +
                "; the scan-line reference integrates a block only where its cells do not overlap: fix the mesh "
                "(`cellfx info` lists duplicate cells), or give overlapping parts blocks of their own, whose media add");
}

} // namespace

ScanlineRenderer::ScanlineRenderer(const CellMesh& mesh) try : mesh_(mesh) {
    const std::vector<CellShape> shapes = check_renderable(mesh, "scan-line renderer");
    if (mesh.cell_count() > kMaxCells) {
        throw Error("scan-line renderer: the mesh has " + std::to_string(mesh.cell_count()) +
                    " cells; at most 2^27 (134217728) are supported");
    }
    cell_flags_.resize(mesh.cell_count(), 0);
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        cell_flags_[c] = shapes[c] == CellShape::Inverted ? kInvertedCell : shapes[c] == CellShape::Flat ? kFlatCell : 0;
    }
    const FaceTopology topo = build_face_topology(mesh);
    const std::vector<CellOverlap> overlaps = find_overlapping_cells(mesh, topo, shapes);
    if (!overlaps.empty()) {
        throw Error("scan-line renderer: " + describe_overlap(overlaps[0]) +
                    (overlaps.size() > 1 ? " (and " + with_commas(overlaps.size() - 1) + " more pairs)" : std::string()) +
                    "; the scan-line reference integrates a block only where its cells do not overlap: fix the mesh, "
                    "or give overlapping parts blocks of their own, whose media add");
    }
    std::vector<std::uint32_t> block_of(mesh.cell_count(), 0);
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const Block& blk = mesh.blocks[b];
        for (std::uint32_t c = blk.first_cell; c < blk.first_cell + blk.cell_count && c < mesh.cell_count(); ++c) {
            block_of[c] = static_cast<std::uint32_t>(b);
        }
    }
    std::size_t estimate = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) estimate += 2 * cell_face_count(mesh.cell_types[c]);
    codes_.reserve(estimate / 2 + 64);
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const Block& blk = mesh.blocks[b];
        const std::size_t c_end = std::min<std::size_t>(blk.first_cell + blk.cell_count, mesh.cell_count());
        for (std::size_t c = blk.first_cell; c < c_end; ++c) {
            if (cell_flags_[c] & kFlatCell) continue; // no medium, and its faces would only toggle twice
            const CellFace* faces = cell_faces(mesh.cell_types[c]);
            for (int f = 0; f < cell_face_count(mesh.cell_types[c]); ++f) {
                const std::uint32_t slot = topo.first_face[c] + static_cast<std::uint32_t>(f);
                const std::uint32_t nb = topo.neighbour[slot];
                // A grid surface: no neighbour in this block (a flat neighbour is none). A face
                // shared inside the block is emitted once, by its lower slot.
                const bool surface = nb == FaceTopology::kBoundary || block_of[topo.slot_cell[nb]] != b ||
                                     (cell_flags_[topo.slot_cell[nb]] & kFlatCell);
                if (!surface && slot > nb) continue;
                const int halves = faces[f].count == 4 ? 2 : 1;
                for (int h = 0; h < halves; ++h) codes_.push_back(mesh_code(c, f, h, surface));
                if (surface) surface_triangles_ += static_cast<std::size_t>(halves);
            }
        }
        blocks_.push_back(CellRange{blk.first_cell, static_cast<std::uint32_t>(c_end)});
    }
    codes_.shrink_to_fit();
    bounds_ = mesh_bounds(mesh);
} catch (const std::bad_alloc&) {
    throw Error("scan-line renderer: out of memory building the triangle table of " + with_commas(mesh.cell_count()) +
                " cells (the mesh-cells limit bounds what is tried; lower it, or free memory)");
}

std::size_t ScanlineRenderer::memory_bytes() const {
    return codes_.capacity() * sizeof(std::uint32_t) + blocks_.capacity() * sizeof(CellRange) + cell_flags_.capacity();
}

Image ScanlineRenderer::render(const Camera& camera, int width, int height, const ScalarField& field,
                               const TransferFunction& tf, const ScanlineOptions& options,
                               ScanlineStats* stats) const {
    try {
        return render_frame(camera, width, height, field, tf, options, stats);
    } catch (const std::bad_alloc&) {
        throw Error("scan-line renderer: out of memory rendering a " + std::to_string(width) + "x" + std::to_string(height) +
                    " frame of " + with_commas(codes_.size()) + " triangles (lower the frame-bytes limit to be told " +
                    "before allocating, or free memory)");
    }
}

Image ScanlineRenderer::render_frame(const Camera& camera, int width, int height, const ScalarField& field,
                                     const TransferFunction& tf_in, const ScanlineOptions& options,
                                     ScanlineStats* stats) const {
    const auto t_start = std::chrono::steady_clock::now();
    if (width < 1 || height < 1 || width > 65534 || height > 65534) {
        throw Error("scan-line renderer: image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside 1..65534");
    }
    check_limit(Limit::ImagePixels, std::uint64_t(width) * std::uint64_t(height),
                "scan-line renderer: a " + std::to_string(width) + "x" + std::to_string(height) + " image");
    check_scalar_field(mesh_, field, "scan-line renderer");
    camera.validate("scan-line renderer: camera");
    if (camera.projection) {
        throw Error("scan-line renderer: a camera with an explicit projection matrix (Camera::from_matrices) is "
                    "not supported; describe it by fov or ortho height");
    }
    if (options.clip_box && options.clip_box->empty()) throw Error("scan-line renderer: empty clip box");
    const TransferFunction tf = tf_in.normalized() ? tf_in.rescaled(scalar_range(field).lo, scalar_range(field).hi)
                                                   : tf_in;
    unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    threads = std::min(threads, 256u);
    if (options.lines_per_task < 0) throw Error("scan-line renderer: lines_per_task must not be negative");
    if (options.medium && options.medium->volumes().size() != mesh_.blocks.size())
        throw Error("scan-line renderer: the medium has " + std::to_string(options.medium->volumes().size()) +
                    " volumes for " + std::to_string(mesh_.blocks.size()) + " grids (one per block)");
    if (options.medium && options.model != OpticalModel::EmissionAbsorption)
        throw Error("scan-line renderer: per-grid media need the emission-absorption model");
    // The frame's fixed buffers (§4.3's components), checked against the frame-bytes budget
    // before any is allocated; what is left bounds each worker's fragments per scan line.
    const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
    const std::uint64_t fixed = 16 * std::uint64_t(mesh_.point_count()) + 7 * std::uint64_t(codes_.size()) +
                                (128 * std::uint64_t(threads + 1) + 72) * std::uint64_t(height) + 16 * pixels +
                                4 * std::uint64_t(width + 1) * threads;
    const std::uint64_t frame_budget = limit_value(resource_limits(), Limit::FrameBytes);
    if (fixed > frame_budget) {
        throw Error(over_limit(Limit::FrameBytes, fixed,
                               "scan-line renderer: a " + std::to_string(width) + "x" + std::to_string(height) +
                                   " frame of " + with_commas(codes_.size()) + " triangles"));
    }
    const std::size_t max_fragments = static_cast<std::size_t>((frame_budget - fixed) / threads / kFragmentBytes);

    // The buffers of an earlier frame, or new ones when another render() holds them.
    std::unique_ptr<FrameBuffers> buffers;
    {
        std::lock_guard<std::mutex> lock(spare_mutex_);
        buffers = std::move(spare_);
    }
    if (!buffers) buffers = std::make_unique<FrameBuffers>();
    FrameBuffers& fb = *buffers;

    // ---- 1. points to screen space, depth in pixels (§5)
    FrameGeometry geo;
    geo.mesh = &mesh_;
    geo.view = camera.view_matrix();
    geo.near = camera.clipping_near(bounds_.empty() ? 0.0 : glm::length(bounds_.size()));
    DepthMap& dm = geo.depth;
    dm.ortho = camera.orthographic();
    dm.cx = 0.5 * width;
    dm.cy = 0.5 * height;
    const double center_depth = bounds_.empty() ? 1.0 : -(geo.view * glm::dvec4(bounds_.center(), 1.0)).z;
    if (dm.ortho) {
        dm.f = height / camera.ortho_height;
        dm.zr = center_depth;
    } else {
        dm.f = 0.5 * height / std::tan(0.5 * glm::radians(camera.fov_y_degrees));
        dm.zr = std::max(center_depth, geo.near);
    }
    const std::size_t point_count = mesh_.point_count();
    geo.points.swap(fb.points);
    geo.points.resize(point_count);
    const float* scalars = field.values.data();
    std::vector<std::size_t> behind_per_thread(threads, 0);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = point_count * t / threads, hi = point_count * (t + 1) / threads;
        const glm::dmat4& v = geo.view;
        std::size_t behind = 0;
        for (std::size_t i = lo; i < hi; ++i) {
            const glm::dvec3 e = glm::dvec3(v * glm::dvec4(mesh_.points[i], 1.0));
            const double ze = -e.z;
            ScreenPoint& s = geo.points[i];
            s.s = scalars[i];
            if (ze < geo.near) {
                s.x = s.y = 0.0f;
                s.z = static_cast<float>(scanline::kBehind);
                ++behind;
            } else {
                const double k = dm.ortho ? dm.f : dm.f / ze;
                s.x = static_cast<float>(dm.cx + k * e.x);
                s.y = static_cast<float>(dm.cy + k * e.y);
                s.z = static_cast<float>(dm.to_screen(ze));
            }
        }
        behind_per_thread[t] = behind;
    });
    std::size_t behind_points = 0;
    for (std::size_t b : behind_per_thread) behind_points += b;
    const double t_transform = seconds_since(t_start);
    const auto t_buckets_start = std::chrono::steady_clock::now();

    // ---- 2. screen rectangle that can see the clip box, caps, the clip box's polygons
    Rect rect{0, height - 1, 0, width - 1};
    const std::uint32_t clip_grid = static_cast<std::uint32_t>(mesh_.blocks.size());
    std::size_t cap_triangles = 0;
    if (options.clip_box) {
        const Bounds& box = *options.clip_box;
        for (int i = 0; i < 8; ++i) {
            geo.box_corners[i] = glm::dvec3((i == 1 || i == 2 || i == 5 || i == 6) ? box.hi.x : box.lo.x,
                                            (i == 2 || i == 3 || i == 6 || i == 7) ? box.hi.y : box.lo.y,
                                            i >= 4 ? box.hi.z : box.lo.z);
        }
        const auto base = static_cast<std::uint32_t>(point_count);
        bool all_in_front = true;
        for (std::uint32_t i = 0; i < 8; ++i) all_in_front = all_in_front && !geo.behind(base + i);
        if (all_in_front) {
            double xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;
            for (std::uint32_t i = 0; i < 8; ++i) {
                const Vertex v = geo.project(base + i);
                xlo = std::min(xlo, v.x), xhi = std::max(xhi, v.x), ylo = std::min(ylo, v.y), yhi = std::max(yhi, v.y);
            }
            // Inclusive on both sides: conservative.
            rect.row_lo = std::max(rect.row_lo, first_center_at_or_after(ylo));
            rect.row_hi = std::min(rect.row_hi, static_cast<int>(std::floor(std::clamp(yhi, -1e9, 1e9) - 0.5)));
            rect.col_lo = std::max(rect.col_lo, first_center_at_or_after(xlo));
            rect.col_hi = std::min(rect.col_hi, static_cast<int>(std::floor(std::clamp(xhi, -1e9, 1e9) - 0.5)));
        }
        const std::uint32_t box_ids[8] = {base, base + 1, base + 2, base + 3, base + 4, base + 5, base + 6, base + 7};
        std::uint32_t box_tris[12][3];
        int nt = 0;
        const CellFace* faces = cell_faces(CellType::Hexahedron);
        for (int f = 0; f < 6; ++f) nt += triangulate_face(faces[f], box_ids, &box_tris[nt]);
        for (int i = 0; i < nt; ++i) geo.add_clipped_triangle(box_tris[i], clip_grid, true, scanline::Facing::Winding);
        if (!all_in_front) cap_triangles += geo.add_cap(&box_tris[0][0], nt, clip_grid);
    }
    if (behind_points > 0) {
        // Caps of the cells the near plane cuts.
        std::vector<std::uint32_t> tris;
        for (std::size_t b = 0; b < mesh_.blocks.size(); ++b) {
            const Block& blk = mesh_.blocks[b];
            const std::size_t c_end = std::min<std::size_t>(blk.first_cell + blk.cell_count, mesh_.cell_count());
            for (std::size_t c = blk.first_cell; c < c_end; ++c) {
                if (cell_flags_[c] & kFlatCell) continue;
                const CellType type = mesh_.cell_types[c];
                const std::uint32_t* cv = mesh_.cell_vertices(c);
                const int nv = cell_vertex_count(type);
                int n_behind = 0;
                for (int i = 0; i < nv; ++i) n_behind += geo.behind(cv[i]) ? 1 : 0;
                if (n_behind == 0 || n_behind == nv) continue;
                tris.clear();
                const CellFace* faces = cell_faces(type);
                for (int f = 0; f < cell_face_count(type); ++f) {
                    std::uint32_t tri[2][3];
                    const int n = triangulate_face(faces[f], cv, tri);
                    for (int i = 0; i < n; ++i) tris.insert(tris.end(), tri[i], tri[i] + 3);
                }
                cap_triangles += geo.add_cap(tris.data(), static_cast<int>(tris.size() / 3), static_cast<std::uint32_t>(b));
            }
        }
    }

    // ---- 3. Y-buckets, pass 1: per-thread counts and bucket_clip_info (§3, Figure 7). Each
    // bucket is ordered by the number of scan lines its triangles cover, longest first, so
    // that a worker that skipped lines reads exactly the triangles still active (see
    // Worker::update_active) and one-line triangles (a third of a large mesh's) never enter
    // an active list.
    const std::size_t base_triangles = codes_.size();
    const std::size_t H = static_cast<std::size_t>(height);
    const std::size_t slots = threads + 1; // per thread, then the per-frame extra triangles
    auto count_index = [&](int span, std::size_t slot, std::size_t row) {
        return (static_cast<std::size_t>(span) * slots + slot) * H + row;
    };
    fb.clip_info.resize(base_triangles);
    fb.span_class.resize((base_triangles + 15) / 16);
    fb.counts.assign(kSpanClasses * slots * H, 0);
    // Thread ranges start on multiples of 64 so that each thread writes whole words of
    // span_class.
    auto split = [&](unsigned t) {
        return t == threads ? base_triangles : (base_triangles * t / threads) & ~std::size_t(63);
    };
    std::vector<std::vector<std::uint32_t>> straddling(threads);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = split(t), hi = split(t + 1);
        std::uint16_t* clip_info = fb.clip_info.data();
        std::uint32_t* count = fb.counts.data();
        std::uint64_t word = 0;
        TriangleDecoder decode(mesh_);
        for (std::size_t i = lo; i < hi; ++i) {
            const std::uint32_t* tri = decode(codes_[i]);
            const ScreenPoint& a = geo.points[tri[0]];
            const ScreenPoint& b = geo.points[tri[1]];
            const ScreenPoint& c = geo.points[tri[2]];
            clip_info[i] = kDropped;
            const bool a_behind = a.z == scanline::kBehind, b_behind = b.z == scanline::kBehind,
                       c_behind = c.z == scanline::kBehind;
            if (a_behind || b_behind || c_behind) {
                if (!(a_behind && b_behind && c_behind)) straddling[t].push_back(static_cast<std::uint32_t>(i));
            } else {
                const double xs[3] = {a.x, b.x, c.x}, ys[3] = {a.y, b.y, c.y};
                const Rows rows = rows_of(xs, ys, rect);
                if (rows.first >= 0) {
                    clip_info[i] = static_cast<std::uint16_t>(rows.first);
                    const int span = span_class(rows);
                    word |= std::uint64_t(span) << (4 * (i % 16));
                    ++count[count_index(span, t, static_cast<std::size_t>(rows.first))];
                }
            }
            if (i % 16 == 15 || i + 1 == hi) {
                fb.span_class[i / 16] = word;
                word = 0;
            }
        }
    });
    // Triangles cut by the near plane: clipped pieces become extra triangles.
    std::size_t near_clipped = 0;
    for (unsigned t = 0; t < threads; ++t) {
        for (std::uint32_t i : straddling[t]) {
            const std::uint32_t code = codes_[i];
            const std::uint32_t cell = code_index(code);
            std::size_t b = 0;
            while (cell >= blocks_[b].end) ++b;
            TriangleDecoder decode(mesh_);
            geo.add_clipped_triangle(decode(code), static_cast<std::uint32_t>(b), code_toggles(code),
                                     (cell_flags_[cell] & kInvertedCell) ? scanline::Facing::Reversed : scanline::Facing::Winding);
            ++near_clipped;
        }
    }
    const std::size_t extra_count = geo.extra_triangles.size();
    if (extra_count >= kMaxCells) {
        throw Error("scan-line renderer: " + std::to_string(extra_count) +
                    " near-plane and clip-box triangles in one frame; at most 2^27 are supported");
    }
    std::vector<Rows> extra_rows(extra_count);
    for (std::size_t i = 0; i < extra_count; ++i) {
        const ExtraTriangle& e = geo.extra_triangles[i];
        const ScreenPoint& a = geo.extra_vertices[e.v[0]];
        const ScreenPoint& b = geo.extra_vertices[e.v[1]];
        const ScreenPoint& c = geo.extra_vertices[e.v[2]];
        const double xs[3] = {a.x, b.x, c.x}, ys[3] = {a.y, b.y, c.y};
        extra_rows[i] = rows_of(xs, ys, rect);
        if (extra_rows[i].first >= 0) {
            ++fb.counts[count_index(span_class(extra_rows[i]), threads, static_cast<std::size_t>(extra_rows[i].first))];
        }
    }
    // Offsets (Figure 7): bucket-major, then span class from long to short, then thread.
    // Within one class of a bucket the ids ascend (threads own ascending id ranges, extra
    // triangles come last).
    fb.offsets.resize(kSpanClasses * slots * H);
    fb.bucket_start.resize(H + 1);
    fb.class_begin.resize(kSpanClasses * H);
    std::uint32_t total = 0;
    for (std::size_t b = 0; b < H; ++b) {
        fb.bucket_start[b] = total;
        for (int span = kSpanClasses - 1; span >= 1; --span) {
            fb.class_begin[b * kSpanClasses + static_cast<std::size_t>(span)] = total;
            for (std::size_t t = 0; t < slots; ++t) {
                fb.offsets[count_index(span, t, b)] = total;
                total += fb.counts[count_index(span, t, b)];
            }
        }
        fb.class_begin[b * kSpanClasses] = total; // end of the bucket
    }
    fb.bucket_start[H] = total;
    // Per line, the triangles it cuts: those of buckets b ≤ y that cover at least y − b + 1
    // lines (class 15 counted as lasting to the end). The multi-line part is the most an
    // active list can hold, reserved up front so the lists never grow by doubling; the whole
    // is the work estimate the scan lines are shared out by.
    std::size_t max_active = 0;
    std::vector<double> work_before(H + 1, 0.0); // estimated work of lines [0, y)
    {
        auto class_count = [&](std::size_t b, int span) {
            const std::uint32_t* c = fb.class_begin.data() + b * kSpanClasses;
            return static_cast<std::size_t>(c[span - 1] - c[span]);
        };
        std::size_t long_so_far = 0;
        for (std::size_t y = 0; y < H; ++y) {
            long_so_far += class_count(y, kSpanClasses - 1);
            std::size_t n = long_so_far;
            for (std::size_t b = y >= kSpanClasses - 2 ? y - (kSpanClasses - 2) : 0; b <= y; ++b) {
                for (int span = std::max<int>(static_cast<int>(y - b) + 1, 2); span < kSpanClasses - 1; ++span) {
                    n += class_count(b, span);
                }
            }
            max_active = std::max(max_active, n);
            // + 1: a line with no triangle still costs a little.
            work_before[y + 1] = work_before[y] + static_cast<double>(n + class_count(y, 1)) + 1.0;
        }
    }
    // Pass 2: the same triangles, placed with the offsets.
    fb.y_buckets.resize(total);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = split(t), hi = split(t + 1);
        std::uint32_t* offsets = fb.offsets.data();
        const std::uint16_t* clip_info = fb.clip_info.data();
        std::uint32_t* y_buckets = fb.y_buckets.data();
        for (std::size_t i = lo; i < hi; ++i) {
            if (clip_info[i] == kDropped) continue;
            const int span = static_cast<int>((fb.span_class[i / 16] >> (4 * (i % 16))) & 15);
            y_buckets[offsets[count_index(span, t, clip_info[i])]++] = codes_[i];
        }
    });
    for (std::size_t i = 0; i < extra_count; ++i) {
        if (extra_rows[i].first < 0) continue;
        const auto row = static_cast<std::size_t>(extra_rows[i].first);
        fb.y_buckets[fb.offsets[count_index(span_class(extra_rows[i]), threads, row)]++] =
            extra_code(i, geo.extra_triangles[i].toggles);
    }
    const double t_buckets = seconds_since(t_buckets_start);
    const auto t_scan_start = std::chrono::steady_clock::now();

    // ---- 4. scan lines
    Image image(width, height);
    FrameContext ctx;
    ctx.geo = &geo;
    ctx.mesh = &mesh_;
    for (const CellRange& r : blocks_) {
        ctx.block_begin.push_back(r.begin);
        ctx.block_end.push_back(r.end);
    }
    ctx.y_buckets = fb.y_buckets.data();
    ctx.bucket_start = fb.bucket_start.data();
    ctx.class_begin = fb.class_begin.data();
    ctx.max_active = max_active;
    ctx.rect = rect;
    ctx.width = width;
    ctx.height = height;
    ctx.grid_count = clip_grid + 1;
    ctx.clip_grid = clip_grid;
    ctx.clip = options.clip_box.has_value();
    ctx.model = options.model;
    ctx.tf = &tf;
    ctx.medium = options.medium;
    ctx.camera = &camera;
    ctx.image = &image;
    ctx.cell_flags = cell_flags_.data();
    ctx.max_fragments = max_fragments;
    ctx.workers = threads;
    {
        // The mesh's depth extent in pixel units: rounding of z is relative to it.
        const double radius = bounds_.empty() ? 0.0 : 0.5 * glm::length(bounds_.size());
        const double z_far = dm.to_screen(dm.zr + radius);
        const double z_near = dm.to_screen(std::max(dm.zr - radius, geo.near));
        ctx.z_tolerance = 1e-6 * (std::abs(z_far) + std::abs(z_near));
    }

    // Scan lines are handed out in chunks of consecutive lines through one atomic counter (no
    // lock). A worker starting a chunk re-reads the triangles still active from lines it did
    // not render, so chunks are large at first and shrink as the work left does: each takes
    // 1/(2·threads) of the estimated work left, at least 2 lines (or lines_per_task each).
    const int row_end = rect.row_hi + 1;
    // A frame watched for progress takes at most 1/32 of its lines at once, so the count moves.
    const int progress_chunk = options.progress ? std::max(2, height / 32) : row_end;
    auto chunk_end = [&](int start) {
        if (options.lines_per_task > 0) return std::min(start + options.lines_per_task, row_end);
        const double from = work_before[static_cast<std::size_t>(start)];
        const double target = from + (work_before[static_cast<std::size_t>(row_end)] - from) / (2.0 * threads);
        const auto it = std::lower_bound(work_before.begin() + start + 1, work_before.begin() + row_end, target);
        const int end = static_cast<int>(it - work_before.begin());
        return std::min({std::max(end, start + 2), start + progress_chunk, row_end});
    };
    std::atomic<int> next_line{rect.row_lo};
    if (fb.workers.size() < threads) fb.workers.resize(threads);
    std::vector<std::size_t> crossings(threads, 0), lost(threads, 0);
    run_threads(threads, [&](unsigned t) {
        try {
            Worker worker(ctx, fb.workers[t]);
            int start = next_line.load(std::memory_order_relaxed);
            while (start < row_end) {
                if (options.progress && options.progress->cancel.load(std::memory_order_relaxed)) break;
                const int end = chunk_end(start);
                if (!next_line.compare_exchange_weak(start, end, std::memory_order_relaxed)) continue;
                for (int y = start; y < end; ++y) worker.process_line(y);
                if (options.progress) options.progress->lines_done.fetch_add(std::uint64_t(end - start), std::memory_order_relaxed);
                start = next_line.load(std::memory_order_relaxed);
            }
            crossings[t] = worker.crossings;
            lost[t] = worker.lost;
        } catch (...) {
            next_line.store(row_end, std::memory_order_relaxed); // the others stop after their chunk
            throw;
        }
    });
    const double t_scan = seconds_since(t_scan_start);

    if (stats) {
        ScanlineStats& s = *stats;
        s = ScanlineStats{};
        s.threads = threads;
        s.seconds_transform = t_transform;
        s.seconds_y_buckets = t_buckets;
        s.seconds_scan = t_scan;
        s.triangles_total = base_triangles;
        s.triangles_surface = surface_triangles_;
        s.triangles_active = total;
        s.triangles_near_clipped = near_clipped;
        s.cap_triangles = cap_triangles;
        ScanlineMemory& m = s.memory;
        for (unsigned t = 0; t < threads; ++t) {
            s.crossings += crossings[t];
            s.lost_segments += lost[t];
        }
        for (const WorkerBuffers& w : fb.workers) {
            m.active_lists += w.active_bytes();
            m.x_buckets += w.x_bytes();
        }
        m.mesh = mesh_.memory_bytes();
        m.triangles = memory_bytes() + bytes(geo.extra_triangles) + bytes(geo.extra_vertices);
        m.transformed_points = bytes(geo.points);
        m.y_buckets = bytes(fb.y_buckets) + bytes(fb.bucket_start) + bytes(fb.class_begin) + bytes(fb.counts) +
                      bytes(fb.offsets);
        m.bucket_clip_info = bytes(fb.clip_info) + bytes(fb.span_class);
        m.frame_buffer = bytes(image.pixels);
    }
    geo.points.swap(fb.points);
    {
        std::lock_guard<std::mutex> lock(spare_mutex_);
        if (!spare_) spare_ = std::move(buffers);
    }
    // The lines outside the rows scanned (nothing there to draw) count as done.
    if (options.progress)
        options.progress->lines_done.fetch_add(std::uint64_t(height - std::max(0, row_end - rect.row_lo)), std::memory_order_relaxed);
    if (stats) stats->seconds_total = seconds_since(t_start);
    return image;
}

ScanlineRenderer::~ScanlineRenderer() = default;

ScanlineRenderer::ScanlineRenderer(const ScanlineRenderer& other)
    : mesh_(other.mesh_), codes_(other.codes_), blocks_(other.blocks_),
      surface_triangles_(other.surface_triangles_), cell_flags_(other.cell_flags_), bounds_(other.bounds_) {}

ScanlineRenderer::ScanlineRenderer(ScanlineRenderer&& other) noexcept
    : mesh_(other.mesh_), codes_(std::move(other.codes_)), blocks_(std::move(other.blocks_)),
      surface_triangles_(other.surface_triangles_), cell_flags_(std::move(other.cell_flags_)), bounds_(other.bounds_) {
    std::lock_guard<std::mutex> lock(other.spare_mutex_);
    spare_ = std::move(other.spare_);
}

} // namespace cellfx::fx
