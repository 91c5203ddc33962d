// `cellfx render FILE [Q_FILE] --path NAME ...`: one frame of a mesh, written to PNG or PFM.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "commands.hpp"
#include "fx/auto_path.hpp"
#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "mesh_input.hpp"
#include "options.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_reference.hpp"
#include "terrain/scene_renderer.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

// True if the camera spec (Camera::parse's form) sets `key`, as in "near=0.5".
bool spec_sets(const std::string& spec, const std::string& key) {
    for (std::size_t at = 0; at <= spec.size();) {
        const std::size_t comma = std::min(spec.find(',', at), spec.size());
        if (spec.compare(at, key.size() + 1, key + "=") == 0) return true;
        at = comma + 1;
    }
    return false;
}

// A --camera without near= gets one in front of the mesh: the default, 0.01, would cut a mesh
// 1e-4 across in front of the eye. (No path cuts cells at the far plane.)
void fit_near(const std::string& spec, const fx::Bounds& bounds, fx::Camera& camera) {
    if (spec_sets(spec, "near")) return;
    camera.validate("--camera");
    const glm::dvec3 forward = camera.forward();
    double nearest = HUGE_VAL;
    for (int k = 0; k < 8; ++k) nearest = std::min(nearest, glm::dot(bounds.corner(k) - camera.eye, forward));
    // Half way to the mesh's nearest corner, or a small part of the mesh when the eye is inside it.
    const double fit = nearest > 0.0 ? 0.5 * nearest : 1e-4 * glm::length(bounds.hi - bounds.lo);
    if (fit > 0.0) camera.near_distance = std::min(camera.near_distance, fit);
}

constexpr const char* kUsage =
    "usage: cellfx render FILE [Q_FILE] --out FILE.png|FILE.pfm [options]\n"
    "  --path NAME        render path: scanline (CPU reference, default), or a GPU path\n"
    "                     (headless OpenGL 4.5): pcp (classic, 8-bit), pcp-exact, mip, absorption\n"
    "                     (sorted, classic), absorption-exact; or auto: the fastest on this machine\n"
    "                     that computes --model within --accuracy, measured on this mesh and view\n"
    "                     (about 0.6 of a frame per path; the pick and why on stderr)\n"
    "  --accuracy E       auto: accepted mean error per pixel, a share of the picture's peak, in\n"
    "                     [1e-6, 1] (default 1e-3: the exact paths and scanline; 4e-3 lets in absorption)\n"
    "  --model NAME       scanline optical model: absorption (default), emission, max (auto: the\n"
    "                     model its candidates compute)\n"
    "  --fog              pcp-exact: also absorb (one-colour medium, bg·e^-tau + c·(1 - e^-tau))\n"
    "  --sort NAME        absorption paths: visibility sort xmpvo (default; exact on convex and\n"
    "                     non-convex meshes), mpvo (convex meshes), power (Delaunay), centroid\n"
    "  --scalar NAME      point field to render (default: the first)\n"
    "  --tf FILE          transfer function JSON (default: a built-in blue-to-red ramp);\n"
    "                     a normalized one is mapped onto the field's range\n"
    "  --density K        multiply the transfer function's extinction by K (default 1)\n"
    "  --camera SPEC      eye=x,y,z,target=x,y,z,up=x,y,z,fov=DEG (or ortho=HEIGHT), near=, far=\n"
    "                     (default: the whole mesh from the +x+y+z diagonal); near left out is\n"
    "                     fitted to the mesh; no path cuts cells at the far plane\n"
    "  --near D           near-plane distance (overrides the camera's)\n"
    "  --size WxH         image size (default 512x512)\n"
    "  --background R,G,B background colour in [0,1] (default 0,0,0)\n"
    "  --threads N        scan-line worker threads (default: all cores)\n"
    "\n"
    "usage: cellfx render SCENE.json --out FILE.png|FILE.pfm [options]   (scenes: docs/terrain.md, docs/effects.md)\n"
    "  --path NAME        render every effect (fog, aurora, campfire, ...) with this GPU path, or\n"
    "                     scanline: the scene's volumes on the CPU, exactly, as intersecting grids (the\n"
    "                     reference; each effect keeps its own path's optical model; no terrain surface)\n"
    "  --threads N        scanline: worker threads (default: all cores)\n"
    "  --time T           scene time in seconds (animation, camera path; default 0)\n"
    "  --camera SPEC      override the scene's camera or camera path (as above)\n"
    "  --disable A,B      switch these effects off; --only A,B switches all others off\n"
    "  --no-terrain       do not draw the terrain surface (it still carries the fog)\n"
    "  --size WxH         override the scene's image size\n"
    "  --pixel-error PX   override the LOD's screen-space error bound\n"
    "  --fx-scale S       the effects' resolution: 1, 0.5 or 0.25 of the image's (default: the scene's\n"
    "                     render.fx_scale), upsampled against the scene's depth\n"
    "  --medium NAME      where volumes overlap: froxel (bounded grid) or exact (per-pixel segment\n"
    "                     lists; default: the scene's render.medium)";

// `cellfx render SCENE.json`: a scene (terrain/scene.hpp: terrain, fog, aurora, effects) in a
// headless context, through the same SceneRenderer a game uses.
int render_scene_file(const ParsedArgs& parsed) {
    require_known(parsed, {"path", "camera", "size", "pixel-error", "out", "time", "disable", "only", "no-terrain", "threads",
                           "fx-scale", "medium"});
    if (parsed.positional.size() != 1)
        throw fx::Error(parsed.positional[0] + ": a scene file is rendered alone, but " +
                        std::to_string(parsed.positional.size() - 1) + " more file" +
                        (parsed.positional.size() > 2 ? "s follow it" : " follows it") + " ('" + parsed.positional[1] +
                        "'): a second file (Q_FILE) goes with a PLOT3D grid only");
    const std::string out = output_file_option(parsed, "out", {".png", ".pfm"}, true);
    // The options, then the scene: a bad value or file is an error before any GL work.
    const double time = number_option(parsed, "render", "time", 0.0);
    const double pixel_error = number_option(parsed, "render", "pixel-error", 0.0);
    const int threads = int_option(parsed, "render", "threads", 0);
    int width = 0, height = 0;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    if (parsed.has("camera")) fx::Camera::parse(parsed.get("camera"), "--camera");
    const auto t0 = std::chrono::steady_clock::now();
    terrain::Scene scene = terrain::load_scene(parsed.positional[0]);
    const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    fx::Camera camera = scene.camera_path ? scene.camera_path->at(time, scene.camera) : scene.camera;
    if (parsed.has("camera")) camera = fx::Camera::parse(parsed.get("camera"), "--camera");
    camera.validate(parsed.has("camera") ? "--camera" : parsed.positional[0] + ": the camera at t = " + format_number(time));
    if (parsed.has("size")) scene.width = width, scene.height = height;
    if (parsed.has("pixel-error")) scene.pixel_error = pixel_error;
    if (parsed.has("no-terrain")) scene.draw_terrain = false;
    if (parsed.has("fx-scale")) scene.fx_scale = parse_fx_scale(parsed.get("fx-scale"));
    if (parsed.has("medium")) scene.medium = parse_medium_option(parsed.get("medium"));
    const fx::HeadlessContext context;
    terrain::SceneRenderer renderer(scene);
    const bool reference = parsed.get("path") == "scanline";
    if (parsed.has("path") && !reference) {
        fx::RenderPath path;
        if (parsed.get("path") == "auto")
            throw fx::Error("--path auto: renders a mesh (cellfx render FILE --path auto); a scene's effects take a named "
                            "path or scanline");
        if (!fx::parse_render_path(parsed.get("path"), path))
            throw fx::Error("--path: unknown render path '" + parsed.get("path") + "'");
        if (renderer.effect_names().empty()) throw fx::Error("--path: the scene has no effects to render");
        for (const std::string& name : renderer.effect_names()) renderer.set_path(name, path);
    }
    for (const std::string& name : split_list(parsed.get("disable"))) renderer.set_enabled(name, false);
    if (parsed.has("only")) {
        const std::vector<std::string> only = split_list(parsed.get("only"));
        for (const std::string& name : only) renderer.enabled(name); // unknown names are errors
        for (const std::string& name : renderer.effect_names())
            renderer.set_enabled(name, std::find(only.begin(), only.end(), name) != only.end());
    }
    renderer.set_time(time);
    if (reference) { // the scene's volumes, exactly, as intersecting grids (terrain not drawn)
        renderer.update(0.0, camera, scene.width, scene.height);
        const auto t1 = std::chrono::steady_clock::now();
        fx::Image image = terrain::render_scene_reference(renderer, camera, scene.width, scene.height, unsigned(threads));
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
        fx::composite_over(image, glm::vec3(scene.background));
        fx::write_image(image, out);
        std::printf("wrote %s (%dx%d, t = %g s, scan-line reference of the volumes; no terrain surface)\n", out.c_str(),
                    scene.width, scene.height, time);
        std::printf("  %-22s %10.2f ms\n", "load scene", load_ms);
        std::printf("  %-22s %10.2f ms\n", "scan-line frame", ms);
        for (const terrain::SceneRenderer::DrawnVolume& v : renderer.drawn_volumes())
            std::printf("  %-10s %-16s %8zu cells%s\n", v.name.c_str(), fx::render_path_name(v.path), v.effect->mesh().cell_count(),
                        v.in_medium ? (v.medium.absorbs ? ", one medium, absorbing" : ", one medium, emission only")
                                    : v.path == fx::RenderPath::Mip ? ", maximum (added)" : ", emission (added)");
        return 0;
    }
    renderer.set_timing(true);
    terrain::FrameStats stats;
    const fx::Image image = renderer.render_to_image(camera, scene.width, scene.height, &stats);
    fx::write_image(image, out);
    std::printf("wrote %s (%dx%d, t = %g s)\n", out.c_str(), scene.width, scene.height, time);
    std::printf("  %-22s %10.2f ms\n", "load scene", load_ms);
    std::printf("  %-22s %10.2f ms\n", "LOD update", stats.lod_ms);
    std::printf("  %-22s %10.2f ms\n", "LOD mesh + prisms", stats.mesh_ms);
    std::printf("  %-22s %10.2f ms\n", "effects upload", stats.upload_ms);
    std::printf("  %-22s %10.2f ms (gpu %.2f ms)\n", "draw (to glFinish)", stats.draw_ms, stats.gpu_ms);
    if (renderer.scene().has_terrain() && renderer.terrain_drawn())
        std::printf("  %-22s %10zu of %zu at full resolution\n", "terrain triangles", stats.terrain_lod.triangles,
                    renderer.terrain_lod().full_resolution_triangles());
    if (renderer.fx_scale() < 1.0) std::printf("  %-22s %10g of the image's resolution\n", "effects at", renderer.fx_scale());
    if (stats.medium.pixels > 0 && stats.medium.method == fx::MediumMethod::Exact)
        std::printf("  %-22s %10zu px, %zu segments (pool %zu, %zu redraws), %zu volumes, gpu %.2f ms (append %.2f, resolve %.2f), %.1f MB\n",
                    "one medium, exact", stats.medium.pixels, stats.medium.segments, stats.medium.capacity, stats.medium.redraws,
                    stats.medium.volumes, stats.medium.gpu_ms, stats.medium.append_gpu_ms, stats.medium.resolve_gpu_ms,
                    double(stats.medium.gpu_bytes) / 1e6);
    if (stats.medium.pixels > 0 && stats.medium.method == fx::MediumMethod::Froxel)
        std::printf("  %-22s %10zu froxels, %zu volumes, gpu %.2f ms (inject %.2f, light + integrate + apply + emission %.2f), %.1f MB\n",
                    "one medium, froxel", stats.medium.froxels, stats.medium.volumes, stats.medium.gpu_ms,
                    stats.medium.append_gpu_ms, stats.medium.resolve_gpu_ms, double(stats.medium.gpu_bytes) / 1e6);
    std::printf("  %-10s %-12s %-11s %-16s %8s %8s %8s %9s %9s %9s\n", "effect", "type", "status", "path", "cells",
                "built", "drawn", "noise", "sim ms", "gpu ms");
    for (const terrain::EffectFrameStats& e : stats.effects)
        std::printf("  %-10s %-12s %-11s %-16s %8zu %8zu %8zu %9zu %9.2f %9.2f\n", e.name.c_str(), e.type.c_str(),
                    terrain::effect_status_name(e.status), fx::render_path_name(e.path), e.cells, e.cells_built,
                    e.cells_drawn, e.noise_samples, e.simulate_ms, e.gpu_ms);
    std::printf("  gl: %s\n", context.description().c_str());
    return 0;
}

struct Frame {
    fx::Image image;
    std::vector<std::pair<std::string, double>> milliseconds; // stage → ms
    std::vector<std::pair<std::string, double>> counts;       // statistic → value
    std::vector<std::string> notes;                           // printed after the figures
};

struct RenderJob {
    const fx::CellMesh* mesh;
    const fx::ScalarField* field;
    fx::TransferFunction tf;
    fx::Camera camera;
    int width, height;
    fx::OpticalModel model;
    unsigned threads;
    bool fog;
    fx::SortMethod sort;
};

// `warm`: a renderer already built on job.mesh (auto's), so its set-up is not paid twice.
Frame render_scanline(const RenderJob& job, const fx::ScanlineRenderer* warm = nullptr) {
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<fx::ScanlineRenderer> own;
    if (!warm) own.emplace(*job.mesh);
    const fx::ScanlineRenderer& renderer = warm ? *warm : *own;
    const double setup_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    fx::ScanlineOptions options;
    options.model = job.model;
    options.threads = job.threads;
    fx::ScanlineStats stats;
    Frame frame;
    frame.image = renderer.render(job.camera, job.width, job.height, *job.field, job.tf, options, &stats);
    frame.milliseconds = {{"setup (triangles)", setup_ms},
                          {"transform", 1e3 * stats.seconds_transform},
                          {"y-buckets", 1e3 * stats.seconds_y_buckets},
                          {"scan", 1e3 * stats.seconds_scan},
                          {"frame", 1e3 * stats.seconds_total}};
    frame.counts = {{"threads", double(stats.threads)},
                    {"triangles", double(stats.triangles_total)},
                    {"active triangles", double(stats.triangles_active)},
                    {"near-plane caps", double(stats.cap_triangles)},
                    {"crossings", double(stats.crossings)},
                    {"memory MB", double(stats.memory.renderer_total()) / 1e6}};
    return frame;
}

// One frame of a GPU cell-projection path in a headless context, timed on the GPU. `warm`:
// a renderer of job.mesh whose context is current (auto's, its programs and sort state made).
Frame render_gpu(const RenderJob& job, fx::RenderPath path, fx::CellRenderer* warm = nullptr,
                 const std::string& warm_gl = "") {
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<fx::HeadlessContext> context;
    if (!warm) context.emplace();
    const auto t1 = std::chrono::steady_clock::now();
    std::optional<fx::CellRenderer> own;
    if (!warm) own.emplace(*job.mesh, job.field->name, job.tf);
    fx::CellRenderer& renderer = warm ? *warm : *own;
    const auto t2 = std::chrono::steady_clock::now();
    fx::CellRenderOptions options;
    options.fog = job.fog;
    options.sort = job.sort;
    options.timing = true;
    fx::CellRenderStats stats;
    Frame frame;
    frame.image = renderer.render_to_image(job.camera, job.width, job.height, path, options, &stats);
    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    frame.milliseconds = {{"context", ms(t0, t1)},
                          {"setup (upload)", ms(t1, t2)},
                          {"frame cpu", stats.cpu_ms},
                          {"frame gpu", stats.gpu_ms}};
    frame.counts = {{"cells", double(stats.cells)},       {"cells drawn", double(stats.cells_drawn)},
                    {"near-plane caps", double(stats.caps)}, {"batches", double(stats.batches)},
                    {"draw calls", double(stats.draw_calls)}, {"gpu MB", double(renderer.gpu_bytes()) / 1e6}};
    if (path == fx::RenderPath::Absorption || path == fx::RenderPath::AbsorptionExact) {
        frame.milliseconds.insert(frame.milliseconds.begin() + 2, {{"sort set-up", stats.setup_ms},
                                                                   {"subdivision (§V)", stats.subdivision_ms},
                                                                   {"sort", stats.sort_ms},
                                                                   {"projection", stats.projection_ms}});
        frame.counts.push_back({"problem cells", double(stats.problem_cells)});
        frame.counts.push_back({"sort cycles", double(stats.sort_cycles)});
        frame.notes.push_back(std::string("sort: ") + fx::sort_method_name(job.sort));
    }
    frame.notes.push_back("gl: " + (context ? context->description() : warm_gl));
    return frame;
}

// The render paths this build offers, by --path name.
const std::map<std::string, std::function<Frame(const RenderJob&)>>& render_paths() {
    static const std::map<std::string, std::function<Frame(const RenderJob&)>> paths = {
        {"scanline", [](const RenderJob& job) { return render_scanline(job); }},
    };
    static const auto all = [] {
        auto with_gpu = paths;
        // Every GPU path fx::CellRenderer offers, under its own name.
        for (const fx::RenderPath path : fx::kRenderPaths)
            with_gpu[fx::render_path_name(path)] = [path](const RenderJob& job) { return render_gpu(job, path); };
        return with_gpu;
    }();
    return all;
}

// --path auto: measures the paths that compute job.model on this machine (fx/auto_path.hpp),
// prints the pick and why on stderr, sets `picked` to its name and draws the frame with the
// renderers the measuring warmed up (their set-up and first frame are paid once). Without a GL
// context the GL paths, for a mesh the scan-line renderer refuses the scan-line renderer, are
// left out (the line says so).
Frame render_auto(const RenderJob& job, double accuracy, std::string& picked) {
    fx::CalibrationFrame frame;
    frame.mesh = job.mesh, frame.field = job.field, frame.tf = &job.tf;
    frame.camera = job.camera, frame.width = job.width, frame.height = job.height;
    frame.model = job.model, frame.threads = job.threads, frame.sort = job.sort;
    std::vector<fx::AutoCandidate> candidates = fx::auto_candidates(job.model);
    std::string left_out; // candidates this machine or mesh cannot run, and why
    std::optional<fx::ScanlineRenderer> scanline;
    try {
        scanline.emplace(*job.mesh);
    } catch (const fx::Error& e) { // a mesh the reference refuses (overlapping cells, ...)
        left_out += std::string("; scanline left out: ") + e.what();
        candidates.erase(candidates.begin());
    }
    std::optional<fx::HeadlessContext> context;
    try {
        context.emplace();
        left_out += "; gl: " + context->description();
    } catch (const fx::Error& e) {
        left_out += std::string("; GL paths left out, no GL context: ") + e.what();
        candidates.resize(candidates.empty() || !candidates.front().scanline ? 0 : 1);
    }
    if (candidates.empty()) throw fx::Error("--path auto: no path can draw this mesh here" + left_out);
    std::optional<fx::CellRenderer> gl;
    if (context) gl.emplace(*job.mesh, job.field->name, job.tf);
    const std::vector<fx::PathCost> costs =
        fx::measure_path_costs(frame, candidates, accuracy, gl ? &*gl : nullptr, scanline ? &*scanline : nullptr);
    const fx::PathChoice choice = fx::choose_path(costs, accuracy, job.width, job.height, "--accuracy");
    picked = fx::candidate_name(choice.candidate);
    std::fprintf(stderr, "%s%s\n", choice.reason.c_str(), left_out.c_str());
    if (choice.candidate.scanline) return render_scanline(job, &*scanline);
    return render_gpu(job, choice.candidate.gl, &*gl, context->description());
}

fx::OpticalModel parse_model(const std::string& name) {
    if (name == "absorption") return fx::OpticalModel::EmissionAbsorption;
    if (name == "emission") return fx::OpticalModel::Emission;
    if (name == "max") return fx::OpticalModel::Maximum;
    throw fx::Error("--model: unknown optical model '" + name + "' (expected absorption, emission or max)");
}

} // namespace

int run_render(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"help", "fog", "no-terrain"});
    if (parsed.has("help")) {
        std::puts(kUsage);
        return 0;
    }
    if (!parsed.positional.empty() && has_extension(parsed.positional[0], ".json")) return render_scene_file(parsed);
    require_known(parsed, {"path", "model", "scalar", "tf", "density", "camera", "near", "size", "background",
                           "threads", "fog", "sort", "out", "accuracy"});
    if (parsed.positional.empty() || parsed.positional.size() > 2) throw fx::Error("expected FILE [Q_FILE]\n" + std::string(kUsage));
    const std::string out = output_file_option(parsed, "out", {".png", ".pfm"}, true);
    // Every option's value before the mesh is read: a typo costs nothing.
    const int threads = int_option(parsed, "render", "threads", 0);
    const double near = number_option(parsed, "render", "near", 0.0);
    int width = 512, height = 512;
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const glm::dvec3 background = parsed.has("background") ? parse_colour(parsed.get("background"), "--background") : glm::dvec3(0.0);
    number_option(parsed, "render", "density", 1.0); // applied with --tf once the field is known
    if (parsed.has("camera")) fx::Camera::parse(parsed.get("camera"), "--camera"); // near fitted to the mesh below
    std::string path_name = parsed.get("path", "scanline");
    const bool automatic = path_name == "auto";
    auto path = render_paths().find(path_name);
    if (path == render_paths().end() && !automatic) {
        std::string names;
        for (const auto& [name, fn] : render_paths()) names += (names.empty() ? "" : ", ") + name;
        throw fx::Error("--path: unknown render path '" + path_name + "' (this build has: " + names + ", auto)");
    }
    const double accuracy = number_option(parsed, "render", "accuracy", fx::kDefaultAccuracy); // its range first
    if (parsed.has("accuracy") && !automatic) throw fx::Error("--accuracy is an option of --path auto");

    const MeshInput input = read_mesh_input(parsed);
    const fx::CellMesh& mesh = input.mesh;
    const fx::ScalarField* field = &input.scalar();
    RenderJob job{&mesh, field, transfer_function_option(parsed, "render", *field, default_transfer_function()), {}, width, height,
                  fx::OpticalModel::EmissionAbsorption, unsigned(threads), parsed.has("fog"), fx::SortMethod::Xmpvo};
    if (parsed.has("sort")) {
        if (path_name != "absorption" && path_name != "absorption-exact" && !automatic)
            throw fx::Error("--sort is an option of the absorption paths (and of auto, which may pick one)");
        if (!fx::parse_sort_method(parsed.get("sort"), job.sort)) {
            std::string names;
            for (const fx::SortMethod m : fx::all_sort_methods()) names += (names.empty() ? "" : ", ") + std::string(fx::sort_method_name(m));
            throw fx::Error("--sort: unknown sort '" + parsed.get("sort") + "' (expected " + names + ")");
        }
    }
    if (job.fog && path_name != "pcp-exact") throw fx::Error("--fog is an option of --path pcp-exact");
    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    job.camera = parsed.has("camera") ? fx::Camera::parse(parsed.get("camera"), "--camera") : fx::Camera::framing(bounds.lo, bounds.hi);
    if (parsed.has("camera")) fit_near(parsed.get("camera"), bounds, job.camera);
    if (parsed.has("near")) job.camera.near_distance = near;
    job.camera.validate(parsed.has("near") ? "--near " + parsed.get("near") : parsed.has("camera") ? "--camera" : "camera");
    if (parsed.has("model")) job.model = parse_model(parsed.get("model"));

    Frame frame;
    try {
        frame = automatic ? render_auto(job, accuracy, path_name) : path->second(job);
    } catch (const fx::Error& e) { // what a renderer refuses, named by the file it came from
        throw fx::Error(parsed.positional[0] + ": " + e.what());
    }
    fx::composite_over(frame.image, glm::vec3(background));
    fx::write_image(frame.image, out);

    std::printf("wrote %s (%dx%d, path %s%s, scalar %s)\n", out.c_str(), job.width, job.height, path_name.c_str(),
                automatic ? " (auto)" : "",
                input.field.c_str());
    std::printf("  %-20s %10.2f ms\n", "load mesh", input.load_ms);
    for (const auto& [stage, ms] : frame.milliseconds) std::printf("  %-20s %10.2f ms\n", stage.c_str(), ms);
    for (const auto& [name, value] : frame.counts) std::printf("  %-20s %10.6g\n", name.c_str(), value);
    for (const std::string& note : frame.notes) std::printf("  %s\n", note.c_str());
    return 0;
}

} // namespace cellfx_cli
