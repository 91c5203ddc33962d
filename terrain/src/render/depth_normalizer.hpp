// cellfx terrain — the game's depth turned into cellfx's canonical depth, once per frame at the
// module boundary (SceneRenderer::render): whatever the game's convention (standard or
// reversed-Z, its projection's own near and far planes, an infinite far plane), format
// (DEPTH_COMPONENT16/24/32/32F, DEPTH24_STENCIL8, DEPTH32F_STENCIL8) and sample count
// (multisampled depth resolves to its nearest sample), the result is the window depth of the
// update() camera's standard projection with GL's default depth range and clip control, in a
// single-sample DEPTH_COMPONENT32F texture of cellfx's — the depth every render path reads.
// Depth textures that cannot be read (not a texture, not 2D, not a depth format, smaller than
// the viewport) are refused with an fx::Error naming the texture and what is wrong.
//
// Ownership: owns its program, sampler and depth target (move-only; destroy it while its context
// is current). Draws inside the scene renderer's StateGuard and sets the state it needs.
#pragma once

#include <glm/vec2.hpp>

#include "gl/gl_object.hpp"
#include "terrain/scene_renderer.hpp"

namespace cellfx::terrain {

// canonical depth = map.x + map.y · game depth for `camera` (both affine in 1/z, or in z for an
// orthographic camera). Throws fx::Error for a convention that cannot describe a projection
// (planes not 0 < near < far, an infinite far plane for an orthographic camera).
glm::dvec2 depth_map(const DepthConvention& convention, const fx::Camera& camera);

// Refuses `convention` when the game's GL state, as render() finds it, is reversed-Z's — a depth
// test of GL_GREATER or GL_GEQUAL with glClipControl's GL_ZERO_TO_ONE — while
// `convention.reversed` is false: read as standard depth, the game's depth would put everything
// in front of the effects, an almost blank frame. Throws
// fx::Error saying what to set. Any other state is taken at the convention's word: a
// reversed-Z game may reset its GL state before render(), and GL_LESS with GL_ZERO_TO_ONE is a
// standard set-up too.
void check_depth_state(const DepthConvention& convention);

class DepthNormalizer {
public:
    DepthNormalizer(); // a GL 4.5 context current

    // Writes the canonical depth of the game's `texture` under `viewport` into the depth of the
    // bound draw framebuffer at viewport (dst_x, dst_y, viewport.width, viewport.height), so
    // that the game's texel (viewport.x + i, viewport.y + j) lands on pixel (dst_x + i, dst_y + j).
    void draw(GLuint texture, const DepthConvention& convention, const fx::Camera& camera, const fx::Viewport& viewport,
              int dst_x, int dst_y);
    // The same into a depth texture of its own with the game's texel layout (texel (x, y) of the
    // viewport's pixels is the game's texel (x, y)): for effects drawn straight into the game's
    // framebuffer. Leaves its own framebuffer bound for drawing. Returns that texture.
    GLuint normalized(GLuint texture, const DepthConvention& convention, const fx::Camera& camera,
                      const fx::Viewport& viewport);

private:
    struct TextureInfo {
        GLuint name = 0;
        fx::Viewport viewport;
        bool multisample = false, depth_stencil = false;
        int samples = 1;
    };
    // Checks the texture when it or the viewport changed since the last frame.
    const TextureInfo& check(GLuint texture, const fx::Viewport& viewport);

    fx::gl::Program single_, multi_;
    fx::gl::Sampler sampler_;
    fx::gl::VertexArray vao_;
    fx::gl::Framebuffer framebuffer_; // normalized(): depth only
    fx::gl::Texture depth_;
    int depth_width_ = 0, depth_height_ = 0;
    TextureInfo info_;
};

} // namespace cellfx::terrain
