// cellfx — the last step of every render path: a premultiplied RGBA image composited over
// what lies behind it, drawn as one full-screen triangle (shaders/fullscreen.vert +
// shaders/composite.frag).
//
// Draws into the currently bound draw framebuffer and viewport (the caller chooses both; the
// host's scissor box and test are left to apply). The image is sampled with the pass's own
// NEAREST/CLAMP sampler, so it should match the viewport's size for an exact result. Every
// other GL state change is undone before returning (StateGuard).
//
// Ownership: owns its programs, sampler and empty vertex array; the image texture belongs to
// the caller. Preconditions: the creating context is current.
#pragma once

#include <glm/vec3.hpp>

#include "gl/gl_object.hpp"
#include "gl/shader_library.hpp"

namespace cellfx::fx::gl {

class CompositePass {
public:
    CompositePass() = default; // empty; create() makes a usable one
    // Compiles and links both variants from `library` (throws fx::Error with file:line).
    static CompositePass create(const ShaderLibrary& library = ShaderLibrary::builtin());

    // out = c + (1 − a)·background, alpha 1. `image` is a 2-D texture name.
    void draw_over_color(GLuint image, const glm::vec3& background) const;
    // out = c + (1 − a)·dst with blending ONE, ONE_MINUS_SRC_ALPHA (alpha likewise): the
    // framebuffer's contents are the background (a game's frame).
    void draw_over_framebuffer(GLuint image) const;

private:
    void draw(const Program& program, GLuint image, bool blend) const;
    Program over_color_;
    Program over_framebuffer_;
    Sampler sampler_;
    VertexArray empty_vao_;
};

} // namespace cellfx::fx::gl
