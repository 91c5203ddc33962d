// cellfx — the classic Absorption flavour's CPU half: cells in visibility order become the
// polygons the GPU composites back to front, with 2-D opacity-table coordinates and the
// corrected colour at every vertex. No GL here (the GL half: fx/src/passes/absorption_pass).
//
// Based on: Max, Williams & Silva 2000, §II (opacity 1 − exp(−l·τ) through a 2-D texture with
// u ∝ thickness l and v ∝ the mean extinction τ_a = (τ_f + τ_b)/2; the colour computed
// analytically at non-profile vertices and divided by α) and §V (cells containing transfer-
// function breakpoints cut into tetrahedra, then into slabs between breakpoint values).
//
// Per cell (or piece of one), in the order given:
//   1. cells wholly behind the near plane are skipped; cells it cuts are clipped to the part in
//      front and closed by a cap on the near plane (clip_polyhedron), so a camera inside the
//      mesh composites only what lies ahead;
//   2. a cell that is not a tetrahedron is cut into its consistent tetrahedra (§IV,
//      subdivide_cell), ordered back to front among themselves through their shared faces: a
//      hexahedron costs what its five or six tetrahedra cost (the overlay of its own front and
//      back faces took 1.4 times the instructions);
//   3. with slicing on, a tetrahedron whose scalar range strictly contains breakpoints of the
//      transfer function is cut into slabs between consecutive breakpoints (the scalar is
//      linear in a tetrahedron, so the cuts are planes and the slabs are ordered along its
//      gradient). Inside a slab colour and extinction are linear in s, which is what §II's
//      texture and vertex colours assume; steps are taken from the slab's side;
//   4. the projected subdivision (Shirley–Tuchman for whole tetrahedra in front of the near
//      plane, the general convex overlay for slabs and clipped pieces: projected_subdivision.hpp);
//   5. at each polygon vertex: τ_f, τ_b = σ(s_front), σ(s_back); the colour C of the vertex ray
//      from emission_absorption() (exact for the linear piece), divided by its α; profile
//      vertices (l = 0) take the glow colour c(s) there. The thickness and τ_a are scaled
//      jointly per piece (only their product matters): u = l/a, v = τ_a·a/K with
//      a = √(l_max·K/τ_max), so both stay in [0, 1] whenever the piece's optical depth stays
//      below K, and neither is squeezed into a corner of the table.
// The GPU interpolates u, v and the colour linearly on screen over each polygon, reads
// α = 1 − exp(−K·u·v) from the table (bilinear, in full float) and composites (C/α·α, α)
// with "over", back to front. With a scene depth, the entry and exit view depths (also
// linear on screen) give the part of the ray in front of the scene, which scales u.
//
// Ownership: the builder keeps references to the geometry and the transfer function, which
// must outlive it (a function changed in place is taken by transfer_function_changed()); it
// holds scratch buffers (use one builder per thread).
// Preconditions: the cells' point ids index the geometry's points; the transfer function is
// in the field's units (not normalized).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "fx/cell_mesh.hpp"
#include "projector/polyhedron_projector.hpp"
#include "absorption/projected_subdivision.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {

// The 2-D opacity texture of §II: texel (i, j) holds 1 − exp(−K·u_i·v_j) with
// u_i = i/(size − 1), v_j = j/(size − 1) and K = max_product, the largest optical depth l·τ_a
// a polygon can show without clamping (beyond it α ≥ 1 − e^(−K)).
struct OpacityTable {
    int size = 0;
    double max_product = 0.0;
    std::vector<float> values; // size × size, u fastest
};
// Throws fx::Error for size < 2 or a non-positive, non-finite max_product.
OpacityTable build_opacity_table(int size, double max_product);
// What the GPU reads: u, v clamped to [0, 1], bilinear between the four nearest texels.
double lookup_opacity(const OpacityTable& table, double u, double v);

struct ClassicVertex {
    glm::vec4 position_uv; // NDC x, y; opacity-table coordinates u, v
    glm::vec3 color;       // polygon colour C/α
    glm::vec2 depth;       // view depths of the ray's entry and exit (a scene's surface cuts there)
};

struct ClassicGeometry {
    std::vector<ClassicVertex> vertices;
    std::vector<std::uint32_t> indices; // triangles (fans of the convex polygons)
    std::size_t pieces = 0;         // convex pieces projected (cells, tetrahedra, slabs)
    std::size_t polygons = 0;       // polygons of their subdivisions
    std::size_t sliced_cells = 0;   // cells cut at breakpoints
    std::size_t clipped_pieces = 0; // pieces cut by the near plane
    std::size_t culled_cells = 0;   // cells wholly behind the near plane
    void clear();
    void append(const ClassicGeometry& other); // indices rebased
};

struct ClassicSettings {
    double max_product = 12.0;     // K of the opacity table
    bool slice_breakpoints = true; // §V slicing
};

class ClassicAbsorptionBuilder {
public:
    ClassicAbsorptionBuilder(const ProjectorGeometry& geometry, const TransferFunction& tf,
                             const ClassicSettings& settings);

    // The transfer function (the object given to the constructor) has new points: its
    // breakpoints are taken again, into the same storage.
    void transfer_function_changed();
    void set_settings(const ClassicSettings& settings) { settings_ = settings; }
    void set_view(const ProjectorView& view, const ProjectionFrame& frame);
    // Appends cells[order[0]], cells[order[1]], ... (back to front) to `out`.
    void append(const CellMesh& cells, const std::uint32_t* order, std::size_t count, ClassicGeometry& out);

    // Transfer-function values inside a piece whose scalar runs over [lo, hi]: at s == hi
    // (> lo) the value from below, elsewhere the value from above (TransferFunction's own).
    struct Sample {
        glm::dvec3 color;
        double sigma;
    };
    Sample sample(double s, double lo, double hi) const;

private:
    void append_cell(const CellMesh& cells, std::uint32_t cell, ClassicGeometry& out);
    void append_tetrahedron(const std::array<std::uint32_t, 4>& tet, bool slice, ClassicGeometry& out);
    void append_piece(const ConvexPolyhedron& piece, double lo, double hi, bool cut_by_near, ClassicGeometry& out);
    void emit(double lo, double hi, ClassicGeometry& out);
    PolyVertex vertex(std::uint32_t point) const;

    const ProjectorGeometry& geometry_;
    const TransferFunction& tf_;
    ClassicSettings settings_;
    std::vector<double> breakpoints_; // distinct control-point scalars, ascending
    ProjectorView view_;
    ProjectionFrame frame_;
    SubdivisionBuilder builder_;
    ProjectedSubdivision subdivision_;
    ConvexPolyhedron poly_, clipped_, slab_, rest_;
    std::vector<double> f_, tau_;
    std::vector<glm::dvec3> color_;
};

} // namespace cellfx::fx
