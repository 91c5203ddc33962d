// `cellfx bench noise`: millions of samples per second of fx::Noise, one call per sample
// (perlin2, fractal3, ...) and in batch fills (fill_grid*, fill_points*), with every instruction
// set of the noise's lane kernels that the CPU has (docs/noise.md, "Speed").
//
// Every item samples the same points, a regular grid near 1000 with an irrational-ish step so
// that samples land all over the cells; a call's results are stored, as a game would use them.
// Items take turns round by round, and the instruction sets too, so that load from other
// processes on a shared machine falls on all of them alike; rates use the thread's CPU time.
// After timing, each fill is checked against the one-sample calls bit for bit, so a broken
// path cannot look fast.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/error.hpp"
#include "fx/noise.hpp"
#include "noise/noise_lanes.hpp"
#include "options.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

using fx::noise_detail::NoiseIsa;

constexpr double kOrigin = 1000.0;
constexpr double kStep = 0.173;

double thread_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// One function: its one-call-per-sample loop and its fill, over the same samples.
struct Item {
    std::string name;
    std::size_t samples;
    std::function<void(float*)> per_call;
    std::function<void(float*)> fill;
};

fx::Fractal fractal(fx::NoiseBasis basis, int octaves) {
    fx::Fractal f;
    f.basis = basis;
    f.octaves = octaves;
    return f;
}

std::vector<Item> make_items(const fx::Noise& noise, std::size_t side2, std::size_t side3) {
    using fx::NoiseBasis;
    const fx::Grid2 g2{{kOrigin, kOrigin}, {kStep, kStep}, side2, side2};
    const fx::Grid3 g3{{kOrigin, kOrigin, kOrigin}, {kStep, kStep, kStep}, side3, side3, side3};
    const fx::Grid4 g4{{kOrigin, kOrigin, kOrigin, 3.5}, {kStep, kStep, kStep, 1.0}, side3, side3, side3, 1};
    const auto at = [](std::size_t i) { return kOrigin + kStep * static_cast<double>(i); };
    // The loops mirror the grids: x fastest, coordinates computed as fill_grid computes them.
    const auto loop2 = [=](float* out, auto f) {
        for (std::size_t j = 0; j < side2; ++j)
            for (std::size_t i = 0; i < side2; ++i)
                *out++ = f(at(i), at(j));
    };
    const auto loop3 = [=](float* out, auto f) {
        for (std::size_t k = 0; k < side3; ++k)
            for (std::size_t j = 0; j < side3; ++j)
                for (std::size_t i = 0; i < side3; ++i)
                    *out++ = f(at(i), at(j), at(k));
    };
    const fx::Fractal perlin = fractal(NoiseBasis::perlin, 1), simplex = fractal(NoiseBasis::simplex, 1);
    const fx::Fractal fbm4 = fractal(NoiseBasis::perlin, 4);
    auto points3 = std::make_shared<std::vector<glm::dvec3>>();
    for (std::size_t k = 0; k < side3; ++k)
        for (std::size_t j = 0; j < side3; ++j)
            for (std::size_t i = 0; i < side3; ++i)
                points3->emplace_back(at(i), at(j), at(k));
    const std::size_t n2 = side2 * side2, n3 = side3 * side3 * side3;
    return {
        {"perlin2", n2, [=](float* o) { loop2(o, [&](double x, double y) { return noise.perlin2(x, y); }); },
         [=](float* o) { fx::fill_grid2(noise, perlin, g2, o); }},
        {"perlin3", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.perlin3(x, y, z); }); },
         [=](float* o) { fx::fill_grid3(noise, perlin, g3, o); }},
        {"perlin3 points", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.perlin3(x, y, z); }); },
         [=](float* o) { fx::fill_points3(noise, perlin, points3->data(), points3->size(), o); }},
        {"perlin4", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.perlin4(x, y, z, 3.5); }); },
         [=](float* o) { fx::fill_grid4(noise, perlin, g4, o); }},
        {"simplex2", n2, [=](float* o) { loop2(o, [&](double x, double y) { return noise.simplex2(x, y); }); },
         [=](float* o) { fx::fill_grid2(noise, simplex, g2, o); }},
        {"simplex3", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.simplex3(x, y, z); }); },
         [=](float* o) { fx::fill_grid3(noise, simplex, g3, o); }},
        {"simplex4", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.simplex4(x, y, z, 3.5); }); },
         [=](float* o) { fx::fill_grid4(noise, simplex, g4, o); }},
        {"fbm2 4 octaves", n2,
         [=](float* o) { loop2(o, [&](double x, double y) { return noise.fractal2(fbm4, x, y); }); },
         [=](float* o) { fx::fill_grid2(noise, fbm4, g2, o); }},
        {"fbm3 4 octaves", n3,
         [=](float* o) { loop3(o, [&](double x, double y, double z) { return noise.fractal3(fbm4, x, y, z); }); },
         [=](float* o) { fx::fill_grid3(noise, fbm4, g3, o); }},
    };
}

struct Rates {
    std::vector<double> per_call, fill;
};

const char* isa_name(NoiseIsa isa) {
    return isa == NoiseIsa::avx2 ? "avx2" : "baseline";
}

} // namespace

int bench_noise(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"rounds", "isa", "size"});
    if (!parsed.positional.empty()) throw fx::Error("bench noise: unexpected argument '" + parsed.positional[0] + "'");
    const int rounds = int_option(parsed, "bench noise", "rounds", 9);
    // --size N: the 3-D items sample N³ points, the 2-D ones (N·√N)² (default 64: 262144 each).
    const int size = int_option(parsed, "bench noise", "size", 64);
    const std::string isa_option = parsed.get("isa", "all");
    std::vector<NoiseIsa> isas;
    if (isa_option == "all" || isa_option == "avx2") {
        if (fx::noise_detail::noise_isa_supported(NoiseIsa::avx2))
            isas.push_back(NoiseIsa::avx2);
        else if (isa_option == "avx2")
            throw fx::Error("bench noise: --isa avx2: this build or CPU has no AVX2 kernels");
    }
    if (isa_option == "all" || isa_option == "baseline") isas.push_back(NoiseIsa::baseline);
    if (isas.empty()) throw fx::Error("bench noise: --isa must be all, avx2 or baseline (got '" + isa_option + "')");

    const std::size_t side3 = static_cast<std::size_t>(size);
    const std::size_t side2 = static_cast<std::size_t>(std::lround(std::pow(static_cast<double>(size), 1.5)));
    const fx::Noise noise(1337);
    const std::vector<Item> items = make_items(noise, side2, side3);
    std::vector<std::vector<Rates>> rates(isas.size(), std::vector<Rates>(items.size()));
    std::vector<float> calls(std::max(side2 * side2, side3 * side3 * side3)), filled(calls.size());

    for (int r = 0; r < rounds; ++r)
        for (std::size_t s = 0; s < isas.size(); ++s) {
            fx::noise_detail::set_noise_isa(isas[s]);
            for (std::size_t i = 0; i < items.size(); ++i) {
                const Item& item = items[i];
                double t0 = thread_seconds();
                item.per_call(calls.data());
                double t1 = thread_seconds();
                rates[s][i].per_call.push_back(static_cast<double>(item.samples) / (t1 - t0) / 1e6);
                t0 = thread_seconds();
                item.fill(filled.data());
                t1 = thread_seconds();
                rates[s][i].fill.push_back(static_cast<double>(item.samples) / (t1 - t0) / 1e6);
                // Verify after timing: a fill gives exactly the one-sample values.
                if (std::memcmp(calls.data(), filled.data(), item.samples * sizeof(float)) != 0)
                    throw fx::Error("bench noise: " + item.name + " (" + isa_name(isas[s]) +
                                    "): the fill differs from one call per sample");
                for (std::size_t k = 0; k < item.samples; ++k)
                    if (!(std::fabs(calls[k]) <= 1.0f))
                        throw fx::Error("bench noise: " + item.name + ": value outside [-1, 1]");
            }
        }
    fx::noise_detail::set_noise_isa(NoiseIsa::automatic);

    std::printf("noise: millions of samples per second, one thread (its CPU time), median (best) of %d rounds;\n"
                "items and instruction sets interleaved; 3-D items %zu^3 samples, 2-D %zu^2, near x = %g\n",
                rounds, side3, side2, kOrigin);
    std::printf("  per call: fx::Noise::perlin2(x, y) etc. in a loop; fill: fill_grid (fill_points for 'points') "
                "of the same samples;\n  ratio: fill / per call (medians)\n\n");
    std::printf("%-16s", "function");
    for (NoiseIsa isa : isas)
        std::printf(" | %-8s %-16s %-16s %6s", isa_name(isa), "per call", "fill", "ratio");
    std::printf("\n");
    for (std::size_t i = 0; i < items.size(); ++i) {
        std::printf("%-16s", items[i].name.c_str());
        for (std::size_t s = 0; s < isas.size(); ++s) {
            const Rates& rs = rates[s][i];
            const double call = median(rs.per_call), fill = median(rs.fill);
            const double call_best = *std::max_element(rs.per_call.begin(), rs.per_call.end());
            const double fill_best = *std::max_element(rs.fill.begin(), rs.fill.end());
            char a[32], b[32];
            std::snprintf(a, sizeof a, "%.1f (%.1f)", call, call_best);
            std::snprintf(b, sizeof b, "%.1f (%.1f)", fill, fill_best);
            std::printf(" | %-8s %-16s %-16s %5.1fx", "", a, b, fill / call);
        }
        std::printf("\n");
    }
    return 0;
}

} // namespace cellfx_cli
