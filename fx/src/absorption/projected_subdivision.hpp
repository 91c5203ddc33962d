// cellfx — the projected subdivision of one convex cell: the classic Absorption path's geometry.
//
// Based on: Max, Williams & Silva 2000, §II (polyhedron projection), after Shirley & Tuchman
// 1990 (the projected tetrahedron). No GL here: the GL half is fx/src/passes/absorption_pass.
//
// The projected edges of a convex polyhedron cut the image plane into convex polygons, each
// lying in the projection of exactly one front face and one back face, so that the ray
// thickness varies (nearly) linearly over it. At every polygon vertex this computes, for the
// viewing ray through it, the thickness l (the length of the ray inside the cell, world units)
// and the scalar where the ray enters (s_front) and leaves (s_back); profile vertices, on the
// silhouette, have l = 0 and s_front = s_back.
//
//   tetrahedron()  Shirley–Tuchman: 3 triangles around the vertex that projects inside the
//                  others' triangle (class 1), or 4 around the crossing point G of the two
//                  edges whose projections cross (class 2); degenerate views give fewer.
//   polyhedron()   the general convex case: the projections of the front triangles and of the
//                  back triangles each tile the silhouette; their overlay (every front
//                  triangle clipped by every back triangle it overlaps) is the subdivision.
//   clip_polyhedron()  cuts a convex polyhedron by a plane given as a linear function f of
//                  the vertices (kept: f ≥ 0) and closes the cut with a cap polygon — the
//                  near plane for a camera inside the mesh (§5 of Roettger & Ertl's caps), or
//                  an iso-value of the scalar for slicing at transfer-function breakpoints (§V).
//
// Coordinates: vertices are in the projector's relative frame (polyhedron_projector.hpp);
// polygon vertices are normalised device coordinates of the camera's projection. Thickness and
// scalars along each vertex ray are exact (perspective-correct barycentrics on the entry and
// exit triangles); between vertices the classic path interpolates linearly on screen, which
// is exact for orthographic views and an approximation under perspective (§II).
//
// Preconditions: every vertex lies in front of the near plane (clip first: a vertex behind
// the eye has no projection, and such a cell produces no polygons); faces wind counter-
// clockwise seen from outside; the cell is convex as seen from the eye (a cell with a
// "problem face", §V, must be cut into tetrahedra first — view_dependent_subdivision.hpp).
// Degenerate input stays finite: edge-on faces and zero-area polygons are dropped.
//
// Ownership: plain values; SubdivisionBuilder keeps scratch buffers between calls (one per
// thread), appending to the caller's ProjectedSubdivision.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "projector/polyhedron_projector.hpp"

namespace cellfx::fx {

// The camera as the subdivision sees it.
struct ProjectionFrame {
    glm::dmat4 view{1.0};       // relative frame → eye space (rigid: lengths are kept)
    glm::dmat4 projection{1.0}; // eye → clip space
    bool orthographic = false;
    // The rasteriser's grid, for snap(): half the viewport in pixels, and the sub-pixel step
    // it snaps corners to (0: not known, snap() changes nothing).
    glm::dvec2 pixels_per_ndc{0.0};
    double subpixel_step = 0.0;
    // `ndc` moved to the nearest corner position the rasteriser can represent. A triangle whose
    // corners lie there is covered exactly where it is, so every pixel centre it covers gets
    // its corners' values interpolated, never extrapolated: a rasteriser decides coverage
    // from corners snapped to its grid but interpolates from the corners it was given, and a
    // sliver thinner than the step then extrapolates without bound.
    glm::dvec2 snap(const glm::dvec2& ndc) const;
};
// From the projector's view of the geometry and the camera; aspect = viewport width / height.
ProjectionFrame make_projection_frame(const ProjectorView& view, const Camera& camera, double aspect);
// The same for a viewport of `width` × `height` pixels drawn by a rasteriser with
// `subpixel_bits` bits of sub-pixel precision (GL_SUBPIXEL_BITS).
ProjectionFrame make_projection_frame(const ProjectorView& view, const Camera& camera, int width, int height,
                                      int subpixel_bits);

struct PolyVertex {
    glm::dvec3 position{0.0}; // relative frame
    double scalar = 0.0;
};

// A convex polyhedron bounded by triangles that wind counter-clockwise seen from outside.
struct ConvexPolyhedron {
    std::vector<PolyVertex> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles; // indices into vertices
    void clear() { vertices.clear(), triangles.clear(); }
};

struct SubdivisionVertex {
    glm::dvec2 ndc{0.0};
    double thickness = 0.0; // l, world units; 0 at profile vertices
    double s_front = 0.0;   // scalar where the ray through this point enters the cell
    double s_back = 0.0;    // ... and where it leaves
    double depth_front = 0.0; // view depth (eye-space −z) of the entry point
    double depth_back = 0.0;  // ... and of the exit point
};

// Convex polygons counter-clockwise on screen; polygon k uses polygon_vertices
// [polygon_start[k], polygon_start[k + 1]), indices into vertices. Vertices are shared by the
// polygons of one cell.
struct ProjectedSubdivision {
    std::vector<SubdivisionVertex> vertices;
    std::vector<std::uint32_t> polygon_start{0};
    std::vector<std::uint32_t> polygon_vertices;

    std::size_t polygon_count() const { return polygon_start.size() - 1; }
    void clear() { vertices.clear(), polygon_vertices.clear(), polygon_start.assign(1, 0u); }
    double area() const; // total screen area of the polygons (NDC units)
};

class SubdivisionBuilder {
public:
    // Appends the subdivision of a tetrahedron (either winding) to `out`.
    void tetrahedron(const ProjectionFrame& frame, const std::array<PolyVertex, 4>& tet, ProjectedSubdivision& out);
    // Appends the subdivision of a convex polyhedron to `out`.
    void polyhedron(const ProjectionFrame& frame, const ConvexPolyhedron& cell, ProjectedSubdivision& out);

private:
    struct Projected {
        glm::dvec2 ndc;
        double w;       // clip w (> 0)
        glm::dvec3 eye; // eye-space position
        double s;
    };
    bool project(const ProjectionFrame& frame, const PolyVertex* v, std::size_t n);
    // Point on triangle (a, b, c) seen at screen position p: eye position and scalar.
    void locate(const glm::dvec2& p, std::uint32_t a, std::uint32_t b, std::uint32_t c, glm::dvec3& eye,
                double& s) const;
    std::uint32_t add_vertex(const glm::dvec2& p, std::uint32_t f[3], std::uint32_t b[3], double tolerance,
                             ProjectedSubdivision& out);
    std::uint32_t add_profile_vertex(std::uint32_t i, ProjectedSubdivision& out);

    std::vector<Projected> points_;
    struct ScreenTriangle {
        std::uint32_t v[3];            // counter-clockwise on screen
        glm::dvec2 lo, hi;             // screen box
        glm::dvec2 origin[3], dir[3];  // edge e from v[e] to v[e + 1]
        double inv_length[3];
    };
    std::vector<ScreenTriangle> front_, back_;
    std::vector<glm::dvec2> polygon_, clipped_;        // Sutherland–Hodgman scratch
    std::size_t first_vertex_ = 0;                     // first vertex of the current cell in out
};

// Cuts `in` by the plane f = 0, where f holds one value per vertex of a function linear over
// the cell, and keeps the part with f ≥ 0, closed by a cap polygon on the plane (fanned into
// triangles wound outward). `increasing` is a direction in which f grows (the cap's outward
// normal is −increasing). New vertices on cut edges interpolate position and scalar linearly,
// or get `cut_scalar` when it is given (iso-value cuts, so the cap carries the value exactly).
// `out` is empty when nothing has f > 0; a copy of `in` when nothing has f < 0.
void clip_polyhedron(const ConvexPolyhedron& in, const std::vector<double>& f, const glm::dvec3& increasing,
                     ConvexPolyhedron& out, double cut_scalar = std::numeric_limits<double>::quiet_NaN());

} // namespace cellfx::fx
