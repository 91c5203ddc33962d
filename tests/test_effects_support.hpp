// Helpers for the effect, scene and embedding tests: an effect's mesh moved into the world (for
// the scan-line reference), frame comparison with the render paths' stated tolerances, cameras.
#pragma once

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "gl_fixture.hpp"
#include "image_check.hpp"
#include "cellfx_names.hpp"

namespace effects_test {

inline fx::Camera look(glm::dvec3 eye, glm::dvec3 target, double fov = 40.0, glm::dvec3 up = {0, 0, 1}) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = up;
    cam.fov_y_degrees = fov;
    cam.near_distance = 0.05;
    cam.far_distance = 5000.0;
    return cam;
}

// The effect's mesh with its points moved by transform(): what the world sees.
inline fx::CellMesh world_mesh(const fx::Effect& effect) {
    fx::CellMesh mesh = effect.mesh();
    const glm::dmat4& m = effect.transform();
    for (glm::dvec3& p : mesh.points) p = glm::dvec3(m * glm::dvec4(p, 1.0));
    return mesh;
}

inline bool absorption_path(fx::RenderPath path) {
    return path == fx::RenderPath::Absorption || path == fx::RenderPath::AbsorptionExact;
}

inline fx::OpticalModel model_of(fx::RenderPath path, bool fog) {
    if (fog || absorption_path(path)) return fx::OpticalModel::EmissionAbsorption;
    return path == fx::RenderPath::Mip ? fx::OpticalModel::Maximum : fx::OpticalModel::Emission;
}

// A frame against the scan-line reference with `path`'s stated tolerance
// (testing/verify/tolerances.cpp: where each bound comes from); `c` says what the frame holds
// (the cells on a ray for classic pcp, ...). Returns the measured difference.
inline verify::Difference check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                                      fx::RenderPath path, const verify::Case& c, bool fog = false) {
    const verify::Path p = verify::path_of(path, fog);
    verify::Options options;
    options.clamp_expected = p == verify::Path::Pcp; // classic pcp's 8-bit target holds at most 1
    return fx_test::check_frame(name + "_" + verify::path_name(p), actual, expected, verify::stated(p, c), options);
}
inline verify::Difference check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                                      fx::RenderPath path, int cells_on_ray) {
    verify::Case c;
    c.cells_on_ray = cells_on_ray;
    return check_frame(name, actual, expected, path, c);
}

// The effect as the scene draws it — its local mesh, the camera moved into its frame — against
// the scan-line reference of the same mesh moved into the world, seen by the world camera.
inline verify::Difference effect_vs_scanline(const std::string& name, const fx::Effect& effect,
                                             const fx::TransferFunction& tf, const fx::Camera& camera,
                                             fx::RenderPath path, int cells_on_ray, bool fog = false, int size = 96) {
    fx_test::gl_context();
    const fx::CellMesh world = world_mesh(effect);
    fx::ScanlineOptions so;
    so.model = model_of(path, fog);
    const fx::Image expected =
        fx::ScanlineRenderer(world).render(camera, size, size, *world.find_scalar(effect.scalar_name()), tf, so);
    fx::CellRenderer renderer(effect.mesh(), effect.scalar_name(), tf);
    fx::CellRenderOptions options;
    options.fog = fog;
    const fx::Image actual =
        renderer.render_to_image(fx::camera_in_frame(camera, effect.transform()), size, size, path, options);
    fx_test::require_no_gl_error();
    verify::Case c;
    c.cells_on_ray = cells_on_ray;
    return check_frame(name, actual, expected, path, c, fog);
}

} // namespace effects_test

namespace effects_test {

// GL state a game typically leaves set between its own draws, read back as numbers (what
// cellfx must leave as it found it), texture units 0–3 and 5 included.
inline std::vector<double> host_state() {
    std::vector<double> v;
    auto ints = [&v](GLenum name, int count) {
        GLint x[4] = {};
        glGetIntegerv(name, x);
        for (int i = 0; i < count; ++i) v.push_back(x[i]);
    };
    auto floats = [&v](GLenum name, int count) {
        GLfloat x[4] = {};
        glGetFloatv(name, x);
        for (int i = 0; i < count; ++i) v.push_back(x[i]);
    };
    for (GLenum cap : {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST, GL_STENCIL_TEST}) v.push_back(glIsEnabled(cap));
    ints(GL_DEPTH_FUNC, 1);
    ints(GL_DEPTH_WRITEMASK, 1);
    ints(GL_BLEND_SRC_RGB, 1);
    ints(GL_BLEND_DST_RGB, 1);
    ints(GL_BLEND_EQUATION_RGB, 1);
    ints(GL_CULL_FACE_MODE, 1);
    ints(GL_VIEWPORT, 4);
    ints(GL_SCISSOR_BOX, 4);
    ints(GL_CURRENT_PROGRAM, 1);
    ints(GL_VERTEX_ARRAY_BINDING, 1);
    ints(GL_ARRAY_BUFFER_BINDING, 1);
    ints(GL_DRAW_FRAMEBUFFER_BINDING, 1);
    ints(GL_READ_FRAMEBUFFER_BINDING, 1);
    ints(GL_UNPACK_ALIGNMENT, 1);
    ints(GL_PACK_ALIGNMENT, 1);
    ints(GL_SHADER_STORAGE_BUFFER_BINDING, 1);
    floats(GL_COLOR_CLEAR_VALUE, 4);
    ints(GL_ACTIVE_TEXTURE, 1);
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (int unit : {0, 1, 2, 3, 5}) {
        glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        ints(GL_TEXTURE_BINDING_2D, 1);
        ints(GL_SAMPLER_BINDING, 1);
    }
    glActiveTexture(GLenum(active));
    for (GLuint i = 0; i < 4; ++i) {
        GLint b = 0;
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &b);
        v.push_back(b);
    }
    return v;
}

// A game's typical leftovers: its own VAO, buffer, textures on units 0–3 and 5, a sampler,
// depth test with an unusual function, blending, culling, odd viewport/scissor, pack state.
struct HostLeftovers {
    GLuint vao = 0, buffer = 0, textures[5] = {}, sampler = 0;
    HostLeftovers() {
        glCreateVertexArrays(1, &vao);
        glCreateBuffers(1, &buffer);
        glCreateTextures(GL_TEXTURE_2D, 5, textures);
        glCreateSamplers(1, &sampler);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, buffer);
        const int units[5] = {0, 1, 2, 3, 5};
        for (int k = 0; k < 5; ++k) {
            glActiveTexture(GLenum(GL_TEXTURE0 + units[k]));
            glBindTexture(GL_TEXTURE_2D, textures[k]);
        }
        glBindSampler(3, sampler);
        glActiveTexture(GL_TEXTURE2);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_GEQUAL);
        glDepthMask(GL_FALSE);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_COLOR, GL_ONE_MINUS_DST_ALPHA);
        glBlendEquation(GL_FUNC_REVERSE_SUBTRACT);
        glViewport(3, 5, 7, 11);
        glScissor(1, 2, 3, 4);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
        glPixelStorei(GL_PACK_ALIGNMENT, 8);
        glClearColor(0.7f, 0.1f, 0.6f, 0.5f);
    }
    ~HostLeftovers() {
        glBindVertexArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, 0);
        const int units[5] = {0, 1, 2, 3, 5};
        for (int unit : units) {
            glActiveTexture(GLenum(GL_TEXTURE0 + unit));
            glBindTexture(GL_TEXTURE_2D, 0);
        }
        glBindSampler(3, 0);
        glActiveTexture(GL_TEXTURE0);
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glDisable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glDisable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ZERO);
        glBlendEquation(GL_FUNC_ADD);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glClearColor(0, 0, 0, 0);
        glDeleteSamplers(1, &sampler);
        glDeleteTextures(5, textures);
        glDeleteBuffers(1, &buffer);
        glDeleteVertexArrays(1, &vao);
    }
};

} // namespace effects_test
