// cellfx — libFuzzer target: greyscale PNG height maps. Feeds each input to
// terrain::parse_height_field_png (what read_height_field_png and scene files use), without
// and with `pad`, and aborts when the reader breaks its promise (fuzz_checks.hpp).
// Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_height_field_png(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_height_field_png: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
