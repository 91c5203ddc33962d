// Based on: Roettger & Ertl 2003, §5 (aurora from a penetration-depth height field, emissive).
#include "terrain/aurora.hpp"

#include <algorithm>
#include <cmath>

#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"

namespace cellfx::terrain {

HeightField make_aurora_depth(int size, double spacing, glm::dvec2 origin, const AuroraCurtains& c,
                              const std::function<double(double x, int band)>& wave,
                              const HeightGenerator& brightness) {
    if (c.count < 1) throw fx::Error("aurora: curtain count must be at least 1");
    if (!(c.max_depth > 0.0) || !std::isfinite(c.max_depth)) throw fx::Error("aurora: max_depth must be positive");
    if (!(c.width > 0.0) || !std::isfinite(c.width)) throw fx::Error("aurora: width must be positive");
    if (!std::isfinite(c.wander) || !(c.cutoff >= 0.0 && c.cutoff < 1.0))
        throw fx::Error("aurora: wander must be finite and cutoff in [0, 1)");
    const double extent = spacing * (size - 1);
    // Built-in shapes: a few incommensurate sinusoids per band (phases from the seed).
    auto phase = [&](int k, int m) { return 2.399963 * (c.seed * 7 + k * 3 + m); };
    auto default_wave = [&](double x, int k) {
        const double u = (x - origin.x) / std::max(extent, 1e-30);
        return 0.6 * std::sin(6.2832 * 1.3 * u + phase(k, 0)) + 0.3 * std::sin(6.2832 * 3.7 * u + phase(k, 1)) +
               0.1 * std::sin(6.2832 * 9.1 * u + phase(k, 2));
    };
    auto default_brightness = [&](double x, double y) {
        const double u = (x - origin.x) / std::max(extent, 1e-30), v = (y - origin.y) / std::max(extent, 1e-30);
        return 0.55 + 0.45 * std::sin(6.2832 * (2.1 * u + 0.7 * v) + phase(0, 5));
    };
    return make_height_field(size, spacing, [&](double x, double y) {
        double d = 0.0;
        for (int k = 0; k < c.count; ++k) {
            const double centre = origin.y + extent * (k + 1.0) / (c.count + 1.0) +
                                  c.wander * std::clamp(wave ? wave(x, k) : default_wave(x, k), -1.0, 1.0);
            const double a = (y - centre) / c.width;
            d = std::max(d, std::exp(-0.5 * a * a));
        }
        const double b = std::clamp(brightness ? brightness(x, y) : default_brightness(x, y), 0.0, 1.0);
        const double depth = c.max_depth * d * b;
        return depth < c.cutoff * c.max_depth ? 0.0 : depth;
    }, origin);
}

AuroraLayer make_aurora_layer(const HeightField& penetration_depth, double ceiling) {
    if (!(std::abs(ceiling) <= fx::kMaxCoordinate))
        throw fx::Error("aurora: the ceiling height must be finite and within ±1e18 (the coordinates cellfx renders)");
    AuroraLayer layer{penetration_depth, penetration_depth};
    for (std::size_t k = 0; k < layer.depth.heights.size(); ++k) {
        const float d = layer.depth.heights[k];
        if (!(d >= 0.0f) || !std::isfinite(d))
            throw fx::Error("aurora: the penetration depth at sample (" + std::to_string(k % layer.depth.size) + ", " +
                            std::to_string(k / layer.depth.size) + ") is negative or not finite");
        layer.lower_border.heights[k] = float(ceiling - d);
    }
    return layer;
}

} // namespace cellfx::terrain
