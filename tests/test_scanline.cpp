// Scan-line renderer against closed forms: slab, tetrahedron, emissive cube, intersecting
// grids, a non-convex grid, a camera inside the mesh, the clip box.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "fx/resource_limits.hpp"
#include "fx/scanline_renderer.hpp"
#include "transfer/segment_integral.hpp"
#include "harness/synthetic_meshes.hpp"
#include "mesh/tetrahedralize.hpp"
#include "scanline_test_support.hpp"
#include "cellfx_names.hpp"

using namespace scanline_test;

namespace {

// Float output of values near 1 carries ~6e-8 relative error, the double pipeline far less;
// 1e-4 leaves room for the float image and for pixel centres within ~1e-9 px of an edge,
// while any wrong thickness, missed crossing or wrong interpolation shows up at >1e-3.
constexpr double kClosedFormTolerance = 1e-4;

glm::vec4 absorb(const glm::dvec3& c, double sigma, double length) {
    const double a = length > 0.0 ? -std::expm1(-sigma * length) : 0.0;
    return glm::vec4(glm::vec3(c * a), static_cast<float>(a));
}

glm::vec4 to_vec4(const fx::SegmentColor& s) { return glm::vec4(glm::vec3(s.color), static_cast<float>(s.alpha)); }

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double fov, glm::dvec3 up = {0, 1, 0}) {
    fx::Camera c;
    c.eye = eye;
    c.target = target;
    c.up = up;
    c.fov_y_degrees = fov;
    c.near_distance = 0.05;
    return c;
}

} // namespace

TEST_CASE("slab of constant extinction: I = c(1 - exp(-sigma l)) per pixel, perspective", "[scanline]") {
    fx::CellMesh mesh;
    const glm::dvec3 lo(-3.0, -2.5, -0.25), hi(3.0, 2.5, 0.3);
    append_box(mesh, "slab", lo, hi, {4, 3, 2});
    set_scalar_field(mesh, "s", [](const glm::dvec3&) { return 0.0; });
    const glm::dvec3 color(1.0, 0.5, 0.25);
    const double sigma = 1.5;
    const fx::TransferFunction tf = fx::TransferFunction::constant(color, sigma);
    fx::ScanlineRenderer renderer(mesh);
    const int w = 48, h = 40;
    for (const fx::Camera& cam : {perspective({0.3, -0.4, 3.0}, {0, 0, 0}, 60.0),
                                  perspective({2.5, 1.5, 1.2}, {0, 0, -0.1}, 70.0),
                                  // long range: a thin slab 2000 units away (§5's precision case)
                                  perspective({0.5, 0.2, 2000.0}, {0, 0, 0}, 0.3)}) {
        fx::ScanlineStats stats;
        const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf, {}, &stats);
        const fx::Image expected = expected_image(w, h, [&](int x, int y) {
            const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
            const auto [t0, t1] = ray_box(ray, lo, hi);
            return absorb(color, sigma, std::max(0.0, t1 - t0));
        });
        check_close(img, expected, kClosedFormTolerance, "scanline_slab");
        CHECK(stats.lost_segments == 0);
    }
}

TEST_CASE("one tetrahedron with a linear scalar matches emission_absorption on the exact segment", "[scanline]") {
    const std::array<glm::dvec3, 4> v = {glm::dvec3(-1.0, -1.0, -1.0), glm::dvec3(1.2, -0.8, -0.7),
                                         glm::dvec3(0.1, 1.1, -0.9), glm::dvec3(0.2, 0.1, 1.0)};
    auto field = [](const glm::dvec3& p) { return 0.3 + 0.2 * p.x - 0.1 * p.y + 0.25 * p.z; };
    fx::CellMesh mesh;
    mesh.points.assign(v.begin(), v.end());
    const std::uint32_t ids[4] = {0, 1, 2, 3};
    mesh.add_cell(fx::CellType::Tetra, ids);
    set_scalar_field(mesh, "s", field);
    // Breakpoints inside the scalar range, so segments are split by the integrator.
    const fx::TransferFunction tf({{-0.2, {0.2, 0.4, 1.0}, 0.5}, {0.3, {1.0, 0.2, 0.1}, 3.0}, {0.7, {0.1, 1.0, 0.2}, 1.0}});
    fx::ScanlineRenderer renderer(mesh);
    const int w = 41, h = 37;
    fx::Camera ortho = perspective({2.0, -1.5, 3.0}, {0.1, 0.0, -0.2}, 45.0);
    ortho.ortho_height = 3.2;
    for (const fx::Camera& cam : {perspective({2.0, -1.5, 3.0}, {0.1, 0.0, -0.2}, 45.0),
                                  perspective({-0.3, 3.0, 0.4}, {0.0, 0.0, -0.3}, 50.0, {0, 0, 1}), ortho}) {
        const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf);
        const fx::Image expected = expected_image(w, h, [&](int x, int y) {
            const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
            const auto [t0, t1] = ray_tet(ray, v);
            if (!(t1 > t0)) return glm::vec4(0.0f);
            const glm::dvec3 p0 = ray.origin + t0 * ray.direction, p1 = ray.origin + t1 * ray.direction;
            return to_vec4(fx::emission_absorption(tf, field(p0), field(p1), t1 - t0));
        });
        check_close(img, expected, kClosedFormTolerance, "scanline_tet");
    }
}

TEST_CASE("emissive cube: emission c*sigma*l and maximum c*sigma", "[scanline]") {
    fx::CellMesh mesh;
    const glm::dvec3 lo(-0.5), hi(0.5);
    append_box(mesh, "cube", lo, hi, {3, 3, 3});
    set_scalar_field(mesh, "s", [](const glm::dvec3&) { return 0.0; });
    const glm::dvec3 color(0.8, 0.6, 0.3);
    const double sigma = 0.7;
    const fx::TransferFunction tf = fx::TransferFunction::constant(color, sigma);
    fx::ScanlineRenderer renderer(mesh);
    const fx::Camera cam = perspective({1.3, 1.1, 1.7}, {0, 0, 0}, 50.0);
    const int w = 40, h = 40;
    fx::ScanlineOptions emission;
    emission.model = fx::OpticalModel::Emission;
    const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf, emission);
    const fx::Image expected = expected_image(w, h, [&](int x, int y) {
        const auto [t0, t1] = ray_box(cam.pixel_ray(x + 0.5, y + 0.5, w, h), lo, hi);
        return glm::vec4(glm::vec3(color * sigma * std::max(0.0, t1 - t0)), 0.0f);
    });
    check_close(img, expected, kClosedFormTolerance, "scanline_emission_cube");

    fx::ScanlineOptions maximum;
    maximum.model = fx::OpticalModel::Maximum;
    const fx::Image mip = renderer.render(cam, w, h, mesh.scalars[0], tf, maximum);
    const fx::Image mip_expected = expected_image(w, h, [&](int x, int y) {
        const auto [t0, t1] = ray_box(cam.pixel_ray(x + 0.5, y + 0.5, w, h), lo, hi);
        return t1 > t0 ? glm::vec4(glm::vec3(color * sigma), 0.0f) : glm::vec4(0.0f);
    });
    check_close(mip, mip_expected, kClosedFormTolerance, "scanline_mip_cube");
}

TEST_CASE("two intersecting grids: optical depths and emissions add where they overlap", "[scanline]") {
    // Grid A has s = 0 everywhere, grid B s = 1: each medium is homogeneous, so the documented
    // rule (media add: σ = σA + σB, emission cAσA + cBσB) has a closed form along each ray.
    fx::CellMesh mesh;
    const glm::dvec3 alo(-1.0, -0.8, -0.6), ahi(0.4, 0.8, 0.6);
    const glm::dvec3 blo(-0.3, -0.5, -0.9), bhi(1.0, 0.9, 0.3);
    append_box(mesh, "A", alo, ahi, {3, 2, 2});
    append_box(mesh, "B", blo, bhi, {2, 3, 2});
    const std::size_t a_points = 4 * 3 * 3;
    mesh.scalars.push_back(fx::ScalarField{"s", std::vector<float>(mesh.points.size(), 1.0f)});
    for (std::size_t i = 0; i < a_points; ++i) mesh.scalars[0].values[i] = 0.0f;
    const glm::dvec3 ca(1.0, 0.1, 0.1), cb(0.1, 0.2, 1.0);
    const double sa = 1.2, sb = 2.5;
    const fx::TransferFunction tf({{0.0, ca, sa}, {1.0, cb, sb}});
    fx::ScanlineRenderer renderer(mesh);
    REQUIRE(renderer.grid_count() == 2);
    const fx::Camera cam = perspective({1.8, 1.4, 2.6}, {0.0, 0.0, -0.1}, 55.0);
    const int w = 48, h = 44;

    auto walk = [&](const fx::Ray& ray, bool emission_only) {
        const auto a = ray_box(ray, alo, ahi), b = ray_box(ray, blo, bhi);
        std::vector<double> ts;
        for (auto iv : {a, b}) {
            if (iv.second > iv.first) ts.insert(ts.end(), {iv.first, iv.second});
        }
        std::sort(ts.begin(), ts.end());
        glm::dvec3 color(0.0);
        double transmittance = 1.0;
        for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
            const double m = 0.5 * (ts[i] + ts[i + 1]), l = ts[i + 1] - ts[i];
            const bool in_a = a.first < m && m < a.second, in_b = b.first < m && m < b.second;
            const double sigma = (in_a ? sa : 0.0) + (in_b ? sb : 0.0);
            const glm::dvec3 emit = (in_a ? ca * sa : glm::dvec3(0.0)) + (in_b ? cb * sb : glm::dvec3(0.0));
            if (sigma == 0.0) continue;
            if (emission_only) {
                color += emit * l;
            } else {
                color += transmittance * emit / sigma * (1.0 - std::exp(-sigma * l));
                transmittance *= std::exp(-sigma * l);
            }
        }
        return emission_only ? glm::vec4(glm::vec3(color), 0.0f)
                             : glm::vec4(glm::vec3(color), static_cast<float>(1.0 - transmittance));
    };
    const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf);
    check_close(img,
                expected_image(w, h, [&](int x, int y) { return walk(cam.pixel_ray(x + 0.5, y + 0.5, w, h), false); }),
                kClosedFormTolerance, "scanline_two_grids");
    fx::ScanlineOptions emission;
    emission.model = fx::OpticalModel::Emission;
    const fx::Image em = renderer.render(cam, w, h, mesh.scalars[0], tf, emission);
    check_close(em,
                expected_image(w, h, [&](int x, int y) { return walk(cam.pixel_ray(x + 0.5, y + 0.5, w, h), true); }),
                kClosedFormTolerance, "scanline_two_grids_emission");
    // Maximum intensity: the largest c·σ of any grid the ray passes through (per channel),
    // not of the added media.
    fx::ScanlineOptions maximum;
    maximum.model = fx::OpticalModel::Maximum;
    const fx::Image mip = renderer.render(cam, w, h, mesh.scalars[0], tf, maximum);
    std::size_t both = 0;
    const fx::Image mip_expected = expected_image(w, h, [&](int x, int y) {
        const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
        const auto a = ray_box(ray, alo, ahi), b = ray_box(ray, blo, bhi);
        glm::dvec3 m(0.0);
        if (a.second > a.first) m = glm::max(m, ca * sa);
        if (b.second > b.first) m = glm::max(m, cb * sb);
        both += a.second > a.first && b.second > b.first ? 1 : 0;
        return glm::vec4(glm::vec3(m), 0.0f);
    });
    CHECK(both > 100); // many rays see both grids
    check_close(mip, mip_expected, kClosedFormTolerance, "scanline_two_grids_mip");
}

TEST_CASE("non-convex C-shaped grid: a ray that leaves and re-enters skips the gap", "[scanline]") {
    // One block: 3x3 columns of cells in x-y, 2 layers in z, without cells (1,1) and (2,1):
    // a C opening towards +x. Rays along y through columns 1 and 2 cross the gap.
    fx::CellMesh mesh;
    const double step = 0.5;
    auto id = [](int i, int j, int k) { return static_cast<std::uint32_t>((k * 4 + j) * 4 + i); };
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) mesh.points.push_back(glm::dvec3(-0.75 + step * i, -0.75 + step * j, -0.5 + step * k));
    std::vector<std::pair<glm::dvec3, glm::dvec3>> boxes;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) {
                if (j == 1 && i >= 1) continue;
                const std::uint32_t v[8] = {id(i, j, k),         id(i + 1, j, k),     id(i + 1, j + 1, k),
                                            id(i, j + 1, k),     id(i, j, k + 1),     id(i + 1, j, k + 1),
                                            id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                mesh.add_cell(fx::CellType::Hexahedron, v);
                boxes.push_back({mesh.points[v[0]], mesh.points[v[6]]});
            }
    set_scalar_field(mesh, "s", [](const glm::dvec3&) { return 0.0; });
    const glm::dvec3 color(0.3, 0.9, 0.5);
    const double sigma = 2.0;
    const fx::TransferFunction tf = fx::TransferFunction::constant(color, sigma);
    fx::ScanlineRenderer renderer(mesh);
    const int w = 44, h = 40;
    for (const fx::Camera& cam : {perspective({0.35, -3.0, 0.8}, {0.3, 0.0, 0.0}, 40.0, {0, 0, 1}),
                                  perspective({2.2, 1.9, 1.5}, {0.0, 0.0, 0.0}, 50.0, {0, 0, 1})}) {
        const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf);
        std::size_t reentering = 0;
        const fx::Image expected = expected_image(w, h, [&](int x, int y) {
            const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
            double l = 0.0;
            for (const auto& b : boxes) {
                const auto [t0, t1] = ray_box(ray, b.first, b.second);
                l += std::max(0.0, t1 - t0);
            }
            const auto gap = ray_box(ray, glm::dvec3(-0.25, -0.25, -0.5), glm::dvec3(0.75, 0.25, 0.5));
            const auto hull = ray_box(ray, glm::dvec3(-0.75, -0.75, -0.5), glm::dvec3(0.75, 0.75, 0.5));
            if (gap.second - gap.first > 0.01 && gap.first > hull.first + 0.01 && gap.second < hull.second - 0.01) {
                ++reentering;
            }
            return absorb(color, sigma, l);
        });
        CHECK(reentering > 20); // the view really has rays that leave and re-enter the grid
        check_close(img, expected, kClosedFormTolerance, "scanline_c_shape");
    }
}

TEST_CASE("camera inside the mesh renders from the near plane on, with the scalar there", "[scanline]") {
    const glm::dvec3 lo(-1.0), hi(1.0);
    auto field = [](const glm::dvec3& p) { return 0.5 + 0.3 * p.x - 0.2 * p.y + 0.15 * p.z; };
    const fx::TransferFunction tf({{0.0, {0.1, 0.3, 1.0}, 0.4}, {0.5, {1.0, 0.6, 0.1}, 1.6}, {1.0, {0.9, 0.1, 0.6}, 0.8}});
    fx::CellMesh hexes;
    append_box(hexes, "box", lo, hi, {3, 3, 3});
    set_scalar_field(hexes, "s", field);
    fx::CellMesh tets = fx::tetrahedralize(hexes);
    const int w = 40, h = 36;
    fx::Camera cam = perspective({0.1, -0.2, 0.3}, {0.5, 0.3, -1.0}, 70.0);
    cam.near_distance = 0.15;
    fx::Camera ortho = cam;
    ortho.ortho_height = 1.2;
    for (const fx::CellMesh* mesh : {&hexes, &tets}) {
        fx::ScanlineRenderer renderer(*mesh);
        for (const fx::Camera& c : {cam, ortho}) {
            fx::ScanlineStats stats;
            const fx::Image img = renderer.render(c, w, h, mesh->scalars[0], tf, {}, &stats);
            CHECK(stats.cap_triangles > 0);
            CHECK(stats.triangles_near_clipped > 0);
            CHECK(stats.lost_segments == 0);
            const fx::Image expected = expected_image(w, h, [&](int x, int y) {
                const fx::Ray ray = c.pixel_ray(x + 0.5, y + 0.5, w, h);
                const double tn = c.orthographic() ? c.near_distance : near_t(c, ray);
                const auto [t0, t1] = ray_box(ray, lo, hi);
                const double a = std::max(t0, tn);
                if (!(t1 > a)) return glm::vec4(0.0f);
                return to_vec4(fx::emission_absorption(tf, field(ray.origin + a * ray.direction),
                                                       field(ray.origin + t1 * ray.direction), t1 - a));
            });
            check_close(img, expected, kClosedFormTolerance,
                        mesh == &hexes ? "scanline_inside_hex" : "scanline_inside_tet");
        }
    }
}

TEST_CASE("clip box: colour only inside it, camera outside and inside the box", "[scanline]") {
    const glm::dvec3 lo(-1.0), hi(1.0);
    auto field = [](const glm::dvec3& p) { return 0.5 + 0.3 * p.x - 0.2 * p.y + 0.15 * p.z; };
    const fx::TransferFunction tf({{0.0, {0.1, 0.3, 1.0}, 0.9}, {1.0, {1.0, 0.6, 0.1}, 1.9}});
    fx::CellMesh mesh;
    append_box(mesh, "box", lo, hi, {4, 4, 4});
    set_scalar_field(mesh, "s", field);
    fx::ScanlineRenderer renderer(mesh);
    fx::ScanlineOptions options;
    options.clip_box = fx::Bounds{glm::dvec3(-0.6, -1.5, -0.45), glm::dvec3(0.7, 0.35, 0.8)};
    const int w = 40, h = 40;
    fx::Camera inside = perspective({0.0, -0.3, 0.2}, {0.4, 0.2, -1.0}, 70.0);
    inside.near_distance = 0.1;
    for (const fx::Camera& cam : {perspective({2.4, 1.7, 2.9}, {0, 0, 0}, 45.0), inside}) {
        fx::ScanlineStats stats;
        const fx::Image img = renderer.render(cam, w, h, mesh.scalars[0], tf, options, &stats);
        CHECK(stats.lost_segments == 0);
        const fx::Image expected = expected_image(w, h, [&](int x, int y) {
            const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
            const auto m = ray_box(ray, lo, hi);
            const auto c = ray_box(ray, options.clip_box->lo, options.clip_box->hi);
            const double a = std::max({m.first, c.first, near_t(cam, ray)}), b = std::min(m.second, c.second);
            if (!(b > a)) return glm::vec4(0.0f);
            return to_vec4(fx::emission_absorption(tf, field(ray.origin + a * ray.direction),
                                                   field(ray.origin + b * ray.direction), b - a));
        });
        check_close(img, expected, kClosedFormTolerance, "scanline_clip_box");
    }
}

TEST_CASE("bad input is rejected with a message", "[scanline]") {
    fx::CellMesh mesh;
    append_box(mesh, "box", glm::dvec3(-1.0), glm::dvec3(1.0), {1, 1, 1});
    set_scalar_field(mesh, "s", [](const glm::dvec3&) { return 0.0; });
    fx::ScanlineRenderer renderer(mesh);
    const fx::TransferFunction tf = fx::TransferFunction::constant({1, 1, 1}, 1.0);
    const fx::Camera cam = perspective({0, 0, 4}, {0, 0, 0}, 40.0);
    CHECK_THROWS_WITH(renderer.render(cam, 0, 10, mesh.scalars[0], tf), Catch::Contains("image size"));
    fx::ScalarField short_field{"short", {1.0f}};
    CHECK_THROWS_WITH(renderer.render(cam, 8, 8, short_field, tf), Catch::Contains("'short' has 1 values"));
    fx::ScalarField nan_field = mesh.scalars[0];
    nan_field.values[3] = std::nanf("");
    CHECK_THROWS_WITH(renderer.render(cam, 8, 8, nan_field, tf), Catch::Contains("'s' is NaN at point 3"));
    fx::CellMesh bad = mesh;
    bad.points[2].x = std::numeric_limits<double>::infinity();
    CHECK_THROWS_WITH(fx::ScanlineRenderer(bad), Catch::Contains("point 2"));
}

TEST_CASE("cells of either winding render alike, flat cells hold nothing, overlapping cells are refused", "[scanline]") {
    fx::CellMesh mesh;
    append_box(mesh, "box", glm::dvec3(-1.0), glm::dvec3(1.0), {2, 2, 2});
    set_scalar_field(mesh, "s", [](const glm::dvec3& p) { return 0.5 + 0.2 * p.x + 0.1 * p.y * p.z; });
    const fx::TransferFunction tf({{0.0, {0.9, 0.4, 0.1}, 0.3}, {1.0, {0.1, 0.5, 1.0}, 1.5}});
    const fx::Camera cam = perspective({2.2, 3.1, 3.7}, {0, 0, 0}, 40.0);
    const fx::Image reference = fx::ScanlineRenderer(mesh).render(cam, 40, 32, mesh.scalars[0], tf);

    SECTION("inverted cells, not oriented: the same picture") {
        fx::CellMesh mixed = mesh;
        for (std::size_t c = 0; c < mixed.cell_count(); c += 2) {
            std::uint32_t* v = mixed.cell_vertices(c);
            std::swap_ranges(v, v + 4, v + 4);
        }
        // Only zero-length segments between crossings at one depth may order differently.
        check_close(fx::ScanlineRenderer(mixed).render(cam, 40, 32, mixed.scalars[0], tf), reference, 1e-6, "scanline_mixed_winding");
    }
    SECTION("a flat cell through the box changes nothing") {
        fx::CellMesh with_flat = mesh;
        const std::uint32_t base = static_cast<std::uint32_t>(with_flat.points.size());
        for (int i = 0; i < 8; ++i) {
            with_flat.points.push_back(glm::dvec3(i & 1 ? 0.8 : -0.8, i & 2 ? 0.8 : -0.8, 0.1));
            with_flat.scalars[0].values.push_back(0.5f);
        }
        const std::uint32_t v[8] = {base, base + 1, base + 3, base + 2, base + 4, base + 5, base + 7, base + 6};
        with_flat.add_cell(fx::CellType::Hexahedron, v);
        check_close(fx::ScanlineRenderer(with_flat).render(cam, 40, 32, with_flat.scalars[0], tf), reference, 0.0,
                    "scanline_flat_cell");
    }
    SECTION("a duplicate cell is refused when the renderer is built, naming both") {
        fx::CellMesh dup = mesh;
        dup.add_cell(fx::CellType::Hexahedron, dup.cell_vertices(3));
        CHECK_THROWS_WITH(fx::ScanlineRenderer(dup), Catch::Contains("cell 8 has the same points as cell 3"));
    }
    SECTION("cells overlapping without a shared face are found along the rays") {
        fx::CellMesh over = mesh;
        append_box(over, "box", glm::dvec3(-0.5), glm::dvec3(0.5), {1, 1, 1});
        over.blocks.pop_back(); // the second box in the first block: one grid with overlapping cells
        over.blocks[0].cell_count = static_cast<std::uint32_t>(over.cell_count());
        set_scalar_field(over, "s", [](const glm::dvec3&) { return 0.5; });
        const fx::ScanlineRenderer renderer(over);
        CHECK_THROWS_WITH(renderer.render(cam, 40, 32, over.scalars[0], tf),
                          Catch::Contains("block 0") && Catch::Contains("cell 8") && Catch::Contains("overlap"));
        // As a block of its own, the same cell adds its medium instead.
        fx::CellMesh grids = mesh;
        append_box(grids, "inner", glm::dvec3(-0.5), glm::dvec3(0.5), {1, 1, 1});
        set_scalar_field(grids, "s", [](const glm::dvec3&) { return 0.5; });
        CHECK_NOTHROW(fx::ScanlineRenderer(grids).render(cam, 40, 32, grids.scalars[0], tf));
    }
    SECTION("a worker over the frame-bytes budget: an fx::Error on the caller's thread, and the renderer still works") {
        // 400 layers seen face on: every pixel of a 64-pixel line crosses 401 faces, 25,664
        // fragments a line; 1.6 MB leaves the frame's small fixed buffers room but a worker
        // about 10,000 fragments.
        fx::CellMesh deep;
        append_box(deep, "deep", glm::dvec3(0.0), glm::dvec3(1.0), {1, 1, 400});
        set_scalar_field(deep, "s", [](const glm::dvec3& p) { return p.z; });
        fx::Camera down = perspective({0.5, 0.5, 3.0}, {0.5, 0.5, 0.5}, 40.0);
        down.ortho_height = 0.05;
        fx::ScanlineOptions two;
        two.threads = 2;
        const fx::ScanlineRenderer renderer(deep);
        const fx::Image before = renderer.render(down, 64, 4, deep.scalars[0], tf, two);
        const fx::ResourceLimits saved = fx::resource_limits();
        fx::ResourceLimits tight = saved;
        tight.frame_bytes = 1600000;
        fx::set_resource_limits(tight);
        CHECK_THROWS_WITH(renderer.render(down, 64, 4, deep.scalars[0], tf, two),
                          Catch::Contains("scan line") && Catch::Contains("frame-bytes limit"));
        fx::set_resource_limits(saved);
        check_close(renderer.render(down, 64, 4, deep.scalars[0], tf, two), before, 0.0, "scanline_after_budget");
    }
}
