// The Absorption path's CPU half, without GL: projected subdivisions (Shirley–Tuchman and the
// general convex overlay) against ray geometry, clipping, the opacity table, one-sided
// transfer-function values, problem faces (§V) against brute-force rays, and the classic
// flavour's polygons rasterised in software against the scan-line reference.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "absorption_test_support.hpp"
#include "absorption/absorption_classic.hpp"
#include "fx/error.hpp"
#include "projector/polyhedron_projector.hpp"
#include "absorption/projected_subdivision.hpp"
#include "fx/scanline_renderer.hpp"
#include "transfer/segment_integral.hpp"
#include "absorption/view_dependent_subdivision.hpp"
#include "fx/visibility_sort.hpp"
#include "mesh/tetrahedralize.hpp"
#include "harness/synthetic_meshes.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "projector_meshes.hpp"
#include "scanline_test_support.hpp"
#include "cellfx_names.hpp"

namespace {

struct Setup {
    fx::ProjectorGeometry geometry;
    fx::ProjectorView view;
    fx::ProjectionFrame frame;
};

Setup setup(const fx::CellMesh& mesh, const fx::Camera& cam, double aspect = 1.0) {
    Setup s;
    s.geometry = fx::build_projector_geometry(mesh, mesh.scalars.empty() ? nullptr : &mesh.scalars[0]);
    s.view = fx::make_projector_view(s.geometry, cam);
    s.frame = fx::make_projection_frame(s.view, cam, aspect);
    return s;
}

fx::ConvexPolyhedron polyhedron_of(const fx::CellMesh& mesh, const Setup& s, std::size_t cell) {
    fx::ConvexPolyhedron p;
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    const int n = fx::cell_vertex_count(mesh.cell_types[cell]);
    for (int i = 0; i < n; ++i) p.vertices.push_back({glm::dvec3(s.geometry.positions[cv[i]]), s.geometry.scalars[cv[i]]});
    for (std::uint32_t t = s.geometry.cell_first_triangle[cell]; t < s.geometry.cell_first_triangle[cell + 1]; ++t) {
        std::array<std::uint32_t, 3> local{};
        for (int c = 0; c < 3; ++c) local[c] = std::uint32_t(std::find(cv, cv + n, s.geometry.triangles[t][c]) - cv);
        p.triangles.push_back(local);
    }
    return p;
}

// The camera ray through a point given in NDC.
fx::Ray ndc_ray(const fx::Camera& cam, const glm::dvec2& ndc) {
    return cam.pixel_ray((ndc.x + 1.0) * 0.5 * 100.0, (ndc.y + 1.0) * 0.5 * 100.0, 100, 100);
}

// Exact thickness and entry/exit scalars of a ray through a cell whose scalar is linear on
// each face triangle (barycentric), from ray–triangle intersections.
struct Exact {
    double thickness = 0.0, s_in = 0.0, s_out = 0.0;
    int crossings = 0;
};
Exact exact_segment(const fx::CellMesh& mesh, std::size_t cell, const fx::Ray& ray) {
    Exact e;
    double t_min = 1e300, t_max = -1e300;
    const fx::CellType type = mesh.cell_types[cell];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    const std::vector<float>& s = mesh.scalars[0].values;
    for (int k = 0; k < fx::cell_face_count(type); ++k) {
        std::uint32_t tri[2][3];
        const int m = fx::triangulate_face(fx::cell_faces(type)[k], cv, tri);
        for (int i = 0; i < m; ++i) {
            const glm::dvec3 a = mesh.points[tri[i][0]], b = mesh.points[tri[i][1]], c = mesh.points[tri[i][2]];
            double t;
            if (!absorption_test::ray_triangle(ray, a, b, c, t)) continue;
            const glm::dvec3 p = ray.origin + t * ray.direction;
            const glm::dvec3 n = glm::cross(b - a, c - a);
            const double wa = glm::dot(glm::cross(c - b, p - b), n) / glm::dot(n, n);
            const double wb = glm::dot(glm::cross(a - c, p - c), n) / glm::dot(n, n);
            const double sv = wa * s[tri[i][0]] + wb * s[tri[i][1]] + (1.0 - wa - wb) * s[tri[i][2]];
            ++e.crossings;
            if (t < t_min) t_min = t, e.s_in = sv;
            if (t > t_max) t_max = t, e.s_out = sv;
        }
    }
    if (e.crossings >= 2) e.thickness = t_max - t_min;
    return e;
}

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double near_d = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = {0, 0, 1};
    cam.fov_y_degrees = 40.0, cam.near_distance = near_d, cam.far_distance = 100.0;
    return cam;
}

// Every subdivision vertex: thickness and scalars equal the exact ray values; polygons are
// counter-clockwise and their areas add up to the silhouette's.
void check_subdivision(const fx::CellMesh& mesh, std::size_t cell, const fx::Camera& cam,
                       const fx::ProjectedSubdivision& sub, double silhouette_area) {
    const double size = glm::length(fx::mesh_bounds(mesh).size());
    REQUIRE(sub.polygon_count() > 0);
    for (std::size_t k = 0; k < sub.polygon_count(); ++k) {
        double a = 0.0;
        for (std::uint32_t i = sub.polygon_start[k]; i < sub.polygon_start[k + 1]; ++i) {
            const std::uint32_t j = i + 1 == sub.polygon_start[k + 1] ? sub.polygon_start[k] : i + 1;
            const glm::dvec2 p = sub.vertices[sub.polygon_vertices[i]].ndc, q = sub.vertices[sub.polygon_vertices[j]].ndc;
            a += 0.5 * (p.x * q.y - p.y * q.x);
        }
        CHECK(a > 0.0);
    }
    CHECK(sub.area() == Approx(silhouette_area).epsilon(1e-9));
    for (std::uint32_t index : sub.polygon_vertices) {
        const fx::SubdivisionVertex& v = sub.vertices[index];
        const Exact e = exact_segment(mesh, cell, ndc_ray(cam, v.ndc));
        INFO("vertex at " << v.ndc.x << ", " << v.ndc.y << ": thickness " << v.thickness << " vs " << e.thickness);
        CHECK(v.thickness == Approx(e.thickness).margin(1e-6 * size));
        if (e.thickness > 1e-6 * size) {
            CHECK(v.s_front == Approx(e.s_in).margin(1e-6));
            CHECK(v.s_back == Approx(e.s_out).margin(1e-6));
        }
    }
}

// Area of the convex hull of the projected points (monotone chain).
double hull_area(std::vector<glm::dvec2> p) {
    std::sort(p.begin(), p.end(), [](auto a, auto b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    std::vector<glm::dvec2> h(2 * p.size());
    std::size_t k = 0;
    auto cross = [](glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
        h[k++] = p[i];
    }
    double a = 0.0;
    for (std::size_t i = 0; i + 1 < k; ++i) a += 0.5 * (h[i].x * h[i + 1].y - h[i].y * h[i + 1].x);
    return a;
}

double silhouette(const fx::CellMesh& mesh, std::size_t cell, const Setup& s) {
    std::vector<glm::dvec2> p;
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int i = 0; i < fx::cell_vertex_count(mesh.cell_types[cell]); ++i) {
        const glm::dvec4 c = s.frame.projection * s.frame.view * glm::dvec4(glm::dvec3(s.geometry.positions[cv[i]]), 1.0);
        p.emplace_back(c.x / c.w, c.y / c.w);
    }
    return hull_area(p);
}

fx::CellMesh one_tet(const std::array<glm::dvec3, 4>& v) {
    fx::CellMesh m;
    m.points.assign(v.begin(), v.end());
    const std::uint32_t ids[4] = {0, 1, 2, 3};
    m.add_cell(fx::CellType::Tetra, ids);
    m.scalars.push_back({"s", {0.1f, 0.9f, 0.4f, 0.7f}});
    return m;
}

} // namespace

TEST_CASE("Shirley–Tuchman: class 1 and class 2 projections of a tetrahedron are exact at their vertices",
          "[absorption]") {
    const fx::CellMesh tet = one_tet({glm::dvec3(0, 0, 0), {1, 0, 0}, {0.3, 1, 0.1}, {0.2, 0.3, 1}});
    fx::SubdivisionBuilder builder;
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    int classes[5] = {};
    for (int view = 0; view < 40; ++view) {
        glm::dvec3 dir(uni(rng), uni(rng), uni(rng));
        if (glm::length(dir) < 0.1) continue;
        fx::Camera cam = perspective(glm::dvec3(0.3) + 2.5 * glm::normalize(dir), glm::dvec3(0.3));
        if (view % 4 == 3) cam.ortho_height = 2.0;
        const Setup s = setup(tet, cam);
        std::array<fx::PolyVertex, 4> v;
        for (int i = 0; i < 4; ++i) v[i] = {glm::dvec3(s.geometry.positions[i]), s.geometry.scalars[i]};
        fx::ProjectedSubdivision sub;
        builder.tetrahedron(s.frame, v, sub);
        INFO("view " << view);
        ++classes[std::min<std::size_t>(sub.polygon_count(), 4)];
        check_subdivision(tet, 0, cam, sub, silhouette(tet, 0, s));
        // The general overlay gives the same coverage and the same values.
        fx::ProjectedSubdivision general;
        builder.polyhedron(s.frame, polyhedron_of(tet, s, 0), general);
        check_subdivision(tet, 0, cam, general, silhouette(tet, 0, s));
    }
    CHECK(classes[3] > 0); // class 1: three triangles around the inner vertex
    CHECK(classes[4] > 0); // class 2: four around the crossing of two edges
    SECTION("degenerate: an edge seen end-on, two faces seen edge-on (orthographic)") {
        const fx::CellMesh right = one_tet({glm::dvec3(0, 0, 0), {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
        fx::Camera cam;
        cam.eye = {0.0, 0.0, 5.0}, cam.target = {0.0, 0.0, 0.0}, cam.up = {0, 1, 0};
        cam.ortho_height = 3.0, cam.near_distance = 0.5;
        const Setup s = setup(right, cam); // edge 0–3 along z projects to one point
        fx::ProjectedSubdivision sub;
        std::array<fx::PolyVertex, 4> v;
        for (int i = 0; i < 4; ++i) v[i] = {glm::dvec3(s.geometry.positions[i]), s.geometry.scalars[i]};
        builder.tetrahedron(s.frame, v, sub);
        CHECK(sub.polygon_count() == 1);
        check_subdivision(right, 0, cam, sub, silhouette(right, 0, s));
        fx::ProjectedSubdivision general;
        builder.polyhedron(s.frame, polyhedron_of(right, s, 0), general);
        check_subdivision(right, 0, cam, general, silhouette(right, 0, s));
    }
}

TEST_CASE("general convex overlay: random views of every cell type, exact at vertices, tiling the silhouette",
          "[absorption]") {
    const fx::CellMesh mesh = fx_test::one_of_each_cell();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307), height(-1.2, 1.2);
    fx::SubdivisionBuilder builder;
    for (int view = 0; view < 12; ++view) {
        for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
            // Cell centre.
            glm::dvec3 centre(0.0);
            const int n = fx::cell_vertex_count(mesh.cell_types[c]);
            for (int i = 0; i < n; ++i) centre += mesh.points[mesh.cell_vertices(c)[i]] / double(n);
            const double a = angle(rng);
            fx::Camera cam = perspective(centre + glm::dvec3(3.0 * std::cos(a), 3.0 * std::sin(a), 3.0 * height(rng)), centre);
            if (view % 3 == 2) cam.ortho_height = 2.5;
            const Setup s = setup(mesh, cam);
            fx::ProjectedSubdivision sub;
            builder.polyhedron(s.frame, polyhedron_of(mesh, s, c), sub);
            INFO("view " << view << ", cell " << fx::cell_type_name(mesh.cell_types[c]));
            check_subdivision(mesh, c, cam, sub, silhouette(mesh, c, s));
            // No point of the silhouette lies in two polygons.
            std::uniform_real_distribution<double> t(0.0, 1.0);
            for (int k = 0; k < 200; ++k) {
                const std::size_t pa = sub.polygon_vertices[std::size_t(t(rng) * (sub.polygon_vertices.size() - 1))];
                const std::size_t pb = sub.polygon_vertices[std::size_t(t(rng) * (sub.polygon_vertices.size() - 1))];
                const glm::dvec2 p = glm::mix(sub.vertices[pa].ndc, sub.vertices[pb].ndc, t(rng));
                int inside = 0;
                for (std::size_t q = 0; q < sub.polygon_count(); ++q) {
                    bool in = true;
                    for (std::uint32_t i = sub.polygon_start[q]; i < sub.polygon_start[q + 1] && in; ++i) {
                        const std::uint32_t j = i + 1 == sub.polygon_start[q + 1] ? sub.polygon_start[q] : i + 1;
                        const glm::dvec2 e0 = sub.vertices[sub.polygon_vertices[i]].ndc, e1 = sub.vertices[sub.polygon_vertices[j]].ndc;
                        in = (e1.x - e0.x) * (p.y - e0.y) - (e1.y - e0.y) * (p.x - e0.x) > 1e-12;
                    }
                    inside += in;
                }
                CHECK(inside <= 1);
            }
        }
    }
}

TEST_CASE("projection frame: corners snapped to the rasteriser's sub-pixel grid", "[absorption]") {
    fx::ProjectionFrame frame;
    const glm::dvec2 p(0.123456789, -0.987654321);
    CHECK(frame.snap(p) == p); // no grid known: unchanged
    frame.pixels_per_ndc = {256.0, 192.0}; // a 512 × 384 viewport
    frame.subpixel_step = 1.0 / 256.0;     // 8 bits
    const glm::dvec2 q = frame.snap(p);
    const glm::dvec2 window = (q + 1.0) * frame.pixels_per_ndc * 256.0;
    CHECK(std::abs(window.x - std::round(window.x)) < 1e-6); // on the grid (to double rounding)
    CHECK(std::abs(window.y - std::round(window.y)) < 1e-6);
    CHECK(std::abs((q - p).x) * frame.pixels_per_ndc.x <= 0.5 / 256.0); // moved by half a step at most
    CHECK(std::abs((q - p).y) * frame.pixels_per_ndc.y <= 0.5 / 256.0);
    CHECK(glm::length(frame.snap(q) - q) < 1e-15); // a corner on the grid stays
    // float keeps a snapped corner within 1e-4 of a grid step (what the GL receives).
    const glm::dvec2 f(float(q.x), float(q.y));
    CHECK(std::abs(((f + 1.0) * frame.pixels_per_ndc * 256.0 - window).x) < 1e-4 * 256.0);
}

TEST_CASE("clip_polyhedron: a closed, outward cap and the right volume", "[absorption]") {
    const fx::CellMesh cube = fx_test::hex_box(1, 1, 1);
    fx::ConvexPolyhedron p;
    for (const glm::dvec3& v : cube.points) p.vertices.push_back({v, v.x});
    for (int k = 0; k < 6; ++k) {
        std::uint32_t tri[2][3];
        fx::triangulate_face(fx::cell_faces(fx::CellType::Hexahedron)[k], cube.cell_vertices(0), tri);
        p.triangles.push_back({tri[0][0], tri[0][1], tri[0][2]});
        p.triangles.push_back({tri[1][0], tri[1][1], tri[1][2]});
    }
    auto volume = [](const fx::ConvexPolyhedron& q) {
        double v = 0.0;
        for (const auto& t : q.triangles)
            v += glm::dot(q.vertices[t[0]].position, glm::cross(q.vertices[t[1]].position, q.vertices[t[2]].position)) / 6.0;
        return v;
    };
    auto closed = [](const fx::ConvexPolyhedron& q) {
        // Every directed edge is matched by its reverse.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
        for (const auto& t : q.triangles)
            for (int e = 0; e < 3; ++e) edges.emplace_back(t[e], t[(e + 1) % 3]);
        for (const auto& e : edges)
            if (std::count(edges.begin(), edges.end(), std::make_pair(e.second, e.first)) != 1) return false;
        return true;
    };
    REQUIRE(volume(p) == Approx(1.0));
    // Plane x + y + z = 1.2 (a hexagon-ish cut through the cube), keeping the part beyond it.
    std::vector<double> f;
    for (const fx::PolyVertex& v : p.vertices) f.push_back(v.position.x + v.position.y + v.position.z - 1.2);
    fx::ConvexPolyhedron out;
    fx::clip_polyhedron(p, f, glm::dvec3(1, 1, 1), out);
    CHECK(closed(out));
    // Volume of {x + y + z ≥ 1.2} in the unit cube: 1 − (1.2³/6 − 3·0.2³/6).
    CHECK(volume(out) == Approx(1.0 - (1.728 / 6.0 - 3.0 * 0.008 / 6.0)).epsilon(1e-12));
    // Scalars on the cut interpolate the linear field x exactly.
    for (const fx::PolyVertex& v : out.vertices) CHECK(v.scalar == Approx(v.position.x).margin(1e-12));
    // A plane through vertices and along edges (x = 0.5 exactly halves it; then x = 1 touches a face).
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = p.vertices[i].position.x - 1.0;
    fx::clip_polyhedron(p, f, glm::dvec3(1, 0, 0), out);
    CHECK(out.triangles.empty()); // only the face x = 1 has f ≥ 0: no volume is left
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = p.vertices[i].position.x - 0.5;
    fx::clip_polyhedron(p, f, glm::dvec3(1, 0, 0), out);
    CHECK(closed(out));
    CHECK(volume(out) == Approx(0.5));
    // Iso-value cut: cap vertices carry the given scalar exactly.
    fx::clip_polyhedron(p, f, glm::dvec3(1, 0, 0), out, 0.5);
    for (const fx::PolyVertex& v : out.vertices)
        if (std::abs(v.position.x - 0.5) < 1e-12) CHECK(v.scalar == 0.5);
}

TEST_CASE("opacity table: 1 - exp(-K u v) read back within its interpolation bound", "[absorption]") {
    const fx::OpacityTable t = fx::build_opacity_table(1024, 12.0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    double worst = 0.0, worst_small = 0.0;
    for (int k = 0; k < 20000; ++k) {
        const double u = uni(rng), v = uni(rng);
        const double exact = -std::expm1(-12.0 * u * v);
        worst = std::max(worst, std::abs(fx::lookup_opacity(t, u, v) - exact));
        // Thin cells: tiny products keep their relative accuracy (the table is bilinear near 0).
        const double us = 1e-4 * u, vs = v;
        const double small = -std::expm1(-12.0 * us * vs);
        if (small > 0.0) worst_small = std::max(worst_small, std::abs(fx::lookup_opacity(t, us, vs) - small) / small);
    }
    // Bilinear error ≤ h²/8·(|f_uu| + |f_vv|) ≤ h²·K²/4 with h = 1/1023: 3.4e-5.
    CHECK(worst < 3.5e-5);
    // First texel column: linear in u from 0, relative error ≤ K·h·v/2 = 0.6%.
    CHECK(worst_small < 6e-3);
    CHECK(fx::lookup_opacity(t, 2.0, -1.0) == 0.0);              // clamped, never wrapped
    CHECK(fx::lookup_opacity(t, 1.0, 1.0) == Approx(1.0 - std::exp(-12.0)).epsilon(1e-6));
    CHECK_THROWS_AS(fx::build_opacity_table(1, 12.0), fx::Error);
}

TEST_CASE("classic builder: transfer-function values are taken from the piece's side of a step", "[absorption]") {
    const fx::TransferFunction tf({{0.0, {0.2, 0.4, 1.0}, 0.05}, {0.5, {0.2, 0.4, 1.0}, 0.05},
                                   {0.5, {1.0, 0.55, 0.1}, 5.0}, {1.0, {1.0, 0.8, 0.3}, 3.0}});
    const fx::CellMesh tet = one_tet({glm::dvec3(0, 0, 0), {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
    const fx::ProjectorGeometry g = fx::build_projector_geometry(tet, &tet.scalars[0]);
    const fx::ClassicAbsorptionBuilder b(g, tf, {});
    CHECK(b.sample(0.5, 0.2, 0.5).sigma == 0.05); // a piece below the step sees the value from below
    CHECK(b.sample(0.5, 0.5, 0.8).sigma == 5.0);  // ... above it, from above
    CHECK(b.sample(0.3, 0.2, 0.5).sigma == 0.05);
    CHECK(b.sample(0.75, 0.5, 1.0).sigma == Approx(5.0 - 2.0 * 0.5));
}

TEST_CASE("problem faces: every cell some ray crosses twice is found, on a twisted grid", "[absorption]") {
    const fx::CellMesh mesh = absorption_test::twisted_box(3, 1.4);
    fx::ViewDependentSubdivision vds(mesh);
    REQUIRE(vds.candidate_faces() > 0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::size_t views_with_problems = 0;
    for (int view = 0; view < 16; ++view) {
        const glm::dvec3 dir = glm::normalize(glm::dvec3(uni(rng), uni(rng), 0.6 * uni(rng)));
        const fx::Camera cam = perspective(glm::dvec3(0.0, 0.0, 0.5) + 2.2 * dir, {0.0, 0.05, 0.5});
        vds.update(cam);
        views_with_problems += vds.subdivided_cells() > 0;
        // Brute force: which cells does some pixel ray (48×48) cross more than twice?
        for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
            bool folded = false;
            const auto r = absorption_test::pixel_bounds(mesh, c, cam, 48, 48);
            for (int y = r[1]; y <= r[3] && !folded; ++y)
                for (int x = r[0]; x <= r[2] && !folded; ++x) {
                    const std::vector<double> ts =
                        absorption_test::cell_crossings(mesh, c, cam.pixel_ray(x + 0.5, y + 0.5, 48, 48));
                    int distinct = ts.empty() ? 0 : 1;
                    for (std::size_t i = 1; i < ts.size(); ++i) distinct += ts[i] - ts[i - 1] > 1e-9;
                    folded = distinct > 2;
                }
            // Sampled rays can miss a thin fold, so a problem cell need not show one; a cell
            // that does must be a problem cell.
            INFO("view " << view << " cell " << c);
            if (folded) CHECK(vds.subdivided(std::uint32_t(c)));
        }
        // The working mesh: problem cells replaced by their tetrahedra, everything else kept.
        const fx::CellMesh& w = vds.cells();
        std::size_t pieces = 0;
        for (std::uint32_t c = 0; c < w.cell_count(); ++c) {
            if (vds.is_piece(c)) {
                ++pieces;
                CHECK(w.cell_types[c] == fx::CellType::Tetra);
                CHECK(vds.subdivided(vds.parent(c)));
            } else {
                CHECK_FALSE(vds.subdivided(vds.parent(c)));
            }
        }
        CHECK((pieces > 0) == (vds.subdivided_cells() > 0));
    }
    CHECK(views_with_problems > 0);
    // A planar mesh has no candidates at all.
    CHECK(fx::ViewDependentSubdivision(fx_test::hex_box(3, 3, 3)).candidate_faces() == 0);
}

TEST_CASE("problem faces: a dented cell is cut for the view that sees through its fold, then restored",
          "[absorption]") {
    // Unit cube with corner (1, 1, 1) (point 7) pushed in along x: only face x = 1 becomes
    // non-planar; it is cut by the diagonal from point 1 to point 7, folded reflex for the cell.
    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    mesh.points[7] = {0.8, 1.0, 1.0};
    fx::ViewDependentSubdivision vds(mesh);
    CHECK(vds.candidate_faces() == 1);
    auto from = [](glm::dvec3 dir) { return perspective(glm::dvec3(0.5) + 20.0 * glm::normalize(dir), glm::dvec3(0.5)); };
    // Face x = 1 is S = (1, 3, 7), normal ∝ (1, 0, 0.2), and T = (1, 7, 5), normal ∝ (1, 0.2, 0):
    // along (−0.1, 1, −1) one faces the eye and the other does not; the other faces agree.
    CHECK(vds.update(from({-0.1, 1.0, -1.0})));
    CHECK(vds.problem_faces() == 1);
    CHECK(vds.subdivided_cells() == 1);
    CHECK(vds.cells().cell_count() >= 5);
    CHECK(vds.cells().cell_types[0] == fx::CellType::Tetra);
    // From (1, −1, −1) both triangles of every dented face face the same way: restored.
    CHECK(vds.update(from({1.0, -1.0, -1.0})));
    CHECK(vds.subdivided_cells() == 0);
    CHECK(&vds.cells() == &mesh);
    const std::size_t rebuilds = vds.rebuilds();
    CHECK_FALSE(vds.update(from({1.0, -1.0, -1.01}))); // nothing changed: nothing rebuilt
    CHECK(vds.rebuilds() == rebuilds);
}

TEST_CASE("classic flavour's CPU half, rasterised in software, against the scan-line reference", "[absorption]") {
    // A small tetrahedral mesh seen from outside (orthographic: the screen-linear thickness of
    // §II is then exact), drawn in the power order after checking it is back to front.
    const fx::CellMesh mesh = absorption_test::delaunay_ball(40, 3);
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.8}, {0.5, {0.9, 0.6, 0.3}, 2.0}, {1.0, {1.0, 0.9, 0.4}, 3.5}});
    fx::Camera cam;
    cam.eye = {2.5, -3.0, 1.6}, cam.target = {0.0, 0.0, 0.0}, cam.up = {0, 0, 1};
    cam.ortho_height = 2.4, cam.near_distance = 0.5, cam.far_distance = 20.0;
    const int size = 40;
    // Delaunay: the power order is a visibility order (checked independently below).
    const std::vector<std::uint32_t> order = absorption_test::power_order(mesh, cam);
    const absorption_test::OrderCheck check = absorption_test::check_order(mesh, order, cam, size, size);

    const Setup s = setup(mesh, cam);
    fx::ClassicAbsorptionBuilder builder(s.geometry, tf, {});
    builder.set_view(s.view, s.frame);
    fx::ClassicGeometry g;
    builder.append(mesh, order.data(), order.size(), g);
    const fx::Image actual = absorption_test::rasterize_classic(g, fx::build_opacity_table(1024, 12.0), size, size);
    fx::ScanlineOptions so;
    const fx::Image expected = fx::ScanlineRenderer(mesh).render(cam, size, size, mesh.scalars[0], tf, so);
    // Orthographic, slices at every breakpoint: thickness, τ_a and so α are exact over each
    // polygon (linear on screen); what is left is the polygon colour C/α interpolated linearly
    // between exact vertex values (§II's approximation) and the opacity table's bilinear error
    // (< 4e-5). Measured 0.15% of peak at worst: per pixel 0.5%, mean 0.02% of peak.
    INFO("pixels out of order " << check.pixels_wrong << " of " << check.pixels_crossed << ", pieces " << g.pieces);
    CHECK(check.pixels_wrong == 0);
    verify::Tolerance t = verify::same_picture(0.0, "orthographic, sliced: §II's colour interpolation and the opacity table");
    t.pixel.of_peak = 0.005, t.mean.of_peak = 0.0002;
    verify::Options in_order;
    in_order.skip = &check.bad;
    fx_test::check_frame("classic_cpu", actual, expected, t, in_order);
}

TEST_CASE("classic builder: a hexahedron, wedge or pyramid draws what its consistent tetrahedra draw", "[absorption]") {
    // The builder projects a cell that is not a tetrahedron as its consistent tetrahedra in a
    // local back-to-front order. Drawn in a visibility order, the mixed mesh must then give
    // the same frame as the same mesh cut into those tetrahedra (fx::tetrahedralize): the same
    // polygons with the same vertex values meet every pixel ray in the same order, so the only
    // difference left is float rounding (1e-6 of peak). Perspective, a camera inside the mesh
    // (the near plane cuts cells) and a transfer function whose breakpoints slice them.
    fx::CellMesh mesh = fx_test::mixed_box(3);
    fx::set_scalar_field(mesh, "s", [](const glm::dvec3& p) { return 0.5 + 0.5 * std::sin(3.0 * p.x + 2.0 * p.y) * p.z; });
    const fx::CellMesh tets = fx::tetrahedralize(mesh);
    const fx::TransferFunction tf({{0.0, {0.2, 0.5, 1.0}, 0.8}, {0.45, {0.9, 0.6, 0.3}, 2.0}, {1.0, {1.0, 0.9, 0.4}, 3.5}});
    const int size = 48;
    struct View {
        const char* name;
        fx::Camera cam;
    };
    const View views[] = {{"outside", perspective({2.3, -1.5, 1.8}, {0.5, 0.5, 0.5})},
                          {"inside", perspective({0.45, 0.3, 0.6}, {1.0, 0.9, 0.4}, 0.15)}};
    for (const View& v : views) {
        for (bool slice : {false, true}) {
            auto draw = [&](const fx::CellMesh& m, std::size_t* pieces) {
                std::vector<std::uint32_t> order;
                fx::VisibilitySort(m, fx::SortMethod::Xmpvo).sort(v.cam, order);
                INFO(v.name << ": " << m.cell_count() << " cells");
                CHECK(absorption_test::check_order(m, order, v.cam, size, size).pixels_wrong == 0);
                const Setup s = setup(m, v.cam);
                fx::ClassicSettings settings;
                settings.slice_breakpoints = slice;
                fx::ClassicAbsorptionBuilder builder(s.geometry, tf, settings);
                builder.set_view(s.view, s.frame);
                fx::ClassicGeometry g;
                builder.append(m, order.data(), order.size(), g);
                *pieces = g.pieces;
                return absorption_test::rasterize_classic(g, fx::build_opacity_table(1024, 12.0), size, size);
            };
            std::size_t cell_pieces = 0, tet_pieces = 0;
            const fx::Image cells = draw(mesh, &cell_pieces), pieces = draw(tets, &tet_pieces);
            CHECK(cell_pieces == tet_pieces);
            verify::Tolerance same = verify::same_picture(0.0, "the same tetrahedra drawn: float rounding only");
            same.pixel.of_peak = 1e-6, same.mean.of_peak = 1e-6;
            fx_test::check_frame(std::string("classic_cells_as_tets_") + v.name + (slice ? "_sliced" : ""), cells, pieces,
                                 same);
        }
    }
}
