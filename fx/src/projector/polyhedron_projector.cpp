// Based on: Roettger & Ertl 2003, §3 (d, d_min, Δd, front/back faces) and §5 (near-plane caps).
#include "projector/polyhedron_projector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/error.hpp"
#include "frame_storage.hpp"

namespace cellfx::fx {

std::size_t ProjectorGeometry::memory_bytes() const {
    return positions.capacity() * sizeof(glm::vec3) + scalars.capacity() * sizeof(float) +
           cell_first_triangle.capacity() * sizeof(std::uint32_t) +
           triangles.capacity() * sizeof(std::array<std::uint32_t, 3>) +
           triangle_cell.capacity() * sizeof(std::uint32_t) + triangle_planes.capacity() * sizeof(glm::vec4);
}

ProjectorGeometry build_projector_geometry(const CellMesh& mesh, const ScalarField* scalars) {
    ProjectorGeometry g;
    build_projector_geometry(mesh, scalars, g);
    return g;
}

glm::vec4 triangle_plane(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    const double scale = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)});
    if (!(len > 1e-12 * scale * scale && len > 0.0)) return glm::vec4(0.0f);
    const glm::dvec3 u = n / len;
    return glm::vec4(glm::vec3(u), float(glm::dot(u, (a + b + c) / 3.0)));
}

void compute_triangle_planes(ProjectorGeometry& g) {
    resize_kept(g.triangle_planes, g.triangles.size());
    // In double from the float positions the GPU sees, so CPU and GPU agree on which side of a
    // plane a point lies.
    for (std::size_t t = 0; t < g.triangles.size(); ++t) {
        const auto& tri = g.triangles[t];
        g.triangle_planes[t] =
            triangle_plane(glm::dvec3(g.positions[tri[0]]), glm::dvec3(g.positions[tri[1]]), glm::dvec3(g.positions[tri[2]]));
    }
}

void build_projector_geometry(const CellMesh& mesh, const ScalarField* scalars, ProjectorGeometry& g, bool planes) {
    const std::size_t np = mesh.point_count();
    if (scalars && scalars->values.size() != np) {
        throw Error("projector: scalar field '" + scalars->name + "' has " + std::to_string(scalars->values.size()) +
                    " values for " + std::to_string(np) + " points");
    }
    const Bounds bounds = mesh_bounds(mesh);
    if (!bounds.empty()) {
        const auto text = [](double v) {
            char buffer[32];
            std::snprintf(buffer, sizeof buffer, "%g", v);
            return std::string(buffer);
        };
        for (const glm::dvec3& corner : {bounds.lo, bounds.hi})
            if (std::max({std::abs(corner.x), std::abs(corner.y), std::abs(corner.z)}) > kMaxCoordinate)
                throw Error("projector: the mesh reaches (" + text(corner.x) + ", " + text(corner.y) + ", " +
                            text(corner.z) + "), beyond ±" + text(kMaxCoordinate) +
                            ", the coordinates cellfx renders (scale the mesh)");
        const double extent = glm::length(bounds.size());
        if (extent > 0.0 && extent < kMinProjectorExtent)
            throw Error("projector: the mesh spans " + text(extent) + " (its bounding box's diagonal), under " +
                        text(kMinProjectorExtent) + ", the smallest the GPU paths keep float precision for (scale the mesh)");
    }
    g.origin = bounds.empty() ? glm::dvec3(0.0) : bounds.center();
    g.extent = bounds.empty() ? 0.0 : glm::length(bounds.size());
    resize_kept(g.positions, np);
    assign_kept(g.scalars, np, 0.0f);
    for (std::size_t i = 0; i < np; ++i) {
        const glm::dvec3& p = mesh.points[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw Error("projector: point " + std::to_string(i) + " has a non-finite coordinate");
        }
        g.positions[i] = glm::vec3(p - g.origin);
        if (scalars) {
            const float s = scalars->values[i];
            if (!std::isfinite(s)) {
                throw Error("projector: scalar '" + scalars->name + "' of point " + std::to_string(i) +
                            " is not finite");
            }
            g.scalars[i] = s;
        }
    }

    const std::size_t nc = mesh.cell_count();
    g.cell_first_triangle.clear();
    g.triangles.clear();
    g.triangle_cell.clear();
    g.triangle_planes.clear();
    reserve_kept(g.cell_first_triangle, nc + 1);
    g.cell_first_triangle.push_back(0);
    for (std::size_t c = 0; c < nc; ++c) {
        const CellType type = mesh.cell_types[c];
        const std::uint32_t* cv = mesh.cell_vertices(c);
        for (int v = 0; v < cell_vertex_count(type); ++v) {
            if (cv[v] >= np) {
                throw Error("projector: cell " + std::to_string(c) + " uses point " + std::to_string(cv[v]) +
                            " but the mesh has " + std::to_string(np) + " points");
            }
        }
        const CellFace* faces = cell_faces(type);
        for (int f = 0; f < cell_face_count(type); ++f) {
            std::uint32_t tri[2][3];
            const int n = triangulate_face(faces[f], cv, tri);
            for (int t = 0; t < n; ++t) {
                g.triangles.push_back({tri[t][0], tri[t][1], tri[t][2]});
                g.triangle_cell.push_back(static_cast<std::uint32_t>(c));
            }
        }
        g.cell_first_triangle.push_back(static_cast<std::uint32_t>(g.triangles.size()));
    }
    if (planes) compute_triangle_planes(g);
}

double ProjectorView::depth(const glm::dvec3& p) const { return glm::dot(p - eye, forward) - near_distance; }

ProjectorView make_projector_view(const ProjectorGeometry& geometry, const Camera& camera) {
    ProjectorView v;
    // world = rel + origin, so view_rel = view_world · translate(origin), composed in double.
    v.view = camera.view_matrix() * glm::translate(glm::dmat4(1.0), geometry.origin);
    v.eye = camera.eye - geometry.origin;
    v.forward = camera.forward();
    v.near_distance = camera.clipping_near(geometry.extent);
    v.far_distance = camera.far_distance;
    v.orthographic = camera.orthographic();
    return v;
}

void project_cells(const CellMesh& mesh, const ProjectorGeometry& geometry, const ProjectorView& view,
                   ProjectedCells& out) {
    const std::size_t np = geometry.positions.size();
    resize_kept(out.point_depth, np);
    for (std::size_t i = 0; i < np; ++i) out.point_depth[i] = float(view.depth(glm::dvec3(geometry.positions[i])));
    const std::size_t nc = mesh.cell_count();
    resize_kept(out.depth_range, nc);
    out.cut_cells.clear();
    for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t* cv = mesh.cell_vertices(c);
        const int n = cell_vertex_count(mesh.cell_types[c]);
        float lo = out.point_depth[cv[0]], hi = lo;
        for (int k = 1; k < n; ++k) {
            const float d = out.point_depth[cv[k]];
            lo = std::min(lo, d);
            hi = std::max(hi, d);
        }
        out.depth_range[c] = glm::vec2(lo, hi - lo);
        if (lo < 0.0f && hi > 0.0f) out.cut_cells.push_back(static_cast<std::uint32_t>(c));
    }
}

float normalized_depth(float d, glm::vec2 depth_range) {
    if (!(depth_range.y > 0.0f)) return 0.0f;
    const float a = (d - depth_range.x) / depth_range.y;
    return std::clamp(a, 0.0f, 1.0f);
}

FaceSide classify_triangle(const ProjectorGeometry& geometry, const ProjectorView& view, std::size_t triangle) {
    const auto& t = geometry.triangles[triangle];
    const glm::dvec3 a(geometry.positions[t[0]]), b(geometry.positions[t[1]]), c(geometry.positions[t[2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area2 = glm::length(n);
    if (!(area2 > 0.0)) return FaceSide::EdgeOn;
    // Signed distance of the eye from the plane (orthographic: the direction towards the eye).
    double s;
    double tolerance;
    if (view.orthographic) {
        s = -glm::dot(n, view.forward) / area2;
        tolerance = 1e-12;
    } else {
        const glm::dvec3 centre = (a + b + c) / 3.0;
        s = glm::dot(n, view.eye - centre) / area2;
        const double size = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b),
                                      glm::length(view.eye - centre)});
        tolerance = 1e-9 * size; // float positions: anything closer is "on the plane"
    }
    if (s > tolerance) return FaceSide::Front;
    if (s < -tolerance) return FaceSide::Back;
    return FaceSide::EdgeOn;
}

void classify_triangles(const ProjectorGeometry& geometry, const ProjectorView& view, std::vector<FaceSide>& out) {
    resize_kept(out, geometry.triangles.size());
    for (std::size_t t = 0; t < out.size(); ++t) out[t] = classify_triangle(geometry, view, t);
}

namespace {

struct CapPoint {
    glm::dvec3 p;   // relative frame
    double s;       // scalar
    glm::dvec2 q;   // coordinates in the near plane (eye x, y)
};

double cross2(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

} // namespace

bool append_near_cap(const ProjectorGeometry& geometry, const ProjectorView& view, const ProjectedCells& projected,
                     std::uint32_t cell, NearCaps& caps) {
    const glm::vec2 range = projected.depth_range[cell];
    if (!(range.x < 0.0f && range.x + range.y > 0.0f)) return false;
    // Screen-aligned axes of the near plane.
    const glm::dvec3 right(view.view[0][0], view.view[1][0], view.view[2][0]);
    const glm::dvec3 up(view.view[0][1], view.view[1][1], view.view[2][1]);
    // Depths recomputed in double: the float point_depth only decides which cells are cut.
    const double tol = 1e-9 * double(range.y);
    thread_local std::vector<CapPoint> points;
    points.clear();
    auto add = [&](const glm::dvec3& p, double s) {
        points.push_back({p, s, glm::dvec2(glm::dot(p, right), glm::dot(p, up))});
    };
    for (std::uint32_t t = geometry.cell_first_triangle[cell]; t < geometry.cell_first_triangle[cell + 1]; ++t) {
        const auto& tri = geometry.triangles[t];
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t ia = tri[e], ib = tri[(e + 1) % 3];
            const glm::dvec3 a(geometry.positions[ia]), b(geometry.positions[ib]);
            const double da = view.depth(a), db = view.depth(b);
            const bool za = std::abs(da) <= tol, zb = std::abs(db) <= tol;
            if (za) add(a - view.forward * da, geometry.scalars[ia]); // on the plane: take it (projected onto it)
            if (!za && !zb && ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))) {
                const double f = da / (da - db); // in (0, 1): no division by ~0 since signs differ
                glm::dvec3 p = a + (b - a) * f;
                p -= view.forward * view.depth(p); // snap exactly onto the plane
                add(p, double(geometry.scalars[ia]) + (double(geometry.scalars[ib]) - geometry.scalars[ia]) * f);
            }
        }
    }
    if (points.size() < 3) return false;
    // Convex hull (Andrew's monotone chain): drops repeated points (each edge is seen from two
    // triangles; vertices on the plane from several) and collinear ones; CCW in (right, up).
    std::sort(points.begin(), points.end(), [](const CapPoint& x, const CapPoint& y) {
        return x.q.x < y.q.x || (x.q.x == y.q.x && x.q.y < y.q.y);
    });
    double extent = 0.0;
    for (const CapPoint& p : points) extent = std::max({extent, std::abs(p.q.x - points[0].q.x), std::abs(p.q.y - points[0].q.y)});
    const double area_tol = 1e-12 * extent * extent;
    thread_local std::vector<std::size_t> hull;
    assign_kept(hull, 2 * points.size(), 0);
    std::size_t k = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross2(points[hull[k - 2]].q, points[hull[k - 1]].q, points[i].q) <= area_tol) --k;
        hull[k++] = i;
    }
    for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross2(points[hull[k - 2]].q, points[hull[k - 1]].q, points[i].q) <= area_tol) --k;
        hull[k++] = i;
    }
    if (k < 4) return false; // closed chain repeats the first point: < 3 distinct corners
    for (std::size_t i = 0; i + 1 < k; ++i) {
        caps.positions.emplace_back(points[hull[i]].p);
        caps.scalars.push_back(float(points[hull[i]].s));
    }
    caps.first_vertex.push_back(static_cast<std::uint32_t>(caps.positions.size()));
    caps.cell.push_back(cell);
    return true;
}

void build_near_caps(const ProjectorGeometry& geometry, const ProjectorView& view, const ProjectedCells& projected,
                     NearCaps& caps) {
    caps.clear();
    for (std::uint32_t c : projected.cut_cells) append_near_cap(geometry, view, projected, c, caps);
}

} // namespace cellfx::fx
