// cellfx — the run-time choice of the noise kernels' instruction set (noise_lanes.hpp).
#include "noise_lanes.hpp"

#include <cstdlib>
#include <cstring>

namespace cellfx::fx::noise_detail {
namespace {

std::atomic<int> g_requested_isa{static_cast<int>(NoiseIsa::automatic)};

NoiseIsa automatic_isa() {
    const char* env = std::getenv("CELLFX_NOISE_ISA");
    if (env != nullptr && std::strcmp(env, "baseline") == 0) return NoiseIsa::baseline;
    return noise_isa_supported(NoiseIsa::avx2) ? NoiseIsa::avx2 : NoiseIsa::baseline;
}

const LaneKernels& kernels_for(NoiseIsa isa) {
    if (isa == NoiseIsa::automatic) isa = automatic_isa();
#if FX_NOISE_HAVE_AVX2
    if (isa == NoiseIsa::avx2 && noise_isa_supported(NoiseIsa::avx2)) return kAvx2LaneKernels;
#endif
    return kBaselineLaneKernels;
}

} // namespace

std::atomic<const LaneKernels*> g_lane_kernels{nullptr};

bool noise_isa_supported(NoiseIsa isa) {
    switch (isa) {
    case NoiseIsa::automatic:
    case NoiseIsa::baseline:
        return true;
    case NoiseIsa::avx2:
#if FX_NOISE_HAVE_AVX2
        return __builtin_cpu_supports("avx2");
#else
        return false;
#endif
    }
    return false;
}

void set_noise_isa(NoiseIsa isa) {
    g_requested_isa.store(static_cast<int>(isa));
    g_lane_kernels.store(&kernels_for(isa));
}

// Threads that race here all store the same choice (unless set_noise_isa runs at the same time,
// which only tests do).
const LaneKernels& resolve_lane_kernels() {
    const LaneKernels& chosen = kernels_for(static_cast<NoiseIsa>(g_requested_isa.load()));
    g_lane_kernels.store(&chosen);
    return chosen;
}

} // namespace cellfx::fx::noise_detail
