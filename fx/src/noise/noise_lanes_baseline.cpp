// cellfx — the lane kernels for the baseline instruction set the build targets (SSE2 on x86-64
// without -march, NEON on ARM64), four lanes.
#define FX_NOISE_ISA baseline
#define FX_NOISE_LANE_KERNELS kBaselineLaneKernels
#include "noise_lanes_impl.hpp"
