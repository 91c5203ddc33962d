// Helpers for the scan-line renderer tests: closed-form ray geometry, meshes built from
// boxes, and image comparison that writes actual/expected/diff PNGs on failure.
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
#include "scanline/synthetic_meshes.hpp"
#include "test_paths.hpp"
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

struct Difference {
    double max = 0.0;  // largest per-channel difference, at pixel (x, y)
    double mean = 0.0; // mean per-channel difference over all pixels and channels
    int x = -1, y = -1;
    glm::vec4 actual{0.0f}, expected{0.0f};
};

// Largest and mean per-channel difference; above `tolerance` (or a mean above
// `mean_tolerance`) writes NAME_actual/expected/diff.png (the diff scaled so that the
// tolerance is 1/8 of full scale).
inline Difference compare(const fx::Image& actual, const fx::Image& expected, double tolerance,
                          const std::string& name, double mean_tolerance = kInf) {
    Difference d;
    double total = 0.0;
    fx::Image diff(actual.width, actual.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const glm::vec4 a = actual.at(x, y), e = expected.at(x, y);
            double m = 0.0;
            for (int c = 0; c < 4; ++c) {
                const double diff_c = std::abs(double(a[c]) - double(e[c]));
                m = std::max(m, diff_c);
                total += diff_c;
            }
            if (!(m <= d.max)) d = Difference{m, 0.0, x, y, a, e};
            const float v = static_cast<float>(std::min(1.0, m / (8.0 * tolerance)));
            diff.at(x, y) = glm::vec4(v, v, v, 1.0f);
        }
    }
    d.mean = actual.pixels.empty() ? 0.0 : total / (4.0 * static_cast<double>(actual.pixels.size()));
    if (!(d.max <= tolerance) || !(d.mean <= mean_tolerance)) {
        auto opaque = [](fx::Image img) {
            for (glm::vec4& p : img.pixels) p.a = 1.0f;
            return img;
        };
        fx::write_png(opaque(actual), fx_test::output_path(name + "_actual.png"));
        fx::write_png(opaque(expected), fx_test::output_path(name + "_expected.png"));
        fx::write_png(diff, fx_test::output_path(name + "_diff.png"));
    }
    return d;
}

} // namespace scanline_test

// CHECKs that two images agree to `tol`, naming the worst pixel.
#define CHECK_IMAGES_CLOSE(ACTUAL_, EXPECTED_, TOL_, NAME_)                                                        \
    do {                                                                                                           \
        const scanline_test::Difference d_ = scanline_test::compare((ACTUAL_), (EXPECTED_), (TOL_), (NAME_));      \
        INFO((NAME_) << ": worst pixel (" << d_.x << ", " << d_.y << ") actual " << d_.actual.r << " "             \
                     << d_.actual.g << " " << d_.actual.b << " " << d_.actual.a << ", expected " << d_.expected.r   \
                     << " " << d_.expected.g << " " << d_.expected.b << " " << d_.expected.a);                      \
        CHECK(d_.max <= (TOL_));                                                                                   \
    } while (0)
