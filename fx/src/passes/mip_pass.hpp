// cellfx — the `mip` render path's pass over the GL projector: every face, and the near-plane
// caps of cells the near plane cuts, with GL_MAX blending (shaders/mip.frag).
//
// Based on: Roettger & Ertl 2003, §2 (maximum intensity projection) and §5 (caps).
//
// Ownership: keeps a reference to the projector, which must outlive it; owns its per-frame
// scratch (caps), kept between frames so that a steady frame allocates nothing.
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "fx/cell_renderer.hpp"
#include "projector/polyhedron_projector.hpp"
#include "gl/gl_object.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

class MipPass {
public:
    explicit MipPass(GlProjector& projector);
    // The frame's CPU work: the near-plane caps of `camera`'s view (none unless the near plane
    // cuts the mesh's bounds).
    void prepare(const Camera& camera);
    // Sends the caps to the GL.
    void upload();
    // Draws into the bound target (cleared to 0) with the projector's mesh bound; may be called
    // again for the same frame (nothing is uploaded here).
    void draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options, CellRenderStats& stats);

private:
    GlProjector& projector_;
    const ProgramVariants programs_;  // the mesh's faces
    const gl::Program& caps_program_; // near-plane caps
    ProjectedCells projected_;
    NearCaps caps_;
    std::vector<glm::uvec4> frame_data_;
};

} // namespace cellfx::fx
