#include "gl/state_guard.hpp"

#include <algorithm>

namespace cellfx::fx::gl {
namespace {

thread_local int guard_depth = 0;       // guards alive on this thread
thread_local std::uint64_t guard_saves = 0;

// Non-indexed enables saved as a block (blend and scissor test are indexed, saved apart).
constexpr GLenum kCaps[] = {
    GL_DEPTH_TEST,          GL_DEPTH_CLAMP,          GL_STENCIL_TEST,        GL_CULL_FACE,
    GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,  GL_POLYGON_OFFSET_POINT, GL_PRIMITIVE_RESTART,
    GL_PRIMITIVE_RESTART_FIXED_INDEX, GL_RASTERIZER_DISCARD, GL_FRAMEBUFFER_SRGB, GL_MULTISAMPLE,
    GL_SAMPLE_ALPHA_TO_COVERAGE, GL_DITHER, GL_SAMPLE_COVERAGE, GL_SAMPLE_MASK, GL_SAMPLE_SHADING,
    GL_POLYGON_SMOOTH, GL_LINE_SMOOTH, GL_COLOR_LOGIC_OP,
};
// Off in set_render_defaults (the others in kCaps it sets one by one, or leaves: multisample).
constexpr GLenum kCapsOff[] = {
    GL_BLEND, GL_SCISSOR_TEST, GL_DEPTH_TEST, GL_DEPTH_CLAMP, GL_STENCIL_TEST, GL_CULL_FACE,
    GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE, GL_POLYGON_OFFSET_POINT, GL_PRIMITIVE_RESTART,
    GL_PRIMITIVE_RESTART_FIXED_INDEX, GL_RASTERIZER_DISCARD, GL_FRAMEBUFFER_SRGB, GL_SAMPLE_ALPHA_TO_COVERAGE,
    GL_DITHER, // the default is on; exact paths want the float values as computed
    GL_SAMPLE_COVERAGE, GL_SAMPLE_MASK, GL_SAMPLE_SHADING, GL_POLYGON_SMOOTH, GL_LINE_SMOOTH, GL_COLOR_LOGIC_OP,
};

// Every texture target of GL 4.5 core: glBindTextureUnit(unit, 0) unbinds all of them.
constexpr GLenum kTargets[StateGuard::kTextureTargets] = {
    GL_TEXTURE_1D,       GL_TEXTURE_2D,        GL_TEXTURE_3D,       GL_TEXTURE_1D_ARRAY,
    GL_TEXTURE_2D_ARRAY, GL_TEXTURE_RECTANGLE, GL_TEXTURE_CUBE_MAP, GL_TEXTURE_CUBE_MAP_ARRAY,
    GL_TEXTURE_BUFFER,   GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_2D_MULTISAMPLE_ARRAY};
constexpr GLenum kTargetBindings[StateGuard::kTextureTargets] = {
    GL_TEXTURE_BINDING_1D,       GL_TEXTURE_BINDING_2D,        GL_TEXTURE_BINDING_3D,       GL_TEXTURE_BINDING_1D_ARRAY,
    GL_TEXTURE_BINDING_2D_ARRAY, GL_TEXTURE_BINDING_RECTANGLE, GL_TEXTURE_BINDING_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY,
    GL_TEXTURE_BINDING_BUFFER,   GL_TEXTURE_BINDING_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY};
constexpr GLenum kPackNames[5] = {GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_ROWS,
                                  GL_PACK_IMAGE_HEIGHT};
constexpr GLenum kUnpackNames[6] = {GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_PIXELS,
                                    GL_UNPACK_SKIP_ROWS, GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_IMAGES};

GLint get_int(GLenum name) {
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

void set_cap(GLenum cap, GLboolean on) {
    if (on)
        glEnable(cap);
    else
        glDisable(cap);
}

template <class T>
void save_indexed(GLenum target, GLint count, T& out) {
    for (GLint i = 0; i < count; ++i) {
        glGetIntegeri_v(target == GL_UNIFORM_BUFFER ? GL_UNIFORM_BUFFER_BINDING : GL_SHADER_STORAGE_BUFFER_BINDING,
                        static_cast<GLuint>(i), &out[i].buffer);
        glGetInteger64i_v(target == GL_UNIFORM_BUFFER ? GL_UNIFORM_BUFFER_START : GL_SHADER_STORAGE_BUFFER_START,
                          static_cast<GLuint>(i), &out[i].start);
        glGetInteger64i_v(target == GL_UNIFORM_BUFFER ? GL_UNIFORM_BUFFER_SIZE : GL_SHADER_STORAGE_BUFFER_SIZE,
                          static_cast<GLuint>(i), &out[i].size);
    }
}

template <class T>
void restore_indexed(GLenum target, GLint count, const T& saved, GLint generic) {
    for (GLint i = 0; i < count; ++i) {
        const auto& b = saved[i];
        // Size 0 means the whole buffer was bound (glBindBufferBase).
        if (b.buffer == 0 || b.size == 0)
            glBindBufferBase(target, static_cast<GLuint>(i), static_cast<GLuint>(b.buffer));
        else
            glBindBufferRange(target, static_cast<GLuint>(i), static_cast<GLuint>(b.buffer),
                              static_cast<GLintptr>(b.start), static_cast<GLsizeiptr>(b.size));
    }
    // glBindBufferBase/Range also set the generic binding point: restore it last.
    glBindBuffer(target, static_cast<GLuint>(generic));
}

} // namespace

static_assert(sizeof(kCaps) / sizeof(kCaps[0]) == StateGuard::kCapCount, "StateGuard::kCapCount must match kCaps");

std::uint64_t StateGuard::saves() { return guard_saves; }

StateGuard::StateGuard() {
    if (guard_depth++ > 0) {
        nested_ = true;
        return;
    }
    ++guard_saves;
    draw_buffers_ = std::min(get_int(GL_MAX_DRAW_BUFFERS), kDrawBuffers);
    viewports_ = std::min(get_int(GL_MAX_VIEWPORTS), kViewports);

    draw_fbo_ = get_int(GL_DRAW_FRAMEBUFFER_BINDING);
    read_fbo_ = get_int(GL_READ_FRAMEBUFFER_BINDING);
    for (int i = 0; i < viewports_; ++i) {
        const auto u = static_cast<GLuint>(i);
        glGetFloati_v(GL_VIEWPORT, u, viewport_[i].data());
        glGetDoublei_v(GL_DEPTH_RANGE, u, depth_range_[i].data());
        glGetIntegeri_v(GL_SCISSOR_BOX, u, scissor_box_[i].data());
        scissor_test_[i] = glIsEnabledi(GL_SCISSOR_TEST, u);
    }
    for (int i = 0; i < draw_buffers_; ++i) {
        const auto u = static_cast<GLuint>(i);
        DrawBufferState& d = draw_buffer_[i];
        d.blend = glIsEnabledi(GL_BLEND, u);
        glGetIntegeri_v(GL_BLEND_SRC_RGB, u, &d.src_rgb);
        glGetIntegeri_v(GL_BLEND_DST_RGB, u, &d.dst_rgb);
        glGetIntegeri_v(GL_BLEND_SRC_ALPHA, u, &d.src_alpha);
        glGetIntegeri_v(GL_BLEND_DST_ALPHA, u, &d.dst_alpha);
        glGetIntegeri_v(GL_BLEND_EQUATION_RGB, u, &d.eq_rgb);
        glGetIntegeri_v(GL_BLEND_EQUATION_ALPHA, u, &d.eq_alpha);
        glGetBooleani_v(GL_COLOR_WRITEMASK, u, d.color_mask.data());
    }
    glGetFloatv(GL_BLEND_COLOR, blend_color_.data());
    glGetFloatv(GL_COLOR_CLEAR_VALUE, clear_color_.data());
    glGetDoublev(GL_DEPTH_CLEAR_VALUE, &clear_depth_);
    depth_func_ = get_int(GL_DEPTH_FUNC);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
    cull_mode_ = get_int(GL_CULL_FACE_MODE);
    front_face_ = get_int(GL_FRONT_FACE);
    GLint modes[2] = {GL_FILL, GL_FILL}; // core: front and back are always equal
    glGetIntegerv(GL_POLYGON_MODE, modes);
    polygon_mode_ = modes[0];
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &offset_factor_);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &offset_units_);
    clip_origin_ = get_int(GL_CLIP_ORIGIN);
    clip_depth_mode_ = get_int(GL_CLIP_DEPTH_MODE);
    restart_index_ = get_int(GL_PRIMITIVE_RESTART_INDEX);
    provoking_vertex_ = get_int(GL_PROVOKING_VERTEX);
    clamp_read_color_ = get_int(GL_CLAMP_READ_COLOR);
    for (int i = 0; i < kCapCount; ++i)
        caps_[i] = glIsEnabled(kCaps[i]);
    for (int i = 0; i < kClipDistances; ++i)
        clip_distances_[i] = glIsEnabled(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));

    program_ = get_int(GL_CURRENT_PROGRAM);
    vertex_array_ = get_int(GL_VERTEX_ARRAY_BINDING);
    array_buffer_ = get_int(GL_ARRAY_BUFFER_BINDING);

    active_texture_ = get_int(GL_ACTIVE_TEXTURE);
    for (int unit = 0; unit < kUnits; ++unit) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        for (int t = 0; t < kTextureTargets; ++t)
            textures_[unit][t] = get_int(kTargetBindings[t]);
        glGetIntegeri_v(GL_SAMPLER_BINDING, static_cast<GLuint>(unit), &samplers_[unit]);
    }
    glActiveTexture(static_cast<GLenum>(active_texture_));

    uniform_buffer_ = get_int(GL_UNIFORM_BUFFER_BINDING);
    storage_buffer_ = get_int(GL_SHADER_STORAGE_BUFFER_BINDING);
    save_indexed(GL_UNIFORM_BUFFER, kUnits, uniform_buffers_);
    save_indexed(GL_SHADER_STORAGE_BUFFER, kUnits, storage_buffers_);

    for (int i = 0; i < kImageUnits; ++i) {
        const auto u = static_cast<GLuint>(i);
        ImageBinding& b = images_[i];
        glGetIntegeri_v(GL_IMAGE_BINDING_NAME, u, &b.texture);
        glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, u, &b.level);
        glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, u, &b.layered);
        glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, u, &b.layer);
        glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, u, &b.access);
        glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, u, &b.format);
    }

    pack_buffer_ = get_int(GL_PIXEL_PACK_BUFFER_BINDING);
    unpack_buffer_ = get_int(GL_PIXEL_UNPACK_BUFFER_BINDING);
    for (int i = 0; i < 5; ++i)
        pack_[i] = get_int(kPackNames[i]);
    for (int i = 0; i < 6; ++i)
        unpack_[i] = get_int(kUnpackNames[i]);
}

StateGuard::~StateGuard() {
    --guard_depth;
    if (nested_) return;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw_fbo_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read_fbo_));
    for (int i = 0; i < viewports_; ++i) {
        const auto u = static_cast<GLuint>(i);
        glViewportIndexedfv(u, viewport_[i].data());
        glDepthRangeIndexed(u, depth_range_[i][0], depth_range_[i][1]);
        glScissorIndexedv(u, scissor_box_[i].data());
        if (scissor_test_[i])
            glEnablei(GL_SCISSOR_TEST, u);
        else
            glDisablei(GL_SCISSOR_TEST, u);
    }
    for (int i = 0; i < draw_buffers_; ++i) {
        const auto u = static_cast<GLuint>(i);
        const DrawBufferState& d = draw_buffer_[i];
        if (d.blend)
            glEnablei(GL_BLEND, u);
        else
            glDisablei(GL_BLEND, u);
        glBlendFuncSeparatei(u, static_cast<GLenum>(d.src_rgb), static_cast<GLenum>(d.dst_rgb),
                             static_cast<GLenum>(d.src_alpha), static_cast<GLenum>(d.dst_alpha));
        glBlendEquationSeparatei(u, static_cast<GLenum>(d.eq_rgb), static_cast<GLenum>(d.eq_alpha));
        glColorMaski(u, d.color_mask[0], d.color_mask[1], d.color_mask[2], d.color_mask[3]);
    }
    glBlendColor(blend_color_[0], blend_color_[1], blend_color_[2], blend_color_[3]);
    glClearColor(clear_color_[0], clear_color_[1], clear_color_[2], clear_color_[3]);
    glClearDepth(clear_depth_);
    glDepthFunc(static_cast<GLenum>(depth_func_));
    glDepthMask(depth_mask_);
    glCullFace(static_cast<GLenum>(cull_mode_));
    glFrontFace(static_cast<GLenum>(front_face_));
    glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(polygon_mode_));
    glPolygonOffset(offset_factor_, offset_units_);
    glClipControl(static_cast<GLenum>(clip_origin_), static_cast<GLenum>(clip_depth_mode_));
    glPrimitiveRestartIndex(static_cast<GLuint>(restart_index_));
    glProvokingVertex(static_cast<GLenum>(provoking_vertex_));
    glClampColor(GL_CLAMP_READ_COLOR, static_cast<GLenum>(clamp_read_color_));
    for (int i = 0; i < kCapCount; ++i)
        set_cap(kCaps[i], caps_[i]);
    for (int i = 0; i < kClipDistances; ++i)
        set_cap(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i), clip_distances_[i]);

    glUseProgram(static_cast<GLuint>(program_));
    glBindVertexArray(static_cast<GLuint>(vertex_array_));
    glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));

    for (int unit = 0; unit < kUnits; ++unit) {
        glActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
        for (int t = 0; t < kTextureTargets; ++t)
            glBindTexture(kTargets[t], static_cast<GLuint>(textures_[unit][t]));
        glBindSampler(static_cast<GLuint>(unit), static_cast<GLuint>(samplers_[unit]));
    }
    glActiveTexture(static_cast<GLenum>(active_texture_));

    restore_indexed(GL_UNIFORM_BUFFER, kUnits, uniform_buffers_, uniform_buffer_);
    restore_indexed(GL_SHADER_STORAGE_BUFFER, kUnits, storage_buffers_, storage_buffer_);

    for (int i = 0; i < kImageUnits; ++i) {
        const ImageBinding& b = images_[i];
        glBindImageTexture(static_cast<GLuint>(i), static_cast<GLuint>(b.texture), b.level, b.layered, b.layer,
                           static_cast<GLenum>(b.access), static_cast<GLenum>(b.format));
    }

    glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(pack_buffer_));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack_buffer_));
    for (int i = 0; i < 5; ++i)
        glPixelStorei(kPackNames[i], pack_[i]);
    for (int i = 0; i < 6; ++i)
        glPixelStorei(kUnpackNames[i], unpack_[i]);
}

void StateGuard::set_render_defaults() {
    for (GLenum cap : kCapsOff)
        glDisable(cap);
    for (int i = 0; i < kClipDistances; ++i)
        glDisable(static_cast<GLenum>(GL_CLIP_DISTANCE0 + i));
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glFrontFace(GL_CCW);
    glProvokingVertex(GL_LAST_VERTEX_CONVENTION);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDepthRange(0.0, 1.0);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glClampColor(GL_CLAMP_READ_COLOR, GL_FALSE);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    for (GLenum name : kPackNames)
        glPixelStorei(name, name == GL_PACK_ALIGNMENT ? 1 : 0);
    for (GLenum name : kUnpackNames)
        glPixelStorei(name, name == GL_UNPACK_ALIGNMENT ? 1 : 0);
}

} // namespace cellfx::fx::gl
