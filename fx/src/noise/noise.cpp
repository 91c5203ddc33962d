// cellfx — noise, one sample at a time: the bases, fractal sums and domain warp.
//
// Based on: Perlin 2002 (improved noise), Gustavson 2005 (simplex noise), FastNoise Lite
// (Peck 2020: hashed lattice, fractal bounding). The kernels are in noise_kernels.hpp; this file
// splits coordinates and runs them on one lane.
#include "fx/noise.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "fx/error.hpp"
#include "noise_lanes.hpp"

namespace cellfx::fx {
namespace noise_detail {
namespace {

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

float evaluate(NoiseBasis basis, std::uint32_t key, double x, double y) {
    return basis == NoiseBasis::perlin ? perlin2_at(key, x, y) : simplex2_at(key, x, y);
}
float evaluate(NoiseBasis basis, std::uint32_t key, double x, double y, double z) {
    return basis == NoiseBasis::perlin ? perlin3_at(key, x, y, z) : simplex3_at(key, x, y, z);
}
float evaluate(NoiseBasis basis, std::uint32_t key, double x, double y, double z, double w) {
    return basis == NoiseBasis::perlin ? perlin4_at(key, x, y, z, w) : simplex4_at(key, x, y, z, w);
}

// Σ over octaves of the plan, with the sample at coordinates·frequency (in double).
template <class... D> float fractal_sum(const FractalPlan& plan, D... coordinates) {
    float sum = 0.0f;
    for (int o = 0; o < plan.octaves; ++o) {
        const float n = evaluate(plan.basis, mix_seed(plan.seed, o), octave_coordinate(coordinates, plan, o)...);
        sum = accumulate(o, sum, shape(plan.type, n), plan.amplitude[o]);
    }
    return finish(sum);
}

// The last octave's frequency, computed as OctaveWalk does (inf when it overflows).
double last_frequency(const Fractal& fractal) {
    double f = fractal.frequency;
    for (int o = 1; o < fractal.octaves && o < kMaxOctaves; ++o) f *= fractal.lacunarity;
    return f;
}

// What check_fractal accepts, without building any message.
bool fractal_valid(const Fractal& fractal) {
    return (fractal.basis == NoiseBasis::perlin || fractal.basis == NoiseBasis::simplex) &&
           (fractal.type == FractalType::fbm || fractal.type == FractalType::ridged ||
            fractal.type == FractalType::turbulence) &&
           fractal.octaves >= 1 && fractal.octaves <= kMaxOctaves && std::isfinite(fractal.frequency) &&
           fractal.frequency > 0.0 && std::isfinite(fractal.lacunarity) && fractal.lacunarity > 0.0 &&
           std::isfinite(fractal.gain) && fractal.gain > 0.0f && std::isfinite(last_frequency(fractal));
}

} // namespace

void check_fractal(const Fractal& fractal, const char* where, const char* name) {
    if (fractal_valid(fractal)) return; // builds no strings
    const std::string at = std::string(where) + name + ".";
    if (fractal.basis != NoiseBasis::perlin && fractal.basis != NoiseBasis::simplex)
        throw Error(at + "basis: unknown value " + std::to_string(static_cast<int>(fractal.basis)));
    if (fractal.type != FractalType::fbm && fractal.type != FractalType::ridged &&
        fractal.type != FractalType::turbulence)
        throw Error(at + "type: unknown value " + std::to_string(static_cast<int>(fractal.type)));
    if (fractal.octaves < 1 || fractal.octaves > kMaxOctaves)
        throw Error(at + "octaves must be in [1, " + std::to_string(kMaxOctaves) + "] (got " +
                    std::to_string(fractal.octaves) + ")");
    if (!std::isfinite(fractal.frequency) || !(fractal.frequency > 0.0))
        throw Error(at + "frequency must be finite and > 0 (got " + number(fractal.frequency) + ")");
    if (!std::isfinite(fractal.lacunarity) || !(fractal.lacunarity > 0.0))
        throw Error(at + "lacunarity must be finite and > 0 (got " + number(fractal.lacunarity) + ")");
    if (!std::isfinite(fractal.gain) || !(fractal.gain > 0.0f))
        throw Error(at + "gain must be finite and > 0 (got " + number(fractal.gain) + ")");
    throw Error(at + "lacunarity: the last octave's frequency overflows (frequency " + number(fractal.frequency) +
                ", lacunarity " + number(fractal.lacunarity) + ", " + std::to_string(fractal.octaves) + " octaves)");
}

std::uint32_t warp_seed(std::uint32_t seed, int axis) {
    return seed ^ (0x68e31da4u + static_cast<std::uint32_t>(axis) * 0x6c8e9cf5u);
}

FractalPlan make_plan(const Fractal& fractal, std::uint32_t seed) {
    FractalPlan plan{};
    plan.basis = fractal.basis;
    plan.type = fractal.type;
    plan.octaves = fractal.octaves;
    plan.seed = seed;
    OctaveWalk walk(fractal);
    for (int o = 0; o < fractal.octaves; ++o, walk.next()) {
        plan.frequency[o] = walk.frequency;
        plan.amplitude[o] = walk.amplitude;
    }
    return plan;
}

void check_warp(const DomainWarp& warp, const char* where) {
    if (!std::isfinite(warp.amplitude))
        throw Error(std::string(where) + "DomainWarp.amplitude must be finite (got " + number(warp.amplitude) + ")");
    check_fractal(warp.fractal, where, "DomainWarp.fractal");
}

float perlin2_at(std::uint32_t key, double x, double y) {
    return perlin2<F1, U1>(key, perlin_axis(x, kPrimeX), perlin_axis(y, kPrimeY));
}
float perlin3_at(std::uint32_t key, double x, double y, double z) {
    return perlin3<F1, U1>(key, perlin_axis(x, kPrimeX), perlin_axis(y, kPrimeY), perlin_axis(z, kPrimeZ));
}
float perlin4_at(std::uint32_t key, double x, double y, double z, double w) {
    return perlin4<F1, U1>(key, perlin_axis(x, kPrimeX), perlin_axis(y, kPrimeY), perlin_axis(z, kPrimeZ),
                           perlin_axis(w, kPrimeW));
}
float simplex2_at(std::uint32_t key, double x, double y) {
    const double p[2] = {x, y};
    return simplex2<F1, U1>(key, simplex_sample<2, D1>(p, kF2, kG2));
}
float simplex3_at(std::uint32_t key, double x, double y, double z) {
    const double p[3] = {x, y, z};
    return simplex3<F1, U1>(key, simplex_sample<3, D1>(p, kF3, kG3));
}
float simplex4_at(std::uint32_t key, double x, double y, double z, double w) {
    const double p[4] = {x, y, z, w};
    return simplex4<F1, U1>(key, simplex_sample<4, D1>(p, kF4, kG4));
}

float fractal2_at(const FractalPlan& plan, double x, double y) { return fractal_sum(plan, x, y); }
float fractal3_at(const FractalPlan& plan, double x, double y, double z) { return fractal_sum(plan, x, y, z); }
float fractal4_at(const FractalPlan& plan, double x, double y, double z, double w) {
    return fractal_sum(plan, x, y, z, w);
}

} // namespace noise_detail

using namespace noise_detail;

Noise::Noise(std::uint32_t seed) noexcept : seed_(seed), key_(mix_seed(seed, 0)) {}

float Noise::perlin2(double x, double y) const noexcept { return lane_kernels().perlin2(key_, x, y); }
float Noise::perlin3(double x, double y, double z) const noexcept { return lane_kernels().perlin3(key_, x, y, z); }
float Noise::perlin4(double x, double y, double z, double w) const noexcept { return perlin4_at(key_, x, y, z, w); }
float Noise::simplex2(double x, double y) const noexcept { return simplex2_at(key_, x, y); }
float Noise::simplex3(double x, double y, double z) const noexcept { return simplex3_at(key_, x, y, z); }
float Noise::simplex4(double x, double y, double z, double w) const noexcept {
    return simplex4_at(key_, x, y, z, w);
}

float Noise::fractal2(const Fractal& fractal, double x, double y) const {
    if (!fractal_valid(fractal)) check_fractal(fractal, "fx::Noise::fractal2: ", "Fractal"); // throws
    return lane_kernels().fractal2(fractal, seed_, x, y);
}
float Noise::fractal3(const Fractal& fractal, double x, double y, double z) const {
    if (!fractal_valid(fractal)) check_fractal(fractal, "fx::Noise::fractal3: ", "Fractal"); // throws
    return lane_kernels().fractal3(fractal, seed_, x, y, z);
}
float Noise::fractal4(const Fractal& fractal, double x, double y, double z, double w) const {
    if (!fractal_valid(fractal)) check_fractal(fractal, "fx::Noise::fractal4: ", "Fractal"); // throws
    return lane_kernels().fractal4(fractal, seed_, x, y, z, w);
}

glm::dvec2 Noise::warp2(const DomainWarp& warp, glm::dvec2 p) const {
    check_warp(warp, "fx::Noise::warp2: ");
    glm::dvec2 out = p;
    for (int a = 0; a < 2; ++a) {
        const Noise axis(warp_seed(seed_, a));
        out[a] = p[a] + warp.amplitude * static_cast<double>(axis.fractal2(warp.fractal, p.x, p.y));
    }
    return out;
}

glm::dvec3 Noise::warp3(const DomainWarp& warp, glm::dvec3 p) const {
    check_warp(warp, "fx::Noise::warp3: ");
    glm::dvec3 out = p;
    for (int a = 0; a < 3; ++a) {
        const Noise axis(warp_seed(seed_, a));
        out[a] = p[a] + warp.amplitude * static_cast<double>(axis.fractal3(warp.fractal, p.x, p.y, p.z));
    }
    return out;
}

} // namespace cellfx::fx
