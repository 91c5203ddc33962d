// The embedding API (cellfx/cellfx.hpp) inside a game's own GLFW window with an OpenGL 4.5 core
// context, run under Xvfb (ctest starts it through xvfb-run). The game clears its window and
// leaves its state set; cellfx::Module draws a campfire scene into a viewport of the window's
// default framebuffer. The picture must equal the headless one over the same background, and
// every piece of the game's GL state must be as it was.
#include <catch2/catch.hpp>

#include <vector>

#include <epoxy/gl.h>

#include "cellfx/cellfx.hpp"
#include "glfw_test_window.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

TEST_CASE("cellfx::Module draws into a GLFW window's frame and leaves the game's GL state as it was", "[window]") {
    constexpr int kWidth = 96, kHeight = 72;
    const fx::Viewport viewport{16, 8, 64, 56}; // not the whole window: offsets must be honoured
    const fx_test::GlfwWindow window(kWidth, kHeight, "cellfx embedding test");
    const glm::vec3 sky(0.05f, 0.07f, 0.12f);

    cellfx::Module fx;
    fx.init(cellfx::Config(fx_test::source_path("content/scenes/campfire.json"), viewport.width, viewport.height));
    fx.set_terrain_drawn(false); // effects only: the game owns the ground
    fx.set_time(0.8);
    const fx::Camera camera = fx.scene_camera();

    // The headless result of the same frame, over the same sky, in an offscreen target.
    fx::Image offscreen(viewport.width, viewport.height);
    {
        GLuint fb = 0, color = 0;
        glCreateFramebuffers(1, &fb);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glTextureStorage2D(color, 1, GL_RGBA32F, viewport.width, viewport.height);
        glNamedFramebufferTexture(fb, GL_COLOR_ATTACHMENT0, color, 0);
        const GLfloat c[4] = {sky.r, sky.g, sky.b, 1.0f};
        glClearNamedFramebufferfv(fb, GL_COLOR, 0, c);
        fx.update(0.0, camera);
        fx.render({fb, {0, 0, viewport.width, viewport.height}, 0});
        glGetTextureImage(color, 0, GL_RGBA, GL_FLOAT, GLsizei(offscreen.pixels.size() * sizeof(glm::vec4)),
                          offscreen.pixels.data());
        glDeleteTextures(1, &color);
        glDeleteFramebuffers(1, &fb);
    }

    // The game's frame so far: a cleared window, and its own state left set.
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, kWidth, kHeight);
    glClearColor(sky.r, sky.g, sky.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    effects_test::HostLeftovers leftovers;
    fx_test::require_no_gl_error();
    const std::vector<double> before = effects_test::host_state();

    fx.update(0.0, camera);
    fx.render({0, viewport, 0});
    fx_test::require_no_gl_error();
    CHECK(effects_test::host_state() == before);
    CHECK(fx.stats().find("fire")->cells_drawn > 0);

    // Read the window back (the back buffer, before any swap), tightly packed.
    std::vector<unsigned char> rgba(std::size_t(kWidth) * kHeight * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, kWidth, kHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 8);
    fx_test::require_no_gl_error();
    fx::Image screenshot(kWidth, kHeight), expected(kWidth, kHeight, glm::vec4(sky, 1.0f));
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const unsigned char* p = &rgba[(std::size_t(y) * kWidth + x) * 4];
            screenshot.at(x, y) = glm::vec4(p[0], p[1], p[2], 255.0f) / 255.0f;
        }
    float brightest = 0.0f;
    for (int y = 0; y < viewport.height; ++y)
        for (int x = 0; x < viewport.width; ++x) {
            const glm::vec4 c = offscreen.at(x, y);
            expected.at(viewport.x + x, viewport.y + y) = glm::vec4(glm::min(glm::vec3(c), glm::vec3(1.0f)), 1.0f);
            brightest = std::max(brightest, c.r);
        }
    fx::write_png(screenshot, fx_test::output_path("embedding_window_screenshot.png"));
    REQUIRE(brightest > 0.5f); // the fire is in the picture, not a blank frame

    // The window is 8 bits per channel: half a step of rounding, plus a little for the
    // composite being done in the window's unorm format rather than in float.
    fx_test::check_image("embedding_window", screenshot, expected,
                         verify::same_picture(1.5 / 255.0, "8 bits a channel: half a step, the composite in unorm"));
    fx.shutdown(); // while the context is current
}
