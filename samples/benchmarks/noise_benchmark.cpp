// cellfx_noise_benchmark: samples per second of the noise bases, one core, scalar and batch.
//
//   ./build/samples/cellfx_noise_benchmark --benchmark_repetitions=5
//
// Items per second = samples per second. Every benchmark fills (or sums) 64×64×64 = 262144
// samples of a grid near x = 1000 (the cell split costs the same anywhere) and checks the values
// are finite and inside [-1, 1] after timing, so a broken kernel cannot look fast.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "fx/noise.hpp"

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
            for (std::size_t i = 0; i < kSide * 1; ++i)
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

} // namespace

BENCHMARK(perlin2_scalar);
BENCHMARK_CAPTURE(grid2, perlin2_grid, fx::NoiseBasis::perlin, 1);
BENCHMARK(perlin3_scalar);
BENCHMARK_CAPTURE(grid3, perlin3_grid, fx::NoiseBasis::perlin, 1);
BENCHMARK_CAPTURE(points3, perlin3_points, fx::NoiseBasis::perlin);
BENCHMARK_CAPTURE(grid4, perlin4_grid, fx::NoiseBasis::perlin);
BENCHMARK(simplex2_scalar);
BENCHMARK_CAPTURE(grid2, simplex2_grid, fx::NoiseBasis::simplex, 1);
BENCHMARK(simplex3_scalar);
BENCHMARK_CAPTURE(grid3, simplex3_grid, fx::NoiseBasis::simplex, 1);
BENCHMARK_CAPTURE(points3, simplex3_points, fx::NoiseBasis::simplex);
BENCHMARK(simplex4_scalar);
BENCHMARK_CAPTURE(grid4, simplex4_grid, fx::NoiseBasis::simplex);
BENCHMARK_CAPTURE(grid2, perlin2_fbm5_grid, fx::NoiseBasis::perlin, 5);
BENCHMARK_CAPTURE(grid3, perlin3_fbm5_grid, fx::NoiseBasis::perlin, 5);

BENCHMARK_MAIN();
