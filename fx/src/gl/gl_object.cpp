#include "gl/gl_object.hpp"

#include <algorithm>
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

bool GrowingBuffer::reserve(std::size_t bytes, std::size_t keep) {
    bytes = std::max<std::size_t>(bytes, 16);
    if (buffer_ && bytes <= capacity_) return false;
    // A multiple of 16 bytes: whole vec4s, and offsets any clear or copy of 32-bit words accepts.
    const std::size_t capacity = (std::max(bytes, capacity_ + capacity_ / 2) + 15) / 16 * 16;
    Buffer grown = make_buffer(GLsizeiptr(capacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
    keep = std::min(keep, capacity_);
    if (buffer_ && keep > 0) glCopyNamedBufferSubData(buffer_.id(), grown.id(), 0, 0, GLsizeiptr(keep));
    buffer_ = std::move(grown);
    capacity_ = capacity;
    FX_GL_CHECK("grow buffer");
    return true;
}

bool GrowingBuffer::upload(const void* data, std::size_t bytes) {
    const bool made = reserve(bytes);
    if (bytes > 0) glNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(bytes), data);
    return made;
}

bool GrowingBuffer::upload(const void* data, std::size_t bytes, Texture& texture, GLenum format) {
    if (!upload(data, bytes)) return false;
    if (!texture) texture = Texture::create(GL_TEXTURE_BUFFER);
    glTextureBuffer(texture.id(), format, buffer_.id());
    FX_GL_CHECK("buffer texture");
    return true;
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
