// cellfx samples — what a frame's accuracy is: the effects of the current frame against the
// scan-line reference, rendered on a background thread while the window goes on drawing.
//
// The figures are those of `cellfx bench accuracy` (its one-sample-per-pixel columns), on the
// pictures a user sees: the GPU's frame (opaque, over the background) and the reference
// composited over the same background, RGB, linear, 1 = white —
//     rmse     √(mean over pixels and channels of the difference²)
//     max_abs  the largest difference of any channel of any pixel
// and, as the panel shows them, both in % of the reference's peak (its brightest channel,
// premultiplied). The heat map colours each pixel's largest channel difference from black (0)
// through blue, red and yellow to white (the worst pixel).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "fx/image.hpp"
#include "sample.hpp"

namespace cellfx_samples {

struct AccuracyResult {
    int width = 0, height = 0;
    double rmse = 0.0, max_abs = 0.0; // 1 = white
    double peak = 0.0;                // the reference's brightest channel (premultiplied)
    bool finite = true;               // no NaN or Inf in the frame
    double seconds = 0.0;             // the reference's wall time
    std::string what;                 // ReferenceJob::what
    fx::Image frame, reference;       // as displayed (the reference over the background)
    fx::Image heat;                   // the difference, coloured (alpha 1)
    double mean_percent() const { return peak > 0.0 ? 100.0 * rmse / peak : 0.0; }
    double worst_percent() const { return peak > 0.0 ? 100.0 * max_abs / peak : 0.0; }
    std::string summary() const; // "mean 0.12% worst 3.4% of peak 0.81 (rmse 0.00097, max 0.028), 64x48, 1.2 s"
};

// The comparison itself (the header comment): `reference` premultiplied, `frame` opaque.
AccuracyResult compare_with_reference(const fx::Image& frame, const fx::Image& reference, const glm::dvec3& background);
// The heat map's colour for t in [0, 1].
glm::vec3 heat_colour(double t);

// One reference at a time on its own thread. Not thread-safe itself: the render thread calls it.
class AccuracyCheck {
public:
    AccuracyCheck() = default;
    ~AccuracyCheck(); // cancels and waits
    AccuracyCheck(const AccuracyCheck&) = delete;
    AccuracyCheck& operator=(const AccuracyCheck&) = delete;

    // Starts the job's reference (a running one is cancelled first).
    void start(ReferenceJob job);
    void cancel();
    bool running() const { return state_ && !state_->done; }
    double progress() const; // 0..1 of the running job
    // The result once it is in (returned once; nullopt before, and after a failure: error()).
    std::optional<AccuracyResult> poll();
    void wait(); // until the running job is done
    const std::string& error() const { return error_; } // why the last job failed ("" : it did not)
    void clear_error() { error_.clear(); }

private:
    struct State {
        fx::ScanlineProgress progress;
        std::uint64_t total_lines = 1;
        std::atomic<bool> done{false};
        std::mutex mutex;
        std::optional<AccuracyResult> result;
        std::string error;
    };
    std::shared_ptr<State> state_;
    std::thread thread_;
    std::string error_;
};

} // namespace cellfx_samples
