// Based on: Wilhelms, Tarantino & Van Gelder 1995, §4 (Tables 3 and 4, §4.3 memory)
//
// `cellfx bench scanline`: the CPU scan-line renderer on a synthetic nine-grid curvilinear
// data set with the dimensions of the paper's Table 3 (941,159 points). Prints seconds per
// frame (median of --repeat) on 1 and 2 threads, the speed-up, active polygons and memory
// by component next to the mesh's own size. The frames are verified after timing: both
// thread counts must give bit-identical, non-empty images.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fx/error.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/synthetic_meshes.hpp"
#include "options.hpp"

namespace cellfx_cli {
namespace {

double mib(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace

int bench_scanline(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"size", "repeat", "scale"});
    if (!parsed.positional.empty()) throw fx::Error("bench scanline: unexpected argument '" + parsed.positional[0] + "'");
    int width = 512, height = 512;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const int repeat = parse_int(parsed.get("repeat", "3"), "--repeat");
    const double scale = parse_double(parsed.get("scale", "1.0"), "--scale");
    if (repeat < 1) throw fx::Error("bench scanline: --repeat must be at least 1");

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
    std::printf("  build mesh %.2f s, renderer set-up (faces, topology) %.2f s; image %dx%d, median of %d\n", t_mesh,
                t_setup, width, height, repeat);

    fx::Image frames[2];
    fx::ScanlineStats last_stats[2];
    double seconds[2];
    const unsigned thread_counts[2] = {1, 2};
    for (int i = 0; i < 2; ++i) {
        fx::ScanlineOptions options;
        options.threads = thread_counts[i];
        std::vector<double> times;
        for (int r = 0; r < repeat; ++r) {
            fx::ScanlineStats stats;
            const auto start = clock::now();
            frames[i] = renderer.render(camera, width, height, field, tf, options, &stats);
            times.push_back(std::chrono::duration<double>(clock::now() - start).count());
            last_stats[i] = stats;
        }
        seconds[i] = median(times);
        const fx::ScanlineStats& s = last_stats[i];
        std::printf("  %u thread%s: %.3f s/frame  (transform %.3f, y-buckets %.3f, scan %.3f)\n", thread_counts[i],
                    thread_counts[i] > 1 ? "s" : " ", seconds[i], s.seconds_transform, s.seconds_y_buckets,
                    s.seconds_scan);
    }
    // Verify after timing: identical frames, something drawn.
    if (frames[0].pixels != frames[1].pixels) throw fx::Error("bench scanline: 1 and 2 threads gave different frames");
    double energy = 0.0;
    for (const auto& p : frames[0].pixels) energy += p.a;
    if (!(energy > 0.01 * width * height)) throw fx::Error("bench scanline: the frame is (nearly) empty");

    const fx::ScanlineStats& s = last_stats[1];
    const fx::ScanlineMemory& m = s.memory;
    std::printf("  speed-up 2 threads: %.2fx\n", seconds[0] / seconds[1]);
    std::printf("  active polygons %zu of %zu (%.3f million), crossings %zu, near-clipped %zu\n", s.triangles_active,
                s.triangles_total, s.triangles_active / 1e6, s.crossings, s.triangles_near_clipped);
    std::printf("  memory (MiB, 2 threads):\n");
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
