#include "gl/render_target.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "gl/state_guard.hpp"

namespace cellfx::fx::gl {

GLenum internal_format(ColorFormat format) {
    switch (format) {
    case ColorFormat::RGBA8: return GL_RGBA8;
    case ColorFormat::RGBA16F: return GL_RGBA16F;
    case ColorFormat::RGBA32F: return GL_RGBA32F;
    }
    return GL_RGBA8;
}

const char* color_format_name(ColorFormat format) {
    switch (format) {
    case ColorFormat::RGBA8: return "RGBA8";
    case ColorFormat::RGBA16F: return "RGBA16F";
    case ColorFormat::RGBA32F: return "RGBA32F";
    }
    return "?";
}

RenderTarget RenderTarget::create(int width, int height, ColorFormat format, bool with_depth) {
    if (width <= 0 || height <= 0)
        throw Error("RenderTarget: bad size " + std::to_string(width) + "x" + std::to_string(height));
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    check_limit(Limit::ImagePixels, std::uint64_t(width) * std::uint64_t(height), "an offscreen " + size + " image");
    // What the driver can hold: past it the framebuffer is only "incomplete" (0x8CD6).
    GLint max_texture = 0, max_renderbuffer = 0, max_viewport[2] = {0, 0};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
    const GLint max_side = std::min({max_texture, max_renderbuffer, max_viewport[0], max_viewport[1]});
    if (max_side > 0 && (width > max_side || height > max_side)) {
        throw Error("an offscreen " + size + " image is larger than this OpenGL driver allows (" + std::to_string(max_side) +
                    " pixels a side, GL_MAX_TEXTURE_SIZE / GL_MAX_VIEWPORT_DIMS); use a smaller --size, or --path scanline");
    }
    RenderTarget target;
    target.width_ = width;
    target.height_ = height;
    target.format_ = format;
    target.framebuffer_ = Framebuffer::create();
    target.color_ = make_texture_2d(internal_format(format), width, height);
    glNamedFramebufferTexture(target.framebuffer_.id(), GL_COLOR_ATTACHMENT0, target.color_.id(), 0);
    FX_GL_CHECK("glNamedFramebufferTexture(GL_COLOR_ATTACHMENT0)");
    if (with_depth) {
        target.depth_ = make_texture_2d(GL_DEPTH_COMPONENT32F, width, height);
        glNamedFramebufferTexture(target.framebuffer_.id(), GL_DEPTH_ATTACHMENT, target.depth_.id(), 0);
        FX_GL_CHECK("glNamedFramebufferTexture(GL_DEPTH_ATTACHMENT)");
    }
    glNamedFramebufferDrawBuffer(target.framebuffer_.id(), GL_COLOR_ATTACHMENT0);
    glNamedFramebufferReadBuffer(target.framebuffer_.id(), GL_COLOR_ATTACHMENT0);
    const GLenum status = glCheckNamedFramebufferStatus(target.framebuffer_.id(), GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04X", static_cast<unsigned>(status));
        throw Error(std::string("RenderTarget: ") + color_format_name(format) + (with_depth ? " + depth32f" : "") +
                    " framebuffer of " + std::to_string(width) + "x" + std::to_string(height) +
                    " is incomplete (status " + hex + ")");
    }
    return target;
}

void RenderTarget::bind_for_drawing() const {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.id());
    glViewportIndexedf(0, 0.0f, 0.0f, static_cast<float>(width_), static_cast<float>(height_));
    FX_GL_CHECK("RenderTarget::bind_for_drawing");
}

void RenderTarget::clear(const glm::vec4& color, float depth) const {
    const GLfloat c[4] = {color.r, color.g, color.b, color.a};
    glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, c);
    if (depth_)
        glClearNamedFramebufferfv(framebuffer_.id(), GL_DEPTH, 0, &depth);
    FX_GL_CHECK("glClearNamedFramebufferfv");
}

Image RenderTarget::read() const {
    if (!color_)
        throw Error("RenderTarget::read on an empty render target");
    StateGuard guard;
    // A host's pixel-pack buffer or row length would redirect or reshape the read.
    StateGuard::set_render_defaults();
    Image image(width_, height_);
    const auto bytes = static_cast<GLsizei>(image.pixels.size() * sizeof(glm::vec4));
    // Row 0 of a texture image is its bottom row, as glReadPixels returns it.
    glGetTextureImage(color_.id(), 0, GL_RGBA, GL_FLOAT, bytes, image.pixels.data());
    FX_GL_CHECK("glGetTextureImage");
    return image;
}

} // namespace cellfx::fx::gl
