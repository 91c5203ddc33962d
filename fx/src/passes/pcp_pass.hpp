// cellfx — the classic `pcp` render path's pass over the GL projector: Roettger & Ertl's three
// passes per batch of cells with disjoint screen footprints, into an 8-bit target
// (shaders/pcp.frag; batching: projector/footprint_batches.hpp).
//
// Based on: Roettger & Ertl 2003, §3 (three passes per cell) and §5 (near-plane caps).
//
// Ownership: keeps a reference to the projector, which must outlive it; owns its per-frame
// scratch (projection, caps, footprints, batches), kept between frames.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "fx/cell_renderer.hpp"
#include "projector/footprint_batches.hpp"
#include "projector/polyhedron_projector.hpp"
#include "gl/gl_object.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

class PcpPass {
public:
    explicit PcpPass(GlProjector& projector);
    // The frame's CPU work: the mesh projected for `camera`, its near-plane caps, footprints and
    // batches, the frame's cell list and cap triangles in batch order; fills projection_ms,
    // cells_drawn, batches and caps of `stats`.
    void prepare(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options, CellRenderStats& stats);
    // Sends the cell list and the caps to the GL.
    void upload();
    // Draws the batches into the bound 8-bit target (cleared to 0); may be called again for the
    // same frame (nothing is uploaded here).
    void draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options, CellRenderStats& stats);
    std::size_t gpu_bytes() const { return list_.gpu_bytes(); } // the frame's cell list

private:
    GlProjector& projector_;
    const ProgramVariants programs_;      // the cells of a batch (cells.vert, CELL_LIST and CLASSIC)
    const ProgramVariants caps_programs_; // their near-plane caps
    GlCellList list_;                 // the frame's cells, batch after batch, with (d_min, Δd)
    ProjectedCells projected_;
    NearCaps caps_;
    CellFootprints footprints_;
    // cell_start_ / cap_first_: per batch, its first listed cell / cap in cap_order_;
    // cap_start_: its first cap vertex.
    std::vector<std::uint32_t> batch_of_, cell_start_, cap_start_, cap_first_, cap_order_, fill_, list_cells_;
    std::vector<glm::vec2> list_ranges_;
    std::vector<std::uint64_t> masks_;
    std::vector<glm::uvec4> cap_data_;
    std::uint32_t batches_ = 0; // this frame's
};

} // namespace cellfx::fx
