// Shared by the hard-case and property tests (test_hard_cases*.cpp, test_property*.cpp): every
// render path behind one call, each path's stated tolerance (from the one table,
// testing/verify/tolerances.cpp), the closed-form image of a box whose scalar is linear in space,
// and the comparison (tests/image_check.hpp: measured, printed, PNGs written on failure).
//
// Paths: the CPU scan-line renderer (fx::ScanlineRenderer) and the GPU flavours of
// fx::CellRenderer — pcp (classic, 8-bit), pcp-exact, pcp-exact with fog, mip, absorption
// (classic) and absorption-exact. Each is compared with the reference of its own optical model:
// emission for pcp and pcp-exact, maximum for mip, emission–absorption for the rest.
//
// The closed form: a mesh that fills the axis-aligned box [lo, hi] with a scalar linear in space,
// s(p) = g·(p − lo) + offset. Every path interpolates linearly inside cells and on faces, so along
// each pixel's ray the scalar is exactly linear between the ray's entry into the box and its
// exit, and the pixel is the transfer function's integral over that one segment
// (fx::emission_integral / segment_maximum / emission_absorption — the CPU's one source of
// truth; test_segment_integral.cpp checks them against quadrature), starting at the near plane.
// Cells inside the box (their size, shape, slivers, zero volume) do not change the answer: that
// is what makes these cases hard for the renderers and easy for the test.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "transfer/segment_integral.hpp"
#include "harness/synthetic_meshes.hpp"
#include "fx/transfer_function.hpp"
#include "gl_fixture.hpp"
#include "image_check.hpp"
#include "cellfx_names.hpp"

namespace hard_case {

using Path = verify::Path;
inline const std::vector<Path> kAllPaths(std::begin(verify::kPaths), std::end(verify::kPaths));
// The paths whose model absorbs (exp(−τ) appears): for extinction-only cases.
inline const std::vector<Path> kAbsorbingPaths = {Path::Scanline, Path::PcpExactFog, Path::Absorption,
                                                  Path::AbsorptionExact};

inline const char* name(Path p) { return verify::path_name(p); }
using verify::model_of;

// Each path's stated tolerance (testing/verify/tolerances.cpp, the one place they are written
// down, each with its derivation), and that every value lies in [0, 1].
// `cells_on_ray`: the most cells a pixel's ray crosses (classic pcp's rounding adds up per cell).
inline verify::Tolerance stated_tolerance(Path p, int cells_on_ray) {
    verify::Case c;
    c.cells_on_ray = cells_on_ray;
    verify::Tolerance t = verify::stated(p, c);
    t.unit_range = true;
    return t;
}

// ---- a case -----------------------------------------------------------------------------------

struct Scene {
    fx::CellMesh mesh;
    std::string field = "s";
    fx::TransferFunction tf;
    fx::Camera camera;
    int width = 40, height = 40;
    fx::SortMethod sort = fx::SortMethod::Xmpvo;       // absorption paths
    fx::OpticalModel scanline_model = fx::OpticalModel::EmissionAbsorption;
    int cells_on_ray = 8;                               // classic pcp's tolerance
};

// Renders one path (a GL context is made current for the GPU paths).
inline fx::Image render(const Scene& s, Path p, fx::CellRenderStats* stats = nullptr) {
    const fx::ScalarField* field = s.mesh.find_scalar(s.field);
    REQUIRE(field != nullptr);
    if (p == Path::Scanline) {
        fx::ScanlineOptions o;
        o.model = s.scanline_model;
        return fx::ScanlineRenderer(s.mesh).render(s.camera, s.width, s.height, *field, s.tf, o);
    }
    fx_test::gl_context();
    fx::CellRenderer renderer(s.mesh, s.field, s.tf);
    fx::CellRenderOptions o;
    o.sort = s.sort;
    fx::RenderPath path = fx::RenderPath::PcpExact;
    switch (p) {
    case Path::Pcp: path = fx::RenderPath::Pcp; break;
    case Path::PcpExactFog: o.fog = true; break;
    case Path::Mip: path = fx::RenderPath::Mip; break;
    case Path::Absorption: path = fx::RenderPath::Absorption; break;
    case Path::AbsorptionExact: path = fx::RenderPath::AbsorptionExact; break;
    default: break;
    }
    fx::CellRenderStats local;
    const fx::Image image = renderer.render_to_image(s.camera, s.width, s.height, path, o, stats ? stats : &local);
    fx_test::require_no_gl_error();
    return image;
}

// The scan-line reference of `model` for the scene.
inline fx::Image scanline_reference(const Scene& s, fx::OpticalModel model) {
    fx::ScanlineOptions o;
    o.model = model;
    return fx::ScanlineRenderer(s.mesh).render(s.camera, s.width, s.height, *s.mesh.find_scalar(s.field), s.tf, o);
}

// ---- the closed form ------------------------------------------------------------------------

struct LinearBox {
    glm::dvec3 lo{0.0}, hi{1.0};
    glm::dvec3 gradient{0.0};
    double offset = 0.0;
    double scalar(const glm::dvec3& p) const { return glm::dot(gradient, p - lo) + offset; }
};

// The ray's segment inside the box, from the near plane on; false when it misses. Slabs in
// double: a ray parallel to a face plane is inside only strictly between the planes.
inline bool box_segment(const LinearBox& box, const fx::Camera& cam, const fx::Ray& ray, double& t0, double& t1) {
    t0 = -1e300, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
        if (ray.direction[a] == 0.0) {
            if (!(ray.origin[a] > box.lo[a] && ray.origin[a] < box.hi[a])) return false;
            continue;
        }
        double u = (box.lo[a] - ray.origin[a]) / ray.direction[a], v = (box.hi[a] - ray.origin[a]) / ray.direction[a];
        if (u > v) std::swap(u, v);
        t0 = std::max(t0, u), t1 = std::min(t1, v);
    }
    // The near plane: eye depth near_distance (perspective rays start at the eye, orthographic
    // ones on the plane through it).
    const double t_near = cam.near_distance / glm::dot(ray.direction, cam.forward());
    t0 = std::max(t0, t_near);
    return t1 > t0;
}

// The model's value along one segment, as the path writes it (premultiplied RGBA).
inline glm::vec4 segment_value(Path p, fx::OpticalModel scanline_model, const fx::TransferFunction& tf, double s0,
                               double s1, double length) {
    const fx::OpticalModel model = model_of(p, scanline_model);
    if (model == fx::OpticalModel::Maximum) return glm::vec4(glm::vec3(fx::segment_maximum(tf, s0, s1)), 0.0f);
    if (model == fx::OpticalModel::Emission) return glm::vec4(glm::vec3(fx::emission_integral(tf, s0, s1, length)), 0.0f);
    if (p == Path::PcpExactFog) {
        // The fog flavour's stated model: optical depth τ and emission E accumulated, composited
        // once: (E·(1 − e^−τ)/τ, 1 − e^−τ) — exact for a medium of one colour.
        std::vector<fx::TransferPoint> white = tf.points();
        for (fx::TransferPoint& q : white) q.color = glm::dvec3(1.0);
        const double tau = fx::emission_integral(fx::TransferFunction(white, tf.normalized()), s0, s1, length).x;
        const glm::dvec3 e = fx::emission_integral(tf, s0, s1, length);
        const double a = -std::expm1(-tau);
        return glm::vec4(glm::vec3(tau > 0.0 ? e * (a / tau) : e), float(a));
    }
    const fx::SegmentColor c = fx::emission_absorption(tf, s0, s1, length);
    return glm::vec4(glm::vec3(c.color), float(c.alpha));
}

inline fx::Image closed_form(const Scene& s, const LinearBox& box, Path p) {
    fx::Image img(s.width, s.height);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const fx::Ray ray = s.camera.pixel_ray(x + 0.5, y + 0.5, s.width, s.height);
            double t0, t1;
            if (!box_segment(box, s.camera, ray, t0, t1)) continue;
            const double s0 = box.scalar(ray.origin + t0 * ray.direction), s1 = box.scalar(ray.origin + t1 * ray.direction);
            img.at(x, y) = segment_value(p, s.scanline_model, s.tf, s0, s1, t1 - t0);
        }
    return img;
}

// A box of nx × ny × nz hexahedra; the layer planes along each axis at lo + (hi − lo)·f(k/n)
// (f = identity by default: equal cells). Scalar "s" linear in space (box.scalar).
inline fx::CellMesh box_mesh(const LinearBox& box, std::array<std::uint32_t, 3> cells,
                             const std::function<double(int axis, double u)>& spacing = {}) {
    fx::CellMesh mesh;
    fx::append_curvilinear_block(mesh, "box", {cells[0] + 1, cells[1] + 1, cells[2] + 1},
                                 [&](double u, double v, double w) {
                                     const double f[3] = {spacing ? spacing(0, u) : u, spacing ? spacing(1, v) : v,
                                                          spacing ? spacing(2, w) : w};
                                     return box.lo + (box.hi - box.lo) * glm::dvec3(f[0], f[1], f[2]);
                                 });
    fx::set_scalar_field(mesh, "s", [&](const glm::dvec3& p) { return box.scalar(p); });
    return mesh;
}

// ---- comparison -------------------------------------------------------------------------------

// Checks `actual` against `expected` with the path's tolerance (fx_test::check_frame: printed,
// checked, the PNGs written on failure).
inline verify::Difference check(const std::string& name, Path p, const fx::Image& actual, const fx::Image& expected,
                                const verify::Tolerance& tol) {
    return fx_test::check_frame(name + "_" + hard_case::name(p), actual, expected, tol);
}

// A path that cannot meet its stated tolerance in a case (docs/accuracy.md gives the measured
// error and why). The tolerance is not widened: for such a path the case checks what it does
// guarantee — every value finite and in [0, 1] — and prints the measured error.
struct Limit {
    Path path;
    const char* why;
};

// What every path guarantees where it cannot meet its stated tolerance: every value finite and
// in [0, 1] (any value in [0, 1] lies within 1 of any other, so the per-pixel bound is 1).
inline verify::Tolerance guaranteed(const std::string& why) {
    verify::Tolerance t;
    t.pixel.absolute = 1.0, t.mean.absolute = 1.0, t.unit_range = true;
    t.why = "beyond its stated tolerance: " + why + "; finite and in [0, 1]";
    return t;
}

// Renders every path in `paths` and checks each against the closed form of `box` with its
// stated tolerance (or, for a path in `limits`, what it guarantees). The reference must show
// something (peak > 0), or the case tests nothing.
inline void check_closed_form(const std::string& name, const Scene& s, const LinearBox& box,
                              const std::vector<Path>& paths, const std::vector<Limit>& limits = {}) {
    for (Path p : paths) {
        const fx::Image expected = closed_form(s, box, p);
        const fx::Image actual = render(s, p);
        const verify::Tolerance tol = stated_tolerance(p, s.cells_on_ray);
        INFO(name << " [" << hard_case::name(p) << "]");
        const auto limit = std::find_if(limits.begin(), limits.end(), [p](const Limit& l) { return l.path == p; });
        if (limit == limits.end()) {
            check(name, p, actual, expected, tol);
            continue;
        }
        fx_test::check_frame(name + "_" + hard_case::name(p), actual, expected, guaranteed(limit->why));
    }
}

} // namespace hard_case
