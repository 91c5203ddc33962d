// cellfx inside a host application's own window: a GLFW window with an OpenGL 4.5 core
// context, as a game makes it. Run under Xvfb (ctest starts it through xvfb-run), so it needs
// no display of its own.
//
// What a game relies on: CellRenderer::render() draws into the framebuffer the game has bound
// (here the window's default framebuffer, inside a viewport that is not the whole window),
// composites over what the game drew, and leaves every piece of GL state the game set as it
// was. The picture must equal the headless one composited over the same background.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include "fx/cell_renderer.hpp"
#include "fx/image.hpp"
#include "gl_fixture.hpp"
#include "glfw_test_window.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace {

// The host state a game typically leaves set between its own draws, read back as numbers.
std::vector<double> host_state() {
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
    for (GLenum cap : {GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_SCISSOR_TEST}) v.push_back(glIsEnabled(cap));
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
    ints(GL_ACTIVE_TEXTURE, 1);
    ints(GL_TEXTURE_BINDING_2D, 1);
    ints(GL_DRAW_FRAMEBUFFER_BINDING, 1);
    ints(GL_READ_FRAMEBUFFER_BINDING, 1);
    ints(GL_UNPACK_ALIGNMENT, 1);
    ints(GL_PACK_ALIGNMENT, 1);
    floats(GL_COLOR_CLEAR_VALUE, 4);
    return v;
}

} // namespace

TEST_CASE("renders into a GLFW window's framebuffer and leaves the host's GL state as it was", "[window]") {
    constexpr int kWidth = 96, kHeight = 72;
    const fx::Viewport viewport{16, 8, 64, 56}; // not the whole window: offsets must be honoured
    const fx_test::GlfwWindow window(kWidth, kHeight, "cellfx host window test");

    const glm::dvec3 lo(0.0), hi(1.0);
    fx::CellMesh mesh = fx_test::hex_box(3, 3, 3, lo, hi);
    fx::ScalarField field{"s", {}};
    for (const glm::dvec3& p : mesh.points) field.values.push_back(float(0.2 + 0.5 * p.x + 0.3 * p.z));
    mesh.scalars.push_back(field);
    const fx::TransferFunction tf = fx::TransferFunction::constant({0.9, 0.8, 0.5}, 1.2);
    fx::Camera camera;
    camera.eye = {2.4, -1.7, 1.8};
    camera.target = {0.5, 0.5, 0.5};
    camera.up = {0.0, 0.0, 1.0};
    camera.fov_y_degrees = 40.0;
    fx::CellRenderOptions options;
    options.fog = true;

    fx::CellRenderer renderer(mesh, "s", tf);
    // The headless result of the same frame: premultiplied colour and alpha.
    const fx::Image offscreen = renderer.render_to_image(camera, viewport.width, viewport.height,
                                                         fx::RenderPath::PcpExact, options);

    // The game's frame so far: a cleared background, and its own state left set.
    const glm::vec3 background(0.2f, 0.3f, 0.4f);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, kWidth, kHeight);
    glClearColor(background.r, background.g, background.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    GLuint host_vao = 0, host_buffer = 0, host_texture = 0;
    glCreateVertexArrays(1, &host_vao);
    glCreateBuffers(1, &host_buffer);
    glCreateTextures(GL_TEXTURE_2D, 1, &host_texture);
    glBindVertexArray(host_vao);
    glBindBuffer(GL_ARRAY_BUFFER, host_buffer);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, host_texture);
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
    fx_test::require_no_gl_error();
    const std::vector<double> before = host_state();

    const fx::CellRenderStats stats = renderer.render(camera, viewport, fx::RenderPath::PcpExact, options);
    fx_test::require_no_gl_error();
    CHECK(stats.draw_calls > 0);
    CHECK(host_state() == before);

    // Read the window back (the back buffer, before any swap), tightly packed.
    std::vector<unsigned char> rgba(std::size_t(kWidth) * kHeight * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, kWidth, kHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 8);
    fx_test::require_no_gl_error();
    fx::Image window_image(kWidth, kHeight), expected(kWidth, kHeight, glm::vec4(background, 1.0f));
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const unsigned char* p = &rgba[(std::size_t(y) * kWidth + x) * 4];
            window_image.at(x, y) = glm::vec4(p[0], p[1], p[2], 255.0f) / 255.0f;
        }
    for (int y = 0; y < viewport.height; ++y)
        for (int x = 0; x < viewport.width; ++x) {
            const glm::vec4 c = offscreen.at(x, y);
            expected.at(viewport.x + x, viewport.y + y) = glm::vec4(glm::vec3(c) + (1.0f - c.a) * background, 1.0f);
        }
    fx::write_png(window_image, fx_test::output_path("host_window_screenshot.png"));

    // The window is 8 bits per channel: half a step of rounding, plus a little for the
    // composite being done in the window's unorm format rather than in float.
    float inside = 0.0f;
    for (const glm::vec4& c : offscreen.pixels) inside = std::max(inside, c.a);
    REQUIRE(inside > 0.3f); // the fog box is in the picture, not a blank frame
    fx_test::check_image("host_window", window_image, expected,
                         verify::same_picture(1.5 / 255.0, "8 bits a channel: half a step, the composite in unorm"));

    glDeleteTextures(1, &host_texture);
    glDeleteBuffers(1, &host_buffer);
    glDeleteVertexArrays(1, &host_vao);
}
