// cellfx — the batch kernels' interface (private): one implementation, noise_batch_impl.hpp,
// compiled once per instruction set (noise_batch_baseline.cpp; noise_batch_avx2.cpp on x86-64),
// and the public fill_* functions in noise_batch.cpp, which validate, allocate and pick the
// kernels at run time. Every set gives the same bits: they run the same IEEE operations.
//
// Only plain data crosses this interface (no inline functions, no containers), so nothing
// compiled for AVX2 can be shared with code that runs on a CPU without it.
#pragma once

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

// The batch kernels of one instruction set. fill_points reads `count` points of N doubles,
// point i at coords + i·stride.
struct BatchKernels {
    const char* name;
    void (*fill_grid2)(const FractalPlan&, const GridSpec<2>&, const GridScratch<2>&, float* out);
    void (*fill_grid3)(const FractalPlan&, const GridSpec<3>&, const GridScratch<3>&, float* out);
    void (*fill_grid4)(const FractalPlan&, const GridSpec<4>&, const GridScratch<4>&, float* out);
    void (*fill_points2)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
    void (*fill_points3)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
    void (*fill_points4)(const FractalPlan&, const double* coords, std::size_t stride, std::size_t count, float* out);
};

const BatchKernels& baseline_batch_kernels(); // SSE2 on x86-64, NEON on ARM (one lane elsewhere)
const BatchKernels& avx2_batch_kernels();     // exists where FX_NOISE_HAVE_AVX2; needs an AVX2 CPU

enum class BatchIsa { automatic, baseline, avx2 };
bool batch_isa_supported(BatchIsa isa); // compiled in and, for AVX2, the CPU has it
// The kernels fill_* use. `automatic` (the default) is AVX2 where supported, unless the
// environment variable CELLFX_NOISE_ISA=baseline is set when the first fill runs. For tests
// and benchmarks; an unsupported choice falls back to baseline.
void set_batch_isa(BatchIsa isa);
const BatchKernels& batch_kernels();

} // namespace cellfx::fx::noise_detail
