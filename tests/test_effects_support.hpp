// Helpers for the effect, scene and embedding tests: an effect's mesh moved into the world (for
// the scan-line reference), frame comparison with the render paths' stated tolerances, cameras.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "gl_fixture.hpp"

namespace effects_test {

inline fx::Camera look(glm::dvec3 eye, glm::dvec3 target, double fov = 40.0, glm::dvec3 up = {0, 0, 1}) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = up;
    cam.fov_y_degrees = fov;
    cam.near_distance = 0.05;
    cam.far_distance = 5000.0;
    return cam;
}

// The effect's mesh with its points moved by transform(): what the world sees.
inline fx::CellMesh world_mesh(const fx::Effect& effect) {
    fx::CellMesh mesh = effect.mesh();
    const glm::dmat4& m = effect.transform();
    for (glm::dvec3& p : mesh.points) p = glm::dvec3(m * glm::dvec4(p, 1.0));
    return mesh;
}

inline fx::OpticalModel model_of(fx::RenderPath path, bool fog) {
    if (fog) return fx::OpticalModel::EmissionAbsorption;
    return path == fx::RenderPath::Mip ? fx::OpticalModel::Maximum : fx::OpticalModel::Emission;
}

struct FrameCheck {
    float peak = 0.0f;       // brightest reference channel
    float max_delta = 0.0f;
    double mean_delta = 0.0;
    double bad_fraction = 0.0; // pixels beyond the per-pixel tolerance
    bool finite = true;
};

// Tolerances per path, relative to the reference's brightest channel (`peak`), as in
// tests/test_pcp_scanline.cpp where they are derived:
//   pcp-exact, mip: both sides integrate exactly; float32 on the GPU against double on the CPU,
//     the 4096-entry tables, and pixel centres within rounding of a silhouette, which rasteriser
//     and reference may assign differently: per pixel 0.5% of peak, ≤ 1% of pixels beyond it,
//     mean ≤ 0.05% of peak.
//   pcp (classic, 8-bit): each of the ≤ N cells on a ray rounds its light and its α to 1/255 and
//     colours the trapezoid rule on κ(s): per pixel 0.5·N/255 + `classic_rel` of the pixel, ≤ 1%
//     of pixels beyond, mean ≤ 0.3·√N/255 + 2% of peak.
inline FrameCheck check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                              fx::RenderPath path, int cells_on_ray, float classic_rel = 0.15f) {
    REQUIRE(actual.width == expected.width);
    REQUIRE(actual.height == expected.height);
    FrameCheck e;
    for (const glm::vec4& p : expected.pixels) e.peak = std::max({e.peak, p.r, p.g, p.b});
    REQUIRE(e.peak > 0.0f); // the view must show something
    const bool classic = path == fx::RenderPath::Pcp;
    const float abs_tol = classic ? 0.5f * float(cells_on_ray) / 255.0f : 0.005f * e.peak;
    const float rel_tol = classic ? classic_rel : 0.0f;
    const double mean_tol = classic ? 0.3 * std::sqrt(double(cells_on_ray)) / 255.0 + 0.02 * e.peak : 0.0005 * e.peak;
    std::size_t bad = 0;
    double sum = 0.0;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        bool ok = true;
        for (int c = 0; c < 4; ++c) {
            const float a = actual.pixels[i][c], x = expected.pixels[i][c];
            if (!std::isfinite(a)) e.finite = false, ok = false;
            const float d = std::fabs(a - x);
            e.max_delta = std::max(e.max_delta, std::isfinite(d) ? d : INFINITY);
            sum += std::isfinite(d) ? d : 1e30;
            if (!(d <= abs_tol + rel_tol * std::fabs(x))) ok = false;
        }
        if (!ok) ++bad;
    }
    e.mean_delta = sum / (4.0 * double(actual.pixels.size()));
    e.bad_fraction = double(bad) / double(actual.pixels.size());
    WARN(name << " [" << fx::render_path_name(path) << "]: peak " << e.peak << ", max delta " << e.max_delta << " ("
              << 100.0 * e.max_delta / e.peak << "% of peak), mean " << 100.0 * e.mean_delta / e.peak
              << "% of peak, pixels beyond tolerance " << 100.0 * e.bad_fraction << "%");
    const bool ok = e.finite && e.bad_fraction <= 0.01 && e.mean_delta <= mean_tol;
    if (!ok) {
        INFO("images: " << fx_test::write_failure_images(name + "_" + fx::render_path_name(path), actual, expected,
                                                         10.0f / e.peak));
        CHECK(ok);
    }
    CHECK(e.finite);
    CHECK(e.bad_fraction <= 0.01);
    CHECK(e.mean_delta <= mean_tol);
    return e;
}

// The effect as the scene draws it — its local mesh, the camera moved into its frame — against
// the scan-line reference of the same mesh moved into the world, seen by the world camera.
inline FrameCheck effect_vs_scanline(const std::string& name, const fx::Effect& effect, const fx::TransferFunction& tf,
                                     const fx::Camera& camera, fx::RenderPath path, int cells_on_ray, bool fog = false,
                                     int size = 96, float classic_rel = 0.15f) {
    fx_test::gl_context();
    const fx::CellMesh world = world_mesh(effect);
    fx::ScanlineOptions so;
    so.model = model_of(path, fog);
    const fx::Image expected =
        fx::ScanlineRenderer(world).render(camera, size, size, *world.find_scalar(effect.scalar_name()), tf, so);
    fx::CellRenderer renderer(effect.mesh(), effect.scalar_name(), tf);
    fx::CellRenderOptions options;
    options.fog = fog;
    const fx::Image actual =
        renderer.render_to_image(fx::camera_in_frame(camera, effect.transform()), size, size, path, options);
    fx_test::require_no_gl_error();
    return check_frame(name, actual, expected, path, cells_on_ray, classic_rel);
}

} // namespace effects_test
