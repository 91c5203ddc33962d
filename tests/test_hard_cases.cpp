// Hard cases of geometry and view, for every render path, against closed forms
// (hard_case_support.hpp: a box with a scalar linear in space, where each pixel is one segment
// integral): grazing rays, Δd → 0, the eye exactly on a face plane, on a vertex, on an edge and
// inside a cell, the near plane through vertices, slivers and zero-volume cells, a mesh 10⁶
// units from the origin, perspective over a 10⁵ depth range.
//
// Where a case already has a test for some paths, only the others run here, and the comment
// names where the rest are: test_pcp_scanline.cpp and test_pcp_paths.cpp (pcp, pcp-exact,
// mip), test_absorption_scanline.cpp (absorption, absorption-exact), test_scanline.cpp.
// Every path is checked with its one stated tolerance (hard_case::stated_tolerance, from testing/verify/tolerances.cpp); a path
// that cannot meet it in a case keeps a check of what it does guarantee, commented, and
// docs/accuracy.md gives the measured error.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "fx/mesh_validation.hpp"
#include "mesh/tetrahedralize.hpp"
#include "hard_case_support.hpp"
#include "cellfx_names.hpp"

using hard_case::LinearBox;
using hard_case::Path;

namespace {

// s over the unit box from 0 to 1.1; c·σ non-decreasing in s in every channel (so MIP's
// maximum lies at a segment's end, where the path looks for it), and emission through the
// box below 1 (classic pcp's 8-bit target).
fx::TransferFunction rising(double sigma_scale = 1.0) {
    return fx::TransferFunction({{0.0, {0.10, 0.15, 0.25}, 0.3 * sigma_scale},
                                 {0.5, {0.25, 0.20, 0.30}, 0.6 * sigma_scale},
                                 {1.1, {0.50, 0.45, 0.35}, 0.9 * sigma_scale}});
}

LinearBox unit_box() { return {glm::dvec3(0.0), glm::dvec3(1.0), {0.3, -0.2, 0.6}, 0.2}; }

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double near_d = 0.05, glm::dvec3 up = {0, 0, 1}) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = up;
    cam.fov_y_degrees = 50.0;
    cam.near_distance = near_d;
    cam.far_distance = 100.0;
    return cam;
}

hard_case::Scene scene(const fx::CellMesh& mesh, const fx::Camera& cam, int cells_on_ray = 12) {
    hard_case::Scene s;
    s.mesh = mesh;
    s.tf = rising();
    s.camera = cam;
    s.cells_on_ray = cells_on_ray;
    return s;
}

// Planes of a 4-cell axis at 0, a, b, c, 1 (of the box), as a spacing map of u = k/4.
std::function<double(int, double)> planes(std::array<double, 3> inner, int axis_mask = 7) {
    return [inner, axis_mask](int axis, double u) {
        if (!((axis_mask >> axis) & 1)) return u;
        const double p[5] = {0.0, inner[0], inner[1], inner[2], 1.0};
        const double k = u * 4.0;
        const int i = std::min(3, int(std::floor(k)));
        return p[i] + (p[i + 1] - p[i]) * (k - i);
    };
}

// Classic absorption interpolates each polygon's thickness and table coordinates linearly on
// screen (Max, Williams & Silva §II): exact for orthographic views, off by a cell's perspective
// foreshortening otherwise — and a cell that reaches the eye is foreshortened without bound
// (its near end is at the near plane). That is the method, not a slip: measured in
// docs/accuracy.md, and each such view is checked again orthographically, where the classic
// flavour must meet its tolerance.
const hard_case::Limit kClassicAtTheEye{Path::Absorption, "thickness linear on screen across cells at the eye"};

void check_orthographic_twin(const std::string& name, hard_case::Scene s, const LinearBox& box) {
    s.camera.ortho_height = 1.2;
    hard_case::check_closed_form(name + "_orthographic", s, box, {Path::Absorption});
}

} // namespace

TEST_CASE("hard cases: grazing rays, thickness going to 0", "[gl][hard]") {
    const LinearBox box = unit_box();
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    SECTION("perspective, the eye just above the top face's plane: rays enter it at grazing angles") {
        // Rows near the horizon cross the top face at angles → 0, so their segments shrink to 0
        // within a pixel or two of the silhouette; every path must fade to 0 there, not blow up.
        for (double above : {1e-3, 1e-6}) {
            const fx::Camera cam = perspective({0.5, -1.6, 1.0 + above}, {0.5, 0.6, 0.55});
            hard_case::check_closed_form("grazing_top_" + std::to_string(above), scene(mesh, cam), box, hard_case::kAllPaths);
        }
    }
    SECTION("orthographic along z: every side face edge-on, pixel centres on inner face planes") {
        // Inner planes at 0.26, 0.5, 0.74 in x and y, on pixel centres (50 px over 2 units, the
        // eye at 0.52); the box's own faces at 0 and 1 fall between centres. pcp, pcp-exact,
        // mip and both absorption flavours have this view in test_pcp_scanline.cpp and
        // test_absorption_scanline.cpp; here the fog flavour and the scan-line renderer.
        const fx::CellMesh uneven = hard_case::box_mesh(box, {4, 4, 4}, planes({0.26, 0.5, 0.74}, 3));
        fx::Camera cam;
        cam.eye = {0.52, 0.52, 3.0}, cam.target = {0.52, 0.52, 0.0}, cam.up = {0, 1, 0};
        cam.ortho_height = 2.0, cam.near_distance = 0.5, cam.far_distance = 20.0;
        hard_case::Scene s = scene(uneven, cam, 4);
        s.width = s.height = 50;
        hard_case::check_closed_form("grazing_ortho", s, box, {Path::Scanline, Path::PcpExactFog});
    }
}

TEST_CASE("hard cases: delta d going to 0, a layer of cells 1e-5 and 1e-9 thick", "[gl][hard]") {
    // The layer between z = 0.6 and 0.6 + t; seen straight down, its cells' depth range Δd is t
    // (classic pcp divides by it). Exactly 0 is tested in test_pcp_scanline.cpp and
    // test_absorption_scanline.cpp (and here, below, with tetrahedra); 1e-9 is below float
    // resolution at 0.6, so on the GPU the layer is flat.
    const LinearBox box = unit_box();
    for (double t : {1e-5, 1e-9}) {
        const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4}, planes({0.3, 0.6, 0.6 + t}, 4));
        fx::Camera ortho;
        ortho.eye = {0.5, 0.5, 3.0}, ortho.target = {0.5, 0.5, 0.0}, ortho.up = {0, 1, 0};
        ortho.ortho_height = 1.4, ortho.near_distance = 0.5, ortho.far_distance = 20.0;
        const fx::Camera above = perspective({0.7, 0.2, 2.6}, {0.5, 0.5, 0.4}, 0.05, {0, 1, 0});
        for (const fx::Camera& cam : {ortho, above})
            hard_case::check_closed_form("thin_layer_" + std::to_string(t) + (cam.orthographic() ? "_ortho" : ""),
                                         scene(mesh, cam), box, hard_case::kAllPaths);
    }
}

TEST_CASE("hard cases: the eye exactly on a face plane", "[gl][hard]") {
    const LinearBox box = unit_box();
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    SECTION("the plane of the box's own side face x = 0: that face is edge-on, all paths") {
        const fx::Camera cam = perspective({0.0, -1.8, 0.5}, {0.45, 0.5, 0.45});
        hard_case::check_closed_form("eye_on_boundary_plane", scene(mesh, cam), box, hard_case::kAllPaths);
    }
    SECTION("an inner plane x = 0.5 shared by a layer of faces") {
        // pcp, pcp-exact, mip: test_pcp_scanline.cpp; absorption: test_absorption_scanline.cpp.
        const fx::Camera cam = perspective({0.5, -1.8, 1.4}, {0.5, 0.5, 0.4});
        hard_case::check_closed_form("eye_on_inner_plane", scene(mesh, cam), box, {Path::Scanline, Path::PcpExactFog});
    }
}

TEST_CASE("hard cases: the eye exactly on a vertex, on an edge, inside a cell", "[gl][hard]") {
    const LinearBox box = unit_box();
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    SECTION("on an inner vertex (0.5, 0.5, 0.5), shared by 8 cells the near plane cuts") {
        const fx::Camera cam = perspective({0.5, 0.5, 0.5}, {0.9, 0.8, 0.2}, 0.05);
        hard_case::check_closed_form("eye_on_inner_vertex", scene(mesh, cam), box, hard_case::kAllPaths, {kClassicAtTheEye});
        check_orthographic_twin("eye_on_inner_vertex", scene(mesh, cam), box);
    }
    SECTION("on the box's corner vertex, looking in") {
        const fx::Camera cam = perspective({0.0, 0.0, 0.0}, {0.6, 0.5, 0.55}, 0.05);
        hard_case::check_closed_form("eye_on_corner_vertex", scene(mesh, cam), box, hard_case::kAllPaths, {kClassicAtTheEye});
        check_orthographic_twin("eye_on_corner_vertex", scene(mesh, cam), box);
    }
    SECTION("on the middle of an inner edge (along z, shared by 4 cells)") {
        const fx::Camera cam = perspective({0.25, 0.75, 0.375}, {0.8, 0.3, 0.7}, 0.05);
        hard_case::check_closed_form("eye_on_inner_edge", scene(mesh, cam), box, hard_case::kAllPaths, {kClassicAtTheEye});
        check_orthographic_twin("eye_on_inner_edge", scene(mesh, cam), box);
    }
    SECTION("on a boundary edge (x = 0, y = 0), looking along the box's diagonal") {
        const fx::Camera cam = perspective({0.0, 0.0, 0.4}, {0.7, 0.8, 0.5}, 0.05);
        hard_case::check_closed_form("eye_on_boundary_edge", scene(mesh, cam), box, hard_case::kAllPaths, {kClassicAtTheEye});
        check_orthographic_twin("eye_on_boundary_edge", scene(mesh, cam), box);
    }
    SECTION("inside a cell, the near plane cutting it and its neighbours") {
        // pcp, pcp-exact, mip inside the box against the closed form: test_pcp_paths.cpp.
        // Absorption inside a mesh is tested against the scan-line reference with a non-linear
        // field (test_absorption_scanline.cpp, a wider tolerance for how the near-plane cut is
        // interpolated); with a linear field there is no such difference, so the closed form here.
        const fx::Camera cam = perspective({0.37, 0.62, 0.41}, {0.9, 0.2, 0.6}, 0.1);
        hard_case::check_closed_form("eye_inside_cell", scene(mesh, cam), box,
                                     {Path::Scanline, Path::PcpExactFog, Path::Absorption, Path::AbsorptionExact},
                                     {kClassicAtTheEye});
        check_orthographic_twin("eye_inside_cell", scene(mesh, cam), box);
    }
}

TEST_CASE("hard cases: the near plane through a vertex", "[gl][hard]") {
    const LinearBox box = unit_box();
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    SECTION("oblique view, the near plane exactly through the box's nearest corner") {
        fx::Camera cam = perspective({1.9, -1.3, 1.7}, {0.5, 0.5, 0.5});
        const glm::dvec3 corner(1.0, 0.0, 1.0);
        cam.near_distance = glm::dot(corner - cam.eye, cam.forward());
        hard_case::check_closed_form("near_through_corner", scene(mesh, cam), box, hard_case::kAllPaths);
    }
    SECTION("the near plane exactly on the inner grid plane z = 0.5 (25 vertices, 16 faces on it)") {
        fx::Camera cam = perspective({0.45, 0.55, -1.0}, {0.5, 0.5, 1.0}, 1.5, {0, 1, 0});
        cam.target = {0.45, 0.55, 1.0}; // straight up +z: the near plane is z = 0.5
        hard_case::check_closed_form("near_on_grid_plane", scene(mesh, cam), box, hard_case::kAllPaths);
    }
    SECTION("eye inside, the near plane through an inner vertex") {
        fx::Camera cam = perspective({0.3, 0.35, 0.2}, {0.8, 0.7, 0.9});
        const glm::dvec3 vertex(0.5, 0.5, 0.5);
        cam.near_distance = glm::dot(vertex - cam.eye, cam.forward());
        hard_case::check_closed_form("near_through_inner_vertex", scene(mesh, cam), box, hard_case::kAllPaths,
                                     {kClassicAtTheEye});
        check_orthographic_twin("near_through_inner_vertex", scene(mesh, cam), box);
    }
}

TEST_CASE("hard cases: a near plane of 1e-300 (or 1e-38, 1e-12) with the eye inside the mesh", "[gl][hard]") {
    // A library caller's near is any positive number, not fitted to the mesh as the CLI fits
    // it. Every path cuts at Camera::clipping_near: no nearer than 1e-9 of the mesh's size,
    // which leaves out at most 1e-9 of a ray (the closed form starts at the eye itself). The
    // scan-line reference drew nothing from near = 1e-38 inside a mesh of size 1 (its float
    // screen depth of the near plane overflowed), the GPU paths drew the picture.
    const LinearBox box = unit_box();
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    for (double near_d : {1e-12, 1e-38, 1e-300}) {
        const fx::Camera cam = perspective({0.37, 0.62, 0.41}, {0.9, 0.2, 0.6}, near_d);
        const std::string name = "near_" + std::to_string(int(std::log10(near_d)));
        hard_case::check_closed_form(name, scene(mesh, cam), box, hard_case::kAllPaths, {kClassicAtTheEye});
        check_orthographic_twin(name, scene(mesh, cam), box);
    }
}

TEST_CASE("hard cases: slivers and zero-volume cells", "[gl][hard]") {
    const LinearBox box = unit_box();
    const fx::Camera cam = perspective({1.8, -1.2, 1.6}, {0.5, 0.5, 0.45});
    SECTION("tetrahedra: a layer 1e-7 thick (slivers) and one collapsed to zero volume") {
        // Consistent tetrahedra of a box whose layers along z lie at 0.3, 0.3 + 1e-7 and 0.6,
        // 0.6: every tetrahedron of those layers is a flat sliver or has zero volume.
        const fx::CellMesh hexes = hard_case::box_mesh(box, {4, 4, 5}, [](int axis, double u) {
            if (axis != 2) return u;
            const double p[6] = {0.0, 0.3, 0.3 + 1e-7, 0.6, 0.6, 1.0};
            const int k = int(std::lround(u * 5.0));
            return p[k];
        });
        fx::CellMesh tets = fx::tetrahedralize(hexes);
        std::size_t flat = 0;
        for (std::size_t c = 0; c < tets.cell_count(); ++c) flat += std::abs(fx::cell_signed_volume(tets, c)) < 1e-6;
        REQUIRE(flat > 100);
        hard_case::check_closed_form("slivers", scene(tets, cam, 20), box, hard_case::kAllPaths);
    }
    SECTION("hexahedra: a collapsed layer, for the paths not tested on one elsewhere") {
        // pcp, pcp-exact, mip: test_pcp_scanline.cpp; absorption: test_absorption_scanline.cpp.
        const fx::CellMesh hexes = hard_case::box_mesh(box, {4, 4, 4}, planes({0.3, 0.6, 0.6}, 4));
        hard_case::check_closed_form("zero_volume_hexes", scene(hexes, cam), box, {Path::Scanline, Path::PcpExactFog});
    }
}

TEST_CASE("hard cases: a mesh centred 1e6 units from the origin", "[gl][hard]") {
    // The absorption paths: test_absorption_scanline.cpp ("far from the origin").
    const glm::dvec3 far(1e6, -2e6, 5e5);
    LinearBox box = unit_box();
    box.lo += far, box.hi += far;
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 4});
    const fx::Camera cam = perspective(far + glm::dvec3(1.9, -1.4, 1.6), far + glm::dvec3(0.5, 0.5, 0.45));
    hard_case::check_closed_form("far_from_origin", scene(mesh, cam), box,
                                 {Path::Scanline, Path::Pcp, Path::PcpExact, Path::PcpExactFog, Path::Mip});
}

TEST_CASE("hard cases: perspective depth over a 1e5 depth range", "[gl][hard]") {
    // The eye at the origin looking down −z into a column of cells from depth 1 to 1e5, layers
    // spaced geometrically (each 2.6× deeper), 4×4 cells across 4e4 units: ground fog to the
    // horizon. The near plane at 0.5, the far plane beyond the mesh. Extinction ~1e-5 per unit
    // so that the optical depth and the emission through the whole column stay ~1.
    LinearBox box{{-2e4, -2e4, -1e5}, {2e4, 2e4, -1.0}, {2e-6, 1e-6, 1e-5}, 0.05};
    const fx::CellMesh mesh = hard_case::box_mesh(box, {4, 4, 12}, [](int axis, double u) {
        if (axis != 2) return u;
        const double depth = std::pow(10.0, 5.0 * (1.0 - u)); // u = 0: depth 1e5, u = 1: depth 1
        return (1e5 - depth) / (1e5 - 1.0);
    });
    fx::Camera cam = perspective({0.0, 0.0, 0.0}, {0.15, 0.1, -1.0}, 0.5, {0, 1, 0});
    cam.far_distance = 1e6;
    hard_case::Scene s = scene(mesh, cam, 14);
    s.tf = rising(1e-5);
    // Classic absorption: every layer is 2.6× deeper than the one before, so every cell is
    // strongly foreshortened (the same limit as cells at the eye; there is no orthographic twin
    // of a depth range).
    hard_case::check_closed_form("depth_range_1e5", s, box, hard_case::kAllPaths,
                                 {{Path::Absorption, "thickness linear on screen across cells spanning 2.6x in depth"}});
}

TEST_CASE("hard cases: a cube at 10^K with extinction at 10^-K gives one picture", "[gl][hard][scale]") {
    // Scale invariance: the unit box (2×2×2 hexahedra, and the same cut into tetrahedra) scaled
    // by 10^K, its extinction by 10^−K and its scalar gradient by 10^−K (the same scalars), seen
    // by Camera::framing of the scaled box (perspective) and by an orthographic camera as tall as
    // the box, is one picture for every K from −30 to 17 — the range of coordinates (±1e18) and
    // extinctions (1e32) cellfx accepts (docs/robustness.md, "Supported range"). Each path is
    // checked at every K, with its stated tolerance, against the scan-line reference of the
    // scaled scene (the fog flavour, whose model is its own, against the closed form) and
    // against its own picture at K = 0.
    const std::vector<Path> gpu_paths = {Path::Pcp, Path::PcpExact, Path::PcpExactFog,
                                         Path::Mip, Path::Absorption, Path::AbsorptionExact};
    SECTION("from 10^-30 to 10^17") {
        for (const bool tetrahedra : {false, true}) {
            for (const bool orthographic : {false, true}) {
                std::map<Path, fx::Image> at_unit;
                for (const int k : {0, -30, -15, -12, -6, 6, 12, 15, 17}) {
                    const double scale = std::pow(10.0, k);
                    LinearBox box = unit_box();
                    box.lo *= scale, box.hi *= scale, box.gradient /= scale;
                    fx::CellMesh mesh = hard_case::box_mesh(box, {2, 2, 2});
                    if (tetrahedra) mesh = fx::tetrahedralize(mesh);
                    hard_case::Scene s = scene(mesh, fx::Camera::framing(box.lo, box.hi), tetrahedra ? 16 : 8);
                    if (orthographic) s.camera.ortho_height = 2.0 * scale;
                    s.tf = rising(1.0 / scale);
                    const std::string name = std::string("scale_") + (tetrahedra ? "tets" : "hexes") +
                                             (orthographic ? "_ortho" : "") + "_e" + std::to_string(k);
                    for (Path p : gpu_paths) {
                        INFO(name << " [" << hard_case::name(p) << "]");
                        const fx::Image actual = hard_case::render(s, p);
                        const fx::Image reference =
                            p == Path::PcpExactFog
                                ? hard_case::closed_form(s, box, p)
                                : hard_case::scanline_reference(s, hard_case::model_of(p, s.scanline_model));
                        verify::Tolerance tol = hard_case::stated_tolerance(p, s.cells_on_ray);
                        // MIP's c·σ grows as 10^−K: only its comparison at K = 0 lies in [0, 1].
                        tol.unit_range = p != Path::Mip;
                        hard_case::check(name, p, actual, reference, tol);
                        if (k == 0) {
                            at_unit[p] = actual;
                            continue;
                        }
                        // MIP shows the largest emission per unit length, c·σ: 10^−K times the
                        // picture at K = 0. Every other path shows integrals over the ray, the same.
                        fx::Image comparable = actual;
                        if (p == Path::Mip)
                            for (glm::vec4& v : comparable.pixels)
                                v *= float(scale);
                        hard_case::check(name + "_vs_e0", p, comparable, at_unit.at(p), tol);
                    }
                }
            }
        }
    }
    SECTION("past the range: every GPU path refuses a cube at 10^19 or 10^-31, naming the limit") {
        // Coordinates beyond ±1e18, as on the CPU paths; a mesh under 1e-30 across, where
        // differences of float positions fall under float's smallest normal number (measured:
        // pcp-exact blank from 10^-36, mip and absorption-exact from 10^-38).
        for (const int k : {19, -31}) {
            const double scale = std::pow(10.0, k);
            LinearBox box = unit_box();
            box.lo *= scale, box.hi *= scale, box.gradient /= scale;
            hard_case::Scene s = scene(hard_case::box_mesh(box, {2, 2, 2}), fx::Camera::framing(box.lo, box.hi));
            s.tf = rising(1.0 / scale);
            for (Path p : gpu_paths) {
                INFO("10^" << k << " [" << hard_case::name(p) << "]");
                REQUIRE_THROWS_WITH(
                    hard_case::render(s, p),
                    Catch::Contains(k > 0 ? "beyond ±1e+18" : "under 1e-30, the smallest the GPU paths"));
            }
        }
    }
}
