// cellfx terrain — the effects at a fraction of the view's resolution (Scene::fx_scale, 1/2 or
// 1/4): every effect path and the one medium draw into this layer, against the scene's depth
// reduced to its size (the nearest depth of each block: fx_layer_depth.frag), and the layer is
// composited over the full-resolution frame with a depth-aware upsample (fx_layer_upsample.frag:
// bilinear among the neighbours on the pixel's own surface, else the neighbour of nearest
// depth), so that edges against geometry stay sharp. Volumes cost the fragments of the reduced
// size: a quarter at 1/2, a sixteenth at 1/4.
//
// Ownership: owns its programs and target (move-only; destroy it while its context is
// current). Draws inside the scene renderer's StateGuard and sets the state it needs.
#pragma once

#include <glm/vec2.hpp>

#include "fx/camera.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"

namespace cellfx::terrain {

// The layer's size for a width × height view at `scale`: each side rounded up, at least 1.
glm::ivec2 fx_layer_size(int width, int height, double scale);

class FxLayer {
public:
    FxLayer(); // a GL 4.5 context current

    // Starts a frame of a width × height view at `scale` (< 1) of `camera`: sizes the layer,
    // clears it to transparent, reduces `depth` (canonical window depth of the full view, texel
    // depth_origin + (i, j) for pixel (i, j); 0: none) into its depth, and binds it for drawing
    // with the viewport set to the whole layer.
    void begin(int width, int height, double scale, unsigned depth, glm::ivec2 depth_origin);
    fx::Viewport viewport() const { return {0, 0, target_.width(), target_.height()}; }
    GLuint framebuffer() const { return target_.framebuffer(); } // colour only: drawn into while its depth is read
    GLuint color_texture() const { return target_.color_texture(); }
    // The reduced depth (0 when the frame has none): CellRenderOptions::scene_depth for the layer.
    GLuint depth_texture() const { return has_depth_ ? depth_.id() : 0; }

    // Composites the layer over the bound draw framebuffer's `viewport` (the full view), blending
    // premultiplied "over"; `depth` and `depth_origin` as given to begin(), read with `camera`'s
    // near and far planes.
    void composite(const fx::Viewport& viewport, unsigned depth, glm::ivec2 depth_origin, const fx::Camera& camera);

private:
    fx::gl::Program reduce_, upsample_;
    fx::gl::Sampler nearest_, linear_;
    fx::gl::VertexArray vao_;
    fx::gl::RenderTarget target_; // RGBA32F
    fx::gl::Texture depth_;       // DEPTH_COMPONENT32F, the target's size
    fx::gl::Framebuffer depth_target_;
    int full_width_ = 0, full_height_ = 0;
    bool has_depth_ = false;
};

} // namespace cellfx::terrain
