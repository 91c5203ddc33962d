// cellfx samples — GL pieces the samples draw themselves (not cellfx): a window-like offscreen
// framebuffer, the frame-stats text, the boxes a sample puts in its world, and the shader
// library of their embedded shaders (shaders/sample_*.{vert,frag}). Each draw saves and
// restores the GL state it changes (fx::gl::StateGuard), so they can sit anywhere in a frame.
#pragma once

#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "gl/gl_object.hpp"
#include "gl/shader_library.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

const fx::gl::ShaderLibrary& sample_shaders();

// Lines of text at the top left of the bound draw framebuffer's viewport, on a translucent
// panel, with stb_easy_font (Debian's libstb-dev): about 6 × 12 pixels per character at scale 1.
// The window's formats without a window (--headless, the bench, tests): an RGBA8 colour and a
// DEPTH24_STENCIL8 renderbuffer. Throws fx::Error if the framebuffer is incomplete.
class OffscreenFramebuffer {
public:
    OffscreenFramebuffer(int width, int height);
    unsigned id() const { return fb_.id(); }

private:
    fx::gl::Framebuffer fb_;
    fx::gl::Renderbuffer color_, depth_;
};

class TextOverlay {
public:
    TextOverlay(); // context current: builds the program and buffers
    // Draws over the viewport (0, 0, width, height) of the bound draw framebuffer.
    void draw(const std::vector<std::string>& lines, int width, int height, float scale = 1.0f);
    // The pixel rectangle the last draw covered (x0, y0 from the top left, exclusive x1, y1).
    int panel_x1() const { return panel_x1_; }
    int panel_y1() const { return panel_y1_; }

private:
    fx::gl::Program program_;
    fx::gl::VertexArray vao_;
    fx::gl::Buffer vertices_, indices_;
    std::size_t vertex_capacity_ = 0, quad_capacity_ = 0;
    int panel_x1_ = 0, panel_y1_ = 0;
};

// Shaded boxes (a vehicle, a tower): depth-tested and depth-writing, into the bound draw
// framebuffer with the camera's projection for a width × height viewport.
class BoxRenderer {
public:
    BoxRenderer();
    // `world_from_box` maps the unit cube [-0.5, 0.5]^3 into the world (scale included).
    void draw(const fx::Camera& camera, int width, int height, const glm::dmat4& world_from_box, const glm::vec3& color,
              const glm::dvec3& light_direction, float ambient);

private:
    fx::gl::Program program_;
    fx::gl::VertexArray vao_;
    fx::gl::Buffer vertices_;
};

} // namespace cellfx_samples
