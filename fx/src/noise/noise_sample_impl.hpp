// cellfx — one sample per call on vector lanes: the kernels behind fx::Noise::perlin2/perlin3 and
// fractal2/3/4. Compiled once per instruction set through noise_lanes_impl.hpp, after
// noise_batch_impl.hpp (whose lane helpers it uses).
//
// Based on: the kernels of noise_kernels.hpp (Perlin 2002, Gustavson 2005), with the cell's
// corners or the fractal's octaves in the lanes instead of samples: a game calls the noise one
// sample at a time from its own code, so the lanes have to come from inside the sample.
// - AVX2: perlin2 puts the cell's 4 corners in an SSE register, perlin3 its 8 corners in an AVX
//   one: one hash multiply, one gradient choice and one dot product for all of them, then lerps
//   that pair the lanes as the one-lane kernel pairs its values. Perlin fractals run octave by
//   octave on these (2-D: two octaves per AVX register).
// - Other fractals (and every fractal without AVX2) put octaves in lanes: octave o's
//   coordinates, key and amplitude in lane o, the basis kernel on every lane, then the weighted
//   octaves added in octave order, as the one-lane sum adds them.
// - Without AVX2, perlin2/3 are the one-lane kernels.
// Each lane does exactly the IEEE operations of the one-lane kernels, so every path returns the
// same bits (tests/test_noise.cpp checks each instruction set against noise.cpp's definitions).
#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace cellfx::fx::noise_detail {
inline namespace FX_NOISE_ISA {
namespace {

#if FX_NOISE_HAVE_VECTOR
#if FX_NOISE_LANES == 8
const VecU kLaneIndex = {0, 1, 2, 3, 4, 5, 6, 7};
#else
const VecU kLaneIndex = {0, 1, 2, 3};
#endif
#else
const VecU kLaneIndex = 0;
#endif

// The octaves' frequencies and amplitudes as in make_plan, in whole vectors of kLanes: the
// entries past the last octave up to the end of its vector are 0 (its lanes are computed and
// dropped), those after that are never read. (Zeroing the whole plan, a rep stos, cost as much
// as the rest of a 2-D octave.)
struct LanePlan {
    alignas(64) double frequency[kMaxOctaves];
    alignas(64) float amplitude[kMaxOctaves];

    explicit LanePlan(const Fractal& fractal) {
        static_assert(kMaxOctaves % kLanes == 0, "whole vectors of octaves");
        const int last = (fractal.octaves - 1) / kLanes * kLanes;
        for (int i = 0; i < kLanes; ++i) {
            frequency[last + i] = 0.0;
            amplitude[last + i] = 0.0f;
        }
        OctaveWalk walk(fractal);
        for (int o = 0; o < fractal.octaves; ++o, walk.next()) {
            frequency[o] = walk.frequency;
            amplitude[o] = walk.amplitude;
        }
    }
};

// Σ over the octaves, kLanes octaves at a time.
template <int N> float fractal_octave_lanes(const Fractal& fractal, std::uint32_t seed, const double (&p)[N]) {
    const LanePlan plan(fractal);
    float sum = 0.0f;
    for (int first = 0; first < fractal.octaves; first += kLanes) {
        const VecD frequency = load_lanes(plan.frequency + first), offset = load_lanes(kOctaveOffsets + first);
        VecD q[N];
        for (int a = 0; a < N; ++a)
            q[a] = splat_d(frequency, p[a]) * frequency + offset; // octave_coordinate
        const VecU key = mix_seed(seed, kLaneIndex + static_cast<std::uint32_t>(first));
        VecF v;
        if (fractal.basis == NoiseBasis::perlin) {
            VAxis ax[N];
            for (int a = 0; a < N; ++a)
                ax[a] = perlin_axis(q[a], kPrimes[a]);
            v = perlin_lanes<N>(key, ax);
        } else {
            v = simplex_lanes<N>(key, simplex_sample<N>(q, skew<N>(), unskew<N>()));
        }
        alignas(64) float weighted[kLanes];
        store_lanes(weighted, shape(fractal.type, v) * load_lanes(plan.amplitude + first));
        const int count = fractal.octaves - first < kLanes ? fractal.octaves - first : kLanes;
        for (int i = 0; i < count; ++i)
            sum = first + i == 0 ? weighted[i] : sum + weighted[i]; // accumulate
    }
    return finish(sum);
}

#if defined(__AVX2__)

// The kernels below are inlined into the functions of the table: a function that takes or
// returns AVX registers gets no vzeroupper at its end, and returning to SSE code with the upper
// halves dirty halved the speed of callers compiled without AVX.
#define FX_NOISE_INLINE inline __attribute__((always_inline))

// The kernels' constants. GCC builds vector constants whose values it knows in general
// registers (mov, vmovd, vpbroadcastd: three instructions, two on the busy vector ports) rather
// than loading them; read through in_memory(), every constant is one load folded into its
// instruction.
struct CornerConstants {
    alignas(32) double min_coordinate[4], max_coordinate[4], round_magic[4];
    alignas(32) std::int32_t even_dwords[8];               // the low halves of 4 qwords
    alignas(32) std::int32_t lane0[8], lane1[8], lane2[8]; // broadcasts of lane 0, 1, 2
    alignas(32) std::int32_t pair_lane0[8], pair_lane1[8]; // lane 0 | 2, lane 1 | 3 (pairs)
    alignas(32) float zero_one[8], zero_zero_one_one[8], zero_one_zero_one[8];
    alignas(32) std::uint32_t primes_xyzz[8], primes_xxyy[8], primes_xyxy[8];
    // the primes added to a corner's cell where it is the far one along an axis (per layout)
    alignas(32) std::uint32_t step_x_y_odd[8], step_x_pairs[8], step_y_odd[8], step_x_high[8], step_y_pairs[8],
        step_z_odd[8];
    alignas(32) std::uint32_t hash_multiplier[8], sign[8], twelve[8], thirteen[8];
    // grad2's choice as two 8-entry tables indexed by the 3 low bits of grad2's h (vpermps reads
    // those): bit 0 the sign of the cos 22.5° term, bit 1 of the sin term, bit 2 swaps them.
    alignas(32) float grad2_x[8], grad2_y[8];
    alignas(32) float perlin2_scale[8];
};
constexpr std::uint32_t kPX = kPrimeX, kPY = kPrimeY, kPZ = kPrimeZ, kM = kHashMultiplier, kS = 0x80000000u;
// clang-format off
constexpr CornerConstants kCorner = {
    {-kMaxCoordinate, -kMaxCoordinate, -kMaxCoordinate, -kMaxCoordinate},
    {kMaxCoordinate, kMaxCoordinate, kMaxCoordinate, kMaxCoordinate},
    {kRoundMagic, kRoundMagic, kRoundMagic, kRoundMagic},
    {0, 2, 4, 6, 0, 2, 4, 6},
    {0, 0, 0, 0, 0, 0, 0, 0}, {1, 1, 1, 1, 1, 1, 1, 1}, {2, 2, 2, 2, 2, 2, 2, 2},
    {0, 0, 0, 0, 2, 2, 2, 2}, {1, 1, 1, 1, 3, 3, 3, 3},
    {0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 1, 1, 0, 0, 1, 1}, {0, 1, 0, 1, 0, 1, 0, 1},
    {kPX, kPY, kPZ, kPZ, kPX, kPY, kPZ, kPZ}, {kPX, kPX, kPY, kPY, kPX, kPX, kPY, kPY},
    {kPX, kPY, kPX, kPY, kPX, kPY, kPX, kPY},
    {0, kPX, 0, kPY, 0, kPX, 0, kPY}, {0, 0, kPX, kPX, 0, 0, kPX, kPX}, {0, kPY, 0, kPY, 0, kPY, 0, kPY},
    {0, 0, 0, 0, kPX, kPX, kPX, kPX}, {0, 0, kPY, kPY, 0, 0, kPY, kPY}, {0, kPZ, 0, kPZ, 0, kPZ, 0, kPZ},
    {kM, kM, kM, kM, kM, kM, kM, kM}, {kS, kS, kS, kS, kS, kS, kS, kS}, {12, 12, 12, 12, 12, 12, 12, 12},
    {13, 13, 13, 13, 13, 13, 13, 13},
    {kCos22, -kCos22, kCos22, -kCos22, kSin22, kSin22, -kSin22, -kSin22},
    {kSin22, kSin22, -kSin22, -kSin22, kCos22, -kCos22, kCos22, -kCos22},
    {kPerlin2Scale, kPerlin2Scale, kPerlin2Scale, kPerlin2Scale, kPerlin2Scale, kPerlin2Scale, kPerlin2Scale,
     kPerlin2Scale},
};
// clang-format on
inline const CornerConstants& in_memory(const CornerConstants& constants) {
    const CornerConstants* p = &constants;
    asm("" : "+r"(p)); // the compiler no longer knows what p points at
    return *p;
}

inline __m256 ps(const float (&a)[8]) {
    return _mm256_load_ps(a);
}
inline __m256i si(const std::int32_t (&a)[8]) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(a));
}
inline __m256i si(const std::uint32_t (&a)[8]) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(a));
}
inline __m128i si128(const std::uint32_t (&a)[8]) {
    return _mm_load_si128(reinterpret_cast<const __m128i*>(a));
}
inline __m256d pd(const double (&a)[4]) {
    return _mm256_load_pd(a);
}
inline __m128 lo(__m256 v) {
    return _mm256_castps256_ps128(v);
}
inline __m128i lo(__m256i v) {
    return _mm256_castsi256_si128(v);
}

// clamp_coordinate and floor_split of two or four coordinates (x, y, z, w lanes): maxpd/minpd
// clamp exactly as clamp_coordinate (NaN, failing every comparison, becomes −2⁴⁸), roundpd
// floors exactly, and + 0.0 turns the −0 that roundpd gives for x = −0 into the +0 of
// floor_split. The offsets x − ⌊x⌋ narrowed to float, and the cells' low 32 bits (the low halves
// of ⌊x⌋ + 1.5·2⁵²). Every later step waits for the split, so the clamp is left out where
// in_range() says it changes nothing (a sample is then ~10% faster).
inline bool in_range(__m128d p) { // |x| < 2⁴⁸ in both lanes (false for NaN)
    const __m128d magnitude = _mm_andnot_pd(_mm_set1_pd(-0.0), p);
    return _mm_movemask_pd(_mm_cmp_pd(magnitude, _mm_set1_pd(kMaxCoordinate), _CMP_LT_OQ)) == 3;
}
inline bool in_range(__m256d p) { // in all four lanes
    const __m256d magnitude = _mm256_andnot_pd(_mm256_set1_pd(-0.0), p);
    return _mm256_movemask_pd(_mm256_cmp_pd(magnitude, _mm256_set1_pd(kMaxCoordinate), _CMP_LT_OQ)) == 15;
}
// (split2 leaves the cells in dwords 0 and 2, for the caller's shuffle; offset lanes 2, 3 are 0.)
template <bool kClamp> inline void split2(const CornerConstants& k, __m128d p, __m128& offset, __m128i& cell_bits) {
    if (kClamp)
        p = _mm_min_pd(_mm_max_pd(p, _mm256_castpd256_pd128(pd(k.min_coordinate))),
                       _mm256_castpd256_pd128(pd(k.max_coordinate)));
    const __m128d r = _mm_floor_pd(p);
    offset = _mm_cvtpd_ps(_mm_sub_pd(p, _mm_add_pd(r, _mm_setzero_pd())));
    cell_bits = _mm_castpd_si128(_mm_add_pd(r, _mm256_castpd256_pd128(pd(k.round_magic))));
}
template <bool kClamp> inline void split4(const CornerConstants& k, __m256d p, __m128& offset, __m128i& cells) {
    if (kClamp) p = _mm256_min_pd(_mm256_max_pd(p, pd(k.min_coordinate)), pd(k.max_coordinate));
    const __m256d r = _mm256_floor_pd(p);
    offset = _mm256_cvtpd_ps(_mm256_sub_pd(p, _mm256_add_pd(r, _mm256_setzero_pd())));
    const __m256i bits = _mm256_castpd_si256(_mm256_add_pd(r, pd(k.round_magic)));
    cells = lo(_mm256_permutevar8x32_epi32(bits, si(k.even_dwords)));
}

// perlin2: the corners (x0,y0), (x0,y1), (x1,y0), (x1,y1) in four lanes, so that the lerp along
// x pairs the low and the high half. g·d = x·gx + y·gy is grad2's sum (its two terms in either
// order: IEEE addition is commutative; a negated table entry negates its product exactly).
template <bool kClamp> FX_NOISE_INLINE float perlin2_corners(std::uint32_t key, __m128d p) {
    const CornerConstants& k = in_memory(kCorner);
    __m128 t;
    __m128i bits;
    split2<kClamp>(k, p, t, bits);
    const __m128i xy =
        _mm_add_epi32(_mm_mullo_epi32(_mm_shuffle_epi32(bits, _MM_SHUFFLE(2, 2, 0, 0)), si128(k.primes_xxyy)),
                      si128(k.step_x_y_odd)); // X X+1 Y Y+1 (times the primes)
    const __m128i cx = _mm_shuffle_epi32(xy, _MM_SHUFFLE(1, 1, 0, 0)),
                  cy = _mm_shuffle_epi32(xy, _MM_SHUFFLE(3, 2, 3, 2));
    const __m128i h =
        _mm_mullo_epi32(_mm_xor_si128(_mm_xor_si128(_mm_set1_epi32(int(key)), cy), cx), si128(k.hash_multiplier));
    const __m128 dx = _mm_sub_ps(_mm_shuffle_ps(t, t, 0x00), lo(ps(k.zero_zero_one_one)));
    const __m128 dy = _mm_sub_ps(_mm_shuffle_ps(t, t, 0x55), lo(ps(k.zero_one_zero_one)));
    const __m256i index = _mm256_castsi128_si256(_mm_srli_epi32(h, 28));
    const __m128 gx = lo(_mm256_permutevar8x32_ps(ps(k.grad2_x), index));
    const __m128 gy = lo(_mm256_permutevar8x32_ps(ps(k.grad2_y), index));
    const __m128 n = _mm_add_ps(_mm_mul_ps(dx, gx), _mm_mul_ps(dy, gy));
    const __m128 f = fade(t);
    const __m128 along_x = lerp(n, _mm_movehl_ps(n, n), _mm_shuffle_ps(f, f, 0x00)); // y0, y1
    return lerp(_mm_cvtss_f32(along_x), _mm_cvtss_f32(_mm_movehdup_ps(along_x)), _mm_cvtss_f32(_mm_movehdup_ps(f))) *
           kPerlin2Scale;
}
inline float perlin2_corners(std::uint32_t key, double x, double y) {
    const __m128d p = _mm_setr_pd(x, y);
    return in_range(p) ? perlin2_corners<false>(key, p) : perlin2_corners<true>(key, p);
}

// Two 2-D samples (two octaves of a fractal) at once, one per half of an AVX register, each
// half laid out and computed as in perlin2_corners.
template <bool kClamp>
FX_NOISE_INLINE void perlin2_corners_pair(std::uint32_t key_a, std::uint32_t key_b, __m256d p, float& na, float& nb) {
    const CornerConstants& k = in_memory(kCorner);
    __m128 t4;
    __m128i cells4;
    split4<kClamp>(k, p, t4, cells4);
    const __m256i c = _mm256_castsi128_si256(_mm_mullo_epi32(cells4, si128(k.primes_xyxy)));
    const __m256i cx = _mm256_add_epi32(_mm256_permutevar8x32_epi32(c, si(k.pair_lane0)), si(k.step_x_pairs));
    const __m256i cy = _mm256_add_epi32(_mm256_permutevar8x32_epi32(c, si(k.pair_lane1)), si(k.step_y_odd));
    const __m256i keys = _mm256_set_m128i(_mm_set1_epi32(int(key_b)), _mm_set1_epi32(int(key_a)));
    const __m256i h = _mm256_mullo_epi32(_mm256_xor_si256(_mm256_xor_si256(keys, cy), cx), si(k.hash_multiplier));
    const __m256 t = _mm256_castps128_ps256(t4);
    const __m256 dx = _mm256_sub_ps(_mm256_permutevar8x32_ps(t, si(k.pair_lane0)), ps(k.zero_zero_one_one));
    const __m256 dy = _mm256_sub_ps(_mm256_permutevar8x32_ps(t, si(k.pair_lane1)), ps(k.zero_one_zero_one));
    const __m256i index = _mm256_srli_epi32(h, 28);
    const __m256 n = _mm256_add_ps(_mm256_mul_ps(dx, _mm256_permutevar8x32_ps(ps(k.grad2_x), index)),
                                   _mm256_mul_ps(dy, _mm256_permutevar8x32_ps(ps(k.grad2_y), index)));
    const __m256 f = _mm256_castps128_ps256(fade(t4));
    const __m256 along_x =
        lerp(n, _mm256_permute_ps(n, _MM_SHUFFLE(3, 2, 3, 2)), _mm256_permutevar8x32_ps(f, si(k.pair_lane0)));
    const __m256 along_y = lerp(along_x, _mm256_movehdup_ps(along_x), _mm256_permutevar8x32_ps(f, si(k.pair_lane1)));
    const __m256 value = _mm256_mul_ps(along_y, ps(k.perlin2_scale));
    na = _mm_cvtss_f32(lo(value));
    nb = _mm_cvtss_f32(_mm256_extractf128_ps(value, 1));
}
inline void perlin2_corners_pair(std::uint32_t key_a, double xa, double ya, std::uint32_t key_b, double xb, double yb,
                                 float& na, float& nb) {
    const __m256d p = _mm256_setr_pd(xa, ya, xb, yb);
    if (in_range(p))
        perlin2_corners_pair<false>(key_a, key_b, p, na, nb);
    else
        perlin2_corners_pair<true>(key_a, key_b, p, na, nb);
}

// perlin3: corner (i, j, k) in lane 4i + 2j + k of an AVX register, so that the lerps pair the
// register's halves (x), then lanes 0, 1 with 2, 3 (y), then lanes 0 and 1 (z). grad3 with blends,
// h4 being grad3's h (the hash's top 4 bits): u is y where h4 ≥ 8 (the hash's sign bit), v is y
// where h4 < 4, x where h4 is 12 or 14, else z; h4's bits 0 and 1 flip their signs.
template <bool kClamp> FX_NOISE_INLINE float perlin3_corners(std::uint32_t key, __m256d p) { // p: x y z z
    const CornerConstants& k = in_memory(kCorner);
    __m128 t4;
    __m128i cells4;
    split4<kClamp>(k, p, t4, cells4);
    const __m256i c = _mm256_castsi128_si256(_mm_mullo_epi32(cells4, si128(k.primes_xyzz)));
    const __m256i cx = _mm256_add_epi32(_mm256_permutevar8x32_epi32(c, si(k.lane0)), si(k.step_x_high));
    const __m256i cy = _mm256_add_epi32(_mm256_permutevar8x32_epi32(c, si(k.lane1)), si(k.step_y_pairs));
    const __m256i cz = _mm256_add_epi32(_mm256_permutevar8x32_epi32(c, si(k.lane2)), si(k.step_z_odd));
    const __m256i h = _mm256_mullo_epi32(
        _mm256_xor_si256(_mm256_xor_si256(_mm256_xor_si256(_mm256_set1_epi32(int(key)), cy), cz), cx),
        si(k.hash_multiplier));
    const __m256 t = _mm256_castps128_ps256(t4);
    const __m256 dx = _mm256_sub_ps(_mm256_permutevar8x32_ps(t, si(k.lane0)), ps(k.zero_one));
    const __m256 dy = _mm256_sub_ps(_mm256_permutevar8x32_ps(t, si(k.lane1)), ps(k.zero_zero_one_one));
    const __m256 dz = _mm256_sub_ps(_mm256_permutevar8x32_ps(t, si(k.lane2)), ps(k.zero_one_zero_one));
    const __m256i h4 = _mm256_srli_epi32(h, 28);
    const __m256 u = _mm256_blendv_ps(dx, dy, _mm256_castsi256_ps(h));
    const __m256i v_is_y = _mm256_cmpeq_epi32(_mm256_and_si256(h4, si(k.twelve)), _mm256_setzero_si256());
    const __m256i v_is_x = _mm256_cmpeq_epi32(_mm256_and_si256(h4, si(k.thirteen)), si(k.twelve));
    const __m256 v =
        _mm256_blendv_ps(_mm256_blendv_ps(dz, dx, _mm256_castsi256_ps(v_is_x)), dy, _mm256_castsi256_ps(v_is_y));
    const __m256 u_sign = _mm256_castsi256_ps(_mm256_and_si256(_mm256_slli_epi32(h, 3), si(k.sign))); // hash bit 28
    const __m256 v_sign = _mm256_castsi256_ps(_mm256_and_si256(_mm256_slli_epi32(h, 2), si(k.sign))); // hash bit 29
    const __m256 n = _mm256_add_ps(_mm256_xor_ps(u, u_sign), _mm256_xor_ps(v, v_sign));
    const __m128 f = fade(t4);
    const __m128 along_x = lerp(lo(n), _mm256_extractf128_ps(n, 1), _mm_shuffle_ps(f, f, 0x00)); // y0z0 y0z1 y1z0 y1z1
    const __m128 along_y = lerp(along_x, _mm_movehl_ps(along_x, along_x), _mm_shuffle_ps(f, f, 0x55)); // z0 z1
    return lerp(_mm_cvtss_f32(along_y), _mm_cvtss_f32(_mm_movehdup_ps(along_y)), _mm_cvtss_f32(_mm_movehl_ps(f, f))) *
           kPerlin3Scale;
}
inline float perlin3_corners(std::uint32_t key, double x, double y, double z) {
    const __m256d p = _mm256_setr_pd(x, y, z, z);
    return in_range(p) ? perlin3_corners<false>(key, p) : perlin3_corners<true>(key, p);
}

// Perlin fractals octave after octave with the corners in lanes, as noise.cpp's fractal_sum:
// each octave is a short chain of its own, so the CPU overlaps them, where a vector of octaves
// is one long chain (split, corners, lerps, then the sum). No plan in memory: the octave's
// frequency and amplitude come from the walk.
template <int N> float fractal_perlin_corners(const Fractal& fractal, std::uint32_t seed, const double (&p)[N]) {
    OctaveWalk walk(fractal);
    float sum = 0.0f;
    int o = 0;
    if constexpr (N == 2) // two octaves per AVX register
        for (; o + 1 < fractal.octaves; o += 2) {
            const double xa = octave_coordinate(p[0], walk.frequency, o),
                         ya = octave_coordinate(p[1], walk.frequency, o);
            const float amplitude_a = walk.amplitude;
            walk.next();
            const double xb = octave_coordinate(p[0], walk.frequency, o + 1);
            const double yb = octave_coordinate(p[1], walk.frequency, o + 1);
            float na, nb;
            perlin2_corners_pair(mix_seed(seed, o), xa, ya, mix_seed(seed, o + 1), xb, yb, na, nb);
            sum = accumulate(o, sum, shape(fractal.type, na), amplitude_a);
            sum = accumulate(o + 1, sum, shape(fractal.type, nb), walk.amplitude);
            walk.next();
        }
    for (; o < fractal.octaves; ++o, walk.next()) {
        double q[N];
        for (int a = 0; a < N; ++a)
            q[a] = octave_coordinate(p[a], walk.frequency, o);
        const std::uint32_t key = mix_seed(seed, o);
        float n;
        if constexpr (N == 2)
            n = perlin2_corners(key, q[0], q[1]);
        else
            n = perlin3_corners(key, q[0], q[1], q[2]);
        sum = accumulate(o, sum, shape(fractal.type, n), walk.amplitude);
    }
    return finish(sum);
}

float perlin2_sample(std::uint32_t key, double x, double y) noexcept {
    return perlin2_corners(key, x, y);
}
float perlin3_sample(std::uint32_t key, double x, double y, double z) noexcept {
    return perlin3_corners(key, x, y, z);
}
float fractal2_sample(const Fractal& fractal, std::uint32_t seed, double x, double y) noexcept {
    return fractal.basis == NoiseBasis::perlin ? fractal_perlin_corners<2>(fractal, seed, {x, y})
                                               : fractal_octave_lanes<2>(fractal, seed, {x, y});
}
float fractal3_sample(const Fractal& fractal, std::uint32_t seed, double x, double y, double z) noexcept {
    return fractal.basis == NoiseBasis::perlin ? fractal_perlin_corners<3>(fractal, seed, {x, y, z})
                                               : fractal_octave_lanes<3>(fractal, seed, {x, y, z});
}

#else

float perlin2_sample(std::uint32_t key, double x, double y) noexcept {
    return perlin2<F1, U1>(key, perlin_axis(x, kPrimeX), perlin_axis(y, kPrimeY));
}
float perlin3_sample(std::uint32_t key, double x, double y, double z) noexcept {
    return perlin3<F1, U1>(key, perlin_axis(x, kPrimeX), perlin_axis(y, kPrimeY), perlin_axis(z, kPrimeZ));
}
float fractal2_sample(const Fractal& fractal, std::uint32_t seed, double x, double y) noexcept {
    return fractal_octave_lanes<2>(fractal, seed, {x, y});
}
float fractal3_sample(const Fractal& fractal, std::uint32_t seed, double x, double y, double z) noexcept {
    return fractal_octave_lanes<3>(fractal, seed, {x, y, z});
}

#endif

float fractal4_sample(const Fractal& fractal, std::uint32_t seed, double x, double y, double z, double w) noexcept {
    return fractal_octave_lanes<4>(fractal, seed, {x, y, z, w});
}

} // namespace
} // namespace FX_NOISE_ISA
} // namespace cellfx::fx::noise_detail
