// cellfx — the lane kernels of one instruction set and their table (noise_lanes.hpp). Included
// once per set, by noise_lanes_baseline.cpp and noise_lanes_avx2.cpp, with FX_NOISE_ISA,
// FX_NOISE_LANES and FX_NOISE_LANE_KERNELS (the table's name) defined.
#include "noise_batch_impl.hpp"
#include "noise_sample_impl.hpp"

namespace cellfx::fx::noise_detail {

#define FX_NOISE_STRING2(x) #x
#define FX_NOISE_STRING(x) FX_NOISE_STRING2(x)
extern const LaneKernels FX_NOISE_LANE_KERNELS;
const LaneKernels FX_NOISE_LANE_KERNELS = {
    FX_NOISE_STRING(FX_NOISE_ISA),
    &perlin2_sample,
    &perlin3_sample,
    &fractal2_sample,
    &fractal3_sample,
    &fractal4_sample,
    &fill_grid<2>,
    &fill_grid<3>,
    &fill_grid<4>,
    &fill_points<2>,
    &fill_points<3>,
    &fill_points<4>,
};

} // namespace cellfx::fx::noise_detail
