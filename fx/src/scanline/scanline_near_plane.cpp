// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (virtual polygons), §5
//
// Near-plane handling for the scan-line renderer. Triangles that cross the near plane are
// clipped in eye space, never projected through the eye. Every cell cut by the plane adds
// its cross-section (a "cap") as virtual grid-surface triangles at the near depth: the cap
// toggles the grid to "inside" where the near point of a pixel ray lies in the cell, and
// carries the scalar there, so a camera inside a grid sees what lies in front of it. Cap and
// clipped-triangle vertices on an edge come from one function evaluated with the edge's
// smaller id first, so caps of neighbouring cells and the clipped faces meet exactly.
#include <algorithm>
#include <array>

#include "scanline/scanline_frame.hpp"

namespace cellfx::fx::scanline {

bool FrameGeometry::behind(std::uint32_t id) const {
    if (id < points.size()) return points[id].z == kBehind;
    return eye(id).z > -near; // clip-box corner: eye depth −z below near
}

glm::dvec3 FrameGeometry::eye(std::uint32_t id) const {
    const glm::dvec3& p = id < points.size() ? mesh->points[id] : box_corners[id - points.size()];
    return glm::dvec3(view * glm::dvec4(p, 1.0));
}

double FrameGeometry::scalar(std::uint32_t id) const {
    return id < points.size() ? static_cast<double>(points[id].s) : 0.0;
}

Vertex FrameGeometry::project(std::uint32_t id) const {
    if (id < points.size()) {
        const ScreenPoint& p = points[id];
        return Vertex{p.x, p.y, p.z, scalar(id)};
    }
    const glm::dvec3 e = eye(id);
    const double ze = -e.z;
    if (depth.ortho) {
        return Vertex{depth.cx + depth.f * e.x, depth.cy + depth.f * e.y, depth.to_screen(ze), 0.0};
    }
    return Vertex{depth.cx + depth.f * e.x / ze, depth.cy + depth.f * e.y / ze, depth.to_screen(ze), 0.0};
}

Vertex FrameGeometry::near_point(std::uint32_t a, std::uint32_t b) const {
    if (b < a) std::swap(a, b);
    const glm::dvec3 ea = eye(a), eb = eye(b);
    const double za = -ea.z, zb = -eb.z;
    // An endpoint exactly on the plane is returned as itself, bit for bit.
    if (za == near) return project(a);
    if (zb == near) return project(b);
    const double t = (near - za) / (zb - za);
    const glm::dvec3 e = ea + t * (eb - ea);
    const double s = scalar(a) + t * (scalar(b) - scalar(a));
    if (depth.ortho) {
        return Vertex{depth.cx + depth.f * e.x, depth.cy + depth.f * e.y, depth.to_screen(near), s};
    }
    return Vertex{depth.cx + depth.f * e.x / near, depth.cy + depth.f * e.y / near, depth.to_screen(near), s};
}

void FrameGeometry::add_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::uint32_t grid,
                                 bool toggles, Facing facing) {
    const auto base = static_cast<std::uint32_t>(extra_vertices.size());
    for (const Vertex* v : {&a, &b, &c}) {
        extra_vertices.push_back(ScreenPoint{static_cast<float>(v->x), static_cast<float>(v->y),
                                             static_cast<float>(v->z), static_cast<float>(v->s)});
    }
    extra_triangles.push_back(ExtraTriangle{{base, base + 1, base + 2}, grid, toggles, facing});
}

void FrameGeometry::add_clipped_triangle(const std::uint32_t tri[3], std::uint32_t grid, bool toggles, Facing facing) {
    // Sutherland–Hodgman against the one plane z_e = near: at most 4 vertices.
    std::array<Vertex, 4> poly;
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const std::uint32_t a = tri[i], b = tri[(i + 1) % 3];
        const bool a_in = !behind(a), b_in = !behind(b);
        if (a_in) poly[n++] = project(a);
        if (a_in != b_in) poly[n++] = near_point(a, b);
    }
    if (n < 3) return;
    add_triangle(poly[0], poly[1], poly[2], grid, toggles, facing);
    if (n == 4) add_triangle(poly[0], poly[2], poly[3], grid, toggles, facing);
}

std::size_t FrameGeometry::add_cap(const std::uint32_t* face_triangles, int triangle_count, std::uint32_t grid) {
    // Each face triangle crossing the plane gives one directed segment: from its edge that
    // goes front → behind to its edge that goes behind → front. Along a shared edge one
    // triangle starts where its neighbour ends, so the segments chain into the section loop.
    struct Key {
        std::uint32_t lo, hi;
        bool operator==(const Key& o) const { return lo == o.lo && hi == o.hi; }
    };
    auto key = [](std::uint32_t a, std::uint32_t b) { return a < b ? Key{a, b} : Key{b, a}; };
    constexpr int kMaxSegments = 2 * kMaxCellFaces + 2;
    std::array<Key, kMaxSegments> start{}, end{};
    int segments = 0;
    for (int t = 0; t < triangle_count; ++t) {
        const std::uint32_t* v = face_triangles + 3 * t;
        const bool in[3] = {!behind(v[0]), !behind(v[1]), !behind(v[2])};
        if (in[0] == in[1] && in[1] == in[2]) continue;
        if (segments == kMaxSegments) return 0; // not a cell this routine knows
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3;
            if (in[i] && !in[j]) start[segments] = key(v[i], v[j]);
            if (!in[i] && in[j]) end[segments] = key(v[i], v[j]);
        }
        ++segments;
    }
    if (segments < 3) return 0;
    // Chain: the loop's vertices are the segments' start points in order.
    std::array<Key, kMaxSegments> loop{};
    std::array<bool, kMaxSegments> used{};
    int n = 0, current = 0;
    for (;;) {
        used[current] = true;
        loop[n++] = start[current];
        int next = -1;
        for (int s = 0; s < segments; ++s) {
            if (!used[s] && start[s] == end[current]) { next = s; break; }
        }
        if (next < 0) break;
        current = next;
    }
    // A loop that does not close over every segment means the cell is not closed (or is
    // not convex enough to have one section); leave it without a cap.
    if (n != segments || !(end[current] == start[0])) return 0;
    std::array<Vertex, kMaxSegments> p;
    for (int i = 0; i < n; ++i) p[i] = near_point(loop[i].lo, loop[i].hi);
    for (int i = 1; i + 1 < n; ++i) add_triangle(p[0], p[i], p[i + 1], grid, true, Facing::Enters);
    return static_cast<std::size_t>(n - 2);
}

} // namespace cellfx::fx::scanline
