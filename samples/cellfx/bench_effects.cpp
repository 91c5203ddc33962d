// Based on: Roettger & Ertl 2003, §4 (Table 4: search light 115.8 fps, campfire 51.3 fps) and §5
// (ground fog ~25 Hz PCP, > 50 Hz MIP).
//
// `cellfx bench effects`: every shipped effect scene (content/scenes: campfire, searchlight,
// laser, fog_valley, aurora, fog_valley_night) with every GPU render path, through terrain::SceneRenderer: frames
// 1/30 s apart on the scene clock along its camera path (or a slow move), each updated and
// rendered (render_to_image: the opaque frame, read back outside the timing), with
// GL_TIME_ELAPSED queries per stage. Per scene and path: median milliseconds per frame (wall,
// update + render to glFinish) and GPU milliseconds, and the medians of the stages — update
// (LOD, effect simulation), upload (set_mesh / set_scalars), terrain surface, effects, composite.
//
// A first row per scene runs the same frames with every effect switched off (the terrain alone):
// nothing is simulated or drawn for them, so the difference is what the effects cost.
// Verified after timing, so that a broken path cannot look fast: the last timed frame is finite
// and differs from the same frame without effects; then the same frame's effects alone (terrain
// not drawn, over black) are compared with the scan-line reference of the effects' meshes as
// intersecting grids (terrain/scene_reference.hpp: one medium for the emission–absorption paths,
// emission or maximum added for pcp and mip): mean and worst error in percent of the
// reference's peak. Classic pcp is compared with the reference clamped to its 8-bit range.
//
// Then the samples (samples/<name>: fog_valley, campfire, searchlight, aurora, fem_viewer):
// each sample's own frame loop — the code its window runs, drawing into an offscreen RGBA8 +
// depth framebuffer (no stats text) — per render path it offers, frames dt = 1/30 s apart, each
// to glFinish: median ms per frame, the update (simulation) and cellfx render (CPU) parts. The
// last frame must differ from the background (the sample tests compare the pictures).
//
// Last, the CPU a game's frame spends in cellfx (bench_game_cpu.cpp): each scene through
// cellfx::Module as a game calls it, the camera flying, cellfx's own CPU apart from the GL
// driver's, allocations per frame, and what teleports, resizes, toggles and reloads cost.
//
// Options: --scenes a,b (all), --frames N (8, after 2 warm-up frames; 60 with --only-cpu), --size
//          WxH (the scenes'), --paths a,b (all; the CPU rows: the scenes' own paths unless given),
//          --fx-scale S[,S...] (the effects' resolution, 1, 0.5, 0.25: a row per scale; default the
//          scenes' own), --medium froxel|exact (default the scenes'), --skip-verify, --samples a,b
//          (all five), --no-samples, --only-samples (skip the scene and CPU rows), --only-cpu (the
//          CPU rows alone), --gl-calls (the CPU rows' GL calls per entry point), --json FILE: every
//          row as {"scenes": [...]}, the scene rows with {"scene", "path", "fx_scale", "medium",
//          "ms_per_frame", "gpu_ms", ...}, the CPU rows with {"scene", "path", "cellfx_cpu_ms":
//          {"median", "p95"}, "driver_cpu_ms": {...}, "gl_state_ms": {...}, "allocations_per_frame",
//          ...}.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <nlohmann/json.hpp>

#include "bench_json.hpp"
#include "bench_support.hpp"
#include "cellfx/cellfx.hpp"
#include "commands.hpp"
#include "fx/campfire.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/scanline_renderer.hpp"
#include "options.hpp"
#include "sample.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_reference.hpp"
#include "terrain/scene_renderer.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

// bench_game_cpu.cpp: the CPU rows, printed and appended to `json` (--json's rows).
void bench_game_cpu(const std::vector<std::string>& scenes, const std::vector<std::string>& paths, int frames, int warmup,
                    const ParsedArgs& parsed, std::vector<BenchJsonRow>& json);

namespace {

const char* const kScenes[] = {"campfire", "searchlight", "laser", "fog_valley", "aurora", "fog_valley_night"};

// Frame f of the timed run: 1/30 s apart along the camera path, or a slow sideways move (1% of
// the eye's distance to the target per frame) when the scene has none.
fx::Camera camera_at(const terrain::Scene& scene, int frame, double dt) {
    if (scene.camera_path) return scene.camera_path->at(frame * dt, scene.camera);
    fx::Camera cam = scene.camera;
    const glm::dvec3 side = cam.right();
    const double step = 0.01 * glm::length(cam.target - cam.eye);
    cam.eye += side * (step * frame);
    cam.target += side * (step * frame);
    return cam;
}

struct Row {
    std::string scene, path;
    double fx_scale = 1.0;
    std::string medium; // the method that ran ("-": no volumes overlapped)
    std::size_t cells = 0, noise = 0;
    double ms = 0, cpu = 0, gpu = 0, update = 0, upload = 0, surface = 0, effects = 0, composite = 0;
    double medium_gpu = 0, medium_mb = 0;
    int width = 0, height = 0, frames = 0;
    verify::Difference error;
    bool verified = false;
};

void print_row(const Row& r) {
    std::printf("  %-12s %-17s %5g %-6s %8zu %8zu %9.2f %8.1f %8.2f %9.2f %8.2f %8.2f %8.2f %9.2f %9.2f %8.2f %7.1f",
                r.scene.c_str(), r.path.c_str(), r.fx_scale, r.medium.c_str(), r.cells, r.noise, r.ms, 1000.0 / r.ms, r.cpu,
                r.gpu, r.update, r.upload, r.surface, r.effects, r.composite, r.medium_gpu, r.medium_mb);
    if (r.verified)
        std::printf(" %8.3f %8.2f\n", 100.0 * r.error.of_peak(r.error.mean), 100.0 * r.error.of_peak(r.error.worst.delta));
    else
        std::printf(" %8s %8s\n", "-", "-");
}

// A scene row as `--json` writes it.
BenchJsonRow json_row(const Row& r) {
    BenchJsonRow j;
    j["scene"] = r.scene;
    j["path"] = r.path;
    j["fx_scale"] = r.fx_scale;
    j["medium"] = r.medium;
    j["width"] = r.width;
    j["height"] = r.height;
    j["frames"] = r.frames;
    j["ms_per_frame"] = r.ms;
    j["gpu_ms"] = r.gpu;
    j["cpu_ms"] = r.cpu;
    j["update_ms"] = r.update;
    j["upload_ms"] = r.upload;
    j["surface_gpu_ms"] = r.surface;
    j["effects_gpu_ms"] = r.effects;
    j["composite_gpu_ms"] = r.composite;
    j["medium_gpu_ms"] = r.medium_gpu;
    j["medium_mb"] = r.medium_mb;
    j["cells"] = r.cells;
    j["noise_samples"] = r.noise;
    if (r.verified) {
        j["error_mean_percent"] = 100.0 * r.error.of_peak(r.error.mean);
        j["error_max_percent"] = 100.0 * r.error.of_peak(r.error.worst.delta);
    }
    return j;
}

// The samples' frame loops (see the header comment), one row per sample and path.
void bench_samples(const ParsedArgs& parsed, const std::vector<fx::RenderPath>& paths, int frames, int warmup, double dt) {
    std::vector<std::string> names = parsed.has("samples") ? split_list(parsed.get("samples")) : std::vector<std::string>();
    if (names.empty())
        for (const cellfx_samples::SampleInfo& s : cellfx_samples::sample_catalog()) names.push_back(s.usage.name);
    std::printf("\n  samples: each sample's frame loop (the window's code, offscreen RGBA8 + depth, no stats text), to glFinish\n");
    std::printf("  %-12s %-17s %9s %10s %8s %10s %10s %10s %10s %10s\n", "sample", "path", "size", "ms/frame", "fps", "update ms",
                "cellfx ms", "cpu ms", "cpu update", "cpu render");
    for (const std::string& name : names) {
        const cellfx_samples::SampleInfo& info = cellfx_samples::find_sample(name);
        for (fx::RenderPath path : paths) {
            cellfx_samples::SampleOptions options;
            options.path = path;
            options.dt = dt;
            if (parsed.has("size")) parse_size(parsed.get("size"), options.width, options.height);
            const cellfx_samples::TimedRun run = cellfx_samples::time_sample(info, options, warmup + frames);
            const auto timed = [&](const std::vector<double>& v) { return median(std::vector<double>(v.begin() + warmup, v.end())); };
            const fx::Image bg(run.last_frame.width, run.last_frame.height, glm::vec4(run.background, 1.0f));
            double changed = 0.0;
            for (std::size_t i = 0; i < bg.pixels.size(); ++i)
                changed += glm::length(glm::vec3(run.last_frame.pixels[i]) - glm::vec3(bg.pixels[i])) > 4.0f / 255.0f ? 1.0 : 0.0;
            if (!(changed > 0.01 * double(bg.pixels.size())))
                throw fx::Error("bench effects: sample " + name + " [" + run.path + "]: the frame shows nothing but the background");
            const double ms = timed(run.frame_ms);
            const std::string size = std::to_string(run.last_frame.width) + "x" + std::to_string(run.last_frame.height);
            std::vector<double> cpu(run.update_cpu_ms.size());
            for (std::size_t i = 0; i < cpu.size(); ++i) cpu[i] = run.update_cpu_ms[i] + run.render_cpu_ms[i];
            std::printf("  %-12s %-17s %9s %10.2f %8.1f %10.2f %10.2f %10.3f %10.3f %10.3f\n", name.c_str(), run.path.c_str(),
                        size.c_str(), ms, 1000.0 / ms, timed(run.update_ms), timed(run.render_ms), timed(cpu),
                        timed(run.update_cpu_ms), timed(run.render_cpu_ms));
            std::fflush(stdout);
        }
    }
    std::printf("  ms/frame: wall time of one frame of the loop (update, clear, props, depth copy, cellfx) to glFinish;\n"
                "  update: the simulation part; cellfx: the wall time of cellfx's render call (GPU work is asynchronous);\n"
                "  cpu: CPU time of cellfx's update and render calls on the game's thread (the thread CPU clock: not the\n"
                "  time spent waiting), and its two parts: update (cellfx alone, no GL) and render (cellfx and the GL\n"
                "  driver's work on that thread; on llvmpipe that includes the vertex stage and binning of every draw).\n");
}

} // namespace

int bench_effects(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"skip-verify", "no-samples", "only-samples", "only-cpu", "gl-calls"});
    require_known(parsed, {"scenes", "frames", "size", "paths", "skip-verify", "samples", "no-samples", "only-samples", "only-cpu",
                           "gl-calls", "fx-scale", "medium", "json"});
    if (!parsed.positional.empty()) throw fx::Error("bench effects: unexpected argument '" + parsed.positional[0] + "'");
    const int frames = int_option(parsed, "bench effects", "frames", parsed.has("only-cpu") ? 60 : 8);
    const std::string json_file = output_file_option(parsed, "json", {}, false); // tried before the work
    std::vector<std::string> scenes = parsed.has("scenes") ? split_list(parsed.get("scenes")) : std::vector<std::string>();
    if (scenes.empty()) scenes.assign(std::begin(kScenes), std::end(kScenes));
    std::vector<fx::RenderPath> paths;
    if (parsed.has("paths")) {
        for (const std::string& name : split_list(parsed.get("paths"))) {
            fx::RenderPath p;
            if (!fx::parse_render_path(name, p)) throw fx::Error("bench effects: --paths: unknown render path '" + name + "'");
            paths.push_back(p);
        }
    } else {
        paths.assign(std::begin(fx::kRenderPaths), std::end(fx::kRenderPaths));
    }
    // The effects' resolutions to run (none given: each scene's own) and the medium's method.
    std::vector<double> scales;
    for (const std::string& item : split_list(parsed.get("fx-scale"))) scales.push_back(parse_fx_scale(item));
    const bool medium_given = parsed.has("medium");
    const fx::MediumMethod medium = medium_given ? parse_medium_option(parsed.get("medium")) : fx::MediumMethod::Froxel;
    const bool verify = !parsed.has("skip-verify");
    constexpr double kDt = 1.0 / 30.0;
    constexpr int kWarmup = 2;

    const fx::HeadlessContext context;
    // The CPU rows: the scenes' own paths unless --paths names some. Every row goes to --json.
    const std::vector<std::string> cpu_paths = parsed.has("paths") ? split_list(parsed.get("paths")) : std::vector<std::string>();
    std::vector<BenchJsonRow> json;
    const auto write_json = [&] {
        if (json_file.empty()) return;
        write_scenes_json(json_file, json);
        std::printf("\n  wrote %s\n", json_file.c_str());
    };
    if (parsed.has("only-cpu")) {
        std::printf("effects: cellfx's CPU per frame in a game\n  gl: %s\n", context.description().c_str());
        bench_game_cpu(scenes, cpu_paths, frames, kWarmup, parsed, json);
        write_json();
        return 0;
    }
    std::printf("effects: shipped scenes x render paths, through SceneRenderer (update + render, GPU-timed per stage)\n");
    std::printf("  gl: %s\n", context.description().c_str());
    std::printf("  %d warm-up + %d timed frames, %.0f ms apart on the scene clock; medians. Paper (2003 hardware): search\n"
                "  light 115.8 fps, campfire 51.3 fps (PCP, Table 4, window size not given); ground fog ~25 Hz PCP,\n"
                "  > 50 Hz MIP at 512x384 (§5).\n",
                kWarmup, frames, 1000.0 * kDt);
    std::printf("\n  %-12s %-17s %5s %-6s %8s %8s %9s %8s %8s %9s %8s %8s %8s %9s %9s %8s %7s %8s %8s\n", "scene", "path",
                "scale", "medium", "cells", "noise", "ms/frame", "fps", "cpu ms", "gpu ms", "update", "upload", "surface",
                "effects", "composite", "medium", "MB", "mean %", "max %");
    std::vector<Row> rows;
    std::map<std::string, std::vector<terrain::EffectFrameStats>> last_effects;
    const std::vector<std::string> cpu_scenes = scenes;
    if (parsed.has("only-samples")) scenes.clear();
    for (const std::string& name : scenes) {
        terrain::Scene scene = terrain::load_scene(std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + name + ".json");
        if (parsed.has("size")) parse_size(parsed.get("size"), scene.width, scene.height);
        if (medium_given) scene.medium = medium;
        const int w = scene.width, h = scene.height;
        const fx::Camera last_camera = camera_at(scene, kWarmup + frames - 1, kDt);
        const std::vector<double> scene_scales = scales.empty() ? std::vector<double>{scene.fx_scale} : scales;
        // The same frames with every effect switched off: what the effects cost on top (the
        // terrain alone), and the picture that proves each path draws something.
        fx::Image bare;
        {
            terrain::SceneRenderer r(scene);
            for (const std::string& e : r.effect_names()) r.set_enabled(e, false);
            r.set_timing(true);
            Row row;
            row.scene = name, row.path = "(effects off)";
            std::vector<double> ms, cpu, gpu, update, surface;
            for (int f = 0; f < kWarmup + frames; ++f) {
                r.set_time(f * kDt);
                terrain::FrameStats s;
                bare = r.render_to_image(camera_at(scene, f, kDt), w, h, &s);
                if (f < kWarmup) continue;
                ms.push_back(s.frame_ms), cpu.push_back(s.update_cpu_ms + s.render_cpu_ms), gpu.push_back(std::max(s.gpu_ms, 0.0)),
                    update.push_back(s.update_ms), surface.push_back(std::max(s.surface_gpu_ms, 0.0));
                row.cells = s.cells_drawn, row.noise = s.noise_samples;
            }
            row.ms = median(ms), row.cpu = median(cpu), row.gpu = median(gpu), row.update = median(update),
            row.surface = median(surface);
            row.medium = "-", row.width = w, row.height = h, row.frames = frames;
            print_row(row);
            json.push_back(json_row(row));
        }
        std::map<fx::RenderPath, fx::Image> references; // by the model a path draws with
        for (fx::RenderPath path : paths)
        for (double scale : scene_scales) {
            terrain::SceneRenderer renderer(scene);
            for (const std::string& e : renderer.effect_names()) renderer.set_path(e, path);
            renderer.set_fx_scale(scale);
            renderer.set_timing(true);
            std::vector<double> ms, cpu, gpu, update, upload, surface, effects, composite, medium_gpu;
            Row row;
            row.scene = name, row.path = fx::render_path_name(path), row.fx_scale = scale;
            row.width = w, row.height = h, row.frames = frames, row.medium = "-";
            fx::Image frame;
            for (int f = 0; f < kWarmup + frames; ++f) {
                const fx::Camera cam = camera_at(scene, f, kDt);
                renderer.set_time(f * kDt);
                terrain::FrameStats s;
                frame = renderer.render_to_image(cam, w, h, &s);
                if (f < kWarmup) continue;
                double effect_gpu = 0.0;
                for (const terrain::EffectFrameStats& e : s.effects) effect_gpu += std::max(e.gpu_ms, 0.0);
                ms.push_back(s.frame_ms), cpu.push_back(s.update_cpu_ms + s.render_cpu_ms), gpu.push_back(s.gpu_ms),
                    update.push_back(s.update_ms), upload.push_back(s.upload_ms),
                    surface.push_back(std::max(s.surface_gpu_ms, 0.0)), effects.push_back(effect_gpu),
                    composite.push_back(std::max(s.composite_gpu_ms, 0.0)), medium_gpu.push_back(std::max(s.medium.gpu_ms, 0.0));
                row.cells = s.cells_drawn;
                row.noise = s.noise_samples;
                if (s.medium.pixels > 0)
                    row.medium = fx::medium_method_name(s.medium.method), row.medium_mb = double(s.medium.gpu_bytes) / 1e6;
                if (scale == scene_scales.front()) last_effects[name + " " + row.path] = s.effects;
            }
            row.ms = median(ms), row.cpu = median(cpu), row.gpu = median(gpu), row.update = median(update),
            row.upload = median(upload);
            row.surface = median(surface), row.effects = median(effects), row.composite = median(composite);
            row.medium_gpu = median(medium_gpu);
            // Verify the last timed frame: finite, and the effects visibly there.
            double changed = 0.0;
            for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
                const glm::vec4 a = frame.pixels[i];
                if (!std::isfinite(a.r + a.g + a.b + a.a))
                    throw fx::Error("bench effects: " + name + " [" + row.path + "]: non-finite pixel");
                changed += std::abs(a.r - bare.pixels[i].r) + std::abs(a.g - bare.pixels[i].g);
            }
            if (!(changed > 1e-4 * double(frame.pixels.size())))
                throw fx::Error("bench effects: " + name + " [" + row.path + "]: the frame shows no effect");
            if (verify) {
                renderer.set_timing(false);
                renderer.set_terrain_drawn(false); // the same effect meshes (no time passes), alone
                renderer.set_background(glm::dvec3(0.0));
                const fx::Image alone = renderer.render_to_image(last_camera, w, h);
                // The scan-line reference of the same volumes as intersecting grids, each with the
                // model this path draws it with (one medium for the emission–absorption paths; the
                // two sorted paths draw the same, every volume absorbing).
                const fx::RenderPath model = path == fx::RenderPath::Absorption ? fx::RenderPath::AbsorptionExact : path;
                if (!references.count(model)) references[model] = terrain::render_scene_reference(renderer, last_camera, w, h);
                // Exact paths: the scan-line figures of the frame tests (≤ 0.05% of peak on average);
                // here a generous 1% so only a wrong picture fails. The classic paths (pcp's 8-bit
                // passes, absorption's per-cell vertex optics), and frames at a reduced
                // resolution or through the froxel grid (their detail blurred over a few pixels,
                // docs/accuracy.md): 10%. No pixel further off than the reference's peak. Classic
                // pcp against the reference clamped to its 8-bit target's range.
                const bool classic = path == fx::RenderPath::Pcp || path == fx::RenderPath::Absorption;
                const bool approximate = classic || scale < 1.0 || row.medium == "froxel";
                verify::Tolerance tol;
                tol.pixel.of_peak = 1.0, tol.mean.of_peak = approximate ? 0.10 : 0.01;
                tol.why = approximate ? "approximate path or resolution" : "exact path";
                verify::Options options;
                options.channels = 3, options.clamp_expected = path == fx::RenderPath::Pcp;
                row.error = verify::measure(alone, references[model], tol, options);
                row.verified = true;
                const std::string broken = verify::failures(row.error, tol);
                if (!broken.empty() || !(row.error.peak > 0.0))
                    throw fx::Error("bench effects: " + name + " [" + row.path +
                                    "]: the effects differ from the scan-line reference: " +
                                    (broken.empty() ? "the reference is blank" : broken));
            }
            print_row(row);
            rows.push_back(row);
            json.push_back(json_row(row));
        }
    }
    std::printf("\n  cells: drawn per frame (all effects); noise: samples evaluated per frame; ms/frame: wall time of\n"
                "  update + render to glFinish; cpu: CPU time of update and render on the calling thread (cellfx and the\n"
                "  driver's work there, waiting excluded; with GPU timing on: read the sample rows for a game's figure);\n"
                "  gpu: sum of the stages' GL_TIME_ELAPSED; update: LOD + effect simulation\n"
                "  (CPU); upload: set_mesh / set_scalars; surface / effects / composite: GPU ms (composite: over the\n"
                "  game's frame and the reduced layer's upsample); scale: the effects' resolution; medium: the method\n"
                "  that integrated overlapping volumes, its GPU ms and MB; mean / max %%: the effects alone against\n"
                "  the scan-line reference, in %% of its peak (pcp: against the reference clamped to 1).\n");
    std::printf("\n  last frame, per effect (pcp-exact where it ran):\n  %-12s %-14s %-12s %-11s %8s %8s %8s %9s %9s %9s\n",
                "scene", "effect", "type", "status", "cells", "built", "noise", "sim ms", "upload ms", "gpu ms");
    for (const std::string& name : scenes) {
        const auto it = last_effects.count(name + " pcp-exact") ? last_effects.find(name + " pcp-exact")
                                                                : last_effects.lower_bound(name + " ");
        if (it == last_effects.end()) continue;
        for (const terrain::EffectFrameStats& e : it->second)
            std::printf("  %-12s %-14s %-12s %-11s %8zu %8zu %8zu %9.3f %9.3f %9.2f\n", name.c_str(), e.name.c_str(),
                        e.type.c_str(), terrain::effect_status_name(e.status), e.cells_drawn, e.cells_built,
                        e.noise_samples, e.simulate_ms, e.upload_ms, e.gpu_ms);
    }
    // What a scalar-only update saves: the campfire's mesh re-uploaded whole (set_mesh: projector
    // geometry, planes, buffers) against its scalars alone (set_scalars: the point buffer).
    if (!parsed.has("only-samples")) {
        fx::Campfire fire;
        fx::EffectView view; // the default camera: the fire's mesh does not depend on it
        fire.update(view);
        fx::CellRenderer renderer(fire.mesh(), fire.scalar_name(), fx::TransferFunction::constant({1, 0.5, 0.2}, 1.0));
        std::vector<double> mesh_ms, scalar_ms;
        for (int k = 0; k < 9; ++k) {
            fire.update(fx::EffectView{view.camera, view.viewport_width, view.viewport_height, 0.1 * (k + 1)});
            auto t = std::chrono::steady_clock::now();
            renderer.set_mesh(fire.mesh(), fire.scalar_name());
            mesh_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
            t = std::chrono::steady_clock::now();
            renderer.set_scalars(fire.mesh().scalars[0].values);
            scalar_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
        }
        std::printf("\n  upload of the campfire's %zu cells after its noise moved (CPU time of the call, median of 9):\n"
                    "  set_mesh %.3f ms, set_scalars %.3f ms\n", fire.mesh().cell_count(), median(mesh_ms), median(scalar_ms));
    }
    if (!parsed.has("no-samples")) bench_samples(parsed, paths, frames, kWarmup, kDt);
    if (!parsed.has("only-samples")) bench_game_cpu(cpu_scenes, cpu_paths, frames, kWarmup, parsed, json);
    write_json();
    return 0;
}

} // namespace cellfx_cli
