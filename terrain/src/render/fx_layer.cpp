// Based on: Cantlay 2007, "High-speed, off-screen particles" (GPU Gems 3, ch. 23) — volumes drawn
// at a reduced resolution against a reduced depth and composited with depth-aware upsampling;
// here with a checkerboard of nearest and farthest depths (fx_layer.hpp).
#include "render/fx_layer.hpp"

#include <algorithm>
#include <cmath>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/state_guard.hpp"
#include "render/terrain_interface.hpp"
#include "render/terrain_shaders.hpp"

namespace cellfx::terrain {

glm::ivec2 fx_layer_size(int width, int height, double scale) {
    return {std::max(1, int(std::ceil(width * scale - 1e-9))), std::max(1, int(std::ceil(height * scale - 1e-9)))};
}

FxLayer::FxLayer() {
    reduce_ = terrain_shaders().link({"fullscreen.vert", "fx_layer_depth.frag"});
    upsample_ = terrain_shaders().link({"fullscreen.vert", "fx_layer_upsample.frag"});
    nearest_ = fx::gl::Sampler::create();
    linear_ = fx::gl::Sampler::create();
    for (GLuint s : {nearest_.id(), linear_.id()}) {
        const GLint filter = s == linear_.id() ? GL_LINEAR : GL_NEAREST;
        glSamplerParameteri(s, GL_TEXTURE_MIN_FILTER, filter);
        glSamplerParameteri(s, GL_TEXTURE_MAG_FILTER, filter);
        glSamplerParameteri(s, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(s, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(s, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    }
    vao_ = fx::gl::VertexArray::create();
    FX_GL_CHECK("fx layer set-up");
}

void FxLayer::begin(int width, int height, double scale, unsigned depth, glm::ivec2 depth_origin) {
    if (width <= 0 || height <= 0 || !(scale > 0.0 && scale < 1.0))
        throw fx::Error("fx layer: a " + std::to_string(width) + "x" + std::to_string(height) + " view at scale " +
                        std::to_string(scale));
    fx::gl::StateGuard::set_render_defaults(); // what the passes before left set (nested guards restore nothing)
    const glm::ivec2 size = fx_layer_size(width, height, scale);
    if (target_.width() != size.x || target_.height() != size.y) {
        target_ = fx::gl::RenderTarget::create(size.x, size.y, fx::gl::ColorFormat::RGBA32F, false);
        depth_ = fx::gl::make_texture_2d(GL_DEPTH_COMPONENT32F, size.x, size.y);
        depth_target_ = fx::gl::Framebuffer::create();
        glNamedFramebufferTexture(depth_target_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
        glNamedFramebufferDrawBuffer(depth_target_.id(), GL_NONE);
        glNamedFramebufferReadBuffer(depth_target_.id(), GL_NONE);
        if (glCheckNamedFramebufferStatus(depth_target_.id(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw fx::Error("fx layer: the depth framebuffer is incomplete");
    }
    full_width_ = width, full_height_ = height;
    has_depth_ = depth != 0;
    target_.clear(glm::vec4(0.0f));
    if (has_depth_) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depth_target_.id());
        glViewportIndexedf(0, 0.0f, 0.0f, float(size.x), float(size.y));
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glUseProgram(reduce_.id());
        glProgramUniform2i(reduce_.id(), kUniformLayerDepthOrigin, depth_origin.x, depth_origin.y);
        glProgramUniform4i(reduce_.id(), kUniformLayerDepthSizes, width, height, size.x, size.y);
        glBindVertexArray(vao_.id());
        glBindTextureUnit(0, depth);
        glBindSampler(0, nearest_.id());
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindTextureUnit(0, 0);
        glBindSampler(0, 0);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
    }
    target_.bind_for_drawing();
    FX_GL_CHECK("fx layer: begin");
}

void FxLayer::composite(const fx::Viewport& viewport, unsigned depth, glm::ivec2 depth_origin, const fx::Camera& camera) {
    if (viewport.width != full_width_ || viewport.height != full_height_)
        throw fx::Error("fx layer: composite() over a viewport of another size than begin()'s");
    fx::gl::StateGuard::set_render_defaults(); // what the passes before left set (nested guards restore nothing)
    const GLuint p = upsample_.id();
    glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glProgramUniform4f(p, kUniformLayerViewport, float(viewport.x), float(viewport.y), float(viewport.width),
                       float(viewport.height));
    glProgramUniform2i(p, kUniformLayerUpsampleDepthOrigin, depth_origin.x, depth_origin.y);
    glProgramUniform2i(p, kUniformLayerLowSize, target_.width(), target_.height());
    glProgramUniform3f(p, kUniformLayerDepthModel, float(camera.near_distance), float(camera.far_distance),
                       depth == 0 || !has_depth_ ? 0.0f : camera.orthographic() ? 2.0f : 1.0f);
    glUseProgram(p);
    glBindVertexArray(vao_.id());
    glBindTextureUnit(0, target_.color_texture());
    glBindSampler(0, linear_.id()); // bilinear without a scene depth; texelFetch ignores it
    glBindTextureUnit(1, depth_.id());
    glBindSampler(1, nearest_.id());
    glBindTextureUnit(2, depth);
    glBindSampler(2, nearest_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    for (GLuint unit = 0; unit < 3; ++unit) glBindTextureUnit(unit, 0), glBindSampler(unit, 0);
    glDisablei(GL_BLEND, 0);
    FX_GL_CHECK("fx layer: composite");
}

} // namespace cellfx::terrain
