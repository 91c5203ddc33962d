// Frame tests of the Absorption paths (`absorption`, `absorption-exact`) against the CPU
// scan-line reference (fx::ScanlineRenderer, EmissionAbsorption), on llvmpipe.
//
// Sorting: the centroid sort is what fx::VisibilitySort offers today; it is exact on grids of
// equal boxes (their cells are the Voronoi cells of their centres) and on some curvilinear
// views, approximate elsewhere. Every test therefore checks the renderer's own order along
// each pixel's ray, independently (ray–triangle intersections, absorption_test::check_order),
// states how many pixels it may get wrong, and compares only the pixels whose order is right.
//
// Tolerances, per flavour (relative to `peak`, the largest reference value of any channel):
//   absorption-exact — both sides integrate the same segments exactly; what is left is the
//     pre-integration table (128 scalar samples per end, 64 lengths, trilinear: ~0.1–0.5% of a
//     cell's colour where the transfer function bends inside a table cell or a cell is much
//     shorter than one length step), float32 against double, and pixel centres within
//     rounding of a silhouette, which the rasteriser and the reference may assign differently
//     (at most 1% of pixels). Per pixel 1.5% of peak, mean 0.1% of peak.
//   absorption (classic) — §II's approximations: thickness and the texture coordinates linear
//     on screen over each polygon (exact for orthographic views, off by the cell's perspective
//     foreshortening otherwise) and the polygon colour C/α interpolated linearly between
//     vertices where colour and extinction vary across the cell. Exact along vertex rays
//     (slices make colour and extinction linear there). Per pixel 6% of peak, mean 0.6%,
//     beyond-tolerance pixels at most 1%: measured values are printed (WARN) for comparison.
//   Camera inside (near plane cuts cells) and non-planar cells: modelling differences, stated
//     at each test.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "absorption_test_support.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/view_dependent_subdivision.hpp"
#include "fx/visibility_sort.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"

namespace {

struct Tolerance {
    float pixel = 0.0f;        // per channel, fraction of peak
    double mean = 0.0;         // mean over compared channels, fraction of peak
    double beyond = 0.01;      // fraction of compared pixels allowed beyond `pixel`
    double misordered = 0.0;   // fraction of covered pixels whose ray order may be wrong
};

Tolerance exact_tolerance() { return {0.015f, 0.001, 0.01, 0.0}; }
Tolerance classic_tolerance() { return {0.06f, 0.006, 0.01, 0.0}; }

struct Result {
    float peak = 0.0f;
    float max_delta = 0.0f;
    double mean_delta = 0.0;
    double beyond = 0.0;
    std::size_t misordered = 0, covered = 0;
    fx::CellRenderStats stats;
};

// Renders `path` and the scan-line reference and checks `tol` on the pixels whose ray order
// (the renderer's sort, redone here on the same cells) is right.
Result compare(const std::string& name, const fx::CellMesh& mesh, const std::string& field,
               const fx::TransferFunction& tf, const fx::Camera& cam, fx::RenderPath path, int size,
               const Tolerance& tol, const fx::CellRenderOptions& options = {}) {
    fx_test::gl_context();
    fx::ScanlineOptions so;
    so.model = fx::OpticalModel::EmissionAbsorption;
    const fx::Image expected = fx::ScanlineRenderer(mesh).render(cam, size, size, *mesh.find_scalar(field), tf, so);
    fx::CellRenderer renderer(mesh, field, tf);
    Result r;
    const fx::Image actual = renderer.render_to_image(cam, size, size, path, options, &r.stats);
    fx_test::require_no_gl_error();

    // The order the renderer used: the same subdivision and sort, on the same cells.
    fx::ViewDependentSubdivision vds(mesh);
    vds.update(cam);
    std::vector<std::uint32_t> order;
    fx::VisibilitySort(vds.cells(), options.sort).sort(cam, order);
    const absorption_test::OrderCheck check = absorption_test::check_order(vds.cells(), order, cam, size, size);
    r.misordered = check.pixels_wrong;
    r.covered = check.pixels_crossed;

    for (const glm::vec4& p : expected.pixels) r.peak = std::max({r.peak, p.r, p.g, p.b, p.a});
    REQUIRE(r.peak > 0.0f); // the view must show something
    double sum = 0.0;
    std::size_t compared = 0, beyond = 0;
    bool finite = true;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        bool ok = true;
        for (int c = 0; c < 4; ++c) finite &= std::isfinite(actual.pixels[i][c]);
        if (check.bad[i]) continue;
        ++compared;
        for (int c = 0; c < 4; ++c) {
            const float d = std::fabs(actual.pixels[i][c] - expected.pixels[i][c]);
            r.max_delta = std::max(r.max_delta, std::isfinite(d) ? d : INFINITY);
            sum += std::isfinite(d) ? d : 1e30;
            ok &= d <= tol.pixel * r.peak;
        }
        beyond += !ok;
    }
    r.mean_delta = sum / (4.0 * double(std::max<std::size_t>(compared, 1)));
    r.beyond = double(beyond) / double(std::max<std::size_t>(compared, 1));
    WARN(name << " [" << fx::render_path_name(path) << ", " << fx::sort_method_name(options.sort) << "]: peak "
              << r.peak << ", max delta " << 100.0 * r.max_delta / r.peak << "% of peak, mean "
              << 100.0 * r.mean_delta / r.peak << "%, beyond tolerance " << 100.0 * r.beyond
              << "% of pixels; misordered " << r.misordered << " of " << r.covered << " covered; problem cells "
              << r.stats.problem_cells << ", pieces " << r.stats.pieces);
    const bool ok = finite && r.beyond <= tol.beyond && r.mean_delta <= tol.mean * r.peak &&
                    double(r.misordered) <= tol.misordered * double(r.covered);
    if (!ok) {
        const std::string prefix = fx_test::write_failure_images(
            name + "_" + fx::render_path_name(path) + "_" + fx::sort_method_name(options.sort), actual, expected,
            10.0f / r.peak);
        INFO("images: " << prefix);
        CHECK(ok);
    }
    CHECK(finite);
    CHECK(r.beyond <= tol.beyond);
    CHECK(r.mean_delta <= tol.mean * r.peak);
    CHECK(double(r.misordered) <= tol.misordered * double(r.covered));
    return r;
}

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up = {0, 0, 1}, double near_d = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = up;
    cam.fov_y_degrees = 40.0;
    cam.near_distance = near_d;
    cam.far_distance = 1000.0;
    return cam;
}

// Normalised: blue haze to a denser, brighter yellow; extinction per world unit `density`.
fx::TransferFunction glow(double density) {
    return fx::TransferFunction({{0.0, {0.2, 0.5, 1.0}, 0.3 * density},
                                 {0.4, {0.6, 0.4, 0.5}, 1.0 * density},
                                 {1.0, {1.0, 0.9, 0.3}, 2.0 * density}},
                                true);
}

const fx::RenderPath kPaths[] = {fx::RenderPath::AbsorptionExact, fx::RenderPath::Absorption};
Tolerance tolerance_of(fx::RenderPath path) {
    return path == fx::RenderPath::AbsorptionExact ? exact_tolerance() : classic_tolerance();
}

} // namespace

TEST_CASE("absorption vs scan-line: a box of hexahedra", "[gl][absorption]") {
    fx::CellMesh mesh = fx_test::hex_box(5, 4, 3, {0, 0, 0}, {1.0, 0.8, 0.6});
    fx::ScalarField f{"s", {}};
    for (const glm::dvec3& p : mesh.points) f.values.push_back(float(p.x + 0.5 * std::sin(3.0 * p.y) * p.z));
    mesh.scalars.push_back(f);
    const fx::Camera cam = perspective({2.2, -1.6, 1.5}, {0.5, 0.4, 0.3});
    for (fx::RenderPath path : kPaths) compare("box", mesh, "s", glow(2.0), cam, path, 64, tolerance_of(path));
}
