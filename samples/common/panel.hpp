// cellfx samples — the tuning panel: Dear ImGui (Debian's libimgui-dev) over the frame, taking
// the window's input (GLFW), or drawn headless without input (for pictures and tests).
//
// What it shows: the frame-time graph (FrameLoop::history: update, cellfx CPU, the driver, GPU
// ms per stage, cells drawn, with the budget lines a game would set), the accuracy check (the
// frame's effects against the scan-line reference, in the background, with a progress bar, the
// mean and worst error and a heat map), Save (the tuned scene to --save's file), and one widget
// per control of FrameLoop::controls(): every change goes through FrameLoop::set_control, so
// through the cellfx::Module calls a game would make, with the ranges the library checks.
//
// Built only when the samples find ImGui (samples/CMakeLists.txt, CELLFX_SAMPLES_IMGUI); without
// it make_panel() says so and returns nullptr, and the samples run as before (keys, --set and
// --save still work). The libraries never depend on it.
#pragma once

#include <memory>
#include <string>

namespace cellfx_samples {

class FrameLoop;

class Panel {
public:
    virtual ~Panel() = default;
    // Builds and draws the panel over the bound draw framebuffer's (0, 0, width, height); the
    // context that made the panel current. Leaves GL state as found.
    virtual void draw(FrameLoop& loop, int width, int height) = 0;
    // The window's input the panel takes this frame (the frame loop leaves it alone then).
    virtual bool wants_mouse() const = 0;
    virtual bool wants_keyboard() const = 0;
    // The size the accuracy check renders at, as a fraction of the frame's (the panel's choice).
    virtual double accuracy_scale() const = 0;
};

// A panel for the window `glfw_window` (a GLFWwindow*, its context current; the panel installs
// ImGui's input callbacks, calling those already installed after its own), or headless for
// nullptr. nullptr when the samples were built without ImGui, after printing that once.
std::unique_ptr<Panel> make_panel(void* glfw_window);
// Whether the samples were built with the panel.
bool panel_built();

} // namespace cellfx_samples
