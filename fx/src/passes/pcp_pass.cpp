// Based on: Roettger & Ertl 2003, §3 (PCP, three passes per cell) and §5 (near-plane caps).
#include "passes/pcp_pass.hpp"

#include <chrono>

#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"
#include "frame_storage.hpp"

namespace cellfx::fx {
PcpPass::PcpPass(GlProjector& projector)
    : projector_(projector), programs_(projector.programs({"cells.vert", "pcp.frag"},
                                                        projector.mesh_defines().set("CELL_LIST").set("CLASSIC"))),
      caps_programs_(projector.programs({"caps.vert", "pcp.frag"})), list_(projector) {}

void PcpPass::prepare(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                      CellRenderStats& stats) {
    const auto start = std::chrono::steady_clock::now();
    const CellMesh& mesh = projector_.mesh();
    const ProjectorGeometry& geometry = projector_.geometry();
    const ProjectorView view = projector_.view(camera);
    project_cells(mesh, geometry, view, projected_);
    build_near_caps(geometry, view, projected_, caps_);
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::dmat4 vp = camera.projection_matrix(aspect) * view.view;
    cell_footprints(mesh, geometry, vp, projected_, caps_, viewport.width, viewport.height, options.batch_tile,
                    footprints_);
    const std::uint32_t batches = batches_ = batch_footprints(footprints_, batch_of_, masks_);

    // Counting sort of cells by batch, then the caps (as fan triangles) grouped the same way.
    // There are never more batches or listed cells than cells: room for that many from the
    // first frame on, so that a view with more batches than any before allocates nothing.
    const std::size_t nc = mesh.cell_count();
    for (std::vector<std::uint32_t>* v : {&cell_start_, &cap_start_, &cap_first_, &fill_, &list_cells_}) reserve_kept(*v, nc + 1);
    reserve_kept(list_ranges_, nc);
    assign_kept(cell_start_, batches + 1, 0u);
    assign_kept(cap_start_, batches + 1, 0u);
    for (std::uint32_t b : batch_of_)
        if (b != kNoBatch) ++cell_start_[b + 1];
    for (std::uint32_t b = 0; b < batches; ++b) cell_start_[b + 1] += cell_start_[b];
    const std::uint32_t drawn = batches ? cell_start_[batches] : 0;
    resize_kept(list_cells_, drawn);
    resize_kept(list_ranges_, drawn);
    assign_range_kept(fill_, cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t c = 0; c < batch_of_.size(); ++c) {
        const std::uint32_t b = batch_of_[c];
        if (b == kNoBatch) continue;
        list_ranges_[fill_[b]] = projected_.depth_range[c];
        list_cells_[fill_[b]++] = std::uint32_t(c);
    }
    // The caps of each batch in batch order: a counting sort like the cells'.
    assign_kept(cap_first_, batches + 1, 0u);
    for (std::size_t k = 0; k < caps_.polygon_count(); ++k) {
        const std::uint32_t b = batch_of_[caps_.cell[k]];
        if (b != kNoBatch) ++cap_first_[b + 1];
    }
    for (std::uint32_t b = 0; b < batches; ++b) cap_first_[b + 1] += cap_first_[b];
    resize_kept(cap_order_, batches ? cap_first_[batches] : 0);
    assign_range_kept(fill_, cap_first_.begin(), cap_first_.end() - 1);
    for (std::size_t k = 0; k < caps_.polygon_count(); ++k) {
        const std::uint32_t b = batch_of_[caps_.cell[k]];
        if (b != kNoBatch) cap_order_[fill_[b]++] = std::uint32_t(k);
    }
    cap_data_.clear();
    for (std::uint32_t b = 0; b < batches; ++b) {
        cap_start_[b] = std::uint32_t(cap_data_.size() / 2);
        for (std::uint32_t i = cap_first_[b]; i < cap_first_[b + 1]; ++i)
            GlProjector::append_cap_vertices(caps_, projected_, cap_order_[i], cap_data_);
    }
    cap_start_[batches] = std::uint32_t(cap_data_.size() / 2);
    stats.cells_drawn = drawn;
    stats.batches = batches;
    stats.caps = caps_.polygon_count();
    stats.projection_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void PcpPass::upload() {
    list_.upload(list_cells_, list_ranges_);
    projector_.upload_frame(cap_data_);
}

void PcpPass::draw(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                   CellRenderStats& stats) {
    const std::uint32_t batches = batches_;
    projector_.bind_frame();
    const gl::Program& program = programs_(options.scene_depth != 0);
    const gl::Program& caps_program = caps_programs_(options.scene_depth != 0);
    for (const gl::Program* p : {&program, &caps_program}) {
        projector_.set_view_uniforms(*p, camera, viewport);
        projector_.set_scene_depth_uniforms(*p, camera, viewport, options.scene_depth);
    }
    list_.bind(program);
    glEnable(GL_CULL_FACE);
    auto set_pass = [&](int pass) {
        glProgramUniform1i(program.id(), kUniformPass, pass);
        glProgramUniform1i(caps_program.id(), kUniformPass, pass);
    };
    for (std::uint32_t b = 0; b < batches; ++b) {
        const std::size_t first = cell_start_[b], count = cell_start_[b + 1] - cell_start_[b];
        const GLint cap_first = GLint(cap_start_[b]);
        const GLsizei cap_count = GLsizei(cap_start_[b + 1] - cap_start_[b]);
        // Pass 1: back faces write α = (d − d_min)/Δd. Each pixel of a convex cell's footprint
        // is covered by exactly one back face, and batches do not overlap: plain writes.
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
        glDisablei(GL_BLEND, 0);
        glCullFace(GL_FRONT);
        set_pass(1);
        glUseProgram(program.id());
        list_.draw(first, count);
        // Pass 2: front faces subtract theirs; caps stand in for clipped front faces (§5).
        glEnablei(GL_BLEND, 0);
        glBlendEquationSeparate(GL_FUNC_REVERSE_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT); // dst − src
        glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
        glCullFace(GL_BACK);
        set_pass(2);
        list_.draw(first, count);
        if (cap_count > 0) {
            glUseProgram(caps_program.id());
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        // Pass 3: colour κ(S)·Δd/2 on all faces (and caps), times the segment length in alpha.
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
        glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
        glBlendFuncSeparate(GL_DST_ALPHA, GL_ONE, GL_ZERO, GL_ONE);
        glDisable(GL_CULL_FACE);
        set_pass(3);
        glUseProgram(program.id());
        list_.draw(first, count);
        if (cap_count > 0) {
            glUseProgram(caps_program.id());
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        glEnable(GL_CULL_FACE);
        stats.draw_calls += cap_count > 0 ? 5 : 3;
    }
    FX_GL_CHECK("pcp draw");
}

} // namespace cellfx::fx
