// cellfx — move-only owners of OpenGL object names (private to the library).
//
// Each wrapper holds one GLuint. Copy is deleted, move is noexcept and leaves the source
// empty (id 0), and the destructor deletes the object — unless it came from wrap(), which
// marks a name the host (the game) owns: cellfx never deletes what it did not create.
// release() gives the name up without deleting it (the caller owns it afterwards).
//
// Objects are created with GL 4.5 direct state access (glCreate*), so they exist as soon as
// create() returns and nothing depends on bindings.
//
// Preconditions: create(), reset() and the destructor need the context that made the object
// (or one sharing with it) current on the calling thread. A default-constructed wrapper is
// empty and its destructor makes no GL call, so empty wrappers may outlive the context.
#pragma once

#include <cstddef>
#include <string>
#include <utility>

#include <epoxy/gl.h>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"

namespace cellfx::fx::gl {

// Traits: `static GLuint create(Args...)`, `static void destroy(GLuint)`, `static const char* kind`.
template <class Traits>
class Object {
public:
    Object() noexcept = default;
    ~Object() { reset(); }

    Object(const Object&) = delete;
    Object& operator=(const Object&) = delete;
    Object(Object&& other) noexcept
        : id_(std::exchange(other.id_, 0u)), owned_(std::exchange(other.owned_, false)) {}
    Object& operator=(Object&& other) noexcept {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0u);
            owned_ = std::exchange(other.owned_, false);
        }
        return *this;
    }

    // A new object; throws fx::Error if GL returns no name.
    template <class... Args>
    static Object create(Args... args) {
        Object object;
        object.id_ = Traits::create(args...);
        object.owned_ = true;
        if (object.id_ == 0)
            throw Error(std::string("GL: could not create a ") + Traits::kind + " object");
        return object;
    }
    // Refers to a name the host owns; the wrapper never deletes it.
    static Object wrap(GLuint id) noexcept {
        Object object;
        object.id_ = id;
        object.owned_ = false;
        return object;
    }

    GLuint id() const noexcept { return id_; }
    explicit operator bool() const noexcept { return id_ != 0; }
    bool owned() const noexcept { return owned_; }

    // Returns the name and empties the wrapper without deleting anything.
    GLuint release() noexcept {
        owned_ = false;
        return std::exchange(id_, 0u);
    }
    // Deletes the object if this wrapper owns it; leaves the wrapper empty.
    void reset() noexcept {
        if (id_ != 0 && owned_)
            Traits::destroy(id_);
        id_ = 0;
        owned_ = false;
    }

private:
    GLuint id_ = 0;
    bool owned_ = false;
};

namespace traits {
struct Buffer {
    static constexpr const char* kind = "buffer";
    static GLuint create() { GLuint id = 0; glCreateBuffers(1, &id); FX_GL_CHECK("glCreateBuffers"); return id; }
    static void destroy(GLuint id) { glDeleteBuffers(1, &id); }
};
struct VertexArray {
    static constexpr const char* kind = "vertex array";
    static GLuint create() { GLuint id = 0; glCreateVertexArrays(1, &id); FX_GL_CHECK("glCreateVertexArrays"); return id; }
    static void destroy(GLuint id) { glDeleteVertexArrays(1, &id); }
};
struct Texture {
    static constexpr const char* kind = "texture";
    static GLuint create(GLenum target) { GLuint id = 0; glCreateTextures(target, 1, &id); FX_GL_CHECK("glCreateTextures"); return id; }
    static void destroy(GLuint id) { glDeleteTextures(1, &id); }
};
struct Sampler {
    static constexpr const char* kind = "sampler";
    static GLuint create() { GLuint id = 0; glCreateSamplers(1, &id); FX_GL_CHECK("glCreateSamplers"); return id; }
    static void destroy(GLuint id) { glDeleteSamplers(1, &id); }
};
struct Framebuffer {
    static constexpr const char* kind = "framebuffer";
    static GLuint create() { GLuint id = 0; glCreateFramebuffers(1, &id); FX_GL_CHECK("glCreateFramebuffers"); return id; }
    static void destroy(GLuint id) { glDeleteFramebuffers(1, &id); }
};
struct Renderbuffer {
    static constexpr const char* kind = "renderbuffer";
    static GLuint create() { GLuint id = 0; glCreateRenderbuffers(1, &id); FX_GL_CHECK("glCreateRenderbuffers"); return id; }
    static void destroy(GLuint id) { glDeleteRenderbuffers(1, &id); }
};
struct Program {
    static constexpr const char* kind = "program";
    static GLuint create() { GLuint id = glCreateProgram(); FX_GL_CHECK("glCreateProgram"); return id; }
    static void destroy(GLuint id) { glDeleteProgram(id); }
};
struct Shader {
    static constexpr const char* kind = "shader";
    static GLuint create(GLenum stage) { GLuint id = glCreateShader(stage); FX_GL_CHECK("glCreateShader"); return id; }
    static void destroy(GLuint id) { glDeleteShader(id); }
};
struct Query {
    static constexpr const char* kind = "query";
    static GLuint create(GLenum target) { GLuint id = 0; glCreateQueries(target, 1, &id); FX_GL_CHECK("glCreateQueries"); return id; }
    static void destroy(GLuint id) { glDeleteQueries(1, &id); }
};
} // namespace traits

using Buffer = Object<traits::Buffer>;             // Buffer::create()
using VertexArray = Object<traits::VertexArray>;   // VertexArray::create()
using Texture = Object<traits::Texture>;           // Texture::create(GL_TEXTURE_2D)
using Sampler = Object<traits::Sampler>;           // Sampler::create()
using Framebuffer = Object<traits::Framebuffer>;   // Framebuffer::create()
using Renderbuffer = Object<traits::Renderbuffer>; // Renderbuffer::create()
using Program = Object<traits::Program>;           // Program::create()
using Shader = Object<traits::Shader>;             // Shader::create(GL_FRAGMENT_SHADER)
using Query = Object<traits::Query>;               // Query::create(GL_TIME_ELAPSED)

// Immutable storage (glNamedBufferStorage) of `size` bytes, filled from `data` if not null.
// flags: GL_DYNAMIC_STORAGE_BIT to allow glNamedBufferSubData later, map bits, ...
Buffer make_buffer(GLsizeiptr size, const void* data, GLbitfield flags = 0);

// A buffer for data replaced every frame or with every new mesh: immutable storage with
// GL_DYNAMIC_STORAGE_BIT that grows by half when a size exceeds its capacity and never shrinks,
// so that sizes seen before cost no new storage and only the bytes written are uploaded.
class GrowingBuffer {
public:
    // Makes room for `bytes` (at least 16). Returns true when the storage was made anew: its
    // name changed (attach it again where it is attached), and only its first `keep` bytes
    // were carried over.
    bool reserve(std::size_t bytes, std::size_t keep = 0);
    // reserve(bytes), then writes `bytes` of `data` at offset 0; returns reserve's answer.
    bool upload(const void* data, std::size_t bytes);
    // The same for a buffer read through `texture` (a GL_TEXTURE_BUFFER, made on first use),
    // which is attached again, with `format`, when the storage was made anew.
    bool upload(const void* data, std::size_t bytes, Texture& texture, GLenum format);
    GLuint id() const { return buffer_.id(); }
    std::size_t capacity() const { return capacity_; }

private:
    Buffer buffer_;
    std::size_t capacity_ = 0;
};

// A 2-D texture with immutable storage (glTextureStorage2D), `levels` mip levels, NEAREST
// filtering and CLAMP_TO_EDGE so that texel values come back exactly unless changed.
Texture make_texture_2d(GLenum internal_format, int width, int height, int levels = 1);

// A renderbuffer with storage (glNamedRenderbufferStorage).
Renderbuffer make_renderbuffer(GLenum internal_format, int width, int height);

} // namespace cellfx::fx::gl
