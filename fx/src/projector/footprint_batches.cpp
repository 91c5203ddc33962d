// Based on: Roettger & Ertl 2003, §3 (three passes per cell through the alpha channel).
#include "fx/footprint_batches.hpp"

#include <algorithm>
#include <cmath>

#include <glm/vec4.hpp>

namespace fx {

void cell_footprints(const CellMesh& mesh, const ProjectorGeometry& geometry, const ProjectorView& view,
                     const glm::dmat4& view_projection, const ProjectedCells& projected, const NearCaps& caps,
                     int width, int height, std::vector<ScreenRect>& out) {
    const std::size_t nc = mesh.cell_count();
    out.assign(nc, ScreenRect{});
    const double far_d = view.far_distance - view.near_distance;
    struct Box {
        double x0, y0, x1, y1;
    };
    std::vector<Box> box(nc, Box{1e300, 1e300, -1e300, -1e300});
    auto include = [&](std::size_t c, const glm::dvec3& p) {
        glm::dvec4 clip = view_projection * glm::dvec4(p, 1.0);
        if (!(clip.w > 0.0)) return;
        const double x = (clip.x / clip.w * 0.5 + 0.5) * width, y = (clip.y / clip.w * 0.5 + 0.5) * height;
        Box& b = box[c];
        b.x0 = std::min(b.x0, x), b.y0 = std::min(b.y0, y), b.x1 = std::max(b.x1, x), b.y1 = std::max(b.y1, y);
    };
    for (std::size_t c = 0; c < nc; ++c) {
        const glm::vec2 r = projected.depth_range[c];
        if (!(r.x + r.y > 0.0f) || r.x > far_d) continue; // wholly in front of near, or beyond far
        const std::uint32_t* cv = mesh.cell_vertices(c);
        for (int k = 0; k < cell_vertex_count(mesh.cell_types[c]); ++k) {
            if (projected.point_depth[cv[k]] >= 0.0f) include(c, glm::dvec3(geometry.positions[cv[k]]));
        }
    }
    for (std::size_t k = 0; k < caps.polygon_count(); ++k) {
        for (std::uint32_t v = caps.first_vertex[k]; v < caps.first_vertex[k + 1]; ++v)
            include(caps.cell[k], glm::dvec3(caps.positions[v]));
    }
    for (std::size_t c = 0; c < nc; ++c) {
        const Box& b = box[c];
        if (!(b.x1 >= b.x0)) continue;
        // One pixel of margin: rasterisation covers pixel centres inside the projected
        // polygon, and float vertex positions on the GPU differ from these by rounding.
        const double lo_x = std::max(b.x0 - 1.0, -1.0), lo_y = std::max(b.y0 - 1.0, -1.0);
        const double hi_x = std::min(b.x1 + 1.0, double(width)), hi_y = std::min(b.y1 + 1.0, double(height));
        ScreenRect s;
        s.x0 = std::max(0, int(std::floor(lo_x)));
        s.y0 = std::max(0, int(std::floor(lo_y)));
        s.x1 = std::min(width - 1, int(std::floor(hi_x)));
        s.y1 = std::min(height - 1, int(std::floor(hi_y)));
        out[c] = s;
    }
}

std::uint32_t batch_footprints(const std::vector<ScreenRect>& rects, int width, int height, int tile,
                               std::vector<std::uint32_t>& batch_of) {
    tile = std::max(tile, 1);
    const int tx = (width + tile - 1) / tile, ty = (height + tile - 1) / tile;
    batch_of.assign(rects.size(), kNoBatch);
    if (tx <= 0 || ty <= 0) return 0;
    // masks[page][tile]: bit b set when batch page·64 + b touches the tile.
    std::vector<std::vector<std::uint64_t>> masks;
    std::uint32_t batches = 0;
    for (std::size_t i = 0; i < rects.size(); ++i) {
        const ScreenRect& r = rects[i];
        if (r.empty()) continue;
        const int a0 = std::clamp(r.x0 / tile, 0, tx - 1), a1 = std::clamp(r.x1 / tile, 0, tx - 1);
        const int b0 = std::clamp(r.y0 / tile, 0, ty - 1), b1 = std::clamp(r.y1 / tile, 0, ty - 1);
        for (std::size_t page = 0;; ++page) {
            if (page == masks.size()) masks.emplace_back(std::size_t(tx) * ty, 0u);
            std::vector<std::uint64_t>& m = masks[page];
            std::uint64_t used = 0;
            for (int y = b0; y <= b1 && used != ~0ull; ++y)
                for (int x = a0; x <= a1; ++x) used |= m[std::size_t(y) * tx + x];
            if (used == ~0ull) continue;
            int bit = 0;
            while (used & (1ull << bit)) ++bit;
            for (int y = b0; y <= b1; ++y)
                for (int x = a0; x <= a1; ++x) m[std::size_t(y) * tx + x] |= (1ull << bit);
            batch_of[i] = std::uint32_t(page * 64 + bit);
            batches = std::max(batches, batch_of[i] + 1);
            break;
        }
    }
    return batches;
}

} // namespace fx
