// Based on: Roettger & Ertl 2003, §3 (emission, no sort), made exact per fragment.
#include "passes/pcp_exact_pass.hpp"

#include <limits>

#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"

namespace cellfx::fx {

PcpExactPass::PcpExactPass(const GlProjector& projector)
    : projector_(projector), programs_(projector.programs({"cells.vert", "pcp_exact.frag"}, projector.mesh_defines())) {}

void PcpExactPass::draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                        CellRenderStats& stats) {
    const gl::Program& program = programs_(options.scene_depth != 0);
    projector_.set_view_uniforms(program, camera, viewport);
    projector_.set_scene_depth_uniforms(program, camera, viewport, options.scene_depth);
    glUseProgram(program.id());
    // Fog divides emission by optical depth: cap a cell's depth (shaders/pcp_exact.frag).
    glUniform1f(kUniformMaxOpticalDepth, options.fog ? 1e30f : std::numeric_limits<float>::infinity());
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each pixel a cell covers gets one fragment
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
    projector_.draw_slots(0, projector_.mesh().cell_count());
    stats.draw_calls += 1;
    stats.cells_drawn = projector_.mesh().cell_count();
    FX_GL_CHECK("pcp-exact draw");
}

} // namespace cellfx::fx
