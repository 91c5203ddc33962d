// Based on: Roettger & Ertl 2003, §3 and Figure 2 (a campfire of 3-D Perlin noise on a hexahedral
// grid, zero-emission cells discarded); the noise is fx::Noise (docs/noise.md), 4-D for time.
#include "fx/campfire.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "fx/noise.hpp"

namespace cellfx::fx {

namespace {

void validate(const CampfireParams& p) {
    check_parameters(p, "campfire"); // each parameter's range (effect_parameters.cpp)
    check_effect_cells(max_cells(p), "campfire: cells_across² × cells_up");
}

// The envelope E (header comment) at a local point.
double envelope(const CampfireParams& p, const glm::dvec3& q) {
    const double h = q.z / p.height;
    if (!(h >= 0.0 && h < 1.0)) return 0.0;
    const double r = p.base_radius * std::pow(1.0 - h, p.taper);
    if (!(r > 0.0)) return 0.0;
    const double u2 = (q.x * q.x + q.y * q.y) / (r * r);
    return std::max(0.0, 1.0 - u2) * (1.0 - h);
}

Fractal fractal_of(const CampfireParams& p) {
    Fractal f;
    f.basis = NoiseBasis::simplex;
    f.type = FractalType::fbm;
    f.octaves = p.noise_octaves;
    f.frequency = p.noise_frequency;
    return f;
}

glm::dvec4 noise_point(const CampfireParams& p, const glm::dvec3& q, double time) {
    return {q.x, q.y, (q.z - p.rise_speed * time) / p.noise_stretch, p.flicker_rate * time / p.noise_frequency};
}

float temperature(const CampfireParams& p, double e, float n) {
    return float(std::clamp(p.intensity * e * (1.0 + p.turbulence * double(n)), 0.0, 1.0));
}

} // namespace

std::uint64_t max_cells(const CampfireParams& p) {
    return std::uint64_t(std::max(p.cells_across, 0)) * std::uint64_t(std::max(p.cells_across, 0)) *
           std::uint64_t(std::max(p.cells_up, 0));
}

Campfire::Campfire(const CampfireParams& params)
    : ParametricEffect("temperature"), params_(params) {
    validate(params_);
}

void Campfire::set_params(const CampfireParams& params) {
    validate(params);
    parameters_changed(change_cost(params_, params));
    params_ = params;
}

glm::dmat4 Campfire::pose_at(double) const { return glm::translate(glm::dmat4(1.0), params_.position); }

MediumLight Campfire::medium_light() const {
    MediumLight light;
    light.kind = MediumLight::Kind::Point;
    light.origin = glm::dvec3(0.0, 0.0, 0.35 * params_.height);
    light.core_radius = params_.base_radius;
    light.radius = 6.0 * params_.height;
    return light;
}

Bounds Campfire::local_bounds() const {
    const double r = params_.base_radius;
    return {glm::dvec3(-r, -r, 0.0), glm::dvec3(r, r, params_.height)};
}

double Campfire::temperature_at(const glm::dvec3& local, double time) const {
    const double e = envelope(params_, local);
    if (e <= 0.0) return 0.0;
    const Noise noise(params_.seed);
    const glm::dvec4 q = noise_point(params_, local, time);
    return temperature(params_, e, noise.fractal4(fractal_of(params_), q.x, q.y, q.z, q.w));
}

void Campfire::build_mesh() {
    const CampfireParams& p = params_;
    const int n = p.cells_across, nz = p.cells_up;
    const int nodes_x = n + 1;
    auto node_id = [&](int i, int j, int k) { return std::size_t((k * nodes_x + j) * nodes_x + i); };
    auto node_position = [&](int i, int j, int k) {
        return glm::dvec3(p.base_radius * (2.0 * i / n - 1.0), p.base_radius * (2.0 * j / n - 1.0), p.height * k / nz);
    };
    const std::size_t node_count = std::size_t(nodes_x) * nodes_x * (nz + 1);
    std::vector<double> e(node_count);
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) e[node_id(i, j, k)] = envelope(p, node_position(i, j, k));

    // Keep the cells with some node inside the envelope; number their nodes on first use.
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> point_of(node_count, kUnused);
    CellMesh mesh;
    mesh.begin_block("campfire");
    active_.clear();
    envelope_.clear();
    auto point = [&](int i, int j, int k) {
        const std::size_t id = node_id(i, j, k);
        if (point_of[id] == kUnused) {
            point_of[id] = std::uint32_t(mesh.points.size());
            mesh.points.push_back(node_position(i, j, k));
            if (e[id] > 0.0) {
                active_.push_back(point_of[id]);
                envelope_.push_back(e[id]);
            }
        }
        return point_of[id];
    };
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                bool inside = false;
                for (int c = 0; c < 8 && !inside; ++c)
                    inside = e[node_id(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2))] > 0.0;
                if (!inside) continue;
                // VTK hexahedron order: the bottom quad counter-clockwise seen from +z, then the top.
                const std::uint32_t v[8] = {point(i, j, k),         point(i + 1, j, k),
                                            point(i + 1, j + 1, k), point(i, j + 1, k),
                                            point(i, j, k + 1),     point(i + 1, j, k + 1),
                                            point(i + 1, j + 1, k + 1), point(i, j + 1, k + 1)};
                mesh.add_cell(CellType::Hexahedron, v);
            }
    mesh_ = std::move(mesh);
}

void Campfire::evaluate_scalars(double time) {
    noise_points_.resize(active_.size());
    noise_values_.resize(active_.size());
    for (std::size_t a = 0; a < active_.size(); ++a) noise_points_[a] = noise_point(params_, mesh_.points[active_[a]], time);
    fill_points4(Noise(params_.seed), fractal_of(params_), noise_points_.data(), noise_points_.size(), noise_values_.data());
    count_noise(active_.size());
    std::vector<float>& t = mesh_.scalars[0].values;
    for (std::size_t a = 0; a < active_.size(); ++a) t[active_[a]] = temperature(params_, envelope_[a], noise_values_[a]);
}

} // namespace cellfx::fx
