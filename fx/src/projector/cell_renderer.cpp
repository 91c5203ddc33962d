// Based on: Roettger & Ertl 2003, §2 (MIP), §3 (PCP, three passes per cell) and §5 (near-plane
// caps). The GL side of the projector and the three paths; shaders in shaders/project.glsl,
// project.vert, pcp.frag, pcp_exact.frag, mip.frag, pcp_resolve.frag.
#include "fx/cell_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "absorption/absorption_pass.hpp"
#include "projector/projector_access.hpp"
#include "fx/error.hpp"
#include "fx/footprint_batches.hpp"
#include "fx/polyhedron_projector.hpp"
#include "fx/segment_integral.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl/shader_library.hpp"
#include "gl/state_guard.hpp"

namespace fx {

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

namespace {

// Uniform locations shared by project.glsl / project.vert / the fragment shaders.
enum Uniform : GLint {
    kViewProjection = 0,
    kEye = 1,
    kForward = 2,
    kNear = 3,
    kOrthographic = 4,
    kTable = 5,
    kSource = 6,
    kCapBase = 7,
    kPass = 8,
    // Scene depth (CellRenderOptions::scene_depth), project.glsl.
    kSceneDepthMode = 20,
    kSceneDepthRange = 21,
    kSceneOrigin = 22,
};
constexpr GLuint kSceneDepthUnit = 3; // within the units gl::StateGuard saves
enum Source : GLint { kSourceMesh = 0, kSourceBatch = 1, kSourceCaps = 2 };
constexpr int kTableSize = 4096;
constexpr int kSlotVertices = 36; // 12 triangles: the most any cell type has (hexahedron)

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

} // namespace

struct CellRenderer::Impl {
    CellMesh mesh; // topology for the per-frame projection (classic PCP, caps)
    ProjectorGeometry geometry;
    ScalarRange field_range;
    TransferFunction source_tf; // as given: normalized ones are rescaled when the field changes

    gl::Buffer points, triangles, cells;
    gl::Buffer frame;
    std::size_t frame_capacity = 0; // uvec4 entries
    gl::Texture tables;
    double s_lo = 0.0, s_hi = 1.0;
    gl::Program exact, classic, mip, resolve, resolve_fog;
    gl::VertexArray vao;
    gl::RenderTarget accumulation_float, accumulation_8bit;
    gl::Query timer;
    std::size_t bytes = 0;
    TransferFunction transfer;                   // as in use (normalized ones rescaled)
    std::unique_ptr<AbsorptionPass> absorption;  // the absorption paths, made on first use

    // Per-frame scratch, kept to avoid reallocations.
    ProjectedCells projected;
    NearCaps caps;
    CellFootprints footprints;
    std::vector<std::uint32_t> batch_of;
    std::vector<glm::uvec4> frame_data;

    void upload_mesh(const CellMesh& source, const std::string& scalar_name);
    void upload_tables(const TransferFunction& tf);
    void set_scene_depth_uniforms(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options) const;
    void set_view_uniforms(const Camera& camera, const Viewport& viewport) const;
    void set_view_uniforms_on(GLuint program, const Camera& camera, const Viewport& viewport) const;
    void set_scene_depth_uniforms_on(GLuint program, const Camera& camera, const Viewport& viewport,
                                     unsigned scene_depth) const;
    bool mesh_crosses_near_plane(const ProjectorView& view) const;
    void upload_frame();
    void append_cap_vertices(std::size_t polygon, std::vector<glm::uvec4>& out) const;
    void draw_classic(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                      CellRenderStats& stats);
    void draw_mip(const Camera& camera, CellRenderStats& stats);
    void draw_exact(CellRenderStats& stats);
    gl::RenderTarget& target_for(RenderPath path, int width, int height);
    AbsorptionPass& absorption_pass();
};

AbsorptionPass& CellRenderer::Impl::absorption_pass() {
    if (!absorption) {
        absorption = std::make_unique<AbsorptionPass>(mesh, geometry);
        absorption->set_transfer_function(transfer);
    }
    return *absorption;
}

CellRenderer::CellRenderer(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.upload_mesh(mesh, scalar_name);
    const gl::ShaderLibrary& lib = gl::ShaderLibrary::builtin();
    m.exact = lib.link({"project.vert", "pcp_exact.frag"});
    m.classic = lib.link({"project.vert", "pcp.frag"});
    m.mip = lib.link({"project.vert", "mip.frag"});
    m.resolve = lib.link({"fullscreen.vert", "pcp_resolve.frag"});
    m.resolve_fog = lib.link({"fullscreen.vert", "pcp_resolve.frag"}, gl::Defines{{"RESOLVE_FOG", "1"}});
    m.vao = gl::VertexArray::create();
    m.timer = gl::Query::create(GL_TIME_ELAPSED);
    m.tables = gl::make_texture_2d(GL_RGBA32F, kTableSize, 2);
    set_transfer_function(tf);
}

void CellRenderer::set_mesh(const CellMesh& mesh, const std::string& scalar_name) {
    impl_->absorption.reset(); // its subdivision, sorts and tables belong to the old mesh
    impl_->upload_mesh(mesh, scalar_name);
    set_transfer_function(impl_->source_tf);
}

void CellRenderer::set_scalars(const std::vector<float>& values) {
    Impl& m = *impl_;
    if (values.size() != m.geometry.scalars.size())
        throw Error("cell renderer: set_scalars got " + std::to_string(values.size()) + " values for " +
                    std::to_string(m.geometry.scalars.size()) + " points");
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) throw Error("cell renderer: set_scalars: value " + std::to_string(i) + " is not finite");
    // The absorption paths' state (working mesh, sorts, tables) depends on the geometry and the
    // transfer function only; their builders read the scalars from `geometry` and the GPU buffer.
    m.geometry.scalars = values;
    std::vector<glm::vec4> point_data(std::max<std::size_t>(values.size(), 1));
    for (std::size_t i = 0; i < values.size(); ++i) point_data[i] = glm::vec4(m.geometry.positions[i], values[i]);
    glNamedBufferSubData(m.points.id(), 0, GLsizeiptr(point_data.size() * sizeof(glm::vec4)), point_data.data());
    FX_GL_CHECK("set_scalars upload");
    m.field_range = values.empty() ? ScalarRange{0.0f, 0.0f} : ScalarRange{values[0], values[0]};
    for (float v : values) m.field_range.lo = std::min(m.field_range.lo, v), m.field_range.hi = std::max(m.field_range.hi, v);
    if (m.source_tf.normalized()) set_transfer_function(m.source_tf); // its tables follow the range
}

void CellRenderer::Impl::upload_mesh(const CellMesh& source, const std::string& scalar_name) {
    Impl& m = *this;
    const ScalarField* field = nullptr;
    if (!scalar_name.empty()) {
        field = source.find_scalar(scalar_name);
        if (!field) throw Error("cell renderer: the mesh has no scalar field '" + scalar_name + "'");
    } else if (!source.scalars.empty()) {
        field = &source.scalars[0];
    }
    m.geometry = build_projector_geometry(source, field);
    m.field_range = field ? scalar_range(*field) : ScalarRange{0.0f, 0.0f};
    m.mesh = source;
    m.mesh.scalars.clear(); // the geometry holds the one field in use

    const std::size_t np = m.geometry.positions.size(), nt = m.geometry.triangles.size();
    std::vector<glm::vec4> point_data(std::max<std::size_t>(np, 1));
    for (std::size_t i = 0; i < np; ++i) point_data[i] = glm::vec4(m.geometry.positions[i], m.geometry.scalars[i]);
    struct GpuTriangle {
        glm::uvec4 v;
        glm::vec4 plane;
    };
    std::vector<GpuTriangle> triangle_data(std::max<std::size_t>(nt, 1));
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& tri = m.geometry.triangles[t];
        triangle_data[t] = {glm::uvec4(tri[0], tri[1], tri[2], m.geometry.triangle_cell[t]), m.geometry.triangle_planes[t]};
    }
    // Dynamic storage: set_scalars rewrites it in place.
    m.points = gl::make_buffer(GLsizeiptr(point_data.size() * sizeof(glm::vec4)), point_data.data(), GL_DYNAMIC_STORAGE_BIT);
    m.triangles = gl::make_buffer(GLsizeiptr(triangle_data.size() * sizeof(GpuTriangle)), triangle_data.data());
    m.cells = gl::make_buffer(GLsizeiptr(m.geometry.cell_first_triangle.size() * sizeof(std::uint32_t)),
                              m.geometry.cell_first_triangle.data());
    m.bytes = point_data.size() * sizeof(glm::vec4) + triangle_data.size() * sizeof(GpuTriangle) +
              m.geometry.cell_first_triangle.size() * sizeof(std::uint32_t) + std::size_t(kTableSize) * 2 * 16;
    // The CPU copy of planes and triangles is only needed for caps; triangles stay (caps walk
    // them), positions stay (projection). Planes are GPU-only from here on.
    m.geometry.triangle_planes = {};
}

CellRenderer::~CellRenderer() = default;
CellRenderer::CellRenderer(CellRenderer&&) noexcept = default;
CellRenderer& CellRenderer::operator=(CellRenderer&&) noexcept = default;

std::size_t CellRenderer::cell_count() const { return impl_->mesh.cell_count(); }
std::size_t CellRenderer::gpu_bytes() const {
    return impl_->bytes + (impl_->absorption ? impl_->absorption->gpu_bytes() : 0);
}

void CellRenderer::set_transfer_function(const TransferFunction& tf) {
    impl_->source_tf = tf;
    const TransferFunction t =
        tf.normalized() ? tf.rescaled(impl_->field_range.lo, std::max(impl_->field_range.hi, impl_->field_range.lo + 1e-30f))
                        : tf;
    impl_->upload_tables(t);
    impl_->transfer = t;
    if (impl_->absorption) impl_->absorption->set_transfer_function(t);
}

void CellRenderer::Impl::upload_tables(const TransferFunction& tf) {
    std::vector<glm::vec4> texels;
    build_emission_rows(tf, kTableSize, texels, s_lo, s_hi);
    glTextureSubImage2D(tables.id(), 0, 0, 0, kTableSize, 2, GL_RGBA, GL_FLOAT, texels.data());
    FX_GL_CHECK("glTextureSubImage2D(tables)");
}

void CellRenderer::Impl::set_view_uniforms(const Camera& camera, const Viewport& viewport) const {
    for (const gl::Program* p : {&exact, &classic, &mip}) set_view_uniforms_on(p->id(), camera, viewport);
    FX_GL_CHECK("view uniforms");
}

void CellRenderer::Impl::set_view_uniforms_on(GLuint program, const Camera& camera, const Viewport& viewport) const {
    const ProjectorView view = make_projector_view(geometry, camera);
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::mat4 vp(camera.projection_matrix(aspect) * view.view);
    const glm::vec3 eye(view.eye), forward(view.forward);
    const double span = s_hi - s_lo;
    const glm::vec4 table(float(s_lo), float(s_hi), float(kTableSize), span > 0.0 ? float((kTableSize - 1) / span) : 0.0f);
    glProgramUniformMatrix4fv(program, kViewProjection, 1, GL_FALSE, glm::value_ptr(vp));
    glProgramUniform3fv(program, kEye, 1, glm::value_ptr(eye));
    glProgramUniform3fv(program, kForward, 1, glm::value_ptr(forward));
    glProgramUniform1f(program, kNear, float(view.near_distance));
    glProgramUniform1i(program, kOrthographic, view.orthographic ? 1 : 0);
    glProgramUniform4fv(program, kTable, 1, glm::value_ptr(table));
}

void CellRenderer::Impl::set_scene_depth_uniforms(const Camera& camera, const Viewport& viewport,
                                                  const CellRenderOptions& options) const {
    for (const gl::Program* p : {&exact, &classic, &mip}) set_scene_depth_uniforms_on(p->id(), camera, viewport, options.scene_depth);
    glBindTextureUnit(kSceneDepthUnit, options.scene_depth);
    glBindSampler(kSceneDepthUnit, 0);
    FX_GL_CHECK("scene depth");
}

void CellRenderer::Impl::set_scene_depth_uniforms_on(GLuint program, const Camera& camera, const Viewport& viewport,
                                                     unsigned scene_depth) const {
    // Mode 0: no scene depth; 1: perspective window depth; 2: orthographic (project.glsl).
    const GLint mode = scene_depth == 0 ? 0 : (camera.orthographic() ? 2 : 1);
    glProgramUniform1i(program, kSceneDepthMode, mode);
    glProgramUniform2f(program, kSceneDepthRange, float(camera.near_distance), float(camera.far_distance));
    glProgramUniform2i(program, kSceneOrigin, viewport.x, viewport.y);
}

GLsizei ProjectorAccess::bind(CellRenderer& renderer, GLuint program, const Camera& camera, const Viewport& viewport,
                              unsigned scene_depth) {
    const CellRenderer::Impl& m = *renderer.impl_;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.points.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m.triangles.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m.cells.id());
    glBindTextureUnit(0, m.tables.id());
    glBindSampler(0, 0);
    glBindTextureUnit(kSceneDepthUnit, scene_depth);
    glBindSampler(kSceneDepthUnit, 0);
    m.set_view_uniforms_on(program, camera, viewport);
    m.set_scene_depth_uniforms_on(program, camera, viewport, scene_depth);
    glProgramUniform1i(program, kSource, kSourceMesh);
    FX_GL_CHECK("projector binding");
    return GLsizei(m.geometry.triangles.size() * 3);
}

bool CellRenderer::Impl::mesh_crosses_near_plane(const ProjectorView& view) const {
    // Any corner of the bounds in front of the near plane: some cell may be cut.
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const glm::vec3& p : geometry.positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    if (geometry.positions.empty()) return false;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 c((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
        if (view.depth(c) <= 0.0) return true;
    }
    return false;
}

void CellRenderer::Impl::upload_frame() {
    if (frame_data.empty()) frame_data.emplace_back(0u);
    if (frame_data.size() > frame_capacity) {
        frame_capacity = std::max(frame_data.size(), frame_capacity * 3 / 2);
        frame = gl::make_buffer(GLsizeiptr(frame_capacity * sizeof(glm::uvec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(frame.id(), 0, GLsizeiptr(frame_data.size() * sizeof(glm::uvec4)), frame_data.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, frame.id());
    FX_GL_CHECK("upload frame data");
}

void CellRenderer::Impl::append_cap_vertices(std::size_t k, std::vector<glm::uvec4>& out) const {
    const std::uint32_t b = caps.first_vertex[k], e = caps.first_vertex[k + 1];
    const glm::vec2 range = projected.depth_range[caps.cell[k]];
    auto vertex = [&](std::uint32_t v) {
        const glm::vec3& p = caps.positions[v];
        out.emplace_back(bits(p.x), bits(p.y), bits(p.z), bits(caps.scalars[v]));
        out.emplace_back(bits(range.x), bits(range.y), 0u, 0u);
    };
    for (std::uint32_t v = b + 1; v + 1 < e; ++v) { // fan: convex polygon
        vertex(b), vertex(v), vertex(v + 1);
    }
}

gl::RenderTarget& CellRenderer::Impl::target_for(RenderPath path, int width, int height) {
    gl::RenderTarget& t = path == RenderPath::Pcp ? accumulation_8bit : accumulation_float;
    const gl::ColorFormat format = path == RenderPath::Pcp ? gl::ColorFormat::RGBA8 : gl::ColorFormat::RGBA32F;
    if (t.width() != width || t.height() != height) t = gl::RenderTarget::create(width, height, format, false);
    return t;
}

void CellRenderer::Impl::draw_exact(CellRenderStats& stats) {
    glUseProgram(exact.id());
    glProgramUniform1i(exact.id(), kSource, kSourceMesh);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each fragment is a ray's exit from its cell
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(geometry.triangles.size() * 3));
    stats.draw_calls += 1;
    stats.cells_drawn = mesh.cell_count();
    FX_GL_CHECK("pcp-exact draw");
}

void CellRenderer::Impl::draw_mip(const Camera& camera, CellRenderStats& stats) {
    const ProjectorView view = make_projector_view(geometry, camera);
    caps.clear();
    if (mesh_crosses_near_plane(view)) {
        project_cells(mesh, geometry, view, projected);
        build_near_caps(geometry, view, projected, caps);
    }
    glUseProgram(mip.id());
    glDisable(GL_CULL_FACE);
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_MAX, GL_MAX);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE); // ignored by GL_MAX
    glProgramUniform1i(mip.id(), kSource, kSourceMesh);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(geometry.triangles.size() * 3));
    stats.draw_calls += 1;
    stats.cells_drawn = mesh.cell_count();
    if (caps.polygon_count() > 0) {
        frame_data.clear();
        for (std::size_t k = 0; k < caps.polygon_count(); ++k) append_cap_vertices(k, frame_data);
        upload_frame();
        glProgramUniform1i(mip.id(), kSource, kSourceCaps);
        glProgramUniform1i(mip.id(), kCapBase, 0);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(frame_data.size() / 2));
        stats.draw_calls += 1;
        stats.caps = caps.polygon_count();
    }
    FX_GL_CHECK("mip draw");
}

void CellRenderer::Impl::draw_classic(const Camera& camera, const Viewport& viewport, const CellRenderOptions& options,
                                      CellRenderStats& stats) {
    const ProjectorView view = make_projector_view(geometry, camera);
    project_cells(mesh, geometry, view, projected);
    build_near_caps(geometry, view, projected, caps);
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::dmat4 vp = camera.projection_matrix(aspect) * view.view;
    cell_footprints(mesh, geometry, view, vp, projected, caps, viewport.width, viewport.height, options.batch_tile,
                    footprints);
    const std::uint32_t batches = batch_footprints(footprints, batch_of);

    // Counting sort of cells by batch, then the caps (as fan triangles) grouped the same way.
    std::vector<std::uint32_t> cell_start(batches + 1, 0), cap_start(batches + 1, 0);
    for (std::uint32_t b : batch_of)
        if (b != kNoBatch) ++cell_start[b + 1];
    for (std::uint32_t b = 0; b < batches; ++b) cell_start[b + 1] += cell_start[b];
    const std::uint32_t drawn = batches ? cell_start[batches] : 0;
    frame_data.assign(drawn, glm::uvec4(0u));
    {
        std::vector<std::uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
        for (std::size_t c = 0; c < batch_of.size(); ++c) {
            const std::uint32_t b = batch_of[c];
            if (b == kNoBatch) continue;
            const glm::vec2 r = projected.depth_range[c];
            frame_data[fill[b]++] = glm::uvec4(std::uint32_t(c), bits(r.x), bits(r.y), 0u);
        }
    }
    std::vector<std::vector<std::uint32_t>> caps_of_batch(batches);
    for (std::size_t k = 0; k < caps.polygon_count(); ++k) {
        const std::uint32_t b = batch_of[caps.cell[k]];
        if (b != kNoBatch) caps_of_batch[b].push_back(std::uint32_t(k));
    }
    const std::size_t cap_base = frame_data.size();
    for (std::uint32_t b = 0; b < batches; ++b) {
        cap_start[b] = std::uint32_t((frame_data.size() - cap_base) / 2);
        for (std::uint32_t k : caps_of_batch[b]) append_cap_vertices(k, frame_data);
    }
    cap_start[batches] = std::uint32_t((frame_data.size() - cap_base) / 2);
    upload_frame();
    stats.cells_drawn = drawn;
    stats.batches = batches;
    stats.caps = caps.polygon_count();

    const GLuint prog = classic.id();
    glUseProgram(prog);
    glProgramUniform1i(prog, kCapBase, GLint(cap_base));
    glEnable(GL_CULL_FACE);
    for (std::uint32_t b = 0; b < batches; ++b) {
        const GLint first = GLint(cell_start[b]) * kSlotVertices;
        const GLsizei count = GLsizei(cell_start[b + 1] - cell_start[b]) * kSlotVertices;
        const GLint cap_first = GLint(cap_start[b]);
        const GLsizei cap_count = GLsizei(cap_start[b + 1] - cap_start[b]);
        // Pass 1: back faces write α = (d − d_min)/Δd. Each pixel of a convex cell's footprint
        // is covered by exactly one back face, and batches do not overlap: plain writes.
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
        glDisablei(GL_BLEND, 0);
        glCullFace(GL_FRONT);
        glProgramUniform1i(prog, kPass, 1);
        glProgramUniform1i(prog, kSource, kSourceBatch);
        glDrawArrays(GL_TRIANGLES, first, count);
        // Pass 2: front faces subtract theirs; caps stand in for clipped front faces (§5).
        glEnablei(GL_BLEND, 0);
        glBlendEquationSeparate(GL_FUNC_REVERSE_SUBTRACT, GL_FUNC_REVERSE_SUBTRACT); // dst − src
        glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ONE, GL_ONE);
        glCullFace(GL_BACK);
        glProgramUniform1i(prog, kPass, 2);
        glDrawArrays(GL_TRIANGLES, first, count);
        if (cap_count > 0) {
            glProgramUniform1i(prog, kSource, kSourceCaps);
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        // Pass 3: colour κ(S)·Δd/2 on all faces (and caps), times the segment length in alpha.
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
        glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
        glBlendFuncSeparate(GL_DST_ALPHA, GL_ONE, GL_ZERO, GL_ONE);
        glDisable(GL_CULL_FACE);
        glProgramUniform1i(prog, kPass, 3);
        glProgramUniform1i(prog, kSource, kSourceBatch);
        glDrawArrays(GL_TRIANGLES, first, count);
        if (cap_count > 0) {
            glProgramUniform1i(prog, kSource, kSourceCaps);
            glDrawArrays(GL_TRIANGLES, cap_first, cap_count);
        }
        glEnable(GL_CULL_FACE);
        stats.draw_calls += cap_count > 0 ? 5 : 3;
    }
    FX_GL_CHECK("pcp draw");
}

CellRenderStats CellRenderer::render(const Camera& camera, const Viewport& viewport, RenderPath path,
                                     const CellRenderOptions& options) {
    if (viewport.width <= 0 || viewport.height <= 0) throw Error("cell renderer: empty viewport");
    Impl& m = *impl_;
    const auto cpu_start = std::chrono::steady_clock::now();
    CellRenderStats stats;
    stats.cells = m.mesh.cell_count();
    gl::StateGuard guard;
    GLint host_framebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host_framebuffer);
    const bool absorption = path == RenderPath::Absorption || path == RenderPath::AbsorptionExact;
    // The absorption paths' CPU work (sort, subdivision, projection) comes before the timed GL work.
    if (absorption) m.absorption_pass().prepare(camera, viewport, path == RenderPath::AbsorptionExact, options, stats);
    if (options.timing) glBeginQuery(GL_TIME_ELAPSED, m.timer.id());

    gl::StateGuard::set_render_defaults();
    gl::RenderTarget& target = m.target_for(path, viewport.width, viewport.height);
    target.clear(glm::vec4(0.0f));
    target.bind_for_drawing();
    glBindVertexArray(m.vao.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.points.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m.triangles.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m.cells.id());
    glBindTextureUnit(0, m.tables.id());
    glBindSampler(0, 0);
    m.set_view_uniforms(camera, viewport);
    m.set_scene_depth_uniforms(camera, viewport, options);

    switch (path) {
    case RenderPath::PcpExact: m.draw_exact(stats); break;
    case RenderPath::Mip: m.draw_mip(camera, stats); break;
    case RenderPath::Pcp: m.draw_classic(camera, viewport, options, stats); break;
    case RenderPath::Absorption:
    case RenderPath::AbsorptionExact:
        m.absorption_pass().draw(camera, viewport, path == RenderPath::AbsorptionExact, options, stats);
        break;
    }

    glBindTextureUnit(kSceneDepthUnit, 0); // the host's depth may be attached to its framebuffer

    // Resolve over the host's framebuffer: premultiplied "over" (emission adds, alpha 0).
    const bool fog = options.fog && path == RenderPath::PcpExact;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(host_framebuffer));
    glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_CULL_FACE);
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    const gl::Program& resolve = absorption ? m.absorption_pass().resolve() : fog ? m.resolve_fog : m.resolve;
    glUseProgram(resolve.id());
    glProgramUniform2i(resolve.id(), 0, viewport.x, viewport.y);
    glBindTextureUnit(0, target.color_texture());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    stats.draw_calls += 1;
    FX_GL_CHECK("resolve");

    if (options.timing) {
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(m.timer.id(), GL_QUERY_RESULT, &ns);
        stats.gpu_ms = double(ns) * 1e-6;
    }
    stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpu_start).count();
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

} // namespace fx
