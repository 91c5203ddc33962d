#include "gl/gl_object.hpp"

#include <string>

namespace cellfx::fx::gl {

Buffer make_buffer(GLsizeiptr size, const void* data, GLbitfield flags) {
    if (size <= 0)
        throw Error("make_buffer: size must be positive, got " + std::to_string(size));
    Buffer buffer = Buffer::create();
    glNamedBufferStorage(buffer.id(), size, data, flags);
    FX_GL_CHECK("glNamedBufferStorage");
    return buffer;
}

Texture make_texture_2d(GLenum internal_format, int width, int height, int levels) {
    if (width <= 0 || height <= 0 || levels <= 0)
        throw Error("make_texture_2d: bad size " + std::to_string(width) + "x" + std::to_string(height) +
                    " with " + std::to_string(levels) + " levels");
    Texture texture = Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(texture.id(), levels, internal_format, width, height);
    FX_GL_CHECK("glTextureStorage2D");
    glTextureParameteri(texture.id(), GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    FX_GL_CHECK("glTextureParameteri");
    return texture;
}

Renderbuffer make_renderbuffer(GLenum internal_format, int width, int height) {
    if (width <= 0 || height <= 0)
        throw Error("make_renderbuffer: bad size " + std::to_string(width) + "x" + std::to_string(height));
    Renderbuffer renderbuffer = Renderbuffer::create();
    glNamedRenderbufferStorage(renderbuffer.id(), internal_format, width, height);
    FX_GL_CHECK("glNamedRenderbufferStorage");
    return renderbuffer;
}

} // namespace cellfx::fx::gl
