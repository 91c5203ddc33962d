#include "options.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
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

void parse_size(const std::string& text, int& width, int& height) {
    const std::size_t x = text.find('x');
    if (x == std::string::npos) throw fx::Error("--size: '" + text + "' is not WxH (e.g. 512x512)");
    width = parse_int(text.substr(0, x), "--size width");
    height = parse_int(text.substr(x + 1), "--size height");
    if (width < 1 || height < 1 || width > 16384 || height > 16384) {
        throw fx::Error("--size: " + text + " is outside 1x1 .. 16384x16384");
    }
    fx::check_limit(fx::Limit::ImagePixels, std::uint64_t(width) * std::uint64_t(height), "--size " + text);
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
        if (!(c[i] >= 0.0 && c[i] <= 1.0)) throw fx::Error(what + ": '" + text + "': each of R, G, B must be in [0, 1]");
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
