// Based on: Roettger & Ertl 2003, §5 — "each triangle of the surface mesh is treated as a base
// triangle onto which a vertically aligned prism is stacked", heights from the fog map, density
// zero at the bottom and rising with the layer height (the MIP set-up).
#include <algorithm>
#include <array>
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

namespace {

void check_options(const LayerPrismOptions& options) {
    if (options.density == LayerDensity::Noise && !options.noise)
        throw fx::Error("layer prisms: noise density needs a noise generator");
    if (!std::isfinite(options.density_scale)) throw fx::Error("layer prisms: density scale is not finite");
    if (options.density == LayerDensity::LowerBorder && !(options.fade_height > 0.0 && std::isfinite(options.fade_height)))
        throw fx::Error("layer prisms: lower-border density needs a fade height > 0 (got " +
                        std::to_string(options.fade_height) + ")");
}

// The density at the bottom of the column at `p`.
double bottom_density(const LayerPrismOptions& options, const glm::dvec3& p) {
    switch (options.density) {
    case LayerDensity::LayerHeight: return 0.0;
    case LayerDensity::Noise: {
        const double v = options.noise(p.x, p.y);
        if (!std::isfinite(v))
            throw fx::Error("layer prisms: the noise generator gave a non-finite value at (" + std::to_string(p.x) + ", " +
                            std::to_string(p.y) + ")");
        return options.density_scale * std::max(v, 0.0);
    }
    case LayerDensity::LowerBorder: return options.density_scale;
    }
    return 0.0;
}

// The density at the top of a column `t` thick whose bottom has `bottom` (the Noise density's
// top is its bottom). LayerHeight and LowerBorder are linear in the height above the bottom, so
// on a prism's side quad the density is one linear function: the picture does not depend on
// which diagonal cuts the quad, which follows the point numbering (an incremental mesh numbers
// its points otherwise than a fresh build).
double top_density(const LayerPrismOptions& options, double t, double bottom) {
    switch (options.density) {
    case LayerDensity::LayerHeight: return options.density_scale * t;
    case LayerDensity::Noise: return bottom;
    case LayerDensity::LowerBorder: return options.density_scale * std::max(0.0, 1.0 - t / options.fade_height);
    }
    return bottom;
}

} // namespace

void LayerPrismBuilder::build(const LodMesh& mesh, const LayerPrismOptions& options, fx::CellMesh& out,
                              LayerPrismStats* stats, const fx::Frustum* view) {
    check_options(options);
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
    // Bottom and top point of a LOD vertex, made on first use; top = bottom + 1.
    auto points_of = [&](std::uint32_t v) {
        if (bottom_[v] != kNone) return bottom_[v];
        const glm::dvec3 p = mesh.positions[v];
        const double t = std::max(double(mesh.thickness[v]), 0.0);
        const double lo = bottom_density(options, p), hi = top_density(options, t, lo);
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

namespace {
constexpr std::uint32_t kNoPair = std::numeric_limits<std::uint32_t>::max();
}

void LayerPrismTracker::set_points(const LayerPrismOptions& options, std::uint32_t pair, const glm::dvec3& p, double t,
                                   fx::CellMesh& out, fx::MeshChanges& changes) {
    out.points[2 * pair] = p;
    out.points[2 * pair + 1] = p + glm::dvec3(0.0, 0.0, t);
    std::vector<float>& density = out.scalars[0].values;
    density[2 * pair + 1] = float(top_density(options, t, density[2 * pair]));
    if (pair_listed_[pair] != update_count_) {
        pair_listed_[pair] = update_count_;
        changes.points.push_back(2 * pair);
        changes.points.push_back(2 * pair + 1);
    }
}

std::uint32_t LayerPrismTracker::acquire_pair(const ContinuousLod& lod, const LayerPrismOptions& options,
                                              std::uint32_t sample, fx::CellMesh& out, fx::MeshChanges& changes) {
    std::uint32_t pair = sample_pair_[sample];
    if (pair != kNoPair) {
        ++pair_refs_[pair];
        return pair;
    }
    if (!free_pairs_.empty()) {
        pair = free_pairs_.back();
        free_pairs_.pop_back();
    } else {
        pair = std::uint32_t(pair_sample_.size());
        pair_sample_.push_back(0), pair_refs_.push_back(0), pair_listed_.push_back(0);
        // Every pair may be freed at once: room kept for that (no allocation when it happens).
        if (free_pairs_.capacity() < pair_sample_.size()) free_pairs_.reserve(pair_sample_.capacity());
        out.points.resize(out.points.size() + 2);
        out.scalars[0].values.resize(out.scalars[0].values.size() + 2);
    }
    sample_pair_[sample] = pair;
    pair_sample_[pair] = sample;
    pair_refs_[pair] = 1;
    // The density at the bottom (build_layer_prisms' rules); the top's follows the thickness in
    // set_points.
    out.scalars[0].values[2 * pair] = float(bottom_density(options, lod.vertex_position(sample)));
    pair_listed_[pair] = update_count_ - 1; // written anew: listed whatever it was
    set_points(options, pair, lod.vertex_position(sample), lod.vertex_thickness(sample), out, changes);
    return pair;
}

void LayerPrismTracker::release_pair(std::uint32_t sample) {
    const std::uint32_t pair = sample_pair_[sample];
    if (--pair_refs_[pair] > 0) return;
    sample_pair_[sample] = kNoPair;
    free_pairs_.push_back(pair);
}

void LayerPrismTracker::cell_changed(std::uint32_t cell, fx::MeshChanges& changes) {
    if (cell_listed_.size() <= cell) cell_listed_.resize(std::max<std::size_t>(cell + 1, cell_listed_.size() * 3 / 2), 0u);
    if (cell_listed_[cell] == update_count_) return;
    cell_listed_[cell] = update_count_;
    changes.cells.push_back(cell);
}

void LayerPrismTracker::add_fan(const ContinuousLod& lod, const LayerPrismOptions& options, const LodFan& fan,
                                fx::CellMesh& out, fx::MeshChanges& changes) {
    // The centre and the ring once each: every triangle shares the centre and two ring vertices.
    glm::dvec3 ring[8];
    double ring_t[8];
    const glm::dvec3 a = lod.vertex_position(fan.center);
    const double ta = lod.vertex_thickness(fan.center);
    for (std::uint32_t k = 0; k < fan.count; ++k)
        ring[k] = lod.vertex_position(fan.ring[k]), ring_t[k] = lod.vertex_thickness(fan.ring[k]);
    std::uint32_t group = kNoPair;
    for (std::uint32_t k = 0; k < fan.count; ++k) {
        const std::uint32_t next = (k + 1) % fan.count;
        // build_layer_prisms' rule: thickness at the corners summing to more than a millionth
        // of the longest edge (ContinuousLod lists the fans around a vertex whose thickness
        // appears or vanishes, so a fan is looked at again when that can change). Only a thin
        // layer needs the edges measured.
        const double thickness = ta + ring_t[k] + ring_t[next];
        if (!(thickness > 0.0)) continue;
        const glm::dvec3 &b = ring[k], &c = ring[next];
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        if (!(thickness > 1e-6 * longest)) continue;
        if (group == kNoPair) {
            if (!free_groups_.empty()) {
                group = free_groups_.back();
                free_groups_.pop_back();
            } else {
                group = std::uint32_t(groups_.size());
                groups_.emplace_back();
                if (free_groups_.capacity() < groups_.size()) free_groups_.reserve(groups_.capacity());
            }
            groups_[group].count = 0;
            node_group_[fan.center] = group;
        }
        const std::uint32_t pa = acquire_pair(lod, options, fan.center, out, changes); // each prism holds its three pairs
        const std::uint32_t pb = acquire_pair(lod, options, fan.ring[k], out, changes);
        const std::uint32_t pc = acquire_pair(lod, options, fan.ring[next], out, changes);
        // LOD triangles wind counter-clockwise from above; VTK's base (0, 1, 2) must face down.
        const std::uint32_t wedge[6] = {2 * pa, 2 * pc, 2 * pb, 2 * pa + 1, 2 * pc + 1, 2 * pb + 1};
        const std::uint32_t cell = std::uint32_t(out.cell_count());
        out.add_cell(fx::CellType::Wedge, wedge);
        Group& g = groups_[group];
        cell_owner_.push_back(8 * group + g.count);
        g.cells[g.count++] = cell;
        cell_changed(cell, changes);
    }
}

void LayerPrismTracker::remove_fan(std::uint32_t node, fx::CellMesh& out, fx::MeshChanges& changes) {
    const std::uint32_t group = node_group_[node];
    if (group == kNoPair) return;
    node_group_[node] = kNoPair;
    free_groups_.push_back(group);
    // Largest cell first: the last cell, moved into a freed place, is never one still to remove.
    std::array<std::uint32_t, 8> cells = groups_[group].cells;
    const std::uint32_t n = groups_[group].count;
    for (std::uint32_t i = 1; i < n; ++i) // at most 8: insertion sort, largest first
        for (std::uint32_t j = i; j > 0 && cells[j - 1] < cells[j]; --j) std::swap(cells[j - 1], cells[j]);
    for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t x = cells[i];
        const std::uint32_t* v = out.cell_vertices(x);
        for (int k = 0; k < 3; ++k) release_pair(pair_sample_[v[k] / 2]);
        const std::uint32_t last = std::uint32_t(out.cell_count() - 1);
        if (x != last) {
            std::copy_n(out.cell_vertices(last), 6, out.cell_vertices(x));
            const std::uint32_t owner = cell_owner_[last];
            cell_owner_[x] = owner;
            groups_[owner / 8].cells[owner % 8] = x;
            cell_changed(x, changes);
        }
        out.cell_types.pop_back();
        out.cell_offsets.pop_back();
        out.connectivity.resize(out.cell_offsets.back());
        cell_owner_.pop_back();
        --out.blocks[0].cell_count;
    }
    groups_[group].count = 0;
}

void LayerPrismTracker::build_whole(const ContinuousLod& lod, const LayerPrismOptions& options, fx::CellMesh& out,
                                    fx::MeshChanges& changes) {
    out.points.clear();
    out.cell_types.clear();
    out.cell_offsets.assign(1, 0u);
    out.connectivity.clear();
    out.scalars[0].values.clear();
    out.blocks[0].cell_count = 0;
    const std::size_t samples = std::size_t(lod.ground().size) * std::size_t(lod.ground().size);
    sample_pair_.assign(samples, kNoPair);
    node_group_.assign(samples, kNoPair);
    pair_sample_.clear(), pair_refs_.clear(), free_pairs_.clear(), pair_listed_.clear();
    groups_.clear(), free_groups_.clear();
    cell_owner_.clear();
    for (std::size_t slot = 0; slot < lod.fan_count(); ++slot) add_fan(lod, options, lod.fan(slot), out, changes);
    changes.whole = true;
}

bool LayerPrismTracker::update(const TerrainLod& lod, const LayerPrismOptions& options, fx::CellMesh& out,
                               fx::MeshChanges& changes, LayerPrismStats* stats) {
    const ContinuousLod& l = lod.lod();
    if (!l.layer()) throw fx::Error("layer prisms: the LOD has no layer");
    check_options(options);
    if (built_ == &lod && version_ == lod.version()) return false;
    // One field, one block named "layer".
    out.scalars.resize(1);
    if (out.scalars[0].name != options.scalar_name) out.scalars[0].name = options.scalar_name;
    out.blocks.resize(1);
    if (out.blocks[0].name != "layer") out.blocks[0].name = "layer";
    out.blocks[0].first_cell = 0, out.blocks[0].dims = {0, 0, 0};
    ++update_count_;
    changes.oriented = true; // prisms on counter-clockwise triangles, grown upwards
    // Room for every point and cell to be listed (twice for cells: removed ones are listed before
    // they go), so a steady frame allocates nothing however much changes.
    if (changes.points.capacity() < out.points.size() + 64) changes.points.reserve(2 * out.points.size() + 64);
    if (changes.cells.capacity() < 2 * out.cell_count() + 64) changes.cells.reserve(3 * out.cell_count() + 64);
    const LodChanges& c = l.changes();
    if (built_ != &lod || version_ + 1 != lod.version() || c.full || out.scalars[0].values.size() != out.points.size()) {
        build_whole(l, options, out, changes);
    } else {
        // The fans that changed (by node: a fan that only moved slot keeps its prisms), then
        // the moved vertices.
        for (std::uint32_t node : c.fan_nodes) {
            remove_fan(node, out, changes);
            LodFan fan;
            if (l.fan_of(node, fan)) add_fan(l, options, fan, out, changes);
        }
        // Positions as vertex_position() makes them, from the values listed with the changes.
        const HeightField& ground = l.ground();
        const std::uint32_t n = std::uint32_t(ground.size);
        for (std::size_t k = 0; k < c.vertices.size(); ++k) {
            const std::uint32_t sample = c.vertices[k];
            if (sample_pair_[sample] == kNoPair) continue;
            const glm::dvec3 p(ground.x(int(sample % n)), ground.y(int(sample / n)), double(c.vertex_heights[k]));
            set_points(options, sample_pair_[sample], p, c.vertex_thicknesses[k], out, changes);
        }
        // A cell listed, then moved away and removed in the same update is gone.
        const std::size_t cells = out.cell_count();
        changes.cells.erase(std::remove_if(changes.cells.begin(), changes.cells.end(),
                                           [cells](std::uint32_t x) { return x >= cells; }),
                            changes.cells.end());
    }
    built_ = &lod;
    version_ = lod.version();
    if (stats) {
        stats->triangles = l.triangle_count();
        stats->prisms = out.cell_count();
        stats->empty = stats->triangles - std::min(stats->triangles, stats->prisms);
        stats->culled = 0;
        stats->points = 2 * (pair_sample_.size() - free_pairs_.size());
    }
    return true;
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
