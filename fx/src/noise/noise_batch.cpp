// cellfx — the public batch fills: validate, allocate scratch and run the chosen kernels
// (noise_lanes.hpp); domain warp of point arrays on top.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "fx/error.hpp"
#include "fx/noise.hpp"
#include "noise_lanes.hpp"

namespace cellfx::fx {
namespace noise_detail {
namespace {

// Scratch for fill_grid: the tables of GridScratch carved out of one allocation.
template <int N> struct GridStorage {
    std::vector<double> memory;
    GridScratch<N> scratch{};

    GridStorage(const FractalPlan& plan, const GridSpec<N>& grid) {
        std::size_t length[N];
        std::size_t total = 0;
        for (int a = 0; a < N; ++a) {
            length[a] = a == 0 ? (grid.count[0] + kBlock - 1) / kBlock * kBlock : grid.count[a];
            total += length[a];
        }
        if (plan.basis == NoiseBasis::perlin) {
            // per octave and axis: cell (4 bytes), t and fade (4 each) — 12 bytes per entry
            const std::size_t bytes = static_cast<std::size_t>(plan.octaves) * total * 12;
            memory.resize(bytes / sizeof(double) + 1);
            auto* p = reinterpret_cast<unsigned char*>(memory.data());
            for (int o = 0; o < plan.octaves; ++o)
                for (int a = 0; a < N; ++a) {
                    scratch.table[o][a].cell = reinterpret_cast<std::uint32_t*>(p);
                    scratch.table[o][a].t = reinterpret_cast<float*>(p + 4 * length[a]);
                    scratch.table[o][a].fade = reinterpret_cast<float*>(p + 8 * length[a]);
                    p += 12 * length[a];
                }
        } else {
            memory.resize(total);
            double* p = memory.data();
            for (int a = 0; a < N; ++a) {
                scratch.coordinate[a] = p;
                p += length[a];
            }
        }
    }
};

template <int N>
void fill_grid(const char* where, const Noise& noise, const Fractal& fractal, const GridSpec<N>& grid,
               void (*kernel)(const FractalPlan&, const GridSpec<N>&, const GridScratch<N>&, float*), float* out) {
    check_fractal(fractal, where, "Fractal");
    std::size_t total = 1;
    for (int a = 0; a < N; ++a) {
        if (grid.count[a] != 0 && total > std::numeric_limits<std::size_t>::max() / grid.count[a])
            throw Error(std::string(where) + "the grid's sample count overflows std::size_t");
        total *= grid.count[a];
    }
    if (total == 0) return;
    if (out == nullptr) throw Error(std::string(where) + "out is null");
    const FractalPlan plan = make_plan(fractal, noise.seed());
    const GridStorage<N> storage(plan, grid);
    kernel(plan, grid, storage.scratch, out);
}

using PointsKernel = void (*)(const FractalPlan&, const double*, std::size_t, std::size_t, float*);

template <int N, class Vec>
void fill_points(const char* where, const Noise& noise, const Fractal& fractal, const Vec* points, std::size_t count,
                 PointsKernel kernel, float* out) {
    static_assert(sizeof(Vec) == N * sizeof(double), "glm vectors are N packed doubles");
    check_fractal(fractal, where, "Fractal");
    if (count == 0) return;
    if (points == nullptr) throw Error(std::string(where) + "points is null");
    if (out == nullptr) throw Error(std::string(where) + "out is null");
    kernel(make_plan(fractal, noise.seed()), &points[0].x, N, count, out);
}

template <int N, class Vec>
void warp_points(const char* where, const Noise& noise, const DomainWarp& warp, Vec* points, std::size_t count,
                 PointsKernel kernel) {
    static_assert(sizeof(Vec) == N * sizeof(double), "glm vectors are N packed doubles");
    check_warp(warp, where);
    if (count == 0) return;
    if (points == nullptr) throw Error(std::string(where) + "points is null");
    FractalPlan plans[N];
    for (int a = 0; a < N; ++a) plans[a] = make_plan(warp.fractal, warp_seed(noise.seed(), a));
    // Displacements of a chunk for every axis first: each axis samples the unmoved point.
    constexpr std::size_t kChunk = 16 * kBlock;
    std::vector<float> d(kChunk * N);
    for (std::size_t start = 0; start < count; start += kChunk) {
        const std::size_t n = std::min(kChunk, count - start);
        for (int a = 0; a < N; ++a) kernel(plans[a], &points[start].x, N, n, d.data() + a * kChunk);
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < N; ++a)
                points[start + i][a] = points[start + i][a] + warp.amplitude * static_cast<double>(d[a * kChunk + i]);
    }
}

} // namespace

} // namespace noise_detail

using namespace noise_detail;

void fill_grid2(const Noise& noise, const Fractal& fractal, const Grid2& g, float* out) {
    const GridSpec<2> grid{{g.origin.x, g.origin.y}, {g.step.x, g.step.y}, {g.nx, g.ny}};
    fill_grid<2>("fx::fill_grid2: ", noise, fractal, grid, lane_kernels().fill_grid2, out);
}
void fill_grid3(const Noise& noise, const Fractal& fractal, const Grid3& g, float* out) {
    const GridSpec<3> grid{{g.origin.x, g.origin.y, g.origin.z}, {g.step.x, g.step.y, g.step.z}, {g.nx, g.ny, g.nz}};
    fill_grid<3>("fx::fill_grid3: ", noise, fractal, grid, lane_kernels().fill_grid3, out);
}
void fill_grid4(const Noise& noise, const Fractal& fractal, const Grid4& g, float* out) {
    const GridSpec<4> grid{{g.origin.x, g.origin.y, g.origin.z, g.origin.w},
                           {g.step.x, g.step.y, g.step.z, g.step.w},
                           {g.nx, g.ny, g.nz, g.nw}};
    fill_grid<4>("fx::fill_grid4: ", noise, fractal, grid, lane_kernels().fill_grid4, out);
}

void fill_points2(const Noise& noise, const Fractal& fractal, const glm::dvec2* points, std::size_t count, float* out) {
    fill_points<2>("fx::fill_points2: ", noise, fractal, points, count, lane_kernels().fill_points2, out);
}
void fill_points3(const Noise& noise, const Fractal& fractal, const glm::dvec3* points, std::size_t count, float* out) {
    fill_points<3>("fx::fill_points3: ", noise, fractal, points, count, lane_kernels().fill_points3, out);
}
void fill_points4(const Noise& noise, const Fractal& fractal, const glm::dvec4* points, std::size_t count, float* out) {
    fill_points<4>("fx::fill_points4: ", noise, fractal, points, count, lane_kernels().fill_points4, out);
}

void warp_points2(const Noise& noise, const DomainWarp& warp, glm::dvec2* points, std::size_t count) {
    warp_points<2>("fx::warp_points2: ", noise, warp, points, count, lane_kernels().fill_points2);
}
void warp_points3(const Noise& noise, const DomainWarp& warp, glm::dvec3* points, std::size_t count) {
    warp_points<3>("fx::warp_points3: ", noise, warp, points, count, lane_kernels().fill_points3);
}

} // namespace cellfx::fx
