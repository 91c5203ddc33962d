// cellfx — libFuzzer target: terrain scene files. Feeds each input to terrain::parse_scene with
// the files it names resolved in content/scenes/ (the real height map and transfer functions),
// and aborts when the loader breaks its promise (fuzz_checks.hpp). Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_scene(data, size, CELLFX_SOURCE_DIR "/content/scenes");
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_scene: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
