// The GL foundation: headless context, object wrappers, state guard, render target, shader
// library (#include, #define prelude, #line error mapping) and the composite pass.
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "gl/composite_pass.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl/shader_library.hpp"
#include "gl/state_guard.hpp"
#include "gl_fixture.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using Catch::Matchers::Contains;

namespace {

std::string read_text(const std::string& relative) {
    std::ifstream in(fx_test::source_path(relative), std::ios::binary);
    REQUIRE(in.good());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// 1-based line of the first line containing `marker`.
int marker_line(const std::string& text, const std::string& marker) {
    std::istringstream in(text);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
        if (line.find(marker) != std::string::npos)
            return n;
    FAIL("marker " << marker << " not found");
    return 0;
}

// builtin() plus every file of tests/shaders/, under the name an #include uses.
fx::gl::ShaderLibrary test_library() {
    fx::gl::ShaderLibrary lib = fx::gl::ShaderLibrary::builtin();
    for (const char* name : {"broken.frag", "constants.glsl", "broken_include.glsl", "nested_include.glsl",
                             "include_error.frag", "error_after_include.frag"}) {
        const std::string path = std::string("tests/shaders/") + name;
        lib.add(name, read_text(path), path);
    }
    return lib;
}

std::string compile_error(const fx::gl::ShaderLibrary& lib, const std::string& name,
                          const fx::gl::Defines& defines = {}) {
    try {
        lib.compile(name, defines);
    } catch (const fx::Error& e) {
        return e.what();
    }
    FAIL(name << " compiled although it has an error");
    return {};
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Headless context

TEST_CASE("headless context is OpenGL 4.5 core", "[gl]") {
    fx::HeadlessContext& context = fx_test::gl_context();
    INFO(context.description());
    CHECK(context.is_current());
    CHECK(context.platform() != fx::EglPlatform::Auto);
    CHECK_FALSE(context.renderer().empty());
    GLint major = 0, minor = 0, profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    CHECK(major * 10 + minor >= 45);
    CHECK((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0);
    // No window system: there is no default framebuffer to draw into.
    GLint fbo = -1;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fbo);
    CHECK(fbo == 0);
    fx_test::require_no_gl_error();
}

TEST_CASE("a second headless context moves, switches and leaves the first usable", "[gl]") {
    fx::HeadlessContext& first = fx_test::gl_context();
    {
        fx::HeadlessContextOptions options;
        options.platform = first.platform(); // what works on this machine
        fx::HeadlessContext second(options);
        CHECK(second.is_current());
        CHECK_FALSE(first.is_current());
        fx::HeadlessContext moved = std::move(second);
        CHECK(moved.is_current());
        CHECK_THROWS_AS(second.make_current(), fx::Error);
        first.make_current();
        CHECK(first.is_current());
        moved.make_current();
    } // destroys the current context; the shared EGL display must stay initialised for `first`
    fx_test::gl_context();
    CHECK(first.is_current());
    fx::gl::Buffer buffer = fx::gl::make_buffer(16, nullptr);
    CHECK(glIsBuffer(buffer.id()) == GL_TRUE);
    fx_test::require_no_gl_error();
}

TEST_CASE("CELLFX_EGL_PLATFORM with a bad value is a clear error", "[gl]") {
    fx_test::gl_context();
    const char* old = std::getenv("CELLFX_EGL_PLATFORM");
    const std::string saved = old ? old : "";
    setenv("CELLFX_EGL_PLATFORM", "wayland", 1);
    std::string message;
    try {
        fx::HeadlessContext context;
    } catch (const fx::Error& e) {
        message = e.what();
    }
    if (old)
        setenv("CELLFX_EGL_PLATFORM", saved.c_str(), 1);
    else
        unsetenv("CELLFX_EGL_PLATFORM");
    CHECK_THAT(message, Contains("CELLFX_EGL_PLATFORM=wayland") && Contains("surfaceless"));
    fx_test::gl_context();
}

// ---------------------------------------------------------------------------------------------
// Wrappers

template <class T>
constexpr bool move_only_v = !std::is_copy_constructible_v<T> && !std::is_copy_assignable_v<T> &&
                             std::is_nothrow_move_constructible_v<T> && std::is_nothrow_move_assignable_v<T>;

TEST_CASE("GL wrappers are move-only", "[gl]") {
    STATIC_REQUIRE(!std::is_copy_constructible_v<fx::gl::Buffer>);
    STATIC_REQUIRE(move_only_v<fx::gl::Buffer>);
    STATIC_REQUIRE(move_only_v<fx::gl::VertexArray>);
    STATIC_REQUIRE(move_only_v<fx::gl::Texture>);
    STATIC_REQUIRE(move_only_v<fx::gl::Sampler>);
    STATIC_REQUIRE(move_only_v<fx::gl::Framebuffer>);
    STATIC_REQUIRE(move_only_v<fx::gl::Renderbuffer>);
    STATIC_REQUIRE(move_only_v<fx::gl::Program>);
    STATIC_REQUIRE(move_only_v<fx::gl::Shader>);
    STATIC_REQUIRE(move_only_v<fx::gl::Query>);
    STATIC_REQUIRE(move_only_v<fx::gl::RenderTarget>);
    STATIC_REQUIRE(move_only_v<fx::gl::CompositePass>);
    STATIC_REQUIRE(move_only_v<fx::HeadlessContext>);
    STATIC_REQUIRE(!std::is_copy_constructible_v<fx::gl::StateGuard>);
    STATIC_REQUIRE(!std::is_move_constructible_v<fx::gl::StateGuard>);
}

namespace {

// Ownership rules for one wrapper type: `make` creates a fresh object, `raw` creates a bare GL
// name, `is` is glIsX, `destroy_raw` deletes a bare name.
template <class W>
void check_ownership(const std::function<W()>& make, const std::function<GLuint()>& raw,
                     const std::function<bool(GLuint)>& is, const std::function<void(GLuint)>& destroy_raw) {
    GLuint id = 0;
    {
        W a = make();
        id = a.id();
        REQUIRE(id != 0);
        CHECK(a.owned());
        CHECK(is(id));
        W b = std::move(a); // move construction transfers the name
        CHECK(a.id() == 0);
        CHECK_FALSE(a);
        CHECK(b.id() == id);
        CHECK(is(id));

        W c = make();
        const GLuint replaced = c.id();
        c = std::move(b); // move assignment deletes what c held
        CHECK(c.id() == id);
        CHECK(b.id() == 0);
        CHECK_FALSE(is(replaced));
        CHECK(is(id));
    }
    CHECK_FALSE(is(id)); // the destructor deleted it

    const GLuint host = raw();
    {
        W wrapped = W::wrap(host);
        CHECK(wrapped.id() == host);
        CHECK_FALSE(wrapped.owned());
        W moved = std::move(wrapped); // still not owned after a move
        CHECK_FALSE(moved.owned());
    }
    CHECK(is(host)); // a wrapped (host) object is never deleted
    destroy_raw(host);

    GLuint released = 0;
    {
        W r = make();
        released = r.release();
        CHECK(r.id() == 0);
    }
    CHECK(is(released)); // release() handed the name over
    destroy_raw(released);
    CHECK_FALSE(is(released));
    fx_test::require_no_gl_error();
}

} // namespace

TEST_CASE("GL wrappers delete what they own and never what they wrap", "[gl]") {
    fx_test::gl_context();
    using namespace fx::gl;
    SECTION("Buffer") {
        check_ownership<Buffer>([] { return Buffer::create(); },
                                [] { GLuint i = 0; glCreateBuffers(1, &i); return i; },
                                [](GLuint i) { return glIsBuffer(i) == GL_TRUE; },
                                [](GLuint i) { glDeleteBuffers(1, &i); });
    }
    SECTION("VertexArray") {
        check_ownership<VertexArray>([] { return VertexArray::create(); },
                                     [] { GLuint i = 0; glCreateVertexArrays(1, &i); return i; },
                                     [](GLuint i) { return glIsVertexArray(i) == GL_TRUE; },
                                     [](GLuint i) { glDeleteVertexArrays(1, &i); });
    }
    SECTION("Texture") {
        check_ownership<Texture>([] { return Texture::create(GL_TEXTURE_3D); },
                                 [] { GLuint i = 0; glCreateTextures(GL_TEXTURE_2D, 1, &i); return i; },
                                 [](GLuint i) { return glIsTexture(i) == GL_TRUE; },
                                 [](GLuint i) { glDeleteTextures(1, &i); });
    }
    SECTION("Sampler") {
        check_ownership<Sampler>([] { return Sampler::create(); },
                                 [] { GLuint i = 0; glCreateSamplers(1, &i); return i; },
                                 [](GLuint i) { return glIsSampler(i) == GL_TRUE; },
                                 [](GLuint i) { glDeleteSamplers(1, &i); });
    }
    SECTION("Framebuffer") {
        check_ownership<Framebuffer>([] { return Framebuffer::create(); },
                                     [] { GLuint i = 0; glCreateFramebuffers(1, &i); return i; },
                                     [](GLuint i) { return glIsFramebuffer(i) == GL_TRUE; },
                                     [](GLuint i) { glDeleteFramebuffers(1, &i); });
    }
    SECTION("Renderbuffer") {
        check_ownership<Renderbuffer>([] { return make_renderbuffer(GL_DEPTH_COMPONENT32F, 4, 4); },
                                      [] { GLuint i = 0; glCreateRenderbuffers(1, &i); return i; },
                                      [](GLuint i) { return glIsRenderbuffer(i) == GL_TRUE; },
                                      [](GLuint i) { glDeleteRenderbuffers(1, &i); });
    }
    SECTION("Program") {
        check_ownership<Program>([] { return Program::create(); }, [] { return glCreateProgram(); },
                                 [](GLuint i) { return glIsProgram(i) == GL_TRUE; },
                                 [](GLuint i) { glDeleteProgram(i); });
    }
    SECTION("Shader") {
        check_ownership<Shader>([] { return Shader::create(GL_FRAGMENT_SHADER); },
                                [] { return glCreateShader(GL_VERTEX_SHADER); },
                                [](GLuint i) { return glIsShader(i) == GL_TRUE; },
                                [](GLuint i) { glDeleteShader(i); });
    }
    SECTION("Query") {
        check_ownership<Query>([] { return Query::create(GL_TIME_ELAPSED); },
                               [] { GLuint i = 0; glCreateQueries(GL_SAMPLES_PASSED, 1, &i); return i; },
                               [](GLuint i) { return glIsQuery(i) == GL_TRUE; },
                               [](GLuint i) { glDeleteQueries(1, &i); });
    }
}

TEST_CASE("make_buffer and make_texture_2d allocate immutable storage", "[gl]") {
    fx_test::gl_context();
    const float data[4] = {1.0f, 2.0f, 3.0f, 4.0f};
    fx::gl::Buffer buffer = fx::gl::make_buffer(sizeof data, data, GL_DYNAMIC_STORAGE_BIT);
    GLint64 size = 0;
    GLint immutable = 0;
    glGetNamedBufferParameteri64v(buffer.id(), GL_BUFFER_SIZE, &size);
    glGetNamedBufferParameteriv(buffer.id(), GL_BUFFER_IMMUTABLE_STORAGE, &immutable);
    CHECK(size == static_cast<GLint64>(sizeof data));
    CHECK(immutable == GL_TRUE);
    float back[4] = {};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof back, back);
    CHECK(back[3] == 4.0f);

    fx::gl::Texture texture = fx::gl::make_texture_2d(GL_RGBA16F, 5, 3);
    GLint w = 0, h = 0, format = 0;
    glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_HEIGHT, &h);
    glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    CHECK(w == 5);
    CHECK(h == 3);
    CHECK(format == GL_RGBA16F);
    CHECK_THROWS_AS(fx::gl::make_texture_2d(GL_RGBA8, 0, 3), fx::Error);
    CHECK_THROWS_AS(fx::gl::make_buffer(0, nullptr), fx::Error);
    fx_test::require_no_gl_error();
}

// ---------------------------------------------------------------------------------------------
// Debug checks

TEST_CASE("check_gl_errors names the call site and drains the error flags", "[gl]") {
    fx_test::gl_context();
    CHECK_NOTHROW(fx::gl::check_gl_errors("glFinish", "render.cpp", 7));
    glEnable(0x7FFF); // not a capability: GL_INVALID_ENUM
    std::string message;
    try {
        fx::gl::check_gl_errors("glEnable(0x7FFF)", "render.cpp", 42);
    } catch (const fx::Error& e) {
        message = e.what();
    }
    CHECK_THAT(message, Contains("render.cpp:42: glEnable(0x7FFF) failed") && Contains("GL_INVALID_ENUM"));
    CHECK(glGetError() == GL_NO_ERROR);
}

// ---------------------------------------------------------------------------------------------
// State guard

namespace {

struct StateItem {
    std::string name;
    std::function<void()> host;                // the host's unusual value
    std::function<void()> ours;                // what a render path might set instead
    std::function<std::vector<double>()> read; // queried independently of StateGuard
};

std::vector<double> get_ints(GLenum name, int n = 1) {
    std::vector<GLint> v(static_cast<std::size_t>(n), 0);
    glGetIntegerv(name, v.data());
    return {v.begin(), v.end()};
}
std::vector<double> get_floats(GLenum name, int n = 1) {
    std::vector<GLfloat> v(static_cast<std::size_t>(n), 0.0f);
    glGetFloatv(name, v.data());
    return {v.begin(), v.end()};
}
std::vector<double> get_int_i(GLenum name, GLuint index, int n = 1) {
    std::vector<GLint> v(static_cast<std::size_t>(n), 0);
    glGetIntegeri_v(name, index, v.data());
    return {v.begin(), v.end()};
}
std::vector<double> enabled(GLenum cap) { return {static_cast<double>(glIsEnabled(cap))}; }
std::vector<double> enabled_i(GLenum cap, GLuint i) { return {static_cast<double>(glIsEnabledi(cap, i))}; }
void set_cap(GLenum cap, bool on) { on ? glEnable(cap) : glDisable(cap); }

} // namespace

TEST_CASE("StateGuard restores every item it promises", "[gl]") {
    // A context of its own: the host state set here must not leak into later tests.
    fx::HeadlessContextOptions options;
    options.platform = fx_test::gl_context().platform();
    fx::HeadlessContext context(options);
    {
        using namespace fx::gl;
        GLint max_viewports = 0, max_draw_buffers = 0, ubo_align = 0, ssbo_align = 0;
        glGetIntegerv(GL_MAX_VIEWPORTS, &max_viewports);
        glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_draw_buffers);
        glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &ubo_align);
        glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &ssbo_align);
        REQUIRE(max_viewports >= 2);
        REQUIRE(max_draw_buffers >= 2);

        // Objects for bindings: one set for the host, one for "us".
        RenderTarget host_target = RenderTarget::create(8, 8, ColorFormat::RGBA8, false);
        RenderTarget our_target = RenderTarget::create(8, 8, ColorFormat::RGBA8, false);
        Framebuffer host_read = Framebuffer::create();
        const ShaderLibrary& lib = ShaderLibrary::builtin();
        Program host_program = lib.link({"fullscreen.vert", "composite.frag"}, {{"UNIFORM_BACKGROUND", "0"}});
        Program our_program = lib.link({"fullscreen.vert", "composite.frag"}, {{"COMPOSITE_OVER_FRAMEBUFFER", "1"}, {"UNIFORM_BACKGROUND", "0"}});
        VertexArray host_vao = VertexArray::create(), our_vao = VertexArray::create();
        Buffer host_buf = make_buffer(4096, nullptr), our_buf = make_buffer(4096, nullptr);
        Buffer host_buf2 = make_buffer(4096, nullptr);
        const GLenum targets[4] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_BUFFER};
        std::vector<Texture> host_tex, our_tex;
        for (int unit = 0; unit < StateGuard::kUnits; ++unit)
            for (GLenum t : targets) {
                host_tex.push_back(Texture::create(t));
                our_tex.push_back(Texture::create(t));
            }
        std::vector<Sampler> host_samplers, our_samplers;
        for (int unit = 0; unit < StateGuard::kUnits; ++unit) {
            host_samplers.push_back(Sampler::create());
            our_samplers.push_back(Sampler::create());
        }
        fx_test::require_no_gl_error();

        std::vector<StateItem> items;
        auto add = [&](std::string name, std::function<void()> host, std::function<void()> ours,
                       std::function<std::vector<double>()> read) {
            items.push_back({std::move(name), std::move(host), std::move(ours), std::move(read)});
        };
        const GLuint hf = host_target.framebuffer(), of = our_target.framebuffer();
        add("draw framebuffer", [=] { glBindFramebuffer(GL_DRAW_FRAMEBUFFER, hf); },
            [&our_target] { our_target.bind_for_drawing(); }, [] { return get_ints(GL_DRAW_FRAMEBUFFER_BINDING); });
        add("read framebuffer", [&] { glBindFramebuffer(GL_READ_FRAMEBUFFER, host_read.id()); },
            [=] { glBindFramebuffer(GL_READ_FRAMEBUFFER, of); }, [] { return get_ints(GL_READ_FRAMEBUFFER_BINDING); });
        for (GLuint i = 0; i < 2; ++i) {
            const float k = static_cast<float>(i + 1);
            add("viewport " + std::to_string(i), [=] { glViewportIndexedf(i, 3.5f * k, 4.0f, 17.0f, 9.0f * k); },
                [] { glViewport(0, 0, 8, 8); },
                [=] { std::vector<GLfloat> v(4); glGetFloati_v(GL_VIEWPORT, i, v.data());
                      return std::vector<double>(v.begin(), v.end()); });
            add("scissor box " + std::to_string(i), [=] { glScissorIndexed(i, 1, 2 * static_cast<GLint>(i), 5, 6); },
                [] { glScissor(0, 0, 8, 8); }, [=] { return get_int_i(GL_SCISSOR_BOX, i, 4); });
            add("scissor test " + std::to_string(i), [=] { i == 0 ? glEnablei(GL_SCISSOR_TEST, i) : glDisablei(GL_SCISSOR_TEST, i); },
                [=] { i == 0 ? glDisablei(GL_SCISSOR_TEST, i) : glEnablei(GL_SCISSOR_TEST, i); },
                [=] { return enabled_i(GL_SCISSOR_TEST, i); });
            add("blend enable " + std::to_string(i), [=] { i == 0 ? glEnablei(GL_BLEND, i) : glDisablei(GL_BLEND, i); },
                [=] { i == 0 ? glDisablei(GL_BLEND, i) : glEnablei(GL_BLEND, i); }, [=] { return enabled_i(GL_BLEND, i); });
            add("blend func " + std::to_string(i),
                [=] { i == 0 ? glBlendFuncSeparatei(i, GL_SRC_COLOR, GL_DST_ALPHA, GL_ONE_MINUS_DST_COLOR, GL_CONSTANT_ALPHA)
                             : glBlendFuncSeparatei(i, GL_DST_COLOR, GL_SRC_ALPHA, GL_ZERO, GL_CONSTANT_COLOR); },
                [] { glBlendFunc(GL_ONE, GL_ONE); },
                [=] { std::vector<double> v;
                      for (GLenum n : {GL_BLEND_SRC_RGB, GL_BLEND_DST_RGB, GL_BLEND_SRC_ALPHA, GL_BLEND_DST_ALPHA})
                          v.push_back(get_int_i(n, i)[0]);
                      return v; });
            add("blend equation " + std::to_string(i),
                [=] { glBlendEquationSeparatei(i, i == 0 ? GL_MAX : GL_MIN, GL_FUNC_REVERSE_SUBTRACT); },
                [] { glBlendEquation(GL_FUNC_ADD); },
                [=] { return std::vector<double>{get_int_i(GL_BLEND_EQUATION_RGB, i)[0],
                                                 get_int_i(GL_BLEND_EQUATION_ALPHA, i)[0]}; });
            add("colour mask " + std::to_string(i),
                [=] { glColorMaski(i, GL_TRUE, GL_FALSE, static_cast<GLboolean>(i), GL_FALSE); },
                [] { glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE); },
                [=] { GLboolean m[4]; glGetBooleani_v(GL_COLOR_WRITEMASK, i, m);
                      return std::vector<double>{double(m[0]), double(m[1]), double(m[2]), double(m[3])}; });
        }
        add("blend colour", [] { glBlendColor(0.1f, 0.2f, 0.3f, 0.4f); }, [] { glBlendColor(0, 0, 0, 0); },
            [] { return get_floats(GL_BLEND_COLOR, 4); });
        add("clear colour", [] { glClearColor(0.5f, 0.25f, 0.125f, 0.75f); }, [] { glClearColor(0, 0, 0, 0); },
            [] { return get_floats(GL_COLOR_CLEAR_VALUE, 4); });
        add("clear depth", [] { glClearDepth(0.375); }, [] { glClearDepth(1.0); },
            [] { return get_floats(GL_DEPTH_CLEAR_VALUE); });
        add("depth func", [] { glDepthFunc(GL_GEQUAL); }, [] { glDepthFunc(GL_LESS); },
            [] { return get_ints(GL_DEPTH_FUNC); });
        add("depth mask", [] { glDepthMask(GL_FALSE); }, [] { glDepthMask(GL_TRUE); },
            [] { GLboolean m; glGetBooleanv(GL_DEPTH_WRITEMASK, &m); return std::vector<double>{double(m)}; });
        add("cull face mode", [] { glCullFace(GL_FRONT_AND_BACK); }, [] { glCullFace(GL_BACK); },
            [] { return get_ints(GL_CULL_FACE_MODE); });
        add("front face", [] { glFrontFace(GL_CW); }, [] { glFrontFace(GL_CCW); }, [] { return get_ints(GL_FRONT_FACE); });
        add("polygon mode", [] { glPolygonMode(GL_FRONT_AND_BACK, GL_LINE); },
            [] { glPolygonMode(GL_FRONT_AND_BACK, GL_POINT); }, [] { return get_ints(GL_POLYGON_MODE, 2); });
        add("polygon offset", [] { glPolygonOffset(2.5f, -3.0f); }, [] { glPolygonOffset(0.0f, 0.0f); },
            [] { auto f = get_floats(GL_POLYGON_OFFSET_FACTOR); f.push_back(get_floats(GL_POLYGON_OFFSET_UNITS)[0]);
                 return f; });
        add("clip control", [] { glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE); },
            [] { glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE); },
            [] { return std::vector<double>{get_ints(GL_CLIP_ORIGIN)[0], get_ints(GL_CLIP_DEPTH_MODE)[0]}; });
        add("primitive restart index", [] { glPrimitiveRestartIndex(12345); }, [] { glPrimitiveRestartIndex(0); },
            [] { return get_ints(GL_PRIMITIVE_RESTART_INDEX); });
        // Capabilities: the host flips each from its default; we flip it back.
        const std::pair<GLenum, const char*> caps[] = {
            {GL_DEPTH_TEST, "depth test"}, {GL_DEPTH_CLAMP, "depth clamp"}, {GL_STENCIL_TEST, "stencil test"},
            {GL_CULL_FACE, "cull face"}, {GL_POLYGON_OFFSET_FILL, "polygon offset fill"},
            {GL_POLYGON_OFFSET_LINE, "polygon offset line"}, {GL_POLYGON_OFFSET_POINT, "polygon offset point"},
            {GL_PRIMITIVE_RESTART, "primitive restart"}, {GL_PRIMITIVE_RESTART_FIXED_INDEX, "primitive restart fixed"},
            {GL_RASTERIZER_DISCARD, "rasterizer discard"}, {GL_FRAMEBUFFER_SRGB, "framebuffer sRGB"},
            {GL_MULTISAMPLE, "multisample"}, {GL_SAMPLE_ALPHA_TO_COVERAGE, "alpha to coverage"}, {GL_DITHER, "dither"}};
        for (const auto& [cap, name] : caps) {
            const GLenum c = cap;
            const bool host_on = glIsEnabled(c) == GL_FALSE;
            add(name, [=] { set_cap(c, host_on); }, [=] { set_cap(c, !host_on); }, [=] { return enabled(c); });
        }
        add("program", [&] { glUseProgram(host_program.id()); }, [&] { glUseProgram(our_program.id()); },
            [] { return get_ints(GL_CURRENT_PROGRAM); });
        add("vertex array", [&] { glBindVertexArray(host_vao.id()); }, [&] { glBindVertexArray(our_vao.id()); },
            [] { return get_ints(GL_VERTEX_ARRAY_BINDING); });
        add("array buffer", [&] { glBindBuffer(GL_ARRAY_BUFFER, host_buf.id()); },
            [&] { glBindBuffer(GL_ARRAY_BUFFER, our_buf.id()); }, [] { return get_ints(GL_ARRAY_BUFFER_BINDING); });
        for (int unit = 0; unit < StateGuard::kUnits; ++unit) {
            for (int t = 0; t < 4; ++t) {
                const GLenum target = targets[t];
                const GLenum binding = target == GL_TEXTURE_1D   ? GL_TEXTURE_BINDING_1D
                                       : target == GL_TEXTURE_2D ? GL_TEXTURE_BINDING_2D
                                       : target == GL_TEXTURE_3D ? GL_TEXTURE_BINDING_3D
                                                                 : GL_TEXTURE_BINDING_BUFFER;
                const GLuint h = host_tex[static_cast<std::size_t>(unit * 4 + t)].id();
                const GLuint o = our_tex[static_cast<std::size_t>(unit * 4 + t)].id();
                const GLenum tex_unit = static_cast<GLenum>(GL_TEXTURE0 + unit);
                add("texture unit " + std::to_string(unit) + " target " + std::to_string(t),
                    [=] { glActiveTexture(tex_unit); glBindTexture(target, h); },
                    [=] { glBindTextureUnit(static_cast<GLuint>(unit), o); },
                    [=] { GLint active = 0; glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
                          glActiveTexture(tex_unit); auto v = get_ints(binding);
                          glActiveTexture(static_cast<GLenum>(active)); return v; });
            }
            const GLuint hs = host_samplers[static_cast<std::size_t>(unit)].id();
            const GLuint os = our_samplers[static_cast<std::size_t>(unit)].id();
            const auto u = static_cast<GLuint>(unit);
            add("sampler " + std::to_string(unit), [=] { glBindSampler(u, hs); }, [=] { glBindSampler(u, os); },
                [=] { return get_int_i(GL_SAMPLER_BINDING, u); });
        }
        // After the texture items: they change the active unit while setting up.
        add("active texture", [] { glActiveTexture(GL_TEXTURE3); }, [] { glActiveTexture(GL_TEXTURE1); },
            [] { return get_ints(GL_ACTIVE_TEXTURE); });
        const std::pair<GLenum, GLint> indexed_targets[] = {{GL_UNIFORM_BUFFER, ubo_align},
                                                            {GL_SHADER_STORAGE_BUFFER, ssbo_align}};
        for (const auto& [target_enum, align] : indexed_targets) {
            const GLenum target = target_enum;
            const GLintptr offset = align;
            const bool ubo = target == GL_UNIFORM_BUFFER;
            const GLenum binding = ubo ? GL_UNIFORM_BUFFER_BINDING : GL_SHADER_STORAGE_BUFFER_BINDING;
            const GLenum start = ubo ? GL_UNIFORM_BUFFER_START : GL_SHADER_STORAGE_BUFFER_START;
            const GLenum size = ubo ? GL_UNIFORM_BUFFER_SIZE : GL_SHADER_STORAGE_BUFFER_SIZE;
            const std::string kind = ubo ? "uniform" : "storage";
            for (GLuint i = 0; i < static_cast<GLuint>(StateGuard::kUnits); ++i) {
                // Even indices whole-buffer, odd ones a range: both restore paths are exercised.
                add(kind + " buffer binding " + std::to_string(i),
                    [&, target, i, offset] {
                        if (i % 2 == 0)
                            glBindBufferBase(target, i, host_buf.id());
                        else
                            glBindBufferRange(target, i, host_buf2.id(), offset * static_cast<GLintptr>(i), 64);
                    },
                    [&, target, i] { glBindBufferRange(target, i, our_buf.id(), 0, 128); },
                    [=] { std::vector<GLint64> s(2);
                          glGetInteger64i_v(start, i, &s[0]);
                          glGetInteger64i_v(size, i, &s[1]);
                          auto v = get_int_i(binding, i);
                          v.push_back(static_cast<double>(s[0]));
                          v.push_back(static_cast<double>(s[1]));
                          return v; });
            }
            // Last: the indexed binds above also move the generic binding point.
            add(kind + " buffer generic binding", [&, target] { glBindBuffer(target, host_buf2.id()); },
                [&, target] { glBindBuffer(target, our_buf.id()); }, [=] { return get_ints(binding); });
        }
        add("pixel pack buffer", [&] { glBindBuffer(GL_PIXEL_PACK_BUFFER, host_buf.id()); },
            [] { glBindBuffer(GL_PIXEL_PACK_BUFFER, 0); }, [] { return get_ints(GL_PIXEL_PACK_BUFFER_BINDING); });
        add("pixel unpack buffer", [&] { glBindBuffer(GL_PIXEL_UNPACK_BUFFER, host_buf2.id()); },
            [] { glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0); }, [] { return get_ints(GL_PIXEL_UNPACK_BUFFER_BINDING); });
        const std::pair<GLenum, GLint> store[] = {
            {GL_PACK_ALIGNMENT, 2},     {GL_PACK_ROW_LENGTH, 7},     {GL_PACK_SKIP_PIXELS, 3},
            {GL_PACK_SKIP_ROWS, 5},     {GL_PACK_IMAGE_HEIGHT, 11},  {GL_UNPACK_ALIGNMENT, 8},
            {GL_UNPACK_ROW_LENGTH, 13}, {GL_UNPACK_SKIP_PIXELS, 2},  {GL_UNPACK_SKIP_ROWS, 4},
            {GL_UNPACK_IMAGE_HEIGHT, 6}, {GL_UNPACK_SKIP_IMAGES, 9}};
        for (const auto& [pname, value] : store) {
            const GLenum p = pname;
            const GLint v = value;
            const GLint initial = p == GL_PACK_ALIGNMENT || p == GL_UNPACK_ALIGNMENT ? 4 : 0;
            add("pixel store 0x" + std::to_string(p), [=] { glPixelStorei(p, v); }, [=] { glPixelStorei(p, initial); },
                [=] { return get_ints(p); });
        }

        for (const StateItem& item : items)
            item.host();
        fx_test::require_no_gl_error();
        std::vector<std::vector<double>> host_values;
        for (const StateItem& item : items)
            host_values.push_back(item.read());

        {
            StateGuard guard;
            StateGuard::set_render_defaults();
            for (const StateItem& item : items)
                item.ours();
            fx_test::require_no_gl_error();
            // Every item really changed, so the restore below is a real test.
            for (std::size_t i = 0; i < items.size(); ++i) {
                INFO("changed: " << items[i].name);
                CHECK(items[i].read() != host_values[i]);
            }
        }
        fx_test::require_no_gl_error();
        for (std::size_t i = 0; i < items.size(); ++i) {
            INFO("restored: " << items[i].name);
            CHECK(items[i].read() == host_values[i]);
        }
        CHECK(items.size() > 80);

        // Unbind before the objects go so that no deleted name stays bound anywhere.
        glUseProgram(0);
    }
    fx_test::gl_context();
}

// ---------------------------------------------------------------------------------------------
// Render target

TEST_CASE("RenderTarget clears and reads back bottom row first", "[gl]") {
    fx_test::gl_context();
    using fx::gl::ColorFormat;
    // RGBA8 quantises to k/255: half a step of rounding; float formats store these exactly.
    const std::pair<ColorFormat, float> formats[] = {
        {ColorFormat::RGBA8, 0.5f / 255.0f + 1e-6f}, {ColorFormat::RGBA16F, 0.0f}, {ColorFormat::RGBA32F, 0.0f}};
    for (const auto& [format, tolerance] : formats) {
        INFO(fx::gl::color_format_name(format));
        fx::gl::RenderTarget target = fx::gl::RenderTarget::create(13, 7, format, true);
        CHECK(target.width() == 13);
        CHECK(target.height() == 7);
        CHECK(target.has_depth());
        const glm::vec4 fill(0.25f, 0.5f, 0.75f, 1.0f), bottom(1.0f, 0.0f, 0.125f, 0.5f);
        {
            fx::gl::StateGuard guard;
            fx::gl::StateGuard::set_render_defaults();
            target.clear(fill, 0.25f);
            // Only the bottom row (y = 0 in GL window coordinates) gets the second colour.
            glEnable(GL_SCISSOR_TEST);
            glScissor(0, 0, 13, 1);
            target.clear(bottom, 0.25f);
        }
        const fx::Image image = target.read();
        REQUIRE(image.width == 13);
        REQUIRE(image.height == 7);
        fx::Image want(13, 7, fill);
        for (int x = 0; x < 13; ++x) want.at(x, 0) = bottom;
        fx_test::check_image("render_target_clear", image, want,
                             verify::same_picture(tolerance, "the clear colour stored in the target's format"));

        std::vector<float> depth(13 * 7, -1.0f);
        glGetTextureImage(target.depth_texture(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                          static_cast<GLsizei>(depth.size() * sizeof(float)), depth.data());
        CHECK(depth.front() == 0.25f);
        CHECK(depth.back() == 0.25f);
    }
    CHECK_FALSE(fx::gl::RenderTarget::create(4, 4, ColorFormat::RGBA8, false).has_depth());
    CHECK_THROWS_AS(fx::gl::RenderTarget::create(0, 4, ColorFormat::RGBA8, false), fx::Error);
    fx_test::require_no_gl_error();
}

// ---------------------------------------------------------------------------------------------
// Composite pass against its closed form

namespace {

// A premultiplied image whose every pixel differs (so any offset in sampling shows).
fx::Image premultiplied_ramp(int w, int h) {
    fx::Image image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float a = static_cast<float>(x) / static_cast<float>(w - 1);
            const float r = static_cast<float>(y) / static_cast<float>(h - 1);
            image.at(x, y) = glm::vec4(a * r, a * 0.5f, a * (1.0f - r), a);
        }
    return image;
}

} // namespace

TEST_CASE("composite pass draws c + (1 - a) * background", "[gl]") {
    fx_test::gl_context();
    const int w = 32, h = 16;
    const fx::Image source = premultiplied_ramp(w, h);
    fx::gl::Texture texture = fx::gl::make_texture_2d(GL_RGBA32F, w, h);
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults(); // tightly packed upload
        glTextureSubImage2D(texture.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, source.pixels.data());
    }
    const glm::vec3 background(0.2f, 0.6f, 0.9f);
    fx::Image expected(w, h);
    for (std::size_t i = 0; i < expected.pixels.size(); ++i) {
        const glm::vec4 c = source.pixels[i];
        expected.pixels[i] = glm::vec4(glm::vec3(c) + (1.0f - c.a) * background, 1.0f);
    }
    const fx::gl::CompositePass pass = fx::gl::CompositePass::create();
    fx::gl::RenderTarget target = fx::gl::RenderTarget::create(w, h, fx::gl::ColorFormat::RGBA32F, false);

    SECTION("over a colour") {
        fx::gl::StateGuard guard;
        target.bind_for_drawing();
        target.clear(glm::vec4(9.0f)); // must be overwritten everywhere
        pass.draw_over_color(texture.id(), background);
    }
    SECTION("over the framebuffer (blended)") {
        fx::gl::StateGuard guard;
        target.bind_for_drawing();
        target.clear(glm::vec4(background, 1.0f));
        pass.draw_over_framebuffer(texture.id());
    }
    fx_test::require_no_gl_error();
    const fx::Image actual = target.read();
    // float32 target and texture: a handful of float roundings of values ≤ 1 (4e-7 each, or an
    // FMA's worth); a one-texel sampling shift would give ≥ 1/31 ≈ 0.03.
    verify::Tolerance t = verify::same_picture(4e-6, "a handful of float roundings of values <= 1");
    t.mean.absolute = 1e-6;
    fx_test::check_image("composite", actual, expected, t);
}

// ---------------------------------------------------------------------------------------------
// Shader library

TEST_CASE("builtin shaders are embedded by file name with their source path", "[gl]") {
    const fx::gl::ShaderLibrary& lib = fx::gl::ShaderLibrary::builtin();
    for (const char* name : {"fullscreen.vert", "composite.frag"}) {
        INFO(name);
        REQUIRE(lib.contains(name));
        CHECK(lib.path(name) == std::string("shaders/") + name);
        // The embedded text is the file as it is in the tree (regenerated when it changes).
        CHECK(lib.source(name) == read_text(std::string("shaders/") + name));
    }
    CHECK_FALSE(lib.contains("missing.frag"));
    CHECK_THROWS_AS(lib.source("missing.frag"), fx::Error);
}

TEST_CASE("assemble resolves includes once, prepends defines and maps lines", "[gl]") {
    fx::gl::ShaderLibrary lib;
    lib.add("a.frag", "// comment\n#version 450 core\n#include \"b.glsl\"\n#include \"b.glsl\"\nvoid main() {}\n",
            "shaders/a.frag");
    lib.add("b.glsl", "#include \"c.glsl\"\nfloat b() { return c(); }\n");
    lib.add("c.glsl", "float c() { return 1.0; }");
    const fx::gl::AssembledSource s = lib.assemble("a.frag", {{"X", "2"}, {"Y", "1"}});
    // Source-string numbers in order of appearance: main file, prelude, then includes.
    REQUIRE(s.files == std::vector<std::string>{"shaders/a.frag", "<defines>", "b.glsl", "c.glsl"});
    CHECK(s.text.rfind("#version 450 core\n#line 1 1\n#define X 2\n#define Y 1\n#line 1 0\n// comment\n\n", 0) == 0);
    CHECK_THAT(s.text, Contains("#line 1 2\n#line 1 3\nfloat c() { return 1.0; }\n#line 2 2\nfloat b()"));
    CHECK_THAT(s.text, Contains("#line 4 0\n\nvoid main() {}\n")); // second include of b: empty line
    CHECK(s.text.find("float b()") == s.text.rfind("float b()"));

    lib.add("d.frag", "void main() {}\n"); // no #version: 450 core is supplied
    CHECK(lib.assemble("d.frag").text.rfind("#version 450 core\n#line 1 0\nvoid main", 0) == 0);

    lib.add("bad.frag", "#version 450 core\n\n  #include \"nope.glsl\"\n");
    CHECK_THROWS_WITH(lib.assemble("bad.frag"), Contains("bad.frag:3: #include \"nope.glsl\": no such shader"));
    lib.add("v.glsl", "\n#version 450\n", "shaders/v.glsl");
    lib.add("uses_v.frag", "#include \"v.glsl\"\n");
    CHECK_THROWS_WITH(lib.assemble("uses_v.frag"), Contains("shaders/v.glsl:2: #version"));
    CHECK_THROWS_WITH(fx::gl::shader_stage("x.glsl"), Contains("unknown stage"));
    CHECK(fx::gl::shader_stage("x.comp") == GL_COMPUTE_SHADER);
}

TEST_CASE("info logs of Mesa, NVIDIA and glslang are rewritten to file:line", "[gl]") {
    const std::vector<std::string> files = {"shaders/pcp.frag", "<defines>", "shaders/project.glsl"};
    CHECK(fx::gl::rewrite_info_log("0:42(7): error: `x' undeclared\n", files) ==
          "shaders/pcp.frag:42: error: `x' undeclared");
    CHECK(fx::gl::rewrite_info_log("2(13) : error C1008: undefined variable \"y\"", files) ==
          "shaders/project.glsl:13: error C1008: undefined variable \"y\"");
    CHECK(fx::gl::rewrite_info_log("ERROR: 2:5: 'z' : undeclared identifier\nERROR: 1 compilation errors.", files) ==
          "shaders/project.glsl:5: error: 'z' : undeclared identifier\nERROR: 1 compilation errors.");
    CHECK(fx::gl::rewrite_info_log("7:1(1): warning: w", files) == "source string 7:1: warning: w");
}

TEST_CASE("a compile error names the shader file and line", "[gl]") {
    fx_test::gl_context();
    const fx::gl::ShaderLibrary lib = test_library();
    // Without BREAK_IT the shader is fine: the error below really comes from the prelude.
    CHECK_NOTHROW(lib.compile("broken.frag"));
    const std::string message = compile_error(lib, "broken.frag", {{"BREAK_IT", "1"}});
    const int line = marker_line(read_text("tests/shaders/broken.frag"), "ERROR HERE");
    INFO(message);
    CHECK_THAT(message, Contains("tests/shaders/broken.frag:" + std::to_string(line) + ": "));
    CHECK_THAT(message, Contains("BREAK_IT=1"));
    fx_test::require_no_gl_error();
}

TEST_CASE("an error in an included file names that file and its line", "[gl]") {
    fx_test::gl_context();
    const fx::gl::ShaderLibrary lib = test_library();
    const std::string message = compile_error(lib, "include_error.frag");
    const int line = marker_line(read_text("tests/shaders/broken_include.glsl"), "ERROR HERE");
    INFO(message);
    CHECK_THAT(message, Contains("tests/shaders/broken_include.glsl:" + std::to_string(line) + ": "));
    fx_test::require_no_gl_error();
}

TEST_CASE("after an include, errors map back to the including file", "[gl]") {
    fx_test::gl_context();
    const fx::gl::ShaderLibrary lib = test_library();
    const std::string message = compile_error(lib, "error_after_include.frag", {{"UNUSED_FEATURE", "3"}});
    const int line = marker_line(read_text("tests/shaders/error_after_include.frag"), "ERROR HERE");
    INFO(message);
    CHECK_THAT(message, Contains("tests/shaders/error_after_include.frag:" + std::to_string(line) + ": "));
    fx_test::require_no_gl_error();
}

TEST_CASE("a link error is reported with the stages involved", "[gl]") {
    fx_test::gl_context();
    fx::gl::ShaderLibrary lib = fx::gl::ShaderLibrary::builtin();
    // Compiles alone (a declared function), but no stage defines the function.
    lib.add("undefined_function.frag",
            "#version 450 core\nlayout(location = 0) out vec4 o;\nfloat defined_nowhere();\n"
            "void main() { o = vec4(defined_nowhere()); }\n",
            "tests/undefined_function.frag");
    lib.add("writes_nothing.vert", "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n",
            "tests/writes_nothing.vert");
    std::string message;
    try {
        lib.link({"writes_nothing.vert", "undefined_function.frag"});
    } catch (const fx::Error& e) {
        message = e.what();
    }
    CHECK_THAT(message, Contains("linking tests/writes_nothing.vert + tests/undefined_function.frag failed"));
    fx_test::require_no_gl_error();
}
