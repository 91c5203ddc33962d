// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2, §5
//
// Private to the scan-line renderer: the per-frame screen-space geometry (transformed points,
// the pixel-unit depth of §5) and the extra triangles made per frame (pieces of triangles
// cut by the near plane, near-plane caps of cut cells, the clip box's virtual polygons).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx::scanline {

// Screen-space depth in pixel units (§5). Perspective: z_s = f·(1 − z_r/z_e), affine in
// 1/z_e and so linear over a projected triangle, one pixel per world unit·f/z_r near the
// reference depth z_r. Orthographic: z_s = k·(z_e − z_r) with k pixels per world unit.
struct DepthMap {
    bool ortho = false;
    double f = 1.0;  // perspective: focal length in pixels; orthographic: k
    double zr = 1.0; // reference eye depth
    double cx = 0.0, cy = 0.0; // principal point in pixels

    double to_screen(double ze) const { return ortho ? f * (ze - zr) : f * (1.0 - zr / ze); }
    // 1/z_e up to a constant factor (1/(f·z_r)), linear on screen; 1 for orthographic views.
    double w(double zs) const { return ortho ? 1.0 : (f - zs); }
    // Eye-depth difference z_e(z2) − z_e(z1), the paper's formula (no subtraction of two
    // large eye depths, so thin segments far away keep their precision).
    double eye_delta(double z1, double z2) const {
        if (ortho) return (z2 - z1) / f;
        return f * zr * (z2 - z1) / ((f - z1) * (f - z2));
    }
    // Eye depth z_e at screen depth z_s.
    double eye_depth(double zs) const { return ortho ? zs / f + zr : f * zr / (f - zs); }
    // 1/cos θ for the ray through pixel centre (xc, yc).
    double inv_cos(double xc, double yc) const {
        if (ortho) return 1.0;
        const double dx = xc - cx, dy = yc - cy;
        return std::sqrt(f * f + dx * dx + dy * dy) / f;
    }
};

constexpr double kBehind = -std::numeric_limits<double>::infinity();

// A transformed mesh point with its scalar, 16 bytes (the paper keeps 3 floats per point,
// §4.3). z == kBehind when it lies behind the near plane. Floats are enough: the view
// transform is done in double relative to the camera, a screen position carries a relative
// error of 6e-8 (3e-5 px at x = 512), and every triangle sharing the point reads the same
// value, so shared edges still meet exactly.
struct ScreenPoint {
    float x, y, z, s;
};

// A vertex with its scalar in double, as the near-plane code computes it; stored as a
// ScreenPoint like the mesh points.
struct Vertex {
    double x, y, z, s;
};

// How the pixel walk tells whether a ray enters a cell where it crosses a triangle.
enum class Facing : std::uint8_t {
    Winding,  // by its winding on screen (a piece of a mesh triangle, outward winding)
    Reversed, // the same, for a piece of an inverted cell's triangle
    Enters,   // always: a near-plane cap, where the ray starts inside the cell
};

struct ExtraTriangle {
    std::uint32_t v[3]; // indices into FrameGeometry::extra_vertices
    std::uint32_t grid;
    bool toggles; // grid surface, cap or clip-box polygon
    Facing facing;
};

struct FrameGeometry {
    const CellMesh* mesh = nullptr;
    glm::dmat4 view{1.0};
    DepthMap depth;
    double near = 0.0;
    std::vector<ScreenPoint> points;  // one per mesh point (buffer reused between frames)
    glm::dvec3 box_corners[8]{};      // clip box, virtual point ids point_count() + i
    std::vector<ScreenPoint> extra_vertices;
    std::vector<ExtraTriangle> extra_triangles;

    std::size_t point_count() const { return points.size(); }
    bool behind(std::uint32_t id) const;
    glm::dvec3 eye(std::uint32_t id) const;    // eye-space position (view looks down −z)
    double scalar(std::uint32_t id) const;     // 0 for clip-box corners
    Vertex project(std::uint32_t id) const;    // a point in front of the near plane
    // The point where edge (a, b) meets the near plane. Computed with the smaller id first,
    // so every triangle and cap sharing the edge gets bit-identical coordinates.
    Vertex near_point(std::uint32_t a, std::uint32_t b) const;

    // Adds the part of triangle (a, b, c) in front of the near plane (1 or 2 triangles),
    // keeping its winding.
    void add_clipped_triangle(const std::uint32_t tri[3], std::uint32_t grid, bool toggles, Facing facing);
    // Adds the near-plane cross-section of a closed cell given by its face triangles
    // (outward winding, 3 ids each). Returns the number of cap triangles added.
    std::size_t add_cap(const std::uint32_t* face_triangles, int triangle_count, std::uint32_t grid);
    // Adds a triangle whose three vertices are in front of the near plane.
    void add_triangle(const Vertex& a, const Vertex& b, const Vertex& c, std::uint32_t grid, bool toggles, Facing facing);
};

} // namespace cellfx::fx::scanline
