// Based on: Roettger & Ertl 2003, §4 (hexahedra per second for PCP and MIP)
//
// `cellfx bench pcp`: cells per second of the three GPU cell-projection paths (pcp classic,
// pcp-exact, mip) on the blunt fin (37,479 hexahedra) and on a synthetic ~1M-cell hexahedral
// grid, at 512² and 1024². GPU time per frame is the median of --repeat GL_TIME_ELAPSED
// queries around all of a frame's GL work (classic PCP's per-frame CPU work — projection,
// caps, batching, upload — is printed separately). After timing, every frame is read back and
// verified: finite, not empty, and classic PCP and MIP compared with pcp-exact (same
// emission model for classic: its error is the price of the 8-bit passes; a frame that is
// empty or not finite is an error). Prints the
// classic/exact ratios in time and the classic error.
//
// Options: --repeat N (5), --grid N (hex grid of N³ cells, 100), --sizes 512,1024,
//          --mesh XYZ [--q Q] (default: the shipped content/meshes/blunt_fin).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "harness/headless_context.hpp"
#include "fx/mesh_io.hpp"
#include "harness/synthetic_meshes.hpp"
#include "options.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

// An n³ grid of hexahedra on the unit cube with a smooth field.
fx::CellMesh hex_grid(int n) {
    fx::CellMesh mesh;
    const std::uint32_t nodes = std::uint32_t(n + 1);
    fx::append_curvilinear_block(mesh, "grid", {nodes, nodes, nodes},
                                 [](double u, double v, double w) { return glm::dvec3(u, v, w); });
    fx::set_scalar_field(mesh, "density", [](const glm::dvec3& p) {
        return 0.5 + 0.5 * std::sin(7.0 * p.x) * std::cos(5.0 * p.y) * std::sin(3.0 + 4.0 * p.z);
    });
    return mesh;
}

verify::Options rgb() {
    verify::Options o;
    o.channels = 3;
    return o;
}

// The frame against `reference` (RGB): finite, its mean and worst difference.
verify::Difference difference(const fx::Image& image, const fx::Image& reference) {
    return verify::measure(image, reference, rgb());
}

void run_mesh(const std::string& name, const fx::CellMesh& mesh, const std::vector<int>& sizes, int repeat,
              double emission_scale) {
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const fx::Camera cam = fx::Camera::framing(b.lo, b.hi, 40.0);
    // Normalised: mapped onto the field's range. Scaled so that classic PCP's 8-bit target
    // does not saturate (κ·Δd/2 per cell and the sum per pixel below 1).
    const fx::TransferFunction tf({{0.0, glm::dvec3(0.2, 0.5, 1.0) * emission_scale, 0.1},
                                   {0.4, glm::dvec3(0.6, 0.4, 0.5) * emission_scale, 0.5},
                                   {1.0, glm::dvec3(1.0, 0.9, 0.3) * emission_scale, 1.0}},
                                  true);
    fx::CellRenderer renderer(mesh, "density", tf);
    std::printf("\n%s: %zu cells, %zu points, GPU buffers %.1f MiB\n", name.c_str(), mesh.cell_count(),
                mesh.point_count(), double(renderer.gpu_bytes()) / (1024.0 * 1024.0));
    std::printf("  %-10s %-9s %10s %10s %14s %8s %8s  %s\n", "size", "path", "gpu ms", "cpu ms", "cells/s", "batches",
                "draws", "verified against pcp-exact");
    for (int size : sizes) {
        const fx::RenderPath paths[] = {fx::RenderPath::PcpExact, fx::RenderPath::Pcp, fx::RenderPath::Mip};
        fx::Image exact_image;
        double exact_ms = 0.0;
        for (fx::RenderPath path : paths) {
            fx::CellRenderOptions o;
            o.timing = true;
            std::vector<double> gpu, cpu;
            fx::CellRenderStats stats;
            fx::Image image;
            renderer.render_to_image(cam, size, size, path, o, &stats); // warm-up (shader JIT, buffers)
            for (int r = 0; r < repeat; ++r) {
                image = renderer.render_to_image(cam, size, size, path, o, &stats);
                gpu.push_back(stats.gpu_ms);
                cpu.push_back(stats.cpu_ms);
            }
            const double ms = median(gpu);
            std::ostringstream check;
            if (path == fx::RenderPath::PcpExact) {
                exact_image = image;
                exact_ms = ms;
                const verify::Difference v = difference(image, image);
                if (v.nonfinite || !(v.peak > 0.0)) throw fx::Error("bench pcp: pcp-exact frame is empty or not finite");
                check << "reference (peak " << v.peak << ")";
            } else {
                const verify::Difference v = difference(image, exact_image);
                if (v.nonfinite) throw fx::Error(std::string("bench pcp: ") + fx::render_path_name(path) + " frame is not finite");
                if (path == fx::RenderPath::Pcp) {
                    // Its error is the measurement, not a failure (faint cells round to 0 in
                    // 8 bits); only an empty frame is.
                    if (!(verify::peak(image, rgb()) > 0.0)) throw fx::Error("bench pcp: classic frame is empty");
                    check << "mean |err| " << v.mean << " (" << 100.0 * v.of_peak(v.mean) << "% of peak), max "
                          << v.worst.delta << "; classic/exact time " << ms / exact_ms;
                } else {
                    const double peak = verify::peak(image, rgb());
                    if (!(peak > 0.0)) throw fx::Error("bench pcp: mip frame is empty");
                    check << "non-empty (max " << peak << ")";
                }
            }
            char label[32];
            std::snprintf(label, sizeof label, "%dx%d", size, size);
            std::printf("  %-10s %-9s %10.3f %10.3f %14.0f %8zu %8zu  %s\n", label, fx::render_path_name(path), ms,
                        median(cpu), double(mesh.cell_count()) / (ms * 1e-3), stats.batches, stats.draw_calls,
                        check.str().c_str());
        }
    }
}

std::string find_blunt_fin(const std::string& file) {
    // The shipped copy: beside the working directory, or in the source tree this was built from.
    for (const std::string& dir : {std::string("content/meshes/blunt_fin/"),
                                  std::string(CELLFX_SOURCE_DIR) + "/content/meshes/blunt_fin/"})
        if (std::filesystem::exists(dir + file)) return dir + file;
    throw fx::Error("bench pcp: cannot find " + file + " (give --mesh XYZ --q Q)");
}

} // namespace

int bench_pcp(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"repeat", "grid", "sizes", "mesh", "q"});
    const int repeat = int_option(parsed, "bench pcp", "repeat", 5);
    const int grid = int_option(parsed, "bench pcp", "grid", 100);
    fx::check_limit(fx::Limit::MeshCells, std::uint64_t(grid) * std::uint64_t(grid) * std::uint64_t(grid),
                    "bench pcp --grid " + std::to_string(grid));
    const std::vector<int> sizes = int_list_option(parsed, "bench pcp", "sizes", "512,1024");
    fx::HeadlessContext context;
    std::printf("cell projection (Roettger & Ertl 2003): pcp classic, pcp-exact, mip\n%s\n", context.description().c_str());
    const std::string xyz = parsed.has("mesh") ? parsed.get("mesh") : find_blunt_fin("bluntfinxyz.bin");
    const std::string q = parsed.has("mesh") ? parsed.get("q") : find_blunt_fin("bluntfinq.bin");
    run_mesh("blunt fin", fx::read_mesh(xyz, q), sizes, repeat, 0.3);
    // The grid is a unit cube: emission per unit length chosen so pixels peak near 0.7 (as on
    // the fin) whatever the resolution; classic PCP then sees per-cell light of ~1/grid of it.
    run_mesh("hex grid " + std::to_string(grid) + "^3", hex_grid(grid), sizes, repeat, 1.0);
    return 0;
}

} // namespace cellfx_cli
