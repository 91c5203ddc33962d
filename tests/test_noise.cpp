// Noise: an independent reference implementation, golden values, ranges (sampled and as an
// analytic bound), continuity, lattice zeros, coordinates far from the origin, seeds, batch ==
// scalar bit for bit, fractal settings and their errors, domain warp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "fx/noise.hpp"
#include "noise/noise_lanes.hpp"
#include "noise/noise_fractal.hpp"
#include "noise/noise_kernels.hpp"
#include "cellfx_names.hpp"

namespace {

using glm::dvec2;
using glm::dvec3;
using glm::dvec4;

std::uint32_t bits(float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    return u;
}

// Number of elements whose bit patterns differ (0 = identical, signs of zero included).
std::size_t count_bit_differences(const std::vector<float>& a, const std::vector<float>& b) {
    REQUIRE(a.size() == b.size());
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.size(); ++i) n += bits(a[i]) != bits(b[i]);
    return n;
}

// --- every basis behind one signature -----------------------------------------------------

struct Basis {
    const char* name;
    int dim;
    fx::NoiseBasis basis;
    std::function<float(const fx::Noise&, const double*)> eval;
    double max_slope; // a bound on |∇n|, see the continuity test
};

const std::vector<Basis>& all_bases() {
    // Slopes measured over 4000 random segments at step 1e-3 (near 0 and near 1e7): Perlin ≤ 3.1,
    // simplex ≤ 7.4 output units per input unit. The bounds leave ~40% headroom.
    static const std::vector<Basis> b = {
        {"perlin2", 2, fx::NoiseBasis::perlin, [](const fx::Noise& n, const double* p) { return n.perlin2(p[0], p[1]); }, 4.5},
        {"perlin3", 3, fx::NoiseBasis::perlin, [](const fx::Noise& n, const double* p) { return n.perlin3(p[0], p[1], p[2]); }, 4.5},
        {"perlin4", 4, fx::NoiseBasis::perlin,
         [](const fx::Noise& n, const double* p) { return n.perlin4(p[0], p[1], p[2], p[3]); }, 4.5},
        {"simplex2", 2, fx::NoiseBasis::simplex, [](const fx::Noise& n, const double* p) { return n.simplex2(p[0], p[1]); }, 10.0},
        {"simplex3", 3, fx::NoiseBasis::simplex,
         [](const fx::Noise& n, const double* p) { return n.simplex3(p[0], p[1], p[2]); }, 10.0},
        {"simplex4", 4, fx::NoiseBasis::simplex,
         [](const fx::Noise& n, const double* p) { return n.simplex4(p[0], p[1], p[2], p[3]); }, 10.0},
    };
    return b;
}

float fractal_at(const fx::Noise& n, const fx::Fractal& f, int dim, const double* p) {
    if (dim == 2) return n.fractal2(f, p[0], p[1]);
    if (dim == 3) return n.fractal3(f, p[0], p[1], p[2]);
    return n.fractal4(f, p[0], p[1], p[2], p[3]);
}

// Axes sorted by decreasing offset (the simplex's corner order).
void sort_axes(const double* d, int dim, int* order) {
    for (int a = 0; a < dim; ++a) order[a] = a;
    for (int i = 1; i < dim; ++i)
        for (int j = i; j > 0 && d[order[j]] > d[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
}

// --- an independent reference, in double, from the definitions in docs/noise.md -------------
// Own copies of every constant, explicit gradient tables, std::floor and int64 cells, explicit
// corner weights instead of nested lerps: it shares nothing with the kernels but the scale
// factors, so a change of hash, gradient choice or lattice handling shows up as a mismatch.
namespace ref {

constexpr std::uint32_t kPrime[4] = {501125321u, 1136930381u, 1720413743u, 1066037191u};
constexpr std::uint32_t kMultiplier = 0x27d4eb2du;

std::uint32_t key(std::uint32_t seed) { // murmur3 fmix32
    std::uint32_t h = seed;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

// Gradient tables indexed by the top hash bits (4 bits in 2-D and 3-D, 6 in 4-D).
std::vector<std::array<double, 4>> gradients(int dim) {
    std::vector<std::array<double, 4>> g;
    if (dim == 2) {
        const double c = std::cos(M_PI / 8), s = std::sin(M_PI / 8);
        for (int h = 0; h < 16; ++h) {
            const double s0 = (h & 1) ? -1 : 1, s1 = (h & 2) ? -1 : 1;
            if (h & 4) g.push_back({s1 * s, s0 * c, 0, 0}); // components swapped
            else g.push_back({s0 * c, s1 * s, 0, 0});
        }
    } else if (dim == 3) { // Perlin 2002: 12 cube edges, padded with 4 repeats
        const double t[16][3] = {{1, 1, 0},  {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 0, 1},  {-1, 0, 1},
                                 {1, 0, -1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, 1}, {0, 1, -1}, {0, -1, -1},
                                 {1, 1, 0},  {0, -1, 1}, {-1, 1, 0}, {0, -1, -1}};
        for (auto& v : t) g.push_back({v[0], v[1], v[2], 0});
    } else {
        for (int h = 0; h < 64; ++h) {
            std::array<double, 4> v{};
            for (int a = 0; a < 4; ++a) v[a] = (h >> a & 1) ? -1.0 : 1.0;
            v[h >> 4] = 0.0;
            g.push_back(v);
        }
    }
    return g;
}

std::uint32_t gradient_index(std::uint32_t k, const std::int64_t* cell, int dim) {
    std::uint32_t h = k;
    for (int a = 0; a < dim; ++a) h ^= static_cast<std::uint32_t>(cell[a]) * kPrime[a];
    h *= kMultiplier;
    return dim == 4 ? h >> 26 : h >> 28;
}

double fade(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

double perlin(std::uint32_t k, const double* p, int dim, double scale) {
    static const std::vector<std::array<double, 4>> g[5] = {{}, {}, gradients(2), gradients(3), gradients(4)};
    std::int64_t base[4];
    double t[4];
    for (int a = 0; a < dim; ++a) {
        const double f = std::floor(p[a]);
        base[a] = static_cast<std::int64_t>(f);
        t[a] = p[a] - f;
    }
    double sum = 0.0;
    for (int c = 0; c < (1 << dim); ++c) {
        std::int64_t cell[4];
        double w = 1.0, dot = 0.0;
        const std::uint32_t idx = [&] {
            for (int a = 0; a < dim; ++a) cell[a] = base[a] + (c >> a & 1);
            return gradient_index(k, cell, dim);
        }();
        for (int a = 0; a < dim; ++a) {
            const int b = c >> a & 1;
            w *= b ? fade(t[a]) : 1.0 - fade(t[a]);
            dot += g[dim][idx][a] * (t[a] - b);
        }
        sum += w * dot;
    }
    return sum * scale;
}

double simplex(std::uint32_t k, const double* p, int dim, double scale) {
    static const std::vector<std::array<double, 4>> g[5] = {{}, {}, gradients(2), gradients(3), gradients(4)};
    const double n1 = dim + 1.0;
    const double F = (std::sqrt(n1) - 1.0) / dim, G = (1.0 - 1.0 / std::sqrt(n1)) / dim;
    double s = 0.0;
    for (int a = 0; a < dim; ++a) s += p[a];
    s *= F;
    std::int64_t cell[4];
    double t = 0.0, d0[4] = {0, 0, 0, 0};
    for (int a = 0; a < dim; ++a) {
        cell[a] = static_cast<std::int64_t>(std::floor(p[a] + s));
        t += static_cast<double>(cell[a]);
    }
    t *= G;
    for (int a = 0; a < dim; ++a) d0[a] = p[a] - (static_cast<double>(cell[a]) - t);
    int order[4];
    sort_axes(d0, dim, order);
    double sum = 0.0;
    std::int64_t off[4] = {0, 0, 0, 0};
    for (int corner = 0; corner <= dim; ++corner) {
        if (corner > 0) off[order[corner - 1]] = 1;
        std::int64_t c[4];
        double d[4], d2 = 0.0;
        for (int a = 0; a < dim; ++a) {
            c[a] = cell[a] + off[a];
            d[a] = d0[a] - static_cast<double>(off[a]) + corner * G;
            d2 += d[a] * d[a];
        }
        const double r = 0.5 - d2;
        if (r <= 0.0) continue;
        const std::uint32_t idx = gradient_index(k, c, dim);
        double dot = 0.0;
        for (int a = 0; a < dim; ++a) dot += g[dim][idx][a] * d[a];
        sum += r * r * r * r * dot;
    }
    return sum * scale;
}

// The documented scale factors (docs/noise.md): 1/supremum · (1 − 2⁻¹⁶).
double scale(const Basis& b) {
    static const double perlin[5] = {0, 0, 1.51325642, 0.964906705, 0.650785005};
    static const double simplex[5] = {0, 0, 100.038574, 76.8795769, 62.7767492};
    return b.basis == fx::NoiseBasis::perlin ? perlin[b.dim] : simplex[b.dim];
}

double eval(const Basis& b, std::uint32_t seed, const double* p) {
    return b.basis == fx::NoiseBasis::perlin ? perlin(key(seed), p, b.dim, scale(b)) : simplex(key(seed), p, b.dim, scale(b));
}

} // namespace ref

void random_point(std::mt19937_64& rng, double lo, double hi, double* p) {
    std::uniform_real_distribution<double> u(lo, hi);
    for (int a = 0; a < 4; ++a) p[a] = u(rng);
}

} // namespace

TEST_CASE("noise matches an independent double-precision reference", "[noise]") {
    // Tolerance: the kernels run in float (24-bit mantissa) through ~20 operations on values of
    // order 1 (simplex: order 0.06 times a scale of ~100), so ~1e-6 is their rounding; 2e-5
    // allows for it while any change of hash, gradient or lattice gives errors of order 0.1.
    for (const Basis& b : all_bases()) {
        for (std::uint32_t seed : {0u, 1u, 1337u, 0xdeadbeefu}) {
            const fx::Noise noise(seed);
            std::mt19937_64 rng(seed + 17);
            double worst = 0.0;
            for (int i = 0; i < 20000; ++i) {
                double p[4];
                random_point(rng, -300.0, 300.0, p);
                worst = std::max(worst, std::fabs(b.eval(noise, p) - ref::eval(b, seed, p)));
            }
            INFO(b.name << " seed " << seed);
            CHECK(worst < 2e-5);
        }
    }
}

TEST_CASE("noise golden values pin the hash, gradients, scales and operation order", "[noise]") {
    // Printed with printf("%a") by this implementation (x86-64, GCC 12, -O3, SSE2 lanes) when
    // the noise was introduced; the reference test above agrees with each to 2e-5, so they are
    // the definition and not an accident of the build. They change only with a deliberate change
    // of the noise (note it in docs/noise.md: every stored field changes with them).
    struct Golden {
        int basis; // index into all_bases()
        std::uint32_t seed;
        double p[4];
        float value;
    };
    const Golden golden[] = {
        {0, 0u, {1.25, -2.5, 3.75, 0.5}, 0x1.24cc0cp-2f}, // 0.285934627
        {0, 0u, {123.456, 789.012, -345.678, 9.87}, -0x1.57f412p-8f}, // -0.00524831237
        {0, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, 0x1.300846p-2f}, // 0.296906561
        {0, 1337u, {1.25, -2.5, 3.75, 0.5}, 0x1.40db36p-2f}, // 0.313336223
        {0, 1337u, {123.456, 789.012, -345.678, 9.87}, -0x1.3c2078p-6f}, // -0.0192948505
        {0, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, 0x1.13114ep-2f}, // 0.2686207
        {1, 0u, {1.25, -2.5, 3.75, 0.5}, 0x1.6bcbd4p-5f}, // 0.0444087163
        {1, 0u, {123.456, 789.012, -345.678, 9.87}, 0x1.064536p-1f}, // 0.512246788
        {1, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.043654p-2f}, // -0.254113495
        {1, 1337u, {1.25, -2.5, 3.75, 0.5}, -0x1.7e380ep-3f}, // -0.186630353
        {1, 1337u, {123.456, 789.012, -345.678, 9.87}, -0x1.c1df96p-5f}, // -0.0549161844
        {1, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, 0x1.14ecc2p-2f}, // 0.270434409
        {2, 0u, {1.25, -2.5, 3.75, 0.5}, -0x1.528ebcp-3f}, // -0.165311307
        {2, 0u, {123.456, 789.012, -345.678, 9.87}, -0x1.8cf3acp-2f}, // -0.387648284
        {2, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.47134ep-8f}, // -0.00499077467
        {2, 1337u, {1.25, -2.5, 3.75, 0.5}, 0x1.0c20bcp-3f}, // 0.130921811
        {2, 1337u, {123.456, 789.012, -345.678, 9.87}, -0x1.ad976ep-3f}, // -0.209761485
        {2, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.356e4ap-6f}, // -0.0188861582
        {3, 0u, {1.25, -2.5, 3.75, 0.5}, -0x1.c125c4p-1f}, // -0.877241254
        {3, 0u, {123.456, 789.012, -345.678, 9.87}, -0x1.39affcp-4f}, // -0.0765838474
        {3, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.0f6d4ep-1f}, // -0.530130804
        {3, 1337u, {1.25, -2.5, 3.75, 0.5}, -0x1.37e918p-1f}, // -0.609200239
        {3, 1337u, {123.456, 789.012, -345.678, 9.87}, -0x1.4f0886p-5f}, // -0.040897619
        {3, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.f06e94p-2f}, // -0.484796822
        {4, 0u, {1.25, -2.5, 3.75, 0.5}, 0x1.33e9ep-3f}, // 0.150348425
        {4, 0u, {123.456, 789.012, -345.678, 9.87}, 0x1.1c281ap-8f}, // 0.00433588633
        {4, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.23ea02p-2f}, // -0.285072356
        {4, 1337u, {1.25, -2.5, 3.75, 0.5}, -0x1.e89ab4p-3f}, // -0.238576323
        {4, 1337u, {123.456, 789.012, -345.678, 9.87}, 0x1.8680b2p-3f}, // 0.190675154
        {4, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, 0x1.3b7d52p-2f}, // 0.308095247
        {5, 0u, {1.25, -2.5, 3.75, 0.5}, 0x1.caaa8ep-5f}, // 0.0559895299
        {5, 0u, {123.456, 789.012, -345.678, 9.87}, 0x1.f2b7b8p-6f}, // 0.0304393098
        {5, 0u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, 0x1.7bdf68p-7f}, // 0.0115927942
        {5, 1337u, {1.25, -2.5, 3.75, 0.5}, 0x1.513976p-5f}, // 0.0411650948
        {5, 1337u, {123.456, 789.012, -345.678, 9.87}, 0x1.c0aaf6p-6f}, // 0.0273845103
        {5, 1337u, {1e7 + 0.3, -1e7 + 0.7, 2.5e6 + 0.1, 42.42}, -0x1.df31f4p-5f}, // -0.0584954992
    };
    for (const Golden& g : golden) {
        const Basis& b = all_bases()[static_cast<std::size_t>(g.basis)];
        const float v = b.eval(fx::Noise(g.seed), g.p);
        INFO(b.name << " seed " << g.seed << " at " << g.p[0] << ", " << g.p[1] << ", " << g.p[2] << ", " << g.p[3]);
        CHECK(bits(v) == bits(g.value));
        CHECK(std::fabs(ref::eval(b, g.seed, g.p) - g.value) < 2e-5);
    }
}

TEST_CASE("noise kernels choose exactly the documented gradients", "[noise]") {
    using namespace fx::noise_detail;
    for (int dim = 2; dim <= 4; ++dim) {
        const auto table = ref::gradients(dim);
        const int shift = dim == 4 ? 26 : 28;
        for (std::uint32_t h = 0; h < table.size(); ++h) {
            const std::uint32_t hashed = h << shift;
            float g[4];
            for (int a = 0; a < dim; ++a) {
                float e[4] = {0, 0, 0, 0};
                e[a] = 1.0f;
                g[a] = dim == 2   ? grad2<F1, U1>(hashed, e[0], e[1])
                       : dim == 3 ? grad3<F1, U1>(hashed, e[0], e[1], e[2])
                                  : grad4<F1, U1>(hashed, e[0], e[1], e[2], e[3]);
            }
            INFO("dim " << dim << " h " << h);
            for (int a = 0; a < dim; ++a) CHECK(g[a] == Approx(table[h][a]).margin(1e-7));
        }
    }
}

TEST_CASE("noise scale factors keep every gradient arrangement inside [-1, 1]", "[noise]") {
    // The bound: at a point of a cell, each corner's term is largest with the gradient that
    // points most along its offset, independently of the others (the weights are ≥ 0), so
    // Σ weight · max_g (g · d) bounds the noise over every hash outcome. Its maximum over the
    // cell times the scale must stay below 1, and reach close to 1 (else the scale wastes range).
    // Dense grids here; the constants come from a finer optimisation (noise_kernels.hpp).
    using namespace fx::noise_detail;
    const auto best = [](const std::vector<std::array<double, 4>>& g, const double* d, int dim) {
        double m = -1e9;
        for (const auto& v : g) {
            double s = 0.0;
            for (int a = 0; a < dim; ++a) s += v[a] * d[a];
            m = std::max(m, s);
        }
        return m;
    };
    for (const Basis& b : all_bases()) {
        const auto g = ref::gradients(b.dim);
        const double scale = b.basis == fx::NoiseBasis::perlin
                                 ? (b.dim == 2 ? kPerlin2Scale : b.dim == 3 ? kPerlin3Scale : kPerlin4Scale)
                                 : (b.dim == 2 ? kSimplex2Scale : b.dim == 3 ? kSimplex3Scale : kSimplex4Scale);
        CHECK(scale == static_cast<float>(ref::scale(b))); // documented == used
        // Perlin's bound is symmetric about the cell centre (the gradient sets are closed under
        // sign changes), so [0, ½]ᴺ covers it; simplex samples the whole skewed cell.
        const bool perlin = b.basis == fx::NoiseBasis::perlin;
        const int steps = b.dim == 2 ? 300 : b.dim == 3 ? (perlin ? 40 : 60) : (perlin ? 14 : 24);
        const double extent = perlin ? 0.5 : 1.0;
        std::size_t total = 1;
        for (int a = 0; a < b.dim; ++a) total *= steps + 1;
        double sup = 0.0;
        for (std::size_t idx = 0; idx < total; ++idx) {
            double u[4];
            std::size_t rest = idx;
            for (int a = 0; a < b.dim; ++a) {
                u[a] = extent * static_cast<double>(rest % (steps + 1)) / steps;
                rest /= steps + 1;
            }
            double bound = 0.0;
            if (perlin) {
                for (int c = 0; c < (1 << b.dim); ++c) {
                    double w = 1.0, d[4];
                    for (int a = 0; a < b.dim; ++a) {
                        const int bit = c >> a & 1;
                        w *= bit ? ref::fade(u[a]) : 1.0 - ref::fade(u[a]);
                        d[a] = u[a] - bit;
                    }
                    bound += w * best(g, d, b.dim);
                }
            } else { // u is a point of the skewed unit cell
                const double G = (1.0 - 1.0 / std::sqrt(b.dim + 1.0)) / b.dim;
                double su = 0.0, d0[4] = {0, 0, 0, 0};
                for (int a = 0; a < b.dim; ++a) su += u[a];
                for (int a = 0; a < b.dim; ++a) d0[a] = u[a] - su * G;
                int order[4];
                sort_axes(d0, b.dim, order);
                double off[4] = {0, 0, 0, 0};
                for (int corner = 0; corner <= b.dim; ++corner) {
                    if (corner > 0) off[order[corner - 1]] = 1.0;
                    double d[4], d2 = 0.0;
                    for (int a = 0; a < b.dim; ++a) {
                        d[a] = d0[a] - off[a] + corner * G;
                        d2 += d[a] * d[a];
                    }
                    const double r = 0.5 - d2;
                    if (r > 0.0) bound += r * r * r * r * best(g, d, b.dim);
                }
            }
            sup = std::max(sup, bound);
        }
        INFO(b.name << ": grid supremum " << sup << " · scale " << scale << " = " << sup * scale);
        CHECK(sup * scale <= 1.0 - 1.0 / 65536.0 + 1e-12);
        CHECK(sup * scale > 0.99);
    }
}

TEST_CASE("simplex kernels vanish outside the simplices around their corner, so simplex noise is continuous", "[noise]") {
    // Each sample sums only its own simplex's corners. That equals the sum over every lattice
    // vertex (a continuous function) only if all other vertices are at least the kernel radius
    // (d² = 0.5) away. Check the distance to every other vertex of the surrounding cells.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int dim = 2; dim <= 4; ++dim) {
        const double G = (1.0 - 1.0 / std::sqrt(dim + 1.0)) / dim;
        double nearest = 1e9;
        for (int i = 0; i < 4000; ++i) {
            double u[4] = {0, 0, 0, 0}, d0[4] = {0, 0, 0, 0}, su = 0.0;
            for (int a = 0; a < dim; ++a) su += (u[a] = u01(rng));
            for (int a = 0; a < dim; ++a) d0[a] = u[a] - su * G;
            int order[4];
            sort_axes(d0, dim, order);
            std::vector<std::array<int, 4>> corners;
            std::array<int, 4> off{};
            corners.push_back(off);
            for (int c = 0; c < dim; ++c) {
                off[order[c]] = 1;
                corners.push_back(off);
            }
            int total = 1;
            for (int a = 0; a < dim; ++a) total *= 5;
            for (int idx = 0; idx < total; ++idx) {
                std::array<int, 4> v{};
                int rest = idx, sv = 0;
                for (int a = 0; a < dim; ++a) {
                    v[a] = rest % 5 - 2;
                    rest /= 5;
                    sv += v[a];
                }
                if (std::find(corners.begin(), corners.end(), v) != corners.end()) continue;
                double d2 = 0.0;
                for (int a = 0; a < dim; ++a) {
                    const double d = d0[a] - v[a] + sv * G;
                    d2 += d * d;
                }
                nearest = std::min(nearest, d2);
            }
        }
        INFO("dim " << dim);
        CHECK(nearest >= 0.5);
    }
}

TEST_CASE("noise stays in [-1, 1] over many samples, near the origin and far from it", "[noise]") {
    // 200 000 samples per basis and region; the maximum |n| seen must also be large (the scale
    // is not far too small) and the spread similar everywhere (nothing degenerates far out).
    for (const Basis& b : all_bases()) {
        const fx::Noise noise(99);
        double sd_near = 0.0;
        for (double centre : {0.0, 1e6, -1e7, 1e7, 1e9}) {
            std::mt19937_64 rng(static_cast<std::uint64_t>(centre) + 3);
            double lo = 0.0, hi = 0.0, sum = 0.0, sum2 = 0.0;
            const int n = 200000;
            for (int i = 0; i < n; ++i) {
                double p[4];
                random_point(rng, centre - 500.0, centre + 500.0, p);
                const float v = b.eval(noise, p);
                lo = std::min<double>(lo, v);
                hi = std::max<double>(hi, v);
                sum += v;
                sum2 += double(v) * v;
            }
            const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
            if (centre == 0.0) sd_near = sd;
            INFO(b.name << " near " << centre << ": [" << lo << ", " << hi << "] mean " << mean << " sd " << sd);
            CHECK(lo >= -1.0);
            CHECK(hi <= 1.0);
            CHECK(std::max(-lo, hi) > 0.65); // perlin4 reaches ~0.74, the others > 0.95
            CHECK(std::fabs(mean) < 0.01);
            CHECK(sd == Approx(sd_near).epsilon(0.05));
        }
    }
}

TEST_CASE("noise is continuous: bounded slope along random segments, also at 1e7", "[noise]") {
    // Along 300 segments per basis and region, consecutive samples 1e-4 apart may differ by at
    // most max_slope·1e-4 (Basis::max_slope, with headroom over the measured slopes). A jump J
    // would show as a slope J·1e4: anything above ~1e-3 fails. At 1e7 this also proves the cell
    // split keeps sub-cell resolution there (float coordinates would step by whole cells).
    const double h = 1e-4;
    for (const Basis& b : all_bases()) {
        const fx::Noise noise(4);
        for (double centre : {0.0, -3.7e6, 1e7}) {
            std::mt19937_64 rng(11);
            std::normal_distribution<double> gauss(0.0, 1.0);
            double worst = 0.0;
            std::size_t changed = 0, steps = 0;
            for (int s = 0; s < 300; ++s) {
                double p[4], d[4] = {0, 0, 0, 0}, len = 0.0;
                random_point(rng, centre - 50.0, centre + 50.0, p);
                for (int a = 0; a < b.dim; ++a) {
                    d[a] = gauss(rng);
                    len += d[a] * d[a];
                }
                len = std::sqrt(len);
                float prev = b.eval(noise, p);
                for (int k = 1; k <= 200; ++k) {
                    double q[4];
                    for (int a = 0; a < 4; ++a) q[a] = p[a] + k * h * d[a] / len;
                    const float v = b.eval(noise, q);
                    worst = std::max(worst, std::fabs(double(v) - prev) / h);
                    changed += v != prev;
                    ++steps;
                    prev = v;
                }
            }
            INFO(b.name << " near " << centre << ": steepest slope " << worst);
            CHECK(worst <= b.max_slope);
            CHECK(changed > steps * 95 / 100); // smooth, not stair-stepped
        }
    }
}

TEST_CASE("noise is exactly zero at the lattice points", "[noise]") {
    // Perlin: integer coordinates (each corner's offset is 0 there, the other weights vanish).
    // Simplex: the skewed lattice's vertices, x = i − (Σi)·G, where every other corner lies
    // beyond the kernel radius; |n| < 1e-6 allows for the rounding of x.
    std::mt19937_64 rng(2);
    std::uniform_int_distribution<int> cell(-1000, 1000);
    for (const Basis& b : all_bases()) {
        const fx::Noise noise(77);
        const double G = (1.0 - 1.0 / std::sqrt(b.dim + 1.0)) / b.dim;
        for (double offset : {0.0, 1e7, -5e8}) {
            double worst = 0.0;
            for (int i = 0; i < 2000; ++i) {
                double p[4] = {0, 0, 0, 0}, sum = 0.0;
                for (int a = 0; a < b.dim; ++a) sum += (p[a] = offset + cell(rng));
                if (b.basis == fx::NoiseBasis::simplex)
                    for (int a = 0; a < b.dim; ++a) p[a] -= sum * G;
                worst = std::max(worst, double(std::fabs(b.eval(noise, p))));
            }
            INFO(b.name << " lattice near " << offset << ": largest |n| " << worst);
            if (b.basis == fx::NoiseBasis::perlin) CHECK(worst == 0.0);
            else CHECK(worst < 1e-6);
        }
    }
}

TEST_CASE("Perlin's lattice repeats every 2^32 cells, and huge and non-finite coordinates stay finite", "[noise]") {
    const fx::Noise noise(8);
    const double period = 4294967296.0;
    std::mt19937_64 rng(3);
    for (int i = 0; i < 1000; ++i) {
        double p[4];
        random_point(rng, -100.0, 100.0, p);
        for (double& x : p) x = std::ldexp(std::round(std::ldexp(x, 20)), -20); // x ± 2³² stays exact
        CHECK(bits(noise.perlin2(p[0] + period, p[1])) == bits(noise.perlin2(p[0], p[1])));
        CHECK(bits(noise.perlin3(p[0], p[1] - period, p[2])) == bits(noise.perlin3(p[0], p[1], p[2])));
        CHECK(bits(noise.perlin4(p[0], p[1], p[2], p[3] - period)) == bits(noise.perlin4(p[0], p[1], p[2], p[3])));
    }
    const double odd[] = {1e12, -1e15, 1e300, -1e300, INFINITY, -INFINITY, NAN};
    for (const Basis& b : all_bases())
        for (double x : odd) {
            const double p[4] = {x, 0.25, x, 0.5};
            const float v = b.eval(noise, p);
            INFO(b.name << " at " << x);
            CHECK(std::isfinite(v));
            CHECK(std::fabs(v) <= 1.0f);
        }
}

TEST_CASE("NaN, infinite and huge coordinates give the documented values", "[noise]") {
    // docs/noise.md, "Far from the origin": each coordinate (times the octave's frequency) is
    // clamped to ±2⁴⁸, and NaN counts as −2⁴⁸, so these are the values at ±2⁴⁸ exactly, bit for
    // bit, in every basis and on every axis, whatever the other coordinates are.
    const double big = 281474976710656.0; // 2⁴⁸
    const fx::Noise noise(12);
    std::mt19937_64 rng(23);
    for (const Basis& b : all_bases())
        for (int axis = 0; axis < b.dim; ++axis)
            for (int i = 0; i < 50; ++i) {
                double p[4];
                random_point(rng, -1e7, 1e7, p);
                const auto at = [&](double x) {
                    double q[4] = {p[0], p[1], p[2], p[3]};
                    q[axis] = x;
                    return bits(b.eval(noise, q));
                };
                INFO(b.name << " axis " << axis);
                CHECK(at(NAN) == at(-big));
                CHECK(at(-NAN) == at(-big));
                CHECK(at(INFINITY) == at(big));
                CHECK(at(-INFINITY) == at(-big));
                CHECK(at(1e300) == at(big));
                CHECK(at(-5e15) == at(-big));
                CHECK(at(std::nextafter(big, 0.0)) != at(big)); // just inside, the cell and offset differ
            }
    // Fractals clamp each octave's coordinate: NaN gives the same value every time, finite and in range.
    fx::Fractal f;
    f.octaves = 5;
    f.frequency = 0.01;
    for (fx::NoiseBasis basis : {fx::NoiseBasis::perlin, fx::NoiseBasis::simplex}) {
        f.basis = basis;
        for (double x : {double(NAN), double(INFINITY), -double(INFINITY), 1e300}) {
            const float v = noise.fractal3(f, x, 0.5, -0.5);
            CHECK(std::isfinite(v));
            CHECK(std::fabs(v) <= 1.0f);
            CHECK(bits(v) == bits(noise.fractal3(f, x, 0.5, -0.5)));
        }
    }
}

TEST_CASE("noise is deterministic per seed and different seeds give unrelated fields", "[noise]") {
    for (const Basis& b : all_bases()) {
        std::mt19937_64 rng(21);
        std::vector<std::array<double, 4>> points(20000);
        for (auto& p : points) random_point(rng, -200.0, 200.0, p.data());
        std::vector<std::vector<float>> fields;
        for (std::uint32_t seed : {0u, 1u, 2u, 3u, 0x80000000u, 0xffffffffu}) {
            const fx::Noise a(seed), a_copy = a;
            std::vector<float> f;
            for (const auto& p : points) {
                const float v = b.eval(a, p.data());
                CHECK(bits(v) == bits(b.eval(fx::Noise(seed), p.data())));
                CHECK(bits(v) == bits(b.eval(a_copy, p.data())));
                f.push_back(v);
            }
            fields.push_back(f);
        }
        for (std::size_t i = 0; i < fields.size(); ++i)
            for (std::size_t j = i + 1; j < fields.size(); ++j) {
                double sxy = 0.0, sxx = 0.0, syy = 0.0;
                std::size_t same = 0;
                for (std::size_t k = 0; k < points.size(); ++k) {
                    sxy += double(fields[i][k]) * fields[j][k];
                    sxx += double(fields[i][k]) * fields[i][k];
                    syy += double(fields[j][k]) * fields[j][k];
                    same += fields[i][k] == fields[j][k];
                }
                // 20 000 independent-ish samples: |correlation| of unrelated fields ~ 0.007.
                // Equal values: where one simplex corner's kernel alone reaches a sample, two seeds
                // agree when that corner's gradient does (p = 1/8 to 1/12), so ~1% of simplex
                // samples match exactly; Perlin needs all 2ᴺ corners to agree.
                INFO(b.name << " seeds #" << i << " and #" << j << ": " << same << " equal values");
                CHECK(std::fabs(sxy / std::sqrt(sxx * syy)) < 0.05);
                CHECK(same < points.size() * (b.basis == fx::NoiseBasis::perlin ? 1 : 3) / 100);
            }
    }
}

namespace {

// Bit for bit (signs of zero included), for every basis and fractal type, on grids whose sizes
// are not multiples of the vector width or the 64-sample block, far from the origin, with
// negative and uneven steps.
void check_batch_equals_scalar() {
    const fx::Noise noise(2024);
    std::vector<fx::Fractal> fractals;
    for (fx::NoiseBasis basis : {fx::NoiseBasis::perlin, fx::NoiseBasis::simplex}) {
        fx::Fractal f;
        f.basis = basis;
        fractals.push_back(f); // the plain basis
        for (fx::FractalType type : {fx::FractalType::fbm, fx::FractalType::ridged, fx::FractalType::turbulence}) {
            f.type = type;
            f.octaves = 3;
            f.frequency = 0.37;
            f.lacunarity = 2.13;
            f.gain = 0.6f;
            fractals.push_back(f);
        }
    }
    for (const fx::Fractal& f : fractals) {
        INFO("basis " << int(f.basis) << " type " << int(f.type) << " octaves " << f.octaves);
        for (double far : {0.0, 1e7}) {
            const fx::Grid2 g2{{far + 0.3, -far - 7.1}, {0.173, -0.41}, 131, 7};
            std::vector<float> batch(g2.nx * g2.ny), scalar;
            fx::fill_grid2(noise, f, g2, batch.data());
            for (std::size_t j = 0; j < g2.ny; ++j)
                for (std::size_t i = 0; i < g2.nx; ++i)
                    scalar.push_back(noise.fractal2(f, g2.origin.x + g2.step.x * double(i), g2.origin.y + g2.step.y * double(j)));
            CHECK(count_bit_differences(batch, scalar) == 0);

            // z starts at −0.0 when far is 0 (−0 + −1.7·0 is −0): a −0 offset broadcast to the lanes
            const fx::Grid3 g3{{far - 2.5, 0.75, -far}, {0.31, 0.29, -1.7}, 67, 5, 3};
            batch.assign(g3.nx * g3.ny * g3.nz, 0.0f);
            scalar.clear();
            fx::fill_grid3(noise, f, g3, batch.data());
            for (std::size_t k = 0; k < g3.nz; ++k)
                for (std::size_t j = 0; j < g3.ny; ++j)
                    for (std::size_t i = 0; i < g3.nx; ++i)
                        scalar.push_back(noise.fractal3(f, g3.origin.x + g3.step.x * double(i),
                                                        g3.origin.y + g3.step.y * double(j),
                                                        g3.origin.z + g3.step.z * double(k)));
            CHECK(count_bit_differences(batch, scalar) == 0);

            const fx::Grid4 g4{{far + 1.0, 2.0, 3.0, far + 0.5}, {0.27, 0.5, 0.33, 0.125}, 9, 3, 2, 2};
            batch.assign(g4.nx * g4.ny * g4.nz * g4.nw, 0.0f);
            scalar.clear();
            fx::fill_grid4(noise, f, g4, batch.data());
            for (std::size_t l = 0; l < g4.nw; ++l)
                for (std::size_t k = 0; k < g4.nz; ++k)
                    for (std::size_t j = 0; j < g4.ny; ++j)
                        for (std::size_t i = 0; i < g4.nx; ++i)
                            scalar.push_back(noise.fractal4(f, g4.origin.x + g4.step.x * double(i),
                                                            g4.origin.y + g4.step.y * double(j),
                                                            g4.origin.z + g4.step.z * double(k),
                                                            g4.origin.w + g4.step.w * double(l)));
            CHECK(count_bit_differences(batch, scalar) == 0);

            std::mt19937_64 rng(6);
            std::vector<dvec2> p2(203);
            std::vector<dvec3> p3(203);
            std::vector<dvec4> p4(203);
            for (std::size_t i = 0; i < p2.size(); ++i) {
                double p[4];
                random_point(rng, far - 40.0, far + 40.0, p);
                p2[i] = {p[0], p[1]};
                p3[i] = {p[0], p[1], p[2]};
                p4[i] = {p[0], p[1], p[2], p[3]};
            }
            // Signed zeros, lattice points, values just below a lattice plane (their offset
            // rounds to 1.0f), on every axis.
            const double special[] = {-0.0, 0.0, -1e-20, 1e-20, -1.0, 3.0, -0.5, far, far - 1e-9};
            std::size_t next = 0;
            for (double s0 : special)
                for (double s1 : {-0.0, -1e-20, 0.25}) {
                    p2[next] = {s0, s1};
                    p3[next] = {s1, s0, -s0};
                    p4[next] = {s1, -0.0, s0, s0};
                    ++next;
                }
            std::vector<float> b2(p2.size()), b3(p3.size()), b4(p4.size()), s2, s3, s4;
            fx::fill_points2(noise, f, p2.data(), p2.size(), b2.data());
            fx::fill_points3(noise, f, p3.data(), p3.size(), b3.data());
            fx::fill_points4(noise, f, p4.data(), p4.size(), b4.data());
            for (std::size_t i = 0; i < p2.size(); ++i) {
                s2.push_back(noise.fractal2(f, p2[i].x, p2[i].y));
                s3.push_back(noise.fractal3(f, p3[i].x, p3[i].y, p3[i].z));
                s4.push_back(noise.fractal4(f, p4[i].x, p4[i].y, p4[i].z, p4[i].w));
            }
            CHECK(count_bit_differences(b2, s2) == 0);
            CHECK(count_bit_differences(b3, s3) == 0);
            CHECK(count_bit_differences(b4, s4) == 0);
        }
        // Lattice points from −0.0 down (−0 + −1·0 is −0): the values are zeros whose signs
        // follow every offset's sign, those of the y, z, w axes broadcast to the lanes included.
        const fx::Grid4 lattice{{-0.0, -0.0, -0.0, -0.0}, {-1.0, -1.0, -1.0, -1.0}, 5, 3, 3, 2};
        std::vector<float> batch(lattice.nx * lattice.ny * lattice.nz * lattice.nw), scalar;
        fx::fill_grid4(noise, f, lattice, batch.data());
        for (std::size_t l = 0; l < lattice.nw; ++l)
            for (std::size_t k = 0; k < lattice.nz; ++k)
                for (std::size_t j = 0; j < lattice.ny; ++j)
                    for (std::size_t i = 0; i < lattice.nx; ++i)
                        scalar.push_back(noise.fractal4(f, -0.0 - double(i), -0.0 - double(j), -0.0 - double(k), -0.0 - double(l)));
        CHECK(count_bit_differences(batch, scalar) == 0);
        batch.resize(lattice.nx * lattice.ny * lattice.nz);
        scalar.clear();
        fx::fill_grid3(noise, f, {{-0.0, -0.0, -0.0}, {-1.0, -1.0, -1.0}, lattice.nx, lattice.ny, lattice.nz}, batch.data());
        for (std::size_t k = 0; k < lattice.nz; ++k)
            for (std::size_t j = 0; j < lattice.ny; ++j)
                for (std::size_t i = 0; i < lattice.nx; ++i)
                    scalar.push_back(noise.fractal3(f, -0.0 - double(i), -0.0 - double(j), -0.0 - double(k)));
        CHECK(count_bit_differences(batch, scalar) == 0);
    }
}

// The chosen lane kernels' one-sample functions (fx::Noise::perlin2/3, fractal2/3/4) against
// the one-lane definitions (perlin2_at, fractal2_at, ...), bit for bit: random points near the
// origin and far from it, signed zeros, lattice points, points just below a lattice plane, huge
// and non-finite coordinates; fractals of 1 to 16 octaves (whole and partial vectors of octaves).
void check_samples_equal_one_lane() {
    using namespace fx::noise_detail;
    const std::uint32_t seed = 77;
    const fx::Noise noise(seed);
    const std::uint32_t key = mix_seed(seed, 0);
    std::vector<std::array<double, 4>> points;
    std::mt19937_64 rng(8);
    for (double far : {0.0, 1e7, -3.7e6})
        for (int i = 0; i < 3000; ++i) {
            std::array<double, 4> p;
            random_point(rng, far - 40.0, far + 40.0, p.data());
            points.push_back(p);
        }
    const double special[] = {-0.0, 0.0, -1e-20, 2.0, -3.0, 1.0 - 1e-17, -1e-300, 1e7 - 1e-9, 1e15, -1e300, INFINITY, -INFINITY, NAN};
    for (double a : special)
        for (double b : special) points.push_back({a, b, -a, 0.5 * b});
    std::size_t differ = 0;
    for (const auto& p : points) {
        differ += bits(noise.perlin2(p[0], p[1])) != bits(perlin2_at(key, p[0], p[1]));
        differ += bits(noise.perlin3(p[0], p[1], p[2])) != bits(perlin3_at(key, p[0], p[1], p[2]));
    }
    CHECK(differ == 0);

    for (fx::NoiseBasis basis : {fx::NoiseBasis::perlin, fx::NoiseBasis::simplex})
        for (fx::FractalType type : {fx::FractalType::fbm, fx::FractalType::ridged, fx::FractalType::turbulence})
            for (int octaves : {1, 2, 4, 5, 9, 16}) {
                fx::Fractal f;
                f.basis = basis;
                f.type = type;
                f.octaves = octaves;
                f.frequency = octaves == 1 ? 1.0 : 0.37;
                f.lacunarity = 2.13;
                f.gain = 0.6f;
                const FractalPlan plan = make_plan(f, seed);
                differ = 0;
                for (std::size_t i = 0; i < points.size(); i += octaves > 4 ? 7 : 1) {
                    const auto& p = points[i];
                    differ += bits(noise.fractal2(f, p[0], p[1])) != bits(fractal2_at(plan, p[0], p[1]));
                    differ += bits(noise.fractal3(f, p[0], p[1], p[2])) != bits(fractal3_at(plan, p[0], p[1], p[2]));
                    differ += bits(noise.fractal4(f, p[0], p[1], p[2], p[3])) != bits(fractal4_at(plan, p[0], p[1], p[2], p[3]));
                }
                INFO("basis " << int(basis) << " type " << int(type) << " octaves " << octaves);
                CHECK(differ == 0);
            }
}

} // namespace

TEST_CASE("every instruction set's kernels give the one-lane values exactly, one sample at a time and in batch", "[noise]") {
    using fx::noise_detail::NoiseIsa;
    int checked = 0;
    for (NoiseIsa isa : {NoiseIsa::baseline, NoiseIsa::avx2}) {
        if (!fx::noise_detail::noise_isa_supported(isa)) continue;
        fx::noise_detail::set_noise_isa(isa);
        const std::string name = fx::noise_detail::lane_kernels().name;
        INFO("kernels: " << name);
        CHECK(name == (isa == NoiseIsa::baseline ? "baseline" : "avx2"));
        check_samples_equal_one_lane();
        check_batch_equals_scalar();
        ++checked;
    }
    fx::noise_detail::set_noise_isa(NoiseIsa::automatic);
    CHECK(checked >= 1);
    if (checked == 1) WARN("this CPU runs only the baseline kernels; the AVX2 ones were not checked");
}

TEST_CASE("one octave of fBm is the basis, and the octave rules are as documented", "[noise]") {
    using namespace fx::noise_detail;
    std::mt19937_64 rng(12);
    for (const Basis& b : all_bases()) {
        const fx::Noise noise(31);
        fx::Fractal f;
        f.basis = b.basis;
        for (int i = 0; i < 2000; ++i) {
            double p[4];
            random_point(rng, -50.0, 50.0, p);
            const float n = b.eval(noise, p);
            INFO(b.name);
            f.type = fx::FractalType::fbm;
            f.frequency = 1.0;
            CHECK(bits(fractal_at(noise, f, b.dim, p)) == bits(n));
            f.type = fx::FractalType::ridged;
            CHECK(bits(fractal_at(noise, f, b.dim, p)) == bits(std::fabs(n) * -2.0f + 1.0f));
            f.type = fx::FractalType::turbulence;
            CHECK(bits(fractal_at(noise, f, b.dim, p)) == bits(std::fabs(n)));
            // frequency scales the coordinates (in double)
            f.type = fx::FractalType::fbm;
            f.frequency = 0.37;
            double q[4];
            for (int a = 0; a < 4; ++a) q[a] = p[a] * 0.37;
            CHECK(bits(fractal_at(noise, f, b.dim, p)) == bits(b.eval(noise, q)));
        }
    }
    // Two octaves: amplitudes 1/(1+g) and g/(1+g), the second at frequency·lacunarity, shifted
    // by kOctaveOffset, with the octave-1 key.
    const fx::Noise noise(5);
    fx::Fractal f;
    f.octaves = 2;
    f.frequency = 0.5;
    f.lacunarity = 3.0;
    f.gain = 0.25f;
    const float a0 = 1.0f / 1.25f, a1 = a0 * 0.25f;
    for (int i = 0; i < 1000; ++i) {
        double p[4];
        random_point(rng, -50.0, 50.0, p);
        const float n0 = noise.perlin3(p[0] * 0.5, p[1] * 0.5, p[2] * 0.5);
        const float n1 = perlin3_at(mix_seed(5, 1), p[0] * 1.5 + kOctaveOffset, p[1] * 1.5 + kOctaveOffset,
                                    p[2] * 1.5 + kOctaveOffset);
        CHECK(bits(noise.fractal3(f, p[0], p[1], p[2])) == bits(n0 * a0 + n1 * a1));
    }
    // A vanishing gain leaves the first octave.
    f.octaves = 8;
    f.gain = 1e-7f;
    for (int i = 0; i < 100; ++i) {
        double p[4];
        random_point(rng, -50.0, 50.0, p);
        CHECK(noise.fractal3(f, p[0], p[1], p[2]) ==
              Approx(noise.perlin3(p[0] * 0.5, p[1] * 0.5, p[2] * 0.5)).margin(1e-6));
    }
}

TEST_CASE("fractals stay in their ranges and are continuous", "[noise]") {
    for (const Basis& b : all_bases())
        for (fx::FractalType type : {fx::FractalType::fbm, fx::FractalType::ridged, fx::FractalType::turbulence}) {
            fx::Fractal f;
            f.basis = b.basis;
            f.type = type;
            f.octaves = 6;
            f.frequency = 0.8;
            f.lacunarity = 2.0;
            f.gain = 0.5f;
            const fx::Noise noise(13);
            // slope bound: Σ amplitude·frequency·max_slope = max_slope·0.8·Σ(2·0.5)ᵒ/Σ0.5ᵒ
            // (ridged doubles the slope: 1 − 2|n|)
            const double slope = b.max_slope * 0.8 * 6.0 / (2.0 - std::ldexp(1.0, -5)) *
                                 (type == fx::FractalType::ridged ? 2.0 : 1.0);
            std::mt19937_64 rng(14);
            double lo = 1.0, hi = -1.0, worst = 0.0;
            for (int s = 0; s < 200; ++s) {
                double p[4];
                random_point(rng, -1e6, 1e6, p);
                float prev = fractal_at(noise, f, b.dim, p);
                for (int k = 1; k <= 100; ++k) {
                    double q[4];
                    for (int a = 0; a < 4; ++a) q[a] = p[a] + k * 1e-4 * (a == 0);
                    const float v = fractal_at(noise, f, b.dim, q);
                    lo = std::min<double>(lo, v);
                    hi = std::max<double>(hi, v);
                    worst = std::max(worst, std::fabs(double(v) - prev) / 1e-4);
                    prev = v;
                }
            }
            INFO(b.name << " type " << int(type) << ": [" << lo << ", " << hi << "], slope " << worst);
            CHECK(lo >= (type == fx::FractalType::turbulence ? 0.0 : -1.0));
            CHECK(hi <= 1.0);
            CHECK(hi - lo > 0.3);
            CHECK(worst <= slope);
        }
}

TEST_CASE("domain warp moves points by at most its amplitude, continuously, and in batch exactly", "[noise]") {
    const fx::Noise noise(3);
    fx::DomainWarp warp;
    warp.amplitude = 2.5;
    warp.fractal.octaves = 3;
    warp.fractal.frequency = 0.1;
    std::mt19937_64 rng(15);
    std::vector<dvec2> p2(300), w2;
    std::vector<dvec3> p3(300), w3;
    for (std::size_t i = 0; i < p2.size(); ++i) {
        double p[4];
        random_point(rng, -1e5, 1e5, p);
        p2[i] = {p[0], p[1]};
        p3[i] = {p[0], p[1], p[2]};
    }
    double largest = 0.0;
    for (std::size_t i = 0; i < p2.size(); ++i) {
        w2.push_back(noise.warp2(warp, p2[i]));
        w3.push_back(noise.warp3(warp, p3[i]));
        for (int a = 0; a < 2; ++a) CHECK(std::fabs(w2[i][a] - p2[i][a]) <= 2.5);
        for (int a = 0; a < 3; ++a) largest = std::max(largest, std::fabs(w3[i][a] - p3[i][a]));
        // A nearby point moves nearly the same: per axis the displacement's slope is at most
        // amplitude · simplex slope bound · Σ amplitudeₒ·frequencyₒ = 2.5 · 10 · 0.1·3/1.75.
        const dvec3 near = noise.warp3(warp, p3[i] + dvec3(1e-3, 0, 0));
        CHECK(glm::length(near - w3[i] - dvec3(1e-3, 0, 0)) <= std::sqrt(3.0) * 2.5 * 10.0 * 0.3 / 1.75 * 1e-3);
    }
    CHECK(largest <= 2.5);
    CHECK(largest > 0.5);
    std::vector<dvec2> b2 = p2;
    std::vector<dvec3> b3 = p3;
    fx::warp_points2(noise, warp, b2.data(), b2.size());
    fx::warp_points3(noise, warp, b3.data(), b3.size());
    CHECK(std::memcmp(b2.data(), w2.data(), b2.size() * sizeof(dvec2)) == 0);
    CHECK(std::memcmp(b3.data(), w3.data(), b3.size() * sizeof(dvec3)) == 0);
    warp.amplitude = 0.0;
    CHECK(noise.warp3(warp, dvec3(1.5, -2.5, 3.5)) == dvec3(1.5, -2.5, 3.5));
}

TEST_CASE("bad fractal settings and batch arguments throw fx::Error naming the problem", "[noise]") {
    const fx::Noise noise(1);
    const auto bad = [&](auto change, const char* text) {
        fx::Fractal f;
        change(f);
        CHECK_THROWS_WITH(noise.fractal3(f, 0.5, 0.5, 0.5), Catch::Contains("fx::Noise::fractal3: Fractal.") &&
                                                                 Catch::Contains(text));
        float out = 0.0f;
        CHECK_THROWS_WITH(fx::fill_grid2(noise, f, {{0.0, 0.0}, {1.0, 1.0}, 1, 1}, &out),
                          Catch::Contains("fx::fill_grid2: Fractal.") && Catch::Contains(text));
    };
    bad([](fx::Fractal& f) { f.octaves = 0; }, "octaves must be in [1, 16] (got 0)");
    bad([](fx::Fractal& f) { f.octaves = 17; }, "octaves must be in [1, 16] (got 17)");
    bad([](fx::Fractal& f) { f.frequency = 0.0; }, "frequency must be finite and > 0");
    bad([](fx::Fractal& f) { f.frequency = -2.0; }, "frequency must be finite and > 0 (got -2)");
    bad([](fx::Fractal& f) { f.frequency = NAN; }, "frequency must be finite");
    bad([](fx::Fractal& f) { f.lacunarity = INFINITY; }, "lacunarity must be finite");
    bad([](fx::Fractal& f) { f.gain = 0.0f; }, "gain must be finite and > 0");
    bad([](fx::Fractal& f) { f.gain = NAN; }, "gain must be finite");
    bad([](fx::Fractal& f) { f.octaves = 16, f.lacunarity = 1e300; }, "the last octave's frequency overflows");
    bad([](fx::Fractal& f) { f.basis = static_cast<fx::NoiseBasis>(7); }, "basis: unknown value 7");
    bad([](fx::Fractal& f) { f.type = static_cast<fx::FractalType>(-1); }, "type: unknown value -1");

    const fx::Fractal plain;
    CHECK_THROWS_WITH(fx::fill_grid3(noise, plain, {{0, 0, 0}, {1, 1, 1}, 2, 2, 2}, nullptr),
                      Catch::Contains("fx::fill_grid3: out is null"));
    CHECK_NOTHROW(fx::fill_grid3(noise, plain, {{0, 0, 0}, {1, 1, 1}, 2, 0, 2}, nullptr)); // nothing to write
    const std::size_t huge = std::size_t(1) << 40;
    CHECK_THROWS_WITH(fx::fill_grid4(noise, plain, {{0, 0, 0, 0}, {1, 1, 1, 1}, huge, huge, 1, 1}, nullptr),
                      Catch::Contains("overflows"));
    float out[2];
    CHECK_THROWS_WITH(fx::fill_points2(noise, plain, nullptr, 2, out), Catch::Contains("fx::fill_points2: points is null"));
    fx::DomainWarp warp;
    warp.amplitude = NAN;
    CHECK_THROWS_WITH(noise.warp2(warp, dvec2(0.0)), Catch::Contains("fx::Noise::warp2: DomainWarp.amplitude must be finite"));
    warp.amplitude = 1.0;
    warp.fractal.octaves = 40;
    dvec3 p(0.0);
    CHECK_THROWS_WITH(fx::warp_points3(noise, warp, &p, 1), Catch::Contains("fx::warp_points3: DomainWarp.fractal.octaves"));
}
