// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2–§3, §5
//
// The scan-line renderer: triangles from cell faces (once per mesh), then per frame
//   1. points to screen space with pixel-unit depth (§2, §5), threads over points;
//   2. near-plane clipping, caps and the clip box's virtual polygons (few, serial);
//   3. the Y-bucket array in two passes with per-thread counts and offsets (§3, Figure 7),
//      culling triangles off screen, outside the clip box's screen rectangle, or covering no
//      scan line / pixel column (at pixel centres); bucket_clip_info keeps each triangle's
//      bucket (or "dropped") between the passes;
//   4. scan lines handed to workers by an atomic counter (no lock); each worker keeps its own
//      active Y list, re-deriving it from the buckets when it skips lines, builds the X-buckets
//      of the line and sweeps the pixels with an active X list kept in depth order (§2.2);
//   5. per pixel, the crossings in depth order toggle inside/outside per grid at surface
//      triangles and the clip flag at clip polygons (§2.4 Figure 6); colour is integrated
//      between consecutive crossings with segment_integral.hpp.
#include "fx/scanline_renderer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"
#include "fx/face_topology.hpp"
#include "fx/segment_integral.hpp"
#include "scanline/scanline_frame.hpp"

namespace fx {
namespace {

using scanline::DepthMap;
using scanline::ExtraTriangle;
using scanline::FrameGeometry;
using scanline::ScreenPoint;
using scanline::Vertex;

constexpr std::uint16_t kDropped = 0xFFFF;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs fn(thread_index) on `threads` threads (the caller is thread 0) and waits.
template <class Fn>
void run_threads(unsigned threads, const Fn& fn) {
    std::vector<std::thread> pool;
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back([&fn, t]() { fn(t); });
    fn(0u);
    for (std::thread& th : pool) th.join();
}

// Smallest pixel index whose centre (i + 0.5) is ≥ v, and largest whose centre is < v.
// v is clamped first so that far off-screen values cannot overflow an int.
int first_center_at_or_after(double v) {
    v = std::clamp(v, -1.0e9, 1.0e9);
    return static_cast<int>(std::ceil(v - 0.5));
}
int last_center_before(double v) { return first_center_at_or_after(v) - 1; }

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

// The Y-bucket of a triangle, or -1 when it is dropped: off screen, outside `r`, or covering
// no scan line or no pixel column at pixel centres.
int bucket_of(const double x[3], const double y[3], const Rect& r) {
    const double ylo = std::min({y[0], y[1], y[2]}), yhi = std::max({y[0], y[1], y[2]});
    const int r0 = std::max(first_center_at_or_after(ylo), r.row_lo);
    const int r1 = std::min(last_center_before(yhi), r.row_hi);
    if (r0 > r1) return -1;
    const double xlo = std::min({x[0], x[1], x[2]}), xhi = std::max({x[0], x[1], x[2]});
    const int c0 = std::max(first_center_at_or_after(xlo), r.col_lo);
    const int c1 = std::min(last_center_before(xhi), r.col_hi);
    if (c0 > c1) return -1;
    return r0;
}

// A vertex as the scan converter uses it: q is the scalar times w (perspective-correct).
struct SVertex {
    double x, y, z, q;
};

// Table 1 of the paper: an active triangle by reference, vertices sorted bottom to top
// (ids below point_count are mesh points, the others extra vertices + point_count).
struct ActiveTriangle {
    std::uint32_t v[3];
    std::int32_t last_row;
    std::uint32_t id;
    std::uint32_t grid : 31;
    std::uint32_t toggles : 1;
};

// Table 2 of the paper: a triangle's span on the current scan line.
struct XEntry {
    double xl, xr, zl, zr, ql, qr;
    double inv_width; // 1/(xr − xl)
    int first, last; // pixel columns
    std::uint32_t id;
    std::uint32_t grid;
    bool toggles;
};

// A triangle in the active X list of a pixel, with its depth and q at that pixel.
struct Live {
    double z, q;
    std::uint32_t id;
    std::uint32_t entry;
};

struct Crossing {
    double z, s;
    std::uint32_t grid;
    bool toggles;
};

// Everything one frame needs, shared read-only by the workers.
struct FrameContext {
    const FrameGeometry* geo;
    const std::vector<std::uint32_t>* triangles;
    std::vector<std::uint32_t> range_begin; // per block: first triangle, surface end, end
    std::vector<std::uint32_t> range_surface_end;
    std::vector<std::uint32_t> range_grid;
    std::size_t base_triangles;
    const std::vector<std::uint32_t>* y_buckets;
    const std::vector<std::uint32_t>* bucket_start; // height + 1 entries
    Rect rect;
    int width, height;
    std::uint32_t grid_count; // blocks + 1 (the clip box)
    std::uint32_t clip_grid;
    bool clip;
    OpticalModel model;
    const TransferFunction* tf;
    Image* image;
};

class Worker {
public:
    explicit Worker(const FrameContext& ctx) : ctx_(ctx) {
        xcount_.assign(static_cast<std::size_t>(ctx.width) + 1, 0);
        inside_.assign(ctx.grid_count, 0);
        last_.assign(ctx.grid_count, -1);
        seen_.assign(ctx.grid_count, -1);
    }

    void process_line(int y);

    std::size_t crossings = 0;
    std::size_t lost = 0;
    std::size_t peak_active_bytes = 0;
    std::size_t peak_x_bytes = 0;

private:
    void load_triangle(std::uint32_t id, int current_row);
    SVertex vertex(std::uint32_t v) const;
    void update_active(int y);
    void shade_pixel(int x, int y, std::size_t n);

    const FrameContext& ctx_;
    int current_line_ = -1;
    std::vector<ActiveTriangle> active_;
    std::vector<XEntry> entries_;
    std::vector<std::uint32_t> xcount_; // X-bucket starts per pixel (counting sort)
    std::vector<std::uint32_t> xorder_;
    std::vector<Live> live_;
    std::vector<Crossing> cross_;
    std::vector<int> next_same_;
    std::vector<std::uint8_t> inside_;
    std::vector<int> last_, seen_;
    std::vector<std::uint32_t> inside_list_;
};

SVertex Worker::vertex(std::uint32_t v) const {
    const FrameGeometry& geo = *ctx_.geo;
    const std::size_t n = geo.points.size();
    if (v < n) {
        const ScreenPoint& p = geo.points[v];
        return SVertex{p.x, p.y, p.z, static_cast<double>(geo.scalars[v]) * geo.depth.w(p.z)};
    }
    const Vertex& p = geo.extra_vertices[v - n];
    return SVertex{p.x, p.y, p.z, p.s * geo.depth.w(p.z)};
}

void Worker::load_triangle(std::uint32_t id, int current_row) {
    const FrameGeometry& geo = *ctx_.geo;
    const auto n = static_cast<std::uint32_t>(geo.points.size());
    ActiveTriangle t;
    t.id = id;
    double y[3];
    if (id < ctx_.base_triangles) {
        const std::uint32_t* tri = ctx_.triangles->data() + 3 * static_cast<std::size_t>(id);
        for (int i = 0; i < 3; ++i) t.v[i] = tri[i], y[i] = geo.points[tri[i]].y;
        const std::size_t r = static_cast<std::size_t>(
            std::upper_bound(ctx_.range_begin.begin(), ctx_.range_begin.end(), id) - ctx_.range_begin.begin() - 1);
        t.grid = ctx_.range_grid[r];
        t.toggles = id < ctx_.range_surface_end[r];
    } else {
        const ExtraTriangle& e = geo.extra_triangles[id - ctx_.base_triangles];
        for (int i = 0; i < 3; ++i) t.v[i] = n + e.v[i], y[i] = geo.extra_vertices[e.v[i]].y;
        t.grid = e.grid;
        t.toggles = e.toggles;
    }
    // Sort the three vertices bottom to top.
    if (y[1] < y[0]) std::swap(y[0], y[1]), std::swap(t.v[0], t.v[1]);
    if (y[2] < y[1]) std::swap(y[1], y[2]), std::swap(t.v[1], t.v[2]);
    if (y[1] < y[0]) std::swap(y[0], y[1]), std::swap(t.v[0], t.v[1]);
    t.last_row = std::min(last_center_before(y[2]), ctx_.rect.row_hi);
    if (t.last_row < current_row) return;
    active_.push_back(t);
}

void Worker::update_active(int y) {
    const std::vector<std::uint32_t>& start = *ctx_.bucket_start;
    const std::vector<std::uint32_t>& ids = *ctx_.y_buckets;
    // Lines skipped since this worker's last one (taken by other workers): their buckets are
    // read too, keeping only triangles still active on line y.
    for (int b = current_line_ + 1; b <= y; ++b) {
        for (std::uint32_t i = start[b]; i < start[b + 1]; ++i) load_triangle(ids[i], y);
    }
    current_line_ = y;
    // Remove finished triangles by moving the last one into their place: the order of the
    // active list does not matter, pixels order their crossings by (depth, id).
    for (std::size_t i = 0; i < active_.size();) {
        if (active_[i].last_row < y) {
            active_[i] = active_.back();
            active_.pop_back();
        } else {
            ++i;
        }
    }
}

void Worker::process_line(int y) {
    update_active(y);
    const double yc = y + 0.5;
    // X-buckets: each active triangle's span on this line, by first pixel.
    entries_.clear();
    int xmin = ctx_.width, xmax = -1;
    for (const ActiveTriangle& t : active_) {
        const SVertex v0 = vertex(t.v[0]);
        const SVertex v1 = vertex(t.v[1]);
        const SVertex v2 = vertex(t.v[2]);
        // Figure 3: the long edge v0→v2 and the short edge below or above the middle vertex.
        const double inv_a = 1.0 / (v2.y - v0.y);
        const double xa = interpolate(v0.x, v2.x, v0.y, v2.y, inv_a, yc);
        const SVertex& p = yc < v1.y ? v0 : v1;
        const SVertex& q = yc < v1.y ? v1 : v2;
        const double inv_b = 1.0 / (q.y - p.y);
        const double xb = interpolate(p.x, q.x, p.y, q.y, inv_b, yc);
        // Cheap reject before the depth and scalar edges: no pixel centre in [x_l, x_r).
        if (first_center_at_or_after(std::min(xa, xb)) > last_center_before(std::max(xa, xb))) continue;
        const double za = interpolate(v0.z, v2.z, v0.y, v2.y, inv_a, yc);
        const double qa = interpolate(v0.q, v2.q, v0.y, v2.y, inv_a, yc);
        const double zb = interpolate(p.z, q.z, p.y, q.y, inv_b, yc);
        const double qb = interpolate(p.q, q.q, p.y, q.y, inv_b, yc);
        XEntry e;
        if (xa <= xb) {
            e.xl = xa, e.zl = za, e.ql = qa, e.xr = xb, e.zr = zb, e.qr = qb;
        } else {
            e.xl = xb, e.zl = zb, e.ql = qb, e.xr = xa, e.zr = za, e.qr = qa;
        }
        e.first = std::max(first_center_at_or_after(e.xl), ctx_.rect.col_lo);
        e.last = std::min(last_center_before(e.xr), ctx_.rect.col_hi);
        if (e.first > e.last) continue;
        e.inv_width = 1.0 / (e.xr - e.xl);
        e.id = t.id;
        e.grid = t.grid;
        e.toggles = t.toggles;
        xmin = std::min(xmin, e.first);
        xmax = std::max(xmax, e.last);
        entries_.push_back(e);
    }
    peak_active_bytes = std::max(peak_active_bytes, active_.capacity() * sizeof(ActiveTriangle) +
                                                        live_.capacity() * sizeof(Live) +
                                                        cross_.capacity() * sizeof(Crossing) +
                                                        next_same_.capacity() * sizeof(int));
    if (entries_.empty()) return;
    // Counting sort of the entries by first pixel: xorder_[xcount_[x] .. xcount_[x+1]).
    std::fill(xcount_.begin() + xmin, xcount_.begin() + xmax + 2, 0u);
    for (const XEntry& e : entries_) ++xcount_[e.first + 1];
    for (int x = xmin + 1; x <= xmax + 1; ++x) xcount_[x] += xcount_[x - 1];
    xorder_.resize(entries_.size());
    {
        // xcount_[xmin] is 0 here; fill uses a running cursor per pixel.
        std::vector<std::uint32_t>& cursor = xcount_;
        for (std::uint32_t i = 0; i < entries_.size(); ++i) xorder_[cursor[entries_[i].first]++] = i;
        // cursor[x] now holds the end of bucket x, i.e. the start of bucket x + 1.
    }
    peak_x_bytes = std::max(peak_x_bytes, entries_.capacity() * sizeof(XEntry) +
                                              xorder_.capacity() * sizeof(std::uint32_t) +
                                              xcount_.capacity() * sizeof(std::uint32_t));

    // Sweep the pixels with the active X list in depth order (§2.2).
    live_.clear();
    std::uint32_t bucket_begin = 0;
    for (int x = xmin; x <= xmax; ++x) {
        const std::uint32_t bucket_end = xcount_[x];
        const double xc = x + 0.5;
        // Drop finished entries, update depth and q of the others at this pixel.
        std::size_t keep = 0;
        for (std::size_t i = 0; i < live_.size(); ++i) {
            const XEntry& e = entries_[live_[i].entry];
            if (e.last < x) continue;
            Live l = live_[i];
            l.z = interpolate(e.zl, e.zr, e.xl, e.xr, e.inv_width, xc);
            l.q = interpolate(e.ql, e.qr, e.xl, e.xr, e.inv_width, xc);
            live_[keep++] = l;
        }
        live_.resize(keep);
        for (std::uint32_t k = bucket_begin; k < bucket_end; ++k) {
            const std::uint32_t ei = xorder_[k];
            const XEntry& e = entries_[ei];
            live_.push_back(Live{interpolate(e.zl, e.zr, e.xl, e.xr, e.inv_width, xc),
                                 interpolate(e.ql, e.qr, e.xl, e.xr, e.inv_width, xc), e.id, ei});
        }
        bucket_begin = bucket_end;
        // Insertion sort by (depth, id): nearly sorted from the previous pixel, and the id
        // makes equal depths order the same way whichever thread renders the line.
        for (std::size_t i = 1; i < live_.size(); ++i) {
            const Live l = live_[i];
            std::size_t j = i;
            while (j > 0 && (live_[j - 1].z > l.z || (live_[j - 1].z == l.z && live_[j - 1].id > l.id))) {
                live_[j] = live_[j - 1];
                --j;
            }
            live_[j] = l;
        }
        if (!live_.empty()) shade_pixel(x, y, live_.size());
    }
}

void Worker::shade_pixel(int x, int y, std::size_t n) {
    const DepthMap& dm = ctx_.geo->depth;
    cross_.resize(n);
    next_same_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Live& l = live_[k];
        const XEntry& e = entries_[l.entry];
        cross_[k] = Crossing{l.z, l.q / dm.w(l.z), e.grid, e.toggles};
    }
    crossings += n;
    // Next crossing of the same grid, for segments that other grids' crossings split.
    for (std::size_t k = n; k-- > 0;) {
        const std::uint32_t g = cross_[k].grid;
        next_same_[k] = seen_[g];
        seen_[g] = static_cast<int>(k);
    }
    for (std::size_t k = 0; k < n; ++k) seen_[cross_[k].grid] = -1;

    const double inv_cos = dm.inv_cos(x + 0.5, y + 0.5);
    bool clip_in = !ctx_.clip;
    inside_list_.clear();
    SegmentColor acc;
    glm::dvec3 sum(0.0);
    const TransferFunction& tf = *ctx_.tf;

    // Scalar of grid g (segment from its crossing a to b) at crossing k.
    auto scalar_at = [&](int a, int b, std::size_t k) {
        if (static_cast<std::size_t>(a) == k) return cross_[a].s;
        if (static_cast<std::size_t>(b) == k) return cross_[b].s;
        const double span = dm.eye_delta(cross_[a].z, cross_[b].z);
        if (!(span > 0.0)) return cross_[a].s;
        const double u = dm.eye_delta(cross_[a].z, cross_[k].z) / span;
        return cross_[a].s + (cross_[b].s - cross_[a].s) * u;
    };

    for (std::size_t k = 0; k < n; ++k) {
        const Crossing& c = cross_[k];
        if (c.toggles) {
            if (c.grid == ctx_.clip_grid) {
                clip_in = !clip_in;
            } else if (inside_[c.grid]) {
                inside_[c.grid] = 0;
                inside_list_.erase(std::find(inside_list_.begin(), inside_list_.end(), c.grid));
            } else {
                inside_[c.grid] = 1;
                inside_list_.push_back(c.grid);
            }
        }
        last_[c.grid] = static_cast<int>(k);
        if (k + 1 == n || !clip_in || inside_list_.empty()) continue;
        const double length = dm.eye_delta(c.z, cross_[k + 1].z) * inv_cos;
        if (!(length > 0.0)) continue;

        if (inside_list_.size() == 1) {
            const std::uint32_t g = inside_list_[0];
            const int a = last_[g], b = next_same_[a];
            if (b < 0) { ++lost; continue; }
            const double sf = scalar_at(a, b, k), sb = scalar_at(a, b, k + 1);
            switch (ctx_.model) {
            case OpticalModel::EmissionAbsorption: acc = composite(acc, emission_absorption(tf, sf, sb, length)); break;
            case OpticalModel::Emission: sum += emission_integral(tf, sf, sb, length); break;
            case OpticalModel::Maximum: sum = glm::max(sum, segment_maximum(tf, sf, sb)); break;
            }
            continue;
        }
        // Several grids over this span: their media add (see the header).
        double tau = 0.0;
        glm::dvec3 weighted(0.0);
        for (std::uint32_t g : inside_list_) {
            const int a = last_[g], b = next_same_[a];
            if (b < 0) { ++lost; continue; }
            const double sf = scalar_at(a, b, k), sb = scalar_at(a, b, k + 1);
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
    for (std::uint32_t g : inside_list_) inside_[g] = 0;

    glm::vec4& out = ctx_.image->at(x, y);
    if (ctx_.model == OpticalModel::EmissionAbsorption) {
        out = glm::vec4(glm::vec3(acc.color), static_cast<float>(acc.alpha));
    } else {
        out = glm::vec4(glm::vec3(sum), 0.0f);
    }
}

} // namespace

ScanlineRenderer::ScanlineRenderer(const CellMesh& mesh) : mesh_(mesh) {
    for (const glm::dvec3& p : mesh.points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw Error("scan-line renderer: point " + std::to_string(&p - mesh.points.data()) +
                        " has a non-finite coordinate");
        }
    }
    for (std::size_t i = 0; i < mesh.connectivity.size(); ++i) {
        if (mesh.connectivity[i] >= mesh.point_count()) {
            throw Error("scan-line renderer: connectivity entry " + std::to_string(i) + " is point " +
                        std::to_string(mesh.connectivity[i]) + " but the mesh has " +
                        std::to_string(mesh.point_count()) + " points");
        }
    }
    const FaceTopology topo = build_face_topology(mesh);
    std::vector<std::uint32_t> block_of(mesh.cell_count(), 0);
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const Block& blk = mesh.blocks[b];
        for (std::uint32_t c = blk.first_cell; c < blk.first_cell + blk.cell_count && c < mesh.cell_count(); ++c) {
            block_of[c] = static_cast<std::uint32_t>(b);
        }
    }
    std::size_t estimate = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) estimate += 2 * cell_face_count(mesh.cell_types[c]);
    triangles_.reserve(3 * estimate / 2 + 64);
    auto emit = [&](std::size_t c, int f) {
        const CellFace& face = cell_faces(mesh.cell_types[c])[f];
        std::uint32_t tri[2][3];
        const int n = triangulate_face(face, mesh.cell_vertices(c), tri);
        for (int i = 0; i < n; ++i) triangles_.insert(triangles_.end(), tri[i], tri[i] + 3);
    };
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const Block& blk = mesh.blocks[b];
        const std::size_t c_end = std::min<std::size_t>(blk.first_cell + blk.cell_count, mesh.cell_count());
        TriangleRange range;
        range.begin = static_cast<std::uint32_t>(triangles_.size() / 3);
        // Grid surfaces first: faces with no neighbour in this block.
        for (int pass = 0; pass < 2; ++pass) {
            for (std::size_t c = blk.first_cell; c < c_end; ++c) {
                const int faces = cell_face_count(mesh.cell_types[c]);
                for (int f = 0; f < faces; ++f) {
                    const std::uint32_t slot = topo.first_face[c] + static_cast<std::uint32_t>(f);
                    const std::uint32_t nb = topo.neighbour[slot];
                    const bool surface = nb == FaceTopology::kBoundary || block_of[topo.slot_cell[nb]] != b;
                    if (pass == 0 && surface) emit(c, f);
                    if (pass == 1 && !surface && slot < nb) emit(c, f); // shared face: once
                }
            }
            if (pass == 0) range.surface_end = static_cast<std::uint32_t>(triangles_.size() / 3);
        }
        range.end = static_cast<std::uint32_t>(triangles_.size() / 3);
        surface_triangles_ += range.surface_end - range.begin;
        ranges_.push_back(range);
    }
    triangles_.shrink_to_fit();
}

std::size_t ScanlineRenderer::memory_bytes() const {
    return triangles_.capacity() * sizeof(std::uint32_t) + ranges_.capacity() * sizeof(TriangleRange);
}

Image ScanlineRenderer::render(const Camera& camera, int width, int height, const ScalarField& field,
                               const TransferFunction& tf_in, const ScanlineOptions& options,
                               ScanlineStats* stats) const {
    const auto t_start = std::chrono::steady_clock::now();
    if (width < 1 || height < 1 || width > 65534 || height > 65534) {
        throw Error("scan-line renderer: image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside 1..65534");
    }
    if (field.values.size() != mesh_.point_count()) {
        throw Error("scan-line renderer: scalar field '" + field.name + "' has " +
                    std::to_string(field.values.size()) + " values for " + std::to_string(mesh_.point_count()) +
                    " points");
    }
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        if (!std::isfinite(field.values[i])) {
            throw Error("scan-line renderer: scalar field '" + field.name + "' value " + std::to_string(i) +
                        " is not finite");
        }
    }
    const glm::dvec3 fwd = camera.target - camera.eye;
    if (!(glm::length(fwd) > 0.0) || !(glm::length(glm::cross(fwd, camera.up)) > 0.0) ||
        !(camera.near_distance > 0.0) || (!camera.orthographic() && !(camera.fov_y_degrees > 0.0 &&
                                                                         camera.fov_y_degrees < 180.0))) {
        throw Error("scan-line renderer: degenerate camera (eye = target, up parallel to the view, near <= 0 "
                    "or fov outside (0, 180))");
    }
    if (options.clip_box && options.clip_box->empty()) throw Error("scan-line renderer: empty clip box");
    const TransferFunction tf = tf_in.normalized() ? tf_in.rescaled(scalar_range(field).lo, scalar_range(field).hi)
                                                   : tf_in;
    unsigned threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    threads = std::min(threads, 256u);
    const int lines_per_task = std::max(1, options.lines_per_task);

    // ---- 1. points to screen space, depth in pixels (§5)
    FrameGeometry geo;
    geo.mesh = &mesh_;
    geo.scalars = field.values.data();
    geo.view = camera.view_matrix();
    geo.near = camera.near_distance;
    DepthMap& dm = geo.depth;
    dm.ortho = camera.orthographic();
    dm.cx = 0.5 * width;
    dm.cy = 0.5 * height;
    const Bounds bounds = mesh_bounds(mesh_);
    const double center_depth = bounds.empty() ? 1.0 : -(geo.view * glm::dvec4(bounds.center(), 1.0)).z;
    if (dm.ortho) {
        dm.f = height / camera.ortho_height;
        dm.zr = center_depth;
    } else {
        dm.f = 0.5 * height / std::tan(0.5 * glm::radians(camera.fov_y_degrees));
        dm.zr = std::max(center_depth, camera.near_distance);
    }
    const std::size_t point_count = mesh_.point_count();
    geo.points.resize(point_count);
    std::vector<std::size_t> behind_per_thread(threads, 0);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = point_count * t / threads, hi = point_count * (t + 1) / threads;
        const glm::dmat4& v = geo.view;
        std::size_t behind = 0;
        for (std::size_t i = lo; i < hi; ++i) {
            const glm::dvec3 e = glm::dvec3(v * glm::dvec4(mesh_.points[i], 1.0));
            const double ze = -e.z;
            ScreenPoint& s = geo.points[i];
            if (ze < geo.near) {
                s = ScreenPoint{0.0, 0.0, scanline::kBehind};
                ++behind;
            } else if (dm.ortho) {
                s = ScreenPoint{dm.cx + dm.f * e.x, dm.cy + dm.f * e.y, dm.to_screen(ze)};
            } else {
                s = ScreenPoint{dm.cx + dm.f * e.x / ze, dm.cy + dm.f * e.y / ze, dm.to_screen(ze)};
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
        for (int i = 0; i < nt; ++i) geo.add_clipped_triangle(box_tris[i], clip_grid, true);
        if (!all_in_front) cap_triangles += geo.add_cap(&box_tris[0][0], nt, clip_grid);
    }
    if (behind_points > 0) {
        // Caps of the cells the near plane cuts.
        std::vector<std::uint32_t> tris;
        for (std::size_t b = 0; b < mesh_.blocks.size(); ++b) {
            const Block& blk = mesh_.blocks[b];
            const std::size_t c_end = std::min<std::size_t>(blk.first_cell + blk.cell_count, mesh_.cell_count());
            for (std::size_t c = blk.first_cell; c < c_end; ++c) {
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

    // ---- 3. Y-buckets, pass 1: per-thread counts and bucket_clip_info (§3)
    const std::size_t base_triangles = triangles_.size() / 3;
    std::vector<std::uint16_t> clip_info(base_triangles);
    const std::size_t H = static_cast<std::size_t>(height);
    std::vector<std::uint32_t> counts((threads + 1) * H, 0); // row `threads`: the extra triangles
    std::vector<std::vector<std::uint32_t>> straddling(threads);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = base_triangles * t / threads, hi = base_triangles * (t + 1) / threads;
        std::uint32_t* count = counts.data() + t * H;
        for (std::size_t i = lo; i < hi; ++i) {
            const std::uint32_t* tri = triangles_.data() + 3 * i;
            const ScreenPoint& a = geo.points[tri[0]];
            const ScreenPoint& b = geo.points[tri[1]];
            const ScreenPoint& c = geo.points[tri[2]];
            if (a.z == scanline::kBehind || b.z == scanline::kBehind || c.z == scanline::kBehind) {
                clip_info[i] = kDropped;
                if (a.z != scanline::kBehind || b.z != scanline::kBehind || c.z != scanline::kBehind) {
                    straddling[t].push_back(static_cast<std::uint32_t>(i));
                }
                continue;
            }
            const double xs[3] = {a.x, b.x, c.x}, ys[3] = {a.y, b.y, c.y};
            const int row = bucket_of(xs, ys, rect);
            if (row < 0) {
                clip_info[i] = kDropped;
                continue;
            }
            clip_info[i] = static_cast<std::uint16_t>(row);
            ++count[row];
        }
    });
    // Triangles cut by the near plane: clipped pieces become extra triangles.
    std::size_t near_clipped = 0;
    for (unsigned t = 0; t < threads; ++t) {
        for (std::uint32_t i : straddling[t]) {
            const std::size_t r = static_cast<std::size_t>(
                std::upper_bound(ranges_.begin(), ranges_.end(), i,
                                 [](std::uint32_t v, const TriangleRange& rg) { return v < rg.begin; }) -
                ranges_.begin() - 1);
            geo.add_clipped_triangle(triangles_.data() + 3 * static_cast<std::size_t>(i), static_cast<std::uint32_t>(r),
                                     i < ranges_[r].surface_end);
            ++near_clipped;
        }
    }
    const std::size_t extra_count = geo.extra_triangles.size();
    std::vector<int> extra_bucket(extra_count);
    for (std::size_t i = 0; i < extra_count; ++i) {
        const ExtraTriangle& e = geo.extra_triangles[i];
        const Vertex& a = geo.extra_vertices[e.v[0]];
        const Vertex& b = geo.extra_vertices[e.v[1]];
        const Vertex& c = geo.extra_vertices[e.v[2]];
        const double xs[3] = {a.x, b.x, c.x}, ys[3] = {a.y, b.y, c.y};
        extra_bucket[i] = bucket_of(xs, ys, rect);
        if (extra_bucket[i] >= 0) ++counts[threads * H + static_cast<std::size_t>(extra_bucket[i])];
    }
    // Offsets (Figure 7): bucket-major, thread-minor.
    std::vector<std::uint32_t> offsets((threads + 1) * H);
    std::vector<std::uint32_t> bucket_start(H + 1);
    std::uint32_t total = 0;
    for (std::size_t b = 0; b < H; ++b) {
        bucket_start[b] = total;
        for (unsigned t = 0; t <= threads; ++t) {
            offsets[t * H + b] = total;
            total += counts[t * H + b];
        }
    }
    bucket_start[H] = total;
    // Pass 2: the same triangles, placed with the offsets.
    std::vector<std::uint32_t> y_buckets(total);
    run_threads(threads, [&](unsigned t) {
        const std::size_t lo = base_triangles * t / threads, hi = base_triangles * (t + 1) / threads;
        std::uint32_t* offset = offsets.data() + t * H;
        for (std::size_t i = lo; i < hi; ++i) {
            if (clip_info[i] != kDropped) y_buckets[offset[clip_info[i]]++] = static_cast<std::uint32_t>(i);
        }
    });
    for (std::size_t i = 0; i < extra_count; ++i) {
        if (extra_bucket[i] >= 0) {
            y_buckets[offsets[threads * H + static_cast<std::size_t>(extra_bucket[i])]++] =
                static_cast<std::uint32_t>(base_triangles + i);
        }
    }
    const double t_buckets = seconds_since(t_buckets_start);
    const auto t_scan_start = std::chrono::steady_clock::now();

    // ---- 4. scan lines
    Image image(width, height);
    FrameContext ctx;
    ctx.geo = &geo;
    ctx.triangles = &triangles_;
    for (std::size_t b = 0; b < ranges_.size(); ++b) {
        ctx.range_begin.push_back(ranges_[b].begin);
        ctx.range_surface_end.push_back(ranges_[b].surface_end);
        ctx.range_grid.push_back(static_cast<std::uint32_t>(b));
    }
    ctx.base_triangles = base_triangles;
    ctx.y_buckets = &y_buckets;
    ctx.bucket_start = &bucket_start;
    ctx.rect = rect;
    ctx.width = width;
    ctx.height = height;
    ctx.grid_count = clip_grid + 1;
    ctx.clip_grid = clip_grid;
    ctx.clip = options.clip_box.has_value();
    ctx.model = options.model;
    ctx.tf = &tf;
    ctx.image = &image;

    std::atomic<int> next_task{0};
    const int tasks = (height + lines_per_task - 1) / lines_per_task;
    std::vector<std::size_t> crossings(threads, 0), lost(threads, 0), active_bytes(threads, 0), x_bytes(threads, 0);
    run_threads(threads, [&](unsigned t) {
        Worker worker(ctx);
        for (;;) {
            const int task = next_task.fetch_add(1, std::memory_order_relaxed);
            if (task >= tasks) break;
            const int y0 = std::max(task * lines_per_task, rect.row_lo);
            const int y1 = std::min((task + 1) * lines_per_task, rect.row_hi + 1);
            for (int y = y0; y < y1; ++y) worker.process_line(y);
        }
        crossings[t] = worker.crossings;
        lost[t] = worker.lost;
        active_bytes[t] = worker.peak_active_bytes;
        x_bytes[t] = worker.peak_x_bytes;
    });
    const double t_scan = seconds_since(t_scan_start);

    if (stats) {
        ScanlineStats& s = *stats;
        s = ScanlineStats{};
        s.threads = threads;
        s.seconds_transform = t_transform;
        s.seconds_y_buckets = t_buckets;
        s.seconds_scan = t_scan;
        s.seconds_total = seconds_since(t_start);
        s.triangles_total = base_triangles;
        s.triangles_surface = surface_triangles_;
        s.triangles_active = total;
        s.triangles_near_clipped = near_clipped;
        s.cap_triangles = cap_triangles;
        for (unsigned t = 0; t < threads; ++t) {
            s.crossings += crossings[t];
            s.lost_segments += lost[t];
            s.memory.active_lists += active_bytes[t];
            s.memory.x_buckets += x_bytes[t];
        }
        ScanlineMemory& m = s.memory;
        m.mesh = mesh_.memory_bytes();
        m.triangles = memory_bytes() + geo.extra_triangles.capacity() * sizeof(ExtraTriangle) +
                      geo.extra_vertices.capacity() * sizeof(Vertex);
        m.transformed_points = geo.points.capacity() * sizeof(ScreenPoint);
        m.y_buckets = (y_buckets.capacity() + bucket_start.capacity() + counts.capacity() + offsets.capacity()) *
                      sizeof(std::uint32_t);
        m.bucket_clip_info = clip_info.capacity() * sizeof(std::uint16_t);
        m.frame_buffer = image.pixels.capacity() * sizeof(glm::vec4);
    }
    return image;
}

} // namespace fx
