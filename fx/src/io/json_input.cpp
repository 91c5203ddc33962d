#include "io/json_input.hpp"

#include <set>
#include <vector>

#include "fx/error.hpp"
#include "io/input_file.hpp"

namespace cellfx::fx::io {

nlohmann::json parse_json_input(std::string_view text, const std::string& source) {
    check_json_encoding(text, source);
    // The keys seen so far in each object being read, innermost last.
    std::vector<std::set<std::string>> keys;
    const auto strict = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start) keys.emplace_back();
        else if (event == Event::object_end && !keys.empty()) keys.pop_back();
        else if (event == Event::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
            throw Error(source + ": the key \"" + parsed.get<std::string>() +
                        "\" appears twice in one object (keep one: a reader would silently take either)");
        return true;
    };
    try {
        return nlohmann::json::parse(text.begin(), text.end(), strict);
    } catch (const nlohmann::json::parse_error& e) {
        throw Error(source + ": JSON syntax error at byte " + std::to_string(e.byte) + ": " + e.what());
    } catch (const nlohmann::json::exception& e) { // e.g. a number too large for a double (1e400)
        throw Error(source + ": JSON error: " + e.what());
    }
}

} // namespace cellfx::fx::io
