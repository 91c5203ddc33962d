// The embedding tests' game (test_embedding.cpp, test_gl_state.cpp, test_depth_conventions.cpp):
// a campfire scene, the game's own framebuffer with a depth texture of a chosen format (single-
// or multisampled), and the game's opaque pass — a sky, and a box in front of part of the fire,
// drawn with scissored clears or as real geometry through the game's projection in any depth
// convention (standard, reversed-Z, infinite far plane).
#pragma once

#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "cellfx/cellfx.hpp"
#include "gl/state_guard.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace embedding_test {

constexpr int kW = 96, kH = 72;
const glm::vec4 kSky(0.10f, 0.15f, 0.22f, 1.0f);
const glm::vec4 kBox(0.80f, 0.30f, 0.20f, 1.0f);
// The box's screen rectangle: the left half, a band through the middle of the fire. Its edges
// lie on pixel boundaries (NDC x = 0, y = ±0.5), so every sample of a pixel agrees.
inline bool in_box(int x, int y) { return x < kW / 2 && y >= kH / 4 && y < 3 * kH / 4; }

// GL window depth of a point at view depth z (GL's default depth range, perspective).
inline float window_depth(const fx::Camera& cam, double z) {
    const double n = cam.near_distance, f = cam.far_distance;
    return float(f * (z - n) / (z * (f - n)));
}

inline terrain::Scene fire_scene(bool with_terrain, const std::string& extra_effect_keys = {}) {
    const std::string terrain = R"("terrain": {"procedural": {"size": 33, "spacing": 0.5, "origin": [-8, -8],
                                                  "noise": {"amplitude": 0.2, "frequency": 0.2, "seed": 5}}},)";
    return terrain::parse_scene(R"({)" + (with_terrain ? terrain : std::string()) + R"(
        "effects": [{"type": "campfire", "name": "fire", "position": [0, 0, 0],)" + extra_effect_keys + R"(
                     "transfer_function": "../transfer_functions/fire.json", "extinction_scale": 0.15}],
        "camera": {"eye": [1.6, -2.4, 1.2], "target": [0, 0, 0.6], "fov": 45, "near": 0.05, "far": 100}})",
                                "embedding.json", fx_test::source_path("content/scenes"));
}

// How the game projects: a projection matrix, the clip control and depth test that go with it,
// and the depth its clear writes.
struct GameProjection {
    glm::dmat4 projection;
    GLenum clip_depth = GL_NEGATIVE_ONE_TO_ONE;
    GLenum depth_func = GL_LESS;
    float clear_depth = 1.0f;
    cellfx::DepthConvention convention; // what the game tells cellfx
};

// GL's standard projection of `cam` (near → 0, far → 1).
inline GameProjection standard_projection(const fx::Camera& cam) {
    return {cam.projection_matrix(double(kW) / kH), GL_NEGATIVE_ONE_TO_ONE, GL_LESS, 1.0f, {}};
}

// A game's framebuffer: colour + a depth texture, attached. `depth_format` is the game's
// choice; `compare` sets a shadow-sampler compare mode on it (a game may leave one set);
// `samples` > 1 makes both multisampled.
struct GameFrame {
    GLuint framebuffer = 0, color = 0, depth = 0;
    int samples = 1;
    GameFrame(GLenum depth_format, bool compare, int sample_count = 1) : samples(sample_count) {
        const GLenum target = samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D;
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(target, 1, &color);
        glCreateTextures(target, 1, &depth);
        if (samples > 1) {
            glTextureStorage2DMultisample(color, samples, GL_RGBA32F, kW, kH, GL_TRUE);
            glTextureStorage2DMultisample(depth, samples, depth_format, kW, kH, GL_TRUE);
        } else {
            glTextureStorage2D(color, 1, GL_RGBA32F, kW, kH);
            glTextureStorage2D(depth, 1, depth_format, kW, kH);
            if (compare) glTextureParameteri(depth, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        }
        const bool stencil = depth_format == GL_DEPTH24_STENCIL8 || depth_format == GL_DEPTH32F_STENCIL8;
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, stencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT, depth, 0);
        REQUIRE(glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    }
    ~GameFrame() {
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
    GameFrame(const GameFrame&) = delete;
    GameFrame& operator=(const GameFrame&) = delete;

    // The game's opaque pass with scissored clears: sky everywhere (depth 1), the box's front
    // face at view depth z.
    void draw(const fx::Camera& cam, bool box, double z) const {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        const GLfloat sky[4] = {kSky.r, kSky.g, kSky.b, kSky.a}, red[4] = {kBox.r, kBox.g, kBox.b, kBox.a};
        const GLfloat far = 1.0f, near = window_depth(cam, z);
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, far, 0);
        if (!box) return;
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, kH / 4, kW / 2, kH / 2);
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, red);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, near, 0);
    }

    // The same frame drawn as a game draws it: cleared to the projection's far depth, the box a
    // quad at view depth z rasterised through `projection` with its clip control and depth test.
    // Leaves the game's clip control and depth function set (cellfx must not depend on them).
    void draw_geometry(const fx::Camera& cam, const GameProjection& p, double z) const {
        glClipControl(GL_LOWER_LEFT, p.clip_depth);
        glDepthFunc(p.depth_func);
        const GLfloat sky[4] = {kSky.r, kSky.g, kSky.b, kSky.a};
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, p.clear_depth, 0);
        // The box's corners in view space: NDC x in [-1, 0], y in [-0.5, 0.5] at depth z.
        const double ty = std::tan(glm::radians(cam.fov_y_degrees) / 2.0) * z, tx = ty * double(kW) / kH;
        const glm::dvec4 corners[4] = {{-tx, -0.5 * ty, -z, 1}, {0, -0.5 * ty, -z, 1}, {-tx, 0.5 * ty, -z, 1}, {0, 0.5 * ty, -z, 1}};
        std::string vs = "#version 450 core\nconst vec4 p[4] = vec4[4](";
        for (int k = 0; k < 4; ++k) {
            const glm::dvec4 c = p.projection * corners[k];
            vs += "vec4(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ", " + std::to_string(c.z) + ", " +
                  std::to_string(c.w) + ")" + (k < 3 ? ", " : "");
        }
        vs += ");\nvoid main() { gl_Position = p[gl_VertexID]; }\n";
        const std::string fs = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(" + std::to_string(kBox.r) + ", " +
                               std::to_string(kBox.g) + ", " + std::to_string(kBox.b) + ", 1.0); }\n";
        const GLuint program = glCreateProgram();
        for (auto [stage, text] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
            const GLuint shader = glCreateShader(stage);
            const char* source = text.c_str();
            glShaderSource(shader, 1, &source, nullptr);
            glCompileShader(shader);
            glAttachShader(program, shader);
            glDeleteShader(shader);
        }
        glLinkProgram(program);
        GLuint vao = 0;
        glCreateVertexArrays(1, &vao);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        glViewport(0, 0, kW, kH);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glUseProgram(program);
        glBindVertexArray(vao);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        glBindVertexArray(0);
        glUseProgram(0);
        glDisable(GL_DEPTH_TEST);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glDeleteVertexArrays(1, &vao);
        glDeleteProgram(program);
    }

    // The colour, resolved when multisampled.
    fx::Image read() const {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        GLuint source = color, resolved = 0, resolve_fb = 0;
        if (samples > 1) {
            glCreateTextures(GL_TEXTURE_2D, 1, &resolved);
            glTextureStorage2D(resolved, 1, GL_RGBA32F, kW, kH);
            glCreateFramebuffers(1, &resolve_fb);
            glNamedFramebufferTexture(resolve_fb, GL_COLOR_ATTACHMENT0, resolved, 0);
            glBlitNamedFramebuffer(framebuffer, resolve_fb, 0, 0, kW, kH, 0, 0, kW, kH, GL_COLOR_BUFFER_BIT, GL_NEAREST);
            source = resolved;
        }
        fx::Image image(kW, kH);
        glGetTextureImage(source, 0, GL_RGBA, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(glm::vec4)), image.pixels.data());
        if (samples > 1) {
            glDeleteFramebuffers(1, &resolve_fb);
            glDeleteTextures(1, &resolved);
        }
        return image;
    }
};

// The campfire of `scene` by the scan-line reference (emission) over the game's sky, with the
// box (in front of all of the fire) where it stands: what the game's frame must show.
inline fx::Image expected_frame(cellfx::Module& fx, const fx::Camera& cam, std::size_t* hidden = nullptr,
                                std::size_t* beside = nullptr) {
    const fx::Effect& fire = *fx.effect<fx::Campfire>("fire");
    const fx::CellMesh world = effects_test::world_mesh(fire);
    fx::ScanlineOptions so;
    so.model = fx::OpticalModel::Emission;
    const terrain::EffectSpec& spec = fx.scene().effects[0];
    const fx::TransferFunction tf = terrain::drawn_transfer_function(spec.transfer_function, spec.extinction_scale, {0.0f, 1.0f});
    const fx::Image light = fx::ScanlineRenderer(world).render(cam, kW, kH, world.scalars[0], tf, so);
    fx::Image expected(kW, kH);
    std::size_t h = 0, b = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const glm::vec3 fire_light(light.at(x, y));
            const bool lit = fire_light.r > 0.02f;
            if (in_box(x, y)) {
                expected.at(x, y) = kBox;
                h += lit;
            } else {
                expected.at(x, y) = glm::vec4(glm::vec3(kSky) + fire_light, 1.0f);
                b += lit;
            }
        }
    if (hidden) *hidden = h;
    if (beside) *beside = b;
    return expected;
}

// The largest difference from the box colour inside the box: 0 when not a trace of fire is on it.
inline float box_error(const fx::Image& frame) {
    float e = 0.0f;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            if (in_box(x, y)) e = std::max(e, glm::length(frame.at(x, y) - kBox));
    return e;
}

} // namespace embedding_test
