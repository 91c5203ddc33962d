// cellfx — libFuzzer target: transfer-function JSON.
// Feeds each input to fx::TransferFunction::parse_json, then evaluation and rescaled(),
// and aborts when the reader breaks its promise (fuzz_checks.hpp). Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_transfer_function(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_transfer_function: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
