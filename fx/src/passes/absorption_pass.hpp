// cellfx — the Absorption paths' pass (`absorption`, `absorption-exact`) over the GL projector,
// used by fx::CellRenderer (fx/include/fx/cell_renderer.hpp).
//
// Based on: Max, Williams & Silva 2000, §II (polyhedron projection, "over" back to front),
// §III (visibility sort: fx::VisibilitySort), §V (view-dependent subdivision).
//
// Per frame: prepare() — on the CPU, before any GL work is timed — finds the problem cells
// for this view and updates the working mesh (ViewDependentSubdivision), sorts it back to
// front (the sort's per-mesh state is built on first use per method, and again when the
// working mesh changes), and for the classic flavour builds every cell's polygons
// (ClassicAbsorptionBuilder, in runs of the order through a fx::ParallelFor, kept in order). draw() then uploads and draws:
//   classic  the polygons with u, v and C/α per vertex; α from the 2-D opacity table;
//   exact    the cells' triangles in order (a subdivided cell's tetrahedra in its place),
//            one indexed draw, back faces only, per-fragment entry/exit through the cell's
//            planes and the pre-integration table;
// both into the caller's float target with premultiplied "over" (ONE, ONE_MINUS_SRC_ALPHA).
//
// A new or changed mesh (set_mesh, update_mesh: terrain prisms every frame) keeps the pass:
// mesh_changed() has its per-mesh state — the subdivision's candidates, every sort's face
// topology, graph and exterior faces, the longest chord — rebuilt in place at the next
// prepare(), into the storage of the last build, so that a steady frame allocates nothing. The
// pre-integration table is rebuilt only when the transfer function changes or the longest chord
// leaves its length range (kept with a margin, so a mesh that changes a little every frame
// does not rebuild it every frame).
//
// Ownership: keeps a reference to the projector (mesh topology, geometry, programs), which must
// outlive it; owns its tables, buffers and per-frame scratch. Preconditions: the renderer's GL
// context current; the projector's mesh bound (GlProjector::bind_mesh) for draw().
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <vector>

#include "absorption/absorption_classic.hpp"
#include "fx/camera.hpp"
#include "fx/parallel_for.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "projector/polyhedron_projector.hpp"
#include "fx/transfer_function.hpp"
#include "absorption/view_dependent_subdivision.hpp"
#include "fx/visibility_sort.hpp"
#include "gl/gl_object.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

class AbsorptionPass {
public:
    explicit AbsorptionPass(GlProjector& projector);
    ~AbsorptionPass();
    AbsorptionPass(const AbsorptionPass&) = delete;
    AbsorptionPass& operator=(const AbsorptionPass&) = delete;

    // The projector's mesh changed (points, cells or both, same kind of cells): the per-mesh state
    // is rebuilt in place at the next prepare(). (A changed transfer function is seen by
    // prepare() itself.)
    void mesh_changed() { mesh_changed_ = true; }

    // CPU work of the frame; fills the sort/subdivision/projection fields of `stats`.
    // The classic flavour's projection runs through `parallel_for`.
    void prepare(const Camera& camera, const Viewport& viewport, bool exact, const CellRenderOptions& options,
                 const ParallelFor& parallel_for, CellRenderStats& stats);
    // Sends the frame prepared last to the GL (and the flavour's table, made on first use).
    void upload(bool exact);
    // GL work of the frame prepared and uploaded last, into the bound target (cleared to 0); may
    // be called again for the same frame. With options.scene_depth the renderer has bound the
    // scene's depth texture to unit 3.
    void draw(const Camera& camera, const Viewport& viewport, bool exact, const CellRenderOptions& options,
              CellRenderStats& stats);

    std::size_t gpu_bytes() const;

private:
    const VisibilitySort& sort_for(SortMethod method, CellRenderStats& stats);
    // The projector's transfer function is not the one tf_points_ holds: tables are rebuilt
    // lazily, the classic builders take its breakpoints.
    void transfer_function_changed();
    // The longest chord of any cell; the pre-integration table's range follows it.
    void measure_cells();
    void ensure_opacity_table();
    void ensure_preintegration_table();

    GlProjector& projector_;
    const ProgramVariants classic_programs_;
    const ProgramVariants exact_programs_;
    double longest_chord_ = 1.0; // of any cell of the mesh
    double max_length_ = 1.0;    // the pre-integration table's length range (≥ longest_chord_)
    bool mesh_changed_ = false;
    ViewDependentSubdivision subdivision_;
    // Per SortMethod: the sort, made on first use; stale when the working mesh changed since
    // it was built (rebuilt in place on its next use).
    static constexpr std::size_t kSortMethods = 4;
    std::unique_ptr<VisibilitySort> sorts_[kSortMethods];
    bool sort_stale_[kSortMethods] = {};
    std::vector<std::uint32_t> order_;
    // The transfer function the tables and builders were made for (compared every frame: a
    // normalized one follows a changed mesh's range).
    std::vector<TransferPoint> tf_points_;

    // Classic: one builder and one output per worker, filled by prepare(), drawn in order.
    ClassicSettings classic_settings_;
    int subpixel_bits_ = -1; // the rasteriser's GL_SUBPIXEL_BITS, asked once (classic polygons snap to it)
    std::vector<std::unique_ptr<ClassicAbsorptionBuilder>> builders_;
    std::vector<ClassicGeometry> parts_;
    std::size_t chunks_ = 0; // parts_ in use this frame
    std::vector<std::exception_ptr> errors_;
    // Exact: the frame's cells in visibility order and the tetrahedra made for this view (4
    // point ids each).
    void build_exact_frame();
    std::vector<std::uint32_t> list_cells_, pieces_;
    GlCellList exact_list_;

    gl::VertexArray vao_; // classic: its element buffer is index_
    gl::GrowingBuffer frame_, index_; // classic: every run's vertices and indices, one after the other
    std::vector<std::size_t> run_vertices_, run_indices_; // classic: where each run starts in them (+ the end)
    gl::Texture opacity_, preintegration_;
    gl::Buffer preintegration_buffer_, opacity_buffer_;
    bool opacity_ready_ = false, preintegration_ready_ = false;
    double s_lo_ = 0.0, s_per_unit_ = 0.0, l_per_unit_ = 0.0;
    std::size_t table_bytes_ = 0;
};

} // namespace cellfx::fx
