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

// The first call of any kernel lands here, makes the choice and forwards.
const LaneKernels kResolvingLaneKernels = {
    "unresolved",
    [](std::uint32_t key, double x, double y) noexcept { return resolve_lane_kernels().perlin2(key, x, y); },
    [](std::uint32_t key, double x, double y, double z) noexcept {
        return resolve_lane_kernels().perlin3(key, x, y, z);
    },
    [](const Fractal& fractal, std::uint32_t seed, double x, double y) noexcept {
        return resolve_lane_kernels().fractal2(fractal, seed, x, y);
    },
    [](const Fractal& fractal, std::uint32_t seed, double x, double y, double z) noexcept {
        return resolve_lane_kernels().fractal3(fractal, seed, x, y, z);
    },
    [](const Fractal& fractal, std::uint32_t seed, double x, double y, double z, double w) noexcept {
        return resolve_lane_kernels().fractal4(fractal, seed, x, y, z, w);
    },
    [](const FractalPlan& plan, const GridSpec<2>& grid, const GridScratch<2>& scratch, float* out) {
        resolve_lane_kernels().fill_grid2(plan, grid, scratch, out);
    },
    [](const FractalPlan& plan, const GridSpec<3>& grid, const GridScratch<3>& scratch, float* out) {
        resolve_lane_kernels().fill_grid3(plan, grid, scratch, out);
    },
    [](const FractalPlan& plan, const GridSpec<4>& grid, const GridScratch<4>& scratch, float* out) {
        resolve_lane_kernels().fill_grid4(plan, grid, scratch, out);
    },
    [](const FractalPlan& plan, const double* coords, std::size_t stride, std::size_t count, float* out) {
        resolve_lane_kernels().fill_points2(plan, coords, stride, count, out);
    },
    [](const FractalPlan& plan, const double* coords, std::size_t stride, std::size_t count, float* out) {
        resolve_lane_kernels().fill_points3(plan, coords, stride, count, out);
    },
    [](const FractalPlan& plan, const double* coords, std::size_t stride, std::size_t count, float* out) {
        resolve_lane_kernels().fill_points4(plan, coords, stride, count, out);
    },
};

} // namespace

std::atomic<const LaneKernels*> g_lane_kernels{&kResolvingLaneKernels};

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
// which only tests do). Later calls return the stored choice.
const LaneKernels& resolve_lane_kernels() {
    const LaneKernels* current = g_lane_kernels.load();
    if (current != &kResolvingLaneKernels) return *current;
    const LaneKernels& chosen = kernels_for(static_cast<NoiseIsa>(g_requested_isa.load()));
    g_lane_kernels.store(&chosen);
    return chosen;
}

} // namespace cellfx::fx::noise_detail
