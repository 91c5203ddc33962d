// Where tests find their inputs and put their outputs.
#pragma once

#include <filesystem>
#include <string>

namespace fx_test {

// A file under the repository (content/, tests/data/).
inline std::string source_path(const std::string& relative) {
    return std::string(CELLFX_SOURCE_DIR) + "/" + relative;
}

// A file under ../shared/data, or "" when that folder is absent (callers SKIP-with-message
// via shared_data_or_skip in test helpers).
inline std::string shared_data_path(const std::string& relative) {
    std::string p = std::string(CELLFX_SHARED_DATA) + "/" + relative;
    return std::filesystem::exists(p) ? p : std::string();
}

// Folder for images written by failing frame tests (actual/expected/diff PNGs).
inline std::string output_path(const std::string& name) {
    std::filesystem::create_directories(CELLFX_TEST_OUTPUT);
    return std::string(CELLFX_TEST_OUTPUT) + "/" + name;
}

} // namespace fx_test
