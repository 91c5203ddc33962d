// Timing helpers shared by the `cellfx bench` subcommands.
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

namespace cellfx_cli {

using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// CPU time of every thread of the process so far, in ms: cellfx's, its job pool's and the GL
// driver's (on Mesa's llvmpipe the rasteriser threads too). What a frame cost the machine, which
// other work on a shared machine inflates far less than it inflates wall time.
inline double process_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

// The median of the samples (the mean of the middle two for an even count); 0 for none.
inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace cellfx_cli
