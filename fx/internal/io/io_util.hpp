// cellfx — helpers shared by the mesh readers and writers: whole-file reading, byte
// order, and a bounds-checked scanner for whitespace-separated text.
//
// Every failure is an fx::Error whose message starts with the file name and the place
// ("spx.inp: line 12: ...", "post.vtk: byte 4096: ..."). Nothing here reads past the buffer.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/resource_limits.hpp"
#include "io/input_file.hpp"

namespace cellfx::fx::io {

// The bytes of a mesh or q file, within the file-bytes budget (input_file.hpp). Every format
// cellfx reads starts with a non-zero byte among the first four (text, or a PLOT3D count or
// record length of at least 1), so a device of zeros is refused at once.
inline std::vector<char> read_file_bytes(const std::string& path) {
    return read_input_file(path, Limit::FileBytes, "mesh file", [&](std::string_view head) {
        if (head.size() >= 4 && head.substr(0, 4) == std::string_view("\0\0\0\0", 4))
            throw Error(path + ": byte 0: not a PLOT3D grid file (nor VTK legacy or AVS UCD): it starts with four zero "
                               "bytes, where every PLOT3D variant has a count or record length of at least 1");
    });
}

inline bool host_is_big_endian() {
    const std::uint16_t probe = 0x0102;
    unsigned char first = 0;
    std::memcpy(&first, &probe, 1);
    return first == 0x01;
}

// Reads a T stored at p in the given byte order (p must have sizeof(T) readable bytes).
template <class T>
T load_scalar(const char* p, bool big_endian) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (big_endian != host_is_big_endian()) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    }
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

// Appends value to out in the given byte order.
template <class T>
void store_scalar(std::string& out, T value, bool big_endian) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (big_endian != host_is_big_endian()) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    }
    out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

// Parses a whole token as a number. Accepts a leading '+', "nan" and "inf" (callers reject
// non-finite values with their own message).
inline bool parse_double(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    return result.ec == std::errc() && result.ptr == end;
}

inline bool parse_int64(std::string_view token, std::int64_t& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    return result.ec == std::errc() && result.ptr == end;
}

// Shortens a token for an error message.
inline std::string quote_token(std::string_view token) {
    std::string s(token.substr(0, 40));
    for (char& c : s) {
        if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    }
    if (token.size() > 40) s += "...";
    return "\"" + s + "\"";
}

// Cursor over an in-memory file. Text and binary reads may be mixed (VTK legacy binary).
// Errors name the file and the line (text) or byte offset (binary) of the offending item.
class Scanner {
public:
    Scanner(const std::vector<char>& bytes, std::string path)
        : data_(bytes.data()), size_(bytes.size()), path_(std::move(path)) {}

    const std::string& path() const { return path_; }
    std::size_t pos() const { return pos_; }
    std::size_t size() const { return size_; }
    std::size_t remaining() const { return size_ - pos_; }
    bool at_end() const { return pos_ >= size_; }
    const char* data() const { return data_; }
    void seek(std::size_t pos) { pos_ = pos < size_ ? pos : size_; }

    // 1-based line number of a byte offset. Linear in the offset: for error messages only.
    std::size_t line_of(std::size_t pos) const {
        std::size_t line = 1;
        const std::size_t end = pos < size_ ? pos : size_;
        for (std::size_t i = 0; i < end; ++i) line += data_[i] == '\n';
        return line;
    }

    [[noreturn]] void fail_at_line(std::size_t pos, const std::string& what) const {
        throw Error(path_ + ": line " + std::to_string(line_of(pos)) + ": " + what);
    }
    [[noreturn]] void fail_at_byte(std::size_t pos, const std::string& what) const {
        throw Error(path_ + ": byte " + std::to_string(pos) + ": " + what);
    }
    [[noreturn]] void fail_at_byte_and_line(std::size_t pos, const std::string& what) const {
        throw Error(path_ + ": byte " + std::to_string(pos) + " (line " + std::to_string(line_of(pos)) + "): " + what);
    }

    void skip_space() {
        while (pos_ < size_ && is_space(data_[pos_])) ++pos_;
    }
    // Skips spaces and tabs but stops at a line end.
    void skip_blanks() {
        while (pos_ < size_ && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
    }

    // Next whitespace-separated token; empty at end of file. token_start() is where it began.
    std::string_view token() {
        skip_space();
        token_start_ = pos_;
        while (pos_ < size_ && !is_space(data_[pos_])) ++pos_;
        return std::string_view(data_ + token_start_, pos_ - token_start_);
    }
    std::size_t token_start() const { return token_start_; }

    // Next token without consuming it.
    std::string_view peek_token() {
        const std::size_t saved = pos_, saved_start = token_start_;
        const std::string_view t = token();
        pos_ = saved;
        token_start_ = saved_start;
        return t;
    }

    // Next token that must exist; `what` names it in the error ("number of points").
    std::string_view require_token(const std::string& what) {
        const std::string_view t = token();
        if (t.empty()) fail_at_line(pos_, "unexpected end of file, expected " + what);
        return t;
    }

    std::int64_t read_int(const std::string& what) {
        const std::string_view t = require_token(what);
        std::int64_t v = 0;
        if (!parse_int64(t, v)) fail_at_line(token_start_, "expected an integer (" + what + "), found " + quote_token(t));
        return v;
    }
    // A count in [0, max_count]; `max_count` is what the rest of the file could hold.
    std::size_t read_count(const std::string& what, std::size_t max_count) {
        const std::int64_t v = read_int(what);
        if (v < 0) fail_at_line(token_start_, what + " is negative (" + std::to_string(v) + ")");
        if (static_cast<std::uint64_t>(v) > max_count) {
            fail_at_line(token_start_, what + " " + std::to_string(v) + " is more than the rest of the file can hold");
        }
        return static_cast<std::size_t>(v);
    }
    double read_double(const std::string& what) {
        const std::string_view t = require_token(what);
        double v = 0.0;
        if (!parse_double(t, v)) fail_at_line(token_start_, "expected a number (" + what + "), found " + quote_token(t));
        return v;
    }

    // Rest of the current line (without the line end), consuming the line end.
    std::string_view rest_of_line() {
        const std::size_t start = pos_;
        while (pos_ < size_ && data_[pos_] != '\n') ++pos_;
        std::size_t end = pos_;
        if (end > start && data_[end - 1] == '\r') --end;
        if (pos_ < size_) ++pos_;
        return std::string_view(data_ + start, end - start);
    }

    // Upper bound on how many whitespace-separated tokens the rest of the file can hold.
    std::size_t max_tokens_left() const { return remaining() / 2 + 1; }

    // Binary: `count` bytes must remain, else a "truncated" error naming `what`.
    void require_bytes(std::size_t count, const std::string& what) const {
        if (count > remaining()) {
            fail_at_byte(pos_, "truncated " + what + ": needs " + std::to_string(count) + " bytes, " +
                                   std::to_string(remaining()) + " left");
        }
    }
    void advance(std::size_t count) { pos_ += count; }

private:
    const char* data_;
    std::size_t size_;
    std::size_t pos_ = 0;
    std::size_t token_start_ = 0;
    std::string path_;
};

// Human-readable number with thousands separators, for notes ("37,479").
using fx::with_commas;

// Every reader orients its cells (the policy of mesh_validation.hpp) and notes what it did:
// how many cells it flipped, and the first cells it left as they are (flat, folded or
// unusable), each named by `name_cell(cell)` ("cell 7 (line 12)").
template <class NameCell>
void orient_and_note(CellMesh& mesh, std::vector<std::string>* notes, NameCell name_cell) {
    const OrientationReport report = orient_cells(mesh);
    if (!notes) return;
    notes->push_back("orientation: flipped " + with_commas(report.flipped) + " of " + with_commas(mesh.cell_count()) +
                     " cells to positive volume");
    constexpr std::size_t kListed = 20;
    for (std::size_t k = 0; k < report.degenerate.size() && k < kListed; ++k) {
        notes->push_back("degenerate cell: " + name_cell(report.degenerate[k]) +
                         ": zero volume or folded over itself, kept as is");
    }
    if (report.degenerate.size() > kListed) {
        notes->push_back("... and " + with_commas(report.degenerate.size() - kListed) + " more degenerate cells");
    }
}

inline bool all_finite(double x, double y, double z) { return std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }

} // namespace cellfx::fx::io
