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

} // namespace

std::uint64_t max_cells(const LaserConeParams& p) {
    return std::uint64_t(std::max(p.segments, 0)) * std::uint64_t(std::max(p.slices, 0));
}

LaserCone::LaserCone(const LaserConeParams& params) : ParametricEffect("intensity"), params_(params) { validate(params_); }

void LaserCone::set_params(const LaserConeParams& params) {
    validate(params);
    parameters_changed(change_cost(params_, params));
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

void LaserCone::build_mesh() {
    effects::ConeMesh cone = effects::build_cone_mesh(shape_of(params_));
    mesh_ = std::move(cone.mesh);
    along_ = std::move(cone.along);
    across_ = std::move(cone.across);
}

void LaserCone::evaluate_scalars(double time) {
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
}

} // namespace cellfx::fx
