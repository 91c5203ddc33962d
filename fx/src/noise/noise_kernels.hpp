// cellfx — the noise kernels shared by scalar and batch evaluation (private to fx/src/noise).
//
// Based on: Perlin 2002, "Improving Noise" (SIGGRAPH 2002): the quintic fade 6t⁵ − 15t⁴ + 10t³
// and the 12 cube-edge gradients padded to 16; Gustavson 2005, "Simplex noise
// demystified": the skewed simplex lattice, the rank ordering of 3-D and 4-D, the radial kernel
// (r² − d²)⁴; the hashed lattice of FastNoise Lite (Peck 2020, MIT licence): a prime per axis,
// xor, one multiply, in place of Perlin's permutation table.
//
// Why it looks like this:
// - Every kernel is a template over its lanes: `float` / `std::uint32_t` for one sample, or GNU
//   vector types for kLanes samples. Both run the same sequence of IEEE operations (no FMA: the
//   noise sources are compiled with -ffp-contract=off), so a batch gives the scalar result bit for
//   bit. Gradients are picked with bit operations, not tables, so the vector code needs no gathers.
// - Integer arithmetic is unsigned 32-bit and wraps (no signed overflow anywhere). The lattice is
//   therefore periodic with period 2³² cells along each axis.
// - Coordinates arrive in double. The integer cell and the offset inside it are split in double
//   (exactly: x − ⌊x⌋ has no rounding error for |x| < 2⁵²) and only the offset, a number in
//   [0, 1], is narrowed to float. Far from the origin the kernels see the same small numbers as
//   near it; the cell's low 32 bits feed the hash.
#pragma once

#include <cfloat>
#include <cstdint>
#include <cstring>
#if defined(__SSE4_1__) || defined(__AVX__)
#include <immintrin.h>
#endif

// The lane kernels are compiled once per instruction set (noise_lanes_impl.hpp); each build puts every
// inline function of these headers in its own namespace, so the linker can never hand an AVX2
// copy of one to the baseline code.
#ifndef FX_NOISE_ISA
#define FX_NOISE_ISA baseline
#endif
#ifndef FX_NOISE_LANES
#define FX_NOISE_LANES 4 // SSE2 / NEON width; 8 lanes without AVX spill registers and run slower
#endif

namespace cellfx::fx::noise_detail {
inline namespace FX_NOISE_ISA {

static_assert(FLT_EVAL_METHOD == 0, "noise needs IEEE single/double arithmetic without excess precision (SSE, not x87)");

// --- constants ------------------------------------------------------------------------------

// Hash: key ^ x·kPrimeX ^ y·kPrimeY ^ ... then one multiply; the top bits choose the gradient.
constexpr std::uint32_t kPrimeX = 501125321u;  // FastNoise Lite's primes
constexpr std::uint32_t kPrimeY = 1136930381u;
constexpr std::uint32_t kPrimeZ = 1720413743u;
constexpr std::uint32_t kPrimeW = 1066037191u;
constexpr std::uint32_t kHashMultiplier = 0x27d4eb2du;

// Largest coordinate magnitude the split accepts (after frequency scaling); beyond it, and for
// NaN, coordinates are clamped. 2⁴⁸ keeps x + skew below 2⁵¹, where the rounding trick is exact.
constexpr double kMaxCoordinate = 281474976710656.0; // 2^48
constexpr double kRoundMagic = 6755399441055744.0;   // 1.5 · 2^52: x + this rounds x to an integer

// Output scales: 1 / (supremum of the unscaled kernel over every gradient assignment) times
// (1 − 2⁻¹⁶), so each basis stays inside [−1, 1] with room for float rounding. The suprema were
// found by maximising, over the cell, the sum of each corner's weight times its best gradient's
// dot product (tests/test_noise.cpp re-checks the bound on a dense grid). The suprema:
// perlin2 0.66081645, perlin3 1.0363538 (FastNoise Lite's 1/0.9649214 agrees),
// perlin4 1.5365823, simplex2 0.0099959915, simplex3 0.013007157, simplex4 0.015929221.
constexpr float kPerlin2Scale = 1.51325642f;
constexpr float kPerlin3Scale = 0.964906705f;
constexpr float kPerlin4Scale = 0.650785005f;
constexpr float kSimplex2Scale = 100.038574f;
constexpr float kSimplex3Scale = 76.8795769f;
constexpr float kSimplex4Scale = 62.7767492f;

// Simplex lattice skew (Gustavson 2005): F = (√(n+1) − 1)/n skews, G = (1 − 1/√(n+1))/n unskews.
constexpr double kF2 = 0.36602540378443864676;  // (√3 − 1)/2
constexpr double kG2 = 0.21132486540518711775;  // (3 − √3)/6
constexpr double kF3 = 1.0 / 3.0;
constexpr double kG3 = 1.0 / 6.0;
constexpr double kF4 = 0.30901699437494742410;  // (√5 − 1)/4
constexpr double kG4 = 0.13819660112501051518;  // (5 − √5)/20
constexpr float kG2f = static_cast<float>(kG2);
constexpr float kG3f = static_cast<float>(kG3);
constexpr float kG4f = static_cast<float>(kG4);
// Squared kernel radius. 0.5 keeps every corner's kernel inside the simplices around it, so the
// noise is continuous (Gustavson's 0.6 in 3-D/4-D leaves small jumps at simplex faces).
constexpr float kSimplexRadius2 = 0.5f;

constexpr float kCos22 = 0.923879532511286756f; // cos 22.5°
constexpr float kSin22 = 0.382683432365089772f; // sin 22.5°

// --- lanes ----------------------------------------------------------------------------------
// Scalar lanes are float / uint32 (and double / uint64 for coordinates); a mask is 0 or all ones.
// Vector lanes behave the same, element by element. The double lanes exist only in the batch
// file (FX_NOISE_BATCH), the one place that needs them.

using F1 = float;
using U1 = std::uint32_t;
using D1 = double;
using Q1 = std::uint64_t;

#if defined(__GNUC__) && !defined(FX_NOISE_NO_VECTOR) // FX_NOISE_NO_VECTOR: try the one-lane path
#define FX_NOISE_HAVE_VECTOR 1
constexpr int kLanes = FX_NOISE_LANES;
typedef float VecF __attribute__((vector_size(4 * kLanes)));
typedef std::uint32_t VecU __attribute__((vector_size(4 * kLanes)));
#else
#define FX_NOISE_HAVE_VECTOR 0
constexpr int kLanes = 1;
using VecF = F1;
using VecU = U1;
#endif

inline U1 as_u(F1 f) {
    U1 u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}
inline F1 as_f(U1 u) {
    F1 f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}
inline Q1 as_q(D1 d) {
    Q1 q;
    std::memcpy(&q, &d, sizeof q);
    return q;
}
inline D1 as_d(Q1 q) {
    D1 d;
    std::memcpy(&d, &q, sizeof d);
    return d;
}
// (0 − bool rather than ?: so that the compiler does not branch on random hash bits)
inline U1 mask_eq(U1 a, U1 b) { return 0u - static_cast<U1>(a == b); }
inline U1 mask_gt(F1 a, F1 b) { return 0u - static_cast<U1>(a > b); }
inline U1 mask_ge(F1 a, F1 b) { return 0u - static_cast<U1>(a >= b); }
inline Q1 mask_gt(D1 a, D1 b) { return Q1(0) - static_cast<Q1>(a > b); }
inline F1 splat_f(F1, float v) { return v; }
inline U1 splat_u(U1, std::uint32_t v) { return v; }
inline D1 splat_d(D1, double v) { return v; }
inline F1 narrow(D1 d) { return static_cast<float>(d); } // round to nearest
inline U1 low32(Q1 q) { return static_cast<U1>(q); }

// The float and uint32 lanes that go with double lanes D.
template <class D> struct LanesOf {
    using F = F1;
    using U = U1;
};

#if FX_NOISE_HAVE_VECTOR
inline VecU as_u(VecF f) { return (VecU)f; }
inline VecF as_f(VecU u) { return (VecF)u; }
inline VecU mask_eq(VecU a, VecU b) { return (VecU)(a == b); }
inline VecU mask_gt(VecF a, VecF b) { return (VecU)(a > b); }
inline VecU mask_ge(VecF a, VecF b) { return (VecU)(a >= b); }
// v in every lane: v − (+0) is v for every v, −0 included (0 + v would turn −0 into +0).
inline VecF splat_f(VecF, float v) { return v - VecF{}; }
inline VecU splat_u(VecU, std::uint32_t v) { return VecU{} + v; }

inline VecF load_f(const float* p) {
    VecF v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline VecU load_u(const std::uint32_t* p) {
    VecU v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline void store_f(float* p, VecF v) { std::memcpy(p, &v, sizeof v); }

#if defined(FX_NOISE_BATCH)
// Double lanes as two halves of kLanes/2: without AVX, GCC turns 32-byte double compares into
// scalar ones, while 16-byte vectors map to single SSE2 / NEON instructions (and 32-byte ones to
// single AVX instructions in the AVX2 build).
typedef double VecD2 __attribute__((vector_size(4 * kLanes)));
typedef std::uint64_t VecQ2 __attribute__((vector_size(4 * kLanes)));
typedef double VecD4 __attribute__((vector_size(8 * kLanes))); // only inside narrow/low32
typedef std::uint64_t VecQ4 __attribute__((vector_size(8 * kLanes)));
struct VecD {
    VecD2 lo, hi;
};
struct VecQ {
    VecQ2 lo, hi;
};
template <> struct LanesOf<VecD> {
    using F = VecF;
    using U = VecU;
};
inline VecD operator+(VecD a, VecD b) { return {a.lo + b.lo, a.hi + b.hi}; }
inline VecD operator-(VecD a, VecD b) { return {a.lo - b.lo, a.hi - b.hi}; }
inline VecD operator*(VecD a, VecD b) { return {a.lo * b.lo, a.hi * b.hi}; }
inline VecD operator+(VecD a, double b) { return {a.lo + b, a.hi + b}; }
inline VecD operator-(VecD a, double b) { return {a.lo - b, a.hi - b}; }
inline VecD operator*(VecD a, double b) { return {a.lo * b, a.hi * b}; }
inline VecQ operator&(VecQ a, VecQ b) { return {a.lo & b.lo, a.hi & b.hi}; }
inline VecQ operator|(VecQ a, VecQ b) { return {a.lo | b.lo, a.hi | b.hi}; }
inline VecQ operator~(VecQ a) { return {~a.lo, ~a.hi}; }
inline VecQ as_q(VecD d) { return {(VecQ2)d.lo, (VecQ2)d.hi}; }
inline VecD as_d(VecQ q) { return {(VecD2)q.lo, (VecD2)q.hi}; }
inline VecQ mask_gt(VecD a, VecD b) { return {(VecQ2)(a.lo > b.lo), (VecQ2)(a.hi > b.hi)}; }
inline VecD splat_d(VecD, double v) { return {v - VecD2{}, v - VecD2{}}; } // as splat_f
inline VecF narrow(VecD d) { // round to nearest, per lane
    VecD4 all;
    std::memcpy(&all, &d, sizeof all);
    return __builtin_convertvector(all, VecF);
}
inline VecU low32(VecQ q) { // truncation, per lane
#if FX_NOISE_LANES == 8 && defined(__AVX2__)
    // two shuffles (shufps per 128-bit lane, then vpermpd) where the conversion below takes five
    const __m256 evens = _mm256_shuffle_ps((__m256)q.lo, (__m256)q.hi, _MM_SHUFFLE(2, 0, 2, 0));
    return (VecU)_mm256_permute4x64_pd((__m256d)evens, _MM_SHUFFLE(3, 1, 2, 0));
#else
    VecQ4 all;
    std::memcpy(&all, &q, sizeof all);
    return __builtin_convertvector(all, VecU);
#endif
}
inline VecD load_d(const double* p) { // per half: one wide load each, no store-forwarding stall
    VecD v;
    std::memcpy(&v.lo, p, sizeof v.lo);
    std::memcpy(&v.hi, p + kLanes / 2, sizeof v.hi);
    return v;
}
#endif
#endif

// Bit `b` of h as a mask for select().
template <class U> inline U bit_mask(U h, int b) { return 0u - ((h >> b) & 1u); }
// m ? a : b, bitwise.
template <class F, class U> inline F select(U m, F a, F b) { return as_f((m & as_u(a)) | (~m & as_u(b))); }
template <class D, class Q> inline D select_d(Q m, D a, D b) { return as_d((m & as_q(a)) | (~m & as_q(b))); }
// v with its sign flipped where bit `b` of h is set.
template <class F, class U> inline F flip(F v, U h, int b) { return as_f(as_u(v) ^ ((h << (31 - b)) & 0x80000000u)); }
// 1.0f where the mask is set, else 0.0f.
template <class F, class U> inline F one_if(U m) { return as_f(m & 0x3f800000u); }

#if FX_NOISE_HAVE_VECTOR && (FX_NOISE_LANES == 8 ? defined(__AVX__) : FX_NOISE_LANES == 4 && defined(__SSE4_1__))
#define FX_NOISE_X86_BLEND 1
// x86 with blend instructions (SSE4.1 for 4 lanes, AVX for 8): a select is one blendv, which
// reads only the sign bit of each mask lane, so a hash bit becomes a mask with one shift, and the
// double lanes clamp with maxpd/minpd and floor with roundpd. Same values as the generic code.
inline VecU bit_mask(VecU h, int b) { return h << (31 - b); } // for select only: bit b in the sign
#if FX_NOISE_LANES == 8
inline VecF select(VecU m, VecF a, VecF b) { return (VecF)_mm256_blendv_ps((__m256)b, (__m256)a, (__m256)m); }
#else
inline VecF select(VecU m, VecF a, VecF b) { return (VecF)_mm_blendv_ps((__m128)b, (__m128)a, (__m128)m); }
#endif
#endif

// --- hash and gradients ---------------------------------------------------------------------

// The lattice hash; its top bits pick a gradient (the multiply mixes every input bit upwards).
template <class U> inline U hash(U v) { return v * kHashMultiplier; }

// 2-D: 8 unit gradients at 22.5° + k·45° (none along an axis or a diagonal, which would leave
// visible lattice lines): (±cos 22.5°, ±sin 22.5°) and (±sin 22.5°, ±cos 22.5°). h = 4 hash
// bits: bit 2 swaps the components, bits 0 and 1 are the signs; each gradient twice.
// (The bits of h are read in place, as bits 28.. of the hash: one shift fewer per corner.)
template <class F, class U> inline F grad2(U hashed, F x, F y) {
    const U swap = bit_mask(hashed, 30);
    const F u = select(swap, y, x), v = select(swap, x, y);
    return flip(u, hashed, 28) * kCos22 + flip(v, hashed, 29) * kSin22;
}

// 3-D: Perlin 2002's 12 cube-edge gradients (length √2) padded to 16 with (1,1,0), (−1,1,0),
// (0,−1,1), (0,−1,−1); h = 4 hash bits, exactly Perlin's grad(): u = h<8 ? x : y,
// v = h<4 ? y : (h==12||h==14 ? x : z), signs from bits 0 and 1.
template <class F, class U> inline F grad3(U hashed, F x, F y, F z) {
    const U h = hashed >> 28;
    const F u = select(bit_mask(hashed, 31), y, x);
    const F v = select(mask_eq(h & 12u, splat_u(h, 0u)), y, select(mask_eq(h & 13u, splat_u(h, 12u)), x, z));
    return flip(u, hashed, 28) + flip(v, hashed, 29);
}
#if FX_NOISE_X86_BLEND
// The same choice with blends on hash bits, fewer instructions where a blend reads one bit
// (b31..b28 = h): v is z where b31 ≠ b30 (4 ≤ h < 12), else y where b31 is clear (h < 4), else
// x or z by b28 (12, 14 or 13, 15).
inline VecF grad3(VecU hashed, VecF x, VecF y, VecF z) {
    const VecU b28 = hashed << 3;
    const VecF u = select(hashed, y, x);
    const VecF v = select(hashed ^ (hashed << 1), z, select(hashed, select(b28, z, x), y));
    return as_f(as_u(u) ^ (b28 & 0x80000000u)) + flip(v, hashed, 29);
}
#endif

// 4-D: the 32 gradients with one zero and three ±1 components (length √3); h = 6 hash bits,
// bits 0–3 the signs, bits 4–5 the zero component; each gradient twice.
template <class F, class U> inline F grad4(U hashed, F x, F y, F z, F w) {
    const U h = hashed >> 26;
    const U zero = h >> 4;
    const F tx = as_f(as_u(flip(x, h, 0)) & ~mask_eq(zero, splat_u(h, 0u)));
    const F ty = as_f(as_u(flip(y, h, 1)) & ~mask_eq(zero, splat_u(h, 1u)));
    const F tz = as_f(as_u(flip(z, h, 2)) & ~mask_eq(zero, splat_u(h, 2u)));
    const F tw = as_f(as_u(flip(w, h, 3)) & ~mask_eq(zero, splat_u(h, 3u)));
    return ((tx + ty) + tz) + tw;
}

// --- improved Perlin noise (Perlin 2002) ----------------------------------------------------

template <class F> inline F fade(F t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
template <class F> inline F lerp(F a, F b, F t) { return a + t * (b - a); }

// One axis of a Perlin sample: the cell times the axis prime (mod 2³²), the offset in the
// cell (in [0, 1]) and its fade.
template <class F, class U> struct PerlinAxis {
    U cell;
    F t;
    F fade;
};

template <class F, class U>
inline F perlin2(U key, const PerlinAxis<F, U>& X, const PerlinAxis<F, U>& Y) {
    const U x1 = X.cell + kPrimeX, y1 = Y.cell + kPrimeY;
    const F tx1 = X.t - 1.0f, ty1 = Y.t - 1.0f;
    const U k0 = key ^ Y.cell, k1 = key ^ y1;
    const F n00 = grad2(hash(k0 ^ X.cell), X.t, Y.t);
    const F n10 = grad2(hash(k0 ^ x1), tx1, Y.t);
    const F n01 = grad2(hash(k1 ^ X.cell), X.t, ty1);
    const F n11 = grad2(hash(k1 ^ x1), tx1, ty1);
    return lerp(lerp(n00, n10, X.fade), lerp(n01, n11, X.fade), Y.fade) * kPerlin2Scale;
}

template <class F, class U>
inline F perlin3(U key, const PerlinAxis<F, U>& X, const PerlinAxis<F, U>& Y, const PerlinAxis<F, U>& Z) {
    const U x1 = X.cell + kPrimeX, y1 = Y.cell + kPrimeY, z1 = Z.cell + kPrimeZ;
    const F tx1 = X.t - 1.0f, ty1 = Y.t - 1.0f, tz1 = Z.t - 1.0f;
    const U k00 = key ^ Y.cell ^ Z.cell, k10 = key ^ y1 ^ Z.cell;
    const U k01 = key ^ Y.cell ^ z1, k11 = key ^ y1 ^ z1;
    const F n000 = grad3(hash(k00 ^ X.cell), X.t, Y.t, Z.t);
    const F n100 = grad3(hash(k00 ^ x1), tx1, Y.t, Z.t);
    const F n010 = grad3(hash(k10 ^ X.cell), X.t, ty1, Z.t);
    const F n110 = grad3(hash(k10 ^ x1), tx1, ty1, Z.t);
    const F n001 = grad3(hash(k01 ^ X.cell), X.t, Y.t, tz1);
    const F n101 = grad3(hash(k01 ^ x1), tx1, Y.t, tz1);
    const F n011 = grad3(hash(k11 ^ X.cell), X.t, ty1, tz1);
    const F n111 = grad3(hash(k11 ^ x1), tx1, ty1, tz1);
    const F y0 = lerp(lerp(n000, n100, X.fade), lerp(n010, n110, X.fade), Y.fade);
    const F y1v = lerp(lerp(n001, n101, X.fade), lerp(n011, n111, X.fade), Y.fade);
    return lerp(y0, y1v, Z.fade) * kPerlin3Scale;
}

// The 8 corners of one w slice of the 4-D cell, interpolated to a value at the sample's x, y, z.
template <class F, class U>
inline F perlin4_slice(U kw, F tw, const PerlinAxis<F, U>& X, const PerlinAxis<F, U>& Y, const PerlinAxis<F, U>& Z) {
    const U x1 = X.cell + kPrimeX, y1 = Y.cell + kPrimeY, z1 = Z.cell + kPrimeZ;
    const F tx1 = X.t - 1.0f, ty1 = Y.t - 1.0f, tz1 = Z.t - 1.0f;
    const U k00 = kw ^ Y.cell ^ Z.cell, k10 = kw ^ y1 ^ Z.cell;
    const U k01 = kw ^ Y.cell ^ z1, k11 = kw ^ y1 ^ z1;
    const F n000 = grad4(hash(k00 ^ X.cell), X.t, Y.t, Z.t, tw);
    const F n100 = grad4(hash(k00 ^ x1), tx1, Y.t, Z.t, tw);
    const F n010 = grad4(hash(k10 ^ X.cell), X.t, ty1, Z.t, tw);
    const F n110 = grad4(hash(k10 ^ x1), tx1, ty1, Z.t, tw);
    const F n001 = grad4(hash(k01 ^ X.cell), X.t, Y.t, tz1, tw);
    const F n101 = grad4(hash(k01 ^ x1), tx1, Y.t, tz1, tw);
    const F n011 = grad4(hash(k11 ^ X.cell), X.t, ty1, tz1, tw);
    const F n111 = grad4(hash(k11 ^ x1), tx1, ty1, tz1, tw);
    const F y0 = lerp(lerp(n000, n100, X.fade), lerp(n010, n110, X.fade), Y.fade);
    const F y1v = lerp(lerp(n001, n101, X.fade), lerp(n011, n111, X.fade), Y.fade);
    return lerp(y0, y1v, Z.fade);
}

template <class F, class U>
inline F perlin4(U key, const PerlinAxis<F, U>& X, const PerlinAxis<F, U>& Y, const PerlinAxis<F, U>& Z,
                 const PerlinAxis<F, U>& W) {
    const F w0 = perlin4_slice(key ^ W.cell, W.t, X, Y, Z);
    const F w1 = perlin4_slice(key ^ (W.cell + kPrimeW), W.t - 1.0f, X, Y, Z);
    return lerp(w0, w1, W.fade) * kPerlin4Scale;
}

// --- simplex noise (Gustavson 2005) ---------------------------------------------------------

// The contribution (r² − |d|²)⁴ (g · d) of one corner at offset d, 0 outside the radius.
template <class F> inline F falloff(F t) {
    const F c = select(mask_gt(t, splat_f(t, 0.0f)), t, splat_f(t, 0.0f));
    const F c2 = c * c;
    return c2 * c2;
}

// A simplex sample: the skewed cell's corner (per axis, times the axis prime) and the unskewed
// offset of the sample from it.
template <class F, class U, int N> struct SimplexSample {
    U cell[N];
    F d[N];
};

template <class F, class U> inline F simplex2(U key, const SimplexSample<F, U, 2>& s) {
    const F x0 = s.d[0], y0 = s.d[1];
    const U x_first = mask_gt(x0, y0); // the middle corner is (1,0) when x0 > y0, else (0,1)
    const F i1 = one_if<F>(x_first), j1 = one_if<F>(~x_first);
    const F x1 = x0 - i1 + kG2f, y1 = y0 - j1 + kG2f;
    const F x2 = x0 - 1.0f + 2.0f * kG2f, y2 = y0 - 1.0f + 2.0f * kG2f;
    const U cx1 = s.cell[0] + (x_first & kPrimeX), cy1 = s.cell[1] + (~x_first & kPrimeY);
    const U cx2 = s.cell[0] + kPrimeX, cy2 = s.cell[1] + kPrimeY;
    const F n0 = falloff(kSimplexRadius2 - x0 * x0 - y0 * y0) * grad2(hash(key ^ s.cell[0] ^ s.cell[1]), x0, y0);
    const F n1 = falloff(kSimplexRadius2 - x1 * x1 - y1 * y1) * grad2(hash(key ^ cx1 ^ cy1), x1, y1);
    const F n2 = falloff(kSimplexRadius2 - x2 * x2 - y2 * y2) * grad2(hash(key ^ cx2 ^ cy2), x2, y2);
    return ((n0 + n1) + n2) * kSimplex2Scale;
}

template <class F, class U> inline F simplex3(U key, const SimplexSample<F, U, 3>& s) {
    const F x0 = s.d[0], y0 = s.d[1], z0 = s.d[2];
    // Which of the six tetrahedra: the second corner steps along the largest offset, the third
    // along the two largest (a = x≥y, b = y≥z, c = x≥z; transitivity rules out the rest).
    const U a = mask_ge(x0, y0), b = mask_ge(y0, z0), c = mask_ge(x0, z0);
    const U i1 = a & c, j1 = ~a & b, k1 = ~b & ~c;
    const U i2 = a | c, j2 = ~a | b, k2 = ~b | ~c;
    const F x1 = x0 - one_if<F>(i1) + kG3f, y1 = y0 - one_if<F>(j1) + kG3f, z1 = z0 - one_if<F>(k1) + kG3f;
    const F x2 = x0 - one_if<F>(i2) + 2.0f * kG3f, y2 = y0 - one_if<F>(j2) + 2.0f * kG3f,
            z2 = z0 - one_if<F>(k2) + 2.0f * kG3f;
    const F x3 = x0 - 1.0f + 3.0f * kG3f, y3 = y0 - 1.0f + 3.0f * kG3f, z3 = z0 - 1.0f + 3.0f * kG3f;
    const U cx = s.cell[0], cy = s.cell[1], cz = s.cell[2];
    const U h0 = hash(key ^ cx ^ cy ^ cz);
    const U h1 = hash(key ^ (cx + (i1 & kPrimeX)) ^ (cy + (j1 & kPrimeY)) ^ (cz + (k1 & kPrimeZ)));
    const U h2 = hash(key ^ (cx + (i2 & kPrimeX)) ^ (cy + (j2 & kPrimeY)) ^ (cz + (k2 & kPrimeZ)));
    const U h3 = hash(key ^ (cx + kPrimeX) ^ (cy + kPrimeY) ^ (cz + kPrimeZ));
    const F n0 = falloff(kSimplexRadius2 - x0 * x0 - y0 * y0 - z0 * z0) * grad3(h0, x0, y0, z0);
    const F n1 = falloff(kSimplexRadius2 - x1 * x1 - y1 * y1 - z1 * z1) * grad3(h1, x1, y1, z1);
    const F n2 = falloff(kSimplexRadius2 - x2 * x2 - y2 * y2 - z2 * z2) * grad3(h2, x2, y2, z2);
    const F n3 = falloff(kSimplexRadius2 - x3 * x3 - y3 * y3 - z3 * z3) * grad3(h3, x3, y3, z3);
    return (((n0 + n1) + n2) + n3) * kSimplex3Scale;
}

template <class F, class U> inline F simplex4(U key, const SimplexSample<F, U, 4>& s) {
    const F x0 = s.d[0], y0 = s.d[1], z0 = s.d[2], w0 = s.d[3];
    // Rank of each offset among the four (Gustavson's ranking): the k-th corner steps along every
    // axis whose rank is ≥ 4 − k.
    const U xy = mask_gt(x0, y0), xz = mask_gt(x0, z0), xw = mask_gt(x0, w0);
    const U yz = mask_gt(y0, z0), yw = mask_gt(y0, w0), zw = mask_gt(z0, w0);
    const U rx = (xy & 1u) + (xz & 1u) + (xw & 1u);
    const U ry = (~xy & 1u) + (yz & 1u) + (yw & 1u);
    const U rz = (~xz & 1u) + (~yz & 1u) + (zw & 1u);
    const U rw = (~xw & 1u) + (~yw & 1u) + (~zw & 1u);
    const U two = splat_u(rx, 2u), one = splat_u(rx, 1u), three = splat_u(rx, 3u);
    const U i1 = mask_eq(rx, three), j1 = mask_eq(ry, three), k1 = mask_eq(rz, three), l1 = mask_eq(rw, three);
    const U i2 = i1 | mask_eq(rx, two), j2 = j1 | mask_eq(ry, two), k2 = k1 | mask_eq(rz, two),
            l2 = l1 | mask_eq(rw, two);
    const U i3 = i2 | mask_eq(rx, one), j3 = j2 | mask_eq(ry, one), k3 = k2 | mask_eq(rz, one),
            l3 = l2 | mask_eq(rw, one);
    const U cx = s.cell[0], cy = s.cell[1], cz = s.cell[2], cw = s.cell[3];
    const U h0 = hash(key ^ cx ^ cy ^ cz ^ cw);
    const U h1 = hash(key ^ (cx + (i1 & kPrimeX)) ^ (cy + (j1 & kPrimeY)) ^ (cz + (k1 & kPrimeZ)) ^ (cw + (l1 & kPrimeW)));
    const U h2 = hash(key ^ (cx + (i2 & kPrimeX)) ^ (cy + (j2 & kPrimeY)) ^ (cz + (k2 & kPrimeZ)) ^ (cw + (l2 & kPrimeW)));
    const U h3 = hash(key ^ (cx + (i3 & kPrimeX)) ^ (cy + (j3 & kPrimeY)) ^ (cz + (k3 & kPrimeZ)) ^ (cw + (l3 & kPrimeW)));
    const U h4 = hash(key ^ (cx + kPrimeX) ^ (cy + kPrimeY) ^ (cz + kPrimeZ) ^ (cw + kPrimeW));
    const F x1 = x0 - one_if<F>(i1) + kG4f, y1 = y0 - one_if<F>(j1) + kG4f, z1 = z0 - one_if<F>(k1) + kG4f,
            w1 = w0 - one_if<F>(l1) + kG4f;
    const F x2 = x0 - one_if<F>(i2) + 2.0f * kG4f, y2 = y0 - one_if<F>(j2) + 2.0f * kG4f,
            z2 = z0 - one_if<F>(k2) + 2.0f * kG4f, w2 = w0 - one_if<F>(l2) + 2.0f * kG4f;
    const F x3 = x0 - one_if<F>(i3) + 3.0f * kG4f, y3 = y0 - one_if<F>(j3) + 3.0f * kG4f,
            z3 = z0 - one_if<F>(k3) + 3.0f * kG4f, w3 = w0 - one_if<F>(l3) + 3.0f * kG4f;
    const F x4 = x0 - 1.0f + 4.0f * kG4f, y4 = y0 - 1.0f + 4.0f * kG4f, z4 = z0 - 1.0f + 4.0f * kG4f,
            w4 = w0 - 1.0f + 4.0f * kG4f;
    const F n0 = falloff(kSimplexRadius2 - x0 * x0 - y0 * y0 - z0 * z0 - w0 * w0) * grad4(h0, x0, y0, z0, w0);
    const F n1 = falloff(kSimplexRadius2 - x1 * x1 - y1 * y1 - z1 * z1 - w1 * w1) * grad4(h1, x1, y1, z1, w1);
    const F n2 = falloff(kSimplexRadius2 - x2 * x2 - y2 * y2 - z2 * z2 - w2 * w2) * grad4(h2, x2, y2, z2, w2);
    const F n3 = falloff(kSimplexRadius2 - x3 * x3 - y3 * y3 - z3 * z3 - w3 * w3) * grad4(h3, x3, y3, z3, w3);
    const F n4 = falloff(kSimplexRadius2 - x4 * x4 - y4 * y4 - z4 * z4 - w4 * w4) * grad4(h4, x4, y4, z4, w4);
    return ((((n0 + n1) + n2) + n3) + n4) * kSimplex4Scale;
}

// --- the double-precision split -------------------------------------------------------------
// Templates over the double lanes D, so the scalar path and the batch run the same operations.

template <class D> inline D clamp_coordinate(D x) {
    const D lo = splat_d(x, -kMaxCoordinate), hi = splat_d(x, kMaxCoordinate);
    x = select_d(mask_gt(x, lo), x, lo); // NaN fails the test and becomes −2⁴⁸
    return select_d(mask_gt(hi, x), x, hi);
}

// ⌊x⌋ as a double and its low 32 bits, for |x| ≤ 2⁵⁰, using only IEEE add/subtract/compare:
// x + 1.5·2⁵² lies in [2⁵², 2⁵³) where doubles are the integers, so it lands on ⌊x⌋ or ⌈x⌉
// (under any rounding mode) and the comparison fixes ⌈x⌉. The mantissa of r + 1.5·2⁵² holds
// 2⁵¹ + r, whose low 32 bits are r mod 2³².
template <class D> struct Floor {
    D value;
    typename LanesOf<D>::U low_bits;
};
template <class D> inline Floor<D> floor_split(D x) {
    const D magic = splat_d(x, kRoundMagic);
    D r = (x + magic) - magic;
    r = select_d(mask_gt(r, x), r - 1.0, r);
    return {r, low32(as_q(r + magic))};
}

// One lane: the same values in a form the compiler keeps in SSE registers, without branches on
// the data (maxsd/minsd for the clamp; r − 0.0 is r, −0 included).
inline D1 clamp_coordinate(D1 x) {
    x = x > -kMaxCoordinate ? x : -kMaxCoordinate;
    return x < kMaxCoordinate ? x : kMaxCoordinate;
}
inline Floor<D1> floor_split(D1 x) {
    // r > x exactly when x − r (exact) is negative: take its sign bit instead of comparing,
    // since GCC compiles every scalar form of the comparison into a branch, which random
    // coordinates mispredict half the time. + 0.0 turns the −0 of x = −0 into +0.
    const double rounded = (x + kRoundMagic) - kRoundMagic;
    const Q1 above = as_q((x - rounded) + 0.0) >> 63;
    const double value = rounded - static_cast<double>(static_cast<int>(above));
    return {value, low32(as_q(value + kRoundMagic))};
}

#if FX_NOISE_X86_BLEND && defined(FX_NOISE_BATCH)
// Double lanes with blend instructions: maxpd(x, lo) is x > lo ? x : lo and minpd(x, hi) is
// x < hi ? x : hi, exactly the generic clamp (NaN becomes −2⁴⁸); roundpd floors exactly and
// + 0.0 turns its −0 (for x = −0) into the +0 of the generic floor.
#if FX_NOISE_LANES == 8
inline VecD2 clamp_half(VecD2 x) {
    const __m256d lo = _mm256_set1_pd(-kMaxCoordinate), hi = _mm256_set1_pd(kMaxCoordinate);
    return (VecD2)_mm256_min_pd(_mm256_max_pd((__m256d)x, lo), hi);
}
inline VecD2 floor_half(VecD2 x) { return (VecD2)_mm256_floor_pd((__m256d)x) + 0.0; }
#else
inline VecD2 clamp_half(VecD2 x) {
    const __m128d lo = _mm_set1_pd(-kMaxCoordinate), hi = _mm_set1_pd(kMaxCoordinate);
    return (VecD2)_mm_min_pd(_mm_max_pd((__m128d)x, lo), hi);
}
inline VecD2 floor_half(VecD2 x) { return (VecD2)_mm_floor_pd((__m128d)x) + 0.0; }
#endif
inline VecD clamp_coordinate(VecD x) { return {clamp_half(x.lo), clamp_half(x.hi)}; }

inline Floor<VecD> floor_split(VecD x) {
    const VecD r = {floor_half(x.lo), floor_half(x.hi)};
    return {r, low32(as_q(r + kRoundMagic))};
}
#endif

constexpr std::uint32_t kPrimes[4] = {kPrimeX, kPrimeY, kPrimeZ, kPrimeW};

// One Perlin axis from a coordinate: the cell times the axis prime and the offset in the cell,
// in [0, 1] (1 only where float rounding of offsets within 2⁻²⁵ of the next cell rounds up;
// both cells give the same value there to float accuracy).
template <class D> inline PerlinAxis<typename LanesOf<D>::F, typename LanesOf<D>::U> perlin_axis(D x, std::uint32_t prime) {
    using F = typename LanesOf<D>::F;
    x = clamp_coordinate(x);
    const Floor<D> f = floor_split(x);
    const F t = narrow(x - f.value);
    return {f.low_bits * prime, t, fade(t)};
}

// Skew to find the simplex lattice cell, unskew to get the offset from its corner (all in double,
// so the narrowed offsets are as accurate far from the origin as near it).
template <int N, class D>
inline SimplexSample<typename LanesOf<D>::F, typename LanesOf<D>::U, N> simplex_sample(const D (&p)[N], double skew,
                                                                                      double unskew) {
    D x[N];
    D sum = splat_d(p[0], 0.0);
    for (int a = 0; a < N; ++a) {
        x[a] = clamp_coordinate(p[a]);
        sum = sum + x[a];
    }
    const D s = sum * skew;
    SimplexSample<typename LanesOf<D>::F, typename LanesOf<D>::U, N> out;
    D cell[N];
    D cell_sum = splat_d(p[0], 0.0);
    for (int a = 0; a < N; ++a) {
        const Floor<D> f = floor_split(x[a] + s);
        cell[a] = f.value;
        cell_sum = cell_sum + f.value;
        out.cell[a] = f.low_bits * kPrimes[a];
    }
    const D t = cell_sum * unskew;
    for (int a = 0; a < N; ++a) out.d[a] = narrow(x[a] - (cell[a] - t));
    return out;
}

// The key of octave `octave` of a noise seeded with `seed` (octave 0 is the noise itself):
// a bijective 32-bit mix (murmur3's finaliser), so nearby seeds give unrelated fields.
// The lanes version takes each lane's octave.
template <class U> inline U mix_seed(std::uint32_t seed, U octave) {
    U h = octave * 0x9e3779b9u + seed;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}
inline std::uint32_t mix_seed(std::uint32_t seed, int octave) { return mix_seed(seed, static_cast<U1>(octave)); }

} // namespace FX_NOISE_ISA
} // namespace cellfx::fx::noise_detail
