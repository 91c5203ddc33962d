#include "scene_depth.hpp"

#include <epoxy/gl.h>

namespace cellfx_paraview {

namespace {

GLint attachment_parameter(GLuint framebuffer, GLenum attachment, GLenum name) {
    GLint value = 0;
    glGetNamedFramebufferAttachmentParameteriv(framebuffer, attachment, name, &value);
    return value;
}

bool has_stencil(GLint format) { return format == GL_DEPTH24_STENCIL8 || format == GL_DEPTH32F_STENCIL8; }

// A texture cellfx can texelFetch as it is: level 0 of a 2-D texture, complete without mipmaps,
// no depth comparison.
bool readable_as_is(GLuint texture, GLint level) {
    GLint target = 0, min_filter = 0, compare = 0;
    glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
    if (target != GL_TEXTURE_2D || level != 0) return false;
    glGetTextureParameteriv(texture, GL_TEXTURE_MIN_FILTER, &min_filter);
    glGetTextureParameteriv(texture, GL_TEXTURE_COMPARE_MODE, &compare);
    return (min_filter == GL_NEAREST || min_filter == GL_LINEAR) && compare == GL_NONE;
}

} // namespace

unsigned int SceneDepth::texture_for_current_framebuffer(int x, int y, int width, int height, std::string& how) {
    GLint bound = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    const GLuint source = GLuint(bound);
    GLint format = 0;
    if (source != 0) {
        const GLint type = attachment_parameter(source, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE);
        if (type == GL_NONE) {
            how = "no depth attachment";
            return 0;
        }
        const GLuint name = GLuint(attachment_parameter(source, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME));
        if (type == GL_TEXTURE) {
            const GLint level = attachment_parameter(source, GL_DEPTH_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LEVEL);
            if (readable_as_is(name, level)) {
                how = "framebuffer's depth texture";
                return name;
            }
            glGetTextureLevelParameteriv(name, level, GL_TEXTURE_INTERNAL_FORMAT, &format);
        } else {
            glGetNamedRenderbufferParameteriv(name, GL_RENDERBUFFER_INTERNAL_FORMAT, &format);
        }
    } else {
        const GLint bits = attachment_parameter(0, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE);
        if (bits == 0) {
            how = "no depth buffer";
            return 0;
        }
        const bool stencil = attachment_parameter(0, GL_STENCIL, GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE) > 0;
        const bool floating = attachment_parameter(0, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE) == GL_FLOAT;
        format = floating ? (stencil ? GL_DEPTH32F_STENCIL8 : GL_DEPTH_COMPONENT32F)
                          : bits > 24 ? GL_DEPTH_COMPONENT32 : (stencil ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24);
    }

    // A copy of the viewport's depth; cellfx reads texel (x + i, y + j) for pixel (i, j).
    const int need_w = x + width, need_h = y + height;
    if (texture_ == 0 || format != format_ || need_w > width_ || need_h > height_) {
        release();
        format_ = format;
        width_ = need_w, height_ = need_h;
        glCreateTextures(GL_TEXTURE_2D, 1, &texture_);
        glTextureStorage2D(texture_, 1, GLenum(format), width_, height_);
        glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glCreateFramebuffers(1, &framebuffer_);
        glNamedFramebufferTexture(framebuffer_, has_stencil(format) ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                                  texture_, 0);
        glNamedFramebufferDrawBuffer(framebuffer_, GL_NONE);
    }
    glBlitNamedFramebuffer(source, framebuffer_, x, y, need_w, need_h, x, y, need_w, need_h, GL_DEPTH_BUFFER_BIT,
                           GL_NEAREST);
    how = "copy of the framebuffer's depth";
    return texture_;
}

void SceneDepth::release() {
    if (framebuffer_) glDeleteFramebuffers(1, &framebuffer_);
    if (texture_) glDeleteTextures(1, &texture_);
    framebuffer_ = texture_ = 0;
    width_ = height_ = format_ = 0;
}

} // namespace cellfx_paraview
