// Based on: Roettger & Ertl 2003, §3 (three passes per cell through the alpha channel).
#include "projector/footprint_batches.hpp"
#include "frame_storage.hpp"

#include <algorithm>
#include <cmath>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace cellfx::fx {
namespace {

// Margin around the projected hull, in pixels. Rasterisation covers pixel centres inside the
// projected polygon; the GPU projects the same float positions with a float matrix and snaps
// vertices to 1/256 pixel, so its polygon is within ~0.01 pixel of this one. An eighth of a
// pixel is ten times that, and small enough not to merge the footprints of sub-pixel cells
// (a whole pixel of margin gave 1.5 times the batches on the blunt fin).
constexpr double kMarginPixels = 0.125;

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Convex hull (Andrew's monotone chain) of `points`, in place; collinear points dropped. One
// or two points stay as they are.
void convex_hull(std::vector<glm::dvec2>& points, std::vector<glm::dvec2>& hull) {
    std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
        return a.x < b.x || (a.x == b.x && a.y < b.y);
    });
    points.erase(std::unique(points.begin(), points.end()), points.end());
    hull.clear();
    if (points.size() < 3) {
        hull = points;
        return;
    }
    resize_kept(hull, 2 * points.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < points.size(); ++i) { // lower chain
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) { // upper chain
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);
}

// x extent of the convex polygon `hull` inside the band ya ≤ y ≤ yb; false if they miss.
bool band_extent(const std::vector<glm::dvec2>& hull, double ya, double yb, double& x0, double& x1) {
    x0 = 1e300, x1 = -1e300;
    const std::size_t n = hull.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2& a = hull[i];
        const glm::dvec2& b = hull[(i + 1) % n];
        if (a.y >= ya && a.y <= yb) x0 = std::min(x0, a.x), x1 = std::max(x1, a.x);
        for (const double y : {ya, yb}) {
            if ((a.y - y) * (b.y - y) < 0.0) {
                const double x = a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
                x0 = std::min(x0, x), x1 = std::max(x1, x);
            }
        }
    }
    return x1 >= x0;
}

} // namespace

void cell_footprints(const CellMesh& mesh, const ProjectorGeometry& geometry, const glm::dmat4& view_projection,
                     const ProjectedCells& projected, const NearCaps& caps, int width, int height, int tile,
                     CellFootprints& out) {
    const std::size_t nc = mesh.cell_count();
    out.tile = std::max(tile, 1);
    out.tiles_x = std::max(0, (width + out.tile - 1) / out.tile);
    out.tiles_y = std::max(0, (height + out.tile - 1) / out.tile);
    assign_kept(out.first_span, 1, 0u);
    out.first_span.reserve(nc + 1);
    out.spans.clear();

    // The cap polygon of each cut cell (at most one per cell).
    std::vector<std::uint32_t>& cap_of = out.cap_of;
    assign_kept(cap_of, nc, kNoBatch);
    for (std::size_t k = 0; k < caps.polygon_count(); ++k) cap_of[caps.cell[k]] = std::uint32_t(k);

    std::vector<glm::dvec2>& points = out.points;
    std::vector<glm::dvec2>& hull = out.hull;
    auto include = [&](const glm::dvec3& p) {
        const glm::dvec4 clip = view_projection * glm::dvec4(p, 1.0);
        if (!(clip.w > 0.0)) return;
        points.emplace_back((clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height);
    };
    for (std::size_t c = 0; c < nc; ++c) {
        points.clear();
        const glm::vec2 r = projected.depth_range[c];
        if (r.x + r.y > 0.0f) { // not wholly in front of the near plane (none is cut at the far plane)
            const std::uint32_t* cv = mesh.cell_vertices(c);
            for (int k = 0; k < cell_vertex_count(mesh.cell_types[c]); ++k)
                if (projected.point_depth[cv[k]] >= 0.0f) include(glm::dvec3(geometry.positions[cv[k]]));
            if (cap_of[c] != kNoBatch)
                for (std::uint32_t v = caps.first_vertex[cap_of[c]]; v < caps.first_vertex[cap_of[c] + 1]; ++v)
                    include(glm::dvec3(caps.positions[v]));
        }
        if (!points.empty()) {
            convex_hull(points, hull);
            double y_lo = 1e300, y_hi = -1e300;
            for (const glm::dvec2& p : hull) y_lo = std::min(y_lo, p.y), y_hi = std::max(y_hi, p.y);
            const double t = out.tile, m = kMarginPixels;
            const int row0 = int(std::max(0.0, std::floor((y_lo - m) / t)));
            const int row1 = int(std::min(double(out.tiles_y - 1), std::floor((y_hi + m) / t)));
            for (int row = row0; row <= row1; ++row) {
                double x0, x1;
                if (!band_extent(hull, row * t - m, (row + 1) * t + m, x0, x1)) continue;
                const double first = std::max(0.0, std::floor((x0 - m) / t));
                const double last = std::min(double(out.tiles_x - 1), std::floor((x1 + m) / t));
                if (first <= last)
                    out.spans.push_back({std::uint16_t(row), std::uint16_t(first), std::uint16_t(last)});
            }
        }
        out.first_span.push_back(std::uint32_t(out.spans.size()));
    }
}

std::uint32_t batch_footprints(const CellFootprints& footprints, std::vector<std::uint32_t>& batch_of) {
    std::vector<std::uint64_t> masks;
    return batch_footprints(footprints, batch_of, masks);
}

std::uint32_t batch_footprints(const CellFootprints& footprints, std::vector<std::uint32_t>& batch_of,
                               std::vector<std::uint64_t>& masks) {
    const std::size_t nc = footprints.cell_count();
    const std::size_t tiles_x = std::size_t(footprints.tiles_x);
    const std::size_t tiles = tiles_x * std::size_t(footprints.tiles_y);
    assign_kept(batch_of, nc, kNoBatch);
    // masks[page·tiles + tile]: bit b set when batch page·64 + b touches the tile.
    std::size_t pages = 0;
    std::uint32_t batches = 0;
    for (std::size_t c = 0; c < nc; ++c) {
        if (footprints.empty(c)) continue;
        const TileSpan* begin = footprints.spans.data() + footprints.first_span[c];
        const TileSpan* end = footprints.spans.data() + footprints.first_span[c + 1];
        for (std::size_t page = 0;; ++page) {
            if (page == pages) {
                ++pages;
                if (masks.size() < pages * tiles) resize_kept(masks, pages * tiles);
                std::fill(masks.begin() + std::ptrdiff_t(page * tiles), masks.begin() + std::ptrdiff_t(pages * tiles), 0u);
            }
            std::uint64_t* m = masks.data() + page * tiles;
            std::uint64_t used = 0;
            for (const TileSpan* s = begin; s != end && used != ~0ull; ++s)
                for (std::size_t x = s->first; x <= s->last; ++x) used |= m[s->row * tiles_x + x];
            if (used == ~0ull) continue;
            int bit = 0;
            while (used & (1ull << bit)) ++bit;
            for (const TileSpan* s = begin; s != end; ++s)
                for (std::size_t x = s->first; x <= s->last; ++x) m[s->row * tiles_x + x] |= (1ull << bit);
            batch_of[c] = std::uint32_t(page * 64 + bit);
            batches = std::max(batches, batch_of[c] + 1);
            break;
        }
    }
    return batches;
}

} // namespace cellfx::fx
