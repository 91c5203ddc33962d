// Based on: Roettger & Ertl 2003, Figure 2 and Table 4 (search light, quadratic attenuation).
#include "fx/search_light.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "effects/cone_mesh.hpp"
#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"

namespace cellfx::fx {

namespace {

constexpr double kDegrees = 0.017453292519943295; // radians per degree

void check(bool ok, const char* name, const char* what) {
    if (!ok) throw Error(std::string("search_light: ") + name + " " + what);
}

void validate(const SearchLightParams& p) {
    check_parameters(p, "search_light"); // each parameter's range (effect_parameters.cpp)
    const SweepMotion& s = p.sweep;
    check(s.amplitude_degrees == 0.0 || glm::length(s.axis) > 0.0, "sweep.axis", "must be non-zero when the light sweeps");
    check_effect_cells(max_cells(p), "search_light: segments × rings × slices");
}

effects::ConeShape shape_of(const SearchLightParams& p) {
    return {p.range, p.lens_radius, p.spread_degrees * kDegrees, p.segments, p.rings, p.slices};
}

} // namespace

std::uint64_t max_cells(const SearchLightParams& p) {
    return std::uint64_t(std::max(p.segments, 0)) * std::uint64_t(std::max(p.rings, 0)) * std::uint64_t(std::max(p.slices, 0));
}

SearchLight::SearchLight(const SearchLightParams& params) : ParametricEffect("intensity"), params_(params) { validate(params_); }

void SearchLight::set_params(const SearchLightParams& params) {
    validate(params);
    parameters_changed(change_cost(params_, params));
    params_ = params;
}

void SearchLight::set_pose(const glm::dvec3& position, const glm::dvec3& direction) {
    SearchLightParams p = params_;
    p.position = position;
    p.direction = direction;
    validate(p);
    params_ = p;
}

glm::dvec3 SearchLight::direction_at(double time) const {
    const glm::dvec3 d = glm::normalize(params_.direction);
    const SweepMotion& s = params_.sweep;
    if (s.amplitude_degrees == 0.0) return d;
    const double angle = s.amplitude_degrees * kDegrees *
                         std::sin(6.283185307179586 * time / s.period + s.phase_degrees * kDegrees);
    const glm::dmat4 r = glm::rotate(glm::dmat4(1.0), angle, glm::normalize(s.axis));
    return glm::normalize(glm::dvec3(r * glm::dvec4(d, 0.0)));
}

glm::dmat4 SearchLight::pose_at(double time) const { return frame_along(params_.position, direction_at(time)); }

MediumLight SearchLight::medium_light() const { return effects::cone_light(shape_of(params_), params_.intensity); }

Bounds SearchLight::local_bounds() const { return effects::cone_bounds(shape_of(params_)); }

void SearchLight::build_mesh() {
    effects::ConeMesh cone = effects::build_cone_mesh(shape_of(params_));
    mesh_ = std::move(cone.mesh);
    along_ = std::move(cone.along);
    across_ = std::move(cone.across);
}

void SearchLight::evaluate_scalars(double) {
    std::vector<float>& v = mesh_.scalars[0].values;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double a = 1.0 - along_[i], b = across_[i];
        v[i] = float(params_.intensity * a * a * (1.0 - b * b));
    }
}

} // namespace cellfx::fx
