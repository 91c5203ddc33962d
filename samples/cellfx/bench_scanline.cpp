// Based on: Wilhelms, Tarantino & Van Gelder 1995, §4 (Tables 3 and 4, §4.3 memory)
//
// `cellfx bench scanline`: the CPU scan-line renderer on a synthetic nine-grid curvilinear
// data set with the dimensions of the paper's Table 3 (941,159 points). Prints seconds per
// frame (median and best of --repeat, and the process CPU time, which shows how much other
// load there was) on 1 and 2 threads, the speed-up, active polygons and memory by component
// next to the mesh's own size. The frames are verified after timing: all thread counts must
// give bit-identical, non-empty images.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/error.hpp"
#include "fx/scanline_renderer.hpp"
#include "harness/synthetic_meshes.hpp"
#include "options.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

} // namespace

int bench_scanline(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"size", "repeat", "scale", "threads"});
    if (!parsed.positional.empty()) throw fx::Error("bench scanline: unexpected argument '" + parsed.positional[0] + "'");
    int width = 512, height = 512;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const int repeat = int_option(parsed, "bench scanline", "repeat", 3);
    const double scale = number_option(parsed, "bench scanline", "scale", 1.0);
    // --threads 1,2 (default): the thread counts to time; the speed-up is against the first.
    std::vector<unsigned> thread_counts;
    for (const int n : int_list_option(parsed, "bench scanline", "threads", "1,2")) thread_counts.push_back(unsigned(n));

    using clock = std::chrono::steady_clock;
    auto t0 = clock::now();
    const fx::CellMesh mesh = fx::make_nine_grid_mesh(scale);
    const double t_mesh = std::chrono::duration<double>(clock::now() - t0).count();
    t0 = clock::now();
    const fx::ScanlineRenderer renderer(mesh);
    const double t_setup = std::chrono::duration<double>(clock::now() - t0).count();

    const fx::ScalarField& field = *mesh.find_scalar("density");
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    const fx::Camera camera = fx::Camera::framing(bounds.lo, bounds.hi, 40.0);
    // Extinction per world unit over a mesh about 2.5 units across: semi-transparent.
    const fx::TransferFunction tf({{0.0, {0.1, 0.2, 0.9}, 0.3},
                                   {0.4, {0.2, 0.8, 0.9}, 0.8},
                                   {0.6, {0.9, 0.9, 0.2}, 1.5},
                                   {1.0, {1.0, 0.2, 0.1}, 3.0}});

    std::printf("scan-line renderer, synthetic nine-grid data set (Wilhelms et al. Table 3 dimensions)\n");
    std::printf("  grids %zu, points %zu, cells %zu, triangles %zu (surface %zu)\n", mesh.blocks.size(),
                mesh.point_count(), mesh.cell_count(), renderer.triangle_count(), renderer.surface_triangle_count());
    std::printf("  build mesh %.2f s, renderer set-up (faces, topology) %.2f s; image %dx%d, %d frames per thread "
                "count, interleaved\n",
                t_mesh, t_setup, width, height, repeat);

    const std::size_t runs = thread_counts.size();
    std::vector<fx::Image> frames(runs);
    std::vector<fx::ScanlineStats> last_stats(runs);
    std::vector<std::vector<double>> times(runs), cpu_times(runs);
    // Thread counts take turns frame by frame, so that load from other processes on a shared
    // machine falls on all of them alike and the ratio stays meaningful.
    for (int r = 0; r < repeat; ++r) {
        for (std::size_t i = 0; i < runs; ++i) {
            fx::ScanlineOptions options;
            options.threads = thread_counts[i];
            const auto start = clock::now();
            const std::clock_t cpu_start = std::clock();
            frames[i] = renderer.render(camera, width, height, field, tf, options, &last_stats[i]);
            times[i].push_back(std::chrono::duration<double>(clock::now() - start).count());
            cpu_times[i].push_back(static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
        }
    }
    std::vector<double> seconds(runs);
    for (std::size_t i = 0; i < runs; ++i) {
        seconds[i] = median(times[i]);
        const fx::ScanlineStats& s = last_stats[i];
        std::printf("  %u thread%s: %.3f s/frame median, %.3f best, CPU %.3f s/frame  (last frame: transform %.3f, "
                    "y-buckets %.3f, scan %.3f)\n",
                    thread_counts[i], thread_counts[i] > 1 ? "s" : " ", seconds[i],
                    *std::min_element(times[i].begin(), times[i].end()), median(cpu_times[i]), s.seconds_transform,
                    s.seconds_y_buckets, s.seconds_scan);
    }
    // Verify after timing: identical frames, something drawn.
    for (std::size_t i = 1; i < runs; ++i) {
        if (frames[i].pixels != frames[0].pixels) {
            throw fx::Error("bench scanline: " + std::to_string(thread_counts[0]) + " and " +
                            std::to_string(thread_counts[i]) + " threads gave different frames");
        }
    }
    double energy = 0.0;
    for (const auto& p : frames[0].pixels) energy += p.a;
    if (!(energy > 0.01 * width * height)) throw fx::Error("bench scanline: the frame is (nearly) empty");

    for (std::size_t i = 1; i < runs; ++i) {
        std::printf("  speed-up %u threads: %.2fx (median against %u thread%s)\n", thread_counts[i],
                    seconds[0] / seconds[i], thread_counts[0], thread_counts[0] > 1 ? "s" : "");
    }
    const fx::ScanlineStats& s = last_stats.back();
    const fx::ScanlineMemory& m = s.memory;
    std::printf("  active polygons %zu of %zu (%.3f million), crossings %zu, near-clipped %zu\n", s.triangles_active,
                s.triangles_total, s.triangles_active / 1e6, s.crossings, s.triangles_near_clipped);
    std::printf("  memory (MiB, %u thread%s):\n", s.threads, s.threads > 1 ? "s" : "");
    std::printf("    mesh               %8.1f\n", mib(m.mesh));
    std::printf("    triangles          %8.1f\n", mib(m.triangles));
    std::printf("    transformed points %8.1f\n", mib(m.transformed_points));
    std::printf("    y-buckets          %8.1f\n", mib(m.y_buckets));
    std::printf("    bucket_clip_info   %8.1f\n", mib(m.bucket_clip_info));
    std::printf("    active lists       %8.1f\n", mib(m.active_lists));
    std::printf("    x-buckets          %8.1f\n", mib(m.x_buckets));
    std::printf("    frame buffer       %8.1f\n", mib(m.frame_buffer));
    std::printf("    renderer total     %8.1f  (%.2fx the mesh)\n", mib(m.renderer_total()),
                static_cast<double>(m.renderer_total()) / static_cast<double>(m.mesh));
    return 0;
}

} // namespace cellfx_cli
