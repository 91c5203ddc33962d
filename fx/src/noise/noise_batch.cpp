// cellfx — batch noise: fill grids and point lists kLanes samples at a time.
//
// Based on: the kernels of noise_kernels.hpp (Perlin 2002, Gustavson 2005) run on vector lanes.
// Work goes in blocks of kBlock samples that stay in L1: for each octave the block's inputs are
// split in double (per sample, or once per grid axis for Perlin grids, whose axes are separable),
// the vector kernel evaluates them, and the octave is added to the block's running sum. Every
// lane does exactly the operations of the scalar path, so the results are the scalar ones.
// The coordinate split runs in double lanes (two SSE2 registers per four samples), the kernels
// in float lanes.
#define FX_NOISE_BATCH 1 // the double vector lanes of noise_kernels.hpp

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "fx/error.hpp"
#include "fx/noise.hpp"
#include "noise_fractal.hpp"

namespace fx {
namespace noise_detail {
namespace {

constexpr std::size_t kBlock = 64;
static_assert(kBlock % kLanes == 0, "a block is whole vectors");

#if FX_NOISE_HAVE_VECTOR
inline VecF load_lanes(const float* p) { return load_f(p); }
inline VecU load_lanes(const std::uint32_t* p) { return load_u(p); }
inline void store_lanes(float* p, VecF v) { store_f(p, v); }
inline VecD load_lanes(const double* p) { return load_d(p); }
#else
using VecD = D1;
inline VecF load_lanes(const float* p) { return *p; }
inline VecU load_lanes(const std::uint32_t* p) { return *p; }
inline VecD load_lanes(const double* p) { return *p; }
inline void store_lanes(float* p, VecF v) { *p = v; }
#endif

using VAxis = PerlinAxis<VecF, VecU>;

template <int N> VecF perlin_lanes(VecU key, const VAxis (&a)[N]) {
    if constexpr (N == 2) return perlin2<VecF, VecU>(key, a[0], a[1]);
    else if constexpr (N == 3) return perlin3<VecF, VecU>(key, a[0], a[1], a[2]);
    else return perlin4<VecF, VecU>(key, a[0], a[1], a[2], a[3]);
}

template <int N> VecF simplex_lanes(VecU key, const SimplexSample<VecF, VecU, N>& s) {
    if constexpr (N == 2) return simplex2<VecF, VecU>(key, s);
    else if constexpr (N == 3) return simplex3<VecF, VecU>(key, s);
    else return simplex4<VecF, VecU>(key, s);
}

template <int N> constexpr double skew() { return N == 2 ? kF2 : N == 3 ? kF3 : kF4; }
template <int N> constexpr double unskew() { return N == 2 ? kG2 : N == 3 ? kG3 : kG4; }

// The running sums of one block.
struct Block {
    alignas(64) float sum[kBlock];

    // Add octave o's lane values v at i..i+kLanes.
    void add(const FractalPlan& plan, int o, std::size_t i, VecF v) {
        const VecF shaped = shape(plan.type, v);
        store_lanes(sum + i, accumulate(o, o == 0 ? shaped : load_lanes(sum + i), shaped, plan.amplitude[o]));
    }
    void finish_to(float* out, std::size_t n) {
        for (std::size_t i = 0; i < n; i += kLanes) store_lanes(sum + i, finish(load_lanes(sum + i)));
        for (std::size_t i = 0; i < n; ++i) out[i] = sum[i];
    }
};

// The coordinates of one block's samples, per axis (lanes past the block's end are 0).
template <int N> struct Coordinates {
    alignas(64) double x[N][kBlock];

    void pad(std::size_t n) {
        for (std::size_t i = n; i < (n + kLanes - 1) / kLanes * kLanes; ++i)
            for (int a = 0; a < N; ++a) x[a][i] = 0.0;
    }
};

// Every octave of a block into its running sums: split in double lanes (scaled as fractal_sum
// does), then the kernel in float lanes.
template <int N> void evaluate_block(const FractalPlan& plan, const Coordinates<N>& c, std::size_t n, Block& b) {
    for (int o = 0; o < plan.octaves; ++o) {
        const VecU key = splat_u(VecU{}, plan.key[o]);
        for (std::size_t i = 0; i < n; i += kLanes) {
            VecD q[N];
            for (int a = 0; a < N; ++a) q[a] = octave_coordinate(load_lanes(c.x[a] + i), plan, o);
            VecF v;
            if (plan.basis == NoiseBasis::perlin) {
                VAxis ax[N];
                for (int a = 0; a < N; ++a) ax[a] = perlin_axis(q[a], kPrimes[a]);
                v = perlin_lanes<N>(key, ax);
            } else {
                v = simplex_lanes<N>(key, simplex_sample<N>(q, skew<N>(), unskew<N>()));
            }
            b.add(plan, o, i, v);
        }
    }
}

// Calls row_fn(index, out_row) for every row of the grid (x fastest, so a row is count[0]
// consecutive samples); index[0] is 0 and the other entries give the row's position.
template <int N, class RowFn> void for_each_row(const std::size_t (&count)[N], float* out, const RowFn& row_fn) {
    std::size_t index[N] = {};
    std::size_t rows = 1;
    for (int a = 1; a < N; ++a) rows *= count[a];
    for (std::size_t row = 0; row < rows; ++row) {
        row_fn(index, out + row * count[0]);
        for (int a = 1; a < N && ++index[a] == count[a]; ++a) index[a] = 0;
    }
}

// Perlin on a grid: the axes are separable, so each axis is split once per octave into a table
// (cell·prime, offset, fade) and the rows combine table entries (x in lanes, the rest broadcast).
struct AxisTable {
    std::vector<std::uint32_t> cell;
    std::vector<float> t, fade;
};

template <int N>
void fill_perlin_grid(const FractalPlan& plan, const double (&origin)[N], const double (&step)[N],
                      const std::size_t (&count)[N], float* out) {
    // tables[o * N + a]; the x tables are padded to whole blocks.
    std::vector<AxisTable> tables(static_cast<std::size_t>(plan.octaves) * N);
    const std::size_t nx_padded = (count[0] + kBlock - 1) / kBlock * kBlock;
    for (int o = 0; o < plan.octaves; ++o)
        for (int a = 0; a < N; ++a) {
            AxisTable& table = tables[static_cast<std::size_t>(o) * N + a];
            const std::size_t n = a == 0 ? nx_padded : count[a];
            table.cell.assign(n, 0u);
            table.t.assign(n, 0.0f);
            table.fade.assign(n, 0.0f);
            for (std::size_t i = 0; i < count[a]; ++i) {
                const double x = origin[a] + step[a] * static_cast<double>(i);
                const PerlinAxis<F1, U1> s = perlin_axis(octave_coordinate(x, plan, o), kPrimes[a]);
                table.cell[i] = s.cell;
                table.t[i] = s.t;
                table.fade[i] = s.fade;
            }
        }

    Block b;
    for_each_row<N>(count, out, [&](const std::size_t (&index)[N], float* row_out) {
        for (std::size_t start = 0; start < count[0]; start += kBlock) {
            const std::size_t n = std::min(kBlock, count[0] - start);
            for (int o = 0; o < plan.octaves; ++o) {
                const VecU key = splat_u(VecU{}, plan.key[o]);
                const AxisTable* t = &tables[static_cast<std::size_t>(o) * N];
                VAxis ax[N];
                for (int a = 1; a < N; ++a) {
                    const std::size_t k = index[a];
                    ax[a] = {splat_u(VecU{}, t[a].cell[k]), splat_f(VecF{}, t[a].t[k]), splat_f(VecF{}, t[a].fade[k])};
                }
                for (std::size_t i = 0; i < n; i += kLanes) {
                    const std::size_t x = start + i;
                    ax[0] = {load_lanes(t[0].cell.data() + x), load_lanes(t[0].t.data() + x),
                             load_lanes(t[0].fade.data() + x)};
                    b.add(plan, o, i, perlin_lanes<N>(key, ax));
                }
            }
            b.finish_to(row_out + start, n);
        }
    });
}

// Simplex on a grid: the skew mixes the axes, so samples are split one by one, but the
// coordinates come from per-axis tables, a row at a time.
template <int N>
void fill_simplex_grid(const FractalPlan& plan, const double (&origin)[N], const double (&step)[N],
                       const std::size_t (&count)[N], float* out) {
    std::vector<double> coordinate[N];
    for (int a = 0; a < N; ++a) {
        coordinate[a].resize(count[a]);
        for (std::size_t i = 0; i < count[a]; ++i) coordinate[a][i] = origin[a] + step[a] * static_cast<double>(i);
    }
    Block b;
    Coordinates<N> c;
    for_each_row<N>(count, out, [&](const std::size_t (&index)[N], float* row_out) {
        for (std::size_t start = 0; start < count[0]; start += kBlock) {
            const std::size_t n = std::min(kBlock, count[0] - start);
            for (std::size_t i = 0; i < n; ++i) c.x[0][i] = coordinate[0][start + i];
            for (int a = 1; a < N; ++a) std::fill(c.x[a], c.x[a] + n, coordinate[a][index[a]]);
            c.pad(n);
            evaluate_block<N>(plan, c, n, b);
            b.finish_to(row_out + start, n);
        }
    });
}

template <int N>
void fill_grid(const char* where, const Noise& noise, const Fractal& fractal, const double (&origin)[N],
               const double (&step)[N], const std::size_t (&count)[N], float* out) {
    check_fractal(fractal, where, "Fractal");
    std::size_t total = 1;
    for (int a = 0; a < N; ++a) {
        if (count[a] != 0 && total > std::numeric_limits<std::size_t>::max() / count[a])
            throw Error(std::string(where) + "the grid's sample count overflows std::size_t");
        total *= count[a];
    }
    if (total == 0) return;
    if (out == nullptr) throw Error(std::string(where) + "out is null");
    const FractalPlan plan = make_plan(fractal, noise.seed());
    if (plan.basis == NoiseBasis::perlin) fill_perlin_grid<N>(plan, origin, step, count, out);
    else fill_simplex_grid<N>(plan, origin, step, count, out);
}

// A list of glm vectors (N components each), in blocks.
template <int N, class Vec> void fill_point_list(const FractalPlan& plan, const Vec* points, std::size_t count, float* out) {
    Block b;
    Coordinates<N> c;
    for (std::size_t start = 0; start < count; start += kBlock) {
        const std::size_t n = std::min(kBlock, count - start);
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < N; ++a) c.x[a][i] = points[start + i][a];
        c.pad(n);
        evaluate_block<N>(plan, c, n, b);
        b.finish_to(out + start, n);
    }
}

template <int N, class Vec>
void fill_points(const char* where, const Noise& noise, const Fractal& fractal, const Vec* points, std::size_t count,
                 float* out) {
    check_fractal(fractal, where, "Fractal");
    if (count == 0) return;
    if (points == nullptr) throw Error(std::string(where) + "points is null");
    if (out == nullptr) throw Error(std::string(where) + "out is null");
    fill_point_list<N>(make_plan(fractal, noise.seed()), points, count, out);
}

template <int N, class Vec>
void warp_points(const char* where, const Noise& noise, const DomainWarp& warp, Vec* points, std::size_t count) {
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
        for (int a = 0; a < N; ++a) fill_point_list<N>(plans[a], points + start, n, d.data() + a * kChunk);
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < N; ++a)
                points[start + i][a] = points[start + i][a] + warp.amplitude * static_cast<double>(d[a * kChunk + i]);
    }
}

} // namespace
} // namespace noise_detail

using namespace noise_detail;

void fill_grid2(const Noise& noise, const Fractal& fractal, const Grid2& g, float* out) {
    const double origin[2] = {g.origin.x, g.origin.y}, step[2] = {g.step.x, g.step.y};
    const std::size_t count[2] = {g.nx, g.ny};
    fill_grid<2>("fx::fill_grid2: ", noise, fractal, origin, step, count, out);
}
void fill_grid3(const Noise& noise, const Fractal& fractal, const Grid3& g, float* out) {
    const double origin[3] = {g.origin.x, g.origin.y, g.origin.z}, step[3] = {g.step.x, g.step.y, g.step.z};
    const std::size_t count[3] = {g.nx, g.ny, g.nz};
    fill_grid<3>("fx::fill_grid3: ", noise, fractal, origin, step, count, out);
}
void fill_grid4(const Noise& noise, const Fractal& fractal, const Grid4& g, float* out) {
    const double origin[4] = {g.origin.x, g.origin.y, g.origin.z, g.origin.w};
    const double step[4] = {g.step.x, g.step.y, g.step.z, g.step.w};
    const std::size_t count[4] = {g.nx, g.ny, g.nz, g.nw};
    fill_grid<4>("fx::fill_grid4: ", noise, fractal, origin, step, count, out);
}

void fill_points2(const Noise& noise, const Fractal& fractal, const glm::dvec2* points, std::size_t count, float* out) {
    fill_points<2>("fx::fill_points2: ", noise, fractal, points, count, out);
}
void fill_points3(const Noise& noise, const Fractal& fractal, const glm::dvec3* points, std::size_t count, float* out) {
    fill_points<3>("fx::fill_points3: ", noise, fractal, points, count, out);
}
void fill_points4(const Noise& noise, const Fractal& fractal, const glm::dvec4* points, std::size_t count, float* out) {
    fill_points<4>("fx::fill_points4: ", noise, fractal, points, count, out);
}

void warp_points2(const Noise& noise, const DomainWarp& warp, glm::dvec2* points, std::size_t count) {
    warp_points<2>("fx::warp_points2: ", noise, warp, points, count);
}
void warp_points3(const Noise& noise, const DomainWarp& warp, glm::dvec3* points, std::size_t count) {
    warp_points<3>("fx::warp_points3: ", noise, warp, points, count);
}

} // namespace fx
