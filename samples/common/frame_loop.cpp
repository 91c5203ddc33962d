// The samples' shared frame loop (frame_loop.hpp).
#include "frame_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"
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
    const double step = first_ || paused_ ? 0.0 : dt;
    first_ = false;
    camera_ = flight_ ? flight_->camera() : content_.scripted_camera(content_.time() + step);
    content_.update(step, camera_, width, height);

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

    content_.render(framebuffer, fx::Viewport{0, 0, width, height}, depth_.id());
    if (overlay_) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        overlay_->draw({label(), stats_text()}, width, height, width >= 1600 ? 2.0f : 1.0f);
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
        << "  P  pause the clock        H  this help        Esc      quit\n";
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
    const double speed = (fast ? 5.0 : 1.0) * std::max(glm::length(scripted.target - scripted.eye), 1e-3) / 3.0;
    flight_->move(forward * speed * seconds, right * speed * seconds, up * speed * seconds);
}

} // namespace cellfx_samples
