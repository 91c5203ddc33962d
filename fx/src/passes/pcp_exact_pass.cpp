// Based on: Roettger & Ertl 2003, §3 (emission, no sort), made exact per fragment.
#include "passes/pcp_exact_pass.hpp"

#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"

namespace fx {

PcpExactPass::PcpExactPass(const GlProjector& projector)
    : projector_(projector), program_(projector.program({"project.vert", "pcp_exact.frag"})) {}

void PcpExactPass::draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                        CellRenderStats& stats) {
    projector_.set_view_uniforms(program_, camera, viewport);
    projector_.set_scene_depth_uniforms(program_, camera, viewport, options.scene_depth);
    glUseProgram(program_.id());
    glProgramUniform1i(program_.id(), kUniformSource, kSourceMesh);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each fragment is a ray's exit from its cell
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(projector_.geometry().triangles.size() * 3));
    stats.draw_calls += 1;
    stats.cells_drawn = projector_.mesh().cell_count();
    FX_GL_CHECK("pcp-exact draw");
}

} // namespace fx
