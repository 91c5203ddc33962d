// Based on: Roettger & Ertl 2003, §5 (ground fog and aurora as prisms on a continuous LOD).
#include "terrain/layer_effects.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"

namespace cellfx::terrain {

namespace {

// Box of the layer between `bottom` and bottom + thickness over the field's square; empty when
// the thickness is zero everywhere (no prism can stand). Every prism vertex is a geomorphed
// blend of samples' bottoms and tops, so it lies within the range of all samples' bottoms and
// tops — a vertex without thickness of its own still belongs to its neighbours' prisms.
fx::Bounds layer_bounds(const HeightField& bottom, const HeightField& thickness) {
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    bool any = false;
    for (std::size_t k = 0; k < bottom.heights.size(); ++k) {
        any = any || thickness.heights[k] > 0.0f;
        lo = std::min(lo, double(bottom.heights[k]));
        hi = std::max(hi, double(bottom.heights[k]) + std::max(0.0f, thickness.heights[k]));
    }
    if (!any) return fx::Bounds{glm::dvec3(1.0), glm::dvec3(-1.0)};
    return {glm::dvec3(bottom.origin.x, bottom.origin.y, lo),
            glm::dvec3(bottom.origin.x + bottom.extent(), bottom.origin.y + bottom.extent(), hi)};
}

// The largest density the prisms can carry (build_layer_prisms' density rules).
double max_density(const HeightField& thickness, const LayerPrismOptions& prisms) {
    switch (prisms.density) {
    case LayerDensity::LayerHeight: return prisms.density_scale * thickness.max_height();
    case LayerDensity::LowerBorder: return prisms.density_scale;
    case LayerDensity::Noise: {
        double top = 0.0;
        for (int j = 0; j < thickness.size; ++j)
            for (int i = 0; i < thickness.size; ++i) top = std::max(top, prisms.noise(thickness.x(i), thickness.y(j)));
        return prisms.density_scale * top;
    }
    }
    return 1.0;
}

} // namespace

namespace {

fx::ScalarRange positive_range(double hi) {
    // A range of width 0 cannot carry a transfer function: keep a sliver.
    return {0.0f, float(std::max(hi, 1e-6))};
}

} // namespace

LayerEffect::LayerEffect(std::string scalar_name, const LayerEffectSettings& settings)
    : fx::Effect(std::move(scalar_name)), settings_(settings) {
    lists_mesh_changes_ = true;
}

GroundFog::GroundFog(std::shared_ptr<TerrainLod> lod, const HeightField& thickness, const LayerPrismOptions& prisms,
                     const LayerEffectSettings& settings)
    : LayerEffect(prisms.scalar_name, settings), lod_(std::move(lod)), prisms_(prisms) {
    if (!lod_ || !lod_->lod().layer()) throw fx::Error("ground fog: the terrain LOD has no fog layer");
    require_same_grid(lod_->lod().ground(), thickness, "ground fog: the fog map");
    if (prisms_.density == LayerDensity::Noise && !prisms_.noise)
        throw fx::Error("ground fog: noise density needs a noise generator");
    bounds_ = layer_bounds(lod_->lod().ground(), thickness);
    range_ = positive_range(max_density(thickness, prisms_));
}

fx::EffectChanges GroundFog::simulate(const fx::EffectView& view) {
    lod_->update(LodView::from_camera(view.camera, view.viewport_height, settings_.pixel_error, settings_.triangle_budget),
                 &lod_stats_);
    return follow_lod(*lod_, prisms_);
}

Aurora::Aurora(const AuroraLayer& layer, const LodSettings& lod, const LayerEffectSettings& settings)
    : LayerEffect("emission", settings), lod_(layer.lower_border, layer.depth, lod) {
    prisms_.density = LayerDensity::LowerBorder;
    prisms_.scalar_name = "emission";
    prisms_.fade_height = std::max(double(layer.depth.max_height()), 1.0); // reaches 0 at the deepest curtain's top
    bounds_ = layer_bounds(layer.lower_border, layer.depth);
}

fx::EffectChanges Aurora::simulate(const fx::EffectView& view) {
    lod_.update(LodView::from_camera(view.camera, view.viewport_height, settings_.pixel_error, settings_.triangle_budget),
                &lod_stats_);
    return follow_lod(lod_, prisms_);
}

fx::EffectChanges LayerEffect::follow_lod(const TerrainLod& lod, const LayerPrismOptions& options) {
    fx::EffectChanges c;
    const std::size_t listed = mesh_changes_.cells.size();
    const bool whole = mesh_changes_.whole;
    if (!tracker_.update(lod, options, mesh_, mesh_changes_, &prism_stats_)) return c;
    c.mesh = true;
    count_partial_build(mesh_changes_.whole && !whole ? mesh_.cell_count() : mesh_changes_.cells.size() - listed);
    // Noise density samples the generator once per LOD vertex that carries a prism, when the
    // vertex first does (counted here for whole builds).
    if (options.density == LayerDensity::Noise && mesh_changes_.whole && !whole) count_noise(prism_stats_.points / 2);
    return c;
}

} // namespace cellfx::terrain
