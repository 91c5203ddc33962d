#include "io/json_input.hpp"

#include <cstddef>
#include <string>
#include <unordered_set>
#include <vector>

#include "fx/error.hpp"
#include "io/input_file.hpp"

namespace cellfx::fx::io {

namespace {

// A SAX pass that only watches keys: the first key repeated within one object (the empty key
// too) is kept in `repeated`. Syntax errors are left to the DOM parse that follows, which names their byte.
// The key sets are kept per depth and cleared, not rebuilt, so a scene of 200,000 effects
// costs a hash per key (nlohmann's callback parser took seven times a plain parse).
class DuplicateKeys : public nlohmann::json::json_sax_t {
public:
    bool found = false;
    std::string repeated;

    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override {
        if (depth_ == keys_.size()) keys_.emplace_back();
        keys_[depth_++].clear();
        return true;
    }
    bool key(string_t& k) override {
        if (keys_[depth_ - 1].insert(k).second) return true;
        found = true, repeated = k;
        return false;
    }
    bool end_object() override {
        --depth_;
        return true;
    }
    bool start_array(std::size_t) override { return true; }
    bool end_array() override { return true; }
    bool parse_error(std::size_t, const std::string&, const nlohmann::json::exception&) override { return false; }

private:
    std::vector<std::unordered_set<std::string>> keys_;
    std::size_t depth_ = 0;
};

} // namespace

nlohmann::json parse_json_input(std::string_view text, const std::string& source) {
    check_json_encoding(text, source);
    DuplicateKeys keys;
    nlohmann::json::sax_parse(text.begin(), text.end(), &keys);
    if (keys.found)
        throw Error(source + ": the key \"" + keys.repeated +
                    "\" appears twice in one object (keep one: a reader would silently take either)");
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::parse_error& e) {
        throw Error(source + ": JSON syntax error at byte " + std::to_string(e.byte) + ": " + e.what());
    } catch (const nlohmann::json::exception& e) { // e.g. a number too large for a double (1e400)
        throw Error(source + ": JSON error: " + e.what());
    }
}

} // namespace cellfx::fx::io
