// The samples' shared frame loop (frame_loop.hpp).
#include "frame_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"
#include "gl_call_clock.hpp"
#include "io/output_file.hpp"
#include "panel.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

double now_ms() {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string fixed(double v, int digits) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
    return buffer;
}

} // namespace

FlightCamera::FlightCamera(const fx::Camera& start) : camera_(start) {
    // The world's up, of any length (scaled first: an up of 1e-300 is an up, as everywhere).
    up_ = glm::normalize(start.up / std::max({std::abs(start.up.x), std::abs(start.up.y), std::abs(start.up.z)}));
    const glm::dvec3 f = start.forward();
    // A horizontal basis: the view's heading if it has one, else any direction across up.
    glm::dvec3 heading = f - glm::dot(f, up_) * up_;
    if (glm::length(heading) < 1e-9) heading = std::abs(up_.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    heading -= glm::dot(heading, up_) * up_;
    east_ = glm::normalize(heading);
    north_ = glm::cross(up_, east_);
    yaw_ = 0.0;
    pitch_ = std::asin(std::clamp(glm::dot(f, up_), -1.0, 1.0));
    look_distance_ = std::max(glm::length(start.target - start.eye), 1e-6);
    rebuild();
}

void FlightCamera::look(double yaw, double pitch) {
    yaw_ += yaw;
    const double limit = glm::radians(89.0);
    pitch_ = std::clamp(pitch_ + pitch, -limit, limit);
    rebuild();
}

void FlightCamera::move(double forward, double right, double up) {
    const glm::dvec3 f = camera_.forward();
    const glm::dvec3 r = glm::normalize(glm::cross(f, up_));
    camera_.eye += f * forward + r * right + up_ * up;
    rebuild();
}

void FlightCamera::rebuild() {
    const glm::dvec3 heading = std::cos(yaw_) * east_ + std::sin(yaw_) * north_;
    const glm::dvec3 f = std::cos(pitch_) * heading + std::sin(pitch_) * up_;
    camera_.target = camera_.eye + look_distance_ * f;
    camera_.up = up_;
}

FrameLoop::FrameLoop(SampleContent& content, const SampleOptions& options, const std::string& name)
    : content_(content), options_(options), name_(name) {
    if (options.overlay) overlay_.emplace();
    camera_ = content_.scripted_camera(content_.time());
    if (options.accuracy) accuracy_request_ = 1.0;
}

FrameLoop::~FrameLoop() = default;

void FrameLoop::set_message(std::string text) {
    message_ = std::move(text);
    std::printf("%s: %s\n", name_.c_str(), message_.c_str());
    std::fflush(stdout);
}

void FrameLoop::frame(unsigned framebuffer, int width, int height, double dt) {
    if (width <= 0 || height <= 0) return; // a minimised window: nothing to draw
    const double start = now_ms();
    if (last_frame_start_ >= 0.0) {
        wall_ms_ = start - last_frame_start_;
        const double fps = wall_ms_ > 0.0 ? 1000.0 / wall_ms_ : 0.0;
        fps_ = fps_ > 0.0 ? 0.9 * fps_ + 0.1 * fps : fps;
    }
    last_frame_start_ = start;
    take_accuracy_result();
    const double step = first_ || paused_ ? 0.0 : dt * time_scale_;
    first_ = false;
    camera_ = flight_ ? flight_->camera() : content_.scripted_camera(content_.time() + step);
    // cellfx's CPU apart from the GL driver's (for the panel's graph; GlCallClock wraps the GL
    // entry points, so only while there is a panel to show it).
    const bool measure = panel_ != nullptr;
    if (measure) {
        GlCallClock::install();
        GlCallClock::reset();
        GlCallClock::set_running(true);
    }
    const double cpu0 = GlCallClock::thread_cpu_ms();
    content_.update(step, camera_, width, height);
    const double cpu1 = GlCallClock::thread_cpu_ms();
    GlCallClock::set_running(false);
    // The accuracy check asked for: this frame's time and view (it draws offscreen).
    if (accuracy_request_) start_requested_accuracy(width, height);

    // The "game" part of the frame: background, the sample's own opaque geometry with depth.
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    const glm::vec3 bg = content_.background();
    glClearColor(bg.r, bg.g, bg.b, 1.0f);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (options_.props) content_.draw_props(camera_, width, height);

    // cellfx reads depth from a texture: copy the framebuffer's depth buffer into one (what a
    // game drawing into the window's default framebuffer does; a game with its own depth
    // texture hands that over instead).
    if (!depth_ || depth_width_ != width || depth_height_ != height) {
        depth_ = fx::gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(depth_.id(), 1, GL_DEPTH_COMPONENT24, width, height);
        glTextureParameteri(depth_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(depth_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        depth_width_ = width, depth_height_ = height;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glCopyTextureSubImage2D(depth_.id(), 0, 0, 0, 0, 0, width, height);

    GlCallClock::set_running(measure);
    const double cpu2 = GlCallClock::thread_cpu_ms();
    content_.render(framebuffer, fx::Viewport{0, 0, width, height}, depth_.id());
    const double cpu3 = GlCallClock::thread_cpu_ms();
    GlCallClock::set_running(false);
    if (measure) {
        figures_.frame_ms = wall_ms_;
        figures_.update_ms = cpu1 - cpu0;
        figures_.driver_ms = GlCallClock::driver_ms();
        figures_.cellfx_cpu_ms = (cpu1 - cpu0) + (cpu3 - cpu2) - figures_.driver_ms;
        figures_.cells_drawn = content_.cells_drawn();
        content_.gpu_stages(figures_.gpu);
        history_.push(figures_);
    }
    if (overlay_) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        overlay_->draw({label(), stats_text()}, width, height, width >= 1600 ? 2.0f : 1.0f);
    }
    if (panel_ && panel_shown_) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        panel_->draw(*this, width, height);
    }
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR) {
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", error);
        throw fx::Error(name_ + ": GL error " + code + " in the frame");
    }
    frame_ms_ = now_ms() - start;
}

fx::Image FrameLoop::read_back(unsigned framebuffer, int width, int height) {
    std::vector<unsigned char> rgba(std::size_t(width) * std::size_t(height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glReadBuffer(framebuffer == 0 ? GL_BACK : GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    fx::Image image(width, height);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        image.pixels[i] = glm::vec4(rgba[4 * i] / 255.0f, rgba[4 * i + 1] / 255.0f, rgba[4 * i + 2] / 255.0f, 1.0f);
    return image;
}

std::string FrameLoop::label() const {
    std::string s = name_ + "  |  path " + content_.path_label();
    std::string off;
    const std::vector<std::string> toggles = content_.toggle_names();
    for (std::size_t i = 0; i < toggles.size(); ++i)
        if (!content_.toggled(i)) off += (off.empty() ? "" : ",") + toggles[i];
    if (!off.empty()) s += "  |  off: " + off;
    if (paused_) s += "  |  paused";
    s += flight_ ? "  |  free camera (C: back to the scene's)" : "  |  scene camera";
    return s;
}

std::string FrameLoop::stats_text() const {
    std::string s;
    if (fps_ > 0.0) s += fixed(fps_, 1) + " fps  ";
    s += "frame " + fixed(frame_ms_, 1) + " ms (update " + fixed(content_.update_ms(), 1) + ", cellfx " +
         fixed(content_.render_ms(), 1) + ")  cells " + std::to_string(content_.cells_drawn()) + "  |  " +
         content_.stats_line();
    return s;
}

std::string FrameLoop::help() const {
    std::ostringstream out;
    out << name_ << " — keys:\n"
        << "  mouse drag (left button)  look around        W A S D  fly     Q E / space ctrl  down / up\n"
        << "  shift                     fly faster          C        back to the scene's camera\n"
        << "  P  pause the clock        H  this help        Esc      quit\n"
        << "  Tab  the tuning panel     R  accuracy against the scan-line reference      Ctrl+S  save (--save FILE)\n";
    const std::vector<fx::RenderPath> paths = content_.paths();
    out << "  render path:";
    for (std::size_t i = 0; i < paths.size(); ++i) out << "  " << i + 1 << " " << fx::render_path_name(paths[i]);
    out << "\n  toggle:     ";
    const std::vector<std::string> toggles = content_.toggle_names();
    for (std::size_t i = 0; i < toggles.size() && i < 12; ++i) out << "  F" << i + 1 << " " << toggles[i];
    out << "\n";
    for (const std::string& line : content_.key_help()) out << "  " << line << "\n";
    return out.str();
}

bool FrameLoop::key(int code) {
    if (code == kKeyEscape) return false;
    const std::vector<fx::RenderPath> paths = content_.paths();
    if (code >= '1' && code <= '9') {
        const std::size_t i = std::size_t(code - '1');
        if (i < paths.size()) content_.set_path(paths[i]);
        return true;
    }
    if (code >= kKeyF1 && code < kKeyF1 + 12) {
        const std::size_t i = std::size_t(code - kKeyF1);
        if (i < content_.toggle_names().size()) content_.toggle(i);
        return true;
    }
    switch (code) {
    case 'P': paused_ = !paused_; return true;
    case 'C': flight_.reset(); return true;
    case 'H': std::fputs(help().c_str(), stdout); return true;
    case 'R': request_accuracy(panel_ ? panel_->accuracy_scale() : 1.0); return true;
    case kKeyTab: panel_shown_ = !panel_shown_; return true;
    case kKeySave:
        try {
            save();
        } catch (const fx::Error& e) {
            set_message(e.what());
        }
        return true;
    default: break;
    }
    if (code >= 'A' && code <= 'Z') content_.key(char(code));
    return true;
}

void FrameLoop::look(double yaw, double pitch) {
    if (!flight_) flight_.emplace(camera_);
    flight_->look(yaw, pitch);
}

void FrameLoop::fly(double forward, double right, double up, double seconds, bool fast) {
    if (forward == 0.0 && right == 0.0 && up == 0.0) return;
    if (!flight_) flight_.emplace(camera_);
    // A third of the scene camera's viewing distance per second: metres around a campfire,
    // hundreds of metres over a valley.
    const fx::Camera scripted = content_.scripted_camera(content_.time());
    const double speed = camera_speed_ * (fast ? 5.0 : 1.0) * std::max(glm::length(scripted.target - scripted.eye), 1e-3) / 3.0;
    flight_->move(forward * speed * seconds, right * speed * seconds, up * speed * seconds);
}

// ---- what the panel works with ----------------------------------------------------------------

namespace {

Control view_number(const std::string& name, double value, const fx::ParameterRange& range, const std::string& unit,
                    const std::string& note) {
    Control c;
    c.name = name, c.kind = Control::Kind::Number, c.number = value, c.range = range, c.unit = unit, c.note = note;
    return c;
}
Control view_toggle(const std::string& name, bool on, const std::string& note) {
    Control c;
    c.name = name, c.kind = Control::Kind::Toggle, c.toggle = on, c.note = note;
    return c;
}

} // namespace

std::vector<ControlGroup> FrameLoop::controls() const {
    std::vector<ControlGroup> groups = content_.controls();
    ControlGroup view{"view", "clock, camera and graph", {}};
    view.controls.push_back(view_toggle("pause", paused_, "the scene clock stops (P)"));
    // The clock's range: --time's.
    view.controls.push_back(view_number("time", content_.time(), {-1e6, 1e6, false}, "s", "the scene clock"));
    view.controls.push_back(view_number("time_scale", time_scale_, {0.0, 100.0, false}, "x", "scene seconds per second"));
    view.controls.push_back(view_number("camera_speed", camera_speed_, {0.0, 1000.0, true}, "x",
                                        "free camera (WASD): a third of the scene camera's distance a second at 1"));
    view.controls.push_back(view_toggle("gpu_timing", gpu_timing_, "GPU ms per stage (each stage waits for its timer: slower frames)"));
    view.controls.push_back(view_number("cpu_budget_ms", cpu_budget_ms_, {0.0, 1000.0, true}, "ms", "the graph's CPU budget line"));
    view.controls.push_back(view_number("gpu_budget_ms", gpu_budget_ms_, {0.0, 1000.0, true}, "ms", "the graph's GPU budget line"));
    groups.push_back(std::move(view));
    return groups;
}

void FrameLoop::set_control(const std::string& group, const Control& c) {
    if (group != "view") {
        content_.set_control(group, c);
        return;
    }
    if (c.name == "pause") paused_ = c.toggle;
    else if (c.name == "time") content_.set_time(c.number);
    else if (c.name == "time_scale") time_scale_ = c.number;
    else if (c.name == "camera_speed") camera_speed_ = c.number;
    else if (c.name == "gpu_timing") {
        content_.set_gpu_timing(c.toggle);
        gpu_timing_ = c.toggle;
    } else if (c.name == "cpu_budget_ms") cpu_budget_ms_ = c.number;
    else if (c.name == "gpu_budget_ms") gpu_budget_ms_ = c.number;
    else throw fx::Error("no control 'view." + c.name + "'");
}

void FrameLoop::apply_setting(const std::string& setting) {
    const std::size_t dot = setting.find('.'), equals = setting.find('=', dot);
    if (dot == std::string::npos || equals == std::string::npos)
        throw fx::Error("--set: expected GROUP.NAME=VALUE, got '" + setting + "'");
    const std::string group = setting.substr(0, dot), name = setting.substr(dot + 1, equals - dot - 1);
    const std::string value = setting.substr(equals + 1);
    std::string groups;
    for (const ControlGroup& g : controls()) {
        groups += (groups.empty() ? "" : ", ") + g.name;
        if (g.name != group) continue;
        std::string names;
        for (const Control& c : g.controls) {
            if (c.name == name) {
                try {
                    set_control(group, parse_control_value(c, value));
                } catch (const fx::Error& e) {
                    throw fx::Error("--set " + setting + ": " + e.what());
                }
                return;
            }
            names += (names.empty() ? "" : ", ") + c.name;
        }
        throw fx::Error("--set " + setting + ": no control '" + name + "' in " + group + " (it has: " + names + ")");
    }
    throw fx::Error("--set " + setting + ": no group '" + group + "' (this sample has: " + groups + ")");
}

void FrameLoop::save() {
    if (options_.save.empty()) throw fx::Error("save: start the sample with --save FILE to say where the tuned scene goes");
    const std::filesystem::path file(options_.save);
    const std::string folder = file.parent_path().empty() ? "." : file.parent_path().string();
    const std::optional<std::string> text = content_.scene_file_text(folder);
    if (!text) throw fx::Error("save: " + name_ + " has no scene file to save");
    fx::io::write_output_file(options_.save, *text); // whole or not at all
    set_message("saved the tuned scene to " + options_.save);
}

void FrameLoop::start_requested_accuracy(int width, int height) {
    const double scale = *accuracy_request_;
    accuracy_request_.reset();
    const int w = std::max(1, int(std::lround(width * scale))), h = std::max(1, int(std::lround(height * scale)));
    try {
        std::optional<ReferenceJob> job = content_.reference_job(camera_, w, h);
        if (!job) {
            set_message("accuracy: nothing in view to compare");
            return;
        }
        accuracy_.start(std::move(*job));
    } catch (const fx::Error& e) {
        set_message(std::string("accuracy check failed: ") + e.what());
    }
}

void FrameLoop::wait_for_accuracy() {
    accuracy_.wait();
    last_frame_start_ = -1.0; // the wait is no frame's time: the next frame keeps the last one's
    take_accuracy_result();
}

void FrameLoop::take_accuracy_result() {
    if (std::optional<AccuracyResult> result = accuracy_.poll()) {
        accuracy_result_ = std::move(result);
        ++accuracy_count_;
        // Printed; the panel shows the result in its own section.
        std::printf("%s: accuracy: %s\n", name_.c_str(), accuracy_result_->summary().c_str());
        std::fflush(stdout);
    } else if (!accuracy_.error().empty()) {
        set_message("accuracy check failed: " + accuracy_.error());
        accuracy_.clear_error();
    }
}

void FrameLoop::set_panel(std::unique_ptr<Panel> panel) { panel_ = std::move(panel); }
bool FrameLoop::panel_wants_mouse() const { return panel_ && panel_shown_ && panel_->wants_mouse(); }
bool FrameLoop::panel_wants_keyboard() const { return panel_ && panel_shown_ && panel_->wants_keyboard(); }

} // namespace cellfx_samples
