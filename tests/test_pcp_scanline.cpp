// Frame tests of the PCP, PCP-exact and MIP paths against the CPU scan-line reference
// (fx/scanline_renderer.hpp), on llvmpipe: one hexahedron, the blunt fin, a noise-filled hex
// grid (campfire-like), a mixed mesh (tetra, pyramid, wedge, hexahedron), the camera inside
// the mesh, the eye on a face plane, a grazing orthographic view and zero-thickness cells.
//
// Tolerances: each path's stated one (testing/verify/tolerances.cpp, where each number is
// derived); the camera-inside view states near_plane_cuts, the one hexahedron spanning the whole
// transfer function a larger trapezoid-rule share for classic pcp (below). Measured errors are
// printed (WARN) and listed in docs/render_paths.md.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <glm/geometric.hpp>

#include "fx/cell_renderer.hpp"
#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "mesh/tetrahedralize.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "projector_meshes.hpp"
#include "cellfx_names.hpp"

namespace {

fx::OpticalModel model_of(fx::RenderPath path) {
    return path == fx::RenderPath::Mip ? fx::OpticalModel::Maximum : fx::OpticalModel::Emission;
}

// Renders `path` and the scan-line reference; checks the path's stated tolerance
// (testing/verify/tolerances.cpp) for a frame with `cells_on_ray` cells on a ray.
verify::Difference compare_with_scanline(const std::string& name, const fx::CellMesh& mesh, const std::string& field,
                                         const fx::TransferFunction& tf, const fx::Camera& cam, fx::RenderPath path,
                                         int size = 64, int cells_on_ray = 40, bool near_cuts = false,
                                         double kappa_share = 0.15) {
    fx_test::gl_context();
    fx::ScanlineOptions so;
    so.model = model_of(path);
    const fx::Image expected = fx::ScanlineRenderer(mesh).render(cam, size, size, *mesh.find_scalar(field), tf, so);
    fx::CellRenderer renderer(mesh, field, tf);
    fx::CellRenderStats stats;
    const fx::Image actual = renderer.render_to_image(cam, size, size, path, {}, &stats);
    fx_test::require_no_gl_error();
    verify::Case c;
    c.cells_on_ray = cells_on_ray, c.near_plane_cuts = near_cuts, c.kappa_share = kappa_share;
    const verify::Path p = verify::path_of(path);
    INFO("batches " << stats.batches << ", caps " << stats.caps);
    return fx_test::check_frame(name + "_" + verify::path_name(p), actual, expected, verify::stated(p, c));
}

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up = {0, 0, 1}, double near_d = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = up;
    cam.fov_y_degrees = 40.0;
    cam.near_distance = near_d;
    cam.far_distance = 1000.0;
    return cam;
}

// Normalised, emission c·σ rising monotonically with s (so MIP's face rule is exact), scaled.
fx::TransferFunction rising(double scale) {
    return fx::TransferFunction({{0.0, glm::dvec3(0.2, 0.5, 1.0) * scale, 0.1},
                                 {0.4, glm::dvec3(0.6, 0.4, 0.5) * scale, 0.5},
                                 {1.0, glm::dvec3(1.0, 0.9, 0.3) * scale, 1.0}},
                                true);
}

// Smooth deterministic value noise in [0, 1] (trilinear lattice of hashed values, 2 octaves).
double value_noise(const glm::dvec3& p) {
    auto lattice = [](int x, int y, int z) {
        std::uint32_t h = std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^ std::uint32_t(z) * 83492791u;
        h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
        return double(h & 0xFFFFu) / 65535.0;
    };
    double sum = 0.0, amp = 0.65;
    glm::dvec3 q = p;
    for (int octave = 0; octave < 2; ++octave) {
        const glm::dvec3 f = glm::floor(q), t = q - f;
        const int x = int(f.x), y = int(f.y), z = int(f.z);
        double v = 0.0;
        for (int k = 0; k < 8; ++k) {
            const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
            v += lattice(x + dx, y + dy, z + dz) * (dx ? t.x : 1 - t.x) * (dy ? t.y : 1 - t.y) * (dz ? t.z : 1 - t.z);
        }
        sum += amp * v;
        q *= 2.03;
        amp *= 0.35;
    }
    return sum;
}

fx::CellMesh campfire(int n) {
    fx::CellMesh mesh = fx_test::hex_box(n, n, n, {-1, -1, 0}, {1, 1, 2});
    fx::ScalarField f{"heat", {}};
    for (const glm::dvec3& p : mesh.points) {
        // Noise, fading with height and distance from the axis, like a flame.
        const double r = std::sqrt(p.x * p.x + p.y * p.y);
        f.values.push_back(float(value_noise(p * 3.0) * std::max(0.0, 1.0 - 0.4 * p.z) * std::max(0.0, 1.2 - r)));
    }
    mesh.scalars.push_back(std::move(f));
    return mesh;
}

// mixed_box_with_tets() with a smooth field.
fx::CellMesh mixed_with_tets(int n) {
    fx::CellMesh mesh = fx_test::mixed_box_with_tets(n);
    fx::ScalarField f{"s", {}};
    for (const glm::dvec3& p : mesh.points) f.values.push_back(float(0.5 + 0.5 * std::sin(3.0 * p.x + 2.0 * p.y) * p.z));
    mesh.scalars.push_back(std::move(f));
    return mesh;
}

const fx::RenderPath kPaths[] = {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Pcp};

} // namespace

TEST_CASE("paths vs scan-line: one hexahedron", "[gl][pcp]") {
    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    // Shear it (faces stay planar, the cell convex) so no face is axis-aligned; bilinear field.
    for (glm::dvec3& p : mesh.points) p += glm::dvec3(0.2 * p.z, 0.1 * p.x, 0.15 * p.y);
    fx::ScalarField f{"s", {}};
    for (const glm::dvec3& p : mesh.points) f.values.push_back(float(p.x + 0.5 * p.y * p.z));
    mesh.scalars.push_back(f);
    const fx::Camera cam = perspective({2.4, -1.7, 1.9}, {0.6, 0.5, 0.5});
    // The one cell spans the transfer function's whole range, kinks and the quadratic c·σ
    // included, so classic PCP's vertex κ — Gouraud-interpolated over faces, then front and
    // back averaged — is off by up to ~50% of a pixel here (measured max: 24% of peak).
    for (fx::RenderPath path : kPaths)
        compare_with_scanline("one_hex", mesh, "s", rising(0.8), cam, path, 64, 1, false, 0.5);
}

TEST_CASE("paths vs scan-line: mixed cells (tetra, pyramid, wedge, hexahedron)", "[gl][pcp]") {
    const fx::CellMesh mesh = mixed_with_tets(4);
    int counts[15] = {};
    for (fx::CellType t : mesh.cell_types) ++counts[int(t)];
    REQUIRE(counts[10] > 0);
    REQUIRE(counts[12] > 0);
    REQUIRE(counts[13] > 0);
    REQUIRE(counts[14] > 0);
    const fx::Camera cam = perspective({2.3, -1.5, 1.8}, {0.5, 0.5, 0.5});
    for (fx::RenderPath path : kPaths) compare_with_scanline("mixed", mesh, "s", rising(0.25), cam, path, 64, 12);
}

TEST_CASE("paths vs scan-line: mixed cells, every other one inverted (faces wound inward)", "[gl][pcp]") {
    // The projector orients each cell when it uploads the mesh: inverted cells render as their
    // positive versions, against the reference of the same (inverted) mesh.
    fx::CellMesh mesh = mixed_with_tets(4);
    fx_test::invert_every_other_cell(mesh);
    const fx::Camera cam = perspective({2.3, -1.5, 1.8}, {0.5, 0.5, 0.5});
    for (fx::RenderPath path : kPaths) compare_with_scanline("inverted", mesh, "s", rising(0.25), cam, path, 64, 12);
}

TEST_CASE("paths vs scan-line: noise-filled hex grid (campfire)", "[gl][pcp]") {
    const fx::CellMesh mesh = campfire(12);
    const fx::Camera cam = perspective({3.5, -4.0, 2.5}, {0.0, 0.0, 0.8});
    for (fx::RenderPath path : kPaths) compare_with_scanline("campfire", mesh, "heat", rising(0.3), cam, path, 64, 30);
}

TEST_CASE("paths vs scan-line: blunt fin", "[gl][pcp]") {
    const std::string xyz = fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin");
    const std::string q = fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin");
    const fx::CellMesh mesh = fx::read_mesh(xyz, q);
    REQUIRE(mesh.cell_count() == 37479);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const fx::Camera cam = fx::Camera::framing(b.lo, b.hi, 40.0);
    for (fx::RenderPath path : kPaths) compare_with_scanline("blunt_fin", mesh, "density", rising(0.3), cam, path, 96, 60);
}

TEST_CASE("paths vs scan-line: camera inside the mesh, near plane cutting cells", "[gl][pcp]") {
    const fx::CellMesh mesh = campfire(8);
    // Eye inside the grid; near plane 0.2 away slices the cells around the eye.
    const fx::Camera cam = perspective({0.35, -0.45, 0.7}, {-0.6, 0.8, 1.0}, {0, 0, 1}, 0.2);
    for (fx::RenderPath path : kPaths) compare_with_scanline("inside", mesh, "heat", rising(0.5), cam, path, 64, 10, true);
}

TEST_CASE("paths vs scan-line: eye exactly on a face plane, grazing view, zero-thickness cells", "[gl][pcp]") {
    SECTION("eye on the plane x = 0 shared by a layer of faces") {
        const fx::CellMesh mesh = campfire(8); // grid planes at x = -1 + k/4: x = 0 is one
        const fx::Camera cam = perspective({0.0, -3.5, 1.2}, {0.0, 0.0, 0.9});
        for (fx::RenderPath path : kPaths) compare_with_scanline("face_plane", mesh, "heat", rising(0.5), cam, path, 64, 10);
    }
    SECTION("orthographic view straight down a grid axis: every side face is edge-on") {
        const fx::CellMesh mesh = campfire(8);
        fx::Camera cam;
        cam.eye = {0.0, 0.0, 5.0}, cam.target = {0.0, 0.0, 0.0}, cam.up = {0, 1, 0};
        cam.ortho_height = 2.5, cam.near_distance = 0.5, cam.far_distance = 20.0;
        for (fx::RenderPath path : kPaths) compare_with_scanline("grazing", mesh, "heat", rising(0.5), cam, path, 64, 10);
    }
    SECTION("a collapsed layer: cells with zero volume (delta d = 0 seen along z)") {
        fx::CellMesh mesh = fx_test::hex_box(4, 4, 4);
        for (glm::dvec3& p : mesh.points)
            if (std::abs(p.z - 0.5) < 1e-9) p.z = 0.25; // layer k=2 onto k=1
        fx::ScalarField f{"s", {}};
        for (const glm::dvec3& p : mesh.points) f.values.push_back(float(p.x * 0.5 + p.z));
        mesh.scalars.push_back(f);
        fx::Camera cam;
        cam.eye = {0.5, 0.5, 4.0}, cam.target = {0.5, 0.5, 0.0}, cam.up = {0, 1, 0};
        cam.ortho_height = 1.5, cam.near_distance = 0.5, cam.far_distance = 20.0;
        for (fx::RenderPath path : kPaths) compare_with_scanline("flat_layer", mesh, "s", rising(0.5), cam, path, 64, 4);
    }
}
