// cellfx — libFuzzer target: PLOT3D grid files alone and grid + q pairs, every variant.
// Each input is split into a grid and an optional q file (fx_fuzz::split_plot3d_input) and fed
// to fx::parse_plot3d; aborts when the reader breaks its promise (fuzz_checks.hpp).
// Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_plot3d(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_plot3d: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
