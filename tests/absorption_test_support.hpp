// Helpers for the Absorption path's tests: meshes (a Delaunay tetrahedralisation, a C-shaped
// grid, twisted hexahedra), an independent check that a cell order is back to front along
// every pixel ray, and a software rasteriser for the classic flavour's CPU output.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "absorption/absorption_classic.hpp"
#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/image.hpp"
#include "harness/synthetic_meshes.hpp"
#include "cellfx_names.hpp"

namespace absorption_test {

// ---- meshes ---------------------------------------------------------------------------------

// Delaunay tetrahedralisation (Bowyer–Watson) of `count` random points in the unit ball
// (fixed seed), positively oriented, with scalar "s" = a smooth function of position.
inline fx::CellMesh delaunay_ball(int count, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::vector<glm::dvec3> pts;
    while (int(pts.size()) < count) {
        const glm::dvec3 p(uni(rng), uni(rng), uni(rng));
        if (glm::dot(p, p) <= 1.0) pts.push_back(p);
    }
    // A super-tetrahedron far outside; its tetrahedra are dropped at the end.
    const double big = 1e4;
    const std::size_t n = pts.size();
    pts.push_back({-big, -big, -big});
    pts.push_back({big, 0.0, -big});
    pts.push_back({0.0, big, -big});
    pts.push_back({0.0, 0.0, big});
    struct Tet {
        std::array<std::uint32_t, 4> v;
        glm::dvec3 centre;
        double r2;
    };
    auto make = [&](std::array<std::uint32_t, 4> v) {
        const glm::dvec3 a = pts[v[0]], b = pts[v[1]] - a, c = pts[v[2]] - a, d = pts[v[3]] - a;
        const double det = 2.0 * glm::dot(b, glm::cross(c, d));
        const glm::dvec3 o = (glm::dot(b, b) * glm::cross(c, d) + glm::dot(c, c) * glm::cross(d, b) +
                              glm::dot(d, d) * glm::cross(b, c)) /
                             det;
        return Tet{v, a + o, glm::dot(o, o)};
    };
    std::vector<Tet> tets{make({std::uint32_t(n), std::uint32_t(n + 1), std::uint32_t(n + 2), std::uint32_t(n + 3)})};
    for (std::uint32_t p = 0; p < n; ++p) {
        std::vector<std::array<std::uint32_t, 3>> faces;
        std::vector<Tet> keep;
        for (const Tet& t : tets) {
            if (glm::dot(pts[p] - t.centre, pts[p] - t.centre) < t.r2) {
                static const int f[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
                for (const auto& k : f) {
                    std::array<std::uint32_t, 3> face{t.v[k[0]], t.v[k[1]], t.v[k[2]]};
                    std::sort(face.begin(), face.end());
                    const auto it = std::find(faces.begin(), faces.end(), face);
                    if (it == faces.end()) faces.push_back(face);
                    else faces.erase(it); // shared by two removed tetrahedra: inside the cavity
                }
            } else {
                keep.push_back(t);
            }
        }
        for (const auto& f : faces) keep.push_back(make({f[0], f[1], f[2], p}));
        tets = std::move(keep);
    }
    fx::CellMesh mesh;
    mesh.points.assign(pts.begin(), pts.begin() + n);
    mesh.begin_block("delaunay");
    for (const Tet& t : tets) {
        if (t.v[0] >= n || t.v[1] >= n || t.v[2] >= n || t.v[3] >= n) continue;
        std::array<std::uint32_t, 4> v = t.v;
        const glm::dvec3 a = pts[v[0]];
        if (glm::dot(pts[v[1]] - a, glm::cross(pts[v[2]] - a, pts[v[3]] - a)) < 0.0) std::swap(v[1], v[2]);
        mesh.add_cell(fx::CellType::Tetra, v.data());
    }
    fx::set_scalar_field(mesh, "s", [](const glm::dvec3& p) { return 0.5 + 0.35 * p.x + 0.25 * p.y * p.z - 0.2 * p.z; });
    return mesh;
}

// A C-shaped (non-convex) structured grid: a 270° annular sector around the z axis, radii
// 1..1.8, height 0..0.8. Its faces are planar (radial planes, chords, horizontal planes).
inline fx::CellMesh c_shape(std::uint32_t n_angle = 18, std::uint32_t n_radius = 3, std::uint32_t n_height = 3) {
    fx::CellMesh mesh;
    fx::append_curvilinear_block(mesh, "c", {n_angle + 1, n_radius + 1, n_height + 1}, [](double u, double v, double w) {
        // Angle falling with u, radius growing with v, height with w: a right-handed map, so
        // the cells are positively oriented.
        const double a = glm::radians(135.0 - 270.0 * u), r = 1.0 + 0.8 * v;
        return glm::dvec3(r * std::cos(a), r * std::sin(a), 0.8 * w);
    });
    fx::set_scalar_field(mesh, "s", [](const glm::dvec3& p) { return 0.5 + 0.3 * std::sin(2.0 * p.x) + 0.4 * p.z; });
    return mesh;
}

// A box of hexahedra twisted about its vertical axis (`twist` radians from bottom to top) and
// sheared: side faces are non-planar, folded one way for one cell and the other way for its
// neighbour.
inline fx::CellMesh twisted_box(std::uint32_t n, double twist) {
    fx::CellMesh mesh;
    fx::append_curvilinear_block(mesh, "twisted", {n + 1, n + 1, n + 1}, [twist](double u, double v, double w) {
        const double x = u - 0.5, y = v - 0.5, a = twist * w;
        return glm::dvec3(x * std::cos(a) - y * std::sin(a), x * std::sin(a) + y * std::cos(a) + 0.15 * w * w, w);
    });
    fx::set_scalar_field(mesh, "s", [](const glm::dvec3& p) { return 0.5 + 0.4 * p.x - 0.3 * p.y + 0.3 * p.z; });
    return mesh;
}

// Power-distance order (Edelsbrunner 1989; Max, Williams & Silva 2000 §III): farthest first by
// |eye − centre|² − r² of each tetrahedron's circumsphere — a visibility order for a Delaunay
// tetrahedralisation from any viewpoint. Orthographic: the eye at infinity behind the camera,
// i.e. by the circumcentre's depth along the view (then the power term).
inline std::vector<std::uint32_t> power_order(const fx::CellMesh& mesh, const fx::Camera& cam) {
    std::vector<std::pair<double, std::uint32_t>> keyed;
    const glm::dvec3 f = cam.forward();
    for (std::uint32_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* v = mesh.cell_vertices(c);
        const glm::dvec3 a = mesh.points[v[0]], b = mesh.points[v[1]] - a, cc = mesh.points[v[2]] - a,
                         d = mesh.points[v[3]] - a;
        const double det = 2.0 * glm::dot(b, glm::cross(cc, d));
        const glm::dvec3 o = (glm::dot(b, b) * glm::cross(cc, d) + glm::dot(cc, cc) * glm::cross(d, b) +
                              glm::dot(d, d) * glm::cross(b, cc)) /
                             det;
        const glm::dvec3 centre = a + o;
        const double key = cam.orthographic() ? glm::dot(centre - cam.eye, f) - 0.0
                                              : glm::dot(cam.eye - centre, cam.eye - centre) - glm::dot(o, o);
        keyed.emplace_back(key, c);
    }
    std::sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    std::vector<std::uint32_t> order;
    for (const auto& k : keyed) order.push_back(k.second);
    return order;
}

// ---- ray geometry -----------------------------------------------------------------------------

// Möller–Trumbore: ray parameter of the hit, or false. Barycentric slack `eps` so that rays
// through an edge or a vertex hit the triangles there despite rounding.
inline bool ray_triangle(const fx::Ray& ray, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double& t,
                         double eps = 1e-9) {
    const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-300) return false;
    const glm::dvec3 s = ray.origin - a;
    const double u = glm::dot(s, p) / det;
    if (u < -eps || u > 1.0 + eps) return false;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(ray.direction, q) / det;
    if (v < -eps || u + v > 1.0 + eps) return false;
    t = glm::dot(e2, q) / det;
    return true;
}

// All crossings of a ray with the faces (as triangles) of one cell, ascending.
inline std::vector<double> cell_crossings(const fx::CellMesh& mesh, std::size_t cell, const fx::Ray& ray) {
    std::vector<double> ts;
    const fx::CellType type = mesh.cell_types[cell];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int k = 0; k < fx::cell_face_count(type); ++k) {
        std::uint32_t tri[2][3];
        const int m = fx::triangulate_face(fx::cell_faces(type)[k], cv, tri);
        for (int i = 0; i < m; ++i) {
            double t;
            if (ray_triangle(ray, mesh.points[tri[i][0]], mesh.points[tri[i][1]], mesh.points[tri[i][2]], t))
                ts.push_back(t);
        }
    }
    std::sort(ts.begin(), ts.end());
    return ts;
}

// Pixel rectangle a cell's projection can touch (the whole image if a vertex is behind the eye).
inline std::array<int, 4> pixel_bounds(const fx::CellMesh& mesh, std::size_t cell, const fx::Camera& cam, int w, int h) {
    const glm::dmat4 vp = cam.projection_matrix(double(w) / h) * cam.view_matrix();
    double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300;
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int i = 0; i < fx::cell_vertex_count(mesh.cell_types[cell]); ++i) {
        const glm::dvec4 c = vp * glm::dvec4(mesh.points[cv[i]], 1.0);
        if (!(c.w > 1e-9)) return {0, 0, w - 1, h - 1};
        const double x = (c.x / c.w + 1.0) * 0.5 * w, y = (c.y / c.w + 1.0) * 0.5 * h;
        lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x), lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
    }
    return {std::max(0, int(std::floor(lo_x)) - 1), std::max(0, int(std::floor(lo_y)) - 1),
            std::min(w - 1, int(std::ceil(hi_x)) + 1), std::min(h - 1, int(std::ceil(hi_y)) + 1)};
}

// Whether drawing `order` back to front is right along each pixel's ray: for every pixel, the
// cells its ray crosses beyond the near plane (by ray–triangle intersection, independent of
// the renderer), nearest first, must appear in `order` in reverse. `bad` marks the pixels
// where they do not; a cell the ray crosses more than twice (a non-convex cell seen through
// its fold) also marks the pixel.
struct OrderCheck {
    std::size_t pixels_crossed = 0; // pixels whose ray crosses at least one cell
    std::size_t pixels_wrong = 0;
    std::vector<std::uint8_t> bad; // per pixel, bottom row first
};
inline OrderCheck check_order(const fx::CellMesh& mesh, const std::vector<std::uint32_t>& order, const fx::Camera& cam,
                              int w, int h) {
    std::vector<std::uint32_t> rank(mesh.cell_count(), 0);
    for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
    struct Hit {
        double t_in, t_out;
        std::uint32_t cell;
    };
    std::vector<std::vector<Hit>> hits(std::size_t(w) * h);
    std::vector<std::uint8_t> folded(std::size_t(w) * h, 0);
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    const double scale = glm::length(bounds.size()) + glm::length(cam.eye - bounds.center());
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const auto r = pixel_bounds(mesh, c, cam, w, h);
        for (int y = r[1]; y <= r[3]; ++y)
            for (int x = r[0]; x <= r[2]; ++x) {
                const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, w, h);
                const std::vector<double> ts = cell_crossings(mesh, c, ray);
                if (ts.size() < 2) continue;
                const double t_near = cam.orthographic() ? cam.near_distance
                                                         : cam.near_distance / glm::dot(ray.direction, cam.forward());
                const double t_in = std::max(ts.front(), t_near), t_out = ts.back();
                if (!(t_out - t_in > 1e-9 * scale)) continue; // grazing, or in front of the near plane
                // More than two distinct crossings: the ray leaves and re-enters the cell.
                int distinct = 1;
                for (std::size_t i = 1; i < ts.size(); ++i) distinct += ts[i] - ts[i - 1] > 1e-9 * scale;
                if (distinct > 2) folded[std::size_t(y) * w + x] = 1;
                hits[std::size_t(y) * w + x].push_back({t_in, t_out, std::uint32_t(c)});
            }
    }
    OrderCheck out;
    out.bad.assign(std::size_t(w) * h, 0);
    for (std::size_t p = 0; p < hits.size(); ++p) {
        auto& list = hits[p];
        if (list.empty()) continue;
        ++out.pixels_crossed;
        std::sort(list.begin(), list.end(), [](const Hit& a, const Hit& b) { return a.t_in + a.t_out < b.t_in + b.t_out; });
        bool wrong = folded[p] != 0;
        for (std::size_t i = 1; i < list.size() && !wrong; ++i) wrong = rank[list[i].cell] > rank[list[i - 1].cell];
        if (wrong) out.bad[p] = 1, ++out.pixels_wrong;
    }
    return out;
}

// ---- software rasteriser of the classic flavour's CPU output ----------------------------------

// Draws the triangles in order with GL's conventions (pixel centres, top-left fill rule),
// u, v and colour interpolated linearly on screen, α from the opacity table, "over".
inline fx::Image rasterize_classic(const fx::ClassicGeometry& g, const fx::OpacityTable& table, int w, int h) {
    fx::Image img(w, h);
    for (std::size_t t = 0; t + 2 < g.indices.size(); t += 3) {
        const fx::ClassicVertex* v[3] = {&g.vertices[g.indices[t]], &g.vertices[g.indices[t + 1]],
                                         &g.vertices[g.indices[t + 2]]};
        glm::dvec2 p[3];
        for (int i = 0; i < 3; ++i)
            p[i] = glm::dvec2((v[i]->position_uv.x + 1.0) * 0.5 * w, (v[i]->position_uv.y + 1.0) * 0.5 * h);
        double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
        if (area == 0.0) continue;
        if (area < 0.0) std::swap(p[1], p[2]), std::swap(v[1], v[2]), area = -area;
        const int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x})))),
                  x1 = std::min(w - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x})))),
                  y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y})))),
                  y1 = std::min(h - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const glm::dvec2 c(x + 0.5, y + 0.5);
                double b[3];
                bool inside = true;
                for (int i = 0; i < 3 && inside; ++i) {
                    const glm::dvec2 a = p[(i + 1) % 3], e = p[(i + 2) % 3] - a;
                    b[i] = (e.x * (c.y - a.y) - e.y * (c.x - a.x)) / area;
                    // Top-left rule: pixels on an edge belong to the triangle left of a top or left edge.
                    const bool top_left = (e.y == 0.0 && e.x < 0.0) || e.y < 0.0;
                    inside = b[i] > 0.0 || (b[i] == 0.0 && top_left);
                }
                if (!inside) continue;
                glm::dvec4 uvc(0.0);
                glm::dvec3 color(0.0);
                for (int i = 0; i < 3; ++i) {
                    uvc += b[i] * glm::dvec4(v[i]->position_uv);
                    color += b[i] * glm::dvec3(v[i]->color);
                }
                const double alpha = fx::lookup_opacity(table, uvc.z, uvc.w);
                glm::vec4& dst = img.at(x, y);
                dst = glm::vec4(glm::dvec4(color * alpha, alpha) + (1.0 - alpha) * glm::dvec4(dst));
            }
    }
    return img;
}

} // namespace absorption_test
