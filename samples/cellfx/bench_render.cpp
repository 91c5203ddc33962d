// `cellfx bench render MESH [Q]`: how fast each render path draws a user's mesh, on a fixed
// orbit, every timed frame checked against the scan-line reference. docs/performance.md
// ("Against VTK") shows it beside VTK's unstructured-grid volume mappers.
//
// The orbit (the same for every renderer, and written to --json for peers): the camera looks
// at the centre c of the mesh's bounding box from elevation 20° above the plane normal to the
// up axis (--up x|y|z, default z), azimuths 360°·k/N (k = 0..N−1, measured from the axis after
// the up axis in x, y, z order: x for z up, y for x up, z for y up), a perspective camera with
// a 30° vertical field of view, its up vector the up axis. The distance d = R / sin(α) puts the
// bounding sphere (centre c, radius R = half the box diagonal) just inside the smaller image
// dimension (α = half the smaller field of view); near = d − 1.01·R, far = d + 1.01·R.
//
// Per renderer: one untimed warm-up frame of view 0 (shader compilation, a sort's per-mesh
// state, first-use buffers: its wall time is printed apart), then one frame per view. A frame
// of a GPU path is CellRenderer::render() into the bench's own RGBA32F target (cleared first,
// inside the timing), to glFinish: its wall time is "ms"; "cpu ms" is the time until render()
// returned (cellfx's CPU work and the driver's command submission); "gpu ms" a GL_TIME_ELAPSED
// query around render(). The scan-line renderer's frame is ScanlineRenderer::render() (all
// cores, or --threads). Figures are medians over the views; cells/s = mesh cells / median
// seconds. Bytes per cell: the GPU buffers (CellRenderer::gpu_bytes()) or the scan-line
// renderer's frame memory, divided by the mesh's cells.
//
// Checks, so that speed is never bought with a wrong picture: after each timed frame the image
// is read back (outside the timing) and compared with the scan-line renderer's frame of the same
// view and optical model (emission for pcp and pcp-exact, maximum for mip, emission-absorption
// for the absorption paths), RGBA, premultiplied. Over the pixels either image covers: the mean
// |difference| and the share of pixels off by more than a bound, both in % of the reference's
// peak; each path has its tolerance (tolerance_for() below, with the reason for each value). A
// frame outside it, or not finite, fails the run: the table says which, and the exit status is 1.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/visibility_sort.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "io/output_file.hpp"
#include "mesh_input.hpp"
#include "projector/gl_projector.hpp"
#include "render/projector_access.hpp"
#include "options.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

constexpr double kElevationDegrees = 20.0;
constexpr double kFovDegrees = 30.0;

constexpr const char* kUsage =
    "usage: cellfx bench render FILE [Q_FILE] [options]\n"
    "  every render path on an orbit of N views around the mesh, each frame checked against the\n"
    "  scan-line reference (exit status 1 if one is outside its tolerance); docs/performance.md\n"
    "  --paths A,B        pcp, pcp-exact, mip, absorption, absorption-exact (default: all); the\n"
    "                     scan-line renderer always runs (it is the reference)\n"
    "  --views N          orbit views (default 8), after one untimed warm-up frame\n"
    "  --size WxH         image size (default 512x512)\n"
    "  --up x|y|z         the mesh's up axis (default z)\n"
    "  --sort A,B         absorption paths: one row per visibility sort (default xmpvo; e.g.\n"
    "                     xmpvo,centroid for the exact sort beside the approximate one)\n"
    "  --scalar NAME      point field (default: the first)\n"
    "  --tf FILE          transfer function (default: cellfx render's blue-to-red ramp, its\n"
    "                     extinction scaled so that the largest one times the bounding-box\n"
    "                     diagonal is 4)\n"
    "  --density K        multiply the extinction by K\n"
    "  --threads N        scan-line worker threads (default: all cores)\n"
    "  --planar-tolerance T  the exact paths' planar test (default 1e-3 of a cell's size;\n"
    "                     negative: no cell is planar, every one searches its triangles)\n"
    "  --json FILE        everything a peer run needs: mesh, field, transfer function in field\n"
    "                     units, image size, every view's camera, every renderer's figures\n"
    "  --images DIR       view 0 of every renderer as PNG (over black)";

// How far a path's frame may be from the scan-line frame, in % of the reference's peak, over
// the pixels either image covers: the mean |difference|, and the share of pixels (in %) whose
// largest channel difference exceeds `pixel`.
struct Tolerance {
    double mean;
    double pixel;
    double share;
    double worst = 0.0; // % of peak every pixel keeps; 0: a pixel beyond `pixel` must lie within it of
                        // the reference's range over its 3x3 neighbourhood (a silhouette's pixel)
};

Tolerance tolerance_for(const std::string& path) {
    // pcp-exact, absorption-exact: per-fragment exact integrals, 1.3e-5 and 1.8e-5 RMSE at the
    // pixel centres on the 1M-tet duct, 0.013% / 0.55% of peak at worst in the property test
    // (docs/accuracy.md); what is left are single pixels where a silhouette edge passes through
    // a pixel centre (GL's and the scan-line's coverage rules differ there) and the
    // pre-integration table's length steps. Mean 0.1%, at most 0.5% of the pixels off by 2%.
    if (path == "pcp-exact" || path == "absorption-exact") return {0.1, 2.0, 0.5};
    // mip: the maximum of the face values (Roettger & Ertl §2), exact where the emission c·σ is
    // monotonic between the faces a ray crosses. Where it peaks inside a cell (c and σ both
    // linear between breakpoints make c·σ quadratic) the scan-line renderer finds a peak the
    // faces miss: with the default ramp up to 5.6% of the peak (its blue channel), on up to 3%
    // of the pixels. Mean 1%, 2% of pixels off by 10%: a missing or misplaced cell is off by
    // its whole value, and a transfer function with a narrow spike fails, as it should. Such a
    // missed peak, c·sigma quadratic across a cell, lies above its faces' values by at most a
    // quarter of the product of c's and sigma's changes: 25% of the peak where c and sigma are
    // largest at the same breakpoint, as in the default ramp (tetraMesh.vtk at 48x48: 4 pixels
    // 11% off, beyond their neighbours' range). Every pixel within 25%.
    if (path == "mip") return {1.0, 10.0, 2.0, 25.0};
    // absorption (classic): the projected subdivision interpolates thickness and colour
    // linearly across each polygon (Max, Williams & Silva §II), 2.5% / 0.12% of peak from
    // outside in the property test. Mean 1%, 2% of pixels off by 10%.
    if (path == "absorption") return {1.0, 10.0, 2.0};
    // pcp (classic): 8-bit passes; every cell's κ·Δd/2 rounds to 1/255, which on fine meshes is
    // most of a cell's light (0.06 RMSE on the 1M-tet duct, 7.5% of its peak). Only a wrong
    // picture fails: mean 15%, no per-pixel bound.
    return {15.0, 100.0, 100.0};
}

struct Check {
    double peak = 0.0, mean = 0.0, max = 0.0, share = 0.0; // mean, max, share in % (of peak / of pixels)
    bool finite = true, passed = false;
    std::string broken; // what broke the tolerance (verify::failures), "" when passed
};

// `frame` against `reference` (clamped to 1 per channel first for an 8-bit path), over the
// pixels either image covers (a channel above 1e-6 of the reference's peak); a pixel beyond
// `pixel` must still lie within it of the reference's range over its 3×3 neighbourhood
// (cellfx_verify: a silhouette pixel shows what the reference shows next to it).
Check check_frame(const fx::Image& frame, const fx::Image& reference, bool clamp_reference, const Tolerance& tol) {
    verify::Options options;
    options.clamp_expected = clamp_reference;
    const verify::Difference whole = verify::measure(frame, reference, options);
    Check c;
    c.peak = whole.peak, c.finite = whole.nonfinite == 0;
    if (!c.finite) return c;
    if (!(c.peak > 0.0)) {
        c.passed = whole.worst.delta == 0.0; // nothing to see: the frame must be empty too
        return c;
    }
    std::vector<std::uint8_t> uncovered(reference.pixels.size());
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
        const glm::vec4 r = clamp_reference ? glm::min(reference.pixels[i], glm::vec4(1.0f)) : reference.pixels[i];
        const glm::vec4 f = glm::abs(frame.pixels[i]);
        uncovered[i] = std::max({f.r, f.g, f.b, f.a, std::fabs(r.r), std::fabs(r.g), std::fabs(r.b), std::fabs(r.a)}) <=
                       1e-6 * c.peak;
    }
    options.skip = &uncovered;
    verify::Tolerance t;
    t.pixel.of_peak = tol.pixel / 100.0, t.share_beyond = tol.share / 100.0, t.mean.of_peak = tol.mean / 100.0;
    t.worst.of_peak = tol.worst / 100.0;
    const verify::Difference d = verify::measure(frame, reference, t, options);
    c.mean = 100.0 * d.of_peak(d.mean), c.max = 100.0 * d.of_peak(d.worst.delta), c.share = 100.0 * d.share_beyond();
    c.broken = verify::failures(d, t);
    c.passed = c.broken.empty();
    return c;
}

// The orbit of the header comment.
struct Orbit {
    glm::dvec3 center{0.0}, up{0.0, 0.0, 1.0}, e1{1.0, 0.0, 0.0}, e2{0.0, 1.0, 0.0};
    double radius = 1.0, distance = 1.0;

    Orbit(const fx::Bounds& b, const std::string& up_axis, int width, int height) {
        const int u = up_axis == "x" ? 0 : up_axis == "y" ? 1 : up_axis == "z" ? 2 : -1;
        if (u < 0) throw fx::Error("--up: '" + up_axis + "' is not x, y or z");
        up = e1 = e2 = glm::dvec3(0.0);
        up[u] = 1.0, e1[(u + 1) % 3] = 1.0, e2[(u + 2) % 3] = 1.0; // e1 × e2 = up
        center = b.center();
        radius = std::max(0.5 * glm::length(b.size()), 1e-30);
        const double half_v = glm::radians(0.5 * kFovDegrees);
        const double half = std::min(half_v, std::atan(std::tan(half_v) * double(width) / double(height)));
        distance = radius / std::sin(half);
    }

    fx::Camera view(int k, int n) const {
        const double az = glm::radians(360.0 * k / n), el = glm::radians(kElevationDegrees);
        fx::Camera cam;
        cam.target = center;
        cam.eye = center + distance * (std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * up);
        cam.up = up;
        cam.fov_y_degrees = kFovDegrees;
        cam.near_distance = distance - 1.01 * radius;
        cam.far_distance = distance + 1.01 * radius;
        return cam;
    }
};

// One renderer's run over the orbit.
struct Run {
    std::string label, path, sort; // sort: absorption paths only
    fx::OpticalModel model = fx::OpticalModel::EmissionAbsorption;
    Tolerance tol{};
    std::vector<double> ms, cpu_ms, gpu_ms, process_ms; // per view
    std::map<std::string, std::vector<double>> stages; // per-stage figures per view
    std::vector<Check> checks;
    double setup_ms = 0.0, first_ms = 0.0, bytes_per_cell = 0.0;
    // GPU paths: the renderer's memory after the run (CellRenderer::gpu_memory) and what of it
    // this path reads (read_bytes(); bytes_per_cell is what it keeps, targets aside).
    std::optional<fx::CellRenderer::Memory> memory;
    double read_bytes_per_cell = 0.0;
    fx::Image view0; // the timed frame of view 0
    bool passed() const {
        return std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed; });
    }
};

const char* model_name(fx::OpticalModel m) {
    return m == fx::OpticalModel::Emission ? "emission" : m == fx::OpticalModel::Maximum ? "maximum" : "emission-absorption";
}

fx::OpticalModel model_of(fx::RenderPath path) {
    if (path == fx::RenderPath::Pcp || path == fx::RenderPath::PcpExact) return fx::OpticalModel::Emission;
    if (path == fx::RenderPath::Mip) return fx::OpticalModel::Maximum;
    return fx::OpticalModel::EmissionAbsorption;
}

// What every renderer draws: the mesh, its field and transfer function, the orbit's views.
struct Scene {
    const fx::CellMesh& mesh;
    const std::string& field_name;
    const fx::ScalarField& field;
    const fx::TransferFunction& tf;
    const std::vector<fx::Camera>& cameras;
    int width, height;
    double planar_tolerance; // GlProjector::set_planar_tolerance
};

using References = std::map<fx::OpticalModel, std::vector<fx::Image>>; // per model, per view

// The scan-line renderer on every view: its timed row (emission-absorption), and the frames of
// each of `models` that the GPU paths are checked against.
Run run_scanline(const Scene& sc, unsigned threads, const std::vector<fx::OpticalModel>& models, References& references) {
    Run run;
    run.label = run.path = "scanline";
    auto t = Clock::now();
    const fx::ScanlineRenderer scanline(sc.mesh);
    run.setup_ms = ms_since(t);
    fx::ScanlineOptions so;
    so.threads = threads;
    t = Clock::now();
    scanline.render(sc.cameras[0], sc.width, sc.height, sc.field, sc.tf, so);
    run.first_ms = ms_since(t);
    for (const fx::Camera& cam : sc.cameras) {
        for (const fx::OpticalModel model : models) {
            so.model = model;
            fx::ScanlineStats stats;
            t = Clock::now();
            const double process_start = process_cpu_ms();
            references[model].push_back(scanline.render(cam, sc.width, sc.height, sc.field, sc.tf, so, &stats));
            const double ms = ms_since(t), process = process_cpu_ms() - process_start;
            if (model != fx::OpticalModel::EmissionAbsorption) continue; // the references alone
            run.ms.push_back(ms);
            run.cpu_ms.push_back(ms);
            run.process_ms.push_back(process);
            run.stages["transform ms"].push_back(1e3 * stats.seconds_transform);
            run.stages["y-buckets ms"].push_back(1e3 * stats.seconds_y_buckets);
            run.stages["scan ms"].push_back(1e3 * stats.seconds_scan);
            run.stages["threads"].push_back(stats.threads);
            run.bytes_per_cell = std::max(run.bytes_per_cell, double(stats.memory.renderer_total()) / double(sc.mesh.cell_count()));
        }
    }
    run.view0 = references[fx::OpticalModel::EmissionAbsorption].front();
    return run;
}

// The stages of a frame in the order it runs them (CellRenderStats; profiled frames): the CPU's
// work (its clock), then the GL's, each stage run alone: by the CPU's clock from one glFinish to
// the next, and by its GL_TIME_ELAPSED query ("gl ..."; their sum "gl total").
constexpr const char* kStageNames[] = {"projection ms", "sort ms",    "tables ms",    "clear ms",
                                       "upload ms",     "vertex ms",  "fragment ms",  "resolve ms"};

std::vector<std::pair<std::string, double>> stage_figures(const fx::CellRenderStats& s) {
    const fx::CellRenderStats::StageTime* gl[] = {&s.tables, &s.clear, &s.upload, &s.vertex, &s.fragment, &s.resolve};
    std::vector<std::pair<std::string, double>> out = {{"projection ms", s.projection_ms},
                                                       {"sort ms", s.subdivision_ms + s.sort_ms}};
    for (int i = 0; i < 6; ++i) out.emplace_back(kStageNames[2 + i], gl[i]->wall);
    for (int i = 0; i < 6; ++i) out.emplace_back(std::string("gl ") + kStageNames[2 + i], gl[i]->gl);
    return out;
}

// What of the renderer's GPU memory `path` reads in a frame (its target aside): pcp the mesh and
// its frame list, pcp-exact the mesh and the cell tables, mip the mesh's points and its unique
// faces, classic absorption its own geometry and tables, absorption-exact the mesh, the cell
// tables and its own list and pre-integration table.
std::size_t read_bytes(fx::RenderPath path, const fx::CellRenderer::Memory& m) {
    switch (path) {
    case fx::RenderPath::Pcp: return m.mesh + m.pcp_list;
    case fx::RenderPath::PcpExact: return m.mesh + m.cell_tables;
    case fx::RenderPath::Mip: return m.mesh + m.unique_faces;
    case fx::RenderPath::Absorption: return m.absorption;
    case fx::RenderPath::AbsorptionExact: return m.mesh + m.cell_tables + m.absorption;
    }
    return 0;
}

// One GPU path (with `sort` for the absorption paths) on every view, drawn into `target` (bound
// for drawing), timed with `query`; each frame checked against the scan-line frame of its model.
Run run_gpu_path(const Scene& sc, fx::RenderPath path, const fx::SortMethod* sort, fx::gl::RenderTarget& target,
                 const fx::gl::Query& query, const References& references) {
    Run run;
    run.path = run.label = fx::render_path_name(path);
    fx::CellRenderOptions options;
    if (sort) {
        options.sort = *sort;
        run.sort = fx::sort_method_name(*sort);
        run.label += " (" + run.sort + ")";
    }
    run.model = model_of(path);
    run.tol = tolerance_for(run.path);
    const auto t = Clock::now();
    fx::CellRenderer renderer(sc.mesh, sc.field_name, sc.tf);
    fx::renderer_projector(renderer).set_planar_tolerance(sc.planar_tolerance);
    run.setup_ms = ms_since(t);
    fx::CellRenderStats stats;
    double cpu = 0.0, gpu = 0.0, process = 0.0;
    const fx::Viewport viewport{0, 0, sc.width, sc.height};
    const auto frame = [&](const fx::Camera& cam) {
        const auto start = Clock::now();
        const double process_start = process_cpu_ms();
        target.clear(glm::vec4(0.0f));
        glBeginQuery(GL_TIME_ELAPSED, query.id());
        stats = renderer.render(cam, viewport, path, options);
        glEndQuery(GL_TIME_ELAPSED);
        cpu = ms_since(start);
        glFinish();
        const double wall = ms_since(start);
        process = process_cpu_ms() - process_start;
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &ns);
        gpu = double(ns) * 1e-6;
        return wall;
    };
    fx::CellRenderOptions profiled = options;
    profiled.profile = true;
    run.first_ms = frame(sc.cameras[0]);
    for (std::size_t k = 0; k < sc.cameras.size(); ++k) {
        run.ms.push_back(frame(sc.cameras[k]));
        run.cpu_ms.push_back(cpu);
        run.gpu_ms.push_back(gpu);
        run.process_ms.push_back(process);
        run.stages["draw calls"].push_back(double(stats.draw_calls));
        if (path == fx::RenderPath::Pcp) run.stages["batches"].push_back(double(stats.batches));
        if (sort) {
            run.stages["subdivision ms"].push_back(stats.subdivision_ms);
            run.stages["sort cycles"].push_back(double(stats.sort_cycles));
        }
        fx::Image image = target.read();
        run.checks.push_back(check_frame(image, references.at(run.model)[k], path == fx::RenderPath::Pcp, run.tol));
        if (k == 0) run.view0 = std::move(image);
        // The same view again, profiled (untimed): where the frame's time goes.
        target.clear(glm::vec4(0.0f));
        const fx::CellRenderStats p = renderer.render(sc.cameras[k], viewport, path, profiled);
        for (const auto& [name, ms] : stage_figures(p)) run.stages[name].push_back(ms);
    }
    run.bytes_per_cell = double(renderer.gpu_bytes()) / double(sc.mesh.cell_count());
    run.memory = renderer.gpu_memory();
    run.read_bytes_per_cell = double(read_bytes(path, *run.memory)) / double(sc.mesh.cell_count());
    return run;
}

nlohmann::json vec_json(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json run_json(const Run& r, std::size_t cells) {
    const auto median_or_null = [](const std::vector<double>& v) {
        return v.empty() ? nlohmann::json(nullptr) : nlohmann::json(median(v));
    };
    nlohmann::json o = {{"name", r.label},
                        {"path", r.path},
                        {"model", model_name(r.model)},
                        {"ms", r.ms},
                        {"median_ms", median(r.ms)},
                        {"cells_per_second", double(cells) / (median(r.ms) * 1e-3)},
                        {"cpu_ms", median_or_null(r.cpu_ms)},
                        {"process_cpu_ms", median_or_null(r.process_ms)},
                        {"gpu_ms", median_or_null(r.gpu_ms)},
                        {"first_frame_ms", r.first_ms},
                        {"setup_ms", r.setup_ms},
                        {"bytes_per_cell", r.bytes_per_cell}};
    if (r.memory) {
        const double n = double(cells);
        o["memory_bytes_per_cell"] = {{"read", r.read_bytes_per_cell},
                                      {"mesh", double(r.memory->mesh) / n},
                                      {"cell_tables", double(r.memory->cell_tables) / n},
                                      {"unique_faces", double(r.memory->unique_faces) / n},
                                      {"pcp_list", double(r.memory->pcp_list) / n},
                                      {"absorption", double(r.memory->absorption) / n}};
        o["target_bytes"] = r.memory->targets;
    }
    if (!r.sort.empty()) o["sort"] = r.sort;
    for (const auto& [name, values] : r.stages) o["stages"][name] = median(values);
    if (!r.checks.empty()) {
        o["check"] = {{"tolerance", {{"mean_percent", r.tol.mean}, {"pixel_percent", r.tol.pixel}, {"share_percent", r.tol.share}, {"worst_percent", r.tol.worst}}},
                      {"passed", r.passed()}};
        for (const Check& c : r.checks)
            o["check"]["frames"].push_back({{"peak", c.peak}, {"mean_percent", c.mean}, {"max_percent", c.max},
                                            {"share_percent", c.share}, {"finite", c.finite}, {"passed", c.passed}});
    }
    return o;
}

// "absorption (xmpvo)" → "absorption_xmpvo"
std::string file_name(const std::string& label) {
    std::string name;
    for (const char ch : label) {
        if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '-') name += ch;
        else if (!name.empty() && name.back() != '_') name += '_';
    }
    if (!name.empty() && name.back() == '_') name.pop_back();
    return name;
}

void print_row(const Run& r, std::size_t cells) {
    const double ms = median(r.ms);
    std::printf("  %-28s %10.2f %12.4g %9.2f ", r.label.c_str(), ms, double(cells) / (ms * 1e-3), median(r.cpu_ms));
    if (r.gpu_ms.empty()) std::printf("%9s ", "-");
    else std::printf("%9.2f ", median(r.gpu_ms));
    std::printf("%9.2f ", median(r.process_ms));
    std::printf("%9.2f %8.0f  ", r.first_ms, r.bytes_per_cell);
    if (r.checks.empty()) {
        std::printf("reference\n");
        return;
    }
    double mean = 0.0, share = 0.0;
    for (const Check& c : r.checks) mean = std::max(mean, c.mean), share = std::max(share, c.share);
    std::printf("%-4s %7.3f %7.3f   (%g / %g%% > %g)\n", r.passed() ? "ok" : "FAIL", mean, share, r.tol.mean, r.tol.share,
                r.tol.pixel);
}

} // namespace

int bench_render(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"help"});
    if (parsed.has("help")) {
        std::puts(kUsage);
        return 0;
    }
    require_known(parsed, {"paths", "views", "size", "up", "sort", "scalar", "tf", "density", "threads", "json", "images",
                           "planar-tolerance"});
    // Every option before the mesh is read; the outputs are tried now, not after the run.
    const int views = int_option(parsed, "bench render", "views", 8);
    int width = 512, height = 512;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const unsigned threads = unsigned(int_option(parsed, "bench render", "threads", int(std::max(1u, std::thread::hardware_concurrency()))));
    number_option(parsed, "bench render", "density", 1.0); // applied to the transfer function below
    const double planar_tolerance = number_option(parsed, "bench render", "planar-tolerance", fx::kPlanarTolerance);
    const std::string json = output_file_option(parsed, "json", {}, false);
    const std::string images = parsed.get("images");
    if (!images.empty()) fx::io::create_output_folder(images);
    const MeshInput input = read_mesh_input(parsed);
    const fx::CellMesh& mesh = input.mesh;
    const fx::ScalarField& field = input.scalar();
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    fx::TransferFunction fallback = default_transfer_function();
    {
        // Scaled so that the largest extinction times the box diagonal is 4: a medium one sees into.
        std::vector<fx::TransferPoint> points = fallback.points();
        double sigma_max = 0.0;
        for (const fx::TransferPoint& p : points) sigma_max = std::max(sigma_max, p.sigma);
        const double k = 4.0 / (sigma_max * std::max(glm::length(bounds.size()), 1e-30));
        for (fx::TransferPoint& p : points) p.sigma *= k;
        fallback = fx::TransferFunction(std::move(points), fallback.normalized());
    }
    const fx::TransferFunction tf = transfer_function_option(parsed, "bench render", field, fallback);

    std::vector<fx::RenderPath> paths;
    for (const std::string& name : split_list(parsed.get("paths", "pcp,pcp-exact,mip,absorption,absorption-exact"))) {
        fx::RenderPath p;
        if (name == "scanline") continue; // always run
        if (!fx::parse_render_path(name, p)) throw fx::Error("--paths: unknown render path '" + name + "'");
        if (std::find(paths.begin(), paths.end(), p) == paths.end()) paths.push_back(p);
    }
    std::vector<fx::SortMethod> sorts;
    for (const std::string& name : split_list(parsed.get("sort", "xmpvo"))) {
        fx::SortMethod m;
        if (!fx::parse_sort_method(name, m)) throw fx::Error("--sort: unknown sort '" + name + "'");
        sorts.push_back(m);
    }
    if (sorts.empty()) throw fx::Error("--sort: no sort given");

    const Orbit orbit(bounds, parsed.get("up", "z"), width, height);
    std::vector<fx::Camera> cameras;
    for (int k = 0; k < views; ++k) cameras.push_back(orbit.view(k, views));

    std::map<std::string, std::size_t> by_type;
    for (const fx::CellType t : mesh.cell_types) by_type[fx::cell_type_name(t)]++;
    std::string types;
    for (const auto& [name, count] : by_type) types += (types.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    const std::size_t cells = mesh.cell_count();
    std::printf("render: %s%s%s, field %s\n", input.files[0].c_str(), input.files.size() > 1 ? " + " : "",
                input.files.size() > 1 ? input.files[1].c_str() : "", input.field.c_str());
    std::printf("  %zu cells (%s), %zu points\n", cells, types.c_str(), mesh.point_count());
    std::printf("  transfer function (field units):");
    for (const fx::TransferPoint& p : tf.points())
        std::printf(" [%g: %g %g %g, sigma %g]", p.s, p.color.r, p.color.g, p.color.b, p.sigma);
    std::printf("\n  %dx%d, %d views: elevation %g deg, azimuth 360*k/%d, fov %g deg, distance %g (bounding radius %g)\n",
                width, height, views, kElevationDegrees, views, kFovDegrees, orbit.distance, orbit.radius);

    // The scan-line renderer first: its timed row, and the references every GPU frame is checked against.
    const Scene scene{mesh, input.field, field, tf, cameras, width, height, planar_tolerance};
    std::vector<fx::OpticalModel> models = {fx::OpticalModel::EmissionAbsorption};
    for (const fx::RenderPath p : paths)
        if (std::find(models.begin(), models.end(), model_of(p)) == models.end()) models.push_back(model_of(p));
    References references;
    std::vector<Run> runs = {run_scanline(scene, threads, models, references)};

    std::optional<fx::HeadlessContext> context;
    if (!paths.empty()) context.emplace();
    std::printf("  gl: %s; scan-line: %u threads\n", context ? context->description().c_str() : "(no GPU path)", threads);
    std::printf("\n  %-28s %10s %12s %9s %9s %9s %9s %8s  %s\n", "renderer", "ms/frame", "cells/s", "cpu ms", "gpu ms",
                "proc ms", "first ms", "B/cell", "check: worst mean, worst share of pixels (tolerance), % of peak");
    print_row(runs.front(), cells);
    std::fflush(stdout);

    std::optional<fx::gl::RenderTarget> target;
    std::optional<fx::gl::Query> query;
    if (context) {
        target = fx::gl::RenderTarget::create(width, height, fx::gl::ColorFormat::RGBA32F, false);
        query = fx::gl::Query::create(GL_TIME_ELAPSED);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target->framebuffer());
        glViewport(0, 0, width, height);
    }
    for (const fx::RenderPath path : paths) {
        const bool sorted = path == fx::RenderPath::Absorption || path == fx::RenderPath::AbsorptionExact;
        for (std::size_t s = 0; s < (sorted ? sorts.size() : 1); ++s) {
            runs.push_back(run_gpu_path(scene, path, sorted ? &sorts[s] : nullptr, *target, *query, references));
            print_row(runs.back(), cells);
            std::fflush(stdout);
        }
    }
    // The exact visibility sort against the approximate one, per absorption path.
    for (const Run& exact : runs)
        for (const Run& centroid : runs)
            if (exact.path == centroid.path && exact.sort == "xmpvo" && centroid.sort == "centroid")
                std::printf("  %s: xmpvo / centroid: frame %.2fx, sort %.2fx\n", exact.path.c_str(),
                            median(exact.ms) / median(centroid.ms),
                            median(exact.stages.at("sort ms")) / median(centroid.stages.at("sort ms")));
    std::printf("  ms/frame: median wall time over the views (GPU paths: render() into an RGBA32F target to glFinish);\n"
                "  cpu ms: until render() returned; gpu ms: GL_TIME_ELAPSED; proc ms: CPU time of all the process's\n"
                "  threads over the frame; first ms: the warm-up frame; B/cell: GPU buffers (scan-line: its frame memory)\n"
                "  per mesh cell; check: against the scan-line frame of the same model.\n");

    // Where the time goes: each GPU path's profiled frames (CellRenderOptions::profile), stage by
    // stage, then the scan-line renderer's own stages; medians over the views.
    std::printf("\n  where the time goes (ms, medians over the views of one profiled frame each, CellRenderOptions::profile):\n"
                "  projection, sort: the CPU's clock, before the GL work; tables .. resolve: each GL stage run alone, by the\n"
                "  CPU's clock from one glFinish to the next (first row) and by its GL_TIME_ELAPSED query (second row; Mesa's\n"
                "  llvmpipe counts only part of the rasteriser's work there); vertex: the draws issued once more first with\n"
                "  rasterisation off; fragment: the draws less vertex\n");
    std::printf("  %-28s %9s", "renderer", "frame");
    for (const char* name : kStageNames) std::printf(" %10.*s", int(std::strlen(name) - 3), name);
    std::printf("\n");
    for (const Run& r : runs) {
        if (r.gpu_ms.empty()) continue;
        std::printf("  %-28s %9.2f", r.label.c_str(), median(r.ms));
        for (const char* name : kStageNames) std::printf(" %10.2f", median(r.stages.at(name)));
        std::printf("\n  %-28s %9s %10s %10s", "", "gl query", "", "");
        for (std::size_t i = 2; i < std::size(kStageNames); ++i)
            std::printf(" %10.2f", median(r.stages.at(std::string("gl ") + kStageNames[i])));
        std::printf("\n");
    }
    // What each path keeps and reads.
    std::printf("\n  GPU memory, bytes per cell (CellRenderer::gpu_memory after the path's run; a renderer per path):\n"
                "  kept: all of it but the target; read: what the path's frame reads of it; target: the path's own, MB\n");
    std::printf("  %-28s %8s %8s %8s %8s %8s %8s %10s %8s\n", "renderer", "kept", "read", "mesh", "cell tab", "uniq fac",
                "pcp list", "absorption", "target");
    for (const Run& r : runs) {
        if (!r.memory) continue;
        const double n = double(cells);
        const fx::CellRenderer::Memory& m = *r.memory;
        std::printf("  %-28s %8.0f %8.0f %8.0f %8.0f %8.0f %8.0f %10.0f %8.2f\n", r.label.c_str(), r.bytes_per_cell,
                    r.read_bytes_per_cell, double(m.mesh) / n, double(m.cell_tables) / n, double(m.unique_faces) / n,
                    double(m.pcp_list) / n, double(m.absorption) / n, double(m.targets) / 1e6);
    }
    std::printf("\n  per stage (medians):\n");
    for (const Run& r : runs) {
        std::printf("  %-28s", r.label.c_str());
        for (const auto& [name, values] : r.stages)
            if (std::find_if(std::begin(kStageNames), std::end(kStageNames),
                             [&](const char* n) { return name == n || name == std::string("gl ") + n; }) == std::end(kStageNames))
                std::printf("  %s %.4g", name.c_str(), median(values));
        std::printf("\n");
    }

    if (!images.empty()) {
        for (const Run& r : runs) {
            fx::Image image = r.view0;
            fx::composite_over(image, glm::vec3(0.0f));
            fx::write_png(image, images + "/" + file_name(r.label) + ".png");
        }
        std::printf("\n  wrote view 0 of every renderer to %s/\n", images.c_str());
    }

    bool passed = true;
    for (const Run& r : runs) passed = passed && r.passed();
    if (!json.empty()) {
        nlohmann::json j;
        j["tool"] = "cellfx bench render";
        j["gl"] = context ? context->description() : "";
        j["scanline_threads"] = threads;
        j["mesh"] = {{"files", input.files}, {"field", input.field}, {"cells", cells}, {"points", mesh.point_count()},
                     {"cell_types", by_type}, {"bounds", {{"lo", vec_json(bounds.lo)}, {"hi", vec_json(bounds.hi)}}}};
        nlohmann::json points = nlohmann::json::array();
        for (const fx::TransferPoint& p : tf.points()) points.push_back({p.s, p.color.r, p.color.g, p.color.b, p.sigma});
        j["transfer_function"] = {{"units", "field"}, {"points", points}, {"source", parsed.get("tf", "default")}};
        j["image"] = {{"width", width}, {"height", height}};
        j["planar_tolerance"] = planar_tolerance;
        j["orbit"] = {{"up", vec_json(orbit.up)},           {"elevation_degrees", kElevationDegrees},
                      {"fov_y_degrees", kFovDegrees},        {"views", views},
                      {"center", vec_json(orbit.center)},    {"radius", orbit.radius},
                      {"distance", orbit.distance}};
        for (const fx::Camera& c : cameras)
            j["views"].push_back({{"eye", vec_json(c.eye)}, {"target", vec_json(c.target)}, {"up", vec_json(c.up)},
                                  {"fov_y_degrees", c.fov_y_degrees}, {"near", c.near_distance}, {"far", c.far_distance}});
        for (const Run& r : runs) j["renderers"].push_back(run_json(r, cells));
        j["passed"] = passed;
        fx::io::write_output_file(json, j.dump(2) + "\n");
        std::printf("  wrote %s\n", json.c_str());
    }
    if (!passed) {
        std::fprintf(stderr, "cellfx bench render: frames outside their tolerance against the scan-line reference:");
        for (const Run& r : runs)
            for (std::size_t k = 0; k < r.checks.size(); ++k)
                if (!r.checks[k].passed)
                    std::fprintf(stderr, " %s view %zu (mean %.3g%%, %.3g%% of pixels%s: %s);", r.label.c_str(), k,
                                 r.checks[k].mean, r.checks[k].share, r.checks[k].finite ? "" : ", not finite",
                                 r.checks[k].broken.c_str());
        std::fprintf(stderr, "\n");
        return 1;
    }
    return 0;
}

} // namespace cellfx_cli
