// The samples' own GL drawing: the offscreen framebuffer, the frame-stats text (stb_easy_font quads) and shaded boxes.
#include "sample_gl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "fx/error.hpp"
#include "cellfx_names.hpp"
#include "gl/state_guard.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace cellfx::fx::gl {
// Generated from the shader list in samples/CMakeLists.txt (build tree: sample_embedded_shaders.cpp).
const EmbeddedShader* sample_embedded_shaders(std::size_t& count);
} // namespace cellfx::fx::gl

namespace cellfx_samples {

OffscreenFramebuffer::OffscreenFramebuffer(int width, int height)
    : fb_(fx::gl::Framebuffer::create()), color_(fx::gl::Renderbuffer::create()), depth_(fx::gl::Renderbuffer::create()) {
    glNamedRenderbufferStorage(color_.id(), GL_RGBA8, width, height);
    glNamedRenderbufferStorage(depth_.id(), GL_DEPTH24_STENCIL8, width, height);
    glNamedFramebufferRenderbuffer(fb_.id(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_.id());
    glNamedFramebufferRenderbuffer(fb_.id(), GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_.id());
    if (glCheckNamedFramebufferStatus(fb_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw fx::Error("headless: the offscreen framebuffer is incomplete");
}

const fx::gl::ShaderLibrary& sample_shaders() {
    static const fx::gl::ShaderLibrary library = [] {
        fx::gl::ShaderLibrary lib;
        std::size_t count = 0;
        const fx::gl::EmbeddedShader* shaders = fx::gl::sample_embedded_shaders(count);
        for (std::size_t k = 0; k < count; ++k) lib.add(shaders[k].name, shaders[k].text, shaders[k].path);
        return lib;
    }();
    return library;
}

namespace {

// stb_easy_font's vertex: x, y, z floats and an RGBA8 colour (16 bytes).
struct TextVertex {
    float x, y, z;
    unsigned char rgba[4];
};
static_assert(sizeof(TextVertex) == 16, "stb_easy_font writes 16-byte vertices");

void add_quad(std::vector<TextVertex>& v, float x0, float y0, float x1, float y1, const std::array<unsigned char, 4>& c) {
    const float xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
    for (int k = 0; k < 4; ++k) v.push_back({xs[k], ys[k], 0.0f, {c[0], c[1], c[2], c[3]}});
}

} // namespace

TextOverlay::TextOverlay() {
    const fx::gl::StateGuard guard;
    program_ = sample_shaders().link({"sample_text.vert", "sample_text.frag"});
    vao_ = fx::gl::VertexArray::create();
    glEnableVertexArrayAttrib(vao_.id(), 0);
    glVertexArrayAttribFormat(vao_.id(), 0, 2, GL_FLOAT, GL_FALSE, offsetof(TextVertex, x));
    glVertexArrayAttribBinding(vao_.id(), 0, 0);
    glEnableVertexArrayAttrib(vao_.id(), 1);
    glVertexArrayAttribFormat(vao_.id(), 1, 4, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(TextVertex, rgba));
    glVertexArrayAttribBinding(vao_.id(), 1, 0);
    FX_GL_CHECK("text overlay set-up");
}

void TextOverlay::draw(const std::vector<std::string>& lines, int width, int height, float scale) {
    if (lines.empty() || width <= 0 || height <= 0) return;
    // Layout in unscaled font pixels: 4 px margin, one line every 12 px.
    constexpr float kMargin = 4.0f, kLine = 12.0f;
    std::vector<TextVertex> glyphs;
    float text_width = 0.0f;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        std::vector<char> text(lines[i].begin(), lines[i].end());
        text.push_back('\0');
        text_width = std::max(text_width, float(stb_easy_font_width(text.data())));
        std::vector<TextVertex> buffer(std::max<std::size_t>(64, text.size() * 60)); // ≤ ~60 vertices per character
        unsigned char white[4] = {235, 240, 245, 255};
        const int quads = stb_easy_font_print(kMargin, kMargin + kLine * float(i), text.data(), white, buffer.data(),
                                              int(buffer.size() * sizeof(TextVertex)));
        glyphs.insert(glyphs.end(), buffer.begin(), buffer.begin() + 4 * quads);
    }
    std::vector<TextVertex> vertices;
    add_quad(vertices, 0.0f, 0.0f, 2.0f * kMargin + text_width, 2.0f * kMargin + kLine * float(lines.size()) - 2.0f,
             {0, 0, 0, 150});
    panel_x1_ = int(std::ceil(vertices[1].x * scale)), panel_y1_ = int(std::ceil(vertices[2].y * scale));
    vertices.insert(vertices.end(), glyphs.begin(), glyphs.end());
    const std::size_t quads = vertices.size() / 4;

    const fx::gl::StateGuard guard;
    fx::gl::StateGuard::set_render_defaults();
    if (vertices.size() > vertex_capacity_) {
        vertex_capacity_ = std::max(vertices.size(), 2 * vertex_capacity_);
        vertices_ = fx::gl::Buffer::create();
        glNamedBufferStorage(vertices_.id(), GLsizeiptr(vertex_capacity_ * sizeof(TextVertex)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, sizeof(TextVertex));
    }
    if (quads > quad_capacity_) {
        quad_capacity_ = std::max(quads, 2 * quad_capacity_);
        std::vector<GLuint> index(6 * quad_capacity_);
        for (std::size_t q = 0; q < quad_capacity_; ++q) {
            const GLuint b = GLuint(4 * q);
            const GLuint tri[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
            std::copy(tri, tri + 6, index.begin() + std::ptrdiff_t(6 * q));
        }
        indices_ = fx::gl::Buffer::create();
        glNamedBufferStorage(indices_.id(), GLsizeiptr(index.size() * sizeof(GLuint)), index.data(), 0);
        glVertexArrayElementBuffer(vao_.id(), indices_.id());
    }
    glNamedBufferSubData(vertices_.id(), 0, GLsizeiptr(vertices.size() * sizeof(TextVertex)), vertices.data());
    glViewport(0, 0, width, height);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE); // the frame's alpha stays
    glBlendEquation(GL_FUNC_ADD);
    glUseProgram(program_.id());
    glUniform2f(0, float(width), float(height));
    glUniform2f(1, 0.0f, 0.0f);
    glUniform1f(2, scale);
    glBindVertexArray(vao_.id());
    glDrawElements(GL_TRIANGLES, GLsizei(6 * quads), GL_UNSIGNED_INT, nullptr);
    FX_GL_CHECK("text overlay draw");
}

namespace {

// The unit cube's 36 vertices (position, normal), outward faces counter-clockwise.
std::vector<float> cube_vertices() {
    std::vector<float> v;
    for (int axis = 0; axis < 3; ++axis)
        for (int sign = -1; sign <= 1; sign += 2) {
            glm::vec3 n(0.0f);
            n[axis] = float(sign);
            const glm::vec3 u = glm::vec3(n.y, n.z, n.x), w = glm::cross(n, u); // u × w = n
            const glm::vec3 c = 0.5f * n;
            const glm::vec3 corners[4] = {c - 0.5f * u - 0.5f * w, c + 0.5f * u - 0.5f * w, c + 0.5f * u + 0.5f * w,
                                          c - 0.5f * u + 0.5f * w};
            for (int k : {0, 1, 2, 0, 2, 3}) {
                v.insert(v.end(), {corners[k].x, corners[k].y, corners[k].z, n.x, n.y, n.z});
            }
        }
    return v;
}

} // namespace

BoxRenderer::BoxRenderer() {
    const fx::gl::StateGuard guard;
    program_ = sample_shaders().link({"sample_props.vert", "sample_props.frag"});
    const std::vector<float> v = cube_vertices();
    vertices_ = fx::gl::Buffer::create();
    glNamedBufferStorage(vertices_.id(), GLsizeiptr(v.size() * sizeof(float)), v.data(), 0);
    vao_ = fx::gl::VertexArray::create();
    for (GLuint a = 0; a < 2; ++a) {
        glEnableVertexArrayAttrib(vao_.id(), a);
        glVertexArrayAttribFormat(vao_.id(), a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
        glVertexArrayAttribBinding(vao_.id(), a, 0);
    }
    glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, 6 * sizeof(float));
    FX_GL_CHECK("box renderer set-up");
}

void BoxRenderer::draw(const fx::Camera& camera, int width, int height, const glm::dmat4& world_from_box,
                       const glm::vec3& color, const glm::dvec3& light_direction, float ambient) {
    const fx::gl::StateGuard guard;
    fx::gl::StateGuard::set_render_defaults();
    // Eye-relative matrices in double, then float: boxes stay steady far from the origin.
    const glm::dmat4 clip = camera.projection_matrix(double(width) / double(height)) * camera.view_matrix() * world_from_box;
    const glm::mat4 clip_f(clip);
    const glm::mat3 normal_f(glm::transpose(glm::inverse(glm::dmat3(world_from_box))));
    const glm::vec3 light(glm::normalize(light_direction));
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glUseProgram(program_.id());
    glUniformMatrix4fv(0, 1, GL_FALSE, &clip_f[0][0]);
    glUniformMatrix3fv(1, 1, GL_FALSE, &normal_f[0][0]);
    glUniform3f(2, color.r, color.g, color.b);
    glUniform3f(3, light.x, light.y, light.z);
    glUniform1f(4, ambient);
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 36);
    FX_GL_CHECK("box draw");
}

} // namespace cellfx_samples
