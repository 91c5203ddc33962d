// cellfx — piecewise-linear transfer functions: scalar → colour and extinction.
//
// A transfer function is a list of control points (s, r, g, b, sigma) with s non-decreasing.
// Between points colour and sigma are linear in s; a point repeated at the same s makes a
// step (discontinuity): the first entry is the value approaching from below, the second from
// above. Outside [first s, last s] the end values are held. sigma is extinction per world
// unit; the emitted light per unit length is colour·sigma ("glowing particles"), so the same
// file drives emission-only, MIP and emission–absorption paths.
//
// File form (JSON): {"points": [[s, r, g, b, sigma], ...]} with optional "normalized": true,
// meaning s runs from exactly 0 to exactly 1 (or, for a single s value, lies in [0, 1]) and is
// to be mapped onto a scalar field's range with rescaled(); optional "description": a string.
// Other keys are rejected. Every value must be finite, colour and sigma non-negative and at
// most kMaxColor and kMaxSigma (so that colour·sigma·length stays finite in every path's float
// arithmetic).
// content/transfer_functions/README.md describes the format for users.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace cellfx::fx {

// The largest extinction (per world unit) and colour component a transfer function may hold:
// every value and colour·sigma (≤ 1e38) fit a float, which the GPU paths' tables are. An
// optical depth beyond ~50 is opaque anyway; the paths keep what they integrate finite.
constexpr double kMaxSigma = 1.0e32;
constexpr double kMaxColor = 1.0e6;

struct TransferPoint {
    double s;
    glm::dvec3 color;
    double sigma;
};

class TransferFunction {
public:
    // No points: colour and sigma are zero everywhere (nothing is drawn).
    TransferFunction() = default;
    // Throws fx::Error if points are empty, unsorted, non-finite, negative, a scalar value
    // appears more than twice, or `normalized` is set and s does not run from 0 to 1. Messages
    // name the entry: "transfer function: points[3]: sigma is negative".
    explicit TransferFunction(std::vector<TransferPoint> points, bool normalized = false);

    // Parses the JSON form; errors name `source` (a file name) and the offending entry or key
    // ("fire.json: points[3]: sigma is negative"); syntax errors give nlohmann's byte position.
    static TransferFunction parse_json(std::string_view text, const std::string& source);
    static TransferFunction read_json(const std::string& path);
    // Colour c and extinction sigma everywhere.
    static TransferFunction constant(const glm::dvec3& color, double sigma);

    const std::vector<TransferPoint>& points() const { return points_; }
    bool normalized() const { return normalized_; }
    // The same function with its s range [first, last] mapped linearly onto [lo, hi]
    // (normalized() becomes false). lo > hi mirrors the function; a non-finite bound throws
    // fx::Error. A function whose points all share one s is centred in [lo, hi]. Where a
    // narrow range maps more than two points onto one s, the first and last are kept.
    // lo == hi (a constant field) gives the constant value the function has at its first s
    // (from above), as if the range were [lo, lo + ε]: the field's one value is its low end.
    TransferFunction rescaled(double lo, double hi) const;
    // The same colours with every sigma multiplied by k (a scene's "extinction_scale"): k ≥ 0
    // and finite, else fx::Error.
    TransferFunction scaled_extinction(double k) const;

    // Values at s; at a step, the value from above (right-continuous).
    glm::dvec3 color(double s) const;
    double sigma(double s) const;
    glm::dvec3 emission(double s) const { return color(s) * sigma(s); }

private:
    std::vector<TransferPoint> points_;
    bool normalized_ = false;
};

} // namespace cellfx::fx
