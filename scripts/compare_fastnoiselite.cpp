// cellfx's noise beside FastNoise Lite, one call per sample, in one process: built and run by
// scripts/compare_fastnoiselite.sh, which passes the include path of a FastNoise Lite checkout
// the user provides. Never part of the build or the test suite (docs/noise.md, "Against FastNoise
// Lite").
//
// The same loop for both: one thread, one call per sample over the same grid of sample points
// near 1000 (an irrational-ish step, so that samples land all over the cells), the results summed
// so that nothing is optimised away. FastNoise Lite gets its coordinates as float (its default)
// and as double; it samples at frequency 1 (our coordinates are in cells), Perlin, and for the
// fractal rows FBm with 4 octaves, lacunarity 2, gain 0.5, as cellfx's Fractal{perlin, fbm, 4}.
// The libraries take turns item by item and round by round (the order rotating), so that load
// from other processes falls on both alike; rates use the thread's CPU time; the ratio is the
// median of each round's cellfx / FastNoise Lite rates.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "FastNoiseLite.h"
#include "fx/noise.hpp"

namespace {

namespace fx = cellfx::fx;

double thread_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

constexpr double kOrigin = 1000.0;
constexpr double kStep = 0.173;

template <class F> float loop2(const F& f, int n) {
    float sum = 0.0f;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += f(kOrigin + kStep * i, kOrigin + kStep * j);
    return sum;
}
template <class F> float loop3(const F& f, int n) {
    float sum = 0.0f;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) sum += f(kOrigin + kStep * i, kOrigin + kStep * j, kOrigin + kStep * k);
    return sum;
}

struct Contender {
    std::string name;
    std::function<float()> run;
    std::vector<double> rates; // M samples/s, one per round
};

struct Row {
    std::string name;
    double samples;
    std::vector<Contender> contenders; // FastNoise Lite (float), FastNoise Lite (double), cellfx
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
    const int rounds = argc > 1 ? std::atoi(argv[1]) : 15;
    if (rounds < 1) return 2;
    FastNoiseLite fnl(1337), fnl_fbm(1337);
    fnl.SetNoiseType(FastNoiseLite::NoiseType_Perlin);
    fnl.SetFrequency(1.0f);
    fnl_fbm.SetNoiseType(FastNoiseLite::NoiseType_Perlin);
    fnl_fbm.SetFrequency(1.0f);
    fnl_fbm.SetFractalType(FastNoiseLite::FractalType_FBm);
    fnl_fbm.SetFractalOctaves(4);
    fnl_fbm.SetFractalLacunarity(2.0f);
    fnl_fbm.SetFractalGain(0.5f);
    const fx::Noise noise(1337);
    fx::Fractal fbm;
    fbm.octaves = 4;

    const int n2 = 512, n3 = 64, f2 = 256, f3 = 32;
    std::vector<Row> rows = {
        {"perlin2",
         double(n2) * n2,
         {{"FastNoise Lite (float)", [&] { return loop2([&](double x, double y) { return fnl.GetNoise(float(x), float(y)); }, n2); }, {}},
          {"FastNoise Lite (double)", [&] { return loop2([&](double x, double y) { return fnl.GetNoise(x, y); }, n2); }, {}},
          {"cellfx", [&] { return loop2([&](double x, double y) { return noise.perlin2(x, y); }, n2); }, {}}}},
        {"perlin3",
         double(n3) * n3 * n3,
         {{"FastNoise Lite (float)",
           [&] { return loop3([&](double x, double y, double z) { return fnl.GetNoise(float(x), float(y), float(z)); }, n3); }, {}},
          {"FastNoise Lite (double)", [&] { return loop3([&](double x, double y, double z) { return fnl.GetNoise(x, y, z); }, n3); }, {}},
          {"cellfx", [&] { return loop3([&](double x, double y, double z) { return noise.perlin3(x, y, z); }, n3); }, {}}}},
        {"fbm2, 4 octaves",
         double(f2) * f2,
         {{"FastNoise Lite (float)", [&] { return loop2([&](double x, double y) { return fnl_fbm.GetNoise(float(x), float(y)); }, f2); }, {}},
          {"FastNoise Lite (double)", [&] { return loop2([&](double x, double y) { return fnl_fbm.GetNoise(x, y); }, f2); }, {}},
          {"cellfx", [&] { return loop2([&](double x, double y) { return noise.fractal2(fbm, x, y); }, f2); }, {}}}},
        {"fbm3, 4 octaves",
         double(f3) * f3 * f3,
         {{"FastNoise Lite (float)",
           [&] { return loop3([&](double x, double y, double z) { return fnl_fbm.GetNoise(float(x), float(y), float(z)); }, f3); }, {}},
          {"FastNoise Lite (double)",
           [&] { return loop3([&](double x, double y, double z) { return fnl_fbm.GetNoise(x, y, z); }, f3); }, {}},
          {"cellfx", [&] { return loop3([&](double x, double y, double z) { return noise.fractal3(fbm, x, y, z); }, f3); }, {}}}},
    };

    double checksum = 0.0;
    for (int r = 0; r < rounds; ++r)
        for (Row& row : rows)
            for (std::size_t k = 0; k < row.contenders.size(); ++k) {
                Contender& c = row.contenders[(k + static_cast<std::size_t>(r)) % row.contenders.size()];
                const double t0 = thread_seconds();
                checksum += c.run();
                const double t1 = thread_seconds();
                c.rates.push_back(row.samples / (t1 - t0) / 1e6);
            }

    std::printf("one call per sample, M samples/s on one thread (its CPU time), median (best) of %d rounds\n\n", rounds);
    std::printf("| function | FastNoise Lite (float) | FastNoise Lite (double) | cellfx | cellfx / FNL float | cellfx / FNL double |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const Row& row : rows) {
        std::printf("| %s |", row.name.c_str());
        for (const Contender& c : row.contenders)
            std::printf(" %.1f (%.1f) |", median(c.rates), *std::max_element(c.rates.begin(), c.rates.end()));
        for (std::size_t k = 0; k < 2; ++k) {
            std::vector<double> ratio;
            for (int r = 0; r < rounds; ++r) ratio.push_back(row.contenders[2].rates[r] / row.contenders[k].rates[r]);
            std::printf(" %.2f |", median(ratio));
        }
        std::printf("\n");
    }
    std::printf("\n(checksum %g)\n", checksum);
    return 0;
}
