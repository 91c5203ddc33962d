// cellfx — libFuzzer target: AVS UCD ASCII files.
// Feeds each input to fx::parse_avs_ucd, including its call to fx::orient_cells,
// and aborts when the reader breaks its promise (fuzz_checks.hpp). Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_avs_ucd(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_avs_ucd: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
