// cellfx — seedable gradient noise: improved Perlin and simplex noise in 2-D, 3-D and 4-D,
// fractal sums (fBm, ridged, turbulence), domain warp, and batch fills of grids and point lists.
//
// Based on: Perlin 2002, "Improving Noise"; Gustavson 2005, "Simplex noise demystified"; the
// hashed lattice and fractal bounding of FastNoise Lite (Peck 2020). Details in docs/noise.md.
//
// Example — a height field, a fog density slice and an animated flame density:
//
//     const fx::Noise noise(42);                                  // a seed fixes the whole field
//     fx::Fractal hills;                                          // plain Perlin until changed:
//     hills.octaves = 6;                                          //   6 octaves of fBm,
//     hills.frequency = 1.0 / 800.0;                              //   features ~800 m across
//     std::vector<float> height(512 * 512);
//     fx::fill_grid2(noise, hills, {{x0, y0}, {4.0, 4.0}, 512, 512}, height.data()); // [-1, 1]
//
//     float fog = noise.fractal2(hills, x, y);                    // one sample, same value
//     float flame = noise.simplex4(x, y, z, 0.8 * seconds);       // time as the 4th axis
//
// Ranges (checked by tests over millions of samples, and by an analytic bound):
//   perlin2/3/4, simplex2/3/4: [-1, 1], 0 at the lattice points (Perlin: integer coordinates;
//     simplex: the skewed lattice's vertices). Each is scaled so its supremum over every
//     gradient arrangement is 1 − 2⁻¹⁶ (perlin4 stays within about ±0.74 in practice); the
//     standard deviation of samples is 0.19 (perlin4) to 0.54 (simplex2), per basis in
//     docs/noise.md.
//   fractal fbm and ridged: [-1, 1]; turbulence: [0, 1].
// Continuity: every function is continuous with a bounded slope (Perlin ≲ 3.1, simplex ≲ 7.4
//   output units per input unit at frequency 1); Perlin is C², simplex C³.
// Determinism: a value depends only on the seed, the basis, the fractal settings and the
//   coordinates: the same on every platform with IEEE float/double (SSE or NEON, not x87) and
//   the default floating-point environment, for every batch size and path. Hashing is unsigned
//   32-bit arithmetic; no permutation or gradient tables, no std::hash, no randomness. Batch fills give the
//   scalar results exactly.
// Far from the origin: coordinates are doubles; the integer cell and the offset in it are split
//   in double before anything is narrowed to float, so noise at x = 1e7 is as smooth as at 1. The
//   lattice repeats every 2³² cells (the hash uses the cell's low 32 bits). Coordinates (times
//   frequency) beyond ±2⁴⁸ are clamped to it, NaN is treated as −2⁴⁸: results stay finite.
// Threads: everything here is const and allocation-free except the fill_* scratch; any number of
//   threads may share one Noise.
// Speed: one call per sample runs on the same run-time chosen kernels (with AVX2: a cell's
//   corners, or a fractal's octaves, in vector lanes), about as fast as FastNoise Lite or faster.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace cellfx::fx {

enum class NoiseBasis { perlin, simplex };

// How octaves combine. Each octave o samples the basis at frequency·lacunarityᵒ with amplitude
// gainᵒ (normalised so the amplitudes sum to 1) and its own seed.
enum class FractalType {
    fbm,        // Σ a·n: range [-1, 1]
    ridged,     // Σ a·(1 − 2|n|): sharp crests (value 1) where the basis crosses 0; [-1, 1]
    turbulence, // Σ a·|n|: billows with creases at 0; [0, 1]
};

// Fractal settings. The defaults are the plain basis: 1 octave of fBm at frequency 1 gives
// exactly perlin2/3/4 (or simplex2/3/4). Invalid settings make the functions that take them
// throw fx::Error naming the field.
struct Fractal {
    NoiseBasis basis = NoiseBasis::perlin;
    FractalType type = FractalType::fbm;
    int octaves = 1;         // 1..16
    double frequency = 1.0;  // of the first octave, in cycles per input unit; finite, > 0
    double lacunarity = 2.0; // frequency ratio of successive octaves; finite, > 0
    float gain = 0.5f;       // amplitude ratio of successive octaves; finite, > 0
};

// Domain warp: p + amplitude·(f₀(p), f₁(p)[, f₂(p)]) with f the fractal below, evaluated with a
// different seed (derived from the Noise's) for each axis. With fbm each axis moves by at most
// `amplitude`. Warp a point, then sample noise there, for swirls and folds.
struct DomainWarp {
    Fractal fractal{NoiseBasis::simplex};
    double amplitude = 1.0; // input units; finite
};

// Regular grids of sample positions. Sample (i, j, ...) is at origin + step·(i, j, ...), each
// coordinate computed in double as origin.x + step.x·i, and is stored at
// out[i + nx·(j + ny·(k + nz·l))] (x fastest).
struct Grid2 {
    glm::dvec2 origin{0.0};
    glm::dvec2 step{1.0};
    std::size_t nx = 0, ny = 0;
};
struct Grid3 {
    glm::dvec3 origin{0.0};
    glm::dvec3 step{1.0};
    std::size_t nx = 0, ny = 0, nz = 0;
};
struct Grid4 {
    glm::dvec4 origin{0.0};
    glm::dvec4 step{1.0};
    std::size_t nx = 0, ny = 0, nz = 0, nw = 0; // nw = 1: one 3-D slice at time origin.w
};

// A noise field: a seed and nothing else (a value type; cheap to copy). Different seeds give
// unrelated fields.
class Noise {
public:
    explicit Noise(std::uint32_t seed = 0) noexcept;
    std::uint32_t seed() const noexcept { return seed_; }

    // The bases at frequency 1 (one lattice cell per input unit); all in [-1, 1].
    float perlin2(double x, double y) const noexcept;
    float perlin3(double x, double y, double z) const noexcept;
    float perlin4(double x, double y, double z, double w) const noexcept;
    float simplex2(double x, double y) const noexcept;
    float simplex3(double x, double y, double z) const noexcept;
    float simplex4(double x, double y, double z, double w) const noexcept;

    // Fractal sums of the fractal's basis (fBm/ridged [-1, 1], turbulence [0, 1]).
    float fractal2(const Fractal& fractal, double x, double y) const;
    float fractal3(const Fractal& fractal, double x, double y, double z) const;
    float fractal4(const Fractal& fractal, double x, double y, double z, double w) const;

    // The point displaced by the warp (see DomainWarp).
    glm::dvec2 warp2(const DomainWarp& warp, glm::dvec2 p) const;
    glm::dvec3 warp3(const DomainWarp& warp, glm::dvec3 p) const;

private:
    std::uint32_t seed_;
    std::uint32_t key_; // the seed mixed, as the lattice hash uses it
};

// Batch evaluation — the fast path: vector lanes (SSE2, or AVX2 where the CPU has it, chosen
// at run time; same bits either way); grids 4-10× the rate of one call per sample, point lists
// about 2.5× (docs/noise.md, "Speed"). Each fills
// `out` (caller-owned, room for every sample) with exactly what noise.fractalN(fractal, ·) gives
// at each sample position; use a default Fractal for the plain basis. Empty grids or lists do
// nothing. Throws fx::Error for invalid fractal settings, a null pointer with samples to write,
// or a grid whose sample count overflows std::size_t.
void fill_grid2(const Noise& noise, const Fractal& fractal, const Grid2& grid, float* out);
void fill_grid3(const Noise& noise, const Fractal& fractal, const Grid3& grid, float* out);
void fill_grid4(const Noise& noise, const Fractal& fractal, const Grid4& grid, float* out);
void fill_points2(const Noise& noise, const Fractal& fractal, const glm::dvec2* points, std::size_t count, float* out);
void fill_points3(const Noise& noise, const Fractal& fractal, const glm::dvec3* points, std::size_t count, float* out);
void fill_points4(const Noise& noise, const Fractal& fractal, const glm::dvec4* points, std::size_t count, float* out);

// Batch domain warp, in place: points[i] = noise.warpN(warp, points[i]) exactly.
void warp_points2(const Noise& noise, const DomainWarp& warp, glm::dvec2* points, std::size_t count);
void warp_points3(const Noise& noise, const DomainWarp& warp, glm::dvec3* points, std::size_t count);

} // namespace cellfx::fx
