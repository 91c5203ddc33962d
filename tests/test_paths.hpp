// Where tests find their inputs and put their outputs.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace fx_test {

// A file under the repository (content/, tests/data/).
inline std::string source_path(const std::string& relative) {
    return std::string(CELLFX_SOURCE_DIR) + "/" + relative;
}

// A file under ../shared/data (CELLFX_SHARED_DATA): the team's files that cellfx may not ship
// (no stated licence, or too large for content/). Throws, failing the test with the path it
// looked at, when the file is absent: such tests carry the [shared-data] tag and run as their own
// ctest entry, `shared_data` (tests/CMakeLists.txt), which ctest lists as not run when the
// folder was missing at configure time.
inline std::string shared_data_path(const std::string& relative) {
    const std::string p = std::string(CELLFX_SHARED_DATA) + "/" + relative;
    if (!std::filesystem::exists(p))
        throw std::runtime_error(p + " is missing: this test reads the team's shared data (../shared/data beside the "
                                     "checkout, or -DCELLFX_SHARED_DATA=DIR); it is not in content/ (no licence, or too large)");
    return p;
}

// Folder for images written by failing frame tests (actual/expected/diff PNGs).
inline std::string output_path(const std::string& name) {
    std::filesystem::create_directories(CELLFX_TEST_OUTPUT);
    return std::string(CELLFX_TEST_OUTPUT) + "/" + name;
}

} // namespace fx_test
