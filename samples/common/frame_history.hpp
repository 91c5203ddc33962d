// cellfx samples — the last few hundred frames' figures, for the panel's frame-time graph.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sample.hpp"

namespace cellfx_samples {

// One frame's figures (milliseconds; GPU stages empty unless GPU timing is on).
struct FrameFigures {
    double frame_ms = 0.0;      // the frame loop's CPU wall time (clock to stats line)
    double update_ms = 0.0;     // cellfx's update(): CPU of the calling thread
    double cellfx_cpu_ms = 0.0; // update() and render() minus the GL driver's part (GlCallClock)
    double driver_ms = 0.0;     // the GL driver's CPU on this thread inside render()
    std::vector<SampleContent::StageTime> gpu; // per stage
    std::size_t cells_drawn = 0;
};

// A ring of the last kFrames frames, one series per figure (and per GPU stage, NaN for frames
// without it): oldest first when read.
class FrameHistory {
public:
    static constexpr std::size_t kFrames = 300;
    struct Series {
        std::string name; // "cellfx CPU", "update", "driver", "gpu fog", ...
        bool gpu = false;
        std::vector<float> values; // kFrames, ring order (see head())
    };
    FrameHistory();
    void push(const FrameFigures& f);
    const std::vector<Series>& series() const { return series_; }
    const Series& cells() const { return cells_; }
    std::size_t head() const { return head_; }   // index of the oldest frame in each ring
    std::size_t frames() const { return count_; } // frames recorded (≤ kFrames)
    // The series' value `age` frames ago (0: the last), NaN where there is none.
    float at(const Series& s, std::size_t age) const;

private:
    Series& find(const std::string& name, bool gpu);
    std::vector<Series> series_;
    Series cells_;
    std::size_t head_ = 0, count_ = 0;
};

} // namespace cellfx_samples
