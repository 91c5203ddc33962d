// cellfx — batch noise kernels: fill grids and point lists kLanes samples at a time. Compiled
// once per instruction set through noise_lanes_impl.hpp; see noise_lanes.hpp.
//
// Based on: the kernels of noise_kernels.hpp (Perlin 2002, Gustavson 2005) run on vector lanes.
// Work goes in blocks of kBlock samples that stay in L1: for each octave the block's coordinates
// are split in double lanes (or once per grid axis for Perlin grids, whose axes are separable),
// the kernel evaluates them in float lanes, and the octave is added to the block's running sum.
// Every lane does exactly the operations of the scalar path, so the results are the scalar ones.
//
// Nothing here may instantiate a template or inline function shared with other files (std::
// containers and algorithms, glm): the linker could keep this build's copy for everyone.
#define FX_NOISE_BATCH 1 // the double vector lanes of noise_kernels.hpp

#include "noise_lanes.hpp"

namespace cellfx::fx::noise_detail {
inline namespace FX_NOISE_ISA {
namespace {

static_assert(kBlock % kLanes == 0, "a block is whole vectors");

inline std::size_t smaller(std::size_t a, std::size_t b) { return a < b ? a : b; }


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
// does), then the kernel in float lanes. One loop per basis, so that each keeps its values in
// registers.
template <int N, NoiseBasis kBasis>
void evaluate_block_of(const FractalPlan& plan, const Coordinates<N>& c, std::size_t n, Block& b) {
    for (int o = 0; o < plan.octaves; ++o) {
        const VecU key = splat_u(VecU{}, mix_seed(plan.seed, o));
        for (std::size_t i = 0; i < n; i += kLanes) {
            VecD q[N];
            for (int a = 0; a < N; ++a) q[a] = octave_coordinate(load_lanes(c.x[a] + i), plan, o);
            VecF v;
            if constexpr (kBasis == NoiseBasis::perlin) {
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
template <int N> void evaluate_block(const FractalPlan& plan, const Coordinates<N>& c, std::size_t n, Block& b) {
    if (plan.basis == NoiseBasis::perlin) evaluate_block_of<N, NoiseBasis::perlin>(plan, c, n, b);
    else evaluate_block_of<N, NoiseBasis::simplex>(plan, c, n, b);
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
template <int N>
void fill_perlin_grid(const FractalPlan& plan, const GridSpec<N>& grid, const GridScratch<N>& scratch, float* out) {
    const std::size_t nx_padded = (grid.count[0] + kBlock - 1) / kBlock * kBlock;
    std::uint32_t keys[kMaxOctaves];
    for (int o = 0; o < plan.octaves; ++o) keys[o] = mix_seed(plan.seed, o);
    for (int o = 0; o < plan.octaves; ++o)
        for (int a = 0; a < N; ++a) {
            const AxisTable& table = scratch.table[o][a];
            for (std::size_t i = 0; i < grid.count[a]; ++i) {
                const double x = grid.origin[a] + grid.step[a] * static_cast<double>(i);
                const PerlinAxis<F1, U1> s = perlin_axis(octave_coordinate(x, plan, o), kPrimes[a]);
                table.cell[i] = s.cell;
                table.t[i] = s.t;
                table.fade[i] = s.fade;
            }
            if (a == 0)
                for (std::size_t i = grid.count[0]; i < nx_padded; ++i) {
                    table.cell[i] = 0u;
                    table.t[i] = 0.0f;
                    table.fade[i] = 0.0f;
                }
        }

    Block b;
    for_each_row<N>(grid.count, out, [&](const std::size_t (&index)[N], float* row_out) {
        for (std::size_t start = 0; start < grid.count[0]; start += kBlock) {
            const std::size_t n = smaller(kBlock, grid.count[0] - start);
            for (int o = 0; o < plan.octaves; ++o) {
                const VecU key = splat_u(VecU{}, keys[o]);
                const AxisTable* t = scratch.table[o];
                VAxis ax[N];
                for (int a = 1; a < N; ++a) {
                    const std::size_t k = index[a];
                    ax[a] = {splat_u(VecU{}, t[a].cell[k]), splat_f(VecF{}, t[a].t[k]), splat_f(VecF{}, t[a].fade[k])};
                }
                for (std::size_t i = 0; i < n; i += kLanes) {
                    const std::size_t x = start + i;
                    ax[0] = {load_lanes(t[0].cell + x), load_lanes(t[0].t + x), load_lanes(t[0].fade + x)};
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
void fill_simplex_grid(const FractalPlan& plan, const GridSpec<N>& grid, const GridScratch<N>& scratch, float* out) {
    for (int a = 0; a < N; ++a)
        for (std::size_t i = 0; i < grid.count[a]; ++i)
            scratch.coordinate[a][i] = grid.origin[a] + grid.step[a] * static_cast<double>(i);
    Block b;
    Coordinates<N> c;
    for_each_row<N>(grid.count, out, [&](const std::size_t (&index)[N], float* row_out) {
        for (std::size_t start = 0; start < grid.count[0]; start += kBlock) {
            const std::size_t n = smaller(kBlock, grid.count[0] - start);
            for (std::size_t i = 0; i < n; ++i) {
                c.x[0][i] = scratch.coordinate[0][start + i];
                for (int a = 1; a < N; ++a) c.x[a][i] = scratch.coordinate[a][index[a]];
            }
            c.pad(n);
            evaluate_block<N>(plan, c, n, b);
            b.finish_to(row_out + start, n);
        }
    });
}

template <int N> void fill_grid(const FractalPlan& plan, const GridSpec<N>& grid, const GridScratch<N>& scratch, float* out) {
    if (plan.basis == NoiseBasis::perlin) fill_perlin_grid<N>(plan, grid, scratch, out);
    else fill_simplex_grid<N>(plan, grid, scratch, out);
}

template <int N>
void fill_points(const FractalPlan& plan, const double* coords, std::size_t stride, std::size_t count, float* out) {
    Block b;
    Coordinates<N> c;
    for (std::size_t start = 0; start < count; start += kBlock) {
        const std::size_t n = smaller(kBlock, count - start);
        for (std::size_t i = 0; i < n; ++i)
            for (int a = 0; a < N; ++a) c.x[a][i] = coords[(start + i) * stride + static_cast<std::size_t>(a)];
        c.pad(n);
        evaluate_block<N>(plan, c, n, b);
        b.finish_to(out + start, n);
    }
}

} // namespace
} // namespace FX_NOISE_ISA

} // namespace cellfx::fx::noise_detail
