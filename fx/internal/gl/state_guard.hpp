// cellfx — saves the host's GL state on construction and restores it on destruction.
//
// cellfx renders inside the host's (a game's) context and frame, so every render entry point
// holds a StateGuard while it changes state. Guards nest: only the outermost guard on a thread
// saves and restores (once per frame at the module boundary — Module::render,
// SceneRenderer::render — however many passes run inside); an inner guard (CellRenderer::render
// called by the scene renderer) does nothing, so code inside a guard sets the state it needs
// (set_render_defaults() and its own bindings) rather than relying on an inner guard's restore.
// Saved and restored, exactly:
//   - draw and read framebuffer bindings; for every viewport index (ARB_viewport_array, up to
//     kViewports): viewport, depth range, scissor test and scissor box;
//   - per draw buffer: blend enable, blend func separate, blend equation separate, colour mask
//     (indexed, so a host with per-buffer blending gets it back); blend colour;
//   - depth test, depth func, depth mask, depth clamp; stencil test; cull face enable + mode,
//     front face; polygon mode; polygon offset fill/line/point enables, factor and units;
//     clip control (origin, depth mode); clip distances 0–7; provoking vertex; primitive
//     restart (+ fixed index) and its index; rasterizer discard, framebuffer sRGB, multisample,
//     sample alpha-to-coverage, sample coverage, sample mask, sample shading, polygon and line
//     smoothing, colour logic op, dither; read-colour clamping; clear colour and clear depth;
//   - current program, vertex array binding, array buffer binding;
//   - active texture unit; on units 0..kUnits-1: the binding of every texture target (1D, 2D,
//     3D, 1D/2D array, rectangle, cube map, cube map array, buffer, 2D multisample and 2D
//     multisample array — glBindTextureUnit(unit, 0) unbinds them all) and the sampler binding;
//   - uniform and shader storage buffers: generic bindings and indexed bindings 0..kUnits-1
//     (buffer, offset, size);
//   - image units 0..kImageUnits-1: texture, level, layered, layer, access and format;
//   - pixel pack/unpack buffer bindings and pack/unpack alignment, row length, skip pixels/rows,
//     image height (+ unpack skip images).
// Render paths must not touch GL state outside this list (extend the list first).
//
// Not copyable or movable: a guard lives in one scope. The context that was current at
// construction must be current at destruction. Objects bound by the host must still exist
// at destruction (the guard re-binds names, it does not keep them alive).
#pragma once

#include <array>
#include <cstdint>

#include <epoxy/gl.h>

namespace cellfx::fx::gl {

class StateGuard {
public:
    static constexpr int kUnits = 16;       // texture units / indexed buffer bindings saved (the projector uses 0–14)
    static constexpr int kTextureTargets = 11;
    static constexpr int kImageUnits = 2;   // image units saved (the froxel medium binds 0–1)
    static constexpr int kDrawBuffers = 8;  // indexed blend/colour-mask state saved (≤ GL max)
    static constexpr int kViewports = 16;   // indexed viewport/scissor/depth-range state saved (≤ GL max)
    static constexpr int kClipDistances = 8;
    static constexpr int kCapCount = 20;    // enables saved as a block (kCaps in state_guard.cpp)

    StateGuard();
    ~StateGuard();
    StateGuard(const StateGuard&) = delete;
    StateGuard& operator=(const StateGuard&) = delete;

    // Puts the state render paths expect as a starting point: blend, depth, stencil, cull,
    // scissor, polygon offset, clip distances, smoothing, logic op, sample coverage/mask/shading,
    // rasterizer discard, primitive restart, sRGB off; fill polygons, counter-clockwise front
    // faces, last-vertex provoking; colour and depth writes on, depth func LESS, depth range
    // [0, 1]; clip control GL's defaults (whatever the game uses, e.g. reversed-Z's
    // GL_ZERO_TO_ONE); read colours unclamped; pack/unpack tightly packed (alignment 1) with no
    // pixel buffers bound. Bindings, viewport and program are untouched.
    static void set_render_defaults();

    // Outermost guards made on this thread so far (each one a full save and restore): tests
    // check that a frame saves once.
    static std::uint64_t saves();

private:
    struct IndexedBuffer {
        GLint buffer = 0;
        GLint64 start = 0, size = 0;
    };
    struct ImageBinding {
        GLint texture = 0, level = 0, layer = 0, access = GL_READ_ONLY, format = GL_R8;
        GLboolean layered = GL_FALSE;
    };
    struct DrawBufferState {
        GLboolean blend = GL_FALSE;
        GLint src_rgb = 0, dst_rgb = 0, src_alpha = 0, dst_alpha = 0;
        GLint eq_rgb = 0, eq_alpha = 0;
        std::array<GLboolean, 4> color_mask{};
    };
    bool nested_ = false; // an outer guard on this thread saves and restores
    int draw_buffers_ = 0, viewports_ = 0;
    GLint draw_fbo_ = 0, read_fbo_ = 0;
    std::array<std::array<GLfloat, 4>, kViewports> viewport_{};
    std::array<std::array<GLdouble, 2>, kViewports> depth_range_{};
    std::array<std::array<GLint, 4>, kViewports> scissor_box_{};
    std::array<GLboolean, kViewports> scissor_test_{};
    std::array<DrawBufferState, kDrawBuffers> draw_buffer_{};
    std::array<GLfloat, 4> blend_color_{}, clear_color_{};
    GLdouble clear_depth_ = 1.0;
    GLint depth_func_ = 0, cull_mode_ = 0, front_face_ = 0, polygon_mode_ = 0, provoking_vertex_ = 0;
    GLboolean depth_mask_ = GL_TRUE;
    GLfloat offset_factor_ = 0.0f, offset_units_ = 0.0f;
    GLint clip_origin_ = 0, clip_depth_mode_ = 0;
    GLint restart_index_ = 0;
    GLint clamp_read_color_ = 0;
    std::array<GLboolean, kCapCount> caps_{};
    std::array<GLboolean, kClipDistances> clip_distances_{};
    GLint program_ = 0, vertex_array_ = 0, array_buffer_ = 0;
    GLint active_texture_ = 0;
    std::array<std::array<GLint, kTextureTargets>, kUnits> textures_{};
    std::array<GLint, kUnits> samplers_{};
    GLint uniform_buffer_ = 0, storage_buffer_ = 0;
    std::array<IndexedBuffer, kUnits> uniform_buffers_{}, storage_buffers_{};
    std::array<ImageBinding, kImageUnits> images_{};
    GLint pack_buffer_ = 0, unpack_buffer_ = 0;
    std::array<GLint, 5> pack_{};   // alignment, row length, skip pixels, skip rows, image height
    std::array<GLint, 6> unpack_{}; // the same + skip images
};

} // namespace cellfx::fx::gl
