// Segment integrals against closed forms and against adaptive quadrature of the defining
// integrals (never against the closed forms in segment_integral.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <glm/common.hpp>

#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"
#include "fx/transfer_function.hpp"
#include "transfer/special_functions.hpp"
#include "cellfx_names.hpp"

namespace {

using glm::dvec3;

// ---- adaptive Gauss–Legendre quadrature -------------------------------------------------

struct GaussLegendre {
    static constexpr int n = 10;
    std::array<double, n> x{}, w{};
    GaussLegendre() {
        // Newton on P_n from the Chebyshev guesses: nodes and weights to full precision.
        for (int i = 0; i < n; ++i) {
            double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = z;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (z * p1 - p0) / (z * z - 1.0);
                const double dz = p1 / dp;
                z -= dz;
                if (std::abs(dz) < 1e-17) break;
            }
            x[i] = z;
            w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        }
    }
};
const GaussLegendre& gl() {
    static const GaussLegendre g;
    return g;
}

template <class T> double magnitude(const T& v);
template <> double magnitude(const double& v) { return std::abs(v); }
template <> double magnitude(const dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

template <class T> T gauss(const std::function<T(double)>& f, double a, double b) {
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    T sum{};
    for (int i = 0; i < GaussLegendre::n; ++i) sum += gl().w[i] * f(mid + half * gl().x[i]);
    return sum * half;
}

// Bisects until the two halves agree with the whole to `tol` per unit length (absolute) or to
// 1e-13 relative. That bounds the error of the coarser whole; the accepted halves are far more
// accurate (10-point Gauss–Legendre on a smooth piece), and the relative floor keeps rounding
// noise from driving the bisection. All integrands here are non-negative.
template <class T>
T adapt(const std::function<T(double)>& f, double a, double b, T whole, double tol_per_length, int depth) {
    const double m = 0.5 * (a + b);
    const T left = gauss<T>(f, a, m), right = gauss<T>(f, m, b);
    const double err = magnitude<T>(left + right - whole);
    if (depth > 60 || err <= tol_per_length * (b - a) || err <= 1e-13 * magnitude<T>(left + right)) return left + right;
    return adapt<T>(f, a, m, left, tol_per_length, depth + 1) + adapt<T>(f, m, b, right, tol_per_length, depth + 1);
}

template <class T> T integrate(const std::function<T(double)>& f, double a, double b, double tol_per_length) {
    if (!(b > a)) return T{};
    return adapt<T>(f, a, b, gauss<T>(f, a, b), tol_per_length, 0);
}

// ---- reference integrals from the definitions -------------------------------------------

struct Reference {
    dvec3 color{0.0}, emission{0.0};
    double tau = 0.0;
};

// colour = ∫₀ˡ c σ e^{−∫₀ᵗσ} dt, emission = ∫₀ˡ c σ dt, τ = ∫₀ˡ σ, with the scalar linear from
// s_f to s_b. The integration is split where the scalar crosses a control point (the integrand
// has a kink or a jump there), and the inner optical depth is itself a quadrature.
Reference reference(const fx::TransferFunction& tf, double s_f, double s_b, double l, double tol = 1e-15) {
    const auto s_of = [&](double t) { return s_f + (s_b - s_f) * (t / l); };
    std::vector<double> cuts{0.0, l};
    for (const fx::TransferPoint& p : tf.points())
        if ((p.s - s_f) * (p.s - s_b) < 0.0) cuts.push_back(l * ((p.s - s_f) / (s_b - s_f)));
    std::sort(cuts.begin(), cuts.end());
    const std::function<double(double)> sigma = [&](double t) { return tf.sigma(s_of(t)); };
    // Between cuts σ is linear in t, so one 10-point Gauss–Legendre rule integrates it exactly.
    const auto depth = [&](double a, double b) { return b > a ? gauss<double>(sigma, a, b) : 0.0; };
    Reference r;
    double tau_start = 0.0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        const double t0 = cuts[i], t1 = cuts[i + 1];
        const double transmittance_start = std::exp(-tau_start);
        const std::function<dvec3(double)> glow = [&](double t) {
            const double tau = depth(t0, t);
            return tf.color(s_of(t)) * tf.sigma(s_of(t)) * std::exp(-tau);
        };
        const std::function<dvec3(double)> emit = [&](double t) { return tf.color(s_of(t)) * tf.sigma(s_of(t)); };
        r.color += transmittance_start * integrate<dvec3>(glow, t0, t1, tol);
        r.emission += integrate<dvec3>(emit, t0, t1, tol);
        tau_start += depth(t0, t1);
    }
    r.tau = tau_start;
    return r;
}

// |got − want| within `rel` of |want| or of `scale` (the natural size of the quantity).
bool near(double got, double want, double rel, double scale) {
    return std::abs(got - want) <= rel * std::max(std::abs(want), scale);
}
bool near(const dvec3& got, const dvec3& want, double rel, double scale) {
    return near(got.x, want.x, rel, scale) && near(got.y, want.y, rel, scale) && near(got.z, want.z, rel, scale);
}

fx::TransferFunction random_tf(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const int n = 1 + static_cast<int>(rng() % 7);
    std::vector<double> s(static_cast<std::size_t>(n));
    for (double& v : s) v = -1.0 + 3.0 * u01(rng);
    std::sort(s.begin(), s.end());
    for (std::size_t i = 1; i < s.size(); ++i) // some steps (never three at one s)
        if (u01(rng) < 0.25 && (i < 2 || s[i - 2] != s[i - 1])) s[i] = s[i - 1];
    std::vector<fx::TransferPoint> points;
    for (double v : s) {
        const double sigma = u01(rng) < 0.15 ? 0.0 : std::pow(10.0, -2.0 + 3.5 * u01(rng));
        points.push_back({v, dvec3(u01(rng), u01(rng), u01(rng)), sigma});
    }
    return fx::TransferFunction(points);
}

// A single linear piece s ∈ [0, 1]: red at the front end (s = 0), green at the back end.
fx::TransferFunction red_to_green(double sigma0, double sigma1) {
    return fx::TransferFunction({{0.0, dvec3(1, 0, 0), sigma0}, {1.0, dvec3(0, 1, 0), sigma1}});
}

} // namespace

TEST_CASE("erfcx and Dawson's function match their defining integrals", "[transfer]") {
    for (double x : {0.0, 1e-9, 0.3, 1.0, 4.0, 20.0, 25.99, 26.01, 40.0, 1e3, 1e8}) {
        // erfcx(x) = (2/√π)∫₀^∞ e^{−t(t+2x)} dt; the integrand is below e^{−100} of its peak past
        // t = min(27, 50/x), which keeps the peak where the first Gauss rule sees it.
        const std::function<double(double)> f = [x](double t) { return std::exp(-t * (t + 2.0 * x)); };
        const double want = 2.0 / std::sqrt(M_PI) * integrate<double>(f, 0.0, std::min(27.0, 50.0 / x), 0.0);
        INFO("x = " << x);
        CHECK(near(fx::detail::erfcx(x), want, 1e-13, 0.0));
    }
    CHECK(fx::detail::erfcx(1e300) > 0.0);
    CHECK(fx::detail::erfcx(1e300) < 1e-300);
    for (double x : {1e-9, 0.1, 0.4999, 0.5, 0.5001, 0.9241, 1.0, 2.5, 7.0, 20.0, 49.99, 50.01, 300.0, 1e7}) {
        // D(x) = ∫₀ˣ e^{y²−x²} dy = ∫₀ˣ e^{−d(2x−d)} dd with d = x − y (so the nodes near the
        // peak are exact); past d = 50/x the integrand is under e^{−50}.
        const std::function<double(double)> f = [x](double d) { return std::exp(-d * (2.0 * x - d)); };
        INFO("x = " << x);
        CHECK(near(fx::detail::dawson(x), integrate<double>(f, 0.0, std::min(x, 50.0 / x), 0.0), 1e-13, 0.0));
    }
}

TEST_CASE("constant medium: I = c(1 − e^(−σl)) in every regime", "[transfer]") {
    const dvec3 c(0.9, 0.5, 0.125);
    for (double sigma : {0.0, 1e-300, 1e-12, 1e-3, 0.3, 0.5, 0.7, 1.0, 30.0, 1e4, fx::kMaxSigma}) {
        for (double l : {1e-300, 1e-9, 1.0, 7.5}) {
            const fx::TransferFunction tf = fx::TransferFunction::constant(c, sigma);
            const double tau = sigma * l;
            const double alpha = -std::expm1(-tau);
            INFO("sigma = " << sigma << ", l = " << l);
            // Relative checks, with an absolute floor of 1e-304 for products that are subnormal.
            const double floor = 1e-290;
            for (auto [sf, sb] : {std::pair{0.0, 0.0}, {-3.0, 5.0}, {2.0, -1.0}}) {
                const fx::SegmentColor r = fx::emission_absorption(tf, sf, sb, l);
                CHECK(near(r.optical_depth, tau, 1e-14, floor));
                CHECK(near(r.alpha, alpha, 1e-14, floor));
                CHECK(near(r.color, c * alpha, 1e-13, floor));
                CHECK(near(fx::emission_integral(tf, sf, sb, l), c * tau, 1e-14, floor));
            }
        }
    }
}

TEST_CASE("linear sigma with constant colour: I = c(1 − e^(−l(σf+σb)/2))", "[transfer]") {
    const dvec3 c(0.25, 1.0, 0.5);
    for (auto [s0, s1] : {std::pair{0.0, 1.0}, {1.0, 0.0}, {0.2, 0.2 + 1e-13}, {1e-9, 3.0}, {5.0, 1e-6},
                          {100.0, 0.0}, {0.0, 1e4}, {1e4, 1e-3}, {1e-12, 0.0}}) {
        const fx::TransferFunction tf({{0.0, c, s0}, {1.0, c, s1}});
        for (double l : {1e-6, 0.1, 1.0, 4.0}) {
            const double tau = l * (s0 + s1) / 2.0;
            INFO("sigma " << s0 << " -> " << s1 << ", l = " << l);
            for (auto [sf, sb] : {std::pair{0.0, 1.0}, {1.0, 0.0}}) {
                const fx::SegmentColor r = fx::emission_absorption(tf, sf, sb, l);
                CHECK(near(r.optical_depth, tau, 1e-14, 0.0));
                CHECK(near(r.color, -std::expm1(-tau) * c, 1e-12, 0.0));
            }
        }
    }
}

TEST_CASE("emission-only integrals of products of linear functions", "[transfer]") {
    // red: (1 − s)·2s, green: s·2s over s ∈ [0, 1]; ∫ = 1/3 and 2/3, times l/Δs = 3.
    const fx::TransferFunction tf({{0.0, dvec3(1, 0, 0), 0.0}, {1.0, dvec3(0, 1, 0), 2.0}});
    CHECK(near(fx::emission_integral(tf, 0.0, 1.0, 3.0), dvec3(1.0, 2.0, 0.0), 1e-15, 0.0));
    CHECK(near(fx::emission_integral(tf, 1.0, 0.0, 3.0), dvec3(1.0, 2.0, 0.0), 1e-15, 0.0));
    // Half the run, s ∈ [0, 0.5], l = 1: red ∫₀^½ 2s(1−s)ds·2 = (1/4 − 1/12)·2 = 1/3,
    // green ∫₀^½ 2s² ds·2 = 1/6.
    CHECK(near(fx::emission_integral(tf, 0.5, 0.0, 1.0), dvec3(1.0 / 3.0, 1.0 / 6.0, 0.0), 1e-15, 0.0));
    // Held ends: beyond s = 1 the emission is green·2; below 0 it is zero.
    CHECK(near(fx::emission_integral(tf, 2.0, 5.0, 0.5), dvec3(0.0, 1.0, 0.0), 1e-15, 0.0));
    CHECK(fx::emission_integral(tf, -5.0, -2.0, 0.5) == dvec3(0.0));
    // Across the end: s from −1 to 1 over l = 2 is half outside (zero), half the full integral.
    CHECK(near(fx::emission_integral(tf, -1.0, 1.0, 2.0), dvec3(1.0 / 3.0, 2.0 / 3.0, 0.0), 1e-15, 0.0));
    CHECK(fx::emission_integral(tf, 0.0, 1.0, 0.0) == dvec3(0.0));
    // The GPU form l·(E(s_b) − E(s_f))/(s_b − s_f) agrees.
    for (auto [sf, sb] : {std::pair{0.0, 1.0}, {0.3, 0.9}, {-1.0, 1.5}, {2.0, 0.25}}) {
        const dvec3 e = 1.7 * (fx::cumulative_emission(tf, sb) - fx::cumulative_emission(tf, sf)) / (sb - sf);
        CHECK(near(fx::emission_integral(tf, sf, sb, 1.7), e, 1e-13, 1e-15));
    }
}

TEST_CASE("linear colour, constant sigma: analytic colour up to huge extinction", "[transfer]") {
    // ∫₀ˡ (c₀ + (c₁−c₀)t/l)σe^{−σt} dt = c₀(1 − e^{−σl}) + (c₁−c₀)[(1 − e^{−σl})/(σl) − e^{−σl}]
    const dvec3 c0(1, 0, 0.5), c1(0, 1, 0.5);
    for (double sl : {1e-12, 1e-6, 0.01, 0.49, 0.51, 2.0, 50.0, 1e4, 1e8}) {
        const fx::TransferFunction tf({{0.0, c0, sl}, {1.0, c1, sl}});
        const double alpha = -std::expm1(-sl);
        // (1 − e^{−x})/x − e^{−x} = Σ_{n≥1} (−1)^{n+1}·n·xⁿ/(n+1)!, summed directly for small x
        // where the difference cancels.
        double bracket = alpha / sl - std::exp(-sl);
        if (sl < 0.01) {
            bracket = 0.0;
            double power = 1.0, fact = 1.0;
            for (int n = 1; n < 12; ++n) {
                power *= -sl;
                fact *= n + 1;
                bracket -= n * power / fact;
            }
        }
        const dvec3 want = c0 * alpha + (c1 - c0) * bracket;
        const fx::SegmentColor r = fx::emission_absorption(tf, 0.0, 1.0, 1.0);
        INFO("sigma l = " << sl);
        CHECK(near(r.color, want, 1e-11, 0.0));
        CHECK(near(r.alpha, alpha, 1e-15, 0.0));
    }
}

TEST_CASE("piece weights match quadrature across every regime of front and back extinction", "[transfer]") {
    // One linear piece, red at the front, green at the back: red = w₀, green = w₁. Checked
    // relative to the opacity, so tiny alphas are held to the same relative accuracy.
    const std::vector<double> values{0.0, 1e-10, 1e-5, 0.01, 0.3, 0.49, 0.51, 0.9, 1.0, 1.0 + 1e-9, 3.0, 20.0, 300.0};
    double worst = 0.0;
    for (double a : values)
        for (double b : values) {
            if (a == 0.0 && b == 0.0) continue;
            const fx::TransferFunction tf = red_to_green(a, b);
            const fx::SegmentColor r = fx::emission_absorption(tf, 0.0, 1.0, 1.0);
            const Reference ref = reference(tf, 0.0, 1.0, 1.0);
            INFO("sigma " << a << " -> " << b);
            const double scale = -std::expm1(-ref.tau);
            CHECK(near(r.color, ref.color, 1e-10, scale));
            CHECK(near(r.alpha, scale, 1e-13, 0.0));
            for (int ch = 0; ch < 2; ++ch) worst = std::max(worst, std::abs(r.color[ch] - ref.color[ch]) / scale);
        }
    CHECK(worst < 1e-10);
    WARN("largest colour error relative to alpha: " << worst);
}

TEST_CASE("random transfer functions and segments match quadrature", "[transfer]") {
    std::mt19937_64 rng(20240611);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    double worst_color = 0.0, worst_emission = 0.0;
    for (int trial = 0; trial < 300; ++trial) {
        const fx::TransferFunction tf = random_tf(rng);
        const auto& pts = tf.points();
        double sf = -1.5 + 4.0 * u01(rng), sb = -1.5 + 4.0 * u01(rng);
        const double pick = u01(rng);
        if (pick < 0.1) sb = sf;                                          // s_f == s_b
        else if (pick < 0.25) sf = pts[rng() % pts.size()].s;             // starts on a breakpoint
        else if (pick < 0.35) sb = pts[rng() % pts.size()].s;             // ends on one
        const double l = std::pow(10.0, -3.0 + 4.0 * u01(rng));
        const fx::SegmentColor r = fx::emission_absorption(tf, sf, sb, l);
        const Reference ref = reference(tf, sf, sb, l);
        const double alpha = -std::expm1(-ref.tau);
        INFO("trial " << trial << ": s " << sf << " -> " << sb << ", l = " << l << ", points " << pts.size());
        REQUIRE(near(r.optical_depth, ref.tau, 1e-12, 0.0));
        REQUIRE(near(r.alpha, alpha, 1e-12, 0.0));
        REQUIRE(near(r.color, ref.color, 1e-9, alpha));
        const dvec3 e = fx::emission_integral(tf, sf, sb, l);
        REQUIRE(near(e, ref.emission, 1e-12, 0.0));
        for (int ch = 0; ch < 3; ++ch) {
            worst_color = std::max(worst_color, std::abs(r.color[ch] - ref.color[ch]) / std::max(alpha, 1e-300));
            worst_emission = std::max(worst_emission, std::abs(e[ch] - ref.emission[ch]) / std::max(ref.emission[ch], 1e-300));
        }
        // Reversing the segment keeps τ and α but not, in general, the colour.
        const fx::SegmentColor rev = fx::emission_absorption(tf, sb, sf, l);
        REQUIRE(near(rev.optical_depth, r.optical_depth, 1e-13, 0.0));
        REQUIRE(near(rev.color, reference(tf, sb, sf, l).color, 1e-9, alpha));
    }
    WARN("largest errors: colour " << worst_color << " (of alpha), emission " << worst_emission << " (relative)");
}

TEST_CASE("l -> 0 goes smoothly to zero and to the emission integral", "[transfer]") {
    const fx::TransferFunction tf({{0.0, dvec3(1, 0.2, 0), 3.0}, {0.5, dvec3(0, 1, 0), 0.5}, {1.0, dvec3(0, 0, 1), 8.0}});
    for (auto [sf, sb] : {std::pair{0.1, 0.9}, {0.9, 0.1}, {0.5, 0.5}}) {
        CHECK(fx::emission_absorption(tf, sf, sb, 0.0).color == dvec3(0.0));
        CHECK(fx::emission_absorption(tf, sf, sb, 0.0).alpha == 0.0);
        CHECK(fx::emission_absorption(tf, sf, sb, -1.0).alpha == 0.0);
        for (double l : {1e-300, 1e-100, 1e-20, 1e-9}) {
            const fx::SegmentColor r = fx::emission_absorption(tf, sf, sb, l);
            const dvec3 e = fx::emission_integral(tf, sf, sb, l);
            INFO("l = " << l);
            // colour = emission·(1 − O(τ)), τ ≤ 8l
            CHECK(near(r.color, e, 1e-8, 0.0));
            CHECK(near(r.alpha, r.optical_depth, 1e-8, 0.0));
            CHECK(r.alpha > 0.0);
        }
    }
}

TEST_CASE("tiny extinction: alpha ≈ σl without cancellation", "[transfer]") {
    const fx::TransferFunction tf({{0.0, dvec3(1, 1, 1), 1e-12}, {1.0, dvec3(0.5, 0.25, 1), 3e-12}});
    const fx::SegmentColor r = fx::emission_absorption(tf, 0.0, 1.0, 1.0);
    CHECK(near(r.alpha, 2e-12, 1e-6, 0.0));
    CHECK(near(r.optical_depth, 2e-12, 1e-12, 0.0));
    // ∫ cσ with c, σ linear: (2c₀σ₀ + c₀σ₁ + c₁σ₀ + 2c₁σ₁)/6
    const dvec3 e = (dvec3(1.0) * (2e-12 + 3e-12) + dvec3(0.5, 0.25, 1) * (1e-12 + 6e-12)) / 6.0;
    CHECK(near(r.color, e, 1e-6, 0.0));
    const fx::SegmentColor flat = fx::emission_absorption(fx::TransferFunction::constant(dvec3(1), 1.0), 0, 0, 1e-12);
    CHECK(near(flat.alpha, 1e-12, 1e-11, 0.0));
}

TEST_CASE("huge extinction: alpha 1, colour the front colour, everything finite", "[transfer]") {
    const dvec3 c0(1, 0, 0), c1(0, 0, 1);
    for (double big : {1e4, 1e20, fx::kMaxSigma}) { // the largest a transfer function holds
        for (auto [s0, s1] : {std::pair{big, big}, {0.0, big}, {big, 0.0}, {big, 1.0}}) {
            const fx::TransferFunction tf({{0.0, c0, s0}, {1.0, c1, s1}});
            for (double l : {1.0, 1e10}) {
                const fx::SegmentColor r = fx::emission_absorption(tf, 0.0, 1.0, l);
                INFO("sigma " << s0 << " -> " << s1 << ", l = " << l);
                CHECK(r.alpha == 1.0);
                CHECK(std::isfinite(r.color.r));
                CHECK(std::isfinite(r.color.b));
                // All the light comes from near the front: within a depth ~1/√(σ′) there.
                CHECK(r.color.r == Approx(1.0).margin(2e-2));
                CHECK(r.color.b == Approx(0.0).margin(2e-2));
                CHECK(r.optical_depth >= 1e4 * 0.5);
            }
        }
    }
    // σl = 1e4 exactly: colour c₀ + (c₁ − c₀)/(σl) to first order.
    const fx::TransferFunction tf({{0.0, c0, 1e4}, {1.0, c1, 1e4}});
    CHECK(near(fx::emission_absorption(tf, 0.0, 1.0, 1.0).color, c0 + (c1 - c0) * 1e-4, 1e-12, 0.0));
    // Something behind an opaque piece adds nothing, and the optical depth still adds up.
    const fx::TransferFunction two({{0.0, c0, fx::kMaxSigma}, {0.5, c0, fx::kMaxSigma}, {0.5, c1, 1.0}, {1.0, c1, 1.0}});
    const fx::SegmentColor r = fx::emission_absorption(two, 0.0, 1.0, 1e300);
    CHECK(r.color == dvec3(1, 0, 0));
    CHECK(std::isinf(r.optical_depth));
}

TEST_CASE("a segment spanning a step matches the two-slab closed form", "[transfer]") {
    const dvec3 red(1, 0, 0), blue(0, 0, 1);
    const fx::TransferFunction tf({{0.0, red, 1.0}, {0.5, red, 1.0}, {0.5, blue, 4.0}, {1.0, blue, 4.0}});
    for (double l : {0.01, 1.0, 6.0}) {
        const double a = 1.0 * l / 2, b = 4.0 * l / 2; // optical depths of the two halves
        INFO("l = " << l);
        const fx::SegmentColor fwd = fx::emission_absorption(tf, 0.0, 1.0, l);
        CHECK(near(fwd.color, red * -std::expm1(-a) + std::exp(-a) * blue * -std::expm1(-b), 1e-14, 0.0));
        const fx::SegmentColor rev = fx::emission_absorption(tf, 1.0, 0.0, l);
        CHECK(near(rev.color, blue * -std::expm1(-b) + std::exp(-b) * red * -std::expm1(-a), 1e-14, 0.0));
        CHECK(near(fwd.alpha, -std::expm1(-(a + b)), 1e-15, 0.0));
        // Starting or ending exactly on the step takes the value on the segment's side.
        CHECK(near(fx::emission_absorption(tf, 0.5, 1.0, l).color, blue * -std::expm1(-4.0 * l), 1e-14, 0.0));
        CHECK(near(fx::emission_absorption(tf, 0.5, 0.0, l).color, red * -std::expm1(-l), 1e-14, 0.0));
        CHECK(near(fx::emission_absorption(tf, 0.0, 0.5, l).color, red * -std::expm1(-l), 1e-14, 0.0));
        CHECK(near(fx::emission_absorption(tf, 1.0, 0.5, l).color, blue * -std::expm1(-4.0 * l), 1e-14, 0.0));
        // s_f == s_b on the step: the value from above, as TransferFunction::color.
        CHECK(near(fx::emission_absorption(tf, 0.5, 0.5, l).color, blue * -std::expm1(-4.0 * l), 1e-14, 0.0));
        // Splitting at the step and compositing gives the same.
        const fx::SegmentColor split = fx::composite(fx::emission_absorption(tf, 0.0, 0.5, l / 2),
                                                     fx::emission_absorption(tf, 0.5, 1.0, l / 2));
        CHECK(near(split.color, fwd.color, 1e-14, 0.0));
        CHECK(near(split.alpha, fwd.alpha, 1e-14, 0.0));
        CHECK(near(split.optical_depth, fwd.optical_depth, 1e-15, 0.0));
    }
    CHECK(fx::segment_maximum(tf, 0.0, 1.0) == dvec3(1, 0, 4));
    CHECK(fx::segment_maximum(tf, 0.0, 0.5) == dvec3(1, 0, 0));   // ends on the step from below
    CHECK(fx::segment_maximum(tf, 1.0, 0.5) == dvec3(0, 0, 4));   // from above
    CHECK(fx::segment_maximum(tf, 0.5, 0.5) == dvec3(0, 0, 4));   // right-continuous
}

TEST_CASE("scalars outside the transfer function hold the end values", "[transfer]") {
    const dvec3 c0(1, 0.5, 0), c1(0, 0.5, 1);
    const fx::TransferFunction tf({{0.0, c0, 2.0}, {1.0, c1, 0.5}});
    for (double l : {0.1, 3.0}) {
        CHECK(near(fx::emission_absorption(tf, -3.0, -1.0, l).color, c0 * -std::expm1(-2.0 * l), 1e-14, 0.0));
        CHECK(near(fx::emission_absorption(tf, 7.0, 1.0, l).color, c1 * -std::expm1(-0.5 * l), 1e-14, 0.0));
        // Partly outside: the in-range part against quadrature.
        const fx::SegmentColor r = fx::emission_absorption(tf, -0.5, 1.5, l);
        CHECK(near(r.color, reference(tf, -0.5, 1.5, l).color, 1e-10, r.alpha));
    }
    CHECK(fx::segment_maximum(tf, 5.0, 9.0) == c1 * 0.5);
    CHECK(fx::segment_maximum(tf, -9.0, -5.0) == c0 * 2.0);
}

TEST_CASE("tiny and huge scalar spacings give the same integrals as unit spacing", "[transfer]") {
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
        const fx::TransferFunction unit = random_tf(rng).rescaled(0.0, 1.0);
        const double sf = -0.2 + 1.4 * u01(rng), sb = -0.2 + 1.4 * u01(rng), l = 0.1 + 3.0 * u01(rng);
        const fx::SegmentColor want = fx::emission_absorption(unit, sf, sb, l);
        const Reference ref = reference(unit, sf, sb, l);
        REQUIRE(near(want.color, ref.color, 1e-9, want.alpha));
        // Control points 1e-7 apart near s = 1, and 1e7 apart near s = −3e7.
        for (auto [lo, hi] : {std::pair{1.0, 1.0 + 1e-7 * unit.points().size()}, {-3e7, -3e7 + 1e7 * unit.points().size()}}) {
            const fx::TransferFunction scaled = unit.rescaled(lo, hi);
            const auto map = [&](double s) { return lo + s * (hi - lo); };
            const fx::SegmentColor got = fx::emission_absorption(scaled, map(sf), map(sb), l);
            INFO("trial " << trial << " range [" << lo << ", " << hi << "]");
            // The scalar positions themselves are only good to ~1e-16·|s| / spacing.
            const double rel = lo == 1.0 ? 1e-7 : 1e-9;
            CHECK(near(got.color, ref.color, rel, want.alpha));
            CHECK(near(got.optical_depth, ref.tau, rel, 0.0));
            CHECK(near(fx::emission_integral(scaled, map(sf), map(sb), l), ref.emission, rel, 1e-300));
        }
    }
}

TEST_CASE("segment maximum is the largest emission on the scalar interval", "[transfer]") {
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int trial = 0; trial < 100; ++trial) {
        const fx::TransferFunction tf = random_tf(rng);
        const double sf = -1.5 + 4.0 * u01(rng), sb = -1.5 + 4.0 * u01(rng);
        const double lo = std::min(sf, sb), hi = std::max(sf, sb);
        // Dense sampling inside each piece, up to 1e-12 of each end (so one-sided values count).
        std::vector<double> cuts{lo, hi};
        for (const fx::TransferPoint& p : tf.points())
            if (p.s > lo && p.s < hi) cuts.push_back(p.s);
        std::sort(cuts.begin(), cuts.end());
        dvec3 sampled(0.0);
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            const double a = cuts[i], w = cuts[i + 1] - cuts[i];
            if (w == 0.0) continue;
            for (int k = 0; k <= 20000; ++k) {
                const double s = a + w * std::clamp(k / 20000.0, 1e-12, 1.0 - 1e-12);
                sampled = glm::max(sampled, tf.emission(s));
            }
        }
        const dvec3 got = fx::segment_maximum(tf, sf, sb);
        INFO("trial " << trial);
        for (int ch = 0; ch < 3; ++ch) {
            CHECK(got[ch] >= sampled[ch] * (1.0 - 1e-9));       // never below a sample
            // and at most a sampling gap above: |f''| ≤ 2·1·32, gap ≤ 4/20000 → ≤ 3.2e-7
            CHECK(got[ch] <= sampled[ch] + 1e-6 * std::max(1.0, sampled[ch]));
        }
        CHECK(fx::segment_maximum(tf, sb, sf) == got);
    }
    // Interior peak: red (1−s) times σ = 4s peaks at s = ½ with value 1.
    const fx::TransferFunction peak({{0.0, dvec3(1, 0, 0), 0.0}, {1.0, dvec3(0, 0, 0), 4.0}});
    CHECK(fx::segment_maximum(peak, 0.0, 1.0).r == Approx(1.0).epsilon(1e-15));
    CHECK(fx::segment_maximum(peak, 0.0, 0.25).r == Approx(0.75).epsilon(1e-15));
}

TEST_CASE("composite is front-to-back over and associative", "[transfer]") {
    const fx::SegmentColor a{dvec3(0.2, 0.1, 0.0), 0.3, -std::log(0.7)};
    const fx::SegmentColor b{dvec3(0.0, 0.4, 0.1), 0.5, -std::log(0.5)};
    const fx::SegmentColor c{dvec3(0.3, 0.0, 0.6), 0.9, -std::log(0.1)};
    const fx::SegmentColor ab = fx::composite(a, b);
    CHECK(near(ab.color, a.color + 0.7 * b.color, 1e-15, 0.0));
    CHECK(near(ab.alpha, 1.0 - 0.7 * 0.5, 1e-15, 0.0));
    CHECK(near(ab.optical_depth, a.optical_depth + b.optical_depth, 1e-15, 0.0));
    const fx::SegmentColor left = fx::composite(ab, c), right = fx::composite(a, fx::composite(b, c));
    CHECK(near(left.color, right.color, 1e-15, 0.0));
    CHECK(near(left.alpha, right.alpha, 1e-15, 0.0));
    const fx::SegmentColor tiny{dvec3(1e-14), 1e-14, 1e-14};
    CHECK(near(fx::composite(tiny, tiny).alpha, 2e-14 - 1e-28, 1e-15, 0.0));
}

TEST_CASE("cumulative emission and the emission table", "[transfer]") {
    const fx::TransferFunction tf({{-1.0, dvec3(1, 0, 0), 1.0}, {0.0, dvec3(0, 1, 0), 3.0}, {0.0, dvec3(0, 0, 1), 1.0},
                                   {2.0, dvec3(1, 1, 1), 0.0}});
    CHECK(fx::cumulative_emission(tf, -1.0) == dvec3(0.0));
    // Linear below the first point with the held emission; the step at 0 is a kink in E.
    CHECK(near(fx::cumulative_emission(tf, -3.0), dvec3(-2, 0, 0), 1e-15, 0.0));
    // ∫_{-1}^{0}: red (−s)·(3 + 2s)… written out: c_r = −s, σ = 3 + 2s → ∫ −s(3+2s) = 3/2 − 2/3.
    CHECK(near(fx::cumulative_emission(tf, 0.0).r, 1.5 - 2.0 / 3.0, 1e-15, 0.0));
    const fx::EmissionTable table = fx::build_emission_table(tf, 301);
    CHECK(table.s_lo == -1.0);
    CHECK(table.s_hi == 2.0);
    REQUIRE(table.cumulative.size() == 301);
    for (std::size_t i = 0; i < table.cumulative.size(); i += 7) {
        const double s = -1.0 + 3.0 * static_cast<double>(i) / 300.0;
        const dvec3 want = fx::cumulative_emission(tf, s);
        CHECK(near(dvec3(table.cumulative[i]), want, 1e-6, 1e-6));
    }
    CHECK_THROWS_AS(fx::build_emission_table(tf, 1), fx::Error);
    // A single-point function: unit range around the point, E linear.
    const fx::EmissionTable flat = fx::build_emission_table(fx::TransferFunction::constant(dvec3(2), 0.5), 3);
    CHECK(flat.s_lo == -0.5);
    CHECK(flat.cumulative[0].x == Approx(-0.5)); // E(s) = (s − 0)·2·0.5
    CHECK(flat.cumulative[2].x == Approx(0.5));
}

TEST_CASE("pre-integration table entries are emission_absorption's mean colour and extinction at the sample points", "[transfer]") {
    const fx::TransferFunction tf({{0.0, dvec3(1, 0, 0), 0.5}, {0.4, dvec3(1, 1, 0), 5.0}, {0.4, dvec3(0, 0, 1), 0.1},
                                   {1.0, dvec3(1, 1, 1), 2.0}});
    const std::size_t n_s = 17, n_l = 5;
    const fx::PreintegrationTable t = fx::build_preintegration_table(tf, n_s, n_l, 2.0);
    REQUIRE(t.entries.size() == n_s * n_s * n_l);
    CHECK(t.n_s == n_s);
    CHECK(t.n_l == n_l);
    CHECK(t.max_length == 2.0);
    for (std::size_t il = 0; il < n_l; ++il)
        for (std::size_t ib = 0; ib < n_s; ib += 3)
            for (std::size_t i_f = 0; i_f < n_s; i_f += 2) {
                const double sf = i_f / 16.0, sb = ib / 16.0, l = 2.0 * il / 4.0;
                const glm::vec4 got = t.entries[(il * n_s + ib) * n_s + i_f];
                // What a reader forms from the entry: τ = σ̄·l, alpha, colour = M·alpha/σ̄.
                const double sigma_mean = fx::emission_absorption(tf, sf, sb, 1.0).optical_depth;
                CHECK(near(got.a, sigma_mean, 1e-6, 0.0));
                if (il == 0) {
                    CHECK(near(dvec3(got), fx::emission_integral(tf, sf, sb, 1.0), 1e-6, 0.0));
                    continue;
                }
                const fx::SegmentColor want = fx::emission_absorption(tf, sf, sb, l);
                const double alpha = 1.0 - std::exp(-double(got.a) * l);
                CHECK(near(alpha, want.alpha, 1e-6, 0.0));
                CHECK(near(dvec3(got) * (alpha / double(got.a)), want.color, 1e-6, 0.0));
            }
    CHECK_THROWS_AS(fx::build_preintegration_table(tf, 1, 4, 1.0), fx::Error);
    CHECK_THROWS_AS(fx::build_preintegration_table(tf, 4, 4, 0.0), fx::Error);
}

TEST_CASE("from transfer samples: the same bits as from the scalars, hinted or not", "[transfer]") {
    // The scan-line renderer looks each crossing up once (transfer_sample) and integrates the
    // segments between crossings from the samples; the frame must not change by a bit.
    std::mt19937_64 rng(20261207);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const auto same = [](const fx::SegmentColor& a, const fx::SegmentColor& b) {
        return a.color == b.color && a.alpha == b.alpha && a.optical_depth == b.optical_depth;
    };
    int on_points = 0, fast = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const fx::TransferFunction tf = random_tf(rng);
        const auto& pts = tf.points();
        auto pick_s = [&]() {
            const double r = u01(rng);
            if (r < 0.3) return pts[rng() % pts.size()].s; // on a point (or a step)
            if (r < 0.4) return pts.front().s - u01(rng);   // a held end
            return -1.5 + 4.0 * u01(rng);
        };
        const double sf = pick_s();
        const double sb = u01(rng) < 0.1 ? sf : pick_s();
        const double l = u01(rng) < 0.05 ? 0.0 : std::pow(10.0, -3.0 + 4.0 * u01(rng));
        const std::size_t hint = rng() % (pts.size() + 2); // right, wrong or out of range
        const fx::TransferSample f = fx::transfer_sample(tf, sf), b = fx::transfer_sample(tf, sb, hint);
        // A hint never changes the sample.
        const fx::TransferSample b0 = fx::transfer_sample(tf, sb);
        REQUIRE(b.down == b0.down);
        REQUIRE(b.up == b0.up);
        REQUIRE(b.c == b0.c);
        REQUIRE(b.sigma == b0.sigma);
        on_points += f.down != f.up ? 1 : 0;
        const bool up = sf < sb;
        fast += (up ? f.up : f.down) != fx::TransferSample::kOnStep && (up ? b.down : b.up) == (up ? f.up : f.down);
        INFO("trial " << trial << ": s " << sf << " -> " << sb << ", l = " << l << ", points " << pts.size());
        REQUIRE(same(fx::emission_absorption(tf, f, b, l), fx::emission_absorption(tf, sf, sb, l)));
        REQUIRE(same(fx::emission_absorption(tf, b, f, l), fx::emission_absorption(tf, sb, sf, l)));
    }
    CHECK(on_points > 1000); // both kinds of segment were tried
    CHECK(fast > 5000);
}

TEST_CASE("alpha of a one-piece segment is 1 − e^(−τ) to a few ulp in every regime", "[transfer]") {
    // One piece sums its colour weights for alpha where the series gives them (τ ≤ 0.5) rather
    // than calling expm1: checked here against expm1 of the optical depth, relative.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    double worst = 0.0;
    for (int trial = 0; trial < 200000; ++trial) {
        const double s0 = std::pow(10.0, -12.0 + 12.5 * u01(rng)) * (u01(rng) < 0.1 ? 0.0 : 1.0);
        const double s1 = std::pow(10.0, -12.0 + 12.5 * u01(rng)) * (u01(rng) < 0.1 ? 0.0 : 1.0);
        const fx::TransferFunction tf({{0.0, dvec3(1, 0.5, 0), s0}, {1.0, dvec3(0, 0.5, 1), s1}});
        const double sf = u01(rng), sb = u01(rng), l = u01(rng);
        const fx::SegmentColor r = fx::emission_absorption(tf, sf, sb, l);
        if (!(r.optical_depth > 0.0)) continue;
        const double want = -std::expm1(-r.optical_depth);
        worst = std::max(worst, std::abs(r.alpha - want) / want);
    }
    WARN("largest relative error of alpha: " << worst);
    CHECK(worst < 1e-15);
}

TEST_CASE("two pieces' colour weights at once: the bits of one at a time", "[transfer]") {
    // The scan-line renderer computes the weights of consecutive segments in pairs
    // (piece_weights_2, two series side by side); each must equal piece_weights' alone.
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    auto rate = [&]() {
        const double r = u01(rng);
        if (r < 0.05) return 0.0;
        if (r < 0.1) return 0.25 + 0.25 * u01(rng); // near the series' limit (T = 0.5)
        return std::pow(10.0, -14.0 + 15.0 * u01(rng));
    };
    int series_pairs = 0;
    for (int trial = 0; trial < 100000; ++trial) {
        double a[2], b[2];
        for (int i = 0; i < 2; ++i) {
            a[i] = rate();
            b[i] = rate();
            if (!(a[i] + b[i] > 0.0)) a[i] = 1e-3;
        }
        fx::detail::PieceWeights w[2];
        fx::detail::piece_weights_2(a, b, w);
        series_pairs += (a[0] + b[0] <= 1.0 && a[1] + b[1] <= 1.0) ? 1 : 0;
        for (int i = 0; i < 2; ++i) {
            const fx::detail::PieceWeights one = fx::detail::piece_weights(a[i], b[i]);
            INFO("trial " << trial << ", piece " << i << ": a " << a[i] << ", b " << b[i]);
            REQUIRE(w[i].w0 == one.w0);
            REQUIRE(w[i].w1 == one.w1);
        }
    }
    CHECK(series_pairs > 50000);
}
