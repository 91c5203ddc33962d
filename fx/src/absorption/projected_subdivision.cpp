// Based on: Max, Williams & Silva 2000, §II (polyhedron projection: the subdivision of the
// image plane by the projected edges, thickness and front/back values at its vertices) and
// Shirley & Tuchman 1990 (the four projection classes of a tetrahedron).
#include "absorption/projected_subdivision.hpp"
#include "frame_storage.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace cellfx::fx {
namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Relative tolerances, as fractions of the cell's screen extent: anything closer to a line is
// on it, anything of smaller area has none. Far above double rounding, far below a pixel.
constexpr double kLineTolerance = 1e-12;
constexpr double kAreaTolerance = 1e-12;

double polygon_area(const std::vector<glm::dvec2>& p) {
    double a = 0.0;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) a += cross2(p[i], p[(i + 1) % n]);
    return 0.5 * a;
}

} // namespace

ProjectionFrame make_projection_frame(const ProjectorView& view, const Camera& camera, double aspect) {
    ProjectionFrame f;
    f.view = view.view;
    f.projection = camera.projection_matrix(aspect);
    f.orthographic = camera.orthographic();
    return f;
}

ProjectionFrame make_projection_frame(const ProjectorView& view, const Camera& camera, int width, int height,
                                      int subpixel_bits) {
    ProjectionFrame f = make_projection_frame(view, camera, double(width) / double(height));
    f.pixels_per_ndc = 0.5 * glm::dvec2(width, height);
    f.subpixel_step = subpixel_bits > 0 ? std::ldexp(1.0, -std::min(subpixel_bits, 16)) : 0.0;
    return f;
}

glm::dvec2 ProjectionFrame::snap(const glm::dvec2& ndc) const {
    if (!(subpixel_step > 0.0) || !(pixels_per_ndc.x > 0.0) || !(pixels_per_ndc.y > 0.0)) return ndc;
    // Window position (the viewport's integer offset keeps the grid), rounded to the step.
    const glm::dvec2 window = (ndc + 1.0) * pixels_per_ndc;
    return glm::round(window / subpixel_step) * subpixel_step / pixels_per_ndc - 1.0;
}

double ProjectedSubdivision::area() const {
    double total = 0.0;
    for (std::size_t k = 0; k + 1 < polygon_start.size(); ++k) {
        const std::uint32_t b = polygon_start[k], e = polygon_start[k + 1];
        for (std::uint32_t i = b; i < e; ++i) {
            const std::uint32_t j = i + 1 == e ? b : i + 1;
            total += 0.5 * cross2(vertices[polygon_vertices[i]].ndc, vertices[polygon_vertices[j]].ndc);
        }
    }
    return total;
}

bool SubdivisionBuilder::project(const ProjectionFrame& frame, const PolyVertex* v, std::size_t n) {
    resize_kept(points_, n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec4 eye = frame.view * glm::dvec4(v[i].position, 1.0);
        const glm::dvec4 clip = frame.projection * eye;
        if (!(clip.w > 0.0)) return false; // behind the eye: the caller must clip first
        points_[i] = {glm::dvec2(clip.x, clip.y) / clip.w, clip.w, glm::dvec3(eye), v[i].scalar};
    }
    return true;
}

void SubdivisionBuilder::locate(const glm::dvec2& p, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                                glm::dvec3& eye, double& s) const {
    const Projected &pa = points_[a], &pb = points_[b], &pc = points_[c];
    const double den = cross2(pb.ndc - pa.ndc, pc.ndc - pa.ndc);
    // Screen barycentrics (exactly 1, 0, 0 at a vertex), clamped against rounding outside.
    double ba = cross2(pb.ndc - p, pc.ndc - p) / den;
    double bb = cross2(pc.ndc - p, pa.ndc - p) / den;
    double bc = 1.0 - ba - bb;
    ba = std::max(ba, 0.0), bb = std::max(bb, 0.0), bc = std::max(bc, 0.0);
    // Perspective-correct: weights β/w, so the point lies on the triangle in 3-D.
    const double la = ba / pa.w, lb = bb / pb.w, lc = bc / pc.w;
    const double sum = la + lb + lc;
    eye = (la * pa.eye + lb * pb.eye + lc * pc.eye) / sum;
    s = (la * pa.s + lb * pb.s + lc * pc.s) / sum;
}

std::uint32_t SubdivisionBuilder::add_vertex(const glm::dvec2& p, std::uint32_t f[3], std::uint32_t b[3],
                                             double tolerance, ProjectedSubdivision& out) {
    // The front and back surfaces of a convex cell are continuous, so one screen point has
    // one set of values whichever polygon it is reached from: share it (the same point
    // reached through different clip lines differs by rounding only).
    for (std::size_t i = first_vertex_; i < out.vertices.size(); ++i) {
        const glm::dvec2 d = out.vertices[i].ndc - p;
        if (std::abs(d.x) <= tolerance && std::abs(d.y) <= tolerance) return static_cast<std::uint32_t>(i);
    }
    SubdivisionVertex v;
    v.ndc = p;
    glm::dvec3 ef, eb;
    locate(p, f[0], f[1], f[2], ef, v.s_front);
    locate(p, b[0], b[1], b[2], eb, v.s_back);
    v.thickness = glm::length(eb - ef); // the view transform is rigid: eye lengths are world lengths
    v.depth_front = -ef.z, v.depth_back = -eb.z;
    out.vertices.push_back(v);
    return static_cast<std::uint32_t>(out.vertices.size() - 1);
}

std::uint32_t SubdivisionBuilder::add_profile_vertex(std::uint32_t i, ProjectedSubdivision& out) {
    SubdivisionVertex v;
    v.ndc = points_[i].ndc;
    v.s_front = v.s_back = points_[i].s;
    v.depth_front = v.depth_back = -points_[i].eye.z;
    out.vertices.push_back(v);
    return static_cast<std::uint32_t>(out.vertices.size() - 1);
}

void SubdivisionBuilder::tetrahedron(const ProjectionFrame& frame, const std::array<PolyVertex, 4>& tet,
                                     ProjectedSubdivision& out) {
    if (!project(frame, tet.data(), 4)) return;
    glm::dvec2 lo = points_[0].ndc, hi = lo;
    for (const Projected& p : points_) lo = glm::min(lo, p.ndc), hi = glm::max(hi, p.ndc);
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    if (!(extent > 0.0)) return;
    const double line_tol = kLineTolerance * extent, area_tol = kAreaTolerance * extent * extent;
    auto orient = [&](std::uint32_t a, std::uint32_t b, const glm::dvec2& p) {
        const glm::dvec2 e = points_[b].ndc - points_[a].ndc;
        return cross2(e, p - points_[a].ndc) / std::max(glm::length(e), 1e-300);
    };
    auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::dvec2& pa, const glm::dvec2& pb,
                    const glm::dvec2& pc) {
        if (!(0.5 * cross2(pb - pa, pc - pa) > area_tol)) return; // degenerate class: no area
        out.polygon_vertices.insert(out.polygon_vertices.end(), {a, b, c});
        out.polygon_start.push_back(static_cast<std::uint32_t>(out.polygon_vertices.size()));
    };

    // Class 1: one vertex projects inside (or onto the border of) the others' triangle.
    for (std::uint32_t i = 0; i < 4; ++i) {
        std::uint32_t j = (i + 1) % 4, k = (i + 2) % 4, l = (i + 3) % 4;
        double area = cross2(points_[k].ndc - points_[j].ndc, points_[l].ndc - points_[j].ndc);
        if (area < 0.0) std::swap(k, l), area = -area;
        if (!(0.5 * area > area_tol)) continue;
        const glm::dvec2& p = points_[i].ndc;
        if (orient(j, k, p) < -line_tol || orient(k, l, p) < -line_tol || orient(l, j, p) < -line_tol) continue;
        // The ray through vertex i meets the opposite face (j, k, l): that is the thickness.
        glm::dvec3 eye;
        double s;
        locate(p, j, k, l, eye, s);
        SubdivisionVertex v;
        v.ndc = p;
        v.thickness = glm::length(eye - points_[i].eye);
        const bool vertex_in_front = points_[i].eye.z > eye.z; // eye looks down −z
        v.s_front = vertex_in_front ? points_[i].s : s;
        v.s_back = vertex_in_front ? s : points_[i].s;
        v.depth_front = -std::max(points_[i].eye.z, eye.z), v.depth_back = -std::min(points_[i].eye.z, eye.z);
        const std::uint32_t base = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(v);
        const std::uint32_t a = add_profile_vertex(j, out), b = add_profile_vertex(k, out),
                            c = add_profile_vertex(l, out);
        emit(base, a, b, p, points_[j].ndc, points_[k].ndc);
        emit(base, b, c, p, points_[k].ndc, points_[l].ndc);
        emit(base, c, a, p, points_[l].ndc, points_[j].ndc);
        return;
    }

    // Class 2: the four points are in convex position and the diagonals of their hull are
    // the two edges whose projections cross, at G.
    glm::dvec2 centre(0.0);
    for (const Projected& p : points_) centre += 0.25 * p.ndc;
    std::array<std::uint32_t, 4> h{0, 1, 2, 3};
    std::array<double, 4> angle; // a pseudo-angle: monotonic in the angle, no atan2
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 d = points_[i].ndc - centre;
        const double r = d.y / (std::abs(d.x) + std::abs(d.y) + 1e-300); // in [−1, 1]
        angle[i] = d.x >= 0.0 ? r : (d.y >= 0.0 ? 2.0 - r : -2.0 - r);
    }
    std::sort(h.begin(), h.end(), [&](std::uint32_t a, std::uint32_t b) { return angle[a] < angle[b]; });
    const glm::dvec2 a = points_[h[0]].ndc, b = points_[h[2]].ndc, c = points_[h[1]].ndc, d = points_[h[3]].ndc;
    const double den = cross2(b - a, d - c);
    if (!(std::abs(den) > area_tol)) return; // collinear projection: no area
    const double t = std::clamp(cross2(c - a, d - c) / den, 0.0, 1.0);
    const double u = std::clamp(cross2(c - a, b - a) / den, 0.0, 1.0);
    const glm::dvec2 g = a + t * (b - a);
    // Perspective-correct points on the two 3-D edges under G.
    auto on_edge = [&](std::uint32_t i0, std::uint32_t i1, double f, glm::dvec3& eye, double& s) {
        const double w0 = (1.0 - f) / points_[i0].w, w1 = f / points_[i1].w;
        const double lambda = w1 / (w0 + w1);
        eye = points_[i0].eye + lambda * (points_[i1].eye - points_[i0].eye);
        s = points_[i0].s + lambda * (points_[i1].s - points_[i0].s);
    };
    glm::dvec3 e1, e2;
    double s1, s2;
    on_edge(h[0], h[2], t, e1, s1);
    on_edge(h[1], h[3], u, e2, s2);
    SubdivisionVertex v;
    v.ndc = g;
    v.thickness = glm::length(e1 - e2);
    v.s_front = e1.z > e2.z ? s1 : s2;
    v.s_back = e1.z > e2.z ? s2 : s1;
    v.depth_front = -std::max(e1.z, e2.z), v.depth_back = -std::min(e1.z, e2.z);
    const std::uint32_t base = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.push_back(v);
    std::array<std::uint32_t, 4> ids;
    for (int i = 0; i < 4; ++i) ids[i] = add_profile_vertex(h[i], out);
    for (int i = 0; i < 4; ++i)
        emit(base, ids[i], ids[(i + 1) % 4], g, points_[h[i]].ndc, points_[h[(i + 1) % 4]].ndc);
}

void SubdivisionBuilder::polyhedron(const ProjectionFrame& frame, const ConvexPolyhedron& cell,
                                    ProjectedSubdivision& out) {
    if (cell.triangles.empty() || !project(frame, cell.vertices.data(), cell.vertices.size())) return;
    glm::dvec2 lo = points_[0].ndc, hi = lo;
    for (const Projected& p : points_) lo = glm::min(lo, p.ndc), hi = glm::max(hi, p.ndc);
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    if (!(extent > 0.0)) return;
    const double line_tol = kLineTolerance * extent, area_tol = kAreaTolerance * extent * extent;

    // Front triangles (counter-clockwise on screen) and back ones, reversed to counter-clockwise,
    // with their screen boxes and (back) clip lines; edge-on ones bound nothing.
    front_.clear(), back_.clear();
    for (std::uint32_t t = 0; t < cell.triangles.size(); ++t) {
        const auto& tri = cell.triangles[t];
        const double a = 0.5 * cross2(points_[tri[1]].ndc - points_[tri[0]].ndc, points_[tri[2]].ndc - points_[tri[0]].ndc);
        if (!(std::abs(a) > area_tol)) continue;
        ScreenTriangle st;
        st.v[0] = tri[0], st.v[1] = a > 0.0 ? tri[1] : tri[2], st.v[2] = a > 0.0 ? tri[2] : tri[1];
        st.lo = glm::min(points_[st.v[0]].ndc, glm::min(points_[st.v[1]].ndc, points_[st.v[2]].ndc));
        st.hi = glm::max(points_[st.v[0]].ndc, glm::max(points_[st.v[1]].ndc, points_[st.v[2]].ndc));
        for (int e = 0; e < 3; ++e) {
            st.origin[e] = points_[st.v[e]].ndc;
            st.dir[e] = points_[st.v[(e + 1) % 3]].ndc - st.origin[e];
            st.inv_length[e] = 1.0 / std::max(glm::length(st.dir[e]), 1e-300);
        }
        (a > 0.0 ? front_ : back_).push_back(st);
    }
    first_vertex_ = out.vertices.size();

    for (ScreenTriangle& f : front_) {
        for (ScreenTriangle& b : back_) {
            if (b.lo.x > f.hi.x + line_tol || b.lo.y > f.hi.y + line_tol || f.lo.x > b.hi.x + line_tol ||
                f.lo.y > b.hi.y + line_tol)
                continue;
            // Sutherland–Hodgman: the front triangle clipped to the back triangle's half-planes.
            polygon_.assign({f.origin[0], f.origin[1], f.origin[2]});
            for (int e = 0; e < 3 && polygon_.size() >= 3; ++e) {
                const glm::dvec2 a = b.origin[e], dir = b.dir[e];
                const double inv_len = b.inv_length[e];
                clipped_.clear();
                const std::size_t n = polygon_.size();
                for (std::size_t i = 0; i < n; ++i) {
                    const glm::dvec2& prev = polygon_[(i + n - 1) % n];
                    const glm::dvec2& cur = polygon_[i];
                    const double dp = cross2(dir, prev - a) * inv_len, dc = cross2(dir, cur - a) * inv_len;
                    if (dc >= -line_tol) {
                        if (dp < -line_tol && dc > line_tol) clipped_.push_back(prev + (dp / (dp - dc)) * (cur - prev));
                        clipped_.push_back(cur);
                    } else if (dp > line_tol) {
                        clipped_.push_back(prev + (dp / (dp - dc)) * (cur - prev));
                    }
                }
                std::swap(polygon_, clipped_);
            }
            // Drop repeated points (a vertex on a clip line is kept once).
            clipped_.clear();
            for (std::size_t i = 0; i < polygon_.size(); ++i) {
                const glm::dvec2& p = polygon_[i];
                const glm::dvec2& q = polygon_[(i + 1) % polygon_.size()];
                if (std::max(std::abs(p.x - q.x), std::abs(p.y - q.y)) > line_tol) clipped_.push_back(p);
            }
            if (clipped_.size() < 3 || !(polygon_area(clipped_) > area_tol)) continue;
            for (const glm::dvec2& p : clipped_) out.polygon_vertices.push_back(add_vertex(p, f.v, b.v, line_tol, out));
            out.polygon_start.push_back(static_cast<std::uint32_t>(out.polygon_vertices.size()));
        }
    }
}

void clip_polyhedron(const ConvexPolyhedron& in, const std::vector<double>& f, const glm::dvec3& increasing,
                     ConvexPolyhedron& out, double cut_scalar) {
    out.clear();
    const std::size_t n = in.vertices.size();
    bool any_below = false, any_above = false;
    for (std::size_t i = 0; i < n; ++i) any_below |= f[i] < 0.0, any_above |= f[i] > 0.0;
    if (!any_above) return;
    if (!any_below) {
        out = in;
        return;
    }
    constexpr std::uint32_t kNone = 0xFFFFFFFFu;
    thread_local std::vector<std::uint32_t> kept;
    assign_kept(kept, n, kNone);
    for (std::size_t i = 0; i < n; ++i)
        if (f[i] >= 0.0) {
            kept[i] = static_cast<std::uint32_t>(out.vertices.size());
            out.vertices.push_back(in.vertices[i]);
        }
    struct Cut {
        std::uint32_t a, b, index;
    };
    thread_local std::vector<Cut> cuts;
    thread_local std::vector<std::uint32_t> cap;
    cuts.clear(), cap.clear();
    // One vertex per cut edge, computed with the edge's smaller index first so both triangles
    // sharing the edge get the same point.
    auto cut = [&](std::uint32_t a, std::uint32_t b) {
        if (b < a) std::swap(a, b);
        for (const Cut& c : cuts)
            if (c.a == a && c.b == b) return c.index;
        const double t = f[a] / (f[a] - f[b]);
        PolyVertex v;
        v.position = in.vertices[a].position + t * (in.vertices[b].position - in.vertices[a].position);
        v.scalar = std::isnan(cut_scalar) ? in.vertices[a].scalar + t * (in.vertices[b].scalar - in.vertices[a].scalar)
                                          : cut_scalar;
        const std::uint32_t index = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(v);
        cuts.push_back({a, b, index});
        cap.push_back(index);
        return index;
    };
    for (const auto& tri : in.triangles) {
        std::uint32_t poly[4];
        int m = 0;
        bool touches_below = false;
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t p = tri[e], q = tri[(e + 1) % 3];
            touches_below |= f[p] < 0.0;
            if (f[p] >= 0.0) poly[m++] = kept[p];
            if ((f[p] > 0.0 && f[q] < 0.0) || (f[p] < 0.0 && f[q] > 0.0)) poly[m++] = cut(p, q);
        }
        // Vertices on the plane next to the removed part border the cap.
        if (touches_below)
            for (int e = 0; e < 3; ++e)
                if (f[tri[e]] == 0.0 && std::find(cap.begin(), cap.end(), kept[tri[e]]) == cap.end())
                    cap.push_back(kept[tri[e]]);
        for (int i = 1; i + 1 < m; ++i) out.triangles.push_back({poly[0], poly[i], poly[i + 1]});
    }
    if (cap.size() < 3) return;
    // The cap is convex (a plane section of a convex cell): order its points by angle around
    // their centre, counter-clockwise seen from outside (from −increasing).
    const glm::dvec3 normal = -glm::normalize(increasing);
    const glm::dvec3 helper = std::abs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(helper, normal)), e2 = glm::cross(normal, e1);
    glm::dvec3 centre(0.0);
    for (std::uint32_t i : cap) centre += out.vertices[i].position;
    centre /= double(cap.size());
    thread_local std::vector<std::pair<double, std::uint32_t>> ordered;
    ordered.clear();
    for (std::uint32_t i : cap) {
        const glm::dvec3 d = out.vertices[i].position - centre;
        ordered.emplace_back(std::atan2(glm::dot(d, e2), glm::dot(d, e1)), i);
    }
    std::sort(ordered.begin(), ordered.end());
    for (std::size_t i = 1; i + 1 < ordered.size(); ++i)
        out.triangles.push_back({ordered[0].second, ordered[i].second, ordered[i + 1].second});
}

} // namespace cellfx::fx
