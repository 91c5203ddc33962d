// Frame tests of the PCP, PCP-exact and MIP paths (headless GL, llvmpipe on CPU machines)
// against closed forms: boxes of hexahedra with a scalar linear in space, where the exact
// per-pixel answer is the transfer function's segment integral over the ray's chord through
// the box (fx/src/transfer/segment_integral.hpp, the CPU's one source of truth).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>

#include "fx/cell_renderer.hpp"
#include "transfer/segment_integral.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "projector/gl_projector.hpp"
#include "projector_meshes.hpp"
#include "render/projector_access.hpp"
#include "cellfx_names.hpp"

namespace {

// Chord of a ray through the axis-aligned box [lo, hi], clipped to start at the near plane.
bool box_chord(const fx::Camera& cam, const fx::Ray& ray, glm::dvec3 lo, glm::dvec3 hi, double& t0, double& t1) {
    t0 = -1e300, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(ray.direction[a]) < 1e-15) {
            if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return false;
            continue;
        }
        double u = (lo[a] - ray.origin[a]) / ray.direction[a], v = (hi[a] - ray.origin[a]) / ray.direction[a];
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u), t1 = std::min(t1, v);
    }
    const double t_near = cam.near_distance / glm::dot(ray.direction, cam.forward());
    t0 = std::max(t0, t_near);
    return t1 > t0;
}

enum class Expect { Emission, Fog, Max };

// Closed-form image of a box whose scalar is s(p) = dot(gradient, p) + offset.
fx::Image box_reference(const fx::Camera& cam, int w, int h, glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 gradient,
                        double offset, const fx::TransferFunction& tf, Expect mode) {
    fx::Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const fx::Ray r = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
            double t0, t1;
            if (!box_chord(cam, r, lo, hi, t0, t1)) continue;
            const double s0 = glm::dot(gradient, r.origin + r.direction * t0) + offset;
            const double s1 = glm::dot(gradient, r.origin + r.direction * t1) + offset;
            glm::dvec3 c;
            double a = 0.0;
            if (mode == Expect::Max) {
                c = fx::segment_maximum(tf, s0, s1);
            } else {
                c = fx::emission_integral(tf, s0, s1, t1 - t0);
                if (mode == Expect::Fog) {
                    std::vector<fx::TransferPoint> white = tf.points();
                    for (auto& p : white) p.color = glm::dvec3(1.0);
                    const double tau = fx::emission_integral(fx::TransferFunction(white), s0, s1, t1 - t0).x;
                    a = 1.0 - std::exp(-tau);
                    c = tau > 0.0 ? c / tau * a : c;
                }
            }
            img.at(x, y) = glm::vec4(glm::vec3(c), float(a));
        }
    return img;
}

fx::CellMesh box_with_linear_field(int n, glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 gradient, double offset) {
    fx::CellMesh mesh = fx_test::hex_box(n, n, n, lo, hi);
    fx::ScalarField f{"s", {}};
    for (const glm::dvec3& p : mesh.points) f.values.push_back(float(glm::dot(gradient, p) + offset));
    mesh.scalars.push_back(std::move(f));
    return mesh;
}

// Against a closed form: every channel within `pixel_tol` (absolute) but for a share
// `bad_fraction` of the pixels (silhouette pixels, where float rasterisation and the
// double-precision reference ray may disagree on whether a pixel centre is inside a cell and the
// chord there changes fast: each still within `pixel_tol` of the closed form's range over its
// 3×3 neighbourhood), and the mean |difference| within `mean_tol` (fx_test::check_frame).
void check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected, float pixel_tol,
                 double mean_tol, double bad_fraction = 0.01) {
    verify::Tolerance t;
    t.pixel.absolute = pixel_tol, t.mean.absolute = mean_tol, t.share_beyond = bad_fraction;
    t.why = "closed form of a linear field in a box (bounds stated at each test)";
    fx_test::check_frame(name, actual, expected, t);
}

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double near_d = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = {0, 0, 1};
    cam.fov_y_degrees = 40.0;
    cam.near_distance = near_d;
    cam.far_distance = 100.0;
    return cam;
}

// Emission rising with s, σ = 1: c·σ monotonic, so MIP's end-point rule is exact.
fx::TransferFunction rising_tf(double scale) {
    return fx::TransferFunction({{0.0, glm::dvec3(0.2, 0.5, 1.0) * scale, 1.0},
                                 {0.5, glm::dvec3(0.6, 0.4, 0.5) * scale, 1.0},
                                 {1.0, glm::dvec3(1.0, 0.9, 0.3) * scale, 1.0}});
}

} // namespace

TEST_CASE("pcp-exact: a box of constant emission gives c·sigma·l", "[gl][pcp]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = box_with_linear_field(3, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, 0.5);
    const fx::TransferFunction tf = fx::TransferFunction::constant({0.3, 0.6, 0.9}, 0.4);
    fx::CellRenderer r(mesh, "s", tf);
    const fx::Camera cam = perspective({2.2, 1.6, 1.9}, {0.5, 0.5, 0.5});
    const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::PcpExact);
    fx_test::require_no_gl_error();
    // float32 along rays ~ 10 units long: chords agree to ~1e-6 relative; 1e-4 leaves margin
    // for silhouette pixels whose rays graze an edge (length → 0 on both sides).
    check_frame("pcp_exact_constant_box", img, box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, {0, 0, 0}, 0.5, tf, Expect::Emission),
                1e-4f, 1e-6);
}

TEST_CASE("pcp-exact and fog: a box with a linear scalar, exact integrals", "[gl][pcp]") {
    fx_test::gl_context();
    const glm::dvec3 grad(0.3, -0.2, 0.6);
    const fx::CellMesh mesh = box_with_linear_field(4, {0, 0, 0}, {1, 1, 1}, grad, 0.2);
    const fx::TransferFunction tf = rising_tf(1.0);
    fx::CellRenderer r(mesh, "s", tf);
    const fx::Camera cam = perspective({2.0, -1.4, 1.5}, {0.5, 0.5, 0.5});
    SECTION("emission") {
        const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::PcpExact);
        // Error sources: the 4096-sample cumulative table (emission piecewise constant per
        // sample, ~1e-5 relative here) and float rounding of E differences; 2e-4 absolute on
        // values up to ~1.
        check_frame("pcp_exact_linear_box", img,
                    box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Emission), 2e-4f, 1e-5);
    }
    SECTION("fog: optical depth accumulated, composited once") {
        const fx::TransferFunction one_colour = fx::TransferFunction::constant({0.8, 0.7, 0.6}, 1.5);
        r.set_transfer_function(one_colour);
        fx::CellRenderOptions o;
        o.fog = true;
        const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::PcpExact, o);
        check_frame("pcp_exact_fog_box", img,
                    box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, one_colour, Expect::Fog), 2e-4f, 1e-5);
    }
}

TEST_CASE("mip: a box with a linear scalar gives the maximum over each chord", "[gl][pcp]") {
    fx_test::gl_context();
    const glm::dvec3 grad(0.3, -0.2, 0.6);
    const fx::CellMesh mesh = box_with_linear_field(4, {0, 0, 0}, {1, 1, 1}, grad, 0.2);
    const fx::TransferFunction tf = rising_tf(1.0);
    fx::CellRenderer r(mesh, "s", tf);
    const fx::Camera cam = perspective({2.0, -1.4, 1.5}, {0.5, 0.5, 0.5});
    const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::Mip);
    // The maximum is at the exit face here (monotonic emission); the 4096-sample emission row
    // interpolated linearly: < 1e-6; float scalars: ~1e-6.
    check_frame("mip_linear_box", img, box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Max), 1e-4f,
                1e-6);
}

TEST_CASE("pcp classic: a box with a linear scalar, 8-bit error measured", "[gl][pcp]") {
    fx_test::gl_context();
    const glm::dvec3 grad(0.3, -0.2, 0.6);
    const fx::CellMesh mesh = box_with_linear_field(4, {0, 0, 0}, {1, 1, 1}, grad, 0.2);
    const fx::TransferFunction tf = rising_tf(0.5); // keeps every pixel below 1
    fx::CellRenderer r(mesh, "s", tf);
    const fx::Camera cam = perspective({2.0, -1.4, 1.5}, {0.5, 0.5, 0.5});
    fx::CellRenderStats stats;
    const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::Pcp, {}, &stats);
    const fx::Image ref = box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Emission);
    INFO("batches " << stats.batches);
    CHECK(stats.batches > 1);
    CHECK(stats.cells_drawn == mesh.cell_count());
    // ≤ 4 cells along a ray here: each adds ≤ 0.5/255 rounding of its colour, ≤ 2/255·(its
    // light) from the 8-bit α difference, plus Gouraud-interpolated κ (trapezoid rule on the
    // linear-in-s emission) — bound 6/255 max, 1/255 mean.
    check_frame("pcp_classic_linear_box", img, ref, 6.0f / 255.0f, 1.0 / 255.0);
}

TEST_CASE("camera inside the mesh: the near plane cuts cells (caps)", "[gl][pcp]") {
    fx_test::gl_context();
    const glm::dvec3 grad(0.3, -0.2, 0.6);
    const fx::CellMesh mesh = box_with_linear_field(4, {0, 0, 0}, {1, 1, 1}, grad, 0.2);
    // Eye inside the box, near plane 0.15 away: it slices through cells of the first layer.
    const fx::Camera cam = perspective({0.55, 0.45, 0.62}, {0.1, 0.9, 0.2}, 0.15);
    SECTION("pcp-exact") {
        const fx::TransferFunction tf = rising_tf(1.0);
        fx::CellRenderer r(mesh, "s", tf);
        const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::PcpExact);
        check_frame("pcp_exact_inside", img, box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Emission),
                    2e-4f, 1e-5);
    }
    SECTION("mip") {
        const fx::TransferFunction tf = rising_tf(1.0);
        fx::CellRenderer r(mesh, "s", tf);
        fx::CellRenderStats stats;
        const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::Mip, {}, &stats);
        CHECK(stats.caps > 0);
        check_frame("mip_inside", img, box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Max), 1e-4f, 1e-6);
    }
    SECTION("pcp classic") {
        const fx::TransferFunction tf = rising_tf(0.5);
        fx::CellRenderer r(mesh, "s", tf);
        fx::CellRenderStats stats;
        const fx::Image img = r.render_to_image(cam, 64, 64, fx::RenderPath::Pcp, {}, &stats);
        CHECK(stats.caps > 0);
        check_frame("pcp_classic_inside", img,
                    box_reference(cam, 64, 64, {0, 0, 0}, {1, 1, 1}, grad, 0.2, tf, Expect::Emission), 6.0f / 255.0f,
                    1.0 / 255.0);
    }
}

TEST_CASE("a profiled frame draws the same picture, with its stages timed and the memory told by reader", "[gl][pcp]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = box_with_linear_field(3, {0, 0, 0}, {1, 1, 1}, {0.3, 0.2, 0.5}, 0.1);
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.5}, {1.0, {1.0, 0.8, 0.3}, 1.5}});
    const fx::Camera cam = perspective({2.2, 1.6, 1.9}, {0.5, 0.5, 0.5});
    for (const fx::RenderPath path : {fx::RenderPath::Pcp, fx::RenderPath::PcpExact, fx::RenderPath::Mip,
                                      fx::RenderPath::Absorption, fx::RenderPath::AbsorptionExact}) {
        INFO(fx::render_path_name(path));
        fx::CellRenderer r(mesh, "s", tf);
        fx::CellRenderOptions profiled;
        profiled.profile = true;
        fx::CellRenderStats stats;
        const fx::Image plain = r.render_to_image(cam, 48, 48, path);
        const fx::Image image = r.render_to_image(cam, 48, 48, path, profiled, &stats);
        fx_test::require_no_gl_error();
        // The draws' rerun with rasterisation off leaves no trace: the same pixels, bit for bit.
        CHECK(image.pixels == plain.pixels);
        // Every GL stage timed (by both clocks: ≥ 0), and the draws took some time.
        for (const fx::CellRenderStats::StageTime* s : {&stats.tables, &stats.clear, &stats.upload, &stats.vertex,
                                                         &stats.fragment, &stats.resolve}) {
            CHECK(s->wall >= 0.0);
            CHECK(s->gl >= 0.0);
        }
        CHECK(stats.vertex.wall + stats.fragment.wall > 0.0);
        CHECK(stats.gpu_ms >= 0.0);
        // Memory: the shared mesh always; the cell tables only once an exact path drew (the
        // others never read them); each path's own part only once it drew.
        const fx::CellRenderer::Memory m = r.gpu_memory();
        CHECK(m.mesh > 0);
        const bool exact = path == fx::RenderPath::PcpExact || path == fx::RenderPath::AbsorptionExact;
        CHECK((m.cell_tables > 0) == exact);
        CHECK((m.unique_faces > 0) == (path == fx::RenderPath::Mip));
        CHECK((m.pcp_list > 0) == (path == fx::RenderPath::Pcp));
        const bool absorption = path == fx::RenderPath::Absorption || path == fx::RenderPath::AbsorptionExact;
        CHECK((m.absorption > 0) == absorption);
        CHECK(m.targets == std::size_t(48 * 48) * (path == fx::RenderPath::Pcp ? 4 : 16));
        CHECK(r.gpu_bytes() == m.mesh + m.cell_tables + m.unique_faces + m.pcp_list + m.absorption);
    }
}

TEST_CASE("the cell tables are made at the first exact frame, after other paths and in-place updates", "[gl][pcp]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = box_with_linear_field(3, {0, 0, 0}, {1, 1, 1}, {0.3, 0.2, 0.5}, 0.1);
    fx::CellMesh moved = mesh;
    fx::MeshChanges changes;
    changes.whole = false;
    for (std::uint32_t p = 0; p < 5; ++p) {
        moved.points[p] += glm::dvec3(0.01, -0.02, 0.015);
        changes.points.push_back(p);
    }
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.5}, {1.0, {1.0, 0.8, 0.3}, 1.5}});
    const fx::Camera cam = perspective({2.2, 1.6, 1.9}, {0.5, 0.5, 0.5});
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
        INFO(fx::render_path_name(path));
        // The same mesh and the same in-place update; one renderer drew the exact path from the
        // start (its tables built and then updated), the other only pcp and mip before it.
        fx::CellRenderer eager(mesh, "s", tf), late(mesh, "s", tf);
        eager.render_to_image(cam, 48, 48, path);
        late.render_to_image(cam, 48, 48, fx::RenderPath::Pcp);
        late.render_to_image(cam, 48, 48, fx::RenderPath::Mip);
        CHECK(late.gpu_memory().cell_tables == 0);
        eager.update_mesh(moved, "s", changes);
        late.update_mesh(moved, "s", changes);
        late.render_to_image(cam, 48, 48, fx::RenderPath::Pcp);
        CHECK(late.gpu_memory().cell_tables == 0);
        // pcp-exact: bit for bit; absorption-exact within float rounding (1.2e-7 measured): the
        // renderer that drew it before sorts from its previous order, so equal depths may blend
        // in another order.
        verify::Tolerance t;
        t.pixel.absolute = t.mean.absolute = path == fx::RenderPath::PcpExact ? 0.0 : 1e-6;
        t.why = "the same tables, built late; absorption-exact's blend order may differ between equal depths";
        fx_test::check_frame(std::string("tables_late_") + fx::render_path_name(path), late.render_to_image(cam, 48, 48, path),
                             eager.render_to_image(cam, 48, 48, path), t);
        CHECK(late.gpu_memory().cell_tables > 0);
    }
}

TEST_CASE("the frame's clear and resolve cover the pixels the mesh can cover, and the picture is the same", "[gl][pcp]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = box_with_linear_field(3, {0, 0, 0}, {1, 1, 1}, {0.3, 0.2, 0.5}, 0.1);
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.5}, {1.0, {1.0, 0.8, 0.3}, 1.5}});
    fx::CellRenderer r(mesh, "s", tf);
    const fx::GlProjector& projector = fx::renderer_projector(r);
    const int w = 96, h = 64;
    const fx::Viewport viewport{0, 0, w, h};
    // Far and off to one side: a small rectangle; every pixel the mesh covers lies in it, and
    // the picture is the one the whole frame gave (a renderer's first frame clears its target
    // whole: compared with a second renderer drawing a wide view first, then this one).
    const fx::Camera far_view = perspective({6.0, 3.5, 3.0}, {1.5, 1.5, 0.8});
    const glm::ivec4 rect = projector.screen_rect(far_view, viewport);
    CHECK(rect.z > 0);
    CHECK(rect.w > 0);
    CHECK(rect.z * rect.w < w * h / 4);
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Pcp, fx::RenderPath::AbsorptionExact}) {
        INFO(fx::render_path_name(path));
        fx::CellRenderer fresh(mesh, "s", tf);
        const fx::Image expected = fresh.render_to_image(far_view, w, h, path);
        (void)r.render_to_image(perspective({2.2, 1.6, 1.9}, {0.5, 0.5, 0.5}), w, h, path); // fills the target widely
        const fx::Image image = r.render_to_image(far_view, w, h, path);
        fx_test::require_no_gl_error();
        CHECK(image.pixels == expected.pixels);
        std::size_t covered = 0, outside = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (image.pixels[std::size_t(y * w + x)] == glm::vec4(0.0f)) continue;
                ++covered;
                outside += x < rect.x || x >= rect.x + rect.z || y < rect.y || y >= rect.y + rect.w;
            }
        CHECK(covered > 50);
        CHECK(outside == 0);
    }
    // The camera inside the box: the whole frame; behind the camera: nothing.
    CHECK(projector.screen_rect(perspective({0.5, 0.5, 0.5}, {1.0, 0.8, 0.6}), viewport) == glm::ivec4(0, 0, w, h));
    CHECK(projector.screen_rect(perspective({3.0, 3.0, 3.0}, {6.0, 6.0, 6.0}), viewport) == glm::ivec4(0));
}
