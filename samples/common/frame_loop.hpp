// cellfx samples — the one frame loop the window and --headless share (see sample.hpp), the
// fly-through camera and the key bindings.
#pragma once

#include <optional>
#include <string>
#include <vector>

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

class FrameLoop {
public:
    FrameLoop(SampleContent& content, const SampleOptions& options, const std::string& name);

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
    bool free_camera() const { return flight_.has_value(); }
    const fx::Camera& camera() const { return camera_; }

private:
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
};

} // namespace cellfx_samples
