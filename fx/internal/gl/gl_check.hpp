// cellfx — error checks after GL calls.
//
// FX_GL_CHECK("glNamedBufferStorage") after a GL call: in debug builds (no NDEBUG, or
// CELLFX_GL_CHECKS defined) it drains glGetError() and throws fx::Error naming the call, the
// source file and line, and every pending error; in release builds it compiles to nothing.
// check_gl_errors() is the function behind it and is always available (tests call it directly).
// Preconditions: a GL context is current on the calling thread.
#pragma once

#include <epoxy/gl.h>

namespace cellfx::fx::gl {

// "GL_INVALID_ENUM", ..., or "GL error 0x1234".
const char* gl_error_name(GLenum error);

// Throws fx::Error("file:line: glFoo failed: GL_INVALID_VALUE") if glGetError() reports
// anything; the flag may also come from an earlier, unchecked call, and the message says so.
void check_gl_errors(const char* call, const char* file, int line);

} // namespace cellfx::fx::gl

#if !defined(NDEBUG) || defined(CELLFX_GL_CHECKS)
#define FX_GL_CHECK(call) ::cellfx::fx::gl::check_gl_errors(call, __FILE__, __LINE__)
#else
#define FX_GL_CHECK(call) ((void)0)
#endif
