// Helpers for the effect, scene and embedding tests: an effect's mesh moved into the world (for
// the scan-line reference), frame comparison with the render paths' stated tolerances, cameras.
#pragma once

#include <algorithm>
#include <cmath>
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

struct FrameCheck {
    float peak = 0.0f;       // brightest reference channel
    float max_delta = 0.0f;
    double mean_delta = 0.0;
    double bad_fraction = 0.0; // pixels beyond the per-pixel tolerance
    bool finite = true;
};

// Tolerances per path, relative to the reference's brightest channel (`peak`), as in
// tests/test_pcp_scanline.cpp where they are derived:
//   pcp-exact, mip: both sides integrate exactly; float32 on the GPU against double on the CPU,
//     the 4096-entry tables, and pixel centres within rounding of a silhouette, which rasteriser
//     and reference may assign differently: per pixel 0.5% of peak, ≤ 1% of pixels beyond it,
//     mean ≤ 0.05% of peak.
//   pcp (classic, 8-bit): each of the ≤ N cells on a ray rounds its light and its α to 1/255 and
//     colours the trapezoid rule on κ(s): per pixel 0.5·N/255 + `classic_rel` of the pixel, ≤ 1%
//     of pixels beyond, mean ≤ 0.3·√N/255 + 2% of peak.
//   absorption-exact, absorption (sorted, emission–absorption), as docs/absorption.md derives
//     them: exact — the pre-integration table is trilinear between its samples (~0.1–0.5% of a
//     segment) plus silhouettes: per pixel 1.5% of peak, mean 0.1%; classic — §II's thickness
//     and opacity-table approximations and vertex colours: per pixel 4% of peak, mean 0.4%; both
//     ≤ 1% of pixels beyond.
// `absorption_pixel` replaces classic absorption's per-pixel 4% where a test says why.
inline FrameCheck check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                              fx::RenderPath path, int cells_on_ray, float classic_rel = 0.15f,
                              float absorption_pixel = 0.04f) {
    REQUIRE(actual.width == expected.width);
    REQUIRE(actual.height == expected.height);
    FrameCheck e;
    for (const glm::vec4& p : expected.pixels) e.peak = std::max({e.peak, p.r, p.g, p.b});
    REQUIRE(e.peak > 0.0f); // the view must show something
    const bool classic = path == fx::RenderPath::Pcp;
    float abs_tol = classic ? 0.5f * float(cells_on_ray) / 255.0f : 0.005f * e.peak;
    const float rel_tol = classic ? classic_rel : 0.0f;
    double mean_tol = classic ? 0.3 * std::sqrt(double(cells_on_ray)) / 255.0 + 0.02 * e.peak : 0.0005 * e.peak;
    if (path == fx::RenderPath::AbsorptionExact) abs_tol = 0.015f * e.peak, mean_tol = 0.001 * e.peak;
    if (path == fx::RenderPath::Absorption) abs_tol = absorption_pixel * e.peak, mean_tol = 0.004 * e.peak;
    std::size_t bad = 0;
    double sum = 0.0;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        bool ok = true;
        for (int c = 0; c < 4; ++c) {
            const float a = actual.pixels[i][c], x = expected.pixels[i][c];
            if (!std::isfinite(a)) e.finite = false, ok = false;
            const float d = std::fabs(a - x);
            e.max_delta = std::max(e.max_delta, std::isfinite(d) ? d : INFINITY);
            sum += std::isfinite(d) ? d : 1e30;
            if (!(d <= abs_tol + rel_tol * std::fabs(x))) ok = false;
        }
        if (!ok) ++bad;
    }
    e.mean_delta = sum / (4.0 * double(actual.pixels.size()));
    e.bad_fraction = double(bad) / double(actual.pixels.size());
    WARN(name << " [" << fx::render_path_name(path) << "]: peak " << e.peak << ", max delta " << e.max_delta << " ("
              << 100.0 * e.max_delta / e.peak << "% of peak), mean " << 100.0 * e.mean_delta / e.peak
              << "% of peak, pixels beyond tolerance " << 100.0 * e.bad_fraction << "%");
    const bool ok = e.finite && e.bad_fraction <= 0.01 && e.mean_delta <= mean_tol;
    if (!ok) {
        INFO("images: " << fx_test::write_failure_images(name + "_" + fx::render_path_name(path), actual, expected,
                                                         10.0f / e.peak));
        CHECK(ok);
    }
    CHECK(e.finite);
    CHECK(e.bad_fraction <= 0.01);
    CHECK(e.mean_delta <= mean_tol);
    return e;
}

// The effect as the scene draws it — its local mesh, the camera moved into its frame — against
// the scan-line reference of the same mesh moved into the world, seen by the world camera.
inline FrameCheck effect_vs_scanline(const std::string& name, const fx::Effect& effect, const fx::TransferFunction& tf,
                                     const fx::Camera& camera, fx::RenderPath path, int cells_on_ray, bool fog = false,
                                     int size = 96, float classic_rel = 0.15f, float absorption_pixel = 0.04f) {
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
    return check_frame(name, actual, expected, path, cells_on_ray, classic_rel, absorption_pixel);
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
