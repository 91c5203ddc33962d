// cellfx — scaled special functions for the Gaussian integrals of segment_integral.cpp.
//
// Based on: Abramowitz & Stegun 7.1.23 (asymptotic erfc) and 7.1.17; G. B. Rybicki, "Dawson's
// integral and the sampling theorem", Computers in Physics 3 (1989) 85 (the sampling-theorem sum,
// as in Numerical Recipes §6.10, here with a finer step for double precision).
//
// Internal (fx/src): header-only so the tests can check them directly.
#pragma once

#include <array>
#include <cmath>

namespace cellfx::fx::detail {

inline constexpr double kInvSqrtPi = 0.56418958354775628695; // 1/√π
inline constexpr double kSqrtPi = 1.77245385090551602730;    // √π

// Scaled complementary error function erfcx(x) = e^{x²}·erfc(x), for x ≥ 0 (the only range the
// segment integrals need). std::erfc underflows near x ≈ 26.5, and e^{x²}·erfc(x) overflows long
// before that cancels, so large x uses the asymptotic series instead.
inline double erfcx(double x) {
    if (!(x < 26.0)) {
        if (x == INFINITY) return 0.0;
        // 1/(x√π)·Σ (−1)ⁿ(2n−1)!!/(2x²)ⁿ; with y ≤ 1/1352 the ninth term is < 2e-19 relative.
        const double y = 0.5 / x / x; // stays finite (possibly 0) for huge x
        const double s =
            1.0 - y * (1.0 - y * (3.0 - y * (15.0 - y * (105.0 - y * (945.0 - y * (10395.0 - y * 135135.0))))));
        return kInvSqrtPi / x * s;
    }
    // e^{x²} with x² split into its rounded value and the rounding error, so the exponential is
    // accurate to a few ulp even where x² ≈ 670.
    const double x2 = x * x;
    const double x2_err = std::fma(x, x, -x2);
    return std::exp(x2) * (1.0 + x2_err) * std::erfc(x);
}

// Dawson's function D(x) = e^{−x²}∫₀ˣ e^{y²} dy, for x ≥ 0.
inline double dawson(double x) {
    if (x < 0.5) {
        // D(x) = Σ (−2x²)ⁿ x/(2n+1)!!: alternating but with ratio ≤ 0.5/(2n+3), no cancellation.
        const double m2x2 = -2.0 * x * x;
        double term = x, sum = x;
        for (int n = 0; n < 40; ++n) {
            term *= m2x2 / (2.0 * n + 3.0);
            sum += term;
            if (std::abs(term) <= 1e-17 * std::abs(sum)) break;
        }
        return sum;
    }
    if (x >= 50.0) {
        if (x == INFINITY) return 0.0;
        // 1/(2x)·Σ (2n−1)!!/(2x²)ⁿ; y ≤ 2e-4, so seven terms reach 1e-19.
        const double y = 0.5 / x / x;
        const double s = 1.0 + y * (1.0 + y * (3.0 + y * (15.0 + y * (105.0 + y * (945.0 + y * 10395.0)))));
        return 0.5 / x * s;
    }
    // Rybicki: D(x) ≈ (1/√π) Σ_{n odd} e^{−(x−nh)²}/n, error ~ e^{−(π/2h)²} (≈ 1e-27 for h = 0.2).
    // Terms beyond |n − n₀| = 35 are below 1e-20 of the sum.
    constexpr double h = 0.2;
    constexpr int kTerms = 18;
    static const std::array<double, kTerms> c = [] {
        std::array<double, kTerms> t{};
        for (int i = 0; i < kTerms; ++i) {
            const double m = (2 * i + 1) * h;
            t[static_cast<std::size_t>(i)] = std::exp(-m * m);
        }
        return t;
    }();
    const int n0 = 2 * static_cast<int>(0.5 * x / h + 0.5); // nearest even multiple of h
    const double xp = x - n0 * h;                           // |xp| ≤ h
    const double e1 = std::exp(2.0 * xp * h);
    const double e2 = e1 * e1;
    double d1 = n0 + 1.0, d2 = n0 - 1.0;
    double ep = e1; // e1^{2i+1}
    double sum = 0.0;
    for (int i = 0; i < kTerms; ++i, d1 += 2.0, d2 -= 2.0, ep *= e2)
        sum += c[static_cast<std::size_t>(i)] * (ep / d1 + 1.0 / (d2 * ep));
    return kInvSqrtPi * std::exp(-xp * xp) * sum;
}

} // namespace cellfx::fx::detail
