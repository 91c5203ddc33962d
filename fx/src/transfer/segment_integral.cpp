// cellfx — exact integrals of a piecewise-linear transfer function along a ray segment.
//
// Based on: Williams & Max 1992 (volume density optical model); Max, Williams & Silva 2000 §II
// (analytic colour of a ray segment with linearly varying glow colour and extinction).
//
// On one piece of the segment (no breakpoint inside) put x = t/h ∈ [0, 1] and a = h·σ₀,
// b = h·σ₁ (front and back optical thickness rates). Then τ(x) = a·x + ((b − a)/2)·x² and
// dτ = h·σ dt, so with J = ∫₀¹ e^{−τ(x)} dx and integrating c·dτ·e^{−τ} by parts:
//
//   colour = c₀·w₀ + c₁·w₁,   w₀ = 1 − J = ∫(1 − e^{−τ}),   w₁ = J − e^{−T} = ∫(e^{−τ} − e^{−T}),
//
// with T = τ(1). Both weights are non-negative and sum to 1 − e^{−T}, so the colour is a
// cancellation-free blend of the end colours — the form that stays accurate for tiny and huge T.
// J is a Gaussian integral: erfcx for increasing σ, Dawson's function for decreasing σ, the
// exponential integral's expm1 form when σ is constant, and a power series when T is small
// (where 1 − J and J − e^{−T} would cancel).
#include "transfer/segment_integral.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/common.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "fx/error.hpp"
#include "transfer/special_functions.hpp"

namespace cellfx::fx {
namespace {

struct Sample {
    glm::dvec3 c;
    double sigma;
};

Sample sample_of(const TransferPoint& p) { return {p.color, p.sigma}; }

// Value at s on interval j of the transfer function: between points j−1 and j (interval 0 and
// interval n are the held ends). Exact at the interval's end points. Inline: the call cost as
// much as its work. transfer_sample() (segment_integral.hpp) repeats its expressions.
inline Sample on_interval(const TransferPoint* p, std::size_t n, std::size_t j, double s) {
    if (j == 0) return sample_of(p[0]);
    if (j == n) return sample_of(p[n - 1]);
    const TransferPoint& a = p[j - 1];
    const TransferPoint& b = p[j];
    if (s == b.s) return sample_of(b);
    const double t = (s - a.s) / (b.s - a.s);
    return {a.color + t * (b.color - a.color), a.sigma + t * (b.sigma - a.sigma)};
}

// Calls piece(ds, entry, exit) for each piece of the scalar run from s_from to s_to
// (s_from != s_to) in that order, where ds > 0 is the piece's scalar width and entry / exit are
// the one-sided transfer function values at its ends. Steps are crossed with the value from the
// side the run comes from, then the value from the other side.
template <class Piece>
void for_each_piece(const std::vector<TransferPoint>& points, double s_from, double s_to, Piece&& piece) {
    const TransferPoint* p = points.data();
    const std::size_t n = points.size();
    const auto below = [](double v, const TransferPoint& q) { return v < q.s; };
    const auto above = [](const TransferPoint& q, double v) { return q.s < v; };
    if (s_from < s_to) {
        // Interval j with p[j−1].s ≤ s_from < p[j].s.
        std::size_t j = static_cast<std::size_t>(std::upper_bound(p, p + n, s_from, below) - p);
        double s0 = s_from;
        Sample v0 = on_interval(p, n, j, s_from);
        while (j < n && p[j].s < s_to) {
            piece(p[j].s - s0, v0, sample_of(p[j]));
            s0 = p[j].s;
            ++j;
            while (j < n && p[j].s == p[j - 1].s) ++j; // skip the zero-width interval of a step
            v0 = sample_of(p[j - 1]);
        }
        piece(s_to - s0, v0, on_interval(p, n, j, s_to));
    } else {
        // Interval j with p[j−1].s < s_from ≤ p[j].s.
        std::size_t j = static_cast<std::size_t>(std::lower_bound(p, p + n, s_from, above) - p);
        double s0 = s_from;
        Sample v0 = on_interval(p, n, j, s_from);
        while (j > 0 && p[j - 1].s > s_to) {
            piece(s0 - p[j - 1].s, v0, sample_of(p[j - 1]));
            s0 = p[j - 1].s;
            --j;
            while (j > 0 && p[j - 1].s == p[j].s) --j;
            v0 = sample_of(p[j]);
        }
        // on_interval is exact at the right end; at the left end t = 0 gives p[j−1] exactly.
        piece(s0 - s_to, v0, on_interval(p, n, j, s_to));
    }
}

// The value at s from above (right-continuous), as TransferFunction::color/sigma.
Sample value_at(const std::vector<TransferPoint>& points, double s) {
    const TransferPoint* p = points.data();
    const std::size_t n = points.size();
    const std::size_t j = static_cast<std::size_t>(
        std::upper_bound(p, p + n, s, [](double v, const TransferPoint& q) { return v < q.s; }) - p);
    return on_interval(p, n, j, s);
}

// ∫₀¹ c(x)σ(x) dx for c, σ linear: exact, all terms non-negative.
glm::dvec3 mean_emission(const Sample& v0, const Sample& v1) {
    return (v0.c * (2.0 * v0.sigma + v1.sigma) + v1.c * (v0.sigma + 2.0 * v1.sigma)) * (1.0 / 6.0);
}

// Coefficient tables for the series (no division in the hot loop): 1/m!, 1/(m+1)!, m/(m+1)!.
constexpr std::size_t kSeriesTerms = 64;
struct SeriesTables {
    std::array<double, kSeriesTerms + 1> inv_fact{}, w0{}, w1{};
};
constexpr SeriesTables kSeries = [] {
    SeriesTables t{};
    double f = 1.0; // 1/m!
    for (std::size_t m = 0; m <= kSeriesTerms; ++m) {
        if (m > 0) f /= static_cast<double>(m);
        t.inv_fact[m] = f;
        t.w0[m] = f / static_cast<double>(m + 1);
        t.w1[m] = f * static_cast<double>(m) / static_cast<double>(m + 1);
    }
    return t;
}();

// Series below this optical depth per piece; above it the closed forms lose at most a few ulp
// to cancellation (1 − J ≥ 0.08 and J − e^{−T} ≥ J·T/2 there; see the file comment).
constexpr double kSeriesMax = detail::kSeriesMax;
// Above this, e^{−a} underflows many times over; clamping keeps every intermediate finite.
constexpr double kHugeDepth = 1e300;

struct Weights {
    double w0, w1, transmittance;
};

// Weights of the front and back colours of one piece; a, b ≥ 0 as in the file comment. The
// transmittance e^{−T} only where kTransmittance (a segment of several pieces); one piece
// leaves it out (in the series, its sum; 0 is returned).
template <bool kTransmittance>
Weights piece_weights(double a, double b) {
    a = std::min(a, kHugeDepth);
    b = std::min(b, kHugeDepth);
    const double A = a;
    const double B = 0.5 * b - 0.5 * a;
    const double T = 0.5 * a + 0.5 * b;
    if (T <= kSeriesMax) {
        // e^{−(Ax + Bx²)} = Σ f_m x^m/m! with f₀ = 1, f₁ = −A, f_{m+1} = −A·f_m − 2B·m·f_{m−1}.
        // Integrating term by term: w₀ = −Σ_{m≥1} f_m/(m+1)!, w₁ = −Σ_{m≥1} f_m·m/(m+1)!, and
        // e^{−T} = Σ f_m/m!. |A|, |B| ≤ 2T, so the terms f_m/m! fall like (2T)^m/m!·… with no
        // significant cancellation, and no transcendental function is needed. Using f_m rather
        // than the Taylor coefficients keeps the dependency chain to one multiply-add.
        double f_prev = 1.0, f = -A; // f₀, f₁
        double w0 = -f * kSeries.w0[1], w1 = -f * kSeries.w1[1];
        double e = 1.0 + f; // Σ f_m/m! so far
        const double two_b = 2.0 * B;
        // Two terms per step, the tail tested once per step (the test costs as much as a term;
        // at most one term more than needed is added). dm is m as a double, counted rather
        // than converted (size_t to double takes several instructions on x86-64).
        double dm = 1.0;
        for (std::size_t m = 1; m + 1 < kSeriesTerms; m += 2, dm += 2.0) {
            const double f2 = -A * f - two_b * dm * f_prev;
            const double f3 = -A * f2 - two_b * (dm + 1.0) * f;
            const double t2 = f2 * kSeries.inv_fact[m + 1], t3 = f3 * kSeries.inv_fact[m + 2];
            w0 -= f2 * kSeries.w0[m + 1];
            w1 -= f2 * kSeries.w1[m + 1];
            if (kTransmittance) e += t2;
            w0 -= f3 * kSeries.w0[m + 2];
            w1 -= f3 * kSeries.w1[m + 2];
            if (kTransmittance) e += t3;
            f_prev = f2;
            f = f3;
            // The tail is below the last two terms once they fall this far (2T ≤ 1).
            if (std::abs(t2) + std::abs(t3) <= 2e-17 * (w0 + w1)) break;
        }
        return {std::max(w0, 0.0), std::max(w1, 0.0), kTransmittance ? e : 0.0};
    }
    const double e = std::exp(-T);
    double J;
    if (std::abs(B) < 1e-15) {
        // σ constant to double precision (e^{−Bx²} = 1 − O(1e-15)); A ≥ T − |B| > 0.
        J = -std::expm1(-A) / A;
    } else if (B > 0.0) {
        // Ax + Bx² = (kx + p)² − p², k = √B, p = A/(2k):
        // J = (√π/2k)·e^{p²}(erfc p − erfc(p + k)) = (√π/2k)·(erfcx p − e^{−T}·erfcx(p + k)).
        const double k = std::sqrt(B);
        const double p = A / (2.0 * k);
        J = detail::kSqrtPi / (2.0 * k) * (detail::erfcx(p) - e * detail::erfcx(p + k));
    } else {
        // Ax − |B|x² = p² − (p − kx)², k = √|B|, p = A/(2k) ≥ k because b = A + 2B ≥ 0:
        // J = e^{−p²}∫_{p−k}^{p} e^{y²} dy / k = (D(p) − e^{−T}·D(p − k)) / k.
        const double k = std::sqrt(-B);
        const double p = A / (2.0 * k);
        J = (detail::dawson(p) - e * detail::dawson(std::max(p - k, 0.0))) / k;
    }
    return {std::max(1.0 - J, 0.0), std::max(J - e, 0.0), e};
}

// The largest value the GPU paths' float emission tables and their sums may reach.
constexpr double kMaxTableValue = 1e38;

std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

void require_table(bool ok, const std::string& what) {
    if (!ok) throw Error("transfer function table: " + what);
}

// The scalar range the tables cover: the control points' range, or a unit range around a
// transfer function whose points all sit at one s.
void table_range(const TransferFunction& tf, double& lo, double& hi) {
    require_table(!tf.points().empty(), "the transfer function has no points");
    lo = tf.points().front().s;
    hi = tf.points().back().s;
    if (lo == hi) {
        lo -= 0.5;
        hi += 0.5;
    }
}

} // namespace

glm::dvec3 emission_integral(const TransferFunction& tf, double s_front, double s_back, double length) {
    const std::vector<TransferPoint>& points = tf.points();
    if (!(length > 0.0) || points.empty()) return glm::dvec3(0.0);
    if (s_front == s_back) {
        const Sample v = value_at(points, s_front);
        return length * v.c * v.sigma;
    }
    // Emission commutes along the ray, so integrate upwards in s; each piece weighs by its
    // share of the scalar run.
    const double lo = std::min(s_front, s_back), hi = std::max(s_front, s_back);
    const double run = hi - lo;
    glm::dvec3 sum(0.0);
    for_each_piece(points, lo, hi, [&](double ds, const Sample& v0, const Sample& v1) {
        sum += (ds / run) * mean_emission(v0, v1);
    });
    return length * sum;
}

glm::dvec3 segment_maximum(const TransferFunction& tf, double s_front, double s_back) {
    const std::vector<TransferPoint>& points = tf.points();
    if (points.empty()) return glm::dvec3(0.0);
    if (s_front == s_back) {
        const Sample v = value_at(points, s_front);
        return v.c * v.sigma;
    }
    glm::dvec3 best(0.0);
    for_each_piece(points, std::min(s_front, s_back), std::max(s_front, s_back),
                   [&](double, const Sample& v0, const Sample& v1) {
                       best = glm::max(best, glm::max(v0.c * v0.sigma, v1.c * v1.sigma));
                       // c(u)σ(u) is a quadratic in u ∈ [0, 1]; concave when c and σ change in
                       // opposite directions, with its peak possibly inside the piece.
                       const double ds = v1.sigma - v0.sigma;
                       for (int ch = 0; ch < 3; ++ch) {
                           const double dc = v1.c[ch] - v0.c[ch];
                           if (!(dc * ds < 0.0)) continue;
                           const double u = -(v0.c[ch] * ds + dc * v0.sigma) / (2.0 * dc * ds);
                           if (u > 0.0 && u < 1.0)
                               best[ch] = std::max(best[ch], (v0.c[ch] + u * dc) * (v0.sigma + u * ds));
                       }
                   });
    return best;
}

SegmentColor emission_absorption(const TransferFunction& tf, double s_front, double s_back, double length) {
    SegmentColor out;
    const std::vector<TransferPoint>& points = tf.points();
    if (!(length > 0.0) || points.empty()) return out;
    if (s_front == s_back) {
        // Constant medium: colour = c·(1 − e^{−σl}).
        const Sample v = value_at(points, s_front);
        out.optical_depth = length * v.sigma;
        out.alpha = -std::expm1(-out.optical_depth);
        out.color = v.c * out.alpha;
        return out;
    }
    const double run = std::abs(s_back - s_front);
    {
        // One piece: no breakpoint strictly between the ends, the common case for the short
        // segments of a fine mesh. The same values for_each_piece would give, without its loop.
        const TransferPoint* p = points.data();
        const std::size_t n = points.size();
        const bool up = s_front < s_back;
        // for_each_piece's interval of s_front, and its test for a breakpoint before s_back.
        const auto below = [](double v, const TransferPoint& q) { return v < q.s; };
        const auto above = [](const TransferPoint& q, double v) { return q.s < v; };
        const std::size_t j = static_cast<std::size_t>(
            (up ? std::upper_bound(p, p + n, s_front, below) : std::lower_bound(p, p + n, s_front, above)) - p);
        if (up ? (j == n || !(p[j].s < s_back)) : (j == 0 || !(p[j - 1].s > s_back))) {
            const Sample v0 = on_interval(p, n, j, s_front), v1 = on_interval(p, n, j, s_back);
            return detail::one_piece(length * v0.sigma, length * v1.sigma, v0.c, v1.c);
        }
    }
    double transmittance = 1.0; // e^{−τ} in front of the current piece
    double tau = 0.0;
    glm::dvec3 color(0.0);
    for_each_piece(points, s_front, s_back, [&](double ds, const Sample& v0, const Sample& v1) {
        const double h = length * (ds / run);
        const double a = h * v0.sigma, b = h * v1.sigma;
        const double depth = 0.5 * a + 0.5 * b;
        tau += depth;
        // No extinction means no emission either (emission is c·σ); nothing behind an opaque
        // piece is seen, but its optical depth still counts.
        if (!(depth > 0.0) || transmittance == 0.0) return;
        const Weights w = piece_weights<true>(a, b);
        color += transmittance * (w.w0 * v0.c + w.w1 * v1.c);
        transmittance *= w.transmittance;
    });
    out.color = color;
    out.optical_depth = tau;
    out.alpha = -std::expm1(-tau); // not 1 − transmittance: keeps tiny alphas accurate
    return out;
}

detail::PieceWeights detail::piece_weights(double a, double b) {
    const Weights w = fx::piece_weights<false>(a, b);
    return {w.w0, w.w1};
}

#if defined(__SSE2__)
// kSeries with each coefficient twice, for SSE2's two lanes.
struct alignas(16) SeriesPairs {
    double inv_fact[kSeriesTerms + 1][2], w0[kSeriesTerms + 1][2], w1[kSeriesTerms + 1][2];
};
constexpr SeriesPairs kSeriesPairs = [] {
    SeriesPairs t{};
    for (std::size_t m = 0; m <= kSeriesTerms; ++m) {
        for (int i = 0; i < 2; ++i) {
            t.inv_fact[m][i] = kSeries.inv_fact[m];
            t.w0[m][i] = kSeries.w0[m];
            t.w1[m][i] = kSeries.w1[m];
        }
    }
    return t;
}();
#endif

void detail::piece_weights_2(const double a[2], const double b[2], PieceWeights out[2]) {
#if defined(__SSE2__)
    // piece_weights<false>'s series for two pieces at once, one per SSE2 lane: the same
    // operations in the same order on each lane (no fused multiply-add on either side), so
    // each lane's weights are the bits piece_weights() gives. A lane's sums are taken when
    // its tail test first passes; it then runs on unused until the other's passes.
    const double a0 = std::min(a[0], kHugeDepth), a1 = std::min(a[1], kHugeDepth);
    const double b0 = std::min(b[0], kHugeDepth), b1 = std::min(b[1], kHugeDepth);
    if (0.5 * a0 + 0.5 * b0 <= kSeriesMax && 0.5 * a1 + 0.5 * b1 <= kSeriesMax) {
        const __m128d half = _mm_set1_pd(0.5);
        const __m128d A = _mm_set_pd(a1, a0);
        const __m128d B = _mm_sub_pd(_mm_mul_pd(half, _mm_set_pd(b1, b0)), _mm_mul_pd(half, A));
        const __m128d sign = _mm_set1_pd(-0.0);
        const __m128d nA = _mm_xor_pd(A, sign); // −A, exactly
        __m128d f_prev = _mm_set1_pd(1.0), f = nA;
        __m128d w0 = _mm_mul_pd(A, _mm_load_pd(kSeriesPairs.w0[1])); // −f·w0[1], f = −A
        __m128d w1 = _mm_mul_pd(A, _mm_load_pd(kSeriesPairs.w1[1]));
        const __m128d two_b = _mm_mul_pd(_mm_set1_pd(2.0), B);
        const __m128d tail = _mm_set1_pd(2e-17);
        const __m128d one = _mm_set1_pd(1.0), two = _mm_set1_pd(2.0);
        __m128d dm = one;
        double r0[2] = {0.0, 0.0}, r1[2] = {0.0, 0.0};
        int taken = 0; // lanes whose sums are taken (bit i: lane i)
        for (std::size_t m = 1; m + 1 < kSeriesTerms; m += 2, dm = _mm_add_pd(dm, two)) {
            const __m128d f2 = _mm_sub_pd(_mm_mul_pd(nA, f), _mm_mul_pd(_mm_mul_pd(two_b, dm), f_prev));
            const __m128d f3 = _mm_sub_pd(_mm_mul_pd(nA, f2), _mm_mul_pd(_mm_mul_pd(two_b, _mm_add_pd(dm, one)), f));
            const __m128d t2 = _mm_mul_pd(f2, _mm_load_pd(kSeriesPairs.inv_fact[m + 1]));
            const __m128d t3 = _mm_mul_pd(f3, _mm_load_pd(kSeriesPairs.inv_fact[m + 2]));
            w0 = _mm_sub_pd(w0, _mm_mul_pd(f2, _mm_load_pd(kSeriesPairs.w0[m + 1])));
            w1 = _mm_sub_pd(w1, _mm_mul_pd(f2, _mm_load_pd(kSeriesPairs.w1[m + 1])));
            w0 = _mm_sub_pd(w0, _mm_mul_pd(f3, _mm_load_pd(kSeriesPairs.w0[m + 2])));
            w1 = _mm_sub_pd(w1, _mm_mul_pd(f3, _mm_load_pd(kSeriesPairs.w1[m + 2])));
            f_prev = f2;
            f = f3;
            const __m128d size = _mm_add_pd(_mm_andnot_pd(sign, t2), _mm_andnot_pd(sign, t3));
            const int done = _mm_movemask_pd(_mm_cmple_pd(size, _mm_mul_pd(tail, _mm_add_pd(w0, w1)))) & ~taken;
            if (done) { // rare: once per lane
                double s0[2], s1[2];
                _mm_storeu_pd(s0, w0);
                _mm_storeu_pd(s1, w1);
                for (int i = 0; i < 2; ++i) {
                    if (done & (1 << i)) r0[i] = s0[i], r1[i] = s1[i];
                }
                taken |= done;
                if (taken == 3) break;
            }
        }
        if (taken != 3) { // the series' last term reached (as piece_weights' loop ends there)
            double s0[2], s1[2];
            _mm_storeu_pd(s0, w0);
            _mm_storeu_pd(s1, w1);
            for (int i = 0; i < 2; ++i) {
                if (!(taken & (1 << i))) r0[i] = s0[i], r1[i] = s1[i];
            }
        }
        for (int i = 0; i < 2; ++i) out[i] = {std::max(r0[i], 0.0), std::max(r1[i], 0.0)};
        return;
    }
#endif
    for (int i = 0; i < 2; ++i) out[i] = piece_weights(a[i], b[i]);
}

glm::dvec3 cumulative_emission(const TransferFunction& tf, double s) {
    const std::vector<TransferPoint>& points = tf.points();
    if (points.empty()) return glm::dvec3(0.0);
    const double s0 = points.front().s;
    if (s == s0) return glm::dvec3(0.0);
    if (s < s0) return (s - s0) * (points.front().color * points.front().sigma); // held end value
    glm::dvec3 sum(0.0);
    for_each_piece(points, s0, s, [&](double ds, const Sample& v0, const Sample& v1) { sum += ds * mean_emission(v0, v1); });
    return sum;
}

EmissionTable build_emission_table(const TransferFunction& tf, std::size_t size) {
    require_table(size >= 2, "an emission table needs at least 2 samples, got " + std::to_string(size));
    EmissionTable table;
    table_range(tf, table.s_lo, table.s_hi);
    table.cumulative.resize(size);
    const double step = (table.s_hi - table.s_lo) / static_cast<double>(size - 1);
    // Accumulate piece by piece between samples (O(log n) each), starting from E(s_lo).
    glm::dvec3 e = cumulative_emission(tf, table.s_lo);
    double s_prev = table.s_lo;
    table.cumulative[0] = glm::vec3(e);
    for (std::size_t i = 1; i < size; ++i) {
        const double s = i + 1 == size ? table.s_hi : table.s_lo + static_cast<double>(i) * step;
        e += emission_integral(tf, s_prev, s, s - s_prev); // length = run: per unit scalar
        table.cumulative[i] = glm::vec3(e);
        s_prev = s;
    }
    return table;
}

void build_emission_rows(const TransferFunction& tf, std::size_t size, std::vector<glm::vec4>& texels, double& s_lo,
                         double& s_hi) {
    const EmissionTable emission = build_emission_table(tf, size);
    std::vector<TransferPoint> white = tf.points(); // unit colour: E is then ∫σ
    for (TransferPoint& p : white) p.color = glm::dvec3(1.0);
    const EmissionTable extinction = build_emission_table(TransferFunction(white), size);
    s_lo = emission.s_lo;
    s_hi = emission.s_hi;
    texels.resize(2 * size);
    for (std::size_t i = 0; i < size; ++i) {
        texels[i] = glm::vec4(emission.cumulative[i], extinction.cumulative[i].x);
        // The held end values outside the table come from these.
        const double s = i + 1 == size ? s_hi : s_lo + (s_hi - s_lo) * double(i) / double(size - 1);
        texels[size + i] = glm::vec4(glm::vec3(tf.emission(s)), float(tf.sigma(s)));
    }
    require_float_emission_tables(tf, emission, extinction);
}

void require_float_emission_tables(const TransferFunction& tf, const EmissionTable& emission,
                                   const EmissionTable& extinction) {
    double largest = 0.0;
    for (std::size_t i = 0; i < emission.cumulative.size(); ++i) {
        const glm::vec3 e = glm::abs(emission.cumulative[i]);
        largest = std::max({largest, double(e.x), double(e.y), double(e.z), double(std::abs(extinction.cumulative[i].x))});
    }
    const double samples = double(emission.cumulative.size());
    for (const TransferPoint& p : tf.points())
        largest = std::max({largest, p.sigma * samples, p.color.x * p.sigma * samples, p.color.y * p.sigma * samples,
                            p.color.z * p.sigma * samples});
    if (!(largest <= kMaxTableValue)) {
        throw Error("transfer function: its emission c·sigma integrated over the scalar range [" +
                    short_number(emission.s_lo) + ", " + short_number(emission.s_hi) + "] reaches " +
                    short_number(largest) + ", beyond the " + short_number(kMaxTableValue) +
                    " that the GPU paths' float tables hold: lower sigma or the colours, or the field's range "
                    "(the scan-line renderer draws it)");
    }
}

PreintegrationTable build_preintegration_table(const TransferFunction& tf, std::size_t n_s, std::size_t n_l,
                                               double max_length) {
    require_table(n_s >= 2 && n_l >= 2, "a pre-integration table needs n_s, n_l >= 2, got " + std::to_string(n_s) +
                                            ", " + std::to_string(n_l));
    require_table(std::isfinite(max_length) && max_length > 0.0, "max_length must be finite and positive");
    PreintegrationTable table;
    table_range(tf, table.s_lo, table.s_hi);
    table.max_length = max_length;
    table.n_s = n_s;
    table.n_l = n_l;
    table.entries.resize(n_s * n_s * n_l);
    const auto s_at = [&](std::size_t i) {
        return i + 1 == n_s ? table.s_hi
                            : table.s_lo + (table.s_hi - table.s_lo) * (static_cast<double>(i) / static_cast<double>(n_s - 1));
    };
    // l = 0: the mean extinction σ̄ (kept in double for the other lengths) and emission.
    std::vector<double> sigma_mean(n_s * n_s);
    for (std::size_t ib = 0; ib < n_s; ++ib) {
        for (std::size_t i_f = 0; i_f < n_s; ++i_f) {
            const std::size_t k = ib * n_s + i_f;
            sigma_mean[k] = emission_absorption(tf, s_at(i_f), s_at(ib), 1.0).optical_depth;
            table.entries[k] = glm::vec4(glm::vec3(emission_integral(tf, s_at(i_f), s_at(ib), 1.0)), float(sigma_mean[k]));
        }
    }
    for (std::size_t il = 1; il < n_l; ++il) {
        const double l = il + 1 == n_l ? max_length : max_length * (static_cast<double>(il) / static_cast<double>(n_l - 1));
        for (std::size_t ib = 0; ib < n_s; ++ib) {
            for (std::size_t i_f = 0; i_f < n_s; ++i_f) {
                const std::size_t k = ib * n_s + i_f;
                const SegmentColor c = emission_absorption(tf, s_at(i_f), s_at(ib), l);
                // Where alpha underflows (or σ is 0 throughout) M keeps its limit at l = 0.
                glm::vec4& e = table.entries[il * n_s * n_s + k];
                e = table.entries[k];
                if (c.alpha > 0.0) e = glm::vec4(glm::vec3(c.color * (sigma_mean[k] / c.alpha)), e.a);
            }
        }
    }
    return table;
}

} // namespace cellfx::fx
