// cellfx_verify — the one image comparison of the tests and the benches.
//
// A frame is compared with an independent reference (the scan-line renderer, a closed form, or
// the same picture made another way) channel by channel:
//   - the images must have the same size (measure() throws fx::Error naming both sizes);
//   - the figures are relative to the reference's peak (its largest value in the compared
//     channels), so one tolerance serves bright and faint scenes;
//   - NaN and ±Inf in the frame are counted, and count as an infinite difference;
//   - each pixel has a bound (Tolerance::pixel). Where the reference changes by more than that
//     bound across a pixel's neighbourhood — an outline, a step — a pixel centre within rounding
//     of the change may be assigned to either side: such a pixel may lie beyond the bound, but
//     only within it of the range of values the reference takes around it (it shows what the
//     reference shows next to it). Elsewhere a stated share of the pixels may lie beyond the
//     bound (a path's own approximation), under the same rule. A pixel outside that range is an
//     outlier, and fails the comparison however few there are — unless the tolerance states a
//     larger bound every pixel keeps (Tolerance::worst, for a path whose error model allows it);
//   - the mean |difference| over the compared channels has its own bound.
// On failure, write_images() writes <prefix>_actual.png, _expected.png and _diff.png (|difference|
// scaled so that the per-pixel bound is a quarter of full scale; pixels beyond it red (at an
// edge: yellow), outliers magenta).
//
// The stated tolerance of each render path, with where each number comes from, is in
// verify/tolerances.hpp. No GL here: the images are fx::Image (premultiplied RGBA floats).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "fx/image.hpp"

namespace cellfx::verify {

// |actual − expected| ≤ of_peak·peak + absolute + relative·|expected|, per channel.
struct Bound {
    double of_peak = 0.0;
    double absolute = 0.0;
    double relative = 0.0;
    double at(double peak, double expected) const { return of_peak * peak + absolute + relative * std::abs(expected); }
};

struct Tolerance {
    Bound pixel;                // per channel of every compared pixel
    double share_beyond = 0.0;  // share of the compared pixels allowed beyond `pixel` away from
                                // any edge of the reference
    int outlier_radius = 1;     // a pixel beyond `pixel` lies within it of the reference's range
                                // over the (2r + 1)² pixels around it (r = 0: no pixel may be
                                // beyond `pixel`), ...
    Bound worst;                // ... or within `worst` of its expected value (0: no such bound)
    Bound mean;                 // mean |difference| over the compared channels (relative unused)
    bool unit_range = false;    // every value of the frame in [0, 1]
    std::string why;            // where the numbers come from (printed with the figures)
};

// What is compared.
struct Options {
    int channels = 4;                      // 4: RGBA; 3: RGB (alpha ignored)
    bool clamp_expected = false;           // the reference clamped to [0, 1]: an 8-bit target's range
    const std::vector<std::uint8_t>* skip = nullptr; // non-zero: pixel y·width + x left out of every figure
};

struct Pixel {
    int x = -1, y = -1;
    glm::vec4 actual{0.0f}, expected{0.0f};
    double delta = 0.0; // the largest |difference| over its channels (outliers: how far outside)
};

struct Difference {
    int width = 0, height = 0, channels = 4;
    std::size_t compared = 0;     // pixels compared
    double peak = 0.0;            // the reference's largest compared value
    double mean = 0.0;            // mean |difference| over the compared channels
    double rms = 0.0;             // root mean square difference over the compared channels
    Pixel worst;                  // the largest |difference|
    std::size_t nonfinite = 0;    // NaN or ±Inf values in the frame
    std::size_t outside_unit = 0; // values of the frame outside [0, 1]
    std::size_t beyond = 0;       // pixels beyond the per-pixel bound
    std::size_t beyond_flat = 0;  // of those, pixels away from any edge of the reference
    std::size_t outliers = 0;     // of those, pixels outside the reference's range around them
    Pixel worst_outlier;          // the one furthest outside (delta: by how much beyond the bound)

    double share_beyond() const { return compared ? double(beyond) / double(compared) : 0.0; }
    double share_beyond_flat() const { return compared ? double(beyond_flat) / double(compared) : 0.0; }
    double of_peak(double value) const { return peak > 0.0 ? value / peak : (value > 0.0 ? INFINITY : 0.0); }
    double psnr() const { return rms > 0.0 ? -20.0 * std::log10(rms) : INFINITY; } // 1 = white
};

// Measures `actual` against `expected` (the reference), counting the pixels beyond `tolerance`.
// Throws fx::Error when the sizes differ.
Difference measure(const fx::Image& actual, const fx::Image& expected, const Tolerance& tolerance,
                   const Options& options = {});
// The largest value of `image` in the compared channels (what the figures are relative to when
// it is the reference).
double peak(const fx::Image& image, const Options& options = {});
// The figures alone (no per-pixel bound: nothing beyond).
Difference measure(const fx::Image& actual, const fx::Image& expected, const Options& options = {});

// What breaks `tolerance`, one clause each ("mean 0.31% of peak > 0.05%"); empty when within.
std::string failures(const Difference& d, const Tolerance& tolerance);
inline bool within(const Difference& d, const Tolerance& tolerance) { return failures(d, tolerance).empty(); }

// One line of figures: peak, worst pixel (% of peak, where, actual and expected), mean, share
// beyond the bound, outliers, non-finite values.
std::string describe(const Difference& d);

// Writes <prefix>_actual.png, <prefix>_expected.png and <prefix>_diff.png (alpha made opaque) and
// returns `prefix`. Throws fx::Error when a file cannot be written.
std::string write_images(const std::string& prefix, const fx::Image& actual, const fx::Image& expected,
                         const Tolerance& tolerance = {}, const Options& options = {});

} // namespace cellfx::verify
