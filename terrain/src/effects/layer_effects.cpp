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

// How far the camera may turn (every way) before the prisms culled for its view are built again.
constexpr double kGuardDegrees = 6.0;

double aspect_of(const fx::EffectView& v) { return double(v.viewport_width) / double(v.viewport_height); }

// The corners of the camera's view volume (perspective: near and far rectangles).
std::array<glm::dvec3, 8> frustum_corners(const fx::Camera& c, double aspect) {
    const fx::Camera::Basis b = c.basis();
    const glm::dvec3 &f = b.forward, &r = b.right, &u = b.up;
    const double ty = std::tan(glm::radians(c.fov_y_degrees) / 2.0), tx = ty * aspect;
    std::array<glm::dvec3, 8> corners;
    for (int k = 0; k < 8; ++k) {
        const double d = (k & 4) ? c.far_distance : c.near_distance;
        corners[std::size_t(k)] = c.eye + d * (f + ((k & 1) ? tx : -tx) * r + ((k & 2) ? ty : -ty) * u);
    }
    return corners;
}

} // namespace

void CulledView::set(const fx::EffectView& view) {
    const fx::Camera& c = view.camera;
    fx::Camera wide = c;
    double aspect = aspect_of(view);
    if (!c.orthographic()) {
        // Every half-angle widened by the guard; nearer near and farther far planes, so that the
        // camera's own volume lies inside while it turns by less than the guard.
        const double hy = glm::radians(c.fov_y_degrees) / 2.0, hx = std::atan(std::tan(hy) * aspect);
        const double g = glm::radians(kGuardDegrees);
        const double wy = std::min(hy + g, glm::radians(85.0)), wx = std::min(hx + g, glm::radians(85.0));
        wide.fov_y_degrees = glm::degrees(2.0 * wy);
        aspect = std::tan(wx) / std::tan(wy);
        wide.near_distance = 0.5 * c.near_distance;
        wide.far_distance = 2.0 * c.far_distance;
    }
    view_ = view;
    frustum_ = fx::Frustum(wide, aspect);
    built_ = true;
}

bool CulledView::covers(const fx::EffectView& view) const {
    if (!built_ || view.viewport_width != view_.viewport_width || view.viewport_height != view_.viewport_height) return false;
    const fx::Camera &a = view.camera, &b = view_.camera;
    if (a.orthographic() || b.orthographic())
        return a.eye == b.eye && a.target == b.target && a.up == b.up && a.ortho_height == b.ortho_height &&
               a.near_distance == b.near_distance && a.far_distance == b.far_distance;
    if (a.fov_y_degrees != b.fov_y_degrees || a.near_distance != b.near_distance || a.far_distance != b.far_distance)
        return false;
    for (const glm::dvec3& corner : frustum_corners(a, aspect_of(view))) {
        const glm::dvec3 p = corner - frustum_.origin; // the planes are relative to the eye
        for (const glm::dvec4& plane : frustum_.planes)
            if (plane.x * p.x + plane.y * p.y + plane.z * p.z + plane.w < 0.0) return false;
    }
    return true;
}

namespace {

fx::ScalarRange positive_range(double hi) {
    // A range of width 0 cannot carry a transfer function: keep a sliver.
    return {0.0f, float(std::max(hi, 1e-6))};
}

} // namespace

GroundFog::GroundFog(std::shared_ptr<TerrainLod> lod, const HeightField& thickness, const LayerPrismOptions& prisms,
                     const LayerEffectSettings& settings)
    : fx::Effect(prisms.scalar_name), lod_(std::move(lod)), prisms_(prisms), settings_(settings) {
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
    fx::EffectChanges changes;
    if (lod_->version() != built_version_ || !culled_.covers(view)) {
        culled_.set(view);
        builder_.build(lod_->mesh(), prisms_, mesh_, &prism_stats_, &culled_.frustum());
        built_version_ = lod_->version();
        count_build();
        // Noise density samples the generator once per LOD vertex that carries a prism.
        if (prisms_.density == LayerDensity::Noise) count_noise(prism_stats_.points / 2);
        changes.mesh = true;
    }
    return changes;
}

Aurora::Aurora(const AuroraLayer& layer, const LodSettings& lod, const LayerEffectSettings& settings)
    : fx::Effect("emission"), lod_(layer.lower_border, layer.depth, lod), settings_(settings) {
    prisms_.density = LayerDensity::LowerBorder;
    prisms_.scalar_name = "emission";
    bounds_ = layer_bounds(layer.lower_border, layer.depth);
}

fx::EffectChanges Aurora::simulate(const fx::EffectView& view) {
    lod_.update(LodView::from_camera(view.camera, view.viewport_height, settings_.pixel_error, settings_.triangle_budget),
                &lod_stats_);
    fx::EffectChanges changes;
    if (lod_.version() != built_version_ || !culled_.covers(view)) {
        culled_.set(view);
        builder_.build(lod_.mesh(), prisms_, mesh_, &prism_stats_, &culled_.frustum());
        built_version_ = lod_.version();
        count_build();
        changes.mesh = true;
    }
    return changes;
}

} // namespace cellfx::terrain
