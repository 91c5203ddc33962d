// A frame's effects against the scan-line reference, on a background thread (accuracy_check.hpp).
#include "accuracy_check.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "fx/error.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

glm::vec3 heat_colour(double t) {
    // black → blue → red → yellow → white
    static const glm::vec3 stops[] = {{0.0f, 0.0f, 0.0f}, {0.1f, 0.15f, 0.9f}, {0.9f, 0.1f, 0.1f}, {1.0f, 0.9f, 0.1f}, {1.0f, 1.0f, 1.0f}};
    const double x = std::clamp(std::isfinite(t) ? t : 1.0, 0.0, 1.0) * 4.0;
    const int i = std::min(int(x), 3);
    return glm::mix(stops[i], stops[i + 1], float(x - i));
}

AccuracyResult compare_with_reference(const fx::Image& frame, const fx::Image& reference, const glm::dvec3& background) {
    if (frame.width != reference.width || frame.height != reference.height)
        throw fx::Error("accuracy: the frame is " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                        ", the reference " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
    AccuracyResult r;
    r.width = frame.width, r.height = frame.height;
    r.frame = frame;
    r.reference = fx::Image(reference.width, reference.height);
    std::vector<double> worst(frame.pixels.size(), 0.0); // per pixel, for the heat map
    double sum = 0.0;
    for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
        const glm::vec4& p = reference.pixels[i];
        r.peak = std::max({r.peak, double(p.r), double(p.g), double(p.b)});
        const glm::dvec3 shown = glm::dvec3(p.r, p.g, p.b) + (1.0 - double(p.a)) * background;
        r.reference.pixels[i] = glm::vec4(glm::vec3(shown), 1.0f);
        const glm::vec4& a = frame.pixels[i];
        if (!std::isfinite(a.r) || !std::isfinite(a.g) || !std::isfinite(a.b)) {
            r.finite = false;
            worst[i] = INFINITY;
            continue;
        }
        const glm::dvec3 d = glm::dvec3(a.r, a.g, a.b) - shown;
        sum += glm::dot(d, d);
        worst[i] = std::max({std::abs(d.r), std::abs(d.g), std::abs(d.b)});
        r.max_abs = std::max(r.max_abs, worst[i]);
    }
    r.rmse = std::sqrt(sum / (3.0 * double(std::max<std::size_t>(frame.pixels.size(), 1))));
    r.heat = fx::Image(frame.width, frame.height);
    for (std::size_t i = 0; i < worst.size(); ++i)
        r.heat.pixels[i] = glm::vec4(heat_colour(r.max_abs > 0.0 ? worst[i] / r.max_abs : 0.0), 1.0f);
    return r;
}

std::string AccuracyResult::summary() const {
    char b[256];
    std::snprintf(b, sizeof b, "mean %.3g%% worst %.3g%% of peak %.3g (rmse %.6g, max %.6g), %dx%d, reference in %.1f s%s",
                  mean_percent(), worst_percent(), peak, rmse, max_abs, width, height, seconds, finite ? "" : ", NOT FINITE");
    return b;
}

AccuracyCheck::~AccuracyCheck() { cancel(); }

void AccuracyCheck::start(ReferenceJob job) {
    cancel();
    error_.clear();
    auto state = std::make_shared<State>();
    state->total_lines = std::uint64_t(std::max(job.frame.height, 1)) * std::uint64_t(std::max(job.passes, 1));
    state_ = state;
    // The thread holds the job (copies of what the reference needs) and the shared state only.
    thread_ = std::thread([state, job = std::move(job)]() {
        try {
            const auto t0 = std::chrono::steady_clock::now();
            const fx::Image reference = job.reference(state->progress);
            if (!state->progress.cancel) {
                AccuracyResult result = compare_with_reference(job.frame, reference, job.background);
                result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                result.what = job.what;
                const std::lock_guard<std::mutex> lock(state->mutex);
                state->result = std::move(result);
            }
        } catch (const std::exception& e) {
            const std::lock_guard<std::mutex> lock(state->mutex);
            state->error = e.what();
        }
        state->done = true;
    });
}

void AccuracyCheck::cancel() {
    if (state_) state_->progress.cancel = true;
    if (thread_.joinable()) thread_.join();
    state_.reset();
}

double AccuracyCheck::progress() const {
    if (!state_) return 0.0;
    return std::min(1.0, double(state_->progress.lines_done.load()) / double(state_->total_lines));
}

std::optional<AccuracyResult> AccuracyCheck::poll() {
    if (!state_ || !state_->done) return std::nullopt;
    if (thread_.joinable()) thread_.join();
    std::optional<AccuracyResult> result;
    {
        const std::lock_guard<std::mutex> lock(state_->mutex);
        result = std::move(state_->result);
        error_ = state_->error;
    }
    state_.reset();
    return result;
}

void AccuracyCheck::wait() {
    if (thread_.joinable()) thread_.join();
}

} // namespace cellfx_samples
