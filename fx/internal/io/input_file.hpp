// cellfx — reading an input file within the resource budget (fx/resource_limits.hpp), and the
// checks every JSON input shares. Private to cellfx's readers (fx and terrain).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "fx/resource_limits.hpp"

namespace cellfx::fx::io {

// Looks at the first bytes of an input (up to 4 KiB, fewer if the input is shorter) and
// throws fx::Error if they cannot start a file of the expected kind, so that a device such as
// /dev/zero or a pipe of the wrong data is refused before it is read to the end.
using HeadCheck = std::function<void(std::string_view head)>;

// The bytes of `path`, at most the `budget` limit's value (Limit::FileBytes or JsonBytes).
// `kind` names the file in messages ("mesh file", "scene file"). A missing, unreadable or
// folder path is an fx::Error naming it; so is a regular file larger than the budget (refused
// before reading). Anything else — a pipe, a device such as /dev/zero, a socket — is read in
// chunks and fails as soon as it passes the budget, or when nothing arrives for
// input_wait_seconds (a named pipe nobody writes to): no input is read without a bound.
std::vector<char> read_input_file(const std::string& path, Limit budget, const char* kind,
                                  const HeadCheck& check_head = {});

// Checks that `text` can be UTF-8 JSON before it is parsed: a UTF-16 or UTF-32 file (a byte
// order mark, or NUL bytes in its first 4 KiB) is an fx::Error naming `source` and the
// encoding, not a syntax error at byte 1. A HeadCheck for JSON inputs.
void check_json_encoding(std::string_view text, const std::string& source);

} // namespace cellfx::fx::io
