// Based on: Roettger & Ertl 2003, §5 — "each triangle of the surface mesh is treated as a base
// triangle onto which a vertically aligned prism is stacked", heights from the fog map, density
// zero at the bottom and rising with the layer height (the MIP set-up).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "terrain/fog_layer.hpp"

namespace cellfx::terrain {

fx::CellMesh build_layer_prisms(const LodMesh& mesh, const LayerPrismOptions& options, LayerPrismStats* stats) {
    fx::CellMesh out;
    LayerPrismBuilder().build(mesh, options, out, stats);
    return out;
}

void LayerPrismBuilder::build(const LodMesh& mesh, const LayerPrismOptions& options, fx::CellMesh& out,
                              LayerPrismStats* stats, const fx::Frustum* view) {
    if (options.density == LayerDensity::Noise && !options.noise)
        throw fx::Error("layer prisms: noise density needs a noise generator");
    if (!std::isfinite(options.density_scale)) throw fx::Error("layer prisms: density scale is not finite");
    LayerPrismStats s;
    // Emptied, capacity kept: one field, one block named "layer".
    out.points.clear();
    out.cell_types.clear();
    out.cell_offsets.assign(1, 0u);
    out.connectivity.clear();
    out.scalars.resize(1);
    if (out.scalars[0].name != options.scalar_name) out.scalars[0].name = options.scalar_name;
    out.scalars[0].values.clear();
    std::vector<float>& density = out.scalars[0].values;
    out.blocks.resize(1);
    if (out.blocks[0].name != "layer") out.blocks[0].name = "layer";
    out.blocks[0].first_cell = 0, out.blocks[0].cell_count = 0, out.blocks[0].dims = {0, 0, 0};

    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    bottom_.assign(mesh.positions.size(), kNone);
    auto noise_at = [&](const glm::dvec3& p) {
        const double v = options.noise(p.x, p.y);
        if (!std::isfinite(v))
            throw fx::Error("layer prisms: the noise generator gave a non-finite value at (" + std::to_string(p.x) +
                            ", " + std::to_string(p.y) + ")");
        return std::max(v, 0.0);
    };
    // Bottom and top point of a LOD vertex, made on first use; top = bottom + 1.
    auto points_of = [&](std::uint32_t v) {
        if (bottom_[v] != kNone) return bottom_[v];
        const glm::dvec3 p = mesh.positions[v];
        const double t = std::max(double(mesh.thickness[v]), 0.0);
        double lo = 0.0, hi = 0.0;
        switch (options.density) {
        case LayerDensity::LayerHeight: lo = 0.0, hi = options.density_scale * t; break;
        case LayerDensity::Noise: lo = hi = options.density_scale * noise_at(p); break;
        case LayerDensity::LowerBorder: lo = options.density_scale, hi = 0.0; break;
        }
        bottom_[v] = std::uint32_t(out.points.size());
        out.points.push_back(p);
        out.points.push_back(p + glm::dvec3(0.0, 0.0, t));
        density.push_back(float(lo));
        density.push_back(float(hi));
        return bottom_[v];
    };

    for (const auto& tri : mesh.triangles) {
        ++s.triangles;
        const double ta = mesh.thickness[tri[0]], tb = mesh.thickness[tri[1]], tc = mesh.thickness[tri[2]];
        const glm::dvec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        if (!(std::max(ta, 0.0) + std::max(tb, 0.0) + std::max(tc, 0.0) > 1e-6 * longest)) {
            ++s.empty;
            continue;
        }
        if (view) {
            const glm::dvec3 lo = glm::min(glm::min(a, b), c);
            const double top = std::max({a.z + std::max(ta, 0.0), b.z + std::max(tb, 0.0), c.z + std::max(tc, 0.0)});
            if (!view->intersects(fx::Bounds{lo, glm::dvec3(std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), top)})) {
                ++s.culled;
                continue;
            }
        }
        // LOD triangles wind counter-clockwise from above; VTK's base (0, 1, 2) must face down.
        const std::uint32_t pa = points_of(tri[0]), pb = points_of(tri[1]), pc = points_of(tri[2]);
        const std::uint32_t wedge[6] = {pa, pc, pb, pa + 1, pc + 1, pb + 1};
        out.add_cell(fx::CellType::Wedge, wedge);
        ++s.prisms;
    }
    s.points = out.points.size();
    if (stats) *stats = s;
}

HeightField make_valley_fog_map(const HeightField& ground, double level, double max_thickness,
                                const HeightGenerator& modulation, double radius) {
    if (!std::isfinite(level) || !std::isfinite(max_thickness) || max_thickness < 0.0 || !std::isfinite(radius) ||
        radius < 0.0)
        throw fx::Error("valley fog map: level, max_thickness and radius must be finite, max_thickness and radius ≥ 0");
    const int n = ground.size;
    // Reference height per sample: 0, or the ground's mean over ±r samples (separable box
    // filter with running sums, clamped at the border).
    std::vector<double> reference(std::size_t(n) * std::size_t(n), 0.0);
    // A radius beyond the grid averages the whole grid; clamping first keeps the conversion to
    // int defined for any finite radius (1e300 / spacing does not fit in an int).
    const double samples = std::floor(radius / ground.spacing);
    const int r = samples >= double(n) ? n : int(samples);
    if (r > 0) {
        std::vector<double> rows(reference.size());
        auto box = [&](auto get, auto set) {
            for (int line = 0; line < n; ++line) {
                double sum = 0.0;
                int count = 0;
                for (int k = 0; k <= std::min(r, n - 1); ++k) sum += get(line, k), ++count;
                for (int k = 0; k < n; ++k) {
                    set(line, k, sum / count);
                    if (k + r + 1 < n) sum += get(line, k + r + 1), ++count;
                    if (k - r >= 0) sum -= get(line, k - r), --count;
                }
            }
        };
        box([&](int j, int i) { return double(ground.at(i, j)); },
            [&](int j, int i, double v) { rows[std::size_t(j) * n + i] = v; });
        box([&](int i, int j) { return rows[std::size_t(j) * n + i]; },
            [&](int i, int j, double v) { reference[std::size_t(j) * n + i] = v; });
    }
    HeightField fog = ground;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double m = modulation ? modulation(ground.x(i), ground.y(j)) : 0.0;
            if (!std::isfinite(m))
                throw fx::Error("valley fog map: the modulation is not finite at sample (" + std::to_string(i) + ", " +
                                std::to_string(j) + ")");
            const double top = reference[std::size_t(j) * n + i] + level + m;
            fog.at(i, j) = float(std::clamp(top - double(ground.at(i, j)), 0.0, max_thickness));
        }
    }
    return fog;
}

} // namespace cellfx::terrain
