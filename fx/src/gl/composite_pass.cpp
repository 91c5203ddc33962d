#include "gl/composite_pass.hpp"

#include "gl/state_guard.hpp"

namespace cellfx::fx::gl {
namespace {

// composite.frag's one uniform location, its whole interface table (reaches GLSL as a #define).
constexpr GLint kUniformBackground = 0;

Defines composite_defines() { return Defines{}.set("UNIFORM_BACKGROUND", kUniformBackground); }

} // namespace

CompositePass CompositePass::create(const ShaderLibrary& library) {
    CompositePass pass;
    pass.over_color_ = library.link({"fullscreen.vert", "composite.frag"}, composite_defines());
    pass.over_framebuffer_ =
        library.link({"fullscreen.vert", "composite.frag"}, composite_defines().set("COMPOSITE_OVER_FRAMEBUFFER", "1"));
    pass.sampler_ = Sampler::create();
    glSamplerParameteri(pass.sampler_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(pass.sampler_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(pass.sampler_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(pass.sampler_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    FX_GL_CHECK("glSamplerParameteri");
    // Core profile draws need a bound vertex array even with no attributes.
    pass.empty_vao_ = VertexArray::create();
    return pass;
}

void CompositePass::draw(const Program& program, GLuint image, bool blend) const {
    if (!program)
        throw Error("CompositePass used before create()");
    StateGuard guard;
    StateGuard::set_render_defaults();
    if (blend) {
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    }
    glUseProgram(program.id());
    glBindVertexArray(empty_vao_.id());
    glBindTextureUnit(0, image);
    glBindSampler(0, sampler_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    FX_GL_CHECK("CompositePass draw");
}

void CompositePass::draw_over_color(GLuint image, const glm::vec3& background) const {
    if (over_color_)
        glProgramUniform3f(over_color_.id(), kUniformBackground, background.r, background.g, background.b);
    draw(over_color_, image, false);
}

void CompositePass::draw_over_framebuffer(GLuint image) const { draw(over_framebuffer_, image, true); }

} // namespace cellfx::fx::gl
