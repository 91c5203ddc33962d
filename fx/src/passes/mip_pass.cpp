// Based on: Roettger & Ertl 2003, §2 (maximum intensity projection) and §5 (near-plane caps).
#include "passes/mip_pass.hpp"

#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"

namespace cellfx::fx {

MipPass::MipPass(GlProjector& projector)
    : projector_(projector), programs_(projector.programs({"faces.vert", "mip.frag"})),
      caps_program_(projector.program({"caps.vert", "mip.frag"}, gl::Defines{{"CAPS", "1"}})) {}

void MipPass::prepare(const Camera& camera) {
    const ProjectorView view = projector_.view(camera);
    caps_.clear();
    if (projector_.mesh_crosses_near_plane(view)) {
        project_cells(projector_.mesh(), projector_.geometry(), view, projected_);
        build_near_caps(projector_.geometry(), view, projected_, caps_);
    }
}

void MipPass::upload() {
    frame_data_.clear();
    for (std::size_t k = 0; k < caps_.polygon_count(); ++k) GlProjector::append_cap_vertices(caps_, projected_, k, frame_data_);
    if (!frame_data_.empty()) projector_.upload_frame(frame_data_);
    projector_.bind_unique_faces(); // made on first use
}

void MipPass::draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                   CellRenderStats& stats) {
    const gl::Program& program = programs_(options.scene_depth != 0);
    projector_.set_view_uniforms(program, camera, viewport);
    projector_.set_scene_depth_uniforms(program, camera, viewport, options.scene_depth);
    projector_.set_view_uniforms(caps_program_, camera, viewport); // caps lie on the near plane: no scene test
    glUseProgram(program.id());
    glDisable(GL_CULL_FACE);
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_MAX, GL_MAX);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE); // ignored by GL_MAX
    // Each face once: a face two cells share shows the same scalars to both.
    projector_.bind_unique_faces();
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * projector_.unique_face_triangles()));
    stats.draw_calls += 1;
    stats.cells_drawn = projector_.mesh().cell_count();
    if (!frame_data_.empty()) {
        projector_.bind_frame();
        glUseProgram(caps_program_.id());
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(frame_data_.size() / 2));
        stats.draw_calls += 1;
        stats.caps = caps_.polygon_count();
    }
    FX_GL_CHECK("mip draw");
}

} // namespace cellfx::fx
