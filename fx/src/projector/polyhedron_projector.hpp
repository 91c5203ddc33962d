// cellfx — the polyhedron projector shared by the GPU render paths (PCP, PCP-exact, MIP).
//
// Based on: Roettger & Ertl 2003, §3 (per-vertex distance d to the near plane, per-cell d_min
// and Δd, front/back faces) and §5 (the near-plane cap: the cell ∩ near plane).
//
// Two stages, no GL here (the GL side lives in fx/src/projector/ and shaders/project.glsl):
//
//   1. ProjectorGeometry — built ONCE per mesh and scalar field: every cell face cut into
//      triangles (quads by triangulate_face(), the smallest-vertex diagonal, so neighbours
//      agree), each triangle's outward plane, the cell → triangle ranges. Positions are stored
//      relative to `origin` (the centre of the mesh bounds) as floats, so a mesh far from the
//      world origin keeps its precision on the GPU.
//   2. Per view — only what the camera changes: ProjectorView (the camera expressed in the
//      geometry's relative frame), project_cells() (per-point d, per-cell d_min/Δd and the
//      cells the near plane cuts), classify_triangles() (front/back/edge-on) and
//      build_near_caps() (the cap polygon of every cut cell).
//
// Conventions: d = (view depth) − near, i.e. the signed distance to the near plane measured
// along the view direction, so d < 0 in front of the near plane (clipped). Cap polygons wind
// counter-clockwise seen from the eye, like the front faces of a cell.
//
// Preconditions: cells are convex (or nearly: a non-planar quad is two triangles and the cell
// is treated as the polyhedron those triangles bound); the mesh passed validate_mesh() (indices
// in range, finite coordinates). Degenerate input stays finite: zero-area triangles get a zero
// plane, Δd = 0 cells get α = 0, a camera exactly on a face plane sees that face edge-on.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

struct ProjectorGeometry {
    glm::dvec3 origin{0.0};                  // positions are relative to this point
    double extent = 0.0;                     // the diagonal of the points' bounds (0: no points)
    std::vector<glm::vec3> positions;        // per mesh point, relative to origin
    std::vector<float> scalars;              // per mesh point (zeros if no field was given)
    std::vector<std::uint32_t> cell_first_triangle;      // cell_count + 1 entries
    std::vector<std::array<std::uint32_t, 3>> triangles; // mesh point ids, CCW seen from outside
    std::vector<std::uint32_t> triangle_cell;            // owning cell of each triangle
    // Outward unit normal n (xyz) and w = n·p for points p of the triangle (relative frame);
    // all zero for a zero-area triangle (it then never bounds a ray).
    std::vector<glm::vec4> triangle_planes;

    std::size_t cell_count() const { return cell_first_triangle.empty() ? 0 : cell_first_triangle.size() - 1; }
    std::size_t memory_bytes() const;
};

// The smallest mesh the geometry keeps float precision for: the diagonal of the bounds of the
// points its cells use. Positions are floats relative to the mesh's centre; below ~1e-31
// differences between them at float's 1e-7 relative precision fall under float's smallest
// normal number (1.2e-38), which GPUs flush to zero, and the GPU paths draw nothing or a
// wrong picture (measured: blank from 1e-36). Scale-free above it: tests/test_hard_cases.cpp,
// "a cube at 10^K".
constexpr double kMinProjectorExtent = 1.0e-30;

// Builds the view-independent geometry. `scalars` may be null (all scalars 0); otherwise it
// must hold one value per mesh point. Throws fx::Error on a size mismatch, an index out of
// range, a non-finite coordinate/scalar (never drawn), a used point beyond ±kMaxCoordinate or
// a mesh of extent under kMinProjectorExtent (zero extent is no error: nothing to draw).
ProjectorGeometry build_projector_geometry(const CellMesh& mesh, const ScalarField* scalars);
// The same into `out`, reusing its storage (a mesh replaced every frame allocates nothing once
// its sizes have been seen). On a throw `out` is left partly built. Without `planes`,
// triangle_planes is left empty (the GPU builds its own: gl_projector.hpp); compute_triangle_planes
// adds them later.
void build_projector_geometry(const CellMesh& mesh, const ScalarField* scalars, ProjectorGeometry& out, bool planes = true);
// Every triangle's plane (triangle_plane) from the geometry's positions and triangles.
void compute_triangle_planes(ProjectorGeometry& geometry);
// The outward unit plane of triangle (a, b, c) — n (xyz) and w = n·(its centroid) — in double
// from the float positions, as every triangle plane is made; zero when the triangle has no area.
glm::vec4 triangle_plane(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// The camera in the geometry's relative frame (doubles; the GPU gets floats of these).
struct ProjectorView {
    glm::dmat4 view{1.0};    // relative coordinates → eye space
    glm::dvec3 eye{0.0};     // relative frame; for orthographic cameras a point on the eye plane
    glm::dvec3 forward{0.0, 0.0, -1.0}; // unit view direction
    double near_distance = 0.01;             // where cells are cut: Camera::clipping_near(extent)
    double far_distance = 1.0e4;
    bool orthographic = false;

    // d of a point (relative frame): distance beyond the near plane along `forward`.
    double depth(const glm::dvec3& p) const;
};
ProjectorView make_projector_view(const ProjectorGeometry& geometry, const Camera& camera);

struct ProjectedCells {
    std::vector<float> point_depth;        // d per point
    std::vector<glm::vec2> depth_range;    // per cell: (d_min, Δd = d_max − d_min), Δd ≥ 0
    std::vector<std::uint32_t> cut_cells;  // cells with d_min < 0 < d_max (the near plane cuts them)
};
// Per-view depths. O(points + cell vertices).
void project_cells(const CellMesh& mesh, const ProjectorGeometry& geometry, const ProjectorView& view,
                   ProjectedCells& out);

// PCP's normalised depth α = (d − d_min)/Δd, clamped to [0, 1]; 0 when Δd is 0 (a flat
// cell has no thickness, so any finite α gives the same zero contribution).
float normalized_depth(float d, glm::vec2 depth_range);

enum class FaceSide : std::uint8_t { Front, Back, EdgeOn };
// Front: the outward normal points towards the eye (towards −forward for orthographic
// cameras). EdgeOn when the eye lies on the triangle's plane (within rounding) or the
// triangle has no area.
FaceSide classify_triangle(const ProjectorGeometry& geometry, const ProjectorView& view, std::size_t triangle);
void classify_triangles(const ProjectorGeometry& geometry, const ProjectorView& view, std::vector<FaceSide>& out);

// Near-plane caps: polygon k has vertices [first_vertex[k], first_vertex[k + 1]) of
// positions/scalars, belongs to cell[k], is convex, lies on the near plane and winds CCW seen
// from the eye. Scalars are interpolated linearly along the cut edges.
struct NearCaps {
    std::vector<glm::vec3> positions; // relative frame
    std::vector<float> scalars;
    std::vector<std::uint32_t> first_vertex{0};
    std::vector<std::uint32_t> cell;

    std::size_t polygon_count() const { return cell.size(); }
    void clear() {
        positions.clear(), scalars.clear(), cell.clear();
        first_vertex.assign(1, 0u);
    }
};
// Appends the cap of one cell (nothing if the plane does not cut it with positive area).
// Robust when the plane passes through vertices or along edges: such points are taken once.
// Returns true if a polygon was appended.
bool append_near_cap(const ProjectorGeometry& geometry, const ProjectorView& view, const ProjectedCells& projected,
                     std::uint32_t cell, NearCaps& caps);
// Caps of all projected.cut_cells (clears `caps` first).
void build_near_caps(const ProjectorGeometry& geometry, const ProjectorView& view, const ProjectedCells& projected,
                     NearCaps& caps);

} // namespace cellfx::fx
