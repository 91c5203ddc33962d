// cellfx — libFuzzer target: VTK legacy files (ASCII and BINARY, UNSTRUCTURED_GRID and
// STRUCTURED_GRID). Feeds each input to fx::parse_vtk_legacy, what fx::read_mesh calls for
// "# vtk DataFile" files, and aborts when the reader breaks its promise (fuzz_checks.hpp).
// Run by scripts/fuzz.sh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string problem = fx_fuzz::check_vtk_legacy(data, size);
    if (!problem.empty()) {
        std::fprintf(stderr, "fuzz_vtk_legacy: %s\n", problem.c_str());
        std::abort();
    }
    return 0;
}
