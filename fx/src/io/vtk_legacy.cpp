// cellfx — VTK legacy reader and writer.
//
// Format: "VTK File Formats" (Kitware, VTK User's Guide, legacy format section). The file is
// a sequence of keyword lines; ASCII data is whitespace-separated, BINARY data is big-endian
// and starts right after the line end of its keyword line.
#include "fx/vtk_legacy.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "io/io_util.hpp"
#include "io/output_file.hpp"

namespace cellfx::fx {
namespace {

using io::Scanner;

std::string upper(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}
std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

// VTK 8+ percent-encodes spaces and other special characters in names.
std::string decode_name(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
            out += static_cast<char>(std::stoi(std::string(s.substr(i + 1, 2)), nullptr, 16));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}
std::string encode_name(const std::string& s) {
    std::string out;
    for (char c : s) {
        const unsigned char u = static_cast<unsigned char>(c);
        if (u <= 32 || u >= 127 || c == '%') {
            char buf[4];
            std::snprintf(buf, sizeof buf, "%%%02X", u);
            out += buf;
        } else {
            out += c;
        }
    }
    return out.empty() ? std::string("unnamed") : out;
}

enum class ValueKind { Int, UInt, Float };
struct DataType {
    std::string name;
    std::size_t bytes = 0;
    ValueKind kind = ValueKind::Float;
};

bool data_type_from_name(std::string_view name, DataType& type) {
    static const std::map<std::string, std::pair<std::size_t, ValueKind>> kTypes = {
        {"unsigned_char", {1, ValueKind::UInt}}, {"char", {1, ValueKind::Int}},
        {"signed_char", {1, ValueKind::Int}},    {"unsigned_short", {2, ValueKind::UInt}},
        {"short", {2, ValueKind::Int}},          {"unsigned_int", {4, ValueKind::UInt}},
        {"int", {4, ValueKind::Int}},            {"unsigned_long", {8, ValueKind::UInt}},
        {"long", {8, ValueKind::Int}},           {"vtktypeint32", {4, ValueKind::Int}},
        {"vtktypeuint32", {4, ValueKind::UInt}}, {"vtktypeint64", {8, ValueKind::Int}},
        {"vtktypeuint64", {8, ValueKind::UInt}}, {"float", {4, ValueKind::Float}},
        {"double", {8, ValueKind::Float}},
    };
    const auto it = kTypes.find(lower(name));
    if (it == kTypes.end()) return false;
    type = DataType{it->first, it->second.first, it->second.second};
    return true;
}

// A keyword line split into tokens, with the offset where it starts.
struct HeaderLine {
    std::size_t pos = 0;
    std::vector<std::string_view> tokens;
    std::string keyword() const { return tokens.empty() ? std::string() : upper(tokens[0]); }
};

class VtkReader {
public:
    VtkReader(const std::vector<char>& bytes, const std::string& name, std::vector<std::string>* notes)
        : s_(bytes, name), notes_(notes) {}

    CellMesh read();

private:
    Scanner s_;
    std::vector<std::string>* notes_;
    bool binary_ = false;
    std::string dataset_;

    std::vector<double> coords_; // 3 per point
    bool have_points_ = false;
    std::size_t points_pos_ = 0;
    std::array<std::int64_t, 3> dims_{0, 0, 0};
    bool have_dims_ = false;

    // Cells as read: offsets into flat connectivity, and where each cell's data starts.
    bool have_cells_ = false;
    std::vector<std::uint64_t> cell_offsets_;
    std::vector<std::int64_t> cell_conn_;
    std::vector<std::size_t> cell_pos_;
    std::vector<int> cell_types_;
    std::vector<std::size_t> cell_type_pos_;
    bool have_cell_types_ = false;

    std::vector<ScalarField> fields_;
    std::set<std::string> field_names_; // a linear search per field made 10^5 FIELD arrays take minutes
    // Count of the first POINT_DATA section, which may come before POINTS; npos until then.
    std::size_t point_data_count_ = std::string::npos;

    void note(const std::string& line) {
        if (notes_) notes_->push_back(line);
    }
    [[noreturn]] void fail_line(std::size_t pos, const std::string& what) const { s_.fail_at_line(pos, what); }
    // Location of a data value: line for ASCII, byte offset for BINARY.
    [[noreturn]] void fail_value(std::size_t pos, const std::string& what) const {
        if (binary_) s_.fail_at_byte(pos, what);
        s_.fail_at_line(pos, what);
    }

    HeaderLine header_line() {
        s_.skip_space();
        HeaderLine h;
        h.pos = s_.pos();
        const std::string_view line = s_.rest_of_line();
        std::size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && io::is_space(line[i])) ++i;
            const std::size_t start = i;
            while (i < line.size() && !io::is_space(line[i])) ++i;
            if (i > start) h.tokens.push_back(line.substr(start, i - start));
        }
        return h;
    }
    // Next keyword line if its keyword is `keyword`, else nothing is consumed.
    bool accept_line(const std::string& keyword, HeaderLine& h) {
        const std::size_t saved = s_.pos();
        if (s_.at_end()) return false;
        h = header_line();
        if (h.keyword() == keyword) return true;
        s_.seek(saved);
        return false;
    }
    void skip_metadata_blocks() {
        HeaderLine h;
        while (accept_line("METADATA", h)) {
            // Metadata runs to the first empty line (or the end of the file).
            while (!s_.at_end()) {
                const std::string_view line = s_.rest_of_line();
                if (line.find_first_not_of(" \t\r") == std::string_view::npos) break;
            }
        }
    }

    std::size_t count_token(const HeaderLine& h, std::size_t index, const std::string& what) const {
        if (index >= h.tokens.size()) fail_line(h.pos, "missing " + what + " after " + std::string(h.tokens[0]));
        std::int64_t v = 0;
        if (!io::parse_int64(h.tokens[index], v)) {
            fail_line(h.pos, "expected an integer (" + what + "), found " + io::quote_token(h.tokens[index]));
        }
        if (v < 0) fail_line(h.pos, what + " is negative (" + std::to_string(v) + ")");
        return static_cast<std::size_t>(v);
    }
    DataType type_token(const HeaderLine& h, std::size_t index) const {
        if (index >= h.tokens.size()) fail_line(h.pos, "missing data type after " + std::string(h.tokens[0]));
        DataType t;
        if (!data_type_from_name(h.tokens[index], t)) {
            fail_line(h.pos, "unsupported data type " + io::quote_token(h.tokens[index]) + " in " + std::string(h.tokens[0]));
        }
        return t;
    }

    // Checks a count against the resource budget (fx/resource_limits.hpp) before allocating.
    void check_budget(Limit limit, std::uint64_t count, std::size_t pos, const std::string& what) const {
        if (exceeds(limit, count)) fail_line(pos, over_limit(limit, count, what));
    }
    // Checks that `count` values of `type` can still be in the file, before anything is allocated.
    void check_room(std::size_t count, std::size_t per_item, const DataType& type, const std::string& what) const {
        const std::size_t left = s_.remaining();
        if (per_item != 0 && count > std::numeric_limits<std::size_t>::max() / per_item / 8) {
            fail_value(s_.pos(), what + ": absurd count " + std::to_string(count));
        }
        const std::size_t values = count * per_item;
        if (binary_) {
            if (values > left / type.bytes) {
                s_.fail_at_byte(s_.pos(), "truncated " + what + ": needs " + std::to_string(values * type.bytes) +
                                              " bytes, " + std::to_string(left) + " left");
            }
        } else if (values > s_.max_tokens_left()) {
            s_.fail_at_line(s_.pos(), "truncated " + what + ": " + std::to_string(values) +
                                          " values announced but the rest of the file is too short");
        }
    }

    // One value; `pos` receives where it starts.
    double next_value(const DataType& type, const std::string& what, std::size_t& pos) {
        if (binary_) {
            pos = s_.pos();
            s_.require_bytes(type.bytes, what);
            const char* p = s_.data() + s_.pos();
            s_.advance(type.bytes);
            switch (type.kind) {
            case ValueKind::Float:
                return type.bytes == 4 ? double(io::load_scalar<float>(p, true)) : io::load_scalar<double>(p, true);
            case ValueKind::Int:
                switch (type.bytes) {
                case 1: return double(static_cast<std::int8_t>(*p));
                case 2: return double(io::load_scalar<std::int16_t>(p, true));
                case 4: return double(io::load_scalar<std::int32_t>(p, true));
                default: return double(io::load_scalar<std::int64_t>(p, true));
                }
            case ValueKind::UInt:
                switch (type.bytes) {
                case 1: return double(static_cast<std::uint8_t>(*p));
                case 2: return double(io::load_scalar<std::uint16_t>(p, true));
                case 4: return double(io::load_scalar<std::uint32_t>(p, true));
                default: return double(io::load_scalar<std::uint64_t>(p, true));
                }
            }
            return 0.0;
        }
        const std::string_view t = s_.token();
        pos = s_.token_start();
        if (t.empty()) s_.fail_at_line(pos, "truncated " + what + ": unexpected end of file");
        double v = 0.0;
        if (!io::parse_double(t, v)) s_.fail_at_line(pos, "expected a number in " + what + ", found " + io::quote_token(t));
        return v;
    }
    std::vector<double> read_values(std::size_t count, const DataType& type, const std::string& what) {
        check_room(count, 1, type, what);
        std::vector<double> values(count);
        std::size_t pos = 0;
        for (std::size_t i = 0; i < count; ++i) values[i] = next_value(type, what, pos);
        return values;
    }
    void skip_values(std::size_t count, const DataType& type, const std::string& what) {
        check_room(count, 1, type, what);
        if (binary_) {
            s_.advance(count * type.bytes);
            return;
        }
        std::size_t pos = 0;
        for (std::size_t i = 0; i < count; ++i) next_value(type, what, pos);
    }
    std::int64_t to_index(double v, std::size_t pos, const std::string& what) const {
        if (!(v >= -9.0e15 && v <= 9.0e15) || v != std::floor(v)) {
            fail_value(pos, what + " is not a valid integer");
        }
        return static_cast<std::int64_t>(v);
    }

    void read_header();
    void read_points(const HeaderLine& h);
    void read_cells(const HeaderLine& h);
    void read_cell_types(const HeaderLine& h);
    void read_dimensions(const HeaderLine& h);
    void read_attributes(const HeaderLine& h, bool point_data);
    void read_field(const HeaderLine& h, std::size_t tuples, bool store, const std::string& where);
    void add_field(std::string name, std::vector<float> values);
    CellMesh build_unstructured();
    CellMesh build_structured();
    void copy_points(CellMesh& mesh) const;
};

void VtkReader::read_header() {
    if (s_.size() == 0) s_.fail_at_line(0, "empty file");
    const std::string_view first = s_.rest_of_line();
    if (first.substr(0, 14) != "# vtk DataFile" && upper(first.substr(0, 14)) != "# VTK DATAFILE") {
        s_.fail_at_line(0, "not a VTK legacy file (first line must start with \"# vtk DataFile\")");
    }
    if (s_.at_end()) s_.fail_at_line(s_.pos(), "truncated header: missing title line");
    s_.rest_of_line(); // title, free text
    if (s_.at_end()) s_.fail_at_line(s_.pos(), "truncated header: missing ASCII/BINARY line");
    HeaderLine format = header_line();
    if (format.keyword() == "ASCII") {
        binary_ = false;
    } else if (format.keyword() == "BINARY") {
        binary_ = true;
    } else {
        fail_line(format.pos, "expected ASCII or BINARY, found " +
                                  (format.tokens.empty() ? std::string("an empty line") : io::quote_token(format.tokens[0])));
    }
    if (s_.at_end()) fail_line(s_.pos(), "truncated header: missing DATASET line");
    HeaderLine dataset = header_line();
    if (dataset.keyword() != "DATASET" || dataset.tokens.size() < 2) {
        fail_line(dataset.pos, "expected \"DATASET <type>\"");
    }
    dataset_ = upper(dataset.tokens[1]);
    if (dataset_ != "UNSTRUCTURED_GRID" && dataset_ != "STRUCTURED_GRID") {
        fail_line(dataset.pos, "unsupported dataset " + io::quote_token(dataset.tokens[1]) +
                                   " (cellfx reads UNSTRUCTURED_GRID and STRUCTURED_GRID)");
    }
}

void VtkReader::read_points(const HeaderLine& h) {
    if (have_points_) fail_line(h.pos, "second POINTS section");
    const std::size_t n = count_token(h, 1, "number of points");
    if (point_data_count_ != std::string::npos && n != point_data_count_) {
        fail_line(h.pos, "POINTS " + std::to_string(n) + " does not match the earlier POINT_DATA " + std::to_string(point_data_count_));
    }
    const DataType type = type_token(h, 2);
    check_room(n, 3, type, "POINTS");
    check_budget(Limit::MeshPoints, n, h.pos, "POINTS");
    points_pos_ = s_.pos();
    coords_.resize(3 * n);
    std::size_t pos = 0;
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t first_pos = 0;
        for (int c = 0; c < 3; ++c) {
            coords_[3 * i + c] = next_value(type, "POINTS", pos);
            if (c == 0) first_pos = pos;
        }
        if (!io::all_finite(coords_[3 * i], coords_[3 * i + 1], coords_[3 * i + 2])) {
            fail_value(first_pos, "point " + std::to_string(i) + " has a non-finite coordinate (NaN or Inf)");
        }
    }
    have_points_ = true;
}

void VtkReader::read_cells(const HeaderLine& h) {
    if (have_cells_) fail_line(h.pos, "second CELLS section");
    const std::size_t first_count = count_token(h, 1, "number of cells");
    const std::size_t second_count = count_token(h, 2, "size of the cell list");
    HeaderLine offsets_line;
    if (accept_line("OFFSETS", offsets_line)) {
        // Version 5 layout: first_count offsets, then second_count connectivity entries.
        if (first_count == 0) fail_line(h.pos, "CELLS with OFFSETS needs at least one offset");
        const DataType offset_type = type_token(offsets_line, 1);
        check_room(first_count, 1, offset_type, "OFFSETS");
        check_budget(Limit::MeshCells, first_count - 1, h.pos, "CELLS");
        cell_offsets_.resize(first_count);
        cell_pos_.resize(first_count - 1);
        std::size_t pos = 0;
        for (std::size_t i = 0; i < first_count; ++i) {
            const std::int64_t off = to_index(next_value(offset_type, "OFFSETS", pos), pos, "cell offset");
            if (i < first_count - 1) cell_pos_[i] = pos;
            if (off < 0 || static_cast<std::uint64_t>(off) > second_count ||
                (i > 0 && static_cast<std::uint64_t>(off) < cell_offsets_[i - 1]) || (i == 0 && off != 0)) {
                fail_value(pos, "cell offset " + std::to_string(i) + " (" + std::to_string(off) +
                                    ") is out of order or past the connectivity size " + std::to_string(second_count));
            }
            cell_offsets_[i] = static_cast<std::uint64_t>(off);
        }
        if (cell_offsets_.back() != second_count) {
            fail_value(pos, "last cell offset " + std::to_string(cell_offsets_.back()) +
                                " does not match the connectivity size " + std::to_string(second_count));
        }
        skip_metadata_blocks();
        HeaderLine conn_line;
        if (!accept_line("CONNECTIVITY", conn_line)) fail_line(s_.pos(), "expected CONNECTIVITY after OFFSETS");
        const DataType conn_type = type_token(conn_line, 1);
        check_room(second_count, 1, conn_type, "CONNECTIVITY");
        cell_conn_.resize(second_count);
        std::size_t cell = 0;
        for (std::size_t i = 0; i < second_count; ++i) {
            while (cell + 1 < cell_offsets_.size() && cell_offsets_[cell + 1] <= i) ++cell;
            cell_conn_[i] = to_index(next_value(conn_type, "CONNECTIVITY", pos), pos, "cell vertex");
            if (i == cell_offsets_[cell] && cell < cell_pos_.size()) cell_pos_[cell] = pos;
        }
        have_cells_ = true;
        return;
    }
    // Classic layout: for each cell, its vertex count then the vertices; second_count ints in all.
    const DataType int_type{"int", 4, ValueKind::Int};
    check_room(second_count, 1, int_type, "CELLS");
    if (first_count > second_count) fail_line(h.pos, "CELLS: " + std::to_string(first_count) +
                                                         " cells cannot fit in a list of " + std::to_string(second_count));
    check_budget(Limit::MeshCells, first_count, h.pos, "CELLS");
    cell_offsets_.reserve(first_count + 1);
    cell_offsets_.push_back(0);
    cell_conn_.reserve(second_count - first_count);
    cell_pos_.reserve(first_count);
    std::size_t used = 0, pos = 0;
    for (std::size_t c = 0; c < first_count; ++c) {
        const std::int64_t k = to_index(next_value(int_type, "CELLS", pos), pos, "vertex count of cell " + std::to_string(c));
        cell_pos_.push_back(pos);
        if (k < 0 || used + 1 + static_cast<std::uint64_t>(k) > second_count) {
            fail_value(pos, "cell " + std::to_string(c) + ": vertex count " + std::to_string(k) +
                                " overruns the cell list size " + std::to_string(second_count));
        }
        used += 1 + static_cast<std::size_t>(k);
        for (std::int64_t v = 0; v < k; ++v) {
            cell_conn_.push_back(to_index(next_value(int_type, "CELLS", pos), pos, "vertex of cell " + std::to_string(c)));
        }
        cell_offsets_.push_back(cell_conn_.size());
    }
    if (used != second_count) {
        fail_line(h.pos, "CELLS announces a list of " + std::to_string(second_count) + " integers but the " +
                             std::to_string(first_count) + " cells use " + std::to_string(used));
    }
    have_cells_ = true;
}

void VtkReader::read_cell_types(const HeaderLine& h) {
    if (have_cell_types_) fail_line(h.pos, "second CELL_TYPES section");
    const std::size_t n = count_token(h, 1, "number of cell types");
    const DataType int_type{"int", 4, ValueKind::Int};
    check_room(n, 1, int_type, "CELL_TYPES");
    check_budget(Limit::MeshCells, n, h.pos, "CELL_TYPES");
    cell_types_.resize(n);
    cell_type_pos_.resize(n);
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t pos = 0;
        const double v = next_value(int_type, "CELL_TYPES", pos);
        cell_type_pos_[c] = pos;
        if (!(v >= -1e9 && v <= 1e9) || v != std::floor(v)) fail_value(pos, "cell " + std::to_string(c) + ": type is not an integer");
        cell_types_[c] = static_cast<int>(v);
        CellType known;
        const int t = cell_types_[c];
        if (!(t >= 1 && t <= 9) && t != 11 && !cell_type_from_vtk(t, known)) {
            fail_value(pos, "cell " + std::to_string(c) + ": unsupported cell type " + std::to_string(t) +
                                " (cellfx reads tetra 10, voxel 11, hexahedron 12, wedge 13, pyramid 14 and skips types 1-9)");
        }
    }
    have_cell_types_ = true;
}

void VtkReader::read_dimensions(const HeaderLine& h) {
    if (dataset_ != "STRUCTURED_GRID") fail_line(h.pos, "DIMENSIONS in a " + dataset_);
    for (int a = 0; a < 3; ++a) {
        if (std::size_t(a + 1) >= h.tokens.size()) fail_line(h.pos, "DIMENSIONS needs three numbers");
        std::int64_t v = 0;
        if (!io::parse_int64(h.tokens[a + 1], v)) fail_line(h.pos, "DIMENSIONS: " + io::quote_token(h.tokens[a + 1]) + " is not an integer");
        if (v < 1 || v > (std::int64_t(1) << 31)) fail_line(h.pos, "DIMENSIONS: " + std::to_string(v) + " is not a valid node count");
        dims_[a] = v;
    }
    have_dims_ = true;
}

void VtkReader::add_field(std::string name, std::vector<float> values) {
    std::size_t bad = 0;
    for (float v : values) bad += !std::isfinite(v);
    if (bad) note("field \"" + name + "\": " + io::with_commas(bad) + " non-finite values");
    if (field_names_.count(name)) {
        note("duplicate field name \"" + name + "\": the later one is renamed");
        name += "_" + std::to_string(fields_.size());
    }
    field_names_.insert(name);
    fields_.push_back(ScalarField{std::move(name), std::move(values)});
}

void VtkReader::read_field(const HeaderLine& h, std::size_t tuples, bool store, const std::string& where) {
    if (h.tokens.size() < 3) fail_line(h.pos, "FIELD needs a name and an array count");
    const std::size_t arrays = count_token(h, 2, "number of FIELD arrays");
    if (arrays > s_.max_tokens_left()) fail_line(h.pos, "FIELD array count " + std::to_string(arrays) + " is more than the file can hold");
    for (std::size_t a = 0; a < arrays; ++a) {
        skip_metadata_blocks();
        if (s_.at_end()) fail_line(s_.pos(), "truncated FIELD: array " + std::to_string(a) + " of " + std::to_string(arrays) + " missing");
        const HeaderLine array = header_line();
        if (array.keyword() == "NULL_ARRAY") continue;
        if (array.tokens.size() < 4) fail_line(array.pos, "FIELD array header needs \"name components tuples type\"");
        const std::string name = decode_name(array.tokens[0]);
        const std::size_t components = count_token(array, 1, "number of components");
        const std::size_t count = count_token(array, 2, "number of tuples");
        const DataType type = type_token(array, 3);
        if (components == 0) fail_line(array.pos, "FIELD array \"" + name + "\" has 0 components");
        check_room(count, components, type, "FIELD array \"" + name + "\"");
        if (!store || count != tuples) {
            skip_values(count * components, type, "FIELD array \"" + name + "\"");
            note("skipped " + where + " field array \"" + name + "\" (" + std::to_string(components) + " components, " +
                 std::to_string(count) + " tuples)");
            continue;
        }
        const std::vector<double> values = read_values(count * components, type, "FIELD array \"" + name + "\"");
        std::vector<float> out(count);
        if (components == 1) {
            for (std::size_t i = 0; i < count; ++i) out[i] = static_cast<float>(values[i]);
            add_field(name, std::move(out));
        } else {
            for (std::size_t i = 0; i < count; ++i) {
                double sum = 0.0;
                for (std::size_t c = 0; c < components; ++c) sum += values[i * components + c] * values[i * components + c];
                out[i] = static_cast<float>(std::sqrt(sum));
            }
            add_field(name + "_magnitude", std::move(out));
        }
    }
}

void VtkReader::read_attributes(const HeaderLine& section, bool point_data) {
    const std::size_t n = count_token(section, 1, point_data ? "POINT_DATA count" : "CELL_DATA count");
    const std::string where = point_data ? "point" : "cell";
    if (point_data && have_points_ && n != coords_.size() / 3) {
        fail_line(section.pos, "POINT_DATA " + std::to_string(n) + " does not match the " + std::to_string(coords_.size() / 3) + " points");
    }
    if (point_data && point_data_count_ != std::string::npos && n != point_data_count_) {
        fail_line(section.pos, "POINT_DATA " + std::to_string(n) + " does not match the earlier POINT_DATA " + std::to_string(point_data_count_));
    }
    if (point_data) point_data_count_ = n;
    if (!point_data && have_cells_ && n != cell_offsets_.size() - 1) {
        fail_line(section.pos, "CELL_DATA " + std::to_string(n) + " does not match the " + std::to_string(cell_offsets_.size() - 1) + " cells");
    }
    if (!point_data) note("skipped CELL_DATA (cellfx renders per-point scalars)");
    const bool store = point_data;
    while (true) {
        skip_metadata_blocks();
        s_.skip_space();
        if (s_.at_end()) return;
        const std::size_t saved = s_.pos();
        const HeaderLine h = header_line();
        const std::string kw = h.keyword();
        const std::string name = h.tokens.size() > 1 ? decode_name(h.tokens[1]) : std::string();
        if (kw == "SCALARS") {
            if (h.tokens.size() < 3) fail_line(h.pos, "SCALARS needs a name and a data type");
            const DataType type = type_token(h, 2);
            std::size_t components = 1;
            if (h.tokens.size() > 3) components = count_token(h, 3, "number of components");
            if (components < 1 || components > 4) fail_line(h.pos, "SCALARS \"" + name + "\": component count must be 1 to 4");
            HeaderLine table;
            accept_line("LOOKUP_TABLE", table);
            check_room(n, components, type, "SCALARS \"" + name + "\"");
            if (!store) {
                skip_values(n * components, type, "SCALARS \"" + name + "\"");
                continue;
            }
            const std::vector<double> values = read_values(n * components, type, "SCALARS \"" + name + "\"");
            for (std::size_t c = 0; c < components; ++c) {
                std::vector<float> out(n);
                for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(values[i * components + c]);
                add_field(components == 1 ? name : name + "_" + std::to_string(c), std::move(out));
            }
        } else if (kw == "VECTORS" || kw == "NORMALS") {
            if (h.tokens.size() < 3) fail_line(h.pos, kw + " needs a name and a data type");
            const DataType type = type_token(h, 2);
            check_room(n, 3, type, kw + " \"" + name + "\"");
            if (!store || kw == "NORMALS") {
                skip_values(3 * n, type, kw + " \"" + name + "\"");
                if (store) note("skipped point NORMALS \"" + name + "\"");
                continue;
            }
            const std::vector<double> values = read_values(3 * n, type, "VECTORS \"" + name + "\"");
            std::vector<float> out(n);
            for (std::size_t i = 0; i < n; ++i) {
                const double* v = &values[3 * i];
                out[i] = static_cast<float>(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            }
            add_field(name + "_magnitude", std::move(out));
        } else if (kw == "TEXTURE_COORDINATES") {
            if (h.tokens.size() < 4) fail_line(h.pos, "TEXTURE_COORDINATES needs a name, a dimension and a data type");
            const std::size_t dim = count_token(h, 2, "texture dimension");
            if (dim < 1 || dim > 3) fail_line(h.pos, "TEXTURE_COORDINATES dimension must be 1 to 3");
            const DataType type = type_token(h, 3);
            check_room(n, dim, type, "TEXTURE_COORDINATES");
            skip_values(n * dim, type, "TEXTURE_COORDINATES");
            if (store) note("skipped point TEXTURE_COORDINATES \"" + name + "\"");
        } else if (kw == "TENSORS" || kw == "TENSORS6") {
            if (h.tokens.size() < 3) fail_line(h.pos, kw + " needs a name and a data type");
            const DataType type = type_token(h, 2);
            const std::size_t per = kw == "TENSORS" ? 9 : 6;
            check_room(n, per, type, kw);
            skip_values(n * per, type, kw);
            if (store) note("skipped point " + kw + " \"" + name + "\"");
        } else if (kw == "GLOBAL_IDS" || kw == "PEDIGREE_IDS") {
            if (h.tokens.size() < 3) fail_line(h.pos, kw + " needs a name and a data type");
            const DataType type = type_token(h, 2);
            skip_values(n, type, kw);
            if (store) note("skipped point " + kw + " \"" + name + "\"");
        } else if (kw == "COLOR_SCALARS") {
            const std::size_t per = count_token(h, 2, "number of color components");
            if (per < 1 || per > 4) fail_line(h.pos, "COLOR_SCALARS component count must be 1 to 4");
            const DataType type = binary_ ? DataType{"unsigned_char", 1, ValueKind::UInt} : DataType{"float", 4, ValueKind::Float};
            check_room(n, per, type, "COLOR_SCALARS");
            skip_values(n * per, type, "COLOR_SCALARS");
            if (store) note("skipped point COLOR_SCALARS \"" + name + "\"");
        } else if (kw == "LOOKUP_TABLE") {
            const std::size_t entries = count_token(h, 2, "lookup table size");
            const DataType type = binary_ ? DataType{"unsigned_char", 1, ValueKind::UInt} : DataType{"float", 4, ValueKind::Float};
            check_room(entries, 4, type, "LOOKUP_TABLE");
            skip_values(entries * 4, type, "LOOKUP_TABLE");
        } else if (kw == "FIELD") {
            read_field(h, n, store, where);
        } else {
            s_.seek(saved); // not an attribute: the section is over
            return;
        }
    }
}

void VtkReader::copy_points(CellMesh& mesh) const {
    const std::size_t n = coords_.size() / 3;
    mesh.points.resize(n);
    for (std::size_t i = 0; i < n; ++i) mesh.points[i] = glm::dvec3(coords_[3 * i], coords_[3 * i + 1], coords_[3 * i + 2]);
    mesh.scalars = fields_;
}

CellMesh VtkReader::build_unstructured() {
    if (!have_points_) s_.fail_at_line(s_.size(), "no POINTS section");
    if (!have_cells_) s_.fail_at_line(s_.size(), "no CELLS section");
    if (!have_cell_types_) s_.fail_at_line(s_.size(), "no CELL_TYPES section");
    const std::size_t cells = cell_offsets_.size() - 1;
    if (cell_types_.size() != cells) {
        fail_line(cell_type_pos_.empty() ? s_.size() : cell_type_pos_.front(),
                  "CELL_TYPES lists " + std::to_string(cell_types_.size()) + " cells but CELLS has " + std::to_string(cells));
    }
    if (cell_conn_.size() >= std::numeric_limits<std::uint32_t>::max()) s_.fail_at_line(0, "too many cell vertices for cellfx (32-bit indices)");
    CellMesh mesh;
    copy_points(mesh);
    const std::size_t npoints = mesh.points.size();
    std::map<int, std::size_t> skipped_by_type;
    std::vector<std::uint32_t> file_cell; // the file's cell index of each mesh cell
    file_cell.reserve(cells);
    std::size_t voxels = 0;
    mesh.cell_types.reserve(cells);
    mesh.connectivity.reserve(cell_conn_.size());
    mesh.cell_offsets.reserve(cells + 1);
    for (std::size_t c = 0; c < cells; ++c) {
        const int vtk_type = cell_types_[c];
        const std::size_t begin = cell_offsets_[c], count = cell_offsets_[c + 1] - begin;
        for (std::size_t k = 0; k < count; ++k) {
            const std::int64_t v = cell_conn_[begin + k];
            if (v < 0 || static_cast<std::uint64_t>(v) >= npoints) {
                fail_value(cell_pos_[c], "cell " + std::to_string(c) + ": vertex " + std::to_string(k) + " is point " +
                                             std::to_string(v) + " but the file has " + std::to_string(npoints) + " points");
            }
        }
        if (vtk_type >= 1 && vtk_type <= 9) {
            ++skipped_by_type[vtk_type];
            continue;
        }
        CellType type = CellType::Hexahedron;
        if (vtk_type != 11 && !cell_type_from_vtk(vtk_type, type)) {
            fail_value(cell_type_pos_[c], "cell " + std::to_string(c) + ": unsupported cell type " + std::to_string(vtk_type));
        }
        const std::size_t expected = vtk_type == 11 ? 8 : static_cast<std::size_t>(cell_vertex_count(type));
        if (count != expected) {
            fail_value(cell_pos_[c], "cell " + std::to_string(c) + " of type " + std::to_string(vtk_type) + " has " +
                                         std::to_string(count) + " vertices, expected " + std::to_string(expected));
        }
        std::uint32_t v[8];
        for (std::size_t k = 0; k < count; ++k) v[k] = static_cast<std::uint32_t>(cell_conn_[begin + k]);
        if (vtk_type == 11) {
            // Voxel corners go x fastest, then y, then z; the hexahedron goes around each face.
            std::swap(v[2], v[3]);
            std::swap(v[6], v[7]);
            ++voxels;
        }
        mesh.add_cell(type, v);
        file_cell.push_back(static_cast<std::uint32_t>(c));
    }
    if (voxels) note("converted " + io::with_commas(voxels) + " voxels (type 11) to hexahedra");
    static const char* kDimension[10] = {"", "0-D", "0-D", "1-D", "1-D", "2-D", "2-D", "2-D", "2-D", "2-D"};
    for (const char* dim : {"0-D", "1-D", "2-D"}) {
        std::size_t total = 0;
        std::string types;
        for (const auto& [t, count] : skipped_by_type) {
            if (std::string(kDimension[t]) != dim) continue;
            total += count;
            types += (types.empty() ? "" : ", ") + std::to_string(t);
        }
        if (total) note("skipped " + io::with_commas(total) + " " + dim + " cells (type" + (types.find(',') != std::string::npos ? "s " : " ") + types + ")");
    }
    io::orient_and_note(mesh, notes_, [&](std::uint32_t c) {
        const std::size_t pos = cell_pos_[file_cell[c]];
        return "cell " + std::to_string(file_cell[c]) + (binary_ ? " (byte " + std::to_string(pos) : " (line " + std::to_string(s_.line_of(pos))) + ")";
    });
    return mesh;
}

CellMesh VtkReader::build_structured() {
    if (!have_dims_) s_.fail_at_line(s_.size(), "STRUCTURED_GRID without DIMENSIONS");
    if (!have_points_) s_.fail_at_line(s_.size(), "no POINTS section");
    const std::uint64_t ni = dims_[0], nj = dims_[1], nk = dims_[2];
    const std::uint64_t expected = ni * nj * nk; // each dim <= 2^31 checked; the product is checked against POINTS
    if (ni > 0 && nj > 0 && (expected / ni / nj != nk || expected != coords_.size() / 3)) {
        fail_line(points_pos_, "DIMENSIONS " + std::to_string(ni) + " x " + std::to_string(nj) + " x " + std::to_string(nk) +
                                   " do not match the " + std::to_string(coords_.size() / 3) + " points");
    }
    if (expected * 8 >= std::numeric_limits<std::uint32_t>::max()) s_.fail_at_line(0, "grid too large for 32-bit indices");
    CellMesh mesh;
    copy_points(mesh);
    mesh.begin_block("0", {static_cast<std::uint32_t>(ni), static_cast<std::uint32_t>(nj), static_cast<std::uint32_t>(nk)});
    if (ni < 2 || nj < 2 || nk < 2) {
        note("structured grid " + std::to_string(ni) + " x " + std::to_string(nj) + " x " + std::to_string(nk) + " is not 3-D: no cells");
        return mesh;
    }
    const std::size_t cells = (ni - 1) * (nj - 1) * (nk - 1);
    mesh.cell_types.reserve(cells);
    mesh.connectivity.reserve(cells * 8);
    mesh.cell_offsets.reserve(cells + 1);
    auto node = [&](std::uint64_t i, std::uint64_t j, std::uint64_t k) { return static_cast<std::uint32_t>(i + ni * (j + nj * k)); };
    for (std::uint64_t k = 0; k + 1 < nk; ++k) {
        for (std::uint64_t j = 0; j + 1 < nj; ++j) {
            for (std::uint64_t i = 0; i + 1 < ni; ++i) {
                const std::uint32_t v[8] = {node(i, j, k),         node(i + 1, j, k),         node(i + 1, j + 1, k),
                                            node(i, j + 1, k),     node(i, j, k + 1),         node(i + 1, j, k + 1),
                                            node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
                mesh.add_cell(CellType::Hexahedron, v);
            }
        }
    }
    io::orient_and_note(mesh, notes_, [&](std::uint32_t c) {
        const std::uint64_t i = c % (ni - 1), j = c / (ni - 1) % (nj - 1), k = c / (ni - 1) / (nj - 1);
        return "cell " + std::to_string(c) + " (i, j, k = " + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")";
    });
    return mesh;
}

CellMesh VtkReader::read() {
    read_header();
    while (true) {
        s_.skip_space();
        if (s_.at_end()) break;
        const HeaderLine h = header_line();
        const std::string kw = h.keyword();
        if (kw == "POINTS") {
            read_points(h);
        } else if (kw == "CELLS" && dataset_ == "UNSTRUCTURED_GRID") {
            read_cells(h);
        } else if (kw == "CELL_TYPES" && dataset_ == "UNSTRUCTURED_GRID") {
            read_cell_types(h);
        } else if (kw == "DIMENSIONS") {
            read_dimensions(h);
        } else if (kw == "POINT_DATA") {
            read_attributes(h, true);
        } else if (kw == "CELL_DATA") {
            read_attributes(h, false);
        } else if (kw == "FIELD") {
            read_field(h, 0, false, "dataset");
        } else if (kw == "METADATA") {
            s_.seek(h.pos);
            skip_metadata_blocks();
        } else if (kw == "BLANKING" && dataset_ == "STRUCTURED_GRID") {
            const std::size_t n = count_token(h, 1, "BLANKING count");
            skip_values(n, DataType{"unsigned_char", 1, ValueKind::UInt}, "BLANKING");
            note("ignored BLANKING");
        } else {
            fail_line(h.pos, "unknown keyword " + io::quote_token(h.tokens.empty() ? std::string_view() : h.tokens[0]) +
                                 " in a " + dataset_);
        }
    }
    return dataset_ == "STRUCTURED_GRID" ? build_structured() : build_unstructured();
}

// --- writing ---------------------------------------------------------------------------------

int vtk_type_id(CellType type) { return static_cast<int>(type); }

void append_text(std::string& out, const char* format, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value);
    out += buf;
}

} // namespace

CellMesh parse_vtk_legacy(const std::vector<char>& bytes, const std::string& name, std::vector<std::string>* notes) {
    VtkReader reader(bytes, name, notes);
    return reader.read();
}

CellMesh read_vtk_legacy(const std::string& path, std::vector<std::string>* notes) {
    return parse_vtk_legacy(io::read_file_bytes(path), path, notes);
}

void write_vtk_legacy(const CellMesh& mesh, const std::string& path, bool binary) {
    const std::size_t npoints = mesh.point_count(), ncells = mesh.cell_count();
    if (mesh.cell_offsets.size() != ncells + 1 || mesh.cell_offsets.back() != mesh.connectivity.size()) {
        throw Error(path + ": cannot write an inconsistent mesh (cell offsets do not match the cells)");
    }
    for (const ScalarField& f : mesh.scalars) {
        if (f.values.size() != npoints) {
            throw Error(path + ": field \"" + f.name + "\" has " + std::to_string(f.values.size()) + " values for " +
                        std::to_string(npoints) + " points");
        }
    }
    std::string out;
    out.reserve(64 + npoints * (binary ? 24 : 60) + mesh.connectivity.size() * (binary ? 4 : 8));
    out += "# vtk DataFile Version 3.0\ncellfx mesh\n";
    out += binary ? "BINARY\n" : "ASCII\n";
    out += "DATASET UNSTRUCTURED_GRID\n";
    out += "POINTS " + std::to_string(npoints) + " double\n";
    for (const glm::dvec3& p : mesh.points) {
        for (int c = 0; c < 3; ++c) {
            if (binary) {
                io::store_scalar<double>(out, p[c], true);
            } else {
                append_text(out, c < 2 ? "%.17g " : "%.17g\n", p[c]);
            }
        }
    }
    out += "\nCELLS " + std::to_string(ncells) + " " + std::to_string(ncells + mesh.connectivity.size()) + "\n";
    for (std::size_t c = 0; c < ncells; ++c) {
        const std::uint32_t begin = mesh.cell_offsets[c], end = mesh.cell_offsets[c + 1];
        if (binary) {
            io::store_scalar<std::int32_t>(out, static_cast<std::int32_t>(end - begin), true);
            for (std::uint32_t k = begin; k < end; ++k) io::store_scalar<std::int32_t>(out, static_cast<std::int32_t>(mesh.connectivity[k]), true);
        } else {
            out += std::to_string(end - begin);
            for (std::uint32_t k = begin; k < end; ++k) out += " " + std::to_string(mesh.connectivity[k]);
            out += "\n";
        }
    }
    out += "\nCELL_TYPES " + std::to_string(ncells) + "\n";
    for (std::size_t c = 0; c < ncells; ++c) {
        if (binary) {
            io::store_scalar<std::int32_t>(out, vtk_type_id(mesh.cell_types[c]), true);
        } else {
            out += std::to_string(vtk_type_id(mesh.cell_types[c])) + "\n";
        }
    }
    if (!mesh.scalars.empty()) {
        out += "\nPOINT_DATA " + std::to_string(npoints) + "\n";
        for (const ScalarField& f : mesh.scalars) {
            out += "SCALARS " + encode_name(f.name) + " float 1\nLOOKUP_TABLE default\n";
            for (float v : f.values) {
                if (binary) {
                    io::store_scalar<float>(out, v, true);
                } else {
                    append_text(out, "%.9g\n", v);
                }
            }
            if (binary) out += "\n";
        }
    }
    io::write_output_file(path, out);
}

} // namespace cellfx::fx
