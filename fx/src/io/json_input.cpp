#include "io/json_input.hpp"

#include <cstddef>
#include <string>
#include <unordered_set>
#include <vector>

#include "fx/error.hpp"
#include "io/input_file.hpp"

namespace cellfx::fx::io {

namespace {

// A SAX pass that watches keys and where it is: the first key repeated within one object (the
// empty key too) is kept in `repeated`, and a parse error (a syntax error, or a number beyond
// a double such as 1e999) with its byte and the key path it happened at ("effects[2].radius").
// The key sets are kept per depth and cleared, not rebuilt, so a scene of 200,000 effects
// costs a hash per key (nlohmann's callback parser took seven times a plain parse).
class KeyPass : public nlohmann::json::json_sax_t {
public:
    bool found = false;
    std::string repeated;
    bool failed = false;
    std::size_t error_byte = 0;
    std::string error_token, error_what, error_path;
    bool number_overflow = false;

    bool null() override { return element(); }
    bool boolean(bool) override { return element(); }
    bool number_integer(number_integer_t) override { return element(); }
    bool number_unsigned(number_unsigned_t) override { return element(); }
    bool number_float(number_float_t, const string_t&) override { return element(); }
    bool string(string_t&) override { return element(); }
    bool binary(binary_t&) override { return element(); }
    bool start_object(std::size_t) override {
        element();
        if (depth_ == keys_.size()) keys_.emplace_back();
        keys_[depth_++].clear();
        path_.push_back({false, 0, {}});
        return true;
    }
    bool key(string_t& k) override {
        path_.back().key = k;
        if (keys_[depth_ - 1].insert(k).second) return true;
        found = true, repeated = k;
        return false;
    }
    bool end_object() override {
        --depth_;
        path_.pop_back();
        return true;
    }
    bool start_array(std::size_t) override {
        element();
        path_.push_back({true, 0, {}});
        return true;
    }
    bool end_array() override {
        path_.pop_back();
        return true;
    }
    bool parse_error(std::size_t byte, const std::string& token, const nlohmann::json::exception& e) override {
        failed = true, error_byte = byte, error_token = token, error_what = e.what();
        number_overflow = e.id == 406; // out_of_range.406: number overflow
        // The failing value: in an array, the element after the last one counted.
        if (!path_.empty() && path_.back().array) ++path_.back().count;
        for (const Level& l : path_) {
            if (l.array) error_path += "[" + std::to_string(l.count == 0 ? 0 : l.count - 1) + "]";
            else if (!l.key.empty()) error_path += (error_path.empty() ? "" : ".") + l.key;
        }
        return false;
    }

private:
    struct Level {
        bool array;
        std::size_t count; // arrays: elements begun so far
        std::string key;   // objects: the key being read
    };
    bool element() {
        if (!path_.empty() && path_.back().array) ++path_.back().count;
        return true;
    }
    std::vector<std::unordered_set<std::string>> keys_;
    std::vector<Level> path_;
    std::size_t depth_ = 0;
};

} // namespace

nlohmann::json parse_json_input(std::string_view text, const std::string& source) {
    check_json_encoding(text, source);
    KeyPass pass;
    nlohmann::json::sax_parse(text.begin(), text.end(), &pass);
    if (pass.found)
        throw Error(source + ": the key \"" + pass.repeated +
                    "\" appears twice in one object (keep one: a reader would silently take either)");
    const std::string at = pass.error_path.empty() ? std::string() : " (at " + pass.error_path + ")";
    if (pass.failed && pass.number_overflow)
        throw Error(source + ": byte " + std::to_string(pass.error_byte) + at + ": the number " + pass.error_token +
                    " is beyond the range of a double (about ±1.8e308)");
    if (pass.failed)
        throw Error(source + ": JSON syntax error at byte " + std::to_string(pass.error_byte) + at + ": " + pass.error_what);
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::exception& e) { // not expected after the pass above
        throw Error(source + ": JSON error: " + e.what());
    }
}

} // namespace cellfx::fx::io
