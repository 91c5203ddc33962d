// The frame-time graph's history (frame_history.hpp).
#include "frame_history.hpp"

#include <cmath>

namespace cellfx_samples {

FrameHistory::FrameHistory() {
    for (const char* name : {"cellfx CPU", "update", "driver", "frame"}) series_.push_back({name, false, std::vector<float>(kFrames, NAN)});
    cells_ = {"cells drawn", false, std::vector<float>(kFrames, NAN)};
}

FrameHistory::Series& FrameHistory::find(const std::string& name, bool gpu) {
    for (Series& s : series_)
        if (s.name == name) return s;
    series_.push_back({name, gpu, std::vector<float>(kFrames, NAN)});
    return series_.back();
}

void FrameHistory::push(const FrameFigures& f) {
    const std::size_t slot = head_; // the oldest slot becomes the newest frame
    for (Series& s : series_) s.values[slot] = NAN;
    series_[0].values[slot] = float(f.cellfx_cpu_ms);
    series_[1].values[slot] = float(f.update_ms);
    series_[2].values[slot] = float(f.driver_ms);
    series_[3].values[slot] = float(f.frame_ms);
    double gpu_total = 0.0;
    for (const SampleContent::StageTime& st : f.gpu) {
        find("gpu " + st.name, true).values[slot] = float(st.gpu_ms);
        gpu_total += st.gpu_ms;
    }
    if (!f.gpu.empty()) find("gpu total", true).values[slot] = float(gpu_total);
    cells_.values[slot] = float(f.cells_drawn);
    head_ = (head_ + 1) % kFrames;
    if (count_ < kFrames) ++count_;
}

float FrameHistory::at(const Series& s, std::size_t age) const {
    if (age >= count_) return NAN;
    return s.values[(head_ + kFrames - 1 - age) % kFrames];
}

} // namespace cellfx_samples
