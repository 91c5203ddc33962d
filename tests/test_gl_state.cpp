// cellfx leaves the game's GL state exactly as it found it, and draws the same frame whatever
// state the game left: a "caching renderer" that keeps a texture of every target (cube maps,
// arrays, multisample, rectangle, buffer, ...) and a sampler on every unit cellfx uses and
// beyond, its program, vertex array, uniform and storage buffer ranges, indexed blending,
// viewports, scissor, reversed-Z clip control, depth range, face culling, clip distances, logic
// op, pixel-store state and distinct draw/read framebuffers. The whole state is read back
// independently of fx::gl::StateGuard (glGet* of each item) before and after render(), for every
// render path, with and without cellfx's terrain, with a multisampled depth texture, and for
// CellRenderer::render called on its own; render() saves and restores once per frame.
#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

#include "embedding_support.hpp"
#include "cellfx_names.hpp"

namespace {

using embedding_test::GameFrame;
using embedding_test::kH;
using embedding_test::kW;
constexpr int kUnitsChecked = 10; // cellfx binds units 0–3; the guard saves 0–7; 8 and 9 must be untouched too

constexpr GLenum kTargets[] = {GL_TEXTURE_1D,       GL_TEXTURE_2D,        GL_TEXTURE_3D,       GL_TEXTURE_1D_ARRAY,
                               GL_TEXTURE_2D_ARRAY, GL_TEXTURE_RECTANGLE, GL_TEXTURE_CUBE_MAP, GL_TEXTURE_CUBE_MAP_ARRAY,
                               GL_TEXTURE_BUFFER,   GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_2D_MULTISAMPLE_ARRAY};
constexpr GLenum kTargetBindings[] = {
    GL_TEXTURE_BINDING_1D,       GL_TEXTURE_BINDING_2D,        GL_TEXTURE_BINDING_3D,       GL_TEXTURE_BINDING_1D_ARRAY,
    GL_TEXTURE_BINDING_2D_ARRAY, GL_TEXTURE_BINDING_RECTANGLE, GL_TEXTURE_BINDING_CUBE_MAP, GL_TEXTURE_BINDING_CUBE_MAP_ARRAY,
    GL_TEXTURE_BINDING_BUFFER,   GL_TEXTURE_BINDING_2D_MULTISAMPLE, GL_TEXTURE_BINDING_2D_MULTISAMPLE_ARRAY};

// Every item of GL state the game may rely on, by name, read with glGet*.
using State = std::vector<std::pair<std::string, double>>;

State read_state() {
    State s;
    auto ints = [&s](const char* name, GLenum e, int n) {
        GLint v[4] = {};
        glGetIntegerv(e, v);
        for (int i = 0; i < n; ++i) s.emplace_back(std::string(name) + "[" + std::to_string(i) + "]", v[i]);
    };
    auto floats = [&s](const char* name, GLenum e, int n) {
        GLfloat v[4] = {};
        glGetFloatv(e, v);
        for (int i = 0; i < n; ++i) s.emplace_back(std::string(name) + "[" + std::to_string(i) + "]", v[i]);
    };
    auto indexed = [&s](const char* name, GLenum e, GLuint index, int n) {
        GLint64 v[4] = {};
        glGetInteger64i_v(e, index, v);
        for (int i = 0; i < n; ++i)
            s.emplace_back(std::string(name) + "(" + std::to_string(index) + ")[" + std::to_string(i) + "]", double(v[i]));
    };
    const std::pair<const char*, GLenum> caps[] = {
        {"depth test", GL_DEPTH_TEST}, {"depth clamp", GL_DEPTH_CLAMP}, {"stencil test", GL_STENCIL_TEST},
        {"cull face", GL_CULL_FACE}, {"offset fill", GL_POLYGON_OFFSET_FILL}, {"offset line", GL_POLYGON_OFFSET_LINE},
        {"primitive restart", GL_PRIMITIVE_RESTART}, {"rasterizer discard", GL_RASTERIZER_DISCARD},
        {"srgb", GL_FRAMEBUFFER_SRGB}, {"multisample", GL_MULTISAMPLE}, {"alpha to coverage", GL_SAMPLE_ALPHA_TO_COVERAGE},
        {"sample coverage", GL_SAMPLE_COVERAGE}, {"sample mask", GL_SAMPLE_MASK}, {"sample shading", GL_SAMPLE_SHADING},
        {"dither", GL_DITHER}, {"polygon smooth", GL_POLYGON_SMOOTH}, {"line smooth", GL_LINE_SMOOTH},
        {"logic op", GL_COLOR_LOGIC_OP}, {"clip distance 0", GL_CLIP_DISTANCE0}, {"clip distance 3", GL_CLIP_DISTANCE3}};
    for (const auto& [name, cap] : caps) s.emplace_back(name, glIsEnabled(cap));
    for (GLuint i = 0; i < 2; ++i) {
        s.emplace_back("blend(" + std::to_string(i) + ")", glIsEnabledi(GL_BLEND, i));
        s.emplace_back("scissor test(" + std::to_string(i) + ")", glIsEnabledi(GL_SCISSOR_TEST, i));
        for (GLenum e : {GL_BLEND_SRC_RGB, GL_BLEND_DST_RGB, GL_BLEND_SRC_ALPHA, GL_BLEND_DST_ALPHA, GL_BLEND_EQUATION_RGB,
                         GL_BLEND_EQUATION_ALPHA})
            indexed("blend state", e, i, 1);
        indexed("colour mask", GL_COLOR_WRITEMASK, i, 4);
        indexed("viewport", GL_VIEWPORT, i, 4);
        indexed("scissor box", GL_SCISSOR_BOX, i, 4);
        GLdouble range[2] = {};
        glGetDoublei_v(GL_DEPTH_RANGE, i, range);
        s.emplace_back("depth range(" + std::to_string(i) + ")", range[0] * 1000.0 + range[1]);
    }
    floats("blend colour", GL_BLEND_COLOR, 4);
    floats("clear colour", GL_COLOR_CLEAR_VALUE, 4);
    floats("clear depth", GL_DEPTH_CLEAR_VALUE, 1);
    ints("depth func", GL_DEPTH_FUNC, 1);
    ints("depth mask", GL_DEPTH_WRITEMASK, 1);
    ints("cull mode", GL_CULL_FACE_MODE, 1);
    ints("front face", GL_FRONT_FACE, 1);
    ints("polygon mode", GL_POLYGON_MODE, 2);
    floats("offset factor", GL_POLYGON_OFFSET_FACTOR, 1);
    floats("offset units", GL_POLYGON_OFFSET_UNITS, 1);
    ints("clip origin", GL_CLIP_ORIGIN, 1);
    ints("clip depth mode", GL_CLIP_DEPTH_MODE, 1);
    ints("provoking vertex", GL_PROVOKING_VERTEX, 1);
    ints("restart index", GL_PRIMITIVE_RESTART_INDEX, 1);
    ints("clamp read colour", GL_CLAMP_READ_COLOR, 1);
    ints("program", GL_CURRENT_PROGRAM, 1);
    ints("vertex array", GL_VERTEX_ARRAY_BINDING, 1);
    ints("array buffer", GL_ARRAY_BUFFER_BINDING, 1);
    ints("element buffer", GL_ELEMENT_ARRAY_BUFFER_BINDING, 1);
    ints("draw framebuffer", GL_DRAW_FRAMEBUFFER_BINDING, 1);
    ints("read framebuffer", GL_READ_FRAMEBUFFER_BINDING, 1);
    ints("uniform buffer", GL_UNIFORM_BUFFER_BINDING, 1);
    ints("storage buffer", GL_SHADER_STORAGE_BUFFER_BINDING, 1);
    ints("pack buffer", GL_PIXEL_PACK_BUFFER_BINDING, 1);
    ints("unpack buffer", GL_PIXEL_UNPACK_BUFFER_BINDING, 1);
    for (GLenum e : {GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_ROWS, GL_UNPACK_ALIGNMENT,
                     GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS, GL_UNPACK_IMAGE_HEIGHT})
        ints("pixel store", e, 1);
    for (GLuint i = 0; i < 8; ++i) {
        indexed("uniform buffer", GL_UNIFORM_BUFFER_BINDING, i, 1);
        indexed("uniform start", GL_UNIFORM_BUFFER_START, i, 1);
        indexed("uniform size", GL_UNIFORM_BUFFER_SIZE, i, 1);
        indexed("storage buffer", GL_SHADER_STORAGE_BUFFER_BINDING, i, 1);
        indexed("storage start", GL_SHADER_STORAGE_BUFFER_START, i, 1);
        indexed("storage size", GL_SHADER_STORAGE_BUFFER_SIZE, i, 1);
    }
    for (GLuint i = 0; i < 2; ++i) { // image units (the froxel medium's compute pass binds 0 and 1)
        for (GLenum e : {GL_IMAGE_BINDING_NAME, GL_IMAGE_BINDING_LEVEL, GL_IMAGE_BINDING_LAYER, GL_IMAGE_BINDING_ACCESS,
                         GL_IMAGE_BINDING_FORMAT})
            indexed("image unit", e, i, 1);
        GLboolean layered = GL_FALSE;
        glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, i, &layered);
        s.emplace_back("image unit(" + std::to_string(i) + ") layered", layered);
    }
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    s.emplace_back("active texture", active);
    for (int unit = 0; unit < kUnitsChecked; ++unit) {
        glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        for (std::size_t t = 0; t < std::size(kTargetBindings); ++t) {
            GLint name = 0;
            glGetIntegerv(kTargetBindings[t], &name);
            s.emplace_back("unit " + std::to_string(unit) + " target " + std::to_string(t), name);
        }
        GLint sampler = 0;
        glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
        s.emplace_back("unit " + std::to_string(unit) + " sampler", sampler);
    }
    glActiveTexture(GLenum(active));
    return s;
}

// What changed between two readings, one line per item.
std::string differences(const State& before, const State& after) {
    std::string d;
    for (std::size_t i = 0; i < before.size() && i < after.size(); ++i)
        if (before[i].second != after[i].second)
            d += before[i].first + ": " + std::to_string(before[i].second) + " -> " + std::to_string(after[i].second) + "\n";
    return d;
}

// A caching renderer's state: everything it leaves bound and set between its own draws, none of
// it GL's default. Restores GL's defaults (and deletes its objects) when it goes.
struct CachingRenderer {
    std::vector<GLuint> textures;
    GLuint samplers[kUnitsChecked] = {};
    GLuint program = 0, vao = 0, buffer = 0, texture_buffer = 0, read_framebuffer = 0, read_color = 0;

    explicit CachingRenderer(GLuint draw_framebuffer) {
        glCreateBuffers(1, &texture_buffer);
        glNamedBufferStorage(texture_buffer, 256, nullptr, 0);
        glCreateBuffers(1, &buffer);
        glNamedBufferStorage(buffer, 4096, nullptr, GL_DYNAMIC_STORAGE_BIT);
        glCreateSamplers(kUnitsChecked, samplers);
        for (int unit = 0; unit < kUnitsChecked; ++unit) {
            glActiveTexture(GLenum(GL_TEXTURE0 + unit));
            for (GLenum target : kTargets) {
                GLuint t = 0;
                glCreateTextures(target, 1, &t);
                switch (target) {
                case GL_TEXTURE_1D: glTextureStorage1D(t, 1, GL_RGBA8, 4); break;
                case GL_TEXTURE_1D_ARRAY:
                case GL_TEXTURE_2D:
                case GL_TEXTURE_RECTANGLE:
                case GL_TEXTURE_CUBE_MAP: glTextureStorage2D(t, 1, GL_RGBA8, 4, 4); break;
                case GL_TEXTURE_3D:
                case GL_TEXTURE_2D_ARRAY: glTextureStorage3D(t, 1, GL_RGBA8, 4, 4, 2); break;
                case GL_TEXTURE_CUBE_MAP_ARRAY: glTextureStorage3D(t, 1, GL_RGBA8, 4, 4, 6); break;
                case GL_TEXTURE_BUFFER: glTextureBuffer(t, GL_RGBA8, texture_buffer); break;
                case GL_TEXTURE_2D_MULTISAMPLE: glTextureStorage2DMultisample(t, 4, GL_RGBA8, 4, 4, GL_TRUE); break;
                case GL_TEXTURE_2D_MULTISAMPLE_ARRAY: glTextureStorage3DMultisample(t, 4, GL_RGBA8, 4, 4, 2, GL_TRUE); break;
                default: break;
                }
                glBindTexture(target, t);
                textures.push_back(t);
            }
            glBindSampler(GLuint(unit), samplers[unit]);
        }
        glActiveTexture(GL_TEXTURE6);
        // Image units: a layer of a 2D array on 0, a whole 3D texture on 1.
        glBindImageTexture(0, textures[4], 0, GL_FALSE, 1, GL_READ_ONLY, GL_RGBA8);
        glBindImageTexture(1, textures[2], 0, GL_TRUE, 0, GL_READ_WRITE, GL_RGBA8UI);

        const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
        const char* fs = "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";
        program = glCreateProgram();
        for (auto [stage, text] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
            const GLuint shader = glCreateShader(stage);
            glShaderSource(shader, 1, &text, nullptr);
            glCompileShader(shader);
            glAttachShader(program, shader);
            glDeleteShader(shader);
        }
        glLinkProgram(program);
        glUseProgram(program);
        glCreateVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffer);
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        for (GLuint i = 0; i < 8; ++i) {
            glBindBufferRange(GL_UNIFORM_BUFFER, i, buffer, GLintptr(256 * i), 256);
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, i, buffer, GLintptr(256 * (i + 1)), 128);
        }
        glBindBuffer(GL_UNIFORM_BUFFER, buffer);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);

        glCreateFramebuffers(1, &read_framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &read_color);
        glTextureStorage2D(read_color, 1, GL_RGBA8, 8, 8);
        glNamedFramebufferTexture(read_framebuffer, GL_COLOR_ATTACHMENT0, read_color, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, draw_framebuffer);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, read_framebuffer);

        glEnablei(GL_BLEND, 0);
        glBlendFuncSeparatei(0, GL_SRC_COLOR, GL_ONE_MINUS_DST_ALPHA, GL_ZERO, GL_SRC_ALPHA);
        glBlendEquationSeparatei(0, GL_FUNC_REVERSE_SUBTRACT, GL_MAX);
        glBlendFunci(1, GL_DST_COLOR, GL_ZERO);
        glColorMaski(1, GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
        glBlendColor(0.1f, 0.2f, 0.3f, 0.4f);
        glViewportIndexedf(0, 3, 5, 7, 11);
        glViewportIndexedf(1, 1, 2, 30, 20);
        glDepthRangeIndexed(0, 0.2, 0.9);
        glDepthRangeIndexed(1, 0.3, 0.4);
        glEnable(GL_SCISSOR_TEST);
        glScissorIndexed(0, 1, 2, 3, 4);
        glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE); // reversed-Z's depth mode, flipped origin
        glEnable(GL_DEPTH_TEST);
        // (Not GL_GREATER: with GL_ZERO_TO_ONE that is a reversed-Z game's state, which render()
        // holds against target.depth — test_depth_conventions.cpp.)
        glDepthFunc(GL_NOTEQUAL);
        glDepthMask(GL_FALSE);
        glClearDepth(0.0);
        glClearColor(0.7f, 0.1f, 0.6f, 0.5f);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
        glFrontFace(GL_CW);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(2.0f, 3.0f);
        glEnable(GL_STENCIL_TEST);
        glEnable(GL_CLIP_DISTANCE0);
        glEnable(GL_CLIP_DISTANCE3);
        glProvokingVertex(GL_FIRST_VERTEX_CONVENTION);
        glEnable(GL_PRIMITIVE_RESTART);
        glPrimitiveRestartIndex(7);
        glEnable(GL_SAMPLE_MASK);
        glEnable(GL_COLOR_LOGIC_OP);
        glEnable(GL_FRAMEBUFFER_SRGB);
        glDisable(GL_DITHER);
        glClampColor(GL_CLAMP_READ_COLOR, GL_TRUE);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 9);
        glPixelStorei(GL_PACK_ALIGNMENT, 8);
        glPixelStorei(GL_PACK_SKIP_ROWS, 1);
    }

    ~CachingRenderer() {
        // GL's defaults again, for the tests that follow in this context.
        glUseProgram(0);
        glBindVertexArray(0);
        for (GLenum target : {GL_ARRAY_BUFFER, GL_UNIFORM_BUFFER, GL_SHADER_STORAGE_BUFFER, GL_PIXEL_PACK_BUFFER,
                              GL_PIXEL_UNPACK_BUFFER})
            glBindBuffer(target, 0);
        for (GLuint i = 0; i < 8; ++i) {
            glBindBufferBase(GL_UNIFORM_BUFFER, i, 0);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, 0);
        }
        for (int unit = 0; unit < kUnitsChecked; ++unit) {
            glBindTextureUnit(GLuint(unit), 0);
            glBindSampler(GLuint(unit), 0);
        }
        for (GLuint unit = 0; unit < 2; ++unit) glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R8);
        glActiveTexture(GL_TEXTURE0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDisablei(GL_BLEND, 0);
        glBlendFunc(GL_ONE, GL_ZERO);
        glBlendEquation(GL_FUNC_ADD);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glBlendColor(0, 0, 0, 0);
        glViewportIndexedf(1, 0, 0, 1, 1);
        glDepthRange(0.0, 1.0);
        glDisable(GL_SCISSOR_TEST);
        glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glClearDepth(1.0);
        glClearColor(0, 0, 0, 0);
        glDisable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glFrontFace(GL_CCW);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDisable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(0, 0);
        glDisable(GL_STENCIL_TEST);
        glDisable(GL_CLIP_DISTANCE0);
        glDisable(GL_CLIP_DISTANCE3);
        glProvokingVertex(GL_LAST_VERTEX_CONVENTION);
        glDisable(GL_PRIMITIVE_RESTART);
        glPrimitiveRestartIndex(0);
        glDisable(GL_SAMPLE_MASK);
        glDisable(GL_COLOR_LOGIC_OP);
        glDisable(GL_FRAMEBUFFER_SRGB);
        glEnable(GL_DITHER);
        glClampColor(GL_CLAMP_READ_COLOR, GL_FIXED_ONLY);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glPixelStorei(GL_PACK_SKIP_ROWS, 0);
        glDeleteTextures(GLsizei(textures.size()), textures.data());
        glDeleteSamplers(kUnitsChecked, samplers);
        glDeleteProgram(program);
        glDeleteVertexArrays(1, &vao);
        glDeleteBuffers(1, &buffer);
        glDeleteBuffers(1, &texture_buffer);
        glDeleteFramebuffers(1, &read_framebuffer);
        glDeleteTextures(1, &read_color);
    }
};

// A small fire: 20 module frames per run.
terrain::Scene fire_scene(bool terrain_drawn) {
    return embedding_test::fire_scene(terrain_drawn, R"("cells_across": 8, "cells_up": 10,)");
}

// One frame of the module over the game's frame, under GL's defaults or under the caching
// renderer's state (then checked unchanged, and saved once).
fx::Image module_frame(cellfx::Module& fx, bool multisample, bool hostile) {
    GameFrame game(GL_DEPTH_COMPONENT32F, false, multisample ? 4 : 1);
    game.draw(fx.scene_camera(), false, 0.0);
    fx.update(0.0, fx.scene_camera());
    const cellfx::Target target{game.framebuffer, {0, 0, kW, kH}, game.depth};
    if (!hostile) {
        fx.render(target);
    } else {
        CachingRenderer renderer(game.framebuffer);
        const State before = read_state();
        const std::uint64_t saves = fx::gl::StateGuard::saves();
        fx.render(target);
        fx_test::require_no_gl_error();
        CHECK(fx::gl::StateGuard::saves() - saves == 1); // one save and restore for the whole frame
        const std::string changed = differences(before, read_state());
        INFO("changed by render():\n" << changed);
        CHECK(changed.empty());
    }
    return game.read();
}

} // namespace

TEST_CASE("render() leaves every GL state of a caching renderer as it was, and draws the same frame under it",
          "[gl][embedding][state]") {
    fx_test::gl_context();
    for (bool terrain_drawn : {false, true}) {
        for (bool multisample : {false, true}) {
            for (fx::RenderPath path : fx::kRenderPaths) {
                INFO((terrain_drawn ? "with" : "without") << " cellfx's terrain, " << (multisample ? "4x multisampled" : "2D")
                                                          << " depth, " << fx::render_path_name(path));
                cellfx::Module fx;
                fx.init(cellfx::Config::from_scene(fire_scene(terrain_drawn), kW, kH));
                fx.set_path("fire", path);
                const fx::Image calm = module_frame(fx, multisample, false);
                const fx::Image hostile = module_frame(fx, multisample, true);
                // The same GL commands under cellfx's own defaults: the same pixels, exactly.
                fx_test::check_image("gl_state_frame", hostile, calm, verify::same_picture(0.0, "the same GL commands"));
                std::size_t lit = 0;
                for (const glm::vec4& p : calm.pixels) lit += p.r > 0.3f;
                CHECK(lit > 50); // the fire is there
            }
        }
    }
}

TEST_CASE("The one medium (froxel grid, exact lists) and the reduced resolutions leave the state as it was",
          "[gl][embedding][state][medium]") {
    // The fire inside a mist volume (one medium), each method at full and quarter resolution.
    fx_test::gl_context();
    terrain::Scene scene = fire_scene(false);
    terrain::EffectSpec mist;
    mist.name = "mist";
    fx::VolumeParams p;
    p.size = {1.4, 1.4, 1.6};
    p.position = {0.0, 0.0, 0.7};
    mist.params = p;
    mist.transfer_function = fx::TransferFunction::constant({0.35, 0.4, 0.5}, 0.8);
    mist.absorb = true;
    mist.albedo = 0.6;
    scene.effects.push_back(mist);
    for (fx::MediumMethod method : {fx::MediumMethod::Froxel, fx::MediumMethod::Exact})
        for (double scale : {1.0, 0.25}) {
            INFO(fx::medium_method_name(method) << " at fx scale " << scale);
            cellfx::Config config = cellfx::Config::from_scene(scene, kW, kH);
            config.medium = method;
            config.fx_scale = scale;
            cellfx::Module fx;
            fx.init(config);
            const fx::Image calm = module_frame(fx, false, false);
            REQUIRE(fx.stats().medium.pixels > 0);
            REQUIRE(fx.stats().medium.method == method);
            const fx::Image hostile = module_frame(fx, false, true);
            fx_test::check_image("gl_state_medium", hostile, calm, verify::same_picture(0.0, "the same GL commands"));
        }
}

TEST_CASE("CellRenderer::render on its own restores the caching renderer's state too", "[gl][state]") {
    fx_test::gl_context();
    const terrain::Scene scene = fire_scene(false);
    fx::Campfire fire(std::get<fx::CampfireParams>(scene.effects[0].params));
    fire.update(fx::EffectView{scene.camera, kW, kH, 0.5});
    fx::CellRenderer renderer(fire.mesh(), fire.scalar_name(), terrain::drawn_transfer_function(
                                                                   scene.effects[0].transfer_function, 0.15, {0.0f, 1.0f}));
    GameFrame game(GL_DEPTH_COMPONENT32F, false);
    game.draw(scene.camera, false, 0.0);
    for (fx::RenderPath path : fx::kRenderPaths) {
        INFO(fx::render_path_name(path));
        CachingRenderer caching(game.framebuffer);
        const State before = read_state();
        fx::CellRenderOptions options;
        options.scene_depth = game.depth;
        renderer.render(scene.camera, {0, 0, kW, kH}, path, options);
        fx_test::require_no_gl_error();
        const std::string changed = differences(before, read_state());
        INFO("changed by CellRenderer::render():\n" << changed);
        CHECK(changed.empty());
    }
}
