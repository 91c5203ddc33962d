// The game's depth in any common convention as cellfx's canonical depth (depth_normalizer.hpp).
#include "render/depth_normalizer.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "render/terrain_interface.hpp"
#include "render/terrain_shaders.hpp"

namespace cellfx::terrain {

namespace {

// Window depth d = a + b·u of a projection, u = 1/z (perspective) or z (orthographic), z the
// view distance: standard near → 0, far → 1; reversed near → 1, far → 0.
glm::dvec2 window_depth_line(bool orthographic, bool reversed, double n, double f) {
    glm::dvec2 line;
    if (orthographic) {
        line = {-n / (f - n), 1.0 / (f - n)}; // (z − n)/(f − n)
    } else if (std::isinf(f)) {
        line = {1.0, -n}; // 1 − n/z
    } else {
        line = {f / (f - n), -f * n / (f - n)}; // f(z − n)/(z(f − n))
    }
    return reversed ? glm::dvec2(1.0 - line.x, -line.y) : line;
}

std::string hex(GLint v) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%04X", unsigned(v));
    return b;
}

const char* texture_target_name(GLint target) {
    switch (target) {
    case GL_TEXTURE_1D: return "GL_TEXTURE_1D";
    case GL_TEXTURE_2D: return "GL_TEXTURE_2D";
    case GL_TEXTURE_3D: return "GL_TEXTURE_3D";
    case GL_TEXTURE_1D_ARRAY: return "GL_TEXTURE_1D_ARRAY";
    case GL_TEXTURE_2D_ARRAY: return "GL_TEXTURE_2D_ARRAY";
    case GL_TEXTURE_RECTANGLE: return "GL_TEXTURE_RECTANGLE";
    case GL_TEXTURE_CUBE_MAP: return "GL_TEXTURE_CUBE_MAP";
    case GL_TEXTURE_CUBE_MAP_ARRAY: return "GL_TEXTURE_CUBE_MAP_ARRAY";
    case GL_TEXTURE_BUFFER: return "GL_TEXTURE_BUFFER";
    case GL_TEXTURE_2D_MULTISAMPLE: return "GL_TEXTURE_2D_MULTISAMPLE";
    case GL_TEXTURE_2D_MULTISAMPLE_ARRAY: return "GL_TEXTURE_2D_MULTISAMPLE_ARRAY";
    }
    return "an unknown target";
}

bool depth_format(GLint f, bool& stencil) {
    stencil = f == GL_DEPTH24_STENCIL8 || f == GL_DEPTH32F_STENCIL8;
    return stencil || f == GL_DEPTH_COMPONENT16 || f == GL_DEPTH_COMPONENT24 || f == GL_DEPTH_COMPONENT32 ||
           f == GL_DEPTH_COMPONENT32F;
}

} // namespace

glm::dvec2 depth_map(const DepthConvention& c, const fx::Camera& camera) {
    const bool ortho = camera.orthographic();
    const double n = c.near_distance > 0.0 ? c.near_distance : camera.near_distance;
    const double f = c.far_distance > 0.0 ? c.far_distance : camera.far_distance;
    if (!(c.near_distance >= 0.0) || !(c.far_distance >= 0.0) || !std::isfinite(c.near_distance))
        throw fx::Error("cellfx render: target.depth: near_distance and far_distance must be ≥ 0 (0: the camera's), "
                        "near_distance finite");
    if (!(f > n)) throw fx::Error("cellfx render: target.depth: the far plane (" + std::to_string(f) +
                                  ") must lie beyond the near plane (" + std::to_string(n) + ")");
    if (ortho && std::isinf(f))
        throw fx::Error("cellfx render: target.depth: an orthographic camera needs a finite far plane");
    const glm::dvec2 game = window_depth_line(ortho, c.reversed, n, f);
    const glm::dvec2 canonical = window_depth_line(ortho, false, camera.near_distance, camera.far_distance);
    // canonical = A_c + B_c·u and u = (game − A_g)/B_g: affine in the game's depth.
    const double scale = canonical.y / game.y;
    return {canonical.x - scale * game.x, scale};
}

void check_depth_state(const DepthConvention& convention) {
    GLint func = GL_LESS, clip = GL_NEGATIVE_ONE_TO_ONE;
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip);
    if (!convention.reversed && (func == GL_GREATER || func == GL_GEQUAL) && clip == GL_ZERO_TO_ONE)
        throw fx::Error(std::string("cellfx render: the game draws reversed-Z (glDepthFunc ") +
                            (func == GL_GREATER ? "GL_GREATER" : "GL_GEQUAL") +
                        ", glClipControl GL_ZERO_TO_ONE) but target.depth.reversed is false: set "
                        "target.depth.reversed = true (and target.depth.near_distance / far_distance where the "
                        "projection's planes are not the camera's); read as standard depth, the game's depth would "
                        "hide almost every effect");
}

DepthNormalizer::DepthNormalizer() {
    single_ = terrain_shaders().link({"fullscreen.vert", "scene_depth_normalize.frag"});
    multi_ = terrain_shaders().link({"fullscreen.vert", "scene_depth_normalize.frag"}, fx::gl::Defines{{"MULTISAMPLE", "1"}});
    sampler_ = fx::gl::Sampler::create();
    glSamplerParameteri(sampler_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(sampler_.id(), GL_TEXTURE_COMPARE_MODE, GL_NONE); // a shadow compare mode on the game's texture does not matter
    vao_ = fx::gl::VertexArray::create();
    FX_GL_CHECK("depth normalizer set-up");
}

const DepthNormalizer::TextureInfo& DepthNormalizer::check(GLuint texture, const fx::Viewport& viewport) {
    if (texture == info_.name && viewport.x == info_.viewport.x && viewport.y == info_.viewport.y &&
        viewport.width == info_.viewport.width && viewport.height == info_.viewport.height)
        return info_;
    info_ = TextureInfo{};
    const std::string what = "cellfx render: target.depth_texture " + std::to_string(texture);
    if (!glIsTexture(texture)) throw fx::Error(what + " is not a texture of the current context");
    GLint target = 0, format = 0, width = 0, height = 0, samples = 0;
    glGetTextureParameteriv(texture, GL_TEXTURE_TARGET, &target);
    if (target != GL_TEXTURE_2D && target != GL_TEXTURE_2D_MULTISAMPLE)
        throw fx::Error(what + " is a " + texture_target_name(target) +
                        "; cellfx reads a GL_TEXTURE_2D or GL_TEXTURE_2D_MULTISAMPLE depth texture (a layer of an "
                        "array can be given as a glTextureView)");
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &height);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_SAMPLES, &samples);
    bool stencil = false;
    if (!depth_format(format, stencil))
        throw fx::Error(what + " has internal format " + hex(format) +
                        ", not a depth format (GL_DEPTH_COMPONENT16/24/32/32F, GL_DEPTH24_STENCIL8, GL_DEPTH32F_STENCIL8)");
    if (width < viewport.x + viewport.width || height < viewport.y + viewport.height)
        throw fx::Error(what + " is " + std::to_string(width) + "x" + std::to_string(height) + ", too small for the viewport " +
                        std::to_string(viewport.width) + "x" + std::to_string(viewport.height) + " at (" +
                        std::to_string(viewport.x) + ", " + std::to_string(viewport.y) + ")");
    FX_GL_CHECK("depth texture queries");
    info_.name = texture;
    info_.viewport = viewport;
    info_.multisample = target == GL_TEXTURE_2D_MULTISAMPLE;
    info_.depth_stencil = stencil;
    info_.samples = info_.multisample ? std::max(samples, 1) : 1;
    return info_;
}

void DepthNormalizer::draw(GLuint texture, const DepthConvention& convention, const fx::Camera& camera,
                           const fx::Viewport& viewport, int dst_x, int dst_y) {
    const glm::dvec2 map = depth_map(convention, camera);
    const TextureInfo& info = check(texture, viewport);
    // A depth-stencil texture set to show its stencil is read as depth for this pass.
    GLint stencil_mode = GL_DEPTH_COMPONENT;
    if (info.depth_stencil) glGetTextureParameteriv(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, &stencil_mode);
    if (stencil_mode != GL_DEPTH_COMPONENT) glTextureParameteri(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    const fx::gl::Program& program = info.multisample ? multi_ : single_;
    glViewportIndexedf(0, float(dst_x), float(dst_y), float(viewport.width), float(viewport.height));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glUseProgram(program.id());
    glProgramUniform2i(program.id(), kUniformNormalizeOffset, viewport.x - dst_x, viewport.y - dst_y);
    glProgramUniform2f(program.id(), kUniformNormalizeMap, float(map.x), float(map.y));
    glProgramUniform1i(program.id(), kUniformNormalizeSamples, info.samples);
    glBindVertexArray(vao_.id());
    glBindTextureUnit(0, texture);
    glBindSampler(0, sampler_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindTextureUnit(0, 0);
    glBindSampler(0, 0);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (stencil_mode != GL_DEPTH_COMPONENT) glTextureParameteri(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, stencil_mode);
    FX_GL_CHECK("scene depth normalization");
}

GLuint DepthNormalizer::normalized(GLuint texture, const DepthConvention& convention, const fx::Camera& camera,
                                   const fx::Viewport& viewport) {
    const int w = viewport.x + viewport.width, h = viewport.y + viewport.height;
    if (!depth_ || depth_width_ < w || depth_height_ < h) {
        depth_width_ = std::max(w, depth_width_), depth_height_ = std::max(h, depth_height_);
        depth_ = fx::gl::make_texture_2d(GL_DEPTH_COMPONENT32F, depth_width_, depth_height_);
        framebuffer_ = fx::gl::Framebuffer::create();
        glNamedFramebufferTexture(framebuffer_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
        glNamedFramebufferDrawBuffer(framebuffer_.id(), GL_NONE);
        glNamedFramebufferReadBuffer(framebuffer_.id(), GL_NONE);
        if (glCheckNamedFramebufferStatus(framebuffer_.id(), GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw fx::Error("cellfx render: the scene depth framebuffer is incomplete");
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.id());
    draw(texture, convention, camera, viewport, viewport.x, viewport.y);
    return depth_.id();
}

} // namespace cellfx::terrain
