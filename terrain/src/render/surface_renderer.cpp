// The terrain surface: height-coloured, sun-lit, depth-writing (shaders/terrain_surface.*).
#include "terrain/surface_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/scatter_pass.hpp"
#include "gl/state_guard.hpp"
#include "render/terrain_interface.hpp"
#include "render/terrain_shaders.hpp"

namespace cellfx::terrain {

namespace {

constexpr std::uint32_t kFanIndices = 24; // a fan slot's 8 triangles (unused ones collapsed to its centre)

} // namespace

struct SurfaceRenderer::Impl {
    glm::dvec3 origin{0.0}; // relative frame: the field's centre at mid height
    int size = 0;
    double spacing = 1.0, field_x0 = 0.0, field_y0 = 0.0;
    float lowest = 0.0f, highest = 0.0f;
    fx::gl::Program program;
    fx::gl::Texture gradients;
    fx::gl::Sampler sampler;
    fx::gl::VertexArray vao;
    // A height per sample (relative frame) and the triangles as sample ids: by fan slot (24 a
    // slot) for a TerrainLod, listed for a LodMesh.
    fx::gl::GrowingBuffer heights, indices;
    std::vector<float> height_data;
    std::vector<std::uint32_t> index_data;
    std::size_t index_count = 0;
    fx::gl::ScatterPass height_scatter{1}, fan_scatter{kFanIndices};
    // The TerrainLod whose version the buffers hold (nullptr: a LodMesh's, or nothing yet).
    const TerrainLod* lod = nullptr;
    std::uint64_t lod_version = 0;

    float relative_height(float h) const { return float(double(h) - origin.z); }
    void write_fan(const ContinuousLod& l, std::size_t slot, std::uint32_t* out) const {
        const LodFan f = l.fan(slot);
        for (std::uint32_t k = 0; k < 8; ++k) {
            const bool used = k < f.count;
            out[3 * k] = f.center;
            out[3 * k + 1] = used ? f.ring[k] : f.center;
            out[3 * k + 2] = used ? f.ring[(k + 1) % f.count] : f.center;
        }
    }
    void upload_lod(const TerrainLod& lod, SurfaceStats& stats);
    SurfaceStats draw_indices(const fx::Camera& camera, const fx::Viewport& viewport, const SurfaceStyle& style,
                              SurfaceStats stats, std::chrono::steady_clock::time_point start);
};

void SurfaceRenderer::Impl::upload_lod(const TerrainLod& l, SurfaceStats& stats) {
    const ContinuousLod& c = l.lod();
    if (c.ground().size != size) throw fx::Error("terrain surface: the LOD is of another height field");
    const LodChanges& changes = c.changes();
    const std::size_t fans = c.fan_count();
    if (lod == &l && lod_version == l.version()) return;
    index_count = kFanIndices * fans;
    if (lod == &l && lod_version + 1 == l.version() && !changes.full) {
        // Only what the refinement changed: its vertices' heights and its fan slots.
        height_scatter.clear();
        height_scatter.reserve(9 * fans); // a fan touches at most 9 vertices: no allocation in a steady frame
        fan_scatter.reserve(fans);
        for (std::size_t k = 0; k < changes.vertices.size(); ++k) {
            const float h = relative_height(changes.vertex_heights[k]);
            std::memcpy(height_scatter.add(changes.vertices[k], 1), &h, 4);
        }
        fan_scatter.clear();
        for (std::uint32_t slot : changes.fans)
            if (slot < fans) write_fan(c, slot, fan_scatter.add(kFanIndices * slot, kFanIndices));
        indices.reserve(index_count * 4, indices.capacity());
        glVertexArrayElementBuffer(vao.id(), indices.id());
        height_scatter.run(heights.id());
        fan_scatter.run(indices.id());
        stats.vertices_uploaded = height_scatter.size();
        stats.fans_uploaded = fan_scatter.size();
    } else {
        const std::size_t samples = std::size_t(size) * std::size_t(size);
        height_data.resize(samples);
        for (std::size_t s = 0; s < samples; ++s) height_data[s] = relative_height(float(c.vertex_position(std::uint32_t(s)).z));
        index_data.resize(index_count);
        for (std::size_t slot = 0; slot < fans; ++slot) write_fan(c, slot, &index_data[kFanIndices * slot]);
        heights.upload(height_data.data(), samples * 4);
        indices.upload(index_data.data(), index_count * 4);
        glVertexArrayElementBuffer(vao.id(), indices.id());
        stats.vertices_uploaded = samples;
        stats.fans_uploaded = fans;
        stats.whole = true;
    }
    lod = &l;
    lod_version = l.version();
}

SurfaceRenderer::SurfaceRenderer(const HeightField& ground) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    if (ground.size < 2 || ground.heights.size() != std::size_t(ground.size) * std::size_t(ground.size))
        throw fx::Error("terrain surface: the height field is empty or inconsistent");
    m.size = ground.size;
    m.spacing = ground.spacing;
    m.lowest = ground.min_height();
    m.highest = ground.max_height();
    m.origin = glm::dvec3(ground.origin.x + 0.5 * ground.extent(), ground.origin.y + 0.5 * ground.extent(),
                          0.5 * (double(m.lowest) + m.highest));
    m.field_x0 = ground.origin.x;
    m.field_y0 = ground.origin.y;

    // Central differences (one-sided at the border) of the full-resolution field.
    const int n = ground.size;
    std::vector<glm::vec2> g(std::size_t(n) * std::size_t(n));
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, n - 1);
            const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, n - 1);
            g[std::size_t(j) * n + i] = {
                float((double(ground.at(i1, j)) - ground.at(i0, j)) / ((i1 - i0) * ground.spacing)),
                float((double(ground.at(i, j1)) - ground.at(i, j0)) / ((j1 - j0) * ground.spacing))};
        }
    }
    m.gradients = fx::gl::make_texture_2d(GL_RG32F, n, n);
    {
        fx::gl::StateGuard guard;
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
        glTextureSubImage2D(m.gradients.id(), 0, 0, 0, n, n, GL_RG, GL_FLOAT, g.data());
    }
    FX_GL_CHECK("terrain surface: gradients");
    m.sampler = fx::gl::Sampler::create();
    glSamplerParameteri(m.sampler.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(m.sampler.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(m.sampler.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(m.sampler.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    m.program = terrain_shaders().link({"terrain_surface.vert", "terrain_surface.frag"});
    m.vao = fx::gl::VertexArray::create();
}

SurfaceRenderer::~SurfaceRenderer() = default;
SurfaceRenderer::SurfaceRenderer(SurfaceRenderer&&) noexcept = default;
SurfaceRenderer& SurfaceRenderer::operator=(SurfaceRenderer&&) noexcept = default;

std::size_t SurfaceRenderer::gpu_bytes() const {
    return std::size_t(impl_->size) * std::size_t(impl_->size) * 8 + impl_->heights.capacity() + impl_->indices.capacity();
}

SurfaceStats SurfaceRenderer::draw(const TerrainLod& lod, const fx::Camera& camera, const fx::Viewport& viewport,
                                   const SurfaceStyle& style) {
    const auto start = std::chrono::steady_clock::now();
    SurfaceStats stats;
    stats.triangles = lod.lod().triangle_count();
    impl_->upload_lod(lod, stats);
    return impl_->draw_indices(camera, viewport, style, stats, start);
}

SurfaceStats SurfaceRenderer::draw(const LodMesh& mesh, const fx::Camera& camera, const fx::Viewport& viewport,
                                   const SurfaceStyle& style) {
    const auto start = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    SurfaceStats stats;
    stats.triangles = mesh.triangles.size();
    // The mesh's vertices into the per-sample heights, its triangles as sample ids.
    const std::size_t samples = std::size_t(m.size) * std::size_t(m.size);
    m.height_data.resize(samples, 0.0f);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        if (mesh.grid_index[v] >= samples) throw fx::Error("terrain surface: the mesh is of another height field");
        m.height_data[mesh.grid_index[v]] = m.relative_height(float(mesh.positions[v].z));
    }
    m.index_data.resize(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) m.index_data[3 * t + k] = mesh.grid_index[mesh.triangles[t][k]];
    m.heights.upload(m.height_data.data(), samples * 4);
    m.indices.upload(m.index_data.data(), m.index_data.size() * 4);
    glVertexArrayElementBuffer(m.vao.id(), m.indices.id());
    m.index_count = m.index_data.size();
    m.lod = nullptr;
    stats.vertices_uploaded = mesh.positions.size();
    stats.whole = true;
    return m.draw_indices(camera, viewport, style, stats, start);
}

SurfaceStats SurfaceRenderer::Impl::draw_indices(const fx::Camera& camera, const fx::Viewport& viewport,
                                                 const SurfaceStyle& style, SurfaceStats stats,
                                                 std::chrono::steady_clock::time_point start) {
    if (viewport.width <= 0 || viewport.height <= 0) throw fx::Error("terrain surface: empty viewport");
    if (style.ramp.empty() || style.ramp.size() > std::size_t(kSurfaceMaxStops))
        throw fx::Error("terrain surface: the colour ramp needs 1 to 8 stops");
    if (index_count == 0) return stats;

    // View in the relative frame: translate the camera instead of the (large) coordinates.
    fx::Camera relative = camera;
    relative.eye -= origin;
    relative.target -= origin;
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::mat4 vp(relative.projection_matrix(aspect) * relative.view_matrix());
    const GLuint p = program.id();
    glProgramUniformMatrix4fv(p, kUniformSurfaceViewProjection, 1, GL_FALSE, glm::value_ptr(vp));
    glProgramUniform2f(p, kUniformSurfaceFieldOrigin, float(field_x0 - origin.x), float(field_y0 - origin.y));
    glProgramUniform2f(p, kUniformSurfaceTexel, float(1.0 / spacing), float(1.0 / size));
    const float range = std::max(highest - lowest, 1e-12f);
    glProgramUniform2f(p, kUniformSurfaceHeightRange, float(lowest - origin.z), 1.0f / range);
    const glm::vec3 sun(glm::normalize(style.sun_direction));
    glProgramUniform3fv(p, kUniformSurfaceSun, 1, glm::value_ptr(sun));
    glProgramUniform1f(p, kUniformSurfaceAmbient, float(style.ambient));
    glProgramUniform1i(p, kUniformSurfaceStops, GLint(style.ramp.size()));
    for (std::size_t k = 0; k < style.ramp.size(); ++k) {
        const auto& [f, c] = style.ramp[k];
        glProgramUniform4f(p, kUniformSurfaceRamp + GLint(k), float(f), float(c.r), float(c.g), float(c.b));
    }
    glProgramUniform1i(p, kUniformSurfaceSize, size);
    glProgramUniform2f(p, kUniformSurfaceFirstSample, float(field_x0 - origin.x), float(field_y0 - origin.y));
    glProgramUniform1f(p, kUniformSurfaceSpacing, float(spacing));

    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glUseProgram(p);
        glBindVertexArray(vao.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, heights.id());
        glBindTextureUnit(0, gradients.id());
        glBindSampler(0, sampler.id());
        glDrawElements(GL_TRIANGLES, GLsizei(index_count), GL_UNSIGNED_INT, nullptr);
        FX_GL_CHECK("terrain surface draw");
    }
    stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

} // namespace cellfx::terrain
