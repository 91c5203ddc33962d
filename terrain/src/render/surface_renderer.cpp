// The terrain surface: height-coloured, sun-lit, depth-writing (shaders/terrain_surface.*).
#include "terrain/surface_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/state_guard.hpp"
#include "render/terrain_shaders.hpp"

namespace cellfx::terrain {

namespace {

enum Uniform : GLint {
    kViewProjection = 0,
    kFieldOrigin = 1,
    kTexel = 2,
    kHeightRange = 3,
    kSun = 4,
    kAmbient = 5,
    kStops = 6,
    kRamp = 8,
};
constexpr int kMaxStops = 8;

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
    fx::gl::Buffer vertices, indices;
    std::size_t vertex_capacity = 0, index_capacity = 0; // bytes
    std::vector<glm::vec4> vertex_data;
    std::vector<std::uint32_t> index_data;
};

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
    return std::size_t(impl_->size) * std::size_t(impl_->size) * 8 + impl_->vertex_capacity + impl_->index_capacity;
}

SurfaceStats SurfaceRenderer::draw(const LodMesh& mesh, const fx::Camera& camera, const fx::Viewport& viewport,
                                   const SurfaceStyle& style) {
    if (viewport.width <= 0 || viewport.height <= 0) throw fx::Error("terrain surface: empty viewport");
    if (style.ramp.empty() || style.ramp.size() > std::size_t(kMaxStops))
        throw fx::Error("terrain surface: the colour ramp needs 1 to 8 stops");
    const auto start = std::chrono::steady_clock::now();
    Impl& m = *impl_;
    SurfaceStats stats;
    stats.triangles = mesh.triangles.size();
    if (mesh.triangles.empty()) return stats;

    m.vertex_data.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) m.vertex_data[v] = glm::vec4(glm::vec3(mesh.positions[v] - m.origin), 0.0f);
    m.index_data.resize(mesh.triangles.size() * 3);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) m.index_data[3 * t + k] = mesh.triangles[t][k];
    auto upload = [](fx::gl::Buffer& buffer, std::size_t& capacity, const void* data, std::size_t bytes) {
        if (bytes > capacity) {
            capacity = std::max(bytes, capacity * 3 / 2);
            buffer = fx::gl::make_buffer(GLsizeiptr(capacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
        }
        glNamedBufferSubData(buffer.id(), 0, GLsizeiptr(bytes), data);
    };
    upload(m.vertices, m.vertex_capacity, m.vertex_data.data(), m.vertex_data.size() * sizeof(glm::vec4));
    upload(m.indices, m.index_capacity, m.index_data.data(), m.index_data.size() * sizeof(std::uint32_t));
    glVertexArrayElementBuffer(m.vao.id(), m.indices.id());

    // View in the relative frame: translate the camera instead of the (large) coordinates.
    fx::Camera relative = camera;
    relative.eye -= m.origin;
    relative.target -= m.origin;
    const double aspect = double(viewport.width) / double(viewport.height);
    const glm::mat4 vp(relative.projection_matrix(aspect) * relative.view_matrix());
    const GLuint p = m.program.id();
    glProgramUniformMatrix4fv(p, kViewProjection, 1, GL_FALSE, glm::value_ptr(vp));
    glProgramUniform2f(p, kFieldOrigin, float(m.field_x0 - m.origin.x), float(m.field_y0 - m.origin.y));
    glProgramUniform2f(p, kTexel, float(1.0 / m.spacing), float(1.0 / m.size));
    const float range = std::max(m.highest - m.lowest, 1e-12f);
    glProgramUniform2f(p, kHeightRange, float(m.lowest - m.origin.z), 1.0f / range);
    const glm::vec3 sun(glm::normalize(style.sun_direction));
    glProgramUniform3fv(p, kSun, 1, glm::value_ptr(sun));
    glProgramUniform1f(p, kAmbient, float(style.ambient));
    glProgramUniform1i(p, kStops, GLint(style.ramp.size()));
    for (std::size_t k = 0; k < style.ramp.size(); ++k) {
        const auto& [f, c] = style.ramp[k];
        glProgramUniform4f(p, kRamp + GLint(k), float(f), float(c.r), float(c.g), float(c.b));
    }

    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glUseProgram(p);
        glBindVertexArray(m.vao.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m.vertices.id());
        glBindTextureUnit(0, m.gradients.id());
        glBindSampler(0, m.sampler.id());
        glDrawElements(GL_TRIANGLES, GLsizei(m.index_data.size()), GL_UNSIGNED_INT, nullptr);
        FX_GL_CHECK("terrain surface draw");
    }
    stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

} // namespace cellfx::terrain
