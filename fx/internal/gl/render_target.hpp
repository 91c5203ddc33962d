// cellfx — an offscreen framebuffer that render paths draw into and tests read back.
//
// One colour attachment of a chosen format (RGBA8 for the classic paths, RGBA16F / RGBA32F for
// the exact ones) and, optionally, a DEPTH_COMPONENT32F depth texture (a texture, not a
// renderbuffer, so that paths can sample scene depth). Textures use NEAREST filtering and
// CLAMP_TO_EDGE.
//
// Ownership: owns its framebuffer and textures (move-only). Preconditions: the creating
// context is current for every call and for destruction. bind()/clear()/read() change GL
// state as documented; callers that render into the host's context hold a StateGuard.
#pragma once

#include <glm/vec4.hpp>

#include "fx/image.hpp"
#include "gl/gl_object.hpp"

namespace cellfx::fx::gl {

enum class ColorFormat { RGBA8, RGBA16F, RGBA32F };
GLenum internal_format(ColorFormat format); // GL_RGBA8, ...
const char* color_format_name(ColorFormat format);

class RenderTarget {
public:
    RenderTarget() = default; // empty; create() makes a usable one
    // Throws fx::Error for a non-positive size or an incomplete framebuffer (naming the status).
    static RenderTarget create(int width, int height, ColorFormat format, bool with_depth);

    int width() const { return width_; }
    int height() const { return height_; }
    ColorFormat format() const { return format_; }
    bool has_depth() const { return static_cast<bool>(depth_); }
    GLuint framebuffer() const { return framebuffer_.id(); }
    GLuint color_texture() const { return color_.id(); }
    GLuint depth_texture() const { return depth_.id(); } // 0 without depth

    // Binds the framebuffer for drawing (GL_DRAW_FRAMEBUFFER) and sets viewport 0 to the whole
    // target. Changes state: draw framebuffer binding, viewport.
    void bind_for_drawing() const;
    // Clears colour (and depth, if present) with glClearNamedFramebuffer*. Like every GL clear
    // it honours the scissor test and the colour/depth write masks: render paths call it after
    // StateGuard::set_render_defaults() (scissor off, masks on) to clear the whole target.
    void clear(const glm::vec4& color, float depth = 1.0f) const;
    // Reads the colour attachment as float RGBA, bottom row first (glReadPixels order). RGBA8
    // values come back as k/255. Holds its own StateGuard (pack state is set and restored).
    Image read() const;

private:
    int width_ = 0, height_ = 0;
    ColorFormat format_ = ColorFormat::RGBA8;
    Framebuffer framebuffer_;
    Texture color_;
    Texture depth_;
};

} // namespace cellfx::fx::gl
