// Planar cells take the plane-based fragment road (shaders/cell_segment.glsl: Cyrus–Beck through
// the faces' planes), folded cells search their triangles: on a grid that mixes both — regular,
// bent (curvilinear, flat within the tolerance) and folded hexahedra beside terrain-fog wedges
// (fx_test::planar_and_folded_grid) — the exact paths draw the same pictures by either road, and
// both match the scan-line reference (which draws every quad as its two triangles).
//
// Tolerances (fractions of `peak`, the brightest reference channel):
//   against the scan-line reference, as the paths' own frame tests state them
//   (test_pcp_scanline.cpp, test_absorption_scanline.cpp): pcp-exact per pixel 0.5%, at most 1%
//   of pixels beyond, mean 0.05%; absorption-exact per pixel 1.5%, at most 1% beyond, mean 0.1%;
//   a camera inside a cell: pcp-exact per pixel 3%, mean 0.2% (the two interpolate the scalar at
//   the near plane differently, docs/render_paths.md);
//   the planar road against the search: a planar cell's faces stand within kPlanarTolerance (1e-3)
//   of its size from its triangles, so where a ray crosses a face between a planar cell and a
//   folded one or the outside, its segment moves by up to 1e-3 of a cell over |cos θ|; between two
//   planar cells nothing moves (they share the plane). On these views (cells 5–20 pixels, tens
//   of faces on a ray) that is far below 0.1% of the peak per pixel except where a face is seen
//   nearly edge-on: per pixel 0.2% of peak, at most 0.5% of the pixels beyond, mean 0.01%.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "fx/cell_renderer.hpp"
#include "fx/scanline_renderer.hpp"
#include "gl_fixture.hpp"
#include "projector/gl_projector.hpp"
#include "projector_meshes.hpp"
#include "render/projector_access.hpp"
#include "cellfx_names.hpp"

namespace {

struct Tolerance {
    float pixel;   // per channel
    double beyond; // share of pixels beyond `pixel`
    double mean;   // mean |difference| per channel
};

struct Difference {
    float max = 0.0f;
    double mean = 0.0, beyond = 0.0;
    bool finite = true;
};

// `actual` against `expected` over every pixel, in fractions of `peak`.
Difference compare_images(const std::string& name, const fx::Image& actual, const fx::Image& expected, float peak,
                          const Tolerance& tol) {
    REQUIRE(actual.pixels.size() == expected.pixels.size());
    Difference d;
    double sum = 0.0;
    std::size_t beyond = 0;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        bool ok = true;
        for (int c = 0; c < 4; ++c) {
            const float a = actual.pixels[i][c], e = expected.pixels[i][c];
            d.finite = d.finite && std::isfinite(a);
            const float delta = std::isfinite(a) ? std::fabs(a - e) / peak : INFINITY;
            d.max = std::max(d.max, delta);
            sum += std::min(double(delta), 1e30);
            ok = ok && delta <= tol.pixel;
        }
        beyond += !ok;
    }
    d.mean = sum / (4.0 * double(actual.pixels.size()));
    d.beyond = double(beyond) / double(actual.pixels.size());
    WARN(name << ": max " << 100.0 * d.max << "% of peak, mean " << 100.0 * d.mean << "%, beyond "
              << 100.0 * d.beyond << "% of pixels");
    const bool ok = d.finite && d.beyond <= tol.beyond && d.mean <= tol.mean;
    if (!ok) INFO("images: " << fx_test::write_failure_images(name, actual, expected, 10.0f / peak));
    CHECK(ok);
    return d;
}

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double near_distance = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = {0, 0, 1};
    cam.fov_y_degrees = 40.0;
    cam.near_distance = near_distance;
    cam.far_distance = 100.0;
    return cam;
}

fx::TransferFunction glow(double density) {
    return fx::TransferFunction({{0.0, {0.2, 0.5, 1.0}, 0.3 * density},
                                 {0.4, {0.6, 0.4, 0.5}, 1.0 * density},
                                 {1.0, {1.0, 0.9, 0.3}, 2.0 * density}},
                                true);
}

struct View {
    const char* name;
    fx::Camera camera;
    bool inside; // the near plane cuts cells
};

std::vector<View> views() {
    fx::Camera grazing;
    grazing.eye = {1.45, -6.0, 0.36}; // along y, level with the boxes' middle: their x faces edge-on
    grazing.target = {1.45, 1.0, 0.36};
    grazing.up = {0, 0, 1};
    grazing.ortho_height = 3.2;
    grazing.near_distance = 0.1;
    grazing.far_distance = 100.0;
    return {{"outside", perspective({4.2, -2.6, 2.8}, {1.4, 1.0, 0.3}), false},
            {"grazing orthographic", grazing, false},
            {"inside the regular box", perspective({0.55, 0.3, 0.4}, {2.6, 0.1, 0.3}, 0.02), true},
            {"inside the folded block", perspective({0.45, 1.55, 0.4}, {0.6, 2.2, 0.3}, 0.02), true}};
}

} // namespace

TEST_CASE("planar and folded cells: either fragment road, the same picture, the scan-line's", "[gl][pcp][planar]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = fx_test::planar_and_folded_grid();
    const fx::TransferFunction tf = glow(1.5);
    const fx::ScalarField& field = *mesh.find_scalar("s");
    const fx::ScanlineRenderer scanline(mesh);
    const int size = 96;
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
        for (const View& view : views()) {
            const std::string name = std::string("planar_") + fx::render_path_name(path) + "_" + view.name;
            INFO(name);
            fx::ScanlineOptions so;
            so.model = path == fx::RenderPath::PcpExact ? fx::OpticalModel::Emission : fx::OpticalModel::EmissionAbsorption;
            const fx::Image reference = scanline.render(view.camera, size, size, field, tf, so);
            float peak = 0.0f;
            for (const glm::vec4& p : reference.pixels) peak = std::max({peak, p.r, p.g, p.b, p.a});
            REQUIRE(peak > 0.0f);

            fx::CellRenderer renderer(mesh, "s", tf);
            fx::CellRenderOptions options;
            options.sort = fx::SortMethod::Xmpvo; // three blocks apart: not convex
            const fx::Image planar = renderer.render_to_image(view.camera, size, size, path, options);
            fx::ProjectorAccess::projector(renderer).set_planar_tolerance(-1.0); // every cell searches
            const fx::Image searched = renderer.render_to_image(view.camera, size, size, path, options);
            fx_test::require_no_gl_error();

            const bool exact_emission = path == fx::RenderPath::PcpExact;
            const Tolerance against_reference = view.inside && exact_emission ? Tolerance{0.03f, 0.01, 0.002}
                                                : exact_emission              ? Tolerance{0.005f, 0.01, 0.0005}
                                                                              : Tolerance{0.015f, 0.01, 0.001};
            compare_images(name + "_planar", planar, reference, peak, against_reference);
            compare_images(name + "_searched", searched, reference, peak, against_reference);
            compare_images(name + "_planar_vs_searched", planar, searched, peak, Tolerance{0.002f, 0.005, 0.0001});
        }
    }
}
