// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (intersecting grids integrated in depth
// order per pixel), on the GPU with per-pixel lists of ray segments. Shaders:
// medium_lists.glsl, medium_append.frag (with the projector's cells.vert), medium_resolve.frag.
#include "medium/medium_compositor.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "fx/effect.hpp" // camera_in_frame
#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/program_cache.hpp"
#include "gl/shader_library.hpp"
#include "gl/state_guard.hpp"
#include "projector/gl_interface.hpp"
#include "render/projector_access.hpp"

namespace cellfx::fx {
namespace {

// Uniform locations are the interface table's (projector/gl_interface.hpp), which the append
// program, a projector program too, shares.
static_assert(MediumCompositor::kMaxVolumes == kMediumVolumes, "medium_resolve.frag's size");
constexpr GLuint kListsBinding = 3;
constexpr GLuint kTablesUnit = 0, kMaskUnit = 1, kBehindUnit = 2;
constexpr int kTableSize = 4096;           // samples per row, as the cell renderer's tables
constexpr std::size_t kHeaderBytes = 16;   // medium_count + padding
constexpr std::size_t kSegmentWords = 5;
constexpr std::size_t kMaxCapacity = (std::size_t(1) << 27) - 2; // 27 bits of "next" (medium_lists.glsl)

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

bool same_points(const TransferFunction& a, const TransferFunction& b) {
    const auto& p = a.points();
    const auto& q = b.points();
    if (p.size() != q.size()) return false;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p[i].s != q[i].s || p[i].color != q[i].color || p[i].sigma != q[i].sigma) return false;
    return true;
}

glm::vec3 vec3f(const glm::dvec3& v) { return glm::vec3(v); }

} // namespace

struct MediumCompositor::Impl {
    // The append program per mesh kind (index: all tetrahedra) from the context's shared cache,
    // which this compositor keeps alive as long as it holds the pointers.
    std::shared_ptr<gl::ProgramCache> program_cache;
    std::array<ProgramVariants, 2> append_programs;
    gl::Program resolve_program;
    gl::VertexArray vao;
    gl::Buffer lists;
    std::size_t lists_bytes = 0, capacity = 0, heads = 0;
    std::size_t wanted = 0; // segments the largest frame so far needed (+ 25%)
    gl::Texture tables;
    std::array<TransferFunction, kMaxVolumes> uploaded; // per table row pair
    std::array<glm::vec4, kMaxVolumes> table_params{};
    gl::Query timer;

    gl::Texture mask;                     // R8, viewport-sized: 1 where the region is resolved
    gl::Framebuffer mask_target, no_target; // the mask attached; nothing attached (the bulk's appends)
    int mask_width = 0, mask_height = 0;

    // The frame begun.
    bool begun = false, timing = false;
    Camera camera;
    Viewport viewport;
    PixelRect region; // viewport pixels
    int bulk = -1;
    std::vector<MediumVolume> volumes;
    struct Append {
        CellRenderer* renderer;
        Camera local_camera;
        std::size_t volume;
        unsigned scene_depth;
    };
    std::vector<Append> appends;
    MediumStats stats;
    std::vector<glm::vec4> scratch;

    void upload_tables();
    void set_resolve_uniforms();
    void reserve(std::size_t segments);
    void clear_lists();
    void ensure_mask();
    void clear_mask();
    void draw_appends();
    void draw_append(const Append& a);
    void timed_begin();
    void timed_end(double& part);
};

MediumCompositor::MediumCompositor() : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    const gl::ShaderLibrary& lib = projector_shader_library(); // the built-in shaders and the interface table
    m.program_cache = gl::ProgramCache::for_current_context();
    m.resolve_program = lib.link({"fullscreen.vert", "medium_resolve.frag"});
    m.vao = gl::VertexArray::create();
    m.tables = gl::make_texture_2d(GL_RGBA32F, kTableSize, 2 * kMaxVolumes);
    m.timer = gl::Query::create(GL_TIME_ELAPSED);
    FX_GL_CHECK("medium compositor set-up");
}

MediumCompositor::~MediumCompositor() = default;
MediumCompositor::MediumCompositor(MediumCompositor&&) noexcept = default;
MediumCompositor& MediumCompositor::operator=(MediumCompositor&&) noexcept = default;

std::size_t MediumCompositor::gpu_bytes() const {
    return impl_->lists_bytes + std::size_t(kTableSize) * 2 * kMaxVolumes * sizeof(glm::vec4);
}

void MediumCompositor::Impl::upload_tables() {
    for (std::size_t v = 0; v < volumes.size(); ++v) {
        const TransferFunction& tf = volumes[v].tf;
        if (same_points(tf, uploaded[v]) && !uploaded[v].points().empty()) continue;
        double s_lo = 0.0, s_hi = 1.0;
        build_emission_rows(tf, kTableSize, scratch, s_lo, s_hi);
        glTextureSubImage2D(tables.id(), 0, 0, GLint(2 * v), kTableSize, 2, GL_RGBA, GL_FLOAT, scratch.data());
        const double span = s_hi - s_lo;
        bool varies = false;
        for (const TransferPoint& q : tf.points()) varies = varies || q.color != tf.points().front().color;
        table_params[v] = glm::vec4(float(s_lo), float(s_hi), span > 0.0 ? float((kTableSize - 1) / span) : 0.0f,
                                    varies ? 1.0f : 0.0f);
        uploaded[v] = tf;
    }
    FX_GL_CHECK("medium tables");
}

void MediumCompositor::Impl::set_resolve_uniforms() {
    const GLuint p = resolve_program.id();
    // The pixel rays from the view's projection (an explicit one included, as the appends'
    // fragment rays): the points of the near plane at ndc (0, 0), (1, 0) and (0, 1), eye-relative.
    const glm::dvec3 forward = camera.forward();
    const Camera relative = camera_in_frame(camera, glm::translate(glm::dmat4(1.0), camera.eye));
    const glm::dmat4 from_clip =
        glm::inverse(camera.projection_matrix(double(viewport.width) / double(viewport.height)) * relative.view_matrix());
    const auto near_point = [&](double x, double y) {
        const glm::dvec4 q = from_clip * glm::dvec4(x, y, -1.0, 1.0);
        return glm::dvec3(q) / q.w;
    };
    const glm::dvec3 centre = near_point(0.0, 0.0), right = near_point(1.0, 0.0) - centre, up = near_point(0.0, 1.0) - centre;
    // Perspective: direction = normalize(centre + ndc.x·right + ndc.y·up); orthographic: origin
    // ndc.x·right + ndc.y·up on the eye plane, direction forward.
    glProgramUniform3fv(p, kUniformMediumForward, 1, glm::value_ptr(vec3f(camera.orthographic() ? forward : centre)));
    glProgramUniform3fv(p, kUniformMediumRight, 1, glm::value_ptr(vec3f(right)));
    glProgramUniform3fv(p, kUniformMediumUp, 1, glm::value_ptr(vec3f(up)));
    glProgramUniform1i(p, kUniformMediumOrtho, camera.orthographic() ? 1 : 0);
    glProgramUniform4f(p, kUniformMediumViewport, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glProgramUniform4i(p, kUniformMediumRegion, region.x, region.y, region.width, region.height);

    std::array<glm::vec4, kMaxVolumes> medium{}, origin{}, axis{}, color{};
    std::array<glm::vec4, kMediumPointLights> point_position{}, point_color{};
    std::array<float, kMediumPointLights> point_g{};
    int points = 0;
    for (std::size_t v = 0; v < volumes.size(); ++v) {
        const MediumVolume& vol = volumes[v];
        const MediumLight& light = vol.light;
        const bool beam = light.kind == MediumLight::Kind::Beam;
        medium[v] = glm::vec4(vol.absorbs ? 1.0f : 0.0f, float(vol.albedo), beam ? 1.0f : 0.0f, float(light.phase_g));
        if (beam) {
            origin[v] = glm::vec4(vec3f(light.origin - camera.eye), float(light.apex_distance));
            axis[v] = glm::vec4(vec3f(glm::normalize(light.axis)), float(light.strength_per_scalar));
            color[v] = glm::vec4(vec3f(light.color), 0.0f);
        } else if (light.kind == MediumLight::Kind::Point && points < kMediumPointLights) {
            point_position[points] = glm::vec4(vec3f(light.origin - camera.eye), float(light.core_radius));
            point_color[points] = glm::vec4(vec3f(light.color), float(light.radius));
            point_g[points] = float(light.phase_g);
            ++points;
        }
    }
    glProgramUniform4fv(p, kUniformMediumTable, kMaxVolumes, glm::value_ptr(table_params[0]));
    glProgramUniform4fv(p, kUniformMediumMedium, kMaxVolumes, glm::value_ptr(medium[0]));
    glProgramUniform4fv(p, kUniformMediumBeamOrigin, kMaxVolumes, glm::value_ptr(origin[0]));
    glProgramUniform4fv(p, kUniformMediumBeamAxis, kMaxVolumes, glm::value_ptr(axis[0]));
    glProgramUniform4fv(p, kUniformMediumBeamColor, kMaxVolumes, glm::value_ptr(color[0]));
    glProgramUniform1i(p, kUniformPointCount, points);
    glProgramUniform4fv(p, kUniformPointPosition, kMediumPointLights, glm::value_ptr(point_position[0]));
    glProgramUniform4fv(p, kUniformPointColor, kMediumPointLights, glm::value_ptr(point_color[0]));
    glProgramUniform1fv(p, kUniformPointG, kMediumPointLights, point_g.data());
    FX_GL_CHECK("medium resolve uniforms");
}

void MediumCompositor::Impl::reserve(std::size_t segments) {
    segments = std::min(segments, kMaxCapacity);
    const std::size_t bytes = kHeaderBytes + 4 * (heads + kSegmentWords * segments);
    if (bytes > lists_bytes) {
        lists = gl::make_buffer(GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
        lists_bytes = bytes;
    }
    capacity = std::min(kMaxCapacity, (lists_bytes - kHeaderBytes - 4 * heads) / (4 * kSegmentWords));
}

void MediumCompositor::Impl::clear_lists() {
    const GLuint zero = 0;
    glClearNamedBufferSubData(lists.id(), GL_R32UI, 0, GLsizeiptr(kHeaderBytes + 4 * heads), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    FX_GL_CHECK("medium: clear lists");
}

void MediumCompositor::Impl::timed_begin() {
    if (timing) glBeginQuery(GL_TIME_ELAPSED, timer.id());
}

void MediumCompositor::Impl::timed_end(double& part) {
    if (!timing) return;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(timer.id(), GL_QUERY_RESULT, &ns);
    stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + double(ns) * 1e-6;
    part = std::max(part, 0.0) + double(ns) * 1e-6;
}

void MediumCompositor::begin(const Camera& camera, const Viewport& viewport, const PixelRect& region,
                             const std::vector<MediumVolume>& volumes, int bulk_volume, bool timing) {
    Impl& m = *impl_;
    if (volumes.size() > std::size_t(kMaxVolumes))
        throw Error("medium: " + std::to_string(volumes.size()) + " volumes; at most " + std::to_string(kMaxVolumes));
    if (viewport.width <= 0 || viewport.height <= 0) throw Error("medium: empty viewport");
    if (region.empty() || region.x < 0 || region.y < 0 || region.x + region.width > viewport.width ||
        region.y + region.height > viewport.height)
        throw Error("medium: the region is empty or outside the viewport");
    if (bulk_volume < -1 || bulk_volume >= int(volumes.size())) throw Error("medium: the bulk volume is not one of the volumes");
    for (std::size_t v = 0; v < volumes.size(); ++v) {
        if (volumes[v].tf.points().empty())
            throw Error("medium: volume " + std::to_string(v) + " has a transfer function without points");
        if (volumes[v].tf.normalized())
            throw Error("medium: volume " + std::to_string(v) + "'s transfer function is normalized (rescale it to its scalars)");
    }
    const auto start = Clock::now();
    m.camera = camera;
    m.viewport = viewport;
    m.region = region;
    m.bulk = bulk_volume;
    m.volumes = volumes;
    m.appends.clear();
    m.timing = timing;
    m.stats = MediumStats{};
    m.stats.pixels = std::size_t(region.width) * std::size_t(region.height);
    m.heads = m.stats.pixels;
    gl::StateGuard guard;
    m.upload_tables();
    m.set_resolve_uniforms();
    m.begun = true;
    m.stats.cpu_ms += ms_since(start);
}

void MediumCompositor::Impl::ensure_mask() {
    if (mask_width == viewport.width && mask_height == viewport.height) return;
    mask = gl::make_texture_2d(GL_R8, viewport.width, viewport.height);
    mask_target = gl::Framebuffer::create();
    glNamedFramebufferTexture(mask_target.id(), GL_COLOR_ATTACHMENT0, mask.id(), 0);
    no_target = gl::Framebuffer::create();
    glNamedFramebufferParameteri(no_target.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, viewport.width);
    glNamedFramebufferParameteri(no_target.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, viewport.height);
    if (glCheckNamedFramebufferStatus(mask_target.id(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE ||
        glCheckNamedFramebufferStatus(no_target.id(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("medium: the mask framebuffers are incomplete");
    mask_width = viewport.width, mask_height = viewport.height;
    FX_GL_CHECK("medium mask");
}

// The mask: 0 in the region, then 1 over the screen rectangle of every point light's reach (its
// glow may light the bulk where no other volume is); the volumes' appends mark the rest.
void MediumCompositor::Impl::clear_mask() {
    const GLubyte zero = 0, one = 255;
    glClearTexSubImage(mask.id(), 0, region.x, region.y, 0, region.width, region.height, 1, GL_RED, GL_UNSIGNED_BYTE, &zero);
    for (const MediumVolume& v : volumes) {
        if (v.light.kind != MediumLight::Kind::Point) continue;
        const Bounds reach{v.light.origin - v.light.radius, v.light.origin + v.light.radius};
        const PixelRect r = screen_rect(reach, camera, viewport.width, viewport.height);
        const int x0 = std::max(r.x, region.x), y0 = std::max(r.y, region.y);
        const int x1 = std::min(r.x + r.width, region.x + region.width), y1 = std::min(r.y + r.height, region.y + region.height);
        if (x1 > x0 && y1 > y0) glClearTexSubImage(mask.id(), 0, x0, y0, 0, x1 - x0, y1 - y0, 1, GL_RED, GL_UNSIGNED_BYTE, &one);
    }
    FX_GL_CHECK("medium: clear mask");
}

void MediumCompositor::Impl::draw_append(const Append& a) {
    GlProjector& projector = renderer_projector(*a.renderer);
    ProgramVariants& variants = append_programs[projector.all_tetrahedra() ? 1 : 0];
    if (!variants.plain) { // linked on first use (once per context: the cache shares them)
        gl::Defines defines = projector.mesh_defines();
        variants.plain = &program_cache->program(projector_shader_library(), {"cells.vert", "medium_append.frag"}, defines);
        variants.with_scene_depth = &program_cache->program(projector_shader_library(),
                                                            {"cells.vert", "medium_append.frag"}, defines.set("SCENE_DEPTH"));
    }
    const gl::Program& program = variants(a.scene_depth != 0);
    const GLuint p = program.id();
    projector.prepare_draw(a.local_camera, viewport);
    projector.bind_mesh();
    // Drawn into the mask's target: the viewport's size at the origin; the scene depth's texel
    // for pixel (i, j) is (viewport.x + i, viewport.y + j).
    projector.set_view_uniforms(program, a.local_camera, viewport);
    projector.set_scene_depth_uniforms(program, a.local_camera, viewport, a.scene_depth);
    GlProjector::bind_scene_depth(a.scene_depth);
    glProgramUniform4i(p, kUniformMediumRegion, region.x, region.y, region.width, region.height);
    glProgramUniform1ui(p, kUniformMediumVolume, GLuint(a.volume));
    glProgramUniform1ui(p, kUniformMediumCapacity, GLuint(capacity));
    glProgramUniform1i(p, kUniformMediumMaskMode, int(a.volume) == bulk ? 1 : 0);
    glUseProgram(p);
    projector.draw_slots(0, projector.mesh().cell_count());
    FX_GL_CHECK("medium append");
}

// Every append into the cleared lists: the other volumes first, marking the mask, then the bulk
// volume inside it.
void MediumCompositor::Impl::draw_appends() {
    clear_lists();
    clear_mask();
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each fragment is a ray's exit from its cell
    glEnable(GL_SCISSOR_TEST);
    glScissor(region.x, region.y, region.width, region.height);
    glViewportIndexedf(0, 0.0f, 0.0f, float(viewport.width), float(viewport.height));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kListsBinding, lists.id());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, mask_target.id());
    for (const Append& a : appends)
        if (int(a.volume) != bulk) draw_append(a);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, no_target.id());
    glBindTextureUnit(kMaskUnit, mask.id());
    glBindSampler(kMaskUnit, 0);
    for (const Append& a : appends)
        if (int(a.volume) == bulk) draw_append(a);
    glBindTextureUnit(kMaskUnit, 0);
}

void MediumCompositor::append(CellRenderer& renderer, const Camera& local_camera, std::size_t volume, unsigned scene_depth) {
    Impl& m = *impl_;
    if (!m.begun) throw Error("medium: append() before begin()");
    if (volume >= m.volumes.size())
        throw Error("medium: volume " + std::to_string(volume) + " of " + std::to_string(m.volumes.size()));
    m.appends.push_back({&renderer, local_camera, volume, scene_depth});
    ++m.stats.volumes;
}

MediumStats MediumCompositor::resolve(unsigned behind_texture) {
    Impl& m = *impl_;
    if (!m.begun) throw Error("medium: resolve() before begin()");
    const auto start = Clock::now();
    gl::StateGuard guard;
    GLint host = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host);
    gl::StateGuard::set_render_defaults();
    m.ensure_mask();
    m.reserve(std::max(m.wanted, std::max<std::size_t>(4 * m.heads, 1 << 16)));
    // The pool must hold every segment: read the count back, and append again with a larger
    // pool if it overflowed (a few times at most: each round holds all that was counted).
    for (;;) {
        m.timed_begin();
        m.draw_appends();
        m.timed_end(m.stats.append_gpu_ms);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        GLuint count = 0;
        glGetNamedBufferSubData(m.lists.id(), 0, sizeof count, &count);
        m.stats.segments = count;
        if (count <= m.capacity) break;
        if (m.capacity >= kMaxCapacity)
            throw Error("medium: " + std::to_string(count) + " segments in the region exceed the pool's limit of " +
                        std::to_string(kMaxCapacity));
        m.wanted = std::size_t(count) + count / 4;
        m.reserve(m.wanted);
        ++m.stats.redraws;
        gl::StateGuard::set_render_defaults();
    }
    m.stats.capacity = m.capacity;
    m.stats.gpu_bytes = gpu_bytes();

    gl::StateGuard::set_render_defaults();
    m.timed_begin();
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(host));
    glEnable(GL_SCISSOR_TEST);
    glScissor(m.viewport.x + m.region.x, m.viewport.y + m.region.y, m.region.width, m.region.height);
    glViewportIndexedf(0, float(m.viewport.x), float(m.viewport.y), float(m.viewport.width), float(m.viewport.height));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kListsBinding, m.lists.id());
    glBindTextureUnit(kTablesUnit, m.tables.id());
    glBindSampler(kTablesUnit, 0);
    glBindTextureUnit(kMaskUnit, m.mask.id());
    glBindSampler(kMaskUnit, 0);
    glBindTextureUnit(kBehindUnit, behind_texture);
    glBindSampler(kBehindUnit, 0);
    glProgramUniform4i(m.resolve_program.id(), kUniformMediumRegion, m.region.x, m.region.y, m.region.width, m.region.height);
    glProgramUniform1i(m.resolve_program.id(), kUniformMediumBulk, m.bulk);
    glUseProgram(m.resolve_program.id());
    glBindVertexArray(m.vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    FX_GL_CHECK("medium resolve");
    m.timed_end(m.stats.resolve_gpu_ms);
    m.begun = false;
    m.stats.cpu_ms += ms_since(start);
    return m.stats;
}

PixelRect screen_rect(const Bounds& bounds, const Camera& camera, int width, int height) {
    if (bounds.empty() || width <= 0 || height <= 0) return {};
    // Relative to the eye, so that a box far from the world's origin projects as precisely.
    const Camera relative = camera_in_frame(camera, glm::translate(glm::dmat4(1.0), camera.eye));
    const glm::dmat4 vp = relative.projection_matrix(double(width) / double(height)) * relative.view_matrix();
    double lo_x = HUGE_VAL, lo_y = HUGE_VAL, hi_x = -HUGE_VAL, hi_y = -HUGE_VAL;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec4 c = vp * glm::dvec4(bounds.corner(k) - camera.eye, 1.0);
        // A corner at or behind the near plane: the box's projection is unbounded, take the view.
        if (!(c.w >= camera.near_distance) && !camera.orthographic()) return {0, 0, width, height};
        lo_x = std::min(lo_x, c.x / c.w), hi_x = std::max(hi_x, c.x / c.w);
        lo_y = std::min(lo_y, c.y / c.w), hi_y = std::max(hi_y, c.y / c.w);
    }
    const double x0 = std::floor((lo_x + 1.0) * 0.5 * width) - 1.0, x1 = std::ceil((hi_x + 1.0) * 0.5 * width) + 1.0;
    const double y0 = std::floor((lo_y + 1.0) * 0.5 * height) - 1.0, y1 = std::ceil((hi_y + 1.0) * 0.5 * height) + 1.0;
    const int ix0 = int(std::clamp(x0, 0.0, double(width))), ix1 = int(std::clamp(x1, 0.0, double(width)));
    const int iy0 = int(std::clamp(y0, 0.0, double(height))), iy1 = int(std::clamp(y1, 0.0, double(height)));
    if (ix1 <= ix0 || iy1 <= iy0) return {};
    return {ix0, iy0, ix1 - ix0, iy1 - iy0};
}

} // namespace cellfx::fx
