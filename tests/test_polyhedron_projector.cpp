// Unit tests of the CPU polyhedron projector and the footprint batching (no GL).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/error.hpp"
#include "projector/footprint_batches.hpp"
#include "fx/mesh_validation.hpp"
#include "projector/polyhedron_projector.hpp"
#include "mesh_builders.hpp"
#include "projector_meshes.hpp"
#include "cellfx_names.hpp"

namespace {

fx::Camera ortho_camera(glm::dvec3 eye, glm::dvec3 target, double height, double near_d = 0.1) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = {0, 1, 0};
    cam.ortho_height = height;
    cam.near_distance = near_d;
    cam.far_distance = 100.0;
    return cam;
}

double polygon_area(const fx::NearCaps& caps, std::size_t k, const glm::dvec3& normal) {
    glm::dvec3 sum(0.0);
    const std::uint32_t b = caps.first_vertex[k], e = caps.first_vertex[k + 1];
    for (std::uint32_t i = b; i < e; ++i) {
        const std::uint32_t j = i + 1 < e ? i + 1 : b;
        sum += glm::cross(glm::dvec3(caps.positions[i]), glm::dvec3(caps.positions[j]));
    }
    return 0.5 * glm::dot(sum, normal);
}

} // namespace

TEST_CASE("projector geometry: triangles, outward planes, relative positions", "[projector]") {
    const fx::CellMesh mesh = fx_test::one_of_each_cell();
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, &mesh.scalars[0]);
    REQUIRE(g.cell_count() == 4);
    // tetra 4, pyramid 1 quad + 4 tris = 6, wedge 2 + 3 quads = 8, hexahedron 12.
    std::size_t expected[] = {4, 6, 8, 12};
    for (std::size_t c = 0; c < 4; ++c) {
        CHECK(g.cell_first_triangle[c + 1] - g.cell_first_triangle[c] == expected[c]);
        // The cell's centroid lies on the inner side of every face plane.
        glm::dvec3 centroid(0.0);
        const int nv = fx::cell_vertex_count(mesh.cell_types[c]);
        for (int v = 0; v < nv; ++v) centroid += glm::dvec3(g.positions[mesh.cell_vertices(c)[v]]) / double(nv);
        for (std::uint32_t t = g.cell_first_triangle[c]; t < g.cell_first_triangle[c + 1]; ++t) {
            const glm::vec4 pl = g.triangle_planes[t];
            CHECK(glm::length(glm::vec3(pl)) == Approx(1.0).epsilon(1e-6));
            CHECK(glm::dot(glm::dvec3(pl), centroid) - pl.w < -1e-3);
            CHECK(g.triangle_cell[t] == c);
        }
    }
    // Scalars copied, positions relative to the bounds centre.
    const fx::Bounds b = fx::mesh_bounds(mesh);
    for (std::size_t i = 0; i < mesh.point_count(); ++i) {
        CHECK(g.scalars[i] == mesh.scalars[0].values[i]);
        CHECK(glm::length(glm::dvec3(g.positions[i]) + b.center() - mesh.points[i]) < 1e-6);
    }
}

TEST_CASE("projector geometry rejects bad input", "[projector]") {
    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    fx::ScalarField short_field{"s", {1.0f}};
    CHECK_THROWS_AS(fx::build_projector_geometry(mesh, &short_field), fx::Error);
    mesh.points[3].y = std::numeric_limits<double>::quiet_NaN();
    CHECK_THROWS_AS(fx::build_projector_geometry(mesh, nullptr), fx::Error);
}

TEST_CASE("projector keeps precision far from the origin", "[projector]") {
    const glm::dvec3 offset(1.0e7, -3.0e6, 2.5e6);
    const fx::CellMesh mesh = fx_test::hex_box(2, 2, 2, offset, offset + glm::dvec3(1.0));
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, nullptr);
    fx::Camera cam = ortho_camera(offset + glm::dvec3(0.5, 0.5, 3.0), offset + glm::dvec3(0.5, 0.5, 0.0), 2.0, 1.0);
    const fx::ProjectorView view = fx::make_projector_view(g, cam);
    fx::ProjectedCells p;
    fx::project_cells(mesh, g, view, p);
    // Cell depth ranges are exactly half a unit (world coordinates would lose ~0.5 in floats).
    for (const glm::vec2& r : p.depth_range) CHECK(r.y == Approx(0.5).margin(1e-6));
    CHECK(p.depth_range[0].x == Approx(1.5).margin(1e-6)); // z = 0.5 .. 1 layer is nearer: d = 3 − 1 − 1 = 1
}

TEST_CASE("per-vertex depth, per-cell d_min and delta d, classification", "[projector]") {
    const fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, nullptr);
    fx::Camera cam;
    cam.eye = {0.5, 0.5, 4.0};
    cam.target = {0.5, 0.5, 0.0};
    cam.near_distance = 0.5;
    const fx::ProjectorView view = fx::make_projector_view(g, cam);
    fx::ProjectedCells p;
    fx::project_cells(mesh, g, view, p);
    for (std::size_t i = 0; i < mesh.point_count(); ++i) {
        CHECK(p.point_depth[i] == Approx(4.0 - mesh.points[i].z - 0.5).margin(1e-6));
    }
    CHECK(p.depth_range[0].x == Approx(2.5).margin(1e-6));
    CHECK(p.depth_range[0].y == Approx(1.0).margin(1e-6));
    CHECK(p.cut_cells.empty());
    CHECK(fx::normalized_depth(3.0f, p.depth_range[0]) == Approx(0.5f));

    std::vector<fx::FaceSide> sides;
    fx::classify_triangles(g, view, sides);
    int front = 0, back = 0;
    for (std::size_t t = 0; t < sides.size(); ++t) {
        const glm::vec3 n(g.triangle_planes[t]);
        if (n.z > 0.5f) CHECK(sides[t] == fx::FaceSide::Front); // top face z = 1 faces the eye
        if (n.z < -0.5f) CHECK(sides[t] == fx::FaceSide::Back);
        front += sides[t] == fx::FaceSide::Front;
        back += sides[t] == fx::FaceSide::Back;
    }
    // Perspective from above the centre: only the top is front-facing; the four sides lean away.
    CHECK(front == 2);
    CHECK(back == 10);
}

TEST_CASE("camera exactly on a face plane, grazing views and zero thickness stay finite", "[projector]") {
    const fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, nullptr);
    SECTION("eye on the plane x = 0 of a face") {
        fx::Camera cam;
        cam.eye = {0.0, 0.5, 4.0};
        cam.target = {0.0, 0.5, 0.0};
        const fx::ProjectorView view = fx::make_projector_view(g, cam);
        for (std::size_t t = 0; t < g.triangles.size(); ++t) {
            if (g.triangle_planes[t].x < -0.5f) CHECK(fx::classify_triangle(g, view, t) == fx::FaceSide::EdgeOn);
        }
    }
    SECTION("orthographic view along the faces: the side faces are edge-on") {
        const fx::ProjectorView view = fx::make_projector_view(g, ortho_camera({0.5, 0.5, 5}, {0.5, 0.5, 0}, 2.0));
        for (std::size_t t = 0; t < g.triangles.size(); ++t) {
            const fx::FaceSide s = fx::classify_triangle(g, view, t);
            if (std::abs(g.triangle_planes[t].z) < 0.5f) CHECK(s == fx::FaceSide::EdgeOn);
        }
    }
    SECTION("a flat cell (zero thickness along the view) has delta d = 0 and alpha 0") {
        const fx::CellMesh flat = fx_test::hex_box(1, 1, 1, {0, 0, 0}, {1, 1, 0});
        const fx::ProjectorGeometry gf = fx::build_projector_geometry(flat, nullptr);
        const fx::ProjectorView view = fx::make_projector_view(gf, ortho_camera({0.5, 0.5, 5}, {0.5, 0.5, 0}, 2.0));
        fx::ProjectedCells p;
        fx::project_cells(flat, gf, view, p);
        CHECK(p.depth_range[0].y == 0.0f);
        for (float d : p.point_depth) {
            const float a = fx::normalized_depth(d, p.depth_range[0]);
            CHECK(std::isfinite(a));
            CHECK(a == 0.0f);
        }
        for (const glm::vec4& pl : gf.triangle_planes) CHECK(std::isfinite(pl.x + pl.y + pl.z + pl.w));
    }
}

TEST_CASE("near-plane cap of a cube cut halfway", "[projector]") {
    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    fx::ScalarField z{"z", {}};
    for (const glm::dvec3& p : mesh.points) z.values.push_back(float(p.z));
    mesh.scalars.push_back(z);
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, &mesh.scalars[0]);
    // Looking down −z from z = 0.8 with near 0.5: the near plane is z = 0.3.
    const fx::ProjectorView view = fx::make_projector_view(g, ortho_camera({0.5, 0.5, 0.8}, {0.5, 0.5, 0}, 2.0, 0.5));
    fx::ProjectedCells p;
    fx::project_cells(mesh, g, view, p);
    REQUIRE(p.cut_cells.size() == 1);
    fx::NearCaps caps;
    fx::build_near_caps(g, view, p, caps);
    REQUIRE(caps.polygon_count() == 1);
    CHECK(caps.first_vertex[1] == 4); // a square: corners on the four vertical edges, nothing else
    CHECK(polygon_area(caps, 0, {0, 0, 1}) == Approx(1.0).epsilon(1e-6)); // CCW seen from the eye (+z)
    for (std::uint32_t v = 0; v < 4; ++v) {
        CHECK(caps.scalars[v] == Approx(0.3).margin(1e-6));
        CHECK(view.depth(glm::dvec3(caps.positions[v])) == Approx(0.0).margin(1e-6));
    }
}

TEST_CASE("near-plane cap through vertices and along edges", "[projector]") {
    const fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, nullptr);
    SECTION("plane through two opposite edges (a diagonal plane of the cube)") {
        // View along (−1, −1, 0)/√2 with the near plane through the edges x+y = 1.
        const glm::dvec3 dir = glm::normalize(glm::dvec3(-1, -1, 0));
        const glm::dvec3 on_plane(0.5, 0.5, 0.5);
        fx::Camera cam = ortho_camera(on_plane - dir * 1.0, on_plane, 3.0, 1.0);
        cam.up = {0, 0, 1};
        const fx::ProjectorView view = fx::make_projector_view(g, cam);
        fx::ProjectedCells p;
        fx::project_cells(mesh, g, view, p);
        REQUIRE(p.cut_cells.size() == 1);
        fx::NearCaps caps;
        fx::build_near_caps(g, view, p, caps);
        REQUIRE(caps.polygon_count() == 1);
        CHECK(caps.first_vertex[1] == 4); // rectangle √2 × 1 with its corners at cube vertices
        CHECK(polygon_area(caps, 0, -dir) == Approx(std::sqrt(2.0)).epsilon(1e-6));
    }
    SECTION("plane touching only a face: no cap") {
        const fx::ProjectorView view = fx::make_projector_view(g, ortho_camera({0.5, 0.5, 1.5}, {0.5, 0.5, 0}, 2.0, 0.5));
        fx::ProjectedCells p;
        fx::project_cells(mesh, g, view, p);
        CHECK(p.cut_cells.empty()); // d_min = 0 exactly: nothing is clipped
    }
    SECTION("plane through one corner and three edges") {
        // Normal (1,1,1)/√3 through vertex (1,0,0): cuts the cube in a triangle with corners
        // (1,0,0), (0,1,0), (0,0,1) — all three are vertices; area √3/2.
        const glm::dvec3 n = glm::normalize(glm::dvec3(1, 1, 1));
        const glm::dvec3 on_plane(1.0 / 3.0);
        fx::Camera cam = ortho_camera(on_plane + n * 1.0, on_plane, 3.0, 1.0);
        const fx::ProjectorView view = fx::make_projector_view(g, cam);
        fx::ProjectedCells p;
        fx::project_cells(mesh, g, view, p);
        fx::NearCaps caps;
        fx::build_near_caps(g, view, p, caps);
        REQUIRE(caps.polygon_count() == 1);
        CHECK(caps.first_vertex[1] == 3);
        CHECK(polygon_area(caps, 0, n) == Approx(std::sqrt(3.0) / 2.0).epsilon(1e-6));
    }
}

TEST_CASE("near-plane caps sweep out each cell's volume", "[projector]") {
    // ∫ area(cap at depth z) dz = volume, for every cell type, oblique views: a strong check
    // that caps are complete, convex and correctly wound.
    const fx::CellMesh mesh = fx_test::one_of_each_cell();
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, &mesh.scalars[0]);
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss;
    for (int trial = 0; trial < 4; ++trial) {
        const glm::dvec3 dir = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
        const fx::Bounds b = fx::mesh_bounds(mesh);
        const double radius = glm::length(b.size());
        for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
            const int steps = 400;
            double volume = 0.0;
            for (int k = 0; k < steps; ++k) {
                const double t = -radius + 2.0 * radius * (k + 0.5) / steps;
                const glm::dvec3 plane_point = b.center() + dir * t;
                fx::Camera cam = ortho_camera(plane_point - dir * 1.0, plane_point, 1.0, 1.0);
                cam.up = std::abs(dir.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
                const fx::ProjectorView view = fx::make_projector_view(g, cam);
                fx::ProjectedCells p;
                fx::project_cells(mesh, g, view, p);
                fx::NearCaps caps;
                if (fx::append_near_cap(g, view, p, std::uint32_t(c), caps)) {
                    const double area = polygon_area(caps, 0, -dir);
                    CHECK(area > 0.0);
                    volume += area * (2.0 * radius / steps);
                }
            }
            CHECK(volume == Approx(fx::cell_signed_volume(mesh, c)).epsilon(2e-3));
        }
    }
}

namespace {

// Does the ray through pixel (x, y) meet the cell's part beyond the near plane? Ray against the
// cell's face planes (convex cell), independent of how footprints are computed.
bool ray_meets_visible_cell(const fx::ProjectorGeometry& g, const fx::ProjectorView& view, const fx::Camera& camera,
                            std::size_t cell, int x, int y, int width, int height) {
    const fx::Ray ray = camera.pixel_ray(x + 0.5, y + 0.5, width, height);
    const glm::dvec3 o = ray.origin - g.origin, d = ray.direction;
    double t0 = 0.0, t1 = 1e30;
    // Beyond the near plane: view.depth(o + t d) >= 0.
    const double d0 = view.depth(o), dd = glm::dot(d, view.forward);
    if (std::fabs(dd) < 1e-15) {
        if (d0 < 0.0) return false;
    } else {
        (dd > 0.0 ? t0 : t1) = (dd > 0.0 ? std::max(t0, -d0 / dd) : std::min(t1, -d0 / dd));
    }
    for (std::uint32_t t = g.cell_first_triangle[cell]; t < g.cell_first_triangle[cell + 1]; ++t) {
        const glm::dvec3 n(g.triangle_planes[t]);
        if (glm::dot(n, n) == 0.0) continue;
        const double side = glm::dot(n, o) - g.triangle_planes[t].w, rate = glm::dot(n, d);
        if (std::fabs(rate) < 1e-15) {
            if (side > 0.0) return false;
            continue;
        }
        const double hit = -side / rate;
        if (rate > 0.0) t1 = std::min(t1, hit);
        else t0 = std::max(t0, hit);
    }
    return t1 > t0 + 1e-9;
}

} // namespace

TEST_CASE("footprints cover every pixel a cell covers, and batches share no tile", "[projector]") {
    fx::CellMesh mesh = fx_test::mixed_box(3);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.03, 0.03), unit(-1.0, 1.0);
    for (glm::dvec3& p : mesh.points) p += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
    REQUIRE(fx::orient_cells(mesh).degenerate.empty());
    const fx::ProjectorGeometry g = fx::build_projector_geometry(mesh, nullptr);
    const int width = 48, height = 40;
    std::size_t tested_pixels = 0, caps_seen = 0;
    for (int view_no = 0; view_no < 12; ++view_no) {
        CAPTURE(view_no);
        fx::Camera cam;
        // Outside views, and views from inside the box so the near plane cuts cells.
        const double distance = view_no % 3 == 0 ? 0.3 : 2.5;
        cam.eye = glm::dvec3(0.5) + distance * glm::normalize(glm::dvec3(unit(rng), unit(rng), unit(rng)));
        cam.target = glm::dvec3(0.5) + 0.2 * glm::dvec3(unit(rng), unit(rng), unit(rng));
        cam.up = {0, 0, 1};
        cam.fov_y_degrees = 50.0;
        cam.near_distance = view_no % 3 == 0 ? 0.15 : 0.1;
        if (view_no == 4) cam.ortho_height = 2.0;
        const fx::ProjectorView view = fx::make_projector_view(g, cam);
        fx::ProjectedCells projected;
        fx::project_cells(mesh, g, view, projected);
        fx::NearCaps caps;
        fx::build_near_caps(g, view, projected, caps);
        caps_seen += caps.polygon_count();
        const glm::dmat4 vp = cam.projection_matrix(double(width) / height) * view.view;
        for (int tile : {1, 4, 7}) {
            CAPTURE(tile);
            fx::CellFootprints fp;
            fx::cell_footprints(mesh, g, vp, projected, caps, width, height, tile, fp);
            REQUIRE(fp.cell_count() == mesh.cell_count());
            std::vector<std::uint32_t> batch;
            const std::uint32_t batches = fx::batch_footprints(fp, batch);
            // Every pixel whose ray meets a cell's visible part lies in one of its tiles.
            for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
                std::vector<char> in_footprint(std::size_t(fp.tiles_x) * fp.tiles_y, 0);
                for (std::uint32_t k = fp.first_span[c]; k < fp.first_span[c + 1]; ++k)
                    for (int x = fp.spans[k].first; x <= fp.spans[k].last; ++x)
                        in_footprint[std::size_t(fp.spans[k].row) * fp.tiles_x + x] = 1;
                for (int y = 0; y < height; ++y)
                    for (int x = 0; x < width; ++x) {
                        if (!ray_meets_visible_cell(g, view, cam, c, x, y, width, height)) continue;
                        ++tested_pixels;
                        CAPTURE(c, x, y);
                        REQUIRE(in_footprint[std::size_t(y / tile) * fp.tiles_x + x / tile]);
                        REQUIRE(batch[c] != fx::kNoBatch);
                    }
            }
            // No two cells of one batch touch the same tile.
            std::vector<std::vector<std::uint32_t>> owner(batches, std::vector<std::uint32_t>(
                                                                        std::size_t(fp.tiles_x) * fp.tiles_y, fx::kNoBatch));
            for (std::size_t c = 0; c < mesh.cell_count(); ++c)
                for (std::uint32_t k = fp.first_span[c]; k < fp.first_span[c + 1]; ++k)
                    for (int x = fp.spans[k].first; x <= fp.spans[k].last; ++x) {
                        std::uint32_t& o = owner[batch[c]][std::size_t(fp.spans[k].row) * fp.tiles_x + x];
                        REQUIRE(o == fx::kNoBatch);
                        o = std::uint32_t(c);
                    }
        }
    }
    CHECK(tested_pixels > 10000);
    CHECK(caps_seen > 0);

    // The same footprint 100 times needs 100 batches (two pages of masks).
    fx::CellFootprints same;
    same.tile = 8, same.tiles_x = 8, same.tiles_y = 8;
    same.first_span = {0};
    for (int c = 0; c < 100; ++c) {
        same.spans.push_back({2, 1, 3});
        same.spans.push_back({3, 2, 2});
        same.first_span.push_back(std::uint32_t(same.spans.size()));
    }
    std::vector<std::uint32_t> batch;
    CHECK(fx::batch_footprints(same, batch) == 100);
    same.first_span.push_back(same.first_span.back()); // an empty footprint is not drawn
    fx::batch_footprints(same, batch);
    CHECK(batch.back() == fx::kNoBatch);
}
