// cellfx samples — the one frame loop the window and --headless share (see sample.hpp), the
// fly-through camera, the key bindings, and what the tuning panel works with: the controls
// (the content's and the view's own), the frame-time history, the accuracy check and saving.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "accuracy_check.hpp"
#include "frame_history.hpp"
#include "fx/image.hpp"
#include "gl/gl_object.hpp"
#include "sample.hpp"
#include "sample_gl.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

// A free camera: yaw and pitch about the scene's up axis, moved in its own frame.
class FlightCamera {
public:
    explicit FlightCamera(const fx::Camera& start);
    // Mouse look: radians of yaw (positive turns left) and pitch (positive looks up), clamped
    // to ±89°.
    void look(double yaw, double pitch);
    // Moves by `forward`, `right`, `up` world units (forward along the view, level with the
    // ground plane only through the view: flight, not walking).
    void move(double forward, double right, double up);
    const fx::Camera& camera() const { return camera_; }
    double yaw() const { return yaw_; }
    double pitch() const { return pitch_; }

private:
    void rebuild();
    fx::Camera camera_;
    glm::dvec3 up_, east_, north_; // up and a horizontal basis (east × north = up)
    double yaw_ = 0.0, pitch_ = 0.0;
    double look_distance_ = 1.0; // target kept this far ahead
};

// Keys the loop understands, independent of the window library: letters and digits as their
// upper-case ASCII codes, function keys from kKeyF1.
constexpr int kKeyEscape = 256;
constexpr int kKeyF1 = 0x101; // kKeyF1 + n − 1 for Fn, n ≤ 12
constexpr int kKeyTab = 0x120;  // shows or hides the panel
constexpr int kKeySave = 0x121; // Ctrl+S: the tuned scene to --save's file

class Panel; // panel.hpp

class FrameLoop {
public:
    FrameLoop(SampleContent& content, const SampleOptions& options, const std::string& name);
    ~FrameLoop();

    // One frame into `framebuffer` (0: the window's default framebuffer), width × height:
    // advances the clock by dt (0 when paused), updates the camera, simulates, clears, draws
    // the props, copies the depth for cellfx, lets cellfx draw, then the stats line.
    void frame(unsigned framebuffer, int width, int height, double dt);
    // The framebuffer's colour (RGBA8 read with glReadPixels, GL_BACK for the window) as an
    // fx::Image (alpha 1). Call after frame() and before any swap.
    static fx::Image read_back(unsigned framebuffer, int width, int height);

    // Input (the window): returns false when the key asks to quit.
    bool key(int code);
    void look(double yaw, double pitch);             // mouse drag, radians
    void fly(double forward, double right, double up, double seconds, bool fast); // WASD/QE held, in −1..1
    std::string help() const;                       // the key list, printed on start

    std::string stats_text() const; // the on-screen line (also printed per headless frame)
    std::string label() const;      // name, path, mode
    double last_frame_ms() const { return frame_ms_; }
    double last_wall_ms() const { return wall_ms_; }
    double fps() const { return fps_; }
    bool free_camera() const { return flight_.has_value(); }
    const fx::Camera& camera() const { return camera_; }
    const std::string& name() const { return name_; }
    SampleContent& content() { return content_; }

    // --- what the panel works with ----------------------------------------------------------
    // The content's controls and the view's own group "view": pause, time, time_scale,
    // camera_speed, gpu_timing, cpu_budget_ms, gpu_budget_ms.
    std::vector<ControlGroup> controls() const;
    void set_control(const std::string& group, const Control& value); // throws fx::Error, changes nothing
    // "GROUP.NAME=VALUE" (--set): parsed against the control's kind and range, then set.
    void apply_setting(const std::string& setting);
    // The tuned scene to options.save (what Save and Ctrl+S do). Throws fx::Error.
    void save();
    const std::string& save_path() const { return options_.save; }
    // Asks for the accuracy check of the next frame's view at `scale` × its size (1, 0.5, 0.25);
    // it starts before that frame draws.
    void request_accuracy(double scale) { accuracy_request_ = scale; }
    const AccuracyCheck& accuracy() const { return accuracy_; }
    void cancel_accuracy() { accuracy_.cancel(); }
    void wait_for_accuracy(); // until the check started is in, its result taken (none started: returns)
    const std::optional<AccuracyResult>& accuracy_result() const { return accuracy_result_; }
    std::uint64_t accuracy_results() const { return accuracy_count_; } // checks finished so far
    const FrameHistory& history() const { return history_; }
    double cpu_budget_ms() const { return cpu_budget_ms_; }
    double gpu_budget_ms() const { return gpu_budget_ms_; }
    bool gpu_timing() const { return gpu_timing_; }
    // The last message for the user (a save, a refused value, a failed check).
    const std::string& message() const { return message_; }
    void set_message(std::string text);

    void set_panel(std::unique_ptr<Panel> panel);
    bool has_panel() const { return panel_ != nullptr; }
    bool panel_shown() const { return panel_ && panel_shown_; }
    bool panel_wants_mouse() const;
    bool panel_wants_keyboard() const;

private:
    void start_requested_accuracy(int width, int height);
    void take_accuracy_result(); // the finished check's result or error, once

    SampleContent& content_;
    SampleOptions options_;
    std::string name_;
    std::optional<TextOverlay> overlay_;
    fx::gl::Texture depth_;
    int depth_width_ = 0, depth_height_ = 0;
    std::optional<FlightCamera> flight_;
    fx::Camera camera_;
    bool paused_ = false, first_ = true;
    double frame_ms_ = 0.0, wall_ms_ = 0.0, fps_ = 0.0;
    double last_frame_start_ = -1.0;
    double time_scale_ = 1.0, camera_speed_ = 1.0;
    double cpu_budget_ms_ = 1.0, gpu_budget_ms_ = 2.0; // what a game might allow cellfx a frame
    bool gpu_timing_ = false;
    FrameHistory history_;
    FrameFigures figures_;
    AccuracyCheck accuracy_;
    std::optional<double> accuracy_request_;
    std::optional<AccuracyResult> accuracy_result_;
    std::uint64_t accuracy_count_ = 0;
    std::string message_;
    std::unique_ptr<Panel> panel_;
    bool panel_shown_ = true;
};

} // namespace cellfx_samples
