// Scan-line renderer: watertightness (many cells render like one), faces emitted once,
// threads give identical frames, memory and statistics are reported.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <utility>

#include "fx/scanline_renderer.hpp"
#include "scanline/scanline_fragments.hpp"
#include "harness/synthetic_meshes.hpp"
#include "mesh/tetrahedralize.hpp"
#include "scanline_test_support.hpp"
#include "cellfx_names.hpp"

using namespace scanline_test;

namespace {

// A globally linear field integrates to the same value whether a ray's segment is one piece
// or many composited pieces (exact arithmetic); what is left is double rounding over ~10
// pieces and the float image, far below 1e-5. A missed or doubled crossing at a shared
// vertex or edge changes a pixel by > 1e-2.
constexpr double kWatertightTolerance = 1e-5;

double linear_field(const glm::dvec3& p) { return 0.45 + 0.2 * p.x + 0.15 * p.y - 0.12 * p.z; }

fx::CellMesh box_mesh(std::uint32_t n) {
    fx::CellMesh mesh;
    append_box(mesh, "box", glm::dvec3(-1.0), glm::dvec3(1.0), {n, n, n});
    set_scalar_field(mesh, "s", linear_field);
    return mesh;
}

std::vector<std::pair<std::string, fx::Camera>> watertight_views() {
    std::vector<std::pair<std::string, fx::Camera>> views;
    fx::Camera c;
    c.near_distance = 0.05;
    // Orthographic along z and along x: 33 pixels over 4.125 units put pixel centres on every
    // multiple of 0.125, so rays run exactly through the 4x4x4 grid's vertices and edges.
    c.eye = {0.0, 0.0, 4.0};
    c.target = {0.0, 0.0, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.ortho_height = 4.125;
    views.push_back({"ortho_z", c});
    c.eye = {4.0, 0.0, 0.0};
    c.up = {0.0, 0.0, 1.0};
    views.push_back({"ortho_x", c});
    // Perspective exactly along the z axis: the centre pixel's ray runs along the grid line
    // x = y = 0, interior planes x = 0 and y = 0 project to lines through pixel centres.
    c.ortho_height = 0.0;
    c.fov_y_degrees = 50.0;
    c.eye = {0.0, 0.0, 4.0};
    c.up = {0.0, 1.0, 0.0};
    views.push_back({"persp_z", c});
    // Perspective through a shared vertex: the centre ray hits vertex (0.5, 0.5, 0.5) and the
    // grid's corner diagonal.
    c.eye = {3.0, 3.0, 3.0};
    c.target = {0.5, 0.5, 0.5};
    c.up = {0.0, 0.0, 1.0};
    views.push_back({"persp_diagonal", c});
    c.eye = {2.7, -1.9, 1.4};
    c.target = {0.1, 0.05, -0.1};
    views.push_back({"persp_oblique", c});
    return views;
}

} // namespace

TEST_CASE("each face is emitted once, and surfaces are the faces without a neighbour", "[scanline]") {
    const fx::CellMesh mesh = box_mesh(4);
    const fx::ScanlineRenderer r(mesh);
    // 4x4x4 hexes: 3·4·4·5 = 240 distinct faces, 6·16 = 96 on the surface, 2 triangles each.
    CHECK(r.triangle_count() == 480);
    CHECK(r.surface_triangle_count() == 192);
    const fx::CellMesh tets = fx::tetrahedralize(mesh);
    const fx::ScanlineRenderer rt(tets);
    // Tetrahedra: every boundary quad still gives 2 triangles; interior faces once each.
    CHECK(rt.surface_triangle_count() == 192);
    std::size_t slots = 4 * tets.cell_count();
    CHECK(rt.triangle_count() == (slots - 192) / 2 + 192);
}

TEST_CASE("a box split into many hexes or tetrahedra renders like one cell (watertight)", "[scanline]") {
    const fx::CellMesh one = box_mesh(1);
    const fx::CellMesh many = box_mesh(4);
    const fx::CellMesh tets = fx::tetrahedralize(many);
    const fx::ScanlineRenderer r_one(one), r_many(many), r_tets(tets);
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.6}, {0.45, {1.0, 0.8, 0.2}, 1.4}, {0.9, {1.0, 0.2, 0.3}, 0.9}});
    const int size = 33;
    for (const auto& [name, cam] : watertight_views()) {
        for (fx::OpticalModel model : {fx::OpticalModel::EmissionAbsorption, fx::OpticalModel::Emission}) {
            fx::ScanlineOptions options;
            options.model = model;
            options.threads = 1;
            fx::ScanlineStats s_many, s_tets;
            const fx::Image ref = r_one.render(cam, size, size, one.scalars[0], tf, options);
            const fx::Image a = r_many.render(cam, size, size, many.scalars[0], tf, options, &s_many);
            const fx::Image b = r_tets.render(cam, size, size, tets.scalars[0], tf, options, &s_tets);
            INFO(name << (model == fx::OpticalModel::Emission ? " emission" : " absorption"));
            CHECK(s_many.lost_segments == 0);
            CHECK(s_tets.lost_segments == 0);
            // The reference must not be empty, or the comparison proves nothing.
            double sum = 0.0;
            for (const glm::vec4& p : ref.pixels) sum += p.r;
            CHECK(sum > 10.0);
            check_close(a, ref, kWatertightTolerance, "scanline_watertight_hex_" + name);
            check_close(b, ref, kWatertightTolerance, "scanline_watertight_tet_" + name);
        }
    }
}

TEST_CASE("one and two threads give identical frames", "[scanline]") {
    const fx::CellMesh mesh = fx::make_nine_grid_mesh(0.12);
    REQUIRE(mesh.blocks.size() == 9);
    const fx::ScanlineRenderer r(mesh);
    const fx::ScalarField& field = *mesh.find_scalar("density");
    const fx::TransferFunction tf({{0.0, {0.1, 0.2, 0.9}, 0.5}, {0.5, {0.9, 0.9, 0.2}, 2.5}, {1.0, {1.0, 0.2, 0.1}, 4.0}});
    const fx::Bounds b = fx::mesh_bounds(mesh);
    fx::Camera outside = fx::Camera::framing(b.lo, b.hi);
    fx::Camera inside = outside;
    inside.eye = glm::dvec3(0.1, -0.05, 0.02);
    inside.target = glm::dvec3(1.0, 0.3, 0.2);
    inside.near_distance = 0.02;
    for (const fx::Camera& cam : {outside, inside}) {
        for (bool clip : {false, true}) {
            fx::ScanlineOptions o1;
            o1.threads = 1;
            if (clip) o1.clip_box = fx::Bounds{glm::dvec3(-0.5, -0.6, -0.3), glm::dvec3(0.8, 0.5, 0.4)};
            fx::ScanlineOptions o2 = o1;
            o2.threads = 2;
            o2.lines_per_task = 1; // workers alternate lines: each re-derives its active list
            fx::ScanlineOptions o3 = o2;
            o3.lines_per_task = 7;
            fx::ScanlineOptions o4 = o2;
            o4.lines_per_task = 0; // chunks from the work estimate (the default)
            fx::ScanlineStats s1, s2;
            const fx::Image a = r.render(cam, 64, 48, field, tf, o1, &s1);
            const fx::Image b2 = r.render(cam, 64, 48, field, tf, o2, &s2);
            const fx::Image b3 = r.render(cam, 64, 48, field, tf, o3);
            const fx::Image b4 = r.render(cam, 64, 48, field, tf, o4);
            CHECK(s2.threads == 2);
            CHECK(s1.triangles_active == s2.triangles_active);
            CHECK(s1.crossings == s2.crossings);
            CHECK(s1.crossings > 1000);
            CHECK(a.pixels == b2.pixels); // bit-identical
            CHECK(a.pixels == b3.pixels);
            CHECK(a.pixels == b4.pixels);
        }
    }
}

TEST_CASE("a copied or moved renderer draws the same frame", "[scanline]") {
    const fx::CellMesh mesh = fx::make_nine_grid_mesh(0.08);
    const fx::ScanlineRenderer original(mesh);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const fx::Camera cam = fx::Camera::framing(b.lo, b.hi);
    const fx::TransferFunction tf = fx::TransferFunction::constant({0.6, 0.8, 1.0}, 1.5);
    const fx::Image a = original.render(cam, 40, 30, *mesh.find_scalar("density"), tf); // keeps buffers
    fx::ScanlineRenderer copy(original);
    const fx::ScanlineRenderer moved(std::move(copy));
    CHECK(moved.triangle_count() == original.triangle_count());
    CHECK(moved.render(cam, 40, 30, *mesh.find_scalar("density"), tf).pixels == a.pixels);
    CHECK(original.render(cam, 40, 30, *mesh.find_scalar("density"), tf).pixels == a.pixels); // reused buffers
}

TEST_CASE("statistics: memory by component, triangle counts, stage times", "[scanline]") {
    const fx::CellMesh mesh = fx::make_nine_grid_mesh(0.1);
    const fx::ScanlineRenderer r(mesh);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    fx::ScanlineStats s;
    const fx::Image img = r.render(fx::Camera::framing(b.lo, b.hi), 80, 60, *mesh.find_scalar("density"),
                                   fx::TransferFunction::constant({1, 1, 1}, 1.0), {}, &s);
    CHECK(s.triangles_total == r.triangle_count());
    CHECK(s.triangles_active > 0);
    CHECK(s.triangles_active <= s.triangles_total);
    CHECK(s.memory.mesh == mesh.memory_bytes());
    CHECK(s.memory.transformed_points >= mesh.point_count() * 4 * sizeof(float)); // x, y, z, scalar
    CHECK(s.memory.triangles >= r.triangle_count() * sizeof(std::uint32_t)); // one code per triangle
    // Per triangle its Y-bucket (16 bits) and its span class (4 bits).
    CHECK(s.memory.bucket_clip_info ==
          r.triangle_count() * sizeof(std::uint16_t) + (r.triangle_count() + 15) / 16 * sizeof(std::uint64_t));
    CHECK(s.memory.y_buckets >= s.triangles_active * sizeof(std::uint32_t));
    CHECK(s.memory.frame_buffer == 80 * 60 * sizeof(glm::vec4));
    CHECK(s.memory.active_lists > 0);
    CHECK(s.memory.x_buckets > 0);
    CHECK(s.seconds_total >= s.seconds_scan);
    CHECK(s.lost_segments == 0);
}

TEST_CASE("per-pixel depth sort gives the (depth, code) order for any input", "[scanline]") {
    // The pixel walk relies on it: a wrong order is a wrong picture. Inputs as a pixel sees
    // them (monotone runs per grid, both directions), random ones, and equal depths that
    // only the code separates; sizes on both sides of the insertion-sort limit.
    std::mt19937 rng(7);
    std::vector<fx::scanline::Fragment> scratch;
    std::vector<std::uint32_t> runs;
    for (std::size_t n : {0u, 1u, 2u, 9u, 28u, 29u, 30u, 47u, 64u, 113u, 318u}) {
        for (int shape = 0; shape < 4; ++shape) {
            std::vector<fx::scanline::Fragment> v(n);
            for (std::size_t i = 0; i < n; ++i) {
                double z = std::uniform_real_distribution<double>(-50.0, 50.0)(rng);
                if (shape == 1) z = (i % 13 < 7 ? 1.0 : -1.0) * static_cast<double>(i % 13) + 0.01 * (i / 13); // runs
                if (shape == 2) z = static_cast<double>(std::uniform_int_distribution<int>(0, 5)(rng)); // many ties
                if (shape == 3) z = -static_cast<double>(i); // one descending run
                v[i].z = z;
                v[i].q = static_cast<double>(i);
                v[i].id = static_cast<std::uint32_t>(i * 2654435761u); // distinct codes
                v[i].grid = static_cast<std::uint32_t>(i % 9);
                v[i].toggles = i % 2;
            }
            std::vector<fx::scanline::Fragment> expected = v;
            std::sort(expected.begin(), expected.end(), fx::scanline::depth_order);
            fx::scanline::sort_by_depth(v.data(), n, scratch, runs);
            INFO("n " << n << " shape " << shape);
            bool same = true;
            for (std::size_t i = 0; i < n; ++i) same = same && v[i].id == expected[i].id && v[i].q == expected[i].q;
            CHECK(same);
        }
    }
}
