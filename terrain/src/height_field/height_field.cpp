#include "terrain/height_field.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"
#include "fx/resource_limits.hpp"

namespace cellfx::terrain {

namespace {

constexpr int kMaxSize = 16385; // 2^14 + 1: 268 M samples is already 1 GiB of floats

std::string number(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

} // namespace

bool is_lod_size(int size) {
    if (size < 3 || size > kMaxSize) return false;
    const int n = size - 1;
    return (n & (n - 1)) == 0;
}

void check_height_field(int size, double spacing, glm::dvec2 origin, double lowest, double highest,
                        const std::string& what) {
    fx::check_limit(fx::Limit::HeightSamples, std::uint64_t(size) * std::uint64_t(size),
                    what + " (" + std::to_string(size) + "x" + std::to_string(size) + ")");
    const double reach = std::max(std::abs(origin.x), std::abs(origin.y)) + spacing * (size - 1);
    if (!(reach <= fx::kMaxCoordinate))
        throw fx::Error(what + ": the grid reaches " + number(reach) + " (origin + spacing × " + std::to_string(size - 1) +
                        "), beyond ±1e18, the coordinates cellfx renders");
    if (!(std::max(std::abs(lowest), std::abs(highest)) <= fx::kMaxCoordinate))
        throw fx::Error(what + ": heights reach " + number(std::abs(lowest) > std::abs(highest) ? lowest : highest) +
                        ", beyond ±1e18, the coordinates cellfx renders (check vertical_scale and vertical_offset)");
}

int lod_size_at_least(int size) {
    int s = 3;
    while (s < size) s = 2 * s - 1;
    return s;
}

double HeightField::sample(double px, double py) const {
    const double u = std::clamp((px - origin.x) / spacing, 0.0, double(size - 1));
    const double v = std::clamp((py - origin.y) / spacing, 0.0, double(size - 1));
    const int i = std::min(int(u), size - 2), j = std::min(int(v), size - 2);
    const double fu = u - i, fv = v - j;
    const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
    return (1.0 - fv) * ((1.0 - fu) * h00 + fu * h10) + fv * ((1.0 - fu) * h01 + fu * h11);
}

float HeightField::min_height() const {
    return heights.empty() ? 0.0f : *std::min_element(heights.begin(), heights.end());
}

float HeightField::max_height() const {
    return heights.empty() ? 0.0f : *std::max_element(heights.begin(), heights.end());
}

HeightField make_height_field(int size, double spacing, const HeightGenerator& generator, glm::dvec2 origin) {
    if (!is_lod_size(size))
        throw fx::Error("height field: size " + std::to_string(size) +
                        " is not 2^n + 1 between 3 and 16385 (e.g. 257 or 1025)");
    if (!(spacing > 0.0) || !std::isfinite(spacing))
        throw fx::Error("height field: spacing " + number(spacing) + " is not a finite positive number");
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y)) throw fx::Error("height field: origin is not finite");
    if (!generator) throw fx::Error("height field: no generator given");
    check_height_field(size, spacing, origin, 0.0, 0.0, "height field");
    HeightField field;
    field.size = size;
    field.spacing = spacing;
    field.origin = origin;
    field.heights.resize(std::size_t(size) * std::size_t(size));
    for (int j = 0; j < size; ++j) {
        for (int i = 0; i < size; ++i) {
            const double x = field.x(i), y = field.y(j);
            const double h = generator(x, y);
            if (!std::isfinite(h) || std::abs(h) > 3.0e38)
                throw fx::Error("height field: the generator gave " + number(h) + " at sample (" + std::to_string(i) +
                                ", " + std::to_string(j) + "), position (" + number(x) + ", " + number(y) + ")");
            field.at(i, j) = float(h);
        }
    }
    return field;
}

HeightField make_height_field_like(const HeightField& like, const HeightGenerator& generator) {
    return make_height_field(like.size, like.spacing, generator, like.origin);
}

void require_same_grid(const HeightField& a, const HeightField& b, const std::string& what) {
    if (a.size != b.size)
        throw fx::Error(what + ": " + std::to_string(b.size) + "x" + std::to_string(b.size) +
                        " samples, but the terrain has " + std::to_string(a.size) + "x" + std::to_string(a.size));
    if (a.spacing != b.spacing)
        throw fx::Error(what + ": spacing " + number(b.spacing) + ", but the terrain's is " + number(a.spacing));
    if (a.origin != b.origin) throw fx::Error(what + ": its origin differs from the terrain's");
}

} // namespace cellfx::terrain
