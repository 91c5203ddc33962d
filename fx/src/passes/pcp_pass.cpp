// Based on: Roettger & Ertl 2003, §3 (PCP, three passes per cell) and §5 (near-plane caps).
#include "passes/pcp_pass.hpp"

#include <cstring>

#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"

namespace fx {
namespace {

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

} // namespace

PcpPass::PcpPass(GlProjector& projector)
    : projector_(projector), program_(projector.program({"project.vert", "pcp.frag"})) {}

void PcpPass::draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                   CellRenderStats& stats) {
    const CellMesh& mesh = projector_.mesh();
    const ProjectorGeometry& geometry = projector_.geometry();
    const ProjectorView view = projector_.view(camera);
    project_cells(mesh, geometry, view, projected_);
    build_near_caps(geometry, view, projected_, caps_);
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::dmat4 vp = camera.projection_matrix(aspect) * view.view;
    cell_footprints(mesh, geometry, view, vp, projected_, caps_, viewport.width, viewport.height, options.batch_tile,
                    footprints_);
    const std::uint32_t batches = batch_footprints(footprints_, batch_of_);

    // Counting sort of cells by batch, then the caps (as fan triangles) grouped the same way.
    cell_start_.assign(batches + 1, 0);
    cap_start_.assign(batches + 1, 0);
    for (std::uint32_t b : batch_of_)
        if (b != kNoBatch) ++cell_start_[b + 1];
    for (std::uint32_t b = 0; b < batches; ++b) cell_start_[b + 1] += cell_start_[b];
    const std::uint32_t drawn = batches ? cell_start_[batches] : 0;
    frame_data_.assign(drawn, glm::uvec4(0u));
    fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t c = 0; c < batch_of_.size(); ++c) {
        const std::uint32_t b = batch_of_[c];
        if (b == kNoBatch) continue;
        const glm::vec2 r = projected_.depth_range[c];
        frame_data_[fill_[b]++] = glm::uvec4(std::uint32_t(c), bits(r.x), bits(r.y), 0u);
    }
    if (caps_of_batch_.size() < batches) caps_of_batch_.resize(batches);
    for (std::uint32_t b = 0; b < batches; ++b) caps_of_batch_[b].clear();
    for (std::size_t k = 0; k < caps_.polygon_count(); ++k) {
        const std::uint32_t b = batch_of_[caps_.cell[k]];
        if (b != kNoBatch) caps_of_batch_[b].push_back(std::uint32_t(k));
    }
    const std::size_t cap_base = frame_data_.size();
    for (std::uint32_t b = 0; b < batches; ++b) {
        cap_start_[b] = std::uint32_t((frame_data_.size() - cap_base) / 2);
        for (std::uint32_t k : caps_of_batch_[b]) GlProjector::append_cap_vertices(caps_, projected_, k, frame_data_);
    }
    cap_start_[batches] = std::uint32_t((frame_data_.size() - cap_base) / 2);
    projector_.upload_frame(frame_data_);
    stats.cells_drawn = drawn;
    stats.batches = batches;
    stats.caps = caps_.polygon_count();

    const GLuint prog = program_.id();
    projector_.set_view_uniforms(program_, camera, viewport);
    projector_.set_scene_depth_uniforms(program_, camera, viewport, options.scene_depth);
    glUseProgram(prog);
    glProgramUniform1i(prog, kUniformCapBase, GLint(cap_base));
    glEnable(GL_CULL_FACE);
    for (std::uint32_t b = 0; b < batches; ++b) {
        const GLint first = GLint(cell_start_[b]) * kSlotVertices;
        const GLsizei count = GLsizei(cell_start_[b + 1] - cell_start_[b]) * kSlotVertices;
        const GLint cap_first = GLint(cap_start_[b]);
        const GLsizei cap_count = GLsizei(cap_start_[b + 1] - cap_start_[b]);
        // Pass 1: back faces write α = (d − d_min)/Δd. Each pixel of a convex cell's footprint
        // is covered by exactly one back face, and batches do not overlap: plain writes.
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
        glDisablei(GL_BLEND, 0);
        glCullFace(GL_FRONT);
        glProgramUniform1i(prog, kUniformPass, 1);
        glProgramUniform1i(prog, kUniformSource, kSourceBatch);
        glDrawArrays(GL_TRIANGLES, first, count);
        // Pass 2: front faces subtract theirs; caps stand in for clipped front faces (§5).
        glEnablei(GL_BLEND, 0);
        glBlendEquationSeparate(GL_FUNC_REVERSE_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT); // dst − src
        glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
        glCullFace(GL_BACK);
        glProgramUniform1i(prog, kUniformPass, 2);
        glDrawArrays(GL_TRIANGLES, first, count);
        if (cap_count > 0) {
            glProgramUniform1i(prog, kUniformSource, kSourceCaps);
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        // Pass 3: colour κ(S)·Δd/2 on all faces (and caps), times the segment length in alpha.
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
        glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
        glBlendFuncSeparate(GL_DST_ALPHA, GL_ONE, GL_ZERO, GL_ONE);
        glDisable(GL_CULL_FACE);
        glProgramUniform1i(prog, kUniformPass, 3);
        glProgramUniform1i(prog, kUniformSource, kSourceBatch);
        glDrawArrays(GL_TRIANGLES, first, count);
        if (cap_count > 0) {
            glProgramUniform1i(prog, kUniformSource, kSourceCaps);
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        glEnable(GL_CULL_FACE);
        stats.draw_calls += cap_count > 0 ? 5 : 3;
    }
    FX_GL_CHECK("pcp draw");
}

} // namespace fx
