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

// A validated Fractal with each octave's frequency and amplitude (OctaveWalk), and the seed of
// the octaves' hash keys (mix_seed(seed, o)); the entries past `octaves` are 0. Trivial: no
// inline member functions for the per-instruction-set builds to duplicate.
struct FractalPlan {
    NoiseBasis basis;
    FractalType type;
    int octaves;
    std::uint32_t seed;
    double frequency[kMaxOctaves];
    float amplitude[kMaxOctaves];
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
// octave's: otherwise fBm is 0 and ridged is 1 on a regular grid of points. Octave 0 is
// "shifted" by −0.0, which changes no value (x + −0.0 is x, −0 included), so that every octave
// runs the same operations.
constexpr double kOctaveOffset = 0.6180339887498949;
constexpr double kOctaveOffsets[kMaxOctaves] = {
    -0.0,               1 * kOctaveOffset,  2 * kOctaveOffset,  3 * kOctaveOffset,
    4 * kOctaveOffset,  5 * kOctaveOffset,  6 * kOctaveOffset,  7 * kOctaveOffset,
    8 * kOctaveOffset,  9 * kOctaveOffset,  10 * kOctaveOffset, 11 * kOctaveOffset,
    12 * kOctaveOffset, 13 * kOctaveOffset, 14 * kOctaveOffset, 15 * kOctaveOffset,
};

// One sample of a basis at frequency 1, given the octave's key.
float perlin2_at(std::uint32_t key, double x, double y);
float perlin3_at(std::uint32_t key, double x, double y, double z);
float perlin4_at(std::uint32_t key, double x, double y, double z, double w);
float simplex2_at(std::uint32_t key, double x, double y);
float simplex3_at(std::uint32_t key, double x, double y, double z);
float simplex4_at(std::uint32_t key, double x, double y, double z, double w);

// One fractal sample, one octave after another with the functions above: the definition the
// lane kernels (LaneKernels::fractalN) are tested against.
float fractal2_at(const FractalPlan& plan, double x, double y);
float fractal3_at(const FractalPlan& plan, double x, double y, double z);
float fractal4_at(const FractalPlan& plan, double x, double y, double z, double w);

inline namespace FX_NOISE_ISA { // inline functions: one copy per instruction set (noise_kernels.hpp)

// The octaves of a valid Fractal in order: each one's frequency and amplitude, computed with
// the same operations wherever they are needed (make_plan, one-sample kernels). Bounding as
// FastNoise Lite: the amplitudes 1, g, g², ... scaled to sum to 1, in float.
struct OctaveWalk {
    double frequency;
    float amplitude;
    double lacunarity;
    float gain;

    explicit OctaveWalk(const Fractal& fractal)
        : frequency(fractal.frequency), lacunarity(fractal.lacunarity), gain(fractal.gain) {
        float total = 1.0f, a = fractal.gain;
        for (int o = 1; o < fractal.octaves; ++o) {
            total += a;
            a *= fractal.gain;
        }
        amplitude = 1.0f / total;
    }
    void next() {
        frequency *= lacunarity;
        amplitude *= gain;
    }
};

// The coordinate octave o samples. Octave 0 is exactly coordinate·frequency, so one octave of
// fBm is the basis itself.
template <class D> inline D octave_coordinate(D x, double frequency, int o) {
    return x * frequency + kOctaveOffsets[o];
}
template <class D> inline D octave_coordinate(D x, const FractalPlan& plan, int o) {
    return octave_coordinate(x, plan.frequency[o], o);
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
