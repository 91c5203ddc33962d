// cellfx — one exception type for every recoverable failure.
//
// Readers, validators and the GL layer throw fx::Error with a message that already names
// where the problem is ("blunt.xyz: byte 4096: truncated X array of block 1"), so callers
// print what() and stop. Nothing in cellfx aborts on bad input.
#pragma once

#include <stdexcept>
#include <string>

namespace cellfx::fx {

class Error : public std::runtime_error {
public:
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

} // namespace cellfx::fx
