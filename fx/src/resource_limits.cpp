// cellfx — the process-wide resource budget, its names and its messages.
#include "fx/resource_limits.hpp"

#include <cmath>
#include <cstdlib>
#include <mutex>

#include "fx/error.hpp"

namespace cellfx::fx {
namespace {

struct LimitInfo {
    const char* name;
    const char* field;
    const char* unit;
    const char* what;
    std::uint64_t ResourceLimits::*member;
};

const LimitInfo kLimits[kLimitCount] = {
    {"file-bytes", "file_bytes", "bytes", "read from one mesh, q or height-map file", &ResourceLimits::file_bytes},
    {"json-bytes", "json_bytes", "bytes", "read from one scene or transfer-function file", &ResourceLimits::json_bytes},
    {"input-wait", "input_wait_seconds", "seconds", "a pipe or device may stay silent before reading it fails",
     &ResourceLimits::input_wait_seconds},
    {"mesh-points", "mesh_points", "points", "in one mesh (read, built or rendered)", &ResourceLimits::mesh_points},
    {"mesh-cells", "mesh_cells", "cells", "in one mesh", &ResourceLimits::mesh_cells},
    {"image-pixels", "image_pixels", "pixels", "in one rendered image (width x height)", &ResourceLimits::image_pixels},
    {"frame-bytes", "frame_bytes", "bytes", "of scan-line working memory in one frame", &ResourceLimits::frame_bytes},
    {"sort-pairs", "sort_pairs", "pairs per boundary triangle", "of projected boundary faces the xmpvo sort tests",
     &ResourceLimits::sort_pairs},
    {"effects", "effects", "effects", "in one scene", &ResourceLimits::effects},
    {"effect-cells", "effect_cells", "cells", "one effect may build", &ResourceLimits::effect_cells},
    {"scene-cells", "scene_cells", "cells", "all of a scene's effects may build together", &ResourceLimits::scene_cells},
    {"height-samples", "height_samples", "samples", "in one height field (terrain, fog map, aurora)",
     &ResourceLimits::height_samples},
};

const LimitInfo& info(Limit limit) { return kLimits[static_cast<int>(limit)]; }

std::mutex g_mutex;
ResourceLimits g_limits;

} // namespace

const char* limit_name(Limit limit) { return info(limit).name; }
const char* limit_unit(Limit limit) { return info(limit).unit; }
const char* limit_field(Limit limit) { return info(limit).field; }
std::uint64_t limit_value(const ResourceLimits& limits, Limit limit) { return limits.*info(limit).member; }

ResourceLimits resource_limits() {
    std::lock_guard<std::mutex> lock(g_mutex);
    return g_limits;
}

void set_resource_limits(const ResourceLimits& limits) {
    std::lock_guard<std::mutex> lock(g_mutex);
    g_limits = limits;
}

void apply_limit(ResourceLimits& limits, std::string_view assignment) {
    const std::size_t eq = assignment.find('=');
    const std::string name(assignment.substr(0, eq));
    const LimitInfo* found = nullptr;
    for (const LimitInfo& l : kLimits) {
        if (name == l.name) found = &l;
    }
    if (!found) {
        std::string names;
        for (const LimitInfo& l : kLimits) names += std::string(names.empty() ? "" : ", ") + l.name;
        throw Error("--limit: unknown limit '" + name + "' (expected NAME=N with NAME one of " + names + ")");
    }
    if (eq == std::string_view::npos) throw Error("--limit: " + name + " needs a value (" + name + "=N)");
    const std::string text(assignment.substr(eq + 1));
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !(v >= 0.0) || v >= 1.8e19 || v != std::floor(v)) {
        throw Error("--limit " + name + ": '" + text + "' is not a whole number of " + found->unit);
    }
    limits.*found->member = static_cast<std::uint64_t>(v);
}

std::string describe_limits(const ResourceLimits& limits) {
    std::string out;
    for (const LimitInfo& l : kLimits) {
        std::string name = l.name;
        name.resize(16, ' ');
        out += "  " + name + with_commas(limits.*l.member) + " " + l.unit + " " + l.what + "\n";
    }
    return out;
}

bool exceeds(Limit limit, std::uint64_t amount) { return amount > limit_value(resource_limits(), limit); }

std::string over_limit(Limit limit, std::uint64_t amount, const std::string& what) {
    const LimitInfo& l = info(limit);
    return what + " needs " + with_commas(amount) + " " + l.unit + ", over the " + l.name + " limit of " +
           with_commas(limit_value(resource_limits(), limit)) + " (raise it with --limit " + l.name +
           "=N or fx::ResourceLimits::" + l.field + ")";
}

void check_limit(Limit limit, std::uint64_t amount, const std::string& what) {
    if (exceeds(limit, amount)) throw Error(over_limit(limit, amount, what));
}

std::string with_commas(std::uint64_t n) {
    const std::string digits = std::to_string(n);
    std::string out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

} // namespace cellfx::fx
