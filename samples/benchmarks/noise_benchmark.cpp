// cellfx_noise_benchmark: samples per second of the noise bases, one core, scalar and batch.
//
//   ./build/samples/cellfx_noise_benchmark --benchmark_repetitions=5
//
// items_per_second = samples per second, on one thread. Fills and one-call-per-sample Perlin
// and fractals use the AVX2 kernels where the CPU has them; CELLFX_NOISE_ISA=baseline runs the
// baseline (SSE2) ones instead. `cellfx bench noise` prints the same functions side by side.
// With repetitions, the `_median` row is the median run and the `_max` row's items_per_second
// the best run (its time column is then the slowest run: Google Benchmark applies one statistic
// to every column). Every benchmark fills
// (or sums) 64×64×64 = 262144 samples of a grid near x = 1000 (the cell split costs the same
// anywhere) and checks the values are finite and inside [-1, 1] after timing, so a broken kernel
// cannot look fast.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fx/noise.hpp"

namespace fx = cellfx::fx;

namespace {

constexpr std::size_t kSide = 64;
constexpr double kStep = 0.173; // irrational-ish spacing: samples land all over the cells
const fx::Noise kNoise(1337);

void verify(const std::vector<float>& values, const char* name) {
    for (float v : values)
        if (!std::isfinite(v) || v < -1.0f || v > 1.0f) {
            std::fprintf(stderr, "%s: value %g outside [-1, 1]\n", name, v);
            std::exit(1);
        }
}

fx::Fractal basis(fx::NoiseBasis b, int octaves = 1) {
    fx::Fractal f;
    f.basis = b;
    f.octaves = octaves;
    return f;
}

// --- scalar: one call per sample ---

void perlin2_scalar(benchmark::State& state) {
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t j = 0; j < kSide * kSide; ++j)
            for (std::size_t i = 0; i < kSide; ++i)
                sum += kNoise.perlin2(1000.0 + kStep * i, 1000.0 + kStep * j);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

void perlin3_scalar(benchmark::State& state) {
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t k = 0; k < kSide; ++k)
            for (std::size_t j = 0; j < kSide; ++j)
                for (std::size_t i = 0; i < kSide; ++i)
                    sum += kNoise.perlin3(1000.0 + kStep * i, 1000.0 + kStep * j, 1000.0 + kStep * k);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

// Scattered points, as particles would ask: nothing shared between consecutive calls.
void perlin3_scalar_random(benchmark::State& state) {
    std::vector<glm::dvec3> points(kSide * kSide * kSide);
    std::uint64_t h = 88172645463325252ull; // xorshift64: a fixed, portable sequence
    const auto next = [&h] {
        h ^= h << 13;
        h ^= h >> 7;
        h ^= h << 17;
        return 1000.0 + 100.0 * static_cast<double>(h >> 11) / 9007199254740992.0;
    };
    for (glm::dvec3& p : points) p = {next(), next(), next()};
    float sum = 0.0f;
    for (auto _ : state)
        for (const glm::dvec3& p : points) sum += kNoise.perlin3(p.x, p.y, p.z);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * points.size());
}

void simplex2_scalar(benchmark::State& state) {
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t j = 0; j < kSide * kSide; ++j)
            for (std::size_t i = 0; i < kSide; ++i)
                sum += kNoise.simplex2(1000.0 + kStep * i, 1000.0 + kStep * j);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

void simplex3_scalar(benchmark::State& state) {
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t k = 0; k < kSide; ++k)
            for (std::size_t j = 0; j < kSide; ++j)
                for (std::size_t i = 0; i < kSide; ++i)
                    sum += kNoise.simplex3(1000.0 + kStep * i, 1000.0 + kStep * j, 1000.0 + kStep * k);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

void simplex4_scalar(benchmark::State& state) {
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t k = 0; k < kSide; ++k)
            for (std::size_t j = 0; j < kSide; ++j)
                for (std::size_t i = 0; i < kSide; ++i)
                    sum += kNoise.simplex4(1000.0 + kStep * i, 1000.0 + kStep * j, 1000.0 + kStep * k, 3.5);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

// Fractal sums, 4 octaves of Perlin fBm, one call per sample.
void fbm2_scalar(benchmark::State& state) {
    const fx::Fractal f = basis(fx::NoiseBasis::perlin, 4);
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t j = 0; j < kSide * kSide; ++j)
            for (std::size_t i = 0; i < kSide; ++i) sum += kNoise.fractal2(f, 1000.0 + kStep * i, 1000.0 + kStep * j);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

void fbm3_scalar(benchmark::State& state) {
    const fx::Fractal f = basis(fx::NoiseBasis::perlin, 4);
    float sum = 0.0f;
    for (auto _ : state)
        for (std::size_t k = 0; k < kSide; ++k)
            for (std::size_t j = 0; j < kSide; ++j)
                for (std::size_t i = 0; i < kSide; ++i)
                    sum += kNoise.fractal3(f, 1000.0 + kStep * i, 1000.0 + kStep * j, 1000.0 + kStep * k);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * kSide * kSide * kSide);
}

// --- batch: fill_grid / fill_points ---

void grid2(benchmark::State& state, fx::NoiseBasis b, int octaves) {
    std::vector<float> out(kSide * kSide * kSide);
    const fx::Grid2 grid{{1000.0, 1000.0}, {kStep, kStep}, kSide, kSide * kSide};
    for (auto _ : state) {
        fx::fill_grid2(kNoise, basis(b, octaves), grid, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    verify(out, "grid2");
    state.SetItemsProcessed(state.iterations() * out.size());
}

void grid3(benchmark::State& state, fx::NoiseBasis b, int octaves) {
    std::vector<float> out(kSide * kSide * kSide);
    const fx::Grid3 grid{{1000.0, 1000.0, 1000.0}, {kStep, kStep, kStep}, kSide, kSide, kSide};
    for (auto _ : state) {
        fx::fill_grid3(kNoise, basis(b, octaves), grid, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    verify(out, "grid3");
    state.SetItemsProcessed(state.iterations() * out.size());
}

void grid4(benchmark::State& state, fx::NoiseBasis b) {
    std::vector<float> out(kSide * kSide * kSide);
    const fx::Grid4 grid{{1000.0, 1000.0, 1000.0, 3.5}, {kStep, kStep, kStep, 1.0}, kSide, kSide, kSide, 1};
    for (auto _ : state) {
        fx::fill_grid4(kNoise, basis(b), grid, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    verify(out, "grid4");
    state.SetItemsProcessed(state.iterations() * out.size());
}

void points3(benchmark::State& state, fx::NoiseBasis b) {
    std::vector<glm::dvec3> points;
    points.reserve(kSide * kSide * kSide);
    for (std::size_t k = 0; k < kSide; ++k)
        for (std::size_t j = 0; j < kSide; ++j)
            for (std::size_t i = 0; i < kSide; ++i)
                points.emplace_back(1000.0 + kStep * i, 1000.0 + kStep * j, 1000.0 + kStep * k);
    std::vector<float> out(points.size());
    for (auto _ : state) {
        fx::fill_points3(kNoise, basis(b), points.data(), points.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    verify(out, "points3");
    state.SetItemsProcessed(state.iterations() * out.size());
}

double max_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

} // namespace

#define NOISE_BENCHMARK(...) BENCHMARK(__VA_ARGS__)->ComputeStatistics("max", max_of)
#define NOISE_BENCHMARK_CAPTURE(...) BENCHMARK_CAPTURE(__VA_ARGS__)->ComputeStatistics("max", max_of)

NOISE_BENCHMARK(perlin2_scalar);
NOISE_BENCHMARK_CAPTURE(grid2, perlin2_grid, fx::NoiseBasis::perlin, 1);
NOISE_BENCHMARK(perlin3_scalar);
NOISE_BENCHMARK(perlin3_scalar_random);
NOISE_BENCHMARK_CAPTURE(grid3, perlin3_grid, fx::NoiseBasis::perlin, 1);
NOISE_BENCHMARK_CAPTURE(points3, perlin3_points, fx::NoiseBasis::perlin);
NOISE_BENCHMARK_CAPTURE(grid4, perlin4_grid, fx::NoiseBasis::perlin);
NOISE_BENCHMARK(simplex2_scalar);
NOISE_BENCHMARK_CAPTURE(grid2, simplex2_grid, fx::NoiseBasis::simplex, 1);
NOISE_BENCHMARK(simplex3_scalar);
NOISE_BENCHMARK_CAPTURE(grid3, simplex3_grid, fx::NoiseBasis::simplex, 1);
NOISE_BENCHMARK_CAPTURE(points3, simplex3_points, fx::NoiseBasis::simplex);
NOISE_BENCHMARK(simplex4_scalar);
NOISE_BENCHMARK_CAPTURE(grid4, simplex4_grid, fx::NoiseBasis::simplex);
NOISE_BENCHMARK(fbm2_scalar);
NOISE_BENCHMARK_CAPTURE(grid2, perlin2_fbm4_grid, fx::NoiseBasis::perlin, 4);
NOISE_BENCHMARK(fbm3_scalar);
NOISE_BENCHMARK_CAPTURE(grid3, perlin3_fbm4_grid, fx::NoiseBasis::perlin, 4);

BENCHMARK_MAIN();
