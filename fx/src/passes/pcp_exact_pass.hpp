// cellfx — the `pcp-exact` render path's pass over the GL projector: one draw of every cell's
// back faces, additive, into a float target (shaders/pcp_exact.frag).
//
// Based on: Roettger & Ertl 2003, §3 (emission, no sort), made exact per fragment.
//
// Ownership: keeps a reference to the projector, which must outlive it.
#pragma once

#include "fx/cell_renderer.hpp"
#include "gl/gl_object.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

class PcpExactPass {
public:
    explicit PcpExactPass(const GlProjector& projector);
    // Draws into the bound target (cleared to 0) with the projector's mesh bound.
    void draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options, CellRenderStats& stats);

private:
    const GlProjector& projector_;
    const ProgramVariants programs_;
};

} // namespace cellfx::fx
