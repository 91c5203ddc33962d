// The dispatcher above the GL projector (projector/gl_projector.hpp) and the render paths'
// passes (passes/): per frame it saves the host's state, picks the path's target and pass,
// and composites the result over the host's framebuffer (pcp_resolve.frag,
// absorption_resolve.frag).
#include "fx/cell_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "passes/absorption_pass.hpp"
#include "passes/mip_pass.hpp"
#include "passes/pcp_exact_pass.hpp"
#include "passes/pcp_pass.hpp"
#include "projector/gl_interface.hpp"
#include "projector/gl_projector.hpp"
#include "render/projector_access.hpp"

namespace cellfx::fx {

const char* render_path_name(RenderPath path) {
    switch (path) {
    case RenderPath::Pcp: return "pcp";
    case RenderPath::PcpExact: return "pcp-exact";
    case RenderPath::Mip: return "mip";
    case RenderPath::Absorption: return "absorption";
    case RenderPath::AbsorptionExact: return "absorption-exact";
    }
    return "unknown";
}

bool parse_render_path(std::string_view name, RenderPath& path) {
    if (name == "pcp") path = RenderPath::Pcp;
    else if (name == "pcp-exact") path = RenderPath::PcpExact;
    else if (name == "mip") path = RenderPath::Mip;
    else if (name == "absorption") path = RenderPath::Absorption;
    else if (name == "absorption-exact") path = RenderPath::AbsorptionExact;
    else return false;
    return true;
}

// The GL stages of a frame CellRenderOptions::profile times (the draw stage: vertex and
// fragment work together).
enum Stage { kStageTables, kStageClear, kStageUpload, kStageVertex, kStageDraw, kStageResolve, kStages };

struct CellRenderer::Impl {
    std::unique_ptr<GlProjector> projector;
    // The passes, each made on first use (the absorption pass's sorts and tables are dear).
    std::unique_ptr<PcpPass> pcp;
    std::unique_ptr<PcpExactPass> pcp_exact;
    std::unique_ptr<MipPass> mip;
    std::unique_ptr<AbsorptionPass> absorption;
    gl::RenderTarget accumulation_float, accumulation_8bit;
    gl::VertexArray vao;
    gl::Query timer;
    gl::Query stage_queries[kStages]; // CellRenderOptions::profile, made on first use
    ParallelFor parallel_for = default_parallel_for();
    // Resolves over the host's framebuffer (the context's shared programs).
    const gl::Program* resolve_emission = nullptr;
    const gl::Program* resolve_fog = nullptr;
    const gl::Program* resolve_premultiplied = nullptr;

    gl::RenderTarget& target_for(RenderPath path, int width, int height);
    AbsorptionPass& absorption_pass() {
        if (!absorption) absorption = std::make_unique<AbsorptionPass>(*projector);
        return *absorption;
    }
    // Every pass made for the mesh's kind of cells (their programs are compiled for its
    // vertices per cell) is dropped when that changes.
    void cell_kind_changed() {
        pcp.reset(), pcp_exact.reset(), mip.reset(), absorption.reset();
    }
};

CellRenderer::CellRenderer(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf)
    : impl_(std::make_unique<Impl>()) {
    impl_->projector = std::make_unique<GlProjector>(mesh, scalar_name, tf);
    impl_->vao = gl::VertexArray::create();
    impl_->timer = gl::Query::create(GL_TIME_ELAPSED);
    const GlProjector& p = *impl_->projector;
    impl_->resolve_emission = &p.program({"fullscreen.vert", "pcp_resolve.frag"});
    impl_->resolve_fog = &p.program({"fullscreen.vert", "pcp_resolve.frag"}, gl::Defines{{"RESOLVE_FOG", "1"}});
    impl_->resolve_premultiplied = &p.program({"fullscreen.vert", "absorption_resolve.frag"});
}

void CellRenderer::set_mesh(const CellMesh& mesh, const std::string& scalar_name) {
    // Every pass stays (with its storage) while the kind of cells does: the absorption pass
    // rebuilds its subdivision, sorts and tables in place for the new mesh; the others keep only
    // per-frame scratch.
    const int vertices_per_cell = impl_->projector->vertices_per_cell();
    impl_->projector->set_mesh(mesh, scalar_name);
    if (impl_->projector->vertices_per_cell() != vertices_per_cell) impl_->cell_kind_changed();
    else if (impl_->absorption) impl_->absorption->mesh_changed();
}

bool CellRenderer::update_mesh(const CellMesh& mesh, const std::string& scalar_name, const MeshChanges& changes) {
    const int vertices_per_cell = impl_->projector->vertices_per_cell();
    const bool in_place = impl_->projector->update_mesh(mesh, scalar_name, changes);
    if (impl_->projector->vertices_per_cell() != vertices_per_cell) impl_->cell_kind_changed();
    else if (impl_->absorption) impl_->absorption->mesh_changed();
    return in_place;
}

void CellRenderer::set_culling(bool culling) { impl_->projector->set_culling(culling); }

void CellRenderer::set_scalars(const std::vector<float>& values) {
    // The absorption paths' state (working mesh, sorts) depends on the geometry only; their
    // builders read the scalars from the projector's geometry, and the pass sees a changed
    // transfer function (a normalized one follows the range) itself.
    impl_->projector->set_scalars(values);
}

void CellRenderer::set_parallel_for(const ParallelFor& parallel_for) { impl_->parallel_for = parallel_for; }

CellRenderer::~CellRenderer() = default;
CellRenderer::CellRenderer(CellRenderer&&) noexcept = default;

CellRenderer::Impl& CellRenderer::impl() { return *impl_; }
GlProjector& renderer_projector(CellRenderer& renderer) { return *renderer.impl().projector; }
CellRenderer& CellRenderer::operator=(CellRenderer&&) noexcept = default;

std::size_t CellRenderer::cell_count() const { return impl_->projector->mesh().cell_count(); }
std::size_t CellRenderer::gpu_bytes() const {
    const Memory m = gpu_memory();
    return m.mesh + m.cell_tables + m.unique_faces + m.pcp_list + m.absorption;
}

CellRenderer::Memory CellRenderer::gpu_memory() const {
    const Impl& m = *impl_;
    const ProjectorMemory projector = m.projector->memory();
    Memory out;
    out.mesh = projector.mesh, out.cell_tables = projector.cell_tables, out.unique_faces = projector.unique_faces;
    out.pcp_list = m.pcp ? m.pcp->gpu_bytes() : 0;
    out.absorption = m.absorption ? m.absorption->gpu_bytes() : 0;
    const auto pixels = [](const gl::RenderTarget& t) { return std::size_t(t.width()) * std::size_t(t.height()); };
    out.targets = pixels(m.accumulation_float) * 16 + pixels(m.accumulation_8bit) * 4;
    return out;
}

void CellRenderer::set_transfer_function(const TransferFunction& tf) {
    impl_->projector->set_transfer_function(tf); // the absorption pass sees it at its next frame
}

gl::RenderTarget& CellRenderer::Impl::target_for(RenderPath path, int width, int height) {
    gl::RenderTarget& t = path == RenderPath::Pcp ? accumulation_8bit : accumulation_float;
    const gl::ColorFormat format = path == RenderPath::Pcp ? gl::ColorFormat::RGBA8 : gl::ColorFormat::RGBA32F;
    if (t.width() != width || t.height() != height) t = gl::RenderTarget::create(width, height, format, false);
    return t;
}

CellRenderStats CellRenderer::render(const Camera& camera, const Viewport& viewport, RenderPath path,
                                     const CellRenderOptions& options) {
    if (viewport.width <= 0 || viewport.height <= 0) throw Error("cell renderer: empty viewport");
    using Clock = std::chrono::steady_clock;
    Impl& m = *impl_;
    GlProjector& projector = *m.projector;
    const auto cpu_start = Clock::now();
    CellRenderStats stats;
    stats.cells = projector.mesh().cell_count();
    gl::StateGuard guard;
    GLint host_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host_framebuffer);
    const bool absorption = path == RenderPath::Absorption || path == RenderPath::AbsorptionExact;
    const bool exact = path == RenderPath::AbsorptionExact;
    // The passes are made on first use.
    if (path == RenderPath::PcpExact && !m.pcp_exact) m.pcp_exact = std::make_unique<PcpExactPass>(projector);
    if (path == RenderPath::Mip && !m.mip) m.mip = std::make_unique<MipPass>(projector);
    if (path == RenderPath::Pcp && !m.pcp) m.pcp = std::make_unique<PcpPass>(projector);
    // The CPU work of the frame (sort, subdivision, projection, batches) comes before the GL work.
    if (absorption) m.absorption_pass().prepare(camera, viewport, exact, options, m.parallel_for, stats);
    if (path == RenderPath::Pcp) m.pcp->prepare(camera, viewport, options, stats);
    if (path == RenderPath::Mip) m.mip->prepare(camera);

    // With options.profile each GL stage runs alone (the GL finished before and after it) inside
    // a GL_TIME_ELAPSED query, and by the CPU's clock from one glFinish to the next
    // (CellRenderStats::StageTime).
    const auto begin_stage = [&](Stage s) {
        if (!options.profile) return Clock::now();
        glFinish();
        if (!m.stage_queries[s]) m.stage_queries[s] = gl::Query::create(GL_TIME_ELAPSED);
        glBeginQuery(GL_TIME_ELAPSED, m.stage_queries[s].id());
        return Clock::now();
    };
    double stage_wall[kStages] = {};
    const auto end_stage = [&](Stage s, Clock::time_point start) {
        if (!options.profile) return;
        glEndQuery(GL_TIME_ELAPSED);
        glFinish();
        stage_wall[s] = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    };
    if (options.timing && !options.profile) glBeginQuery(GL_TIME_ELAPSED, m.timer.id()); // queries do not nest

    gl::StateGuard::set_render_defaults();
    auto start = begin_stage(kStageTables);
    // The GPU's tables (and culled cells) for this mesh and view: the exact paths' alone.
    if (path == RenderPath::PcpExact || path == RenderPath::AbsorptionExact) projector.prepare_draw(camera, viewport);
    end_stage(kStageTables, start);
    gl::RenderTarget& target = m.target_for(path, viewport.width, viewport.height);
    // Only the pixels the mesh can cover are cleared, drawn and resolved: a small mesh in a large
    // frame pays for its own pixels (what lies outside them in the target is never read).
    const glm::ivec4 rect = projector.screen_rect(camera, viewport);
    glEnable(GL_SCISSOR_TEST);
    glScissorIndexed(0, rect.x, rect.y, rect.z, rect.w);
    start = begin_stage(kStageClear);
    target.clear(glm::vec4(0.0f));
    end_stage(kStageClear, start);
    start = begin_stage(kStageUpload);
    switch (path) {
    case RenderPath::Pcp: m.pcp->upload(); break;
    case RenderPath::Mip: m.mip->upload(); break;
    case RenderPath::Absorption:
    case RenderPath::AbsorptionExact: m.absorption_pass().upload(exact); break;
    case RenderPath::PcpExact: break;
    }
    end_stage(kStageUpload, start);
    target.bind_for_drawing();
    glBindVertexArray(m.vao.id());
    projector.bind_mesh();
    GlProjector::bind_scene_depth(options.scene_depth);

    const auto draw = [&](CellRenderStats& s) {
        switch (path) {
        case RenderPath::PcpExact: m.pcp_exact->draw(camera, viewport, options, s); break;
        case RenderPath::Mip: m.mip->draw(camera, viewport, options, s); break;
        case RenderPath::Pcp: m.pcp->draw(camera, viewport, options, s); break;
        case RenderPath::Absorption:
        case RenderPath::AbsorptionExact: m.absorption_pass().draw(camera, viewport, exact, options, s); break;
        }
    };
    if (options.profile) {
        // The same draws with rasterisation off first: what the vertex stage costs alone (the
        // draws' own figure less it is the fragment stage's).
        CellRenderStats discarded = stats;
        start = begin_stage(kStageVertex);
        glEnable(GL_RASTERIZER_DISCARD);
        draw(discarded);
        glDisable(GL_RASTERIZER_DISCARD);
        end_stage(kStageVertex, start);
    }
    start = begin_stage(kStageDraw);
    draw(stats);
    end_stage(kStageDraw, start);

    GlProjector::bind_scene_depth(0); // the host's depth may be attached to its framebuffer

    // Resolve over the host's framebuffer: premultiplied "over" (emission adds, alpha 0).
    const bool fog = options.fog && path == RenderPath::PcpExact;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(host_framebuffer));
    glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glScissorIndexed(0, viewport.x + rect.x, viewport.y + rect.y, rect.z, rect.w);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_CULL_FACE);
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    const gl::Program& resolve = absorption ? *m.resolve_premultiplied : fog ? *m.resolve_fog : *m.resolve_emission;
    glUseProgram(resolve.id());
    glProgramUniform2i(resolve.id(), kUniformResolveOrigin, viewport.x, viewport.y);
    glBindTextureUnit(kUnitAccumulation, target.color_texture());
    start = begin_stage(kStageResolve);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    end_stage(kStageResolve, start);
    stats.draw_calls += 1;
    FX_GL_CHECK("resolve");

    const auto query_ms = [](const gl::Query& q) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
        return double(ns) * 1e-6;
    };
    if (options.profile) {
        double gl[kStages];
        for (int s = 0; s < kStages; ++s) gl[s] = query_ms(m.stage_queries[s]);
        const auto time = [&](Stage s) { return CellRenderStats::StageTime{stage_wall[s], gl[s]}; };
        stats.tables = time(kStageTables), stats.clear = time(kStageClear), stats.upload = time(kStageUpload);
        stats.vertex = time(kStageVertex), stats.resolve = time(kStageResolve);
        stats.fragment = {std::max(stage_wall[kStageDraw] - stage_wall[kStageVertex], 0.0),
                          std::max(gl[kStageDraw] - gl[kStageVertex], 0.0)};
        stats.gpu_ms = gl[kStageTables] + gl[kStageClear] + gl[kStageUpload] + gl[kStageDraw] + gl[kStageResolve];
    } else if (options.timing) {
        glEndQuery(GL_TIME_ELAPSED);
        stats.gpu_ms = query_ms(m.timer);
    }
    stats.cpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - cpu_start).count();
    return stats;
}

Image CellRenderer::render_to_image(const Camera& camera, int width, int height, RenderPath path,
                                    const CellRenderOptions& options, CellRenderStats* stats) {
    gl::RenderTarget out = gl::RenderTarget::create(width, height, gl::ColorFormat::RGBA32F, false);
    {
        gl::StateGuard guard;
        gl::StateGuard::set_render_defaults();
        out.clear(glm::vec4(0.0f));
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, out.framebuffer());
        const CellRenderStats s = render(camera, Viewport{0, 0, width, height}, path, options);
        if (stats) *stats = s;
    }
    return out.read();
}

} // namespace cellfx::fx
