#include "gl/gl_check.hpp"

#include <cstdio>
#include <string>

#include "fx/error.hpp"

namespace cellfx::fx::gl {

const char* gl_error_name(GLenum error) {
    switch (error) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "GL error (unknown code)";
    }
}

void check_gl_errors(const char* call, const char* file, int line) {
    GLenum error = glGetError();
    if (error == GL_NO_ERROR)
        return;
    std::string message = std::string(file) + ":" + std::to_string(line) + ": " + call + " failed:";
    // Several flags can be pending (one per error kind); a lost context keeps reporting, so cap.
    for (int i = 0; i < 8 && error != GL_NO_ERROR; ++i) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(error));
        message += std::string(" ") + gl_error_name(error) + " (" + code + ")";
        error = glGetError();
    }
    message += " (the flag may have been set by an earlier unchecked GL call)";
    throw Error(message);
}

} // namespace cellfx::fx::gl
