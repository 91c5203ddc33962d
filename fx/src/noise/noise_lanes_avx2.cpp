// cellfx — the lane kernels for AVX2 CPUs, eight lanes; built with -mavx2 (not -mfma: no fused
// multiply-add, so the results equal the baseline's bit for bit) and used only where the CPU
// reports AVX2 (noise_lanes.cpp).
#if !defined(__AVX2__)
#error "noise_lanes_avx2.cpp must be compiled with -mavx2"
#endif
#if defined(__FMA__)
#error "noise_lanes_avx2.cpp must not be compiled with FMA enabled"
#endif
#define FX_NOISE_ISA avx2
#define FX_NOISE_LANES 8
#define FX_NOISE_LANE_KERNELS kAvx2LaneKernels
#include "noise_lanes_impl.hpp"
