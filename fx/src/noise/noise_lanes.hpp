// cellfx — the kernels that run on vector lanes (private), and the run-time choice between
// instruction sets. One implementation, noise_lanes_impl.hpp, is compiled once per instruction set
// (noise_lanes_baseline.cpp; noise_lanes_avx2.cpp on x86-64). The public batch fills
// (noise_batch.cpp) and the one-sample functions of fx::Noise (noise.cpp) validate their
// arguments and call the kernels of lane_kernels(). Every set gives the same bits: they run the
// same IEEE operations.
//
// Only plain data crosses this interface (no containers; the one inline function sits in the
// per-set namespace), so nothing compiled for AVX2 can be shared with code that runs on a CPU
// without it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>

#include "noise_fractal.hpp"

namespace cellfx::fx::noise_detail {

constexpr std::size_t kBlock = 64; // samples per block: the running sums stay in L1

template <int N> struct GridSpec {
    double origin[N];
    double step[N];
    std::size_t count[N]; // each ≥ 1
};

// One axis of one octave of a Perlin grid: cell·prime, offset and fade per grid index.
struct AxisTable {
    std::uint32_t* cell;
    float* t;
    float* fade;
};

// Caller-owned scratch of fill_grid. Perlin: a table per octave and axis, the x tables padded
// to whole blocks (kBlock). Simplex: the coordinates along each axis.
template <int N> struct GridScratch {
    AxisTable table[kMaxOctaves][N];
    double* coordinate[N];
};

// The kernels of one instruction set. fill_points reads `count` points of N doubles, point i at
// coords + i·stride. perlinN take the octave key (mix_seed) and give perlinN_at's value;
// fractalN take settings that passed check_fractal and give fractalN_at's value for their plan.
struct LaneKernels {
    const char* name;
    float (*perlin2)(std::uint32_t key, double x, double y) noexcept; // (noexcept: tail calls)
    float (*perlin3)(std::uint32_t key, double x, double y, double z) noexcept;
    float (*fractal2)(const Fractal&, std::uint32_t seed, double x, double y) noexcept;
    float (*fractal3)(const Fractal&, std::uint32_t seed, double x, double y, double z) noexcept;
    float (*fractal4)(const Fractal&, std::uint32_t seed, double x, double y, double z, double w) noexcept;
    void (*fill_grid2)(const FractalPlan&, const GridSpec<2>&, const GridScratch<2>&, float* out);
    void (*fill_grid3)(const FractalPlan&, const GridSpec<3>&, const GridScratch<3>&, float* out);
    void (*fill_grid4)(const FractalPlan&, const GridSpec<4>&, const GridScratch<4>&, float* out);
    void (*fill_points2)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
    void (*fill_points3)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
    void (*fill_points4)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
};

extern const LaneKernels kBaselineLaneKernels; // SSE2 on x86-64, NEON on ARM (one lane elsewhere)
extern const LaneKernels kAvx2LaneKernels;     // exists where FX_NOISE_HAVE_AVX2; needs an AVX2 CPU

enum class NoiseIsa { automatic, baseline, avx2 };
bool noise_isa_supported(NoiseIsa isa); // compiled in and, for AVX2, the CPU has it
// Choose the kernels lane_kernels() returns. `automatic` (the default) is AVX2 where supported,
// unless the environment variable CELLFX_NOISE_ISA=baseline is set when the noise is first used.
// For tests and benchmarks; an unsupported choice falls back to baseline.
void set_noise_isa(NoiseIsa isa);

// The kernels in use. Until the first use it points at a table whose functions make the
// choice (resolve_lane_kernels) and then call the chosen one, so that one sample costs a load and
// an indirect jump, with no test and no CPU query. (Its name is "unresolved": call
// resolve_lane_kernels() to read the chosen name.)
extern std::atomic<const LaneKernels*> g_lane_kernels;
const LaneKernels& resolve_lane_kernels();

inline namespace FX_NOISE_ISA {
inline const LaneKernels& lane_kernels() {
    return *g_lane_kernels.load(std::memory_order_relaxed);
}
} // namespace FX_NOISE_ISA

} // namespace cellfx::fx::noise_detail
