// Based on: Max, Williams & Silva 2000, §II–§V (the paper's figure: 12,936 cells in 0.95 s per
// new view after 4.92 s of set-up, SGI O2, one 180 MHz R5000)
//
// `cellfx bench absorption`: the `absorption` and `absorption-exact` paths, for every visibility
// sort this build offers, on the blunt fin (37,479 hexahedra), a ~1M-tetrahedron box and —
// when its file is there — the SPX mesh of the paper's figure (12,936 tetrahedra). Every timed
// frame is a new view (the camera orbits 3° per frame), so the sort and the problem-face test
// redo their work each time. Prints per frame: GPU ms (GL_TIME_ELAPSED, median), the CPU ms of
// the problem faces and working mesh (§V), the sort and the projection (classic: projected
// subdivisions), the whole frame's wall ms, and the error against the scan-line reference of
// the same view; set-up (renderer upload, the sort's per-mesh state, tables) separately.
// Verified after timing: every frame must be finite and non-empty and stay within a sanity
// bound of the reference, or the bench fails.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "harness/synthetic_meshes.hpp"
#include "mesh/tetrahedralize.hpp"
#include "fx/visibility_sort.hpp"
#include "options.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Scene {
    std::string name;
    fx::CellMesh mesh;
    std::string field;
    fx::TransferFunction tf;
    double load_s = 0.0;
};

// A box of n³ hexahedra cut into consistent tetrahedra (5 or 6 each), with a smooth field.
fx::CellMesh tetrahedral_box(int n) {
    fx::CellMesh hexes;
    const std::uint32_t nodes = std::uint32_t(n) + 1;
    fx::append_curvilinear_block(hexes, "box", {nodes, nodes, nodes}, [](double u, double v, double w) {
        return glm::dvec3(u, v, w);
    });
    fx::set_scalar_field(hexes, "s", [](const glm::dvec3& p) {
        return 0.5 + 0.25 * std::sin(6.0 * p.x) * std::cos(5.0 * p.y) + 0.2 * std::sin(7.0 * p.z + 2.0 * p.x);
    });
    return fx::tetrahedralize(hexes);
}

// Extinction per world unit for a mesh `size` across: an optical depth of up to ~10 through
// it, dense enough that a wrong order shows in the error.
fx::TransferFunction glow(double size) {
    const double k = 5.0 / size;
    return fx::TransferFunction({{0.0, {0.10, 0.25, 0.90}, 0.2 * k},
                                 {0.5, {0.20, 0.90, 0.40}, 0.8 * k},
                                 {1.0, {1.00, 0.25, 0.10}, 2.0 * k}},
                                /*normalized=*/true);
}

fx::Camera view_of(const fx::CellMesh& mesh, int frame) {
    const fx::Bounds b = fx::mesh_bounds(mesh);
    fx::Camera cam = fx::Camera::framing(b.lo, b.hi, 40.0);
    const double a = glm::radians(3.0 * frame);
    const glm::dvec3 d = cam.eye - cam.target;
    cam.eye = cam.target + glm::dvec3(d.x * std::cos(a) - d.y * std::sin(a), d.x * std::sin(a) + d.y * std::cos(a), d.z);
    return cam;
}

struct FrameError {
    double max = 0.0, mean = 0.0; // fractions of the reference's peak, over the pixels either covers
    bool finite = true;
    double coverage = 0.0; // fraction of pixels the reference covers (alpha > 1e-3) that the frame covers too
};
FrameError frame_error(const fx::Image& actual, const fx::Image& expected) {
    std::vector<std::uint8_t> uncovered(actual.pixels.size(), 0); // by neither: left out of the figures
    std::size_t covered = 0, both = 0;
    for (std::size_t i = 0; i < actual.pixels.size() && i < expected.pixels.size(); ++i) {
        const bool in_reference = expected.pixels[i].a > 1e-3f, in_frame = actual.pixels[i].a > 1e-3f;
        covered += in_reference, both += in_reference && in_frame;
        uncovered[i] = !(in_reference || in_frame);
    }
    verify::Options options;
    options.skip = &uncovered;
    const verify::Difference d = verify::measure(actual, expected, options);
    FrameError e;
    e.max = d.of_peak(d.worst.delta), e.mean = d.of_peak(d.mean), e.finite = d.nonfinite == 0;
    e.coverage = covered ? double(both) / double(covered) : 0.0;
    return e;
}

} // namespace

int bench_absorption(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"size", "frames", "cells", "sort", "blunt-fin", "spx", "scenes"});
    if (!parsed.positional.empty()) throw fx::Error("bench absorption: unexpected argument '" + parsed.positional[0] + "'");
    int width = 256, height = 256;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const int frames = int_option(parsed, "bench absorption", "frames", 5);
    const int target_cells = int_option(parsed, "bench absorption", "cells", 1000000);
    const std::string blunt = parsed.get("blunt-fin", std::string(CELLFX_SOURCE_DIR) + "/content/meshes/blunt_fin");
    const std::string spx = parsed.get("spx", std::string(CELLFX_SHARED_DATA) + "/spx/spx.inp");
    const std::string scenes = parsed.get("scenes", "spx,blunt-fin,box");
    std::vector<fx::SortMethod> sorts = fx::all_sort_methods();
    if (parsed.has("sort")) {
        sorts.clear();
        std::string list = parsed.get("sort");
        for (std::size_t start = 0; start <= list.size();) {
            const std::size_t comma = std::min(list.find(',', start), list.size());
            fx::SortMethod m;
            const std::string name = list.substr(start, comma - start);
            if (!fx::parse_sort_method(name, m)) throw fx::Error("--sort: unknown sort '" + name + "'");
            sorts.push_back(m);
            start = comma + 1;
        }
    }
    auto wanted = [&](const std::string& s) { return ("," + scenes + ",").find("," + s + ",") != std::string::npos; };

    fx::HeadlessContext context;
    std::printf("absorption paths (Max, Williams & Silva 2000), %s\n", context.description().c_str());
    std::printf("  image %dx%d, %d new views per run (orbit 3 deg/frame), CPU threads %u\n", width, height, frames,
                std::max(1u, std::thread::hardware_concurrency()));

    std::vector<Scene> list;
    if (wanted("spx")) {
        if (std::filesystem::exists(spx)) {
            const auto t0 = Clock::now();
            Scene s{"spx", fx::read_mesh(spx), "", {}};
            s.field = s.mesh.scalars.at(0).name;
            s.load_s = seconds_since(t0);
            s.tf = glow(glm::length(fx::mesh_bounds(s.mesh).size()));
            list.push_back(std::move(s));
        } else {
            std::printf("  (no SPX mesh at %s: the paper's data set is skipped; --spx FILE)\n", spx.c_str());
        }
    }
    if (wanted("blunt-fin")) {
        const auto t0 = Clock::now();
        Scene s{"blunt fin", fx::read_mesh(blunt + "/bluntfinxyz.bin", blunt + "/bluntfinq.bin"), "density", {}};
        s.load_s = seconds_since(t0);
        s.tf = glow(glm::length(fx::mesh_bounds(s.mesh).size()));
        list.push_back(std::move(s));
    }
    if (wanted("box")) {
        const auto t0 = Clock::now();
        const int n = std::max(1, int(std::lround(std::cbrt(double(target_cells) / 5.5))));
        Scene s{"tet box " + std::to_string(n) + "^3", tetrahedral_box(n), "s", {}};
        s.load_s = seconds_since(t0);
        s.tf = glow(std::sqrt(3.0));
        list.push_back(std::move(s));
    }

    bool failed = false;
    const fx::RenderPath paths[] = {fx::RenderPath::Absorption, fx::RenderPath::AbsorptionExact};
    for (const Scene& scene : list) {
        std::printf("\n%s: %zu cells, %zu points (built/loaded in %.2f s)\n", scene.name.c_str(), scene.mesh.cell_count(),
                    scene.mesh.point_count(), scene.load_s);
        // References: the scan-line renderer on every view, all cores.
        auto t0 = Clock::now();
        const fx::ScanlineRenderer reference(scene.mesh);
        std::vector<fx::Image> expected;
        for (int f = 0; f < frames; ++f)
            expected.push_back(reference.render(view_of(scene.mesh, f), width, height, *scene.mesh.find_scalar(scene.field),
                                                scene.tf));
        std::printf("  scan-line reference: %.2f s per view\n", seconds_since(t0) / frames);
        std::printf("  %-8s %-17s %8s %9s %8s %7s %8s %7s %8s %9s %8s %8s\n", "sort", "path", "setup s", "frame ms",
                    "gpu ms", "subdiv", "rebuild", "sort", "project", "err max%", "mean%", "problem");
        for (fx::SortMethod sort : sorts) {
            for (fx::RenderPath path : paths) {
                // Set-up: upload, then one frame (the sort's per-mesh state, tables, shaders).
                t0 = Clock::now();
                fx::CellRenderer renderer(scene.mesh, scene.field, scene.tf);
                fx::CellRenderOptions options;
                options.sort = sort;
                fx::CellRenderStats warm;
                renderer.render_to_image(view_of(scene.mesh, frames), width, height, path, options, &warm);
                const double setup_s = seconds_since(t0);
                options.timing = true;
                std::vector<double> wall, gpu, subdiv, rebuild, sort_ms, project;
                std::size_t problems = 0;
                double err_max = 0.0, err_mean = 0.0;
                for (int f = 0; f < frames; ++f) {
                    fx::CellRenderStats stats;
                    const auto tf0 = Clock::now();
                    const fx::Image image = renderer.render_to_image(view_of(scene.mesh, f), width, height, path, options, &stats);
                    wall.push_back(1e3 * seconds_since(tf0));
                    gpu.push_back(stats.gpu_ms), subdiv.push_back(stats.subdivision_ms), sort_ms.push_back(stats.sort_ms);
                    rebuild.push_back(stats.setup_ms);
                    project.push_back(stats.projection_ms);
                    problems = std::max(problems, stats.problem_cells);
                    // Verify after timing: against the reference of the same view.
                    const FrameError e = frame_error(image, expected[std::size_t(f)]);
                    err_max = std::max(err_max, e.max), err_mean = std::max(err_mean, e.mean);
                    if (!e.finite || e.coverage < 0.98 || e.mean > 0.1) {
                        std::printf("  FAILED: %s, %s, view %d: finite %d, coverage %.3f, mean error %.3f of peak\n",
                                    fx::sort_method_name(sort), fx::render_path_name(path), f, int(e.finite), e.coverage,
                                    e.mean);
                        failed = true;
                    }
                }
                std::printf("  %-8s %-17s %8.2f %9.1f %8.1f %7.1f %8.1f %7.1f %8.1f %9.2f %8.3f %8zu\n",
                            fx::sort_method_name(sort), fx::render_path_name(path), setup_s, median(wall), median(gpu),
                            median(subdiv), median(rebuild), median(sort_ms), median(project), 100.0 * err_max,
                            100.0 * err_mean, problems);
            }
        }
    }
    std::printf("\npaper (SGI O2, 180 MHz R5000): SPX 12,936 cells, 0.95 s per new view after 4.92 s of set-up\n");
    std::printf("columns: frame = wall ms per new view (CPU work + GPU + read-back); gpu = GL_TIME_ELAPSED;\n"
                "subdiv = problem faces and working mesh (section V); rebuild = the sort's per-mesh state rebuilt\n"
                "because the problem cells changed; sort = visibility sort; project = classic\n"
                "projected subdivisions (exact: item list); err = worst view's max |difference| and its mean over\n"
                "covered pixels against the scan-line reference, %% of its peak; problem = most cells cut into\n"
                "tetrahedra in a view. Verified: finite, covering >= 98%% of the reference, mean error < 10%%\n");
    if (failed) throw fx::Error("bench absorption: some frames failed verification");
    return 0;
}

} // namespace cellfx_cli
