// A sample's main(): the command line, then the GLFW window or the headless loop around the
// shared FrameLoop (sample.hpp).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>

#include "frame_loop.hpp"
#include "panel.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/image.hpp"
#include "io/output_file.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

std::string frame_file(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame);
    return (std::filesystem::path(dir) / name).string();
}

// The folder for the frames, made and tried before the first frame (fx::write_png writes each
// through io::OutputFile).
void prepare_out(const std::string& dir) {
    if (dir.empty()) return;
    try {
        fx::io::create_output_folder(dir);
        fx::io::check_output_file(frame_file(dir, 0));
    } catch (const fx::Error& e) {
        throw fx::Error(std::string("--out ") + e.what());
    }
}

void apply_start_options(SampleContent& content, const SampleOptions& options) {
    // --save names a file for the tuned scene: refused at once where there is no scene to save.
    if (!options.save.empty() && !content.scene_file_text("."))
        throw fx::Error("--save: this sample shows no scene file (a mesh viewer): there is nothing to save");
    // ... and where it cannot be written, before the tuning that would be lost.
    if (!options.save.empty()) {
        try {
            fx::io::check_output_file(options.save);
        } catch (const fx::Error& e) {
            throw fx::Error(std::string("--save ") + e.what());
        }
    }
    if (options.path) content.set_path(*options.path);
    const std::vector<std::string> names = content.toggle_names();
    for (const std::string& off : options.disable) {
        const auto it = std::find(names.begin(), names.end(), off);
        if (it == names.end()) {
            std::string known;
            for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
            throw fx::Error("--disable: no effect '" + off + "' (this sample has: " + known + ")");
        }
        const std::size_t i = std::size_t(it - names.begin());
        if (content.toggled(i)) content.toggle(i);
    }
}

// What the command line asks of the loop itself: the controls of --set (after the content's own
// start options, in order).
void apply_settings(FrameLoop& loop, const SampleOptions& options) {
    for (const std::string& setting : options.set) loop.apply_setting(setting);
}

// "  | accuracy check 37%" while one runs (the frames of a --frames run say how far it is).
std::string accuracy_note(const FrameLoop& loop) {
    if (!loop.accuracy().running()) return "";
    return "  | accuracy check " + std::to_string(int(100.0 * loop.accuracy().progress())) + "%";
}

// The end of a --frames run: the accuracy check waited for (before the last frame, so that it
// shows the result) and the scene saved (after it).
// (Waited for whether or not it still runs: one that finished unseen is taken in too.)
void before_last_frame(FrameLoop& loop, const SampleOptions& options) {
    if (options.accuracy) loop.wait_for_accuracy();
}
int after_last_frame(FrameLoop& loop, const SampleOptions& options) {
    if (options.accuracy) loop.wait_for_accuracy(); // one frame: it started in it
    if (!options.save.empty()) loop.save();
    if (options.accuracy && loop.accuracy_results() == 0) {
        std::fprintf(stderr, "%s: error: the accuracy check gave no result (%s)\n", loop.name().c_str(), loop.message().c_str());
        return 1;
    }
    return 0;
}

// --headless: an EGL context and an offscreen framebuffer with the window's formats.
int run_headless(const SampleInfo& info, const SampleOptions& options) {
    const fx::HeadlessContext context;
    std::unique_ptr<SampleContent> content = info.make(options);
    apply_start_options(*content, options);
    const int w = options.width > 0 ? options.width : content->default_width();
    const int h = options.height > 0 ? options.height : content->default_height();
    prepare_out(options.out);
    const OffscreenFramebuffer fb(w, h);
    FrameLoop loop(*content, options, info.usage.name);
    apply_settings(loop, options);
    if (options.panel.value_or(false)) loop.set_panel(make_panel(nullptr));
    std::printf("%s: headless, %dx%d, %d frames, dt %g s, gl: %s\n", info.usage.name.c_str(), w, h, options.frames,
                options.dt, context.description().c_str());
    for (int f = 0; f < options.frames; ++f) {
        if (f + 1 == options.frames) before_last_frame(loop, options);
        loop.frame(fb.id(), w, h, options.dt);
        glFinish();
        if (!options.out.empty()) fx::write_png(FrameLoop::read_back(fb.id(), w, h), frame_file(options.out, f));
        std::printf("frame %d  t %.3f s  %s%s\n", f, content->time(), loop.stats_text().c_str(), accuracy_note(loop).c_str());
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (!options.out.empty()) std::printf("wrote %d frames to %s\n", options.frames, options.out.c_str());
    return after_last_frame(loop, options);
}

struct WindowInput {
    FrameLoop* loop = nullptr;
    bool quit = false, dragging = false;
    double last_x = 0.0, last_y = 0.0;
};

int glfw_to_key(int key, int mods) {
    if (key == GLFW_KEY_S && (mods & GLFW_MOD_CONTROL)) return kKeySave;
    if ((key >= GLFW_KEY_0 && key <= GLFW_KEY_9) || (key >= GLFW_KEY_A && key <= GLFW_KEY_Z)) return key; // ASCII
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) return kKeyF1 + (key - GLFW_KEY_F1);
    if (key == GLFW_KEY_ESCAPE) return kKeyEscape;
    if (key == GLFW_KEY_TAB) return kKeyTab;
    return -1;
}

struct Glfw {
    Glfw() {
        glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
        if (!glfwInit())
            throw fx::Error("cannot open a window (no X display? DISPLAY is unset or unreachable); "
                            "run with --headless --frames N, or under xvfb-run");
    }
    ~Glfw() { glfwTerminate(); }
};

int run_window(const SampleInfo& info, const SampleOptions& options) {
    const Glfw glfw;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    glfwWindowHint(GLFW_STENCIL_BITS, 8);
    // A fixed-size run (--frames) keeps the window at the size asked for.
    glfwWindowHint(GLFW_RESIZABLE, options.frames > 0 ? GLFW_FALSE : GLFW_TRUE);
    // The window's size before the content exists: the option, or 1024 × 768 until the content
    // says otherwise (then resized).
    int w = options.width > 0 ? options.width : 1024, h = options.height > 0 ? options.height : 768;
    const std::string title = "cellfx " + info.usage.name;
    GLFWwindow* window = glfwCreateWindow(w, h, title.c_str(), nullptr, nullptr);
    if (!window) throw fx::Error("glfwCreateWindow failed: no OpenGL 4.5 core context on this display");
    struct Closer {
        GLFWwindow* w;
        ~Closer() { glfwDestroyWindow(w); }
    } closer{window};
    glfwMakeContextCurrent(window);
    glfwSwapInterval(options.frames > 0 ? 0 : 1);

    std::unique_ptr<SampleContent> content = info.make(options);
    apply_start_options(*content, options);
    if (options.width == 0) {
        w = content->default_width(), h = content->default_height();
        glfwSetWindowSize(window, w, h);
    }
    prepare_out(options.out);
    FrameLoop loop(*content, options, info.usage.name);
    apply_settings(loop, options);
    WindowInput input;
    input.loop = &loop;
    glfwSetWindowUserPointer(window, &input);
    // Input the panel takes (a slider dragged, a field typed into) does not reach the loop.
    glfwSetKeyCallback(window, [](GLFWwindow* win, int key, int, int action, int mods) {
        auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(win));
        const int code = glfw_to_key(key, mods);
        if (in->loop->panel_wants_keyboard() && code != kKeyTab) return;
        if (action == GLFW_PRESS && code >= 0 && !in->loop->key(code)) in->quit = true;
    });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* win, int button, int action, int) {
        auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(win));
        if (button != GLFW_MOUSE_BUTTON_LEFT) return;
        in->dragging = action == GLFW_PRESS && !in->loop->panel_wants_mouse();
        glfwGetCursorPos(win, &in->last_x, &in->last_y);
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* win, double x, double y) {
        auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(win));
        if (!in->dragging) return;
        constexpr double kRadiansPerPixel = 0.004;
        in->loop->look(-(x - in->last_x) * kRadiansPerPixel, -(y - in->last_y) * kRadiansPerPixel);
        in->last_x = x, in->last_y = y;
    });
    // After the sample's callbacks: ImGui's call them after its own.
    if (options.panel.value_or(true)) loop.set_panel(make_panel(window));
    std::fputs(loop.help().c_str(), stdout);
    std::fflush(stdout);

    double last = glfwGetTime(), last_print = last;
    for (int frame = 0; !glfwWindowShouldClose(window) && !input.quit; ++frame) {
        glfwPollEvents();
        const double now = glfwGetTime();
        // Fixed steps for a recorded run (comparable with --headless); real time otherwise.
        const double dt = options.frames > 0 ? options.dt : std::min(now - last, 0.25);
        last = now;
        const bool typing = loop.panel_wants_keyboard();
        const auto held = [&](int k) { return !typing && glfwGetKey(window, k) == GLFW_PRESS ? 1.0 : 0.0; };
        const bool fast = held(GLFW_KEY_LEFT_SHIFT) + held(GLFW_KEY_RIGHT_SHIFT) > 0.0;
        loop.fly(held(GLFW_KEY_W) - held(GLFW_KEY_S), held(GLFW_KEY_D) - held(GLFW_KEY_A),
                 std::min(1.0, held(GLFW_KEY_E) + held(GLFW_KEY_SPACE)) -
                     std::min(1.0, held(GLFW_KEY_Q) + held(GLFW_KEY_LEFT_CONTROL)),
                 options.frames > 0 ? options.dt : dt, fast);
        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        if (options.frames > 0 && frame + 1 == options.frames) before_last_frame(loop, options);
        loop.frame(0, fbw, fbh, dt);
        if (!options.out.empty()) {
            glFinish();
            fx::write_png(FrameLoop::read_back(0, fbw, fbh), frame_file(options.out, frame)); // before the swap
        }
        if (options.frames > 0)
            std::printf("frame %d  t %.3f s  %s%s\n", frame, content->time(), loop.stats_text().c_str(), accuracy_note(loop).c_str());
        else if (now - last_print > 2.0) {
            std::printf("%s\n", loop.stats_text().c_str());
            std::fflush(stdout);
            last_print = now;
        }
        glfwSwapBuffers(window);
        if (options.frames > 0 && frame + 1 >= options.frames) break;
    }
    const int status = options.frames > 0 ? after_last_frame(loop, options) : 0;
    loop.set_panel(nullptr); // GL objects go while the context is current
    content.reset();
    return status;
}

} // namespace

TimedRun time_sample(const SampleInfo& info, const SampleOptions& options, int frames) {
    SampleOptions o = options;
    o.overlay = false;
    std::unique_ptr<SampleContent> content = info.make(o);
    apply_start_options(*content, o);
    const int w = o.width > 0 ? o.width : content->default_width();
    const int h = o.height > 0 ? o.height : content->default_height();
    TimedRun run;
    {
        const OffscreenFramebuffer fb(w, h);
        FrameLoop loop(*content, o, info.usage.name);
        for (int f = 0; f < frames; ++f) {
            const auto t0 = std::chrono::steady_clock::now();
            loop.frame(fb.id(), w, h, o.dt);
            glFinish();
            run.frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            run.update_ms.push_back(content->update_ms());
            run.render_ms.push_back(content->render_ms());
            run.update_cpu_ms.push_back(content->update_cpu_ms());
            run.render_cpu_ms.push_back(content->render_cpu_ms());
        }
        run.cells_drawn = content->cells_drawn();
        run.path = content->path_label();
        run.background = content->background();
        run.last_frame = FrameLoop::read_back(fb.id(), w, h);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    return run;
}

const SampleInfo& find_sample(const std::string& name) {
    for (const SampleInfo& s : sample_catalog())
        if (s.usage.name == name) return s;
    throw fx::Error("no sample named '" + name + "'");
}

int run_sample(const std::string& name, int argc, char** argv) {
    const SampleInfo& info = find_sample(name);
    std::optional<SampleOptions> options;
    try {
        options = parse_options(std::vector<std::string>(argv + 1, argv + argc), info.usage);
    } catch (const fx::Error& e) {
        std::fprintf(stderr, "%s: %s\n%s", name.c_str(), e.what(), usage_text(info.usage).c_str());
        return 2;
    }
    if (!options) return 0;
    try {
        return options->headless ? run_headless(info, *options) : run_window(info, *options);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: error: %s\n", name.c_str(), e.what());
        return 1;
    }
}

} // namespace cellfx_samples
