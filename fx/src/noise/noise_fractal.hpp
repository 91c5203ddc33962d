// cellfx — pieces shared by the scalar (noise.cpp) and lane (noise_lanes_impl.hpp) evaluation:
// the validated fractal plan, one scalar sample of each basis, and the octave arithmetic.
// Both must go through these so that a batch gives the scalar result bit for bit.
//
// Based on: FastNoise Lite (Peck 2020): fractal bounding (amplitudes normalised to sum to 1),
// a new seed per octave, ridged as 1 − 2|n|.
#pragma once

#include <cstdint>

#include "fx/noise.hpp"
#include "noise_kernels.hpp"

namespace cellfx::fx::noise_detail {

constexpr int kMaxOctaves = 16;

// A validated Fractal with each octave's frequency, amplitude and hash key (trivial: no inline
// member functions for the per-instruction-set builds to duplicate).
struct FractalPlan {
    NoiseBasis basis;
    FractalType type;
    int octaves;
    double frequency[kMaxOctaves];
    double offset[kMaxOctaves]; // added to every coordinate of octaves ≥ 1
    float amplitude[kMaxOctaves];
    std::uint32_t key[kMaxOctaves];
};

// Throw fx::Error naming the caller (`where`, "fx::fill_grid3: "), the struct (`name`,
// "Fractal") and the bad field. Cheap when the settings are good.
void check_fractal(const Fractal& fractal, const char* where, const char* name);
void check_warp(const DomainWarp& warp, const char* where);
// The plan of settings that passed check_fractal.
FractalPlan make_plan(const Fractal& fractal, std::uint32_t seed);

// The seed of warp axis `axis`'s noise.
std::uint32_t warp_seed(std::uint32_t seed, int axis);

// Octaves ≥ 1 are shifted by o·(golden ratio − 1) cells along every axis, so that with an
// integer lacunarity their lattices (where the basis is 0) never line up with the first
// octave's: otherwise fBm is 0 and ridged is 1 on a regular grid of points.
constexpr double kOctaveOffset = 0.6180339887498949;

// One sample of a basis at frequency 1, given the octave's key.
float perlin2_at(std::uint32_t key, double x, double y);
float perlin3_at(std::uint32_t key, double x, double y, double z);
float perlin4_at(std::uint32_t key, double x, double y, double z, double w);
float simplex2_at(std::uint32_t key, double x, double y);
float simplex3_at(std::uint32_t key, double x, double y, double z);
float simplex4_at(std::uint32_t key, double x, double y, double z, double w);

inline namespace FX_NOISE_ISA { // inline functions: one copy per instruction set (noise_kernels.hpp)

// The coordinate octave o samples. Octave 0 is exactly coordinate·frequency, so one octave of
// fBm is the basis itself.
template <class D> inline D octave_coordinate(D x, const FractalPlan& plan, int o) {
    const D q = x * plan.frequency[o];
    return o == 0 ? q : q + plan.offset[o];
}

// |n| with the sign bit cleared (same in every lane type).
template <class F> inline F abs_value(F n) { return as_f(as_u(n) & 0x7fffffffu); }

// An octave's value before weighting.
template <class F> inline F shape(FractalType type, F n) {
    switch (type) {
    case FractalType::ridged:
        return abs_value(n) * -2.0f + 1.0f;
    case FractalType::turbulence:
        return abs_value(n);
    case FractalType::fbm:
        break;
    }
    return n;
}

// The running sum after octave o: the first octave starts it (no 0 + ·, which would turn −0
// into +0), the others add to it.
template <class F> inline F accumulate(int octave, F sum, F shaped, float amplitude) {
    return octave == 0 ? shaped * amplitude : sum + shaped * amplitude;
}

// Clamp the finished sum to the documented range; it only ever moves values that float rounding
// of the amplitudes pushed a few ulps past ±1.
template <class F> inline F finish(F sum) {
    const F one = splat_f(sum, 1.0f), minus_one = splat_f(sum, -1.0f);
    sum = select(mask_gt(sum, one), one, sum);
    return select(mask_gt(minus_one, sum), minus_one, sum);
}

} // namespace FX_NOISE_ISA
} // namespace cellfx::fx::noise_detail
