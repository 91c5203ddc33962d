#include "options.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "fx/auto_path.hpp"
#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "fx/cell_mesh.hpp"        // kMaxCoordinate
#include "io/output_file.hpp"
#include "terrain/scene.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

bool ParsedArgs::has(const std::string& key) const {
    return std::any_of(options.begin(), options.end(), [&](const auto& kv) { return kv.first == key; });
}

std::string ParsedArgs::get(const std::string& key, const std::string& fallback) const {
    for (auto it = options.rbegin(); it != options.rend(); ++it) {
        if (it->first == key) return it->second;
    }
    return fallback;
}

ParsedArgs parse_args(const std::vector<std::string>& args, const std::vector<std::string>& flags) {
    ParsedArgs parsed;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() < 3 || a.compare(0, 2, "--") != 0) {
            parsed.positional.push_back(a);
            continue;
        }
        std::string key = a.substr(2), value;
        const std::size_t eq = key.find('=');
        if (eq != std::string::npos) {
            value = key.substr(eq + 1);
            key = key.substr(0, eq);
        } else if (std::find(flags.begin(), flags.end(), key) == flags.end()) {
            if (i + 1 >= args.size()) throw fx::Error("--" + key + " needs a value");
            value = args[++i];
        }
        parsed.options.emplace_back(key, value);
    }
    return parsed;
}

void require_known(const ParsedArgs& parsed, const std::vector<std::string>& known) {
    for (const auto& [key, value] : parsed.options) {
        if (std::find(known.begin(), known.end(), key) == known.end()) throw fx::Error("unknown option --" + key);
    }
}

double parse_double(const std::string& text, const std::string& what) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
        throw fx::Error(what + ": '" + text + "' is not a finite number");
    }
    return v;
}

double parse_fx_scale(const std::string& text) {
    const double scale = text == "1/2" ? 0.5 : text == "1/4" ? 0.25 : parse_double(text, "--fx-scale");
    if (!terrain::valid_fx_scale(scale))
        throw fx::Error("--fx-scale: '" + text + "' must be 1, 0.5 or 0.25 (the effects' resolution: full, half, quarter)");
    return scale;
}

fx::MediumMethod parse_medium_option(const std::string& text) {
    fx::MediumMethod method;
    if (!fx::parse_medium_method(text, method))
        throw fx::Error("--medium: unknown method '" + text + "' (expected froxel or exact)");
    return method;
}

int parse_int(const std::string& text, const std::string& what) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || end != text.c_str() + text.size() || v < -1000000000L || v > 1000000000L) {
        throw fx::Error(what + ": '" + text + "' is not an integer");
    }
    return static_cast<int>(v);
}

namespace {

// A row of the table: the option's command, name, kind and range, a resource limit that bounds
// it too, and what it sets.
enum class OptionKind {
    Integer,     // one whole number in [lo, hi]
    Number,      // one number in [lo, hi] (or (lo, hi] with lo_open)
    IntegerList, // "A,B,...": each in [lo, hi]
    Size,        // "WxH" (parse_size): each side in [lo, hi], W·H within image-pixels
    Colour,      // "R,G,B" (parse_colour): each in [lo, hi]
    Camera,      // fx::Camera::parse's form, every number checked by Camera::validate
};
struct NumericOption {
    const char* command; // "render", "bench sort", ...
    const char* name;    // without the dashes
    OptionKind kind;
    double lo, hi;
    bool lo_open;        // lo itself excluded
    const char* budget;  // a resource limit that also bounds it ("mesh-cells"), or nullptr
    const char* what;    // what it sets, for `cellfx limits`
};

// The largest side of an image (GL's textures and most drivers' framebuffers stop there).
constexpr double kMaxImageSide = 16384;
// Benchmark repetitions and frames: enough for any median, bounded so a typo cannot run for days.
constexpr double kMaxRepeat = 1000;
// Orbit and sort views: one per degree.
constexpr double kMaxViews = 360;

using K = OptionKind;
// Every numeric option of every subcommand (docs: `cellfx limits`, docs/robustness.md).
const std::vector<NumericOption> kNumericOptions = {
    {"render", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"render", "near", K::Number, 0, fx::kMaxCoordinate, true, nullptr, "near-plane distance (and below the camera's far)"},
    {"render", "camera", K::Camera, -fx::kMaxCoordinate, fx::kMaxCoordinate, false, nullptr,
     "eye and target coordinates; fov in (0, 180), ortho, near, far > 0 (fx::Camera::validate)"},
    {"render", "density", K::Number, 0, 1e300, false, nullptr,
     "factor on the extinction; every point's sigma times it must stay within 1e32 (checked with the transfer function)"},
    {"render", "background", K::Colour, 0, 1, false, nullptr, "background colour R,G,B"},
    {"render", "threads", K::Integer, 1, 256, false, nullptr, "scan-line worker threads"},
    {"render", "accuracy", K::Number, fx::kMinAccuracy, fx::kMaxAccuracy, false, nullptr,
     "--path auto: accepted mean error per pixel, share of the picture's peak"},
    {"render", "time", K::Number, -1e6, 1e6, false, nullptr, "scene time in seconds (the samples' --time range)"},
    {"render", "pixel-error", K::Number, 0, 1e6, true, nullptr, "scene: the terrain LOD's screen-space error in pixels"},
    {"convert", "cells", K::Integer, 1, 1e9, false, "mesh-cells", "cells of a --synthetic mesh"},
    {"bench scanline", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"bench scanline", "repeat", K::Integer, 1, kMaxRepeat, false, nullptr, "frames timed per thread count"},
    {"bench scanline", "scale", K::Number, 0, 2.5, true, nullptr, "resolution of the nine grids (points grow as its cube)"},
    {"bench scanline", "threads", K::IntegerList, 1, 256, false, nullptr, "thread counts to time"},
    {"bench pcp", "repeat", K::Integer, 1, kMaxRepeat, false, nullptr, "frames timed per size"},
    {"bench pcp", "grid", K::Integer, 1, 256, false, nullptr, "hexahedra along each side of the grid (its cube: mesh-cells)"},
    {"bench pcp", "sizes", K::IntegerList, 1, kMaxImageSide, false, "image-pixels", "square image sides"},
    {"bench sort", "cells", K::Integer, 6, 1e9, false, "mesh-cells", "tetrahedra of each mesh"},
    {"bench sort", "views", K::Integer, 2, kMaxViews, false, nullptr, "views sorted per mesh"},
    {"bench sort", "repeat", K::Integer, 1, kMaxRepeat, false, nullptr, "sorts per view (best taken)"},
    {"bench terrain", "lod-frames", K::Integer, 2, 100000, false, nullptr, "frames of the LOD flight"},
    {"bench terrain", "frames", K::Integer, 1, kMaxRepeat, false, nullptr, "fog valley frames timed per path"},
    {"bench terrain", "views", K::Integer, 1, kMaxViews, false, nullptr, "views of the pixels-changed test"},
    {"bench terrain", "sizes", K::IntegerList, 3, 16385, false, "height-samples", "height field sides, each 2^n + 1"},
    {"bench terrain", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "frame width x height (WxH)"},
    {"bench absorption", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"bench absorption", "frames", K::Integer, 1, kMaxRepeat, false, nullptr, "frames timed per sort"},
    {"bench absorption", "cells", K::Integer, 6, 1e9, false, "mesh-cells", "tetrahedra of the box scene"},
    {"bench effects", "frames", K::Integer, 1, kMaxRepeat, false, nullptr, "frames timed per scene and path"},
    {"bench effects", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"bench render", "views", K::Integer, 1, kMaxViews, false, nullptr, "views of the orbit"},
    {"bench render", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"bench render", "threads", K::Integer, 1, 256, false, nullptr, "scan-line worker threads"},
    {"bench render", "density", K::Number, 0, 1e300, false, nullptr, "factor on the extinction (as render's)"},
    {"bench render", "planar-tolerance", K::Number, -1, 1, false, nullptr,
     "the exact paths' planar test, a fraction of a cell's size (negative: no cell is planar)"},
    {"bench accuracy", "frames", K::Integer, 1, kMaxRepeat, false, nullptr, "frames timed per flavour"},
    {"bench flicker", "frames", K::Integer, 2, kMaxRepeat, false, nullptr, "frames of the flight (consecutive pairs compared)"},
    {"bench flicker", "time", K::Number, -1e6, 1e6, false, nullptr, "scene time of the first frame in seconds"},
    {"bench flicker", "size", K::Size, 1, kMaxImageSide, false, "image-pixels", "image width x height (WxH)"},
    {"bench noise", "rounds", K::Integer, 1, kMaxRepeat, false, nullptr, "rounds timed per function (medians)"},
    {"bench noise", "size", K::Integer, 4, 256, false, nullptr, "samples per axis of the 3-D items (N^3)"},
    {"bench accuracy", "fem-cells", K::Integer, 6, 1e9, false, "mesh-cells", "tetrahedra of the FEM scene"},
};

const NumericOption& find_option(const char* command, const char* name) {
    for (const NumericOption& o : kNumericOptions)
        if (std::string(o.command) == command && std::string(o.name) == name) return o;
    throw std::logic_error(std::string("no documented range for ") + command + " --" + name);
}

std::string range_text(const NumericOption& o) {
    const bool whole = o.kind != K::Number && o.kind != K::Camera && o.kind != K::Colour;
    const std::string lo = whole ? fx::with_commas(std::uint64_t(o.lo)) : format_number(o.lo);
    const std::string hi = whole ? fx::with_commas(std::uint64_t(o.hi)) : format_number(o.hi);
    switch (o.kind) {
    case K::Size: return lo + " .. " + hi + " a side";
    case K::Colour: return "each in [" + lo + ", " + hi + "]";
    case K::Camera: return "coordinates within ±" + hi;
    case K::Integer:
    case K::IntegerList: return lo + " .. " + hi + (o.kind == K::IntegerList ? " each" : "");
    case K::Number: break;
    }
    return (o.lo_open ? "(" : "[") + lo + ", " + hi + "]";
}

fx::Limit budget_of(const NumericOption& o) {
    for (int l = 0; l < fx::kLimitCount; ++l)
        if (std::string(fx::limit_name(fx::Limit(l))) == o.budget) return fx::Limit(l);
    throw std::logic_error(std::string("unknown budget ") + o.budget);
}

[[noreturn]] void outside(const NumericOption& o, const std::string& text) {
    throw fx::Error(std::string(o.command) + " --" + o.name + ": " + text + " is outside " + range_text(o) + " (" + o.what +
                    "; `cellfx limits` lists every option's range)");
}

// A whole number of the option's range (any number of digits: 1e10 is outside, not "not an integer").
long long checked_integer(const NumericOption& o, const std::string& text) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || end != text.c_str() + text.size())
        throw fx::Error(std::string(o.command) + " --" + o.name + ": '" + text + "' is not a whole number");
    if (errno == ERANGE || double(v) < o.lo || double(v) > o.hi) outside(o, text);
    return v;
}

} // namespace

void parse_size(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find('x');
    if (x == std::string::npos) throw fx::Error("--size: '" + text + "' is not WxH (e.g. 512x512)");
    width = parse_int(text.substr(0, x), "--size width");
    height = parse_int(text.substr(x + 1), "--size height");
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide) {
        throw fx::Error("--size: " + text + " is outside 1x1 .. 16384x16384");
    }
    fx::check_limit(fx::Limit::ImagePixels, std::uint64_t(width) * std::uint64_t(height), "--size " + text);
}

std::string describe_numeric_options() {
    std::string out;
    for (const NumericOption& o : kNumericOptions) {
        std::string name = std::string(o.command) + " --" + o.name;
        name.resize(std::max<std::size_t>(name.size() + 1, 30), ' ');
        std::string range = range_text(o);
        if (o.budget) range += std::string(" and ") + o.budget;
        range.resize(std::max<std::size_t>(range.size() + 1, 40), ' ');
        out += "  " + name + range + o.what + "\n";
    }
    return out;
}

int int_option(const ParsedArgs& parsed, const char* command, const char* name, int fallback) {
    const NumericOption& o = find_option(command, name);
    if (!parsed.has(name)) return fallback;
    const std::string text = parsed.get(name);
    const long long v = checked_integer(o, text);
    if (o.budget) fx::check_limit(budget_of(o), std::uint64_t(v), std::string(command) + " --" + name + " " + text);
    return int(v);
}

double number_option(const ParsedArgs& parsed, const char* command, const char* name, double fallback) {
    const NumericOption& o = find_option(command, name);
    if (!parsed.has(name)) return fallback;
    const std::string text = parsed.get(name);
    const double v = parse_double(text, std::string(command) + " --" + name);
    if (v < o.lo || v > o.hi || (o.lo_open && v == o.lo)) outside(o, text);
    return v;
}

std::vector<int> int_list_option(const ParsedArgs& parsed, const char* command, const char* name,
                                 const std::string& fallback) {
    const NumericOption& o = find_option(command, name);
    const std::string list = parsed.get(name, fallback);
    std::vector<int> values;
    for (const std::string& item : split_list(list)) {
        const long long v = checked_integer(o, item);
        // Each value is a side of something square (an image, a height field): its square is
        // what the budget bounds.
        if (o.budget)
            fx::check_limit(budget_of(o), std::uint64_t(v) * std::uint64_t(v), std::string(command) + " --" + name + " " + item);
        values.push_back(int(v));
    }
    if (values.empty()) throw fx::Error(std::string(command) + " --" + name + ": no value given");
    return values;
}

std::string output_file_option(const ParsedArgs& parsed, const std::string& name,
                               const std::vector<std::string>& extensions, bool required) {
    std::string kinds;
    for (const std::string& e : extensions) kinds += (kinds.empty() ? "FILE" : "|FILE") + e;
    const std::string path = parsed.get(name);
    if (path.empty()) {
        if (!required) return path;
        throw fx::Error("--" + name + " " + (kinds.empty() ? "FILE" : kinds) + " is required");
    }
    try {
        fx::io::check_output_file(path);
    } catch (const fx::Error& e) {
        throw fx::Error("--" + name + " " + e.what());
    }
    if (!extensions.empty() &&
        std::none_of(extensions.begin(), extensions.end(), [&](const std::string& e) { return has_extension(path, e); }))
        throw fx::Error("--" + name + " " + path + ": not a file type this command writes (name it " + kinds + ")");
    return path;
}

glm::dvec3 parse_vec3(const std::string& text, const std::string& what) {
    glm::dvec3 v;
    std::size_t start = 0;
    for (int i = 0; i < 3; ++i) {
        const std::size_t comma = text.find(',', start);
        if ((i < 2) != (comma != std::string::npos)) throw fx::Error(what + ": '" + text + "' is not x,y,z");
        v[i] = parse_double(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start), what);
        start = comma + 1;
    }
    return v;
}

glm::dvec3 parse_colour(const std::string& text, const std::string& what) {
    const glm::dvec3 c = parse_vec3(text, what);
    for (int i = 0; i < 3; ++i) {
        if (!(c[i] >= 0.0 && c[i] <= 1.0)) throw fx::Error(what + ": " + text + " is outside [0, 1] (each of R, G, B)");
    }
    return c;
}

std::string format_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

bool has_extension(const std::string& path, const std::string& extension) {
    if (path.size() < extension.size()) return false;
    for (std::size_t i = 0; i < extension.size(); ++i) {
        const char c = path[path.size() - extension.size() + i];
        if (std::tolower(static_cast<unsigned char>(c)) != std::tolower(static_cast<unsigned char>(extension[i]))) return false;
    }
    return true;
}

std::vector<std::string> split_list(const std::string& list) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = list.find(',', start);
        const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!item.empty()) out.push_back(item);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return out;
}

} // namespace cellfx_cli
