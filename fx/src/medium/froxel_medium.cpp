// Based on: Wronski 2014 and Hillaire 2015 (froxel volumetric fog), with exact per-cell segment
// integrals injected. Shaders: froxel_grid.glsl, froxel_inject.frag (with the projector's
// cells.vert), froxel_integrate.comp, froxel_apply.frag, froxel_emission.frag, medium_lights.glsl.
#include "medium/froxel_medium.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "fx/effect.hpp" // camera_in_frame
#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/program_cache.hpp"
#include "gl/shader_library.hpp"
#include "gl/state_guard.hpp"
#include "projector/gl_interface.hpp"
#include "render/projector_access.hpp"

namespace cellfx::fx {
namespace {

// Uniform locations are the interface table's (projector/gl_interface.hpp). The six ray uniforms
// from kUniformFroxelRayOrigin: origin, its x and y steps, direction, its x and y steps (ndc).
static_assert(cellfx::fx::kUniformFroxelRayDirectionY == kUniformFroxelRayOrigin + 5, "the six ray uniforms in a row");
static_assert(cellfx::fx::FroxelMedium::kMaxPointLights == cellfx::fx::kMediumPointLights, "medium_lights.glsl's size");
constexpr GLuint kInjectionBinding = 4;
constexpr GLuint kIntegratedUnit = 0, kScatteringImage = 1;       // integrate: image units
constexpr GLuint kApplyGridUnit = 0, kApplyDepthUnit = 1;          // apply: texture units
constexpr GLuint kEmissionGridUnit = 1, kEmissionScatteringUnit = 2; // emission: texture units (clear of the projector's)
constexpr int kWords = 5;                                          // per froxel (froxel_grid.glsl)

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

gl::Texture make_texture_3d(GLenum format, glm::ivec3 size) {
    gl::Texture texture = gl::Texture::create(GL_TEXTURE_3D);
    glTextureStorage3D(texture.id(), 1, format, size.x, size.y, size.z);
    glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
        glTextureParameteri(texture.id(), wrap, GL_CLAMP_TO_EDGE);
    FX_GL_CHECK("froxel grid texture");
    return texture;
}

std::size_t froxel_count(glm::ivec3 g) { return std::size_t(g.x) * std::size_t(g.y) * std::size_t(g.z); }

glm::vec3 vec3f(const glm::dvec3& v) { return glm::vec3(v); }

} // namespace

glm::ivec3 FroxelMedium::grid_size(int width, int height) {
    if (width <= 0 || height <= 0) return glm::ivec3(0);
    const int tile = std::max({kTilePixels, (width + kMaxTilesAcross - 1) / kMaxTilesAcross,
                               (height + kMaxTilesUp - 1) / kMaxTilesUp});
    return {(width + tile - 1) / tile, (height + tile - 1) / tile, kSlices};
}

std::size_t FroxelMedium::gpu_bytes_for(int width, int height) {
    // Injection: 5 floats; integrated: RGBA16F; scattering: R16F.
    return froxel_count(grid_size(width, height)) * (kWords * 4 + 8 + 2);
}

struct FroxelMedium::Impl {
    std::shared_ptr<gl::ProgramCache> program_cache;
    std::array<const gl::Program*, 2> inject_programs{};       // per mesh kind (index: all tetrahedra)
    std::array<ProgramVariants, 2> emission_programs;          // per mesh kind, with and without scene depth
    gl::Program integrate_program, apply_program;
    gl::VertexArray vao;
    gl::Buffer injection;
    gl::Texture integrated, scattering;
    gl::Framebuffer no_target; // the injection's: the grid's size, nothing attached
    glm::ivec3 allocated{0};
    gl::Query timer;

    // The frame begun.
    bool begun = false, integrated_this_frame = false, timing = false;
    Camera camera; // world, with the begin() view's projection made explicit
    int width = 0, height = 0;
    glm::ivec3 grid{0};
    glm::vec2 slicing{0.0f};
    std::vector<MediumVolume> volumes;
    MediumStats stats;

    void allocate(glm::ivec3 size);
    void set_grid_uniforms(GLuint program) const;
    void timed_begin() const {
        if (timing) glBeginQuery(GL_TIME_ELAPSED, timer.id());
    }
    void timed_end(double& part) {
        if (!timing) return;
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(timer.id(), GL_QUERY_RESULT, &ns);
        stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + double(ns) * 1e-6;
        part = std::max(part, 0.0) + double(ns) * 1e-6;
    }
    const MediumVolume& volume(std::size_t v, const char* who) const {
        if (!begun) throw Error(std::string("froxel medium: ") + who + " before begin()");
        if (v >= volumes.size())
            throw Error("froxel medium: " + std::string(who) + ": volume " + std::to_string(v) + " of " + std::to_string(volumes.size()));
        return volumes[v];
    }
};

FroxelMedium::FroxelMedium() : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    const gl::ShaderLibrary& lib = projector_shader_library(); // the built-in shaders and the interface table
    m.program_cache = gl::ProgramCache::for_current_context();
    m.integrate_program = lib.link({"froxel_integrate.comp"});
    m.apply_program = lib.link({"fullscreen.vert", "froxel_apply.frag"});
    m.vao = gl::VertexArray::create();
    m.timer = gl::Query::create(GL_TIME_ELAPSED);
    FX_GL_CHECK("froxel medium set-up");
}

FroxelMedium::~FroxelMedium() = default;
FroxelMedium::FroxelMedium(FroxelMedium&&) noexcept = default;
FroxelMedium& FroxelMedium::operator=(FroxelMedium&&) noexcept = default;

std::size_t FroxelMedium::gpu_bytes() const { return froxel_count(impl_->allocated) * (kWords * 4 + 8 + 2); }
const MediumStats& FroxelMedium::stats() const { return impl_->stats; }

void FroxelMedium::Impl::allocate(glm::ivec3 size) {
    if (size == allocated) return;
    const std::size_t bytes = froxel_count(size) * kWords * 4;
    injection = gl::make_buffer(GLsizeiptr(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
    integrated = make_texture_3d(GL_RGBA16F, size);
    scattering = make_texture_3d(GL_R16F, size);
    no_target = gl::Framebuffer::create();
    glNamedFramebufferParameteri(no_target.id(), GL_FRAMEBUFFER_DEFAULT_WIDTH, size.x);
    glNamedFramebufferParameteri(no_target.id(), GL_FRAMEBUFFER_DEFAULT_HEIGHT, size.y);
    if (glCheckNamedFramebufferStatus(no_target.id(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("froxel medium: the injection framebuffer is incomplete");
    allocated = size;
    FX_GL_CHECK("froxel grid");
}

void FroxelMedium::Impl::set_grid_uniforms(GLuint program) const {
    glProgramUniform3i(program, kUniformFroxelGrid, grid.x, grid.y, grid.z);
    glProgramUniform2f(program, kUniformFroxelSlicing, slicing.x, slicing.y);
}

void FroxelMedium::begin(const Camera& camera, int width, int height, double far_depth,
                         const std::vector<MediumVolume>& volumes, bool timing) {
    Impl& m = *impl_;
    if (width <= 0 || height <= 0) throw Error("froxel medium: empty view " + std::to_string(width) + "x" + std::to_string(height));
    if (!std::isfinite(far_depth) || !(far_depth > 0.0))
        throw Error("froxel medium: the volumes' far depth must be finite and positive, got " + std::to_string(far_depth));
    for (std::size_t v = 0; v < volumes.size(); ++v) {
        if (volumes[v].tf.points().empty())
            throw Error("froxel medium: volume " + std::to_string(v) + " has a transfer function without points");
        if (volumes[v].tf.normalized())
            throw Error("froxel medium: volume " + std::to_string(v) + "'s transfer function is normalized (rescale it to its scalars)");
    }
    const auto start = Clock::now();
    m.camera = camera;
    // The grid and the passes drawn at other sizes see the same view: the projection of this
    // view's aspect, whatever size they rasterise at.
    if (!m.camera.projection) m.camera.projection = camera.projection_matrix(double(width) / double(height));
    m.width = width, m.height = height;
    m.grid = grid_size(width, height);
    // Slices from the near plane to the volumes' far end; at least a factor 2 so that a volume
    // at the near plane still gets slices of finite depth.
    const double near = camera.near_distance, far = std::max(far_depth, 2.0 * near);
    m.slicing = glm::vec2(float(near), float(std::log(far / near) / kSlices));
    m.volumes = volumes;
    m.timing = timing;
    m.stats = MediumStats{};
    m.stats.method = MediumMethod::Froxel;
    m.stats.pixels = std::size_t(width) * std::size_t(height);
    m.stats.froxels = froxel_count(m.grid);
    gl::StateGuard guard;
    m.allocate(m.grid);
    m.stats.gpu_bytes = gpu_bytes();
    const GLuint zero = 0;
    glClearNamedBufferSubData(m.injection.id(), GL_R32UI, 0, GLsizeiptr(froxel_count(m.grid) * kWords * 4), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    FX_GL_CHECK("froxel medium: clear");
    m.begun = true;
    m.integrated_this_frame = false;
    m.stats.cpu_ms += ms_since(start);
}

void FroxelMedium::inject(CellRenderer& renderer, const glm::dmat4& world_from_local, std::size_t volume) {
    Impl& m = *impl_;
    const MediumVolume& v = m.volume(volume, "inject()");
    if (!v.absorbs) throw Error("froxel medium: inject(): volume " + std::to_string(volume) + " does not absorb (draw it with draw_emission)");
    if (m.integrated_this_frame) throw Error("froxel medium: inject() after integrate()");
    const auto start = Clock::now();
    gl::StateGuard guard;
    gl::StateGuard::set_render_defaults();
    GlProjector& projector = renderer_projector(renderer);
    const gl::Program*& program = m.inject_programs[projector.all_tetrahedra() ? 1 : 0];
    if (!program) // linked on first use (once per context: the cache shares it)
        program = &m.program_cache->program(projector_shader_library(), {"cells.vert", "froxel_inject.frag"},
                                             projector.mesh_defines());
    const GLuint p = program->id();
    const Camera local = camera_in_frame(m.camera, world_from_local);
    const Viewport grid_view{0, 0, m.grid.x, m.grid.y};
    projector.prepare_draw(local, grid_view);
    projector.bind_mesh();
    projector.set_view_uniforms(*program, local, grid_view);
    projector.set_scene_depth_uniforms(*program, local, grid_view, 0);
    m.set_grid_uniforms(p);
    glProgramUniform1f(p, kUniformFroxelAlbedo, float(v.albedo));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.no_target.id());
    glViewportIndexedf(0, 0.0f, 0.0f, float(m.grid.x), float(m.grid.y));
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each fragment is a tile ray's exit from its cell
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kInjectionBinding, m.injection.id());
    glUseProgram(p);
    m.timed_begin();
    projector.draw_slots(0, projector.mesh().cell_count());
    m.timed_end(m.stats.append_gpu_ms);
    FX_GL_CHECK("froxel medium: inject");
    ++m.stats.volumes;
    m.stats.cpu_ms += ms_since(start);
}

void FroxelMedium::integrate() {
    Impl& m = *impl_;
    if (!m.begun) throw Error("froxel medium: integrate() before begin()");
    const auto start = Clock::now();
    gl::StateGuard guard;
    const GLuint p = m.integrate_program.id();
    m.set_grid_uniforms(p);
    // The tile rays in the eye-relative world frame, linear in ndc as fragment_ray is in pixels:
    // the points of the near plane, back through the view's projection.
    const Camera relative = camera_in_frame(m.camera, glm::translate(glm::dmat4(1.0), m.camera.eye));
    const glm::dmat4 from_clip = glm::inverse(*m.camera.projection * relative.view_matrix());
    const auto near_point = [&](double x, double y) {
        const glm::dvec4 q = from_clip * glm::dvec4(x, y, -1.0, 1.0);
        return glm::dvec3(q) / q.w;
    };
    const glm::dvec3 forward = m.camera.forward();
    const glm::dvec3 p00 = near_point(0.0, 0.0), px = near_point(1.0, 0.0) - p00, py = near_point(0.0, 1.0) - p00;
    glm::dvec3 origin(0.0), origin_x(0.0), origin_y(0.0), direction = p00, direction_x = px, direction_y = py;
    if (m.camera.orthographic()) {
        origin = p00 - forward * glm::dot(p00, forward), origin_x = px, origin_y = py;
        direction = forward, direction_x = direction_y = glm::dvec3(0.0);
    }
    const glm::dvec3 rays[6] = {origin, origin_x, origin_y, direction, direction_x, direction_y};
    for (int i = 0; i < 6; ++i) glProgramUniform3fv(p, kUniformFroxelRayOrigin + i, 1, glm::value_ptr(vec3f(rays[i])));
    glProgramUniform3fv(p, kUniformFroxelViewForward, 1, glm::value_ptr(vec3f(forward)));
    glProgramUniform1i(p, kUniformFroxelOrtho, m.camera.orthographic() ? 1 : 0);
    // The point lights (a fire's glow) of every volume, eye-relative.
    std::array<glm::vec4, kMaxPointLights> position{}, color{};
    std::array<float, kMaxPointLights> g{};
    int points = 0;
    for (const MediumVolume& v : m.volumes) {
        const MediumLight& l = v.light;
        if (l.kind != MediumLight::Kind::Point || points == kMaxPointLights) continue;
        position[points] = glm::vec4(vec3f(l.origin - m.camera.eye), float(l.core_radius));
        color[points] = glm::vec4(vec3f(l.color), float(l.radius));
        g[points] = float(l.phase_g);
        ++points;
    }
    glProgramUniform1i(p, kUniformPointCount, points);
    glProgramUniform4fv(p, kUniformPointPosition, kMaxPointLights, glm::value_ptr(position[0]));
    glProgramUniform4fv(p, kUniformPointColor, kMaxPointLights, glm::value_ptr(color[0]));
    glProgramUniform1fv(p, kUniformPointG, kMaxPointLights, g.data());
    m.timed_begin();
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kInjectionBinding, m.injection.id());
    glBindImageTexture(kIntegratedUnit, m.integrated.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA16F);
    glBindImageTexture(kScatteringImage, m.scattering.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16F);
    glUseProgram(p);
    glDispatchCompute(GLuint((m.grid.x + 7) / 8), GLuint((m.grid.y + 7) / 8), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    m.timed_end(m.stats.resolve_gpu_ms);
    FX_GL_CHECK("froxel medium: integrate");
    m.integrated_this_frame = true;
    m.stats.cpu_ms += ms_since(start);
}

void FroxelMedium::apply(const Viewport& viewport, unsigned scene_depth, glm::ivec2 depth_origin) {
    Impl& m = *impl_;
    if (!m.integrated_this_frame) throw Error("froxel medium: apply() before integrate()");
    if (viewport.width <= 0 || viewport.height <= 0) throw Error("froxel medium: apply(): empty viewport");
    const auto start = Clock::now();
    gl::StateGuard guard;
    gl::StateGuard::set_render_defaults();
    const GLuint p = m.apply_program.id();
    m.set_grid_uniforms(p);
    glProgramUniform4f(p, kUniformFroxelApplyViewport, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glProgramUniform2i(p, kUniformFroxelApplyDepthOrigin, depth_origin.x, depth_origin.y);
    glProgramUniform3f(p, kUniformFroxelApplyDepth, float(m.camera.near_distance), float(m.camera.far_distance),
                       scene_depth == 0 ? 0.0f : m.camera.orthographic() ? 2.0f : 1.0f);
    glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glBindTextureUnit(kApplyGridUnit, m.integrated.id());
    glBindSampler(kApplyGridUnit, 0);
    glBindTextureUnit(kApplyDepthUnit, scene_depth);
    glBindSampler(kApplyDepthUnit, 0);
    glUseProgram(p);
    glBindVertexArray(m.vao.id());
    m.timed_begin();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    m.timed_end(m.stats.resolve_gpu_ms);
    FX_GL_CHECK("froxel medium: apply");
    m.stats.cpu_ms += ms_since(start);
}

void FroxelMedium::draw_emission(CellRenderer& renderer, const glm::dmat4& world_from_local, std::size_t volume,
                                 const Viewport& viewport, unsigned scene_depth) {
    Impl& m = *impl_;
    const MediumVolume& v = m.volume(volume, "draw_emission()");
    if (!m.integrated_this_frame) throw Error("froxel medium: draw_emission() before integrate()");
    if (viewport.width <= 0 || viewport.height <= 0) throw Error("froxel medium: draw_emission(): empty viewport");
    const auto start = Clock::now();
    gl::StateGuard guard;
    gl::StateGuard::set_render_defaults();
    GlProjector& projector = renderer_projector(renderer);
    ProgramVariants& variants = m.emission_programs[projector.all_tetrahedra() ? 1 : 0];
    if (!variants.plain) {
        gl::Defines defines = projector.mesh_defines();
        variants.plain = &m.program_cache->program(projector_shader_library(), {"cells.vert", "froxel_emission.frag"}, defines);
        variants.with_scene_depth = &m.program_cache->program(projector_shader_library(), {"cells.vert", "froxel_emission.frag"},
                                                              defines.set("SCENE_DEPTH"));
    }
    const gl::Program& program = variants(scene_depth != 0);
    const GLuint p = program.id();
    const Camera local = camera_in_frame(m.camera, world_from_local);
    projector.prepare_draw(local, viewport);
    projector.bind_mesh();
    // The rays of the viewport's pixels (the shader takes its origin off gl_FragCoord); the
    // scene depth's texel is the framebuffer's pixel.
    projector.set_view_uniforms(program, local, viewport);
    projector.set_scene_depth_uniforms(program, local, Viewport{0, 0, viewport.width, viewport.height}, scene_depth);
    GlProjector::bind_scene_depth(scene_depth);
    m.set_grid_uniforms(p);
    glProgramUniform4f(p, kUniformFroxelViewport, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    const MediumLight& l = v.light;
    if (l.kind == MediumLight::Kind::Beam) {
        // The beam in the projector's relative frame (the mesh's own frame, about its centre).
        const glm::dmat4 local_from_world = glm::inverse(world_from_local);
        const glm::dvec3 origin = glm::dvec3(local_from_world * glm::dvec4(l.origin, 1.0)) - projector.geometry().origin;
        const glm::dvec3 axis = glm::normalize(glm::dvec3(local_from_world * glm::dvec4(l.axis, 0.0)));
        glProgramUniform4f(p, kUniformFroxelBeam, 1.0f, float(l.phase_g), float(l.strength_per_scalar), float(l.apex_distance));
        glProgramUniform3fv(p, kUniformFroxelBeamOrigin, 1, glm::value_ptr(vec3f(origin)));
        glProgramUniform3fv(p, kUniformFroxelBeamAxis, 1, glm::value_ptr(vec3f(axis)));
        glProgramUniform3fv(p, kUniformFroxelBeamColor, 1, glm::value_ptr(vec3f(l.color)));
    } else {
        glProgramUniform4f(p, kUniformFroxelBeam, 0.0f, 0.0f, 0.0f, 0.0f);
    }
    glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT); // back faces only: each fragment is its ray's exit from the cell
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE, GL_ZERO, GL_ONE); // light adds, alpha stays
    glBindTextureUnit(kEmissionGridUnit, m.integrated.id());
    glBindSampler(kEmissionGridUnit, 0);
    glBindTextureUnit(kEmissionScatteringUnit, m.scattering.id());
    glBindSampler(kEmissionScatteringUnit, 0);
    glUseProgram(p);
    m.timed_begin();
    projector.draw_slots(0, projector.mesh().cell_count());
    m.timed_end(m.stats.resolve_gpu_ms);
    GlProjector::bind_scene_depth(0);
    FX_GL_CHECK("froxel medium: emission");
    ++m.stats.volumes;
    m.stats.cpu_ms += ms_since(start);
}

} // namespace cellfx::fx
