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
#include <cstdio>
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
#include "fx/headless_context.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/visibility_sort.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "io/output_file.hpp"
#include "mesh_input.hpp"
#include "options.hpp"
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
    // its whole value, and a transfer function with a narrow spike fails, as it should.
    if (path == "mip") return {1.0, 10.0, 2.0};
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
};

// `frame` against `reference` (clamped to 1 per channel first for an 8-bit path).
Check check_frame(const fx::Image& frame, const fx::Image& reference, bool clamp_reference, const Tolerance& tol) {
    Check c;
    const auto ref_at = [&](std::size_t i) {
        const glm::vec4 r = reference.pixels[i];
        return clamp_reference ? glm::min(r, glm::vec4(1.0f)) : r;
    };
    double frame_peak = 0.0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
        const glm::vec4 r = ref_at(i), f = frame.pixels[i];
        for (int k = 0; k < 4; ++k) {
            c.peak = std::max(c.peak, double(r[k]));
            if (!std::isfinite(f[k])) c.finite = false;
            else frame_peak = std::max(frame_peak, double(std::fabs(f[k])));
        }
    }
    if (!c.finite) return c;
    if (!(c.peak > 0.0)) {
        c.passed = frame_peak == 0.0; // nothing to see: the frame must be empty too
        return c;
    }
    const double covered_above = 1e-6 * c.peak, bad_above = tol.pixel / 100.0 * c.peak;
    double sum = 0.0;
    std::size_t covered = 0, bad = 0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i) {
        const glm::vec4 r = ref_at(i), f = frame.pixels[i];
        double largest = 0.0, value = 0.0, pixel_sum = 0.0;
        for (int k = 0; k < 4; ++k) {
            largest = std::max(largest, double(std::fabs(f[k] - r[k])));
            value = std::max({value, double(std::fabs(f[k])), double(std::fabs(r[k]))});
            pixel_sum += std::fabs(f[k] - r[k]);
        }
        if (value <= covered_above) continue;
        ++covered;
        sum += pixel_sum;
        c.max = std::max(c.max, largest);
        if (largest > bad_above) ++bad;
    }
    covered = std::max<std::size_t>(covered, 1);
    c.mean = 100.0 * sum / (4.0 * double(covered) * c.peak);
    c.max = 100.0 * c.max / c.peak;
    c.share = 100.0 * double(bad) / double(covered);
    c.passed = c.mean <= tol.mean && c.share <= tol.share;
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
    std::vector<double> ms, cpu_ms, gpu_ms; // per view
    std::map<std::string, std::vector<double>> stages; // per-stage figures per view
    std::vector<Check> checks;
    double setup_ms = 0.0, first_ms = 0.0, bytes_per_cell = 0.0;
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
            references[model].push_back(scanline.render(cam, sc.width, sc.height, sc.field, sc.tf, so, &stats));
            const double ms = ms_since(t);
            if (model != fx::OpticalModel::EmissionAbsorption) continue; // the references alone
            run.ms.push_back(ms);
            run.cpu_ms.push_back(ms);
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
    run.setup_ms = ms_since(t);
    fx::CellRenderStats stats;
    double cpu = 0.0, gpu = 0.0;
    const auto frame = [&](const fx::Camera& cam) {
        const auto start = Clock::now();
        target.clear(glm::vec4(0.0f));
        glBeginQuery(GL_TIME_ELAPSED, query.id());
        stats = renderer.render(cam, fx::Viewport{0, 0, sc.width, sc.height}, path, options);
        glEndQuery(GL_TIME_ELAPSED);
        cpu = ms_since(start);
        glFinish();
        const double wall = ms_since(start);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query.id(), GL_QUERY_RESULT, &ns);
        gpu = double(ns) * 1e-6;
        return wall;
    };
    run.first_ms = frame(sc.cameras[0]);
    for (std::size_t k = 0; k < sc.cameras.size(); ++k) {
        run.ms.push_back(frame(sc.cameras[k]));
        run.cpu_ms.push_back(cpu);
        run.gpu_ms.push_back(gpu);
        run.stages["draw calls"].push_back(double(stats.draw_calls));
        if (path == fx::RenderPath::Pcp) run.stages["batches"].push_back(double(stats.batches));
        if (sort) {
            run.stages["sort ms"].push_back(stats.sort_ms);
            run.stages["subdivision ms"].push_back(stats.subdivision_ms);
            run.stages["projection ms"].push_back(stats.projection_ms);
            run.stages["sort cycles"].push_back(double(stats.sort_cycles));
        }
        fx::Image image = target.read();
        run.checks.push_back(check_frame(image, references.at(run.model)[k], path == fx::RenderPath::Pcp, run.tol));
        if (k == 0) run.view0 = std::move(image);
    }
    run.bytes_per_cell = double(renderer.gpu_bytes()) / double(sc.mesh.cell_count());
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
                        {"gpu_ms", median_or_null(r.gpu_ms)},
                        {"first_frame_ms", r.first_ms},
                        {"setup_ms", r.setup_ms},
                        {"bytes_per_cell", r.bytes_per_cell}};
    if (!r.sort.empty()) o["sort"] = r.sort;
    for (const auto& [name, values] : r.stages) o["stages"][name] = median(values);
    if (!r.checks.empty()) {
        o["check"] = {{"tolerance", {{"mean_percent", r.tol.mean}, {"pixel_percent", r.tol.pixel}, {"share_percent", r.tol.share}}},
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
    require_known(parsed, {"paths", "views", "size", "up", "sort", "scalar", "tf", "density", "threads", "json", "images"});
    // Every option before the mesh is read; the outputs are tried now, not after the run.
    const int views = int_option(parsed, "bench render", "views", 8);
    int width = 512, height = 512;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const unsigned threads = unsigned(int_option(parsed, "bench render", "threads", int(std::max(1u, std::thread::hardware_concurrency()))));
    number_option(parsed, "bench render", "density", 1.0); // applied to the transfer function below
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
    const Scene scene{mesh, input.field, field, tf, cameras, width, height};
    std::vector<fx::OpticalModel> models = {fx::OpticalModel::EmissionAbsorption};
    for (const fx::RenderPath p : paths)
        if (std::find(models.begin(), models.end(), model_of(p)) == models.end()) models.push_back(model_of(p));
    References references;
    std::vector<Run> runs = {run_scanline(scene, threads, models, references)};

    std::optional<fx::HeadlessContext> context;
    if (!paths.empty()) context.emplace();
    std::printf("  gl: %s; scan-line: %u threads\n", context ? context->description().c_str() : "(no GPU path)", threads);
    std::printf("\n  %-28s %10s %12s %9s %9s %9s %8s  %s\n", "renderer", "ms/frame", "cells/s", "cpu ms", "gpu ms",
                "first ms", "B/cell", "check: worst mean, worst share of pixels (tolerance), % of peak");
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
                "  cpu ms: until render() returned; gpu ms: GL_TIME_ELAPSED; first ms: the warm-up frame; B/cell: GPU\n"
                "  buffers (scan-line: its frame memory) per mesh cell; check: against the scan-line frame of the same model.\n");

    // Where the time goes: the renderers' own per-stage figures, medians over the views.
    std::printf("\n  per stage (medians):\n");
    for (const Run& r : runs) {
        std::printf("  %-28s", r.label.c_str());
        for (const auto& [name, values] : r.stages) std::printf("  %s %.4g", name.c_str(), median(values));
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
                    std::fprintf(stderr, " %s view %zu (mean %.3g%%, %.3g%% of pixels%s);", r.label.c_str(), k,
                                 r.checks[k].mean, r.checks[k].share, r.checks[k].finite ? "" : ", not finite");
        std::fprintf(stderr, "\n");
        return 1;
    }
    return 0;
}

} // namespace cellfx_cli
