// cellfx — reading a JSON input (a transfer function, a scene) strictly.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace cellfx::fx::io {

// Parses `text`, the JSON input named `source`. Each of these is an fx::Error naming `source`:
// an encoding that is not UTF-8 (check_json_encoding), a syntax error and a number beyond a
// double (1e400), each with its byte and the key path it is at ("byte 312 (at
// effects[0].base_radius)"), and a key repeated within one object — JSON allows it, and a
// reader would silently keep one of the two (two "camera" sections, say).
nlohmann::json parse_json_input(std::string_view text, const std::string& source);

} // namespace cellfx::fx::io
