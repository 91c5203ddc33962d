// The consumer games' shared half: the game's own headless GL context (EGL; cellfx installs no
// context of its own: it draws into whatever context the game has current), a "game" frame (its own framebuffer with a colour
// texture and a depth texture), a campfire scene built in code (no files: an installed cellfx
// has no content folder), the game's own GL state (a caching renderer's bindings) and its check.
#pragma once

#include <cstdio>
#include <cstring>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>

#include "cellfx/cellfx.hpp"

// The game's own fx and terrain namespaces, with names cellfx once declared at the top level
// (fx::Error, terrain::Scene): cellfx declares everything under cellfx::, so they do not clash.
namespace fx {
struct Error {
    const char* what = nullptr;
};
} // namespace fx
namespace terrain {
struct Scene {
    int tiles = 64;
};
} // namespace terrain

namespace game {

constexpr int kWidth = 160, kHeight = 120;

// The game's GL 4.5 core context with no window: EGL's surfaceless platform (Mesa), else the
// default display, made current on this thread. ok() is false (with the failing step printed)
// when neither gives one.
class Context {
public:
    Context() {
        const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (client && std::strstr(client, "EGL_MESA_platform_surfaceless"))
            display_ = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display_ == EGL_NO_DISPLAY) display_ = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        EGLint major = 0, minor = 0;
        if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, &major, &minor)) {
            step("eglInitialize");
            return;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            step("eglBindAPI");
            return;
        }
        // No surface is made, but the config names a surface type: EGL's default (windows) has no
        // config on a surfaceless display.
        const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        if (!eglChooseConfig(display_, config_attribs, &config, 1, &configs) || configs == 0) {
            step("eglChooseConfig (OpenGL, pbuffer)");
            return;
        }
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, attribs);
        if (context_ == EGL_NO_CONTEXT) {
            step("eglCreateContext (OpenGL 4.5 core)");
            return;
        }
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) step("eglMakeCurrent (no surface)");
        else ok_ = true;
    }
    ~Context() {
        if (context_ != EGL_NO_CONTEXT) {
            eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display_, context_);
        }
        if (display_ != EGL_NO_DISPLAY) eglTerminate(display_);
    }
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;
    bool ok() const { return ok_; }

private:
    void step(const char* what) { std::fprintf(stderr, "game: no GL context: %s failed (EGL error 0x%x)\n", what, unsigned(eglGetError())); }
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
    bool ok_ = false;
};

inline cellfx::Scene campfire_scene() {
    cellfx::Scene scene;
    cellfx::EffectSpec fire;
    fire.name = "fire";
    fire.params = cellfx::fx::CampfireParams{};
    // Black to red to yellow-white, sigma rising with temperature (normalized: mapped onto [0, 1]).
    fire.transfer_function = cellfx::fx::TransferFunction({{0.0, {0.0, 0.0, 0.0}, 0.0},
                                                           {0.5, {1.0, 0.25, 0.05}, 4.0},
                                                           {1.0, {1.0, 0.9, 0.5}, 12.0}},
                                                          true);
    fire.extinction_scale = 0.2;
    scene.effects.push_back(fire);
    scene.camera.eye = {1.6, -2.4, 1.2};
    scene.camera.target = {0.0, 0.0, 0.6};
    scene.camera.up = {0.0, 0.0, 1.0};
    return scene;
}

// The game's view of the fire (z up), as its engine would hold it: a view matrix.
inline glm::dmat4 view_matrix() { return glm::lookAt(glm::dvec3(1.6, -2.4, 1.2), glm::dvec3(0.0, 0.0, 0.6), glm::dvec3(0, 0, 1)); }

struct Frame {
    GLuint framebuffer = 0, color = 0, depth = 0;
    Frame() {
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glTextureStorage2D(color, 1, GL_RGBA8, kWidth, kHeight);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT32F, kWidth, kHeight);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth, 0);
    }
    ~Frame() {
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
    Frame(const Frame&) = delete;
    Frame& operator=(const Frame&) = delete;
    bool complete() const { return glCheckNamedFramebufferStatus(framebuffer, GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE; }
    // The game's opaque pass: a dark sky, nothing in front of the fire (depth 1).
    void clear() const {
        const GLfloat sky[4] = {0.1f, 0.15f, 0.2f, 1.0f};
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    }
    // Pixels brighter than the sky in red by 0.2: the fire's.
    int fire_pixels() const {
        std::vector<unsigned char> rgba(std::size_t(kWidth) * std::size_t(kHeight) * 4u);
        glGetTextureImage(color, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
        int lit = 0;
        for (std::size_t i = 0; i < rgba.size(); i += 4) lit += rgba[i] > 26 + 51 ? 1 : 0;
        return lit;
    }
};

// Bindings a caching renderer keeps between its draws: a cube map on unit 3, a VAO, a clip
// control for reversed-Z. They must be as they were after cellfx's render().
struct GameState {
    GLuint cube = 0, vao = 0;
    GameState() {
        glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &cube);
        glTextureStorage2D(cube, 1, GL_RGBA8, 4, 4);
        glCreateVertexArrays(1, &vao);
        glBindTextureUnit(3, cube);
        glBindVertexArray(vao);
        glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    }
    ~GameState() {
        glBindVertexArray(0);
        glBindTextureUnit(3, 0);
        glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
        glDeleteTextures(1, &cube);
        glDeleteVertexArrays(1, &vao);
    }
    GameState(const GameState&) = delete;
    GameState& operator=(const GameState&) = delete;
    bool intact() const {
        GLint bound_cube = 0, bound_vao = 0, depth_mode = 0;
        glActiveTexture(GL_TEXTURE3);
        glGetIntegerv(GL_TEXTURE_BINDING_CUBE_MAP, &bound_cube);
        glActiveTexture(GL_TEXTURE0);
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &bound_vao);
        glGetIntegerv(GL_CLIP_DEPTH_MODE, &depth_mode);
        return GLuint(bound_cube) == cube && GLuint(bound_vao) == vao && depth_mode == GL_ZERO_TO_ONE;
    }
};

inline int fail(const char* what) {
    std::fprintf(stderr, "cellfx consumer game: %s\n", what);
    return 1;
}

} // namespace game
