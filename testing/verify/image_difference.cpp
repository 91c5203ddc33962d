#include "verify/image_difference.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "fx/error.hpp"

namespace cellfx::verify {
namespace {

double expected_value(const fx::Image& expected, std::size_t i, int c, const Options& o) {
    const double e = expected.pixels[i][c];
    return o.clamp_expected ? std::clamp(e, 0.0, 1.0) : e;
}

bool skipped(const Options& o, std::size_t i) { return o.skip && (*o.skip)[i]; }

// |a − e|, with a non-finite frame value an infinite difference.
double delta(double a, double e) { return std::isfinite(a) ? std::abs(a - e) : INFINITY; }

// How one pixel stands against the tolerance.
struct Verdict {
    double largest = 0.0;  // its largest |difference|
    bool beyond = false;   // some channel beyond the per-pixel bound
    bool at_edge = false;  // the reference changes by more than the bound across its neighbourhood
    double outside = 0.0;  // > 0: an outlier, by this much outside the reference's range + the bound
};

Verdict judge(const fx::Image& actual, const fx::Image& expected, int x, int y, double peak, const Tolerance& t,
              const Options& o) {
    const std::size_t i = actual.index(x, y);
    const int r = std::max(t.outlier_radius, 0);
    Verdict v;
    for (int c = 0; c < o.channels; ++c) {
        const double a = actual.pixels[i][c], e = expected_value(expected, i, c, o);
        const double d = delta(a, e), bound = t.pixel.at(peak, e);
        v.largest = std::max(v.largest, d);
        if (d <= bound) continue;
        v.beyond = true;
        double lo = INFINITY, hi = -INFINITY;
        for (int yy = std::max(y - r, 0); yy <= std::min(y + r, actual.height - 1); ++yy)
            for (int xx = std::max(x - r, 0); xx <= std::min(x + r, actual.width - 1); ++xx) {
                const double n = expected_value(expected, expected.index(xx, yy), c, o);
                lo = std::min(lo, n), hi = std::max(hi, n);
            }
        v.at_edge = v.at_edge || hi - lo > bound;
        const double off = (std::isfinite(a) ? std::max({lo - a, a - hi, 0.0}) : INFINITY) - bound;
        if (off > 0.0 && !(d <= t.worst.at(peak, e))) v.outside = std::max(v.outside, off);
    }
    return v;
}

std::string percent(double part) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g%%", 100.0 * part);
    return buf;
}

std::string rgba(const glm::vec4& v, int channels) {
    std::ostringstream s;
    s << v.r << " " << v.g << " " << v.b;
    if (channels == 4) s << " " << v.a;
    return s.str();
}

void check_inputs(const fx::Image& actual, const fx::Image& expected, const Options& options) {
    if (actual.width != expected.width || actual.height != expected.height ||
        actual.pixels.size() != expected.pixels.size())
        throw fx::Error("image comparison: the frame is " + std::to_string(actual.width) + "x" +
                        std::to_string(actual.height) + ", the reference " + std::to_string(expected.width) + "x" +
                        std::to_string(expected.height));
    if (options.channels != 3 && options.channels != 4)
        throw fx::Error("image comparison: " + std::to_string(options.channels) + " channels (3 or 4)");
    if (options.skip && options.skip->size() != expected.pixels.size())
        throw fx::Error("image comparison: the skip mask has " + std::to_string(options.skip->size()) +
                        " entries for " + std::to_string(expected.pixels.size()) + " pixels");
}


} // namespace

double peak(const fx::Image& image, const Options& options) {
    double p = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        if (!skipped(options, i))
            for (int c = 0; c < options.channels; ++c) p = std::max(p, expected_value(image, i, c, options));
    return p;
}

Difference measure(const fx::Image& actual, const fx::Image& expected, const Tolerance& tolerance,
                   const Options& options) {
    check_inputs(actual, expected, options);
    Difference d;
    d.width = actual.width, d.height = actual.height, d.channels = options.channels;
    d.peak = peak(expected, options);
    double sum = 0.0, squares = 0.0;
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const std::size_t i = actual.index(x, y);
            if (skipped(options, i)) continue;
            ++d.compared;
            for (int c = 0; c < options.channels; ++c) {
                const double a = actual.pixels[i][c], dc = delta(a, expected_value(expected, i, c, options));
                if (!std::isfinite(a)) ++d.nonfinite;
                if (!(a >= 0.0 && a <= 1.0)) ++d.outside_unit;
                sum += std::isfinite(dc) ? dc : 1e30;
                squares += std::isfinite(dc) ? dc * dc : 1e60;
            }
            const Verdict v = judge(actual, expected, x, y, d.peak, tolerance, options);
            if (!(v.largest <= d.worst.delta) || d.worst.x < 0)
                d.worst = {x, y, actual.pixels[i], expected.pixels[i], v.largest};
            if (!v.beyond) continue;
            ++d.beyond;
            d.beyond_flat += !v.at_edge;
            if (v.outside > 0.0) {
                ++d.outliers;
                if (!(v.outside <= d.worst_outlier.delta) || d.worst_outlier.x < 0)
                    d.worst_outlier = {x, y, actual.pixels[i], expected.pixels[i], v.outside};
            }
        }
    }
    const double n = double(std::max<std::size_t>(d.compared, 1)) * options.channels;
    d.mean = sum / n;
    d.rms = std::sqrt(squares / n);
    return d;
}

Difference measure(const fx::Image& actual, const fx::Image& expected, const Options& options) {
    Tolerance unbounded;
    unbounded.pixel.absolute = INFINITY;
    return measure(actual, expected, unbounded, options);
}

std::string failures(const Difference& d, const Tolerance& t) {
    std::ostringstream s;
    auto clause = [&s](const std::string& text) { s << (s.tellp() > 0 ? "; " : "") << text; };
    if (d.nonfinite) clause(std::to_string(d.nonfinite) + " values NaN or infinite");
    if (t.unit_range && d.outside_unit) clause(std::to_string(d.outside_unit) + " values outside [0, 1]");
    if (d.share_beyond_flat() > t.share_beyond)
        clause(percent(d.share_beyond_flat()) + " of the pixels beyond the per-pixel bound away from any edge > " +
               percent(t.share_beyond));
    if (d.outliers)
        clause(std::to_string(d.outliers) + " pixels beyond the bound and outside the reference's range within " +
               std::to_string(t.outlier_radius) + " px (worst at (" + std::to_string(d.worst_outlier.x) + ", " +
               std::to_string(d.worst_outlier.y) + "), " + percent(d.of_peak(d.worst_outlier.delta)) +
               " of peak outside)");
    const double mean_bound = t.mean.at(d.peak, 0.0);
    if (!(d.mean <= mean_bound))
        clause("mean " + percent(d.of_peak(d.mean)) + " of peak > " + percent(d.of_peak(mean_bound)));
    return s.str();
}

std::string describe(const Difference& d) {
    std::ostringstream s;
    s << d.width << "x" << d.height << ", peak " << d.peak << ": worst " << percent(d.of_peak(d.worst.delta))
      << " of peak at (" << d.worst.x << ", " << d.worst.y << ") actual " << rgba(d.worst.actual, d.channels)
      << " expected " << rgba(d.worst.expected, d.channels) << "; mean " << percent(d.of_peak(d.mean))
      << "; beyond the bound " << percent(d.share_beyond()) << " of " << d.compared << " pixels";
    if (d.beyond) s << " (" << percent(d.share_beyond_flat()) << " away from edges)";
    if (d.outliers) s << ", " << d.outliers << " outliers";
    if (d.nonfinite) s << "; " << d.nonfinite << " NaN/Inf";
    return s.str();
}

std::string write_images(const std::string& prefix, const fx::Image& actual, const fx::Image& expected,
                         const Tolerance& tolerance, const Options& options) {
    check_inputs(actual, expected, options);
    const double peak = verify::peak(expected, options);
    // |difference| scaled so that the per-pixel bound at the peak is a quarter of full scale
    // (10% of peak where the bound is 0).
    const double bound = tolerance.pixel.at(peak, peak);
    const double gain = bound > 0.0 ? 0.25 / bound : (peak > 0.0 ? 10.0 / peak : 1.0);
    fx::Image diff(actual.width, actual.height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    for (int y = 0; y < actual.height; ++y)
        for (int x = 0; x < actual.width; ++x) {
            const std::size_t i = actual.index(x, y);
            if (skipped(options, i)) {
                diff.pixels[i] = glm::vec4(0.0f, 0.0f, 0.3f, 1.0f);
                continue;
            }
            const Verdict v = judge(actual, expected, x, y, peak, tolerance, options);
            const float g = float(std::min(1.0, v.largest * gain));
            diff.pixels[i] = v.outside > 0.0 ? glm::vec4(1.0f, 0.0f, 1.0f, 1.0f)
                             : v.beyond      ? (v.at_edge ? glm::vec4(1.0f, 1.0f, 0.0f, 1.0f) : glm::vec4(1.0f, 0.0f, 0.0f, 1.0f))
                                             : glm::vec4(g, g, g, 1.0f);
        }
    auto opaque = [](fx::Image img) {
        for (glm::vec4& p : img.pixels) p.a = 1.0f;
        return img;
    };
    fx::write_png(opaque(actual), prefix + "_actual.png");
    fx::write_png(opaque(expected), prefix + "_expected.png");
    fx::write_png(diff, prefix + "_diff.png");
    return prefix;
}

} // namespace cellfx::verify
