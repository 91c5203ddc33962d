// Helpers shared by the mesh reader tests: temporary files, notes search, truncation sweeps.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "fx/error.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace fx_test {

// Writes bytes to a file in the test output folder and returns its path.
inline std::string write_temp_file(const std::string& name, const std::string& bytes) {
    const std::string path = output_path("io_" + name);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return path;
}

inline std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// True when some note contains `text`.
inline bool notes_contain(const std::vector<std::string>& notes, const std::string& text) {
    return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(text) != std::string::npos; });
}

// The message of the fx::Error that `read` throws; fails the test if it throws nothing or
// something else.
inline std::string error_message(const std::function<void()>& read) {
    try {
        read();
    } catch (const fx::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        FAIL("expected fx::Error, got std::exception: " << e.what());
    }
    FAIL("expected fx::Error, nothing was thrown");
    return {};
}

// Feeds `read` every prefix of `bytes` at the given cut points (written to a file). Each must
// either parse or throw fx::Error naming the file and a location. Returns how many threw.
inline std::size_t sweep_truncations(const std::string& name, const std::string& bytes, const std::vector<std::size_t>& cuts,
                                     const std::function<void(const std::string& path)>& read) {
    std::size_t errors = 0;
    for (std::size_t cut : cuts) {
        const std::string path = write_temp_file(name, bytes.substr(0, cut));
        try {
            read(path);
        } catch (const fx::Error& e) {
            ++errors;
            const std::string message = e.what();
            INFO("cut at " << cut << ": " << message);
            CHECK(message.rfind(path, 0) == 0);
            CHECK((message.find(": line ") != std::string::npos || message.find(": byte ") != std::string::npos ||
                   message.find(": block ") != std::string::npos || message.find("empty") != std::string::npos));
        } catch (const std::exception& e) {
            FAIL("cut at " << cut << ": unexpected exception type: " << e.what());
        }
    }
    return errors;
}

// Cut points: every offset up to `dense`, then `sparse` evenly spaced ones to the end.
inline std::vector<std::size_t> cut_points(std::size_t size, std::size_t dense, std::size_t sparse) {
    std::vector<std::size_t> cuts;
    for (std::size_t i = 0; i < std::min(size, dense); ++i) cuts.push_back(i);
    for (std::size_t k = 0; k < sparse && size > dense; ++k) cuts.push_back(dense + (size - dense) * k / sparse);
    return cuts;
}

} // namespace fx_test
