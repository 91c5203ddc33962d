// Helpers for the scan-line renderer tests: closed-form ray geometry, meshes built from
// boxes, and the closed-form comparison (image_check.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/image.hpp"
#include "harness/synthetic_meshes.hpp"
#include "image_check.hpp"
#include "cellfx_names.hpp"

namespace scanline_test {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Ray ∩ axis-aligned box as a parameter interval; empty when first > second.
inline std::pair<double, double> ray_box(const fx::Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi) {
    double t0 = -kInf, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
        if (ray.direction[a] == 0.0) {
            if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return {1.0, 0.0};
            continue;
        }
        double ta = (lo[a] - ray.origin[a]) / ray.direction[a];
        double tb = (hi[a] - ray.origin[a]) / ray.direction[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return {t0, t1};
}

// Ray ∩ tetrahedron (Cyrus–Beck against its four face planes).
inline std::pair<double, double> ray_tet(const fx::Ray& ray, const std::array<glm::dvec3, 4>& v) {
    double t0 = -kInf, t1 = kInf;
    static const int faces[4][4] = {{0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 3, 1}, {1, 2, 3, 0}};
    for (const auto& f : faces) {
        glm::dvec3 n = glm::cross(v[f[1]] - v[f[0]], v[f[2]] - v[f[0]]);
        if (glm::dot(n, v[f[3]] - v[f[0]]) > 0.0) n = -n; // outward
        const double denom = glm::dot(n, ray.direction);
        const double dist = glm::dot(n, v[f[0]] - ray.origin); // inside: n·(p − v0) ≤ 0
        if (denom == 0.0) {
            if (dist < 0.0) return {1.0, 0.0};
            continue;
        }
        const double t = dist / denom;
        if (denom > 0.0) t1 = std::min(t1, t); else t0 = std::max(t0, t);
    }
    return {t0, t1};
}

// Where the renderer's rays start: the near plane (eye depth near_distance).
inline double near_t(const fx::Camera& cam, const fx::Ray& ray) {
    return cam.near_distance / glm::dot(ray.direction, cam.forward());
}

// One structured block of hexahedra filling [lo, hi] with n cells per axis.
inline void append_box(fx::CellMesh& mesh, const std::string& name, const glm::dvec3& lo, const glm::dvec3& hi,
                       std::array<std::uint32_t, 3> cells) {
    fx::append_curvilinear_block(mesh, name, {cells[0] + 1, cells[1] + 1, cells[2] + 1},
                                 [lo, hi](double u, double v, double w) {
                                     return lo + (hi - lo) * glm::dvec3(u, v, w);
                                 });
}

inline fx::Image expected_image(int w, int h, const std::function<glm::vec4(int, int)>& fn) {
    fx::Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = fn(x, y);
    return img;
}

// Every channel within `tolerance` of the expected image (absolute), none beyond it, and the
// mean |difference| within `mean_tolerance` (fx_test::check_image: printed, checked, the PNGs
// written on failure). `why` says where the bound comes from.
inline verify::Difference check_close(const fx::Image& actual, const fx::Image& expected, double tolerance,
                                      const std::string& name, double mean_tolerance = kInf,
                                      const std::string& why = "closed form: double segments, the float image") {
    verify::Tolerance t = verify::same_picture(tolerance, why);
    t.mean.absolute = mean_tolerance;
    return fx_test::check_image(name, actual, expected, t);
}

} // namespace scanline_test
