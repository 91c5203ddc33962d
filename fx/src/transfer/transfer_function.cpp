// cellfx — piecewise-linear transfer functions: validation, JSON form, evaluation.
//
// Based on: Max, Williams & Silva 2000 §II and §V (glow colour and extinction as transfer
// functions of the scalar, breakpoints as discontinuities).
#include "fx/transfer_function.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fx/error.hpp"
#include "io/input_file.hpp"
#include "io/json_input.hpp"

namespace cellfx::fx {
namespace {

std::string number(double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
}

// A number for a message about its size: "1e+300", "2000000".
std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// A JSON value for an error message, at most ~60 characters. Arrays are shown only when flat
// and short: dump() recurses once per nesting level, and a file of a million '[' would
// overflow the stack while the message is being built.
std::string brief(const nlohmann::json& v) {
    if (v.is_object()) return "an object";
    if (v.is_array()) {
        const bool flat = std::none_of(v.begin(), v.end(), [](const nlohmann::json& e) { return e.is_structured(); });
        if (!flat || v.size() > 8) return "an array of " + std::to_string(v.size()) + (v.size() == 1 ? " entry" : " entries");
    }
    const std::string s = v.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

// Every rule of the format, in one place; `where` prefixes each message ("fire.json: ").
void validate(const std::vector<TransferPoint>& points, bool normalized, const std::string& where) {
    if (points.empty()) throw Error(where + "points: at least 1 point is needed");
    static const char* const names[5] = {"s", "r", "g", "b", "sigma"};
    for (std::size_t i = 0; i < points.size(); ++i) {
        const TransferPoint& p = points[i];
        const std::string at = where + "points[" + std::to_string(i) + "]: ";
        const double v[5] = {p.s, p.color.r, p.color.g, p.color.b, p.sigma};
        for (int k = 0; k < 5; ++k)
            if (!std::isfinite(v[k])) throw Error(at + names[k] + " is not finite");
        for (int k = 1; k < 5; ++k)
            if (v[k] < 0.0) throw Error(at + names[k] + " is negative");
        for (int k = 1; k < 4; ++k)
            if (v[k] > kMaxColor)
                throw Error(at + names[k] + " = " + short_number(v[k]) + " is over " + short_number(kMaxColor) +
                            ", the largest colour component cellfx integrates");
        if (p.sigma > kMaxSigma)
            throw Error(at + "sigma = " + short_number(p.sigma) + " is over " + short_number(kMaxSigma) +
                        " per world unit, the largest extinction cellfx integrates (anything above ~50 over a cell is opaque)");
        if (i > 0 && p.s < points[i - 1].s)
            throw Error(at + "s decreases (" + number(p.s) + " after " + number(points[i - 1].s) + ")");
        if (i > 1 && p.s == points[i - 2].s)
            throw Error(at + "s = " + number(p.s) + " appears more than twice (a step needs exactly two)");
    }
    if (normalized) {
        const double first = points.front().s, last = points.back().s;
        const bool single = first == last;
        if (single ? (first < 0.0 || first > 1.0) : (first != 0.0 || last != 1.0))
            throw Error(where + "a normalized transfer function must run from s = 0 to s = 1 (it runs from " +
                        number(first) + " to " + number(last) + ")");
    }
}

// Linear interpolation of point data at s, a ≤ s ≤ b with a.s < b.s.
TransferPoint lerp(const TransferPoint& a, const TransferPoint& b, double s) {
    const double t = (s - a.s) / (b.s - a.s);
    return {s, a.color + t * (b.color - a.color), a.sigma + t * (b.sigma - a.sigma)};
}

// The value from above at s (right-continuous).
TransferPoint evaluate(const std::vector<TransferPoint>& p, double s) {
    if (p.empty()) return {s, glm::dvec3(0.0), 0.0}; // default-constructed: nothing there
    const auto it = std::upper_bound(p.begin(), p.end(), s, [](double v, const TransferPoint& q) { return v < q.s; });
    if (it == p.begin()) return p.front();
    if (it == p.end()) return p.back();
    return lerp(*(it - 1), *it, s);
}

} // namespace

TransferFunction::TransferFunction(std::vector<TransferPoint> points, bool normalized)
    : points_(std::move(points)), normalized_(normalized) {
    validate(points_, normalized_, "transfer function: ");
}

TransferFunction TransferFunction::parse_json(std::string_view text, const std::string& source) {
    const std::string where = source + ": ";
    const nlohmann::json root = io::parse_json_input(text, source);
    if (!root.is_object()) throw Error(where + "expected a JSON object {\"points\": [[s, r, g, b, sigma], ...]}");
    for (const auto& item : root.items())
        if (item.key() != "points" && item.key() != "normalized" && item.key() != "description")
            throw Error(where + "unknown key \"" + item.key() + "\" (expected points, normalized, description)");
    bool normalized = false;
    if (const auto n = root.find("normalized"); n != root.end()) {
        if (!n->is_boolean()) throw Error(where + "normalized: must be true or false");
        normalized = n->get<bool>();
    }
    if (const auto d = root.find("description"); d != root.end() && !d->is_string())
        throw Error(where + "description: must be a string");
    const auto pts = root.find("points");
    if (pts == root.end()) throw Error(where + "missing \"points\"");
    if (!pts->is_array()) throw Error(where + "points: must be an array of [s, r, g, b, sigma]");

    static const char* const names[5] = {"s", "r", "g", "b", "sigma"};
    std::vector<TransferPoint> points;
    points.reserve(pts->size());
    for (std::size_t i = 0; i < pts->size(); ++i) {
        const nlohmann::json& e = (*pts)[i];
        const std::string at = where + "points[" + std::to_string(i) + "]: ";
        if (!e.is_array() || e.size() != 5) throw Error(at + "expected 5 numbers [s, r, g, b, sigma], got " + brief(e));
        double v[5];
        for (std::size_t k = 0; k < 5; ++k) {
            if (!e[k].is_number()) throw Error(at + names[k] + " is not a number (" + brief(e[k]) + ")");
            v[k] = e[k].get<double>(); // 1e999 parses to inf; validate() rejects it
        }
        points.push_back({v[0], glm::dvec3(v[1], v[2], v[3]), v[4]});
    }
    validate(points, normalized, where);
    TransferFunction tf;
    tf.points_ = std::move(points);
    tf.normalized_ = normalized;
    return tf;
}

TransferFunction TransferFunction::read_json(const std::string& path) {
    const std::vector<char> bytes = io::read_input_file(path, Limit::JsonBytes, "transfer function file",
                                                        [&](std::string_view head) { io::check_json_encoding(head, path); });
    return parse_json(std::string_view(bytes.data(), bytes.size()), path);
}

TransferFunction TransferFunction::constant(const glm::dvec3& color, double sigma) {
    return TransferFunction({{0.0, color, sigma}});
}

TransferFunction TransferFunction::scaled_extinction(double k) const {
    if (!(k >= 0.0) || !std::isfinite(k)) throw Error("transfer function: the extinction scale must be finite and ≥ 0, got " + number(k));
    if (points_.empty()) return {};
    std::vector<TransferPoint> points = points_;
    for (TransferPoint& p : points) p.sigma *= k;
    return TransferFunction(std::move(points), normalized_);
}

TransferFunction TransferFunction::rescaled(double lo, double hi) const {
    if (!std::isfinite(lo) || !std::isfinite(hi))
        throw Error("transfer function: cannot map it onto [" + number(lo) + ", " + number(hi) +
                    "]: the range of a field must be finite");
    if (points_.empty()) return {};
    if (lo == hi) {
        // A constant field: it sees the value at the function's first s, from above.
        const TransferPoint& p = evaluate(points_, points_.front().s);
        return TransferFunction({{lo, p.color, p.sigma}}, false);
    }
    std::vector<TransferPoint> out = points_;
    const double first = points_.front().s, last = points_.back().s;
    if (first == last) {
        // Only a constant or a single step: put it in the middle of the new range.
        for (TransferPoint& p : out) p.s = 0.5 * lo + 0.5 * hi;
    } else {
        const double scale = (hi - lo) / (last - first);
        for (TransferPoint& p : out) p.s = lo + (p.s - first) * scale; // monotone in p.s
        // Hit the ends exactly; the clamp keeps the order that rounding could have broken.
        for (TransferPoint& p : out) p.s = lo < hi ? std::min(p.s, hi) : std::max(p.s, hi);
        out.back().s = hi;
    }
    // lo > hi mirrors the function; reversing the list also swaps the two entries of each step,
    // which is what "value from below" / "from above" need after the mirror.
    if (lo > hi) std::reverse(out.begin(), out.end());
    // Points closer together than the new range resolves land on one s (s = 0, 1, 1, 2e94
    // onto [1e-7, 2e-7]); three there would not be a valid step. Keep the first and the last
    // of such a run: the values from below and from above, what the squeezed function tends to.
    std::vector<TransferPoint> kept;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const bool inside_run = i > 0 && i + 1 < out.size() && out[i - 1].s == out[i].s && out[i + 1].s == out[i].s;
        if (!inside_run) kept.push_back(out[i]);
    }
    return TransferFunction(std::move(kept), false);
}

glm::dvec3 TransferFunction::color(double s) const { return evaluate(points_, s).color; }

double TransferFunction::sigma(double s) const { return evaluate(points_, s).sigma; }

} // namespace cellfx::fx
