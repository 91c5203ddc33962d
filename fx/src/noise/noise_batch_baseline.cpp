// cellfx — the batch kernels for the baseline instruction set the build targets (SSE2 on
// x86-64 without -march, NEON on ARM64), four lanes.
#define FX_NOISE_ISA baseline
#define FX_NOISE_BATCH_KERNELS baseline_batch_kernels
#include "noise_batch_impl.hpp"
