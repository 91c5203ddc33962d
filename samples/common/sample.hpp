// cellfx samples — the small framework every sample (samples/<name>/main.cpp) runs on.
//
// One frame loop (FrameLoop, frame_loop.hpp) draws a sample's content into a framebuffer the
// way a game would: clear to the background, draw the sample's own opaque geometry with depth,
// copy that depth into a texture for cellfx, let cellfx draw over it, then the frame-stats line.
// The framebuffer is the GLFW window's default framebuffer (OpenGL 4.5 core) or, with
// --headless, an offscreen framebuffer of the same formats (RGBA8 + 24-bit depth) in an EGL
// context — the same code either way, so the headless frames the tests check are the frames
// the window shows.
//
// A sample is a SampleContent (what to simulate and draw, which render paths and toggles it
// offers, the controls of its tuning panel) made by a factory from the parsed command line;
// run_sample() does the rest. The panel (panel.hpp, Dear ImGui) is drawn by the frame loop when
// the samples are built with ImGui; everything it changes goes through SampleContent's
// controls, which --set reaches from the command line as well.
//
// Ownership: FrameLoop and the content own their GL objects; the context must be current for
// every call and when they are destroyed. One thread.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect_parameters.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

// The command line every sample understands (parse_options documents each flag).
struct SampleOptions {
    bool headless = false;
    int frames = 0;                   // 0: run until the window is closed (window only)
    std::string out;                  // folder for frame_NNNN.png ("" : none written)
    int width = 0, height = 0;        // 0: the content's default size
    std::optional<fx::RenderPath> path; // every effect drawn with this path (default: the scene's)
    double dt = 1.0 / 30.0;           // scene seconds per frame with --frames (fixed steps)
    double start_time = 0.0;          // scene clock of the first frame
    bool overlay = true;              // the frame-stats line
    bool props = true;                // the sample's own opaque geometry (searchlight's drone)
    std::vector<std::string> disable; // effects switched off at start
    std::optional<bool> panel;        // the tuning panel (default: shown in a window, not headless)
    std::vector<std::string> set;     // "GROUP.NAME=VALUE": controls set at start (as the panel sets them)
    std::string save;                 // scene file the panel's Save writes ("" : none); with --frames, after the last frame
    bool accuracy = false;            // the accuracy check of the first frame (printed; the panel shows it)
    // Sample-specific: positional arguments and --name value options it declared.
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;
};

// What a sample declares about its command line.
struct SampleUsage {
    std::string name;                     // "campfire"
    std::string summary;                  // one line
    std::string positional;               // e.g. "[MESH [Q_FILE]]" ("" : none accepted)
    std::size_t max_positional = 0;
    std::vector<std::pair<std::string, std::string>> options; // {"--scalar NAME", "help"}
};

// Parses argv (without argv[0]). Throws fx::Error with a message naming the bad argument.
// Returns nullopt for --help (after printing the usage).
std::optional<SampleOptions> parse_options(const std::vector<std::string>& args, const SampleUsage& usage);
std::string usage_text(const SampleUsage& usage);

// One thing a user can tune: a toggle, a choice, a number or a vector, with its current value.
// The panel draws one widget per control; --set parses its text into one (parse_control_value).
struct Control {
    enum class Kind { Toggle, Choice, Number, Integer, Vector, Direction };
    std::string name;                 // "base_radius", "enabled", "path"
    Kind kind = Kind::Number;
    fx::ParameterRange range;         // Number, Integer, each Vector component: what the library accepts
    std::vector<std::string> choices; // Choice
    std::string unit;                 // "m", "ms", "degrees" ("" : none)
    std::string note;                 // what a change costs ("rebuild", "scalars", "pose") or means
    // The value (by kind).
    bool toggle = false;
    double number = 0.0; // Number, Integer
    glm::dvec3 vector{0.0};
    std::string choice;
};
struct ControlGroup {
    std::string name;  // what --set names: "fire", "fog", "scene", "view"
    std::string title; // "fire (campfire)"
    std::vector<Control> controls;
};
// `control` with the value `text` ("0.8", "12", "1,2,3", "true"/"false"/"on"/"off", a choice's
// name), checked against its kind and range. Throws fx::Error naming the control.
Control parse_control_value(const Control& control, const std::string& text);
std::string control_value_text(const Control& control); // the value as --set takes it

// The effects of a frame, ready to be compared with the scan-line reference: the GPU's picture
// of them alone (opaque, over the background; no terrain, no props) and a job that renders the
// reference of the same volumes on another thread (it holds copies: nothing of the content).
struct ReferenceJob {
    fx::Image frame;          // float, alpha 1, bottom row first
    glm::dvec3 background{0.0};
    int passes = 1;           // scan-line frames the job renders (progress: height × passes lines)
    std::function<fx::Image(fx::ScanlineProgress&)> reference; // premultiplied RGBA
    std::string what;         // what is compared, one line
};

// A sample's scene: everything the frame loop needs from it. All calls with the context current.
class SampleContent {
public:
    virtual ~SampleContent() = default;
    virtual int default_width() const { return 1024; }
    virtual int default_height() const { return 768; }
    virtual glm::vec3 background() const = 0;
    // The scripted camera (camera path or fixed view) at scene time t.
    virtual fx::Camera scripted_camera(double t) const = 0;
    virtual double time() const = 0;
    virtual void set_time(double seconds) = 0; // the scene clock (the panel's slider)
    // Advances the scene clock by dt (≥ 0) and simulates the view (no drawing).
    virtual void update(double dt, const fx::Camera& camera, int width, int height) = 0;
    // Opaque geometry of the sample itself, drawn with depth test and writes into the bound
    // framebuffer before cellfx (default: none). Leaves GL state as found.
    virtual void draw_props(const fx::Camera& /*camera*/, int /*width*/, int /*height*/) {}
    // cellfx's part of the frame, over the framebuffer's contents; depth_texture holds the
    // frame's depth (window depth in [0, 1], the camera of update()).
    virtual void render(unsigned framebuffer, const fx::Viewport& viewport, unsigned depth_texture) = 0;

    // Render paths offered (keys 1, 2, ...) and the one in use ("" : the scene's own mix).
    virtual std::vector<fx::RenderPath> paths() const = 0;
    virtual void set_path(fx::RenderPath path) = 0;
    virtual std::string path_label() const = 0;
    // Toggles (F1, F2, ...): names and states.
    virtual std::vector<std::string> toggle_names() const = 0;
    virtual bool toggled(std::size_t i) const = 0;
    virtual void toggle(std::size_t i) = 0;
    // Sample-specific keys: 'A'..'Z' (after the framework's own); returns true if used.
    virtual bool key(char /*letter*/) { return false; }
    virtual std::vector<std::string> key_help() const { return {}; }

    // The frame's statistics for the on-screen line and the headless log.
    virtual std::string stats_line() const = 0;
    virtual std::size_t cells_drawn() const = 0;
    virtual double update_ms() const = 0; // simulation part of the last frame
    virtual double render_ms() const = 0; // cellfx's render part of the last frame (CPU)
    // CPU time the frame's cellfx calls took on the calling thread, waiting for the GPU excluded
    // (update: cellfx alone; render: cellfx and the GL driver's work on that thread).
    virtual double update_cpu_ms() const = 0;
    virtual double render_cpu_ms() const = 0;
    // GPU time of the last frame per stage ("surface", "fog", "fire", ...; GL timer queries),
    // while set_gpu_timing(true): each stage waits for its result, which costs frame rate.
    struct StageTime {
        std::string name;
        double gpu_ms = 0.0;
    };
    virtual void set_gpu_timing(bool /*on*/) {}
    virtual void gpu_stages(std::vector<StageTime>& out) const { out.clear(); }

    // The panel's controls, grouped (current values), and the call that changes one: through
    // the API a game would use (cellfx::Module for the scene samples). set_control throws
    // fx::Error naming the control and what is wrong, and then changes nothing.
    virtual std::vector<ControlGroup> controls() const { return {}; }
    virtual void set_control(const std::string& group, const Control& value);
    // The tuned scene as a scene file saved in the folder `save_dir` (nullopt: the content has
    // no scene file to write).
    virtual std::optional<std::string> scene_file_text(const std::string& /*save_dir*/) const { return std::nullopt; }
    // The current frame's effects and their reference job (nullopt: nothing to compare) for
    // `camera` at width × height (context current; may draw offscreen).
    virtual std::optional<ReferenceJob> reference_job(const fx::Camera& /*camera*/, int /*width*/, int /*height*/) {
        return std::nullopt;
    }
};

using ContentFactory = std::function<std::unique_ptr<SampleContent>(const SampleOptions&)>;

// One of the five samples (for the executables, the tests' reference renders and the bench).
struct SampleInfo {
    SampleUsage usage;
    bool animated = false; // frames change with time from the scripted camera
    ContentFactory make;
};
const std::vector<SampleInfo>& sample_catalog();
const SampleInfo& find_sample(const std::string& name); // throws fx::Error for an unknown name

// Timing for `cellfx bench effects`: `frames` frames of the sample's frame loop into an offscreen
// framebuffer (as --headless draws them; no PNGs, no overlay) in the current GL context, each
// to glFinish. Returns per-frame wall ms and the last frame (read back) with its statistics.
struct TimedRun {
    std::vector<double> frame_ms, update_ms, render_ms, update_cpu_ms, render_cpu_ms;
    std::size_t cells_drawn = 0;
    std::string path; // the content's path label
    fx::Image last_frame;
    glm::vec3 background{0.0f};
};
TimedRun time_sample(const SampleInfo& info, const SampleOptions& options, int frames);

// The whole program: parses argv, runs the window or the headless loop, prints errors.
// Returns the process exit code (0 fine, 1 runtime error, 2 bad arguments).
int run_sample(const std::string& name, int argc, char** argv);

} // namespace cellfx_samples
