#include "scanline_image.hpp"

#include <epoxy/gl.h>

#include "gl/composite_pass.hpp"
#include "gl/gl_object.hpp"

namespace cellfx_paraview {

struct ScanlineImage::Gl {
    std::unique_ptr<cellfx::fx::gl::CompositePass> composite =
        std::make_unique<cellfx::fx::gl::CompositePass>(cellfx::fx::gl::CompositePass::create());
    cellfx::fx::gl::Texture texture;
    int width = 0, height = 0;
};

ScanlineImage::ScanlineImage() = default;

ScanlineImage::~ScanlineImage() { abandon(); }

void ScanlineImage::draw_over(const cellfx::fx::Image& image, int x, int y) {
    if (!gl_) gl_ = std::make_unique<Gl>();
    if (!gl_->texture || gl_->width != image.width || gl_->height != image.height) {
        gl_->texture = cellfx::fx::gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(gl_->texture.id(), 1, GL_RGBA32F, image.width, image.height);
        gl_->width = image.width, gl_->height = image.height;
    }
    GLint alignment = 4;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    GLint unpack_buffer = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(gl_->texture.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_FLOAT, image.pixels.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(unpack_buffer));
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    glViewport(x, y, image.width, image.height);
    gl_->composite->draw_over_framebuffer(gl_->texture.id());
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
}

void ScanlineImage::release() { gl_.reset(); }

void ScanlineImage::abandon() {
    if (!gl_) return;
    // Deleting the objects would call GL without their context (as the mapper does with its
    // renderer, they are let go undeleted).
    static_cast<void>(gl_->texture.release());
    static_cast<void>(gl_->composite.release());
    gl_.reset();
}

} // namespace cellfx_paraview
