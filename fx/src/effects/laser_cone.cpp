// Based on: Roettger & Ertl 2003, Figure 2 (laser cone); dust from fx::Noise (docs/noise.md).
#include "fx/laser_cone.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "effects/cone_mesh.hpp"
#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "fx/noise.hpp"

namespace cellfx::fx {

namespace {

constexpr double kDegrees = 0.017453292519943295;

void validate(const LaserConeParams& p) {
    check_parameters(p, "laser_cone"); // each parameter's range (effect_parameters.cpp)
    check_effect_cells(max_cells(p), "laser_cone: segments × slices");
}

effects::ConeShape shape_of(const LaserConeParams& p) {
    return {p.range, p.radius, p.divergence_degrees * kDegrees, p.segments, 1, p.slices};
}

bool same_shape(const LaserConeParams& a, const LaserConeParams& b) {
    return a.range == b.range && a.radius == b.radius && a.divergence_degrees == b.divergence_degrees &&
           a.segments == b.segments && a.slices == b.slices;
}

bool same_scalars(const LaserConeParams& a, const LaserConeParams& b) {
    return a.intensity == b.intensity && a.end_fade == b.end_fade && a.dust_amount == b.dust_amount &&
           a.dust_frequency == b.dust_frequency && a.dust_octaves == b.dust_octaves && a.dust_drift == b.dust_drift &&
           a.seed == b.seed;
}

} // namespace

std::uint64_t max_cells(const LaserConeParams& p) {
    return std::uint64_t(std::max(p.segments, 0)) * std::uint64_t(std::max(p.slices, 0));
}

LaserCone::LaserCone(const LaserConeParams& params) : Effect("intensity"), params_(params) { validate(params_); }

void LaserCone::set_params(const LaserConeParams& params) {
    validate(params);
    if (!same_shape(params, params_)) dirty_mesh_ = true;
    if (!same_scalars(params, params_)) dirty_scalars_ = true;
    params_ = params;
}

void LaserCone::set_pose(const glm::dvec3& position, const glm::dvec3& direction) {
    LaserConeParams p = params_;
    p.position = position;
    p.direction = direction;
    validate(p);
    params_ = p;
}

glm::dmat4 LaserCone::pose_at(double) const { return frame_along(params_.position, params_.direction); }

Bounds LaserCone::local_bounds() const { return effects::cone_bounds(shape_of(params_)); }

MediumLight LaserCone::medium_light() const { return effects::cone_light(shape_of(params_), params_.intensity); }

void LaserCone::build() {
    effects::ConeMesh cone = effects::build_cone_mesh(shape_of(params_));
    mesh_ = std::move(cone.mesh);
    along_ = std::move(cone.along);
    across_ = std::move(cone.across);
    mesh_.scalars.push_back({scalar_name(), std::vector<float>(mesh_.points.size(), 0.0f)});
    count_build();
}

void LaserCone::evaluate(double time) {
    const LaserConeParams& p = params_;
    const std::size_t n = mesh_.points.size();
    dust_.assign(n, 0.0f);
    if (dusty()) {
        dust_points_.resize(n);
        for (std::size_t i = 0; i < n; ++i) dust_points_[i] = mesh_.points[i] - p.dust_drift * time;
        Fractal f;
        f.basis = NoiseBasis::perlin;
        f.type = FractalType::turbulence;
        f.octaves = p.dust_octaves;
        f.frequency = p.dust_frequency;
        fill_points3(Noise(p.seed), f, dust_points_.data(), n, dust_.data());
        count_noise(n);
    }
    std::vector<float>& v = mesh_.scalars[0].values;
    for (std::size_t i = 0; i < n; ++i) {
        const double b = across_[i];
        const double fade = p.end_fade > 0.0 ? std::min(1.0, (1.0 - along_[i]) / p.end_fade) : 1.0;
        const double dust = 1.0 - p.dust_amount + p.dust_amount * std::min(1.0, 2.0 * double(dust_[i]));
        v[i] = float(p.intensity * (1.0 - b * b) * fade * dust);
    }
    sampled_time_ = time;
}

EffectChanges LaserCone::simulate(const EffectView& view) {
    EffectChanges changes;
    if (dirty_mesh_) {
        build();
        changes.mesh = true;
        dirty_scalars_ = true;
    }
    if (dirty_scalars_ || (animated() && view.time != sampled_time_)) {
        evaluate(view.time);
        if (!changes.mesh) {
            changes.scalars = true;
            count_scalar_update();
        }
    }
    dirty_mesh_ = dirty_scalars_ = false;
    return changes;
}

} // namespace cellfx::fx
