// Based on: Röttger, Heidrich, Slusallek & Seidel 1998 (continuous LOD) and Roettger & Ertl
// 2003, §5 (ground fog as prisms).
//
// `cellfx bench terrain`: three parts, all measured side by side in one run.
//   1. LOD along a fixed flight: for 1025² and 2049² procedural height fields (with a valley fog
//      layer driving refinement), triangles per frame and LOD update milliseconds per frame at
//      several screen-space error bounds, against the full-resolution triangle count; nodes
//      re-examined per frame (the incremental update's work) and a rebuild from the root for
//      comparison; geomorphed vertices per second.
//   2. Pixels changed: the terrain surface at 1024x768 (--size) rendered from the LOD and from the full-
//      resolution mesh, the fraction of pixels whose 8-bit colour differs (Lindstrom et al.'s
//      measure), with the polygon reduction.
//   3. The fog valley (content/scenes/fog_valley.json) at 1024x768 (--size): milliseconds and frames per
//      second for each render path along a short camera move, verified after timing.
// The paper figures (libMini ~20 M geomorphed vertices/s on 2004 hardware; Lindstrom et al. 100x
// fewer polygons at < 5% pixels changed; Roettger & Ertl ~25 Hz PCP / > 50 Hz MIP fog at
// 512x384 on 2003 hardware) are printed beside ours.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "options.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

constexpr double kFov = 60.0;
constexpr double kSpacing = 10.0; // metres between samples

// Mountains of fBm (10 octaves) over the whole field, ~1.2 km of relief.
terrain::HeightField mountains(int size) {
    terrain::NoiseSpec n;
    n.amplitude = 900.0;
    n.offset = 600.0;
    n.frequency = 1.0 / 3000.0;
    n.octaves = 10;
    n.gain = 0.5;
    n.seed = 11;
    const terrain::HeightGenerator g = terrain::make_noise_generator(n);
    return terrain::make_height_field(size, kSpacing, g);
}

// The flight: 10 m per frame along a gentle S-curve across the middle of the field, 150 m above
// the ground below (a fast, low pass: 600 m/s at 60 Hz), looking ahead and down.
fx::Camera flight(const terrain::HeightField& ground, int frame, int frames) {
    const double extent = ground.extent();
    const double s = double(frame) / std::max(frames - 1, 1);
    const double length = 10.0 * frames;
    auto at = [&](double u) {
        const double x = 0.5 * extent - 0.5 * length + length * u;
        const double y = 0.5 * extent + 0.12 * extent * std::sin(6.2832 * u);
        return glm::dvec2(x, y);
    };
    const glm::dvec2 p = at(s), dir = glm::normalize(at(s + 1e-3) - at(s - 1e-3));
    fx::Camera cam;
    cam.eye = {p.x, p.y, ground.sample(p.x, p.y) + 150.0};
    cam.target = {p.x + 1000.0 * dir.x, p.y + 1000.0 * dir.y, ground.sample(p.x, p.y) - 150.0};
    cam.up = {0, 0, 1};
    cam.fov_y_degrees = kFov;
    cam.near_distance = 1.0;
    cam.far_distance = 4.0 * extent;
    return cam;
}

struct LodRow {
    int size;
    double tau;
    double triangles_mean, triangles_max;
    double update_ms_mean, update_ms_max, rebuild_ms;
    double live, examined, woken, morphing;
    double morphed_per_s, output_vertices_per_s;
};

void bench_lod(int size, const std::vector<double>& bounds, int frames, int width, int height) {
    auto t = Clock::now();
    const terrain::HeightField ground = mountains(size);
    const double build_field_ms = ms_since(t);
    const terrain::HeightField fog = terrain::make_valley_fog_map(ground, -40.0, 200.0, {}, 1500.0);
    t = Clock::now();
    terrain::ContinuousLod lod(ground, fog);
    const double d2_ms = ms_since(t);
    std::printf("\n%dx%d height field (%.1f km, %.0f m relief, fBm), fog layer %s; field %.0f ms, d2 %.0f ms, LOD state %.0f MB\n",
                size, size, ground.extent() / 1000.0, double(ground.max_height() - ground.min_height()),
                "valley fog up to 200 m", build_field_ms, d2_ms, double(lod.memory_bytes()) / 1e6);
    std::printf("  full resolution: %zu triangles. %d frames, 10 m per frame, 150 m above the ground, %dx%d, %.0f deg fov\n",
                lod.full_resolution_triangles(), frames, width, height, kFov);
    std::printf("  %6s %10s %10s %9s %9s %8s %10s %9s %9s %8s %9s %10s %10s\n", "tau px", "tris mean", "tris max",
                "reduction", "update ms", "max ms", "rebuild ms", "live", "examined", "woken", "morphing", "morph v/s",
                "mesh v/s");
    for (double tau : bounds) {
        lod.reset();
        LodRow r{size, tau, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
        double morphed = 0.0, update_ms = 0.0, out_vertices = 0.0, extract_ms = 0.0;
        std::vector<double> rebuilds;
        terrain::LodMesh mesh;
        for (int f = 0; f < frames; ++f) {
            const fx::Camera cam = flight(ground, f, frames);
            const terrain::LodStats s = lod.update(terrain::LodView::from_camera(cam, height, tau));
            if (f == 0) continue; // the first frame builds from the root
            r.triangles_mean += double(s.triangles);
            r.triangles_max = std::max(r.triangles_max, double(s.triangles));
            update_ms += s.milliseconds;
            r.update_ms_max = std::max(r.update_ms_max, s.milliseconds);
            r.live += double(s.live_nodes);
            r.examined += double(s.nodes_examined);
            r.woken += double(s.nodes_woken);
            r.morphing += double(s.morphing_nodes);
            morphed += double(s.vertices_morphed);
            const auto te = Clock::now();
            lod.extract(mesh);
            extract_ms += ms_since(te);
            out_vertices += double(mesh.positions.size());
            if (f % (frames / 6 + 1) == 0) { // a rebuild from the root at the same eye, for comparison
                terrain::ContinuousLod fresh(ground, fog);
                rebuilds.push_back(fresh.update(terrain::LodView::from_camera(cam, height, tau)).milliseconds);
            }
        }
        const double n = frames - 1;
        r.triangles_mean /= n;
        r.update_ms_mean = update_ms / n;
        r.rebuild_ms = median(rebuilds);
        r.live /= n, r.examined /= n, r.woken /= n, r.morphing /= n;
        r.morphed_per_s = morphed / (update_ms * 1e-3);
        r.output_vertices_per_s = out_vertices / ((update_ms + extract_ms) * 1e-3);
        std::printf("  %6.2f %10.0f %10.0f %8.0fx %9.3f %8.2f %10.2f %9.0f %9.0f %8.0f %9.0f %9.2fM %9.2fM\n", tau,
                    r.triangles_mean, r.triangles_max, double(lod.full_resolution_triangles()) / r.triangles_mean,
                    r.update_ms_mean, r.update_ms_max, r.rebuild_ms, r.live, r.examined, r.woken, r.morphing,
                    r.morphed_per_s / 1e6, r.output_vertices_per_s / 1e6);
        if (!(r.triangles_mean > 0.0)) throw fx::Error("bench terrain: the LOD produced no triangles");
    }
}

// Fraction of pixels whose 8-bit colour differs between two frames by more than `levels`
// (0: any difference at all).
double changed_fraction(const fx::Image& a, const fx::Image& b, int levels) {
    auto eight_bit = [](fx::Image image) {
        for (glm::vec4& p : image.pixels) p = glm::round(glm::clamp(p, 0.0f, 1.0f) * 255.0f) / 255.0f;
        return image;
    };
    verify::Tolerance t;
    t.pixel.absolute = (levels + 0.5) / 255.0; // whole steps apart: more than `levels` of them
    verify::Options rgb;
    rgb.channels = 3;
    return verify::measure(eight_bit(a), eight_bit(b), t, rgb).share_beyond();
}

void bench_pixels(int size, const std::vector<double>& bounds, int views, int frames, int width, int height) {
    terrain::Scene scene;
    scene.ground = mountains(size);
    scene.camera = flight(scene.ground, 0, frames);
    std::printf("\n%dx%d: terrain surface at %dx%d, LOD against full resolution (%d views along the flight)\n", size,
                size, width, height, views);
    std::printf("  %6s %12s %10s %16s %12s %18s\n", "tau px", "triangles", "reduction", "pixels changed", "worst view",
                "changed > 8/255");
    std::vector<fx::Image> full;
    std::vector<fx::Camera> cams;
    std::size_t full_triangles = 0;
    {
        terrain::SceneRenderer renderer(scene);
        renderer.set_pixel_error(1e-9); // every sample
        for (int v = 0; v < views; ++v) {
            cams.push_back(flight(scene.ground, v * (frames - 1) / std::max(views - 1, 1), frames));
            terrain::FrameStats s;
            full.push_back(renderer.render_to_image(cams.back(), width, height, &s));
            full_triangles = s.terrain_lod.triangles;
        }
    }
    for (double tau : bounds) {
        terrain::SceneRenderer renderer(scene);
        renderer.set_pixel_error(tau);
        double changed = 0.0, worst = 0.0, triangles = 0.0, clearly = 0.0;
        for (int v = 0; v < views; ++v) {
            terrain::FrameStats s;
            const fx::Image image = renderer.render_to_image(cams[v], width, height, &s);
            const double c = changed_fraction(image, full[v], 0);
            changed += c / views;
            worst = std::max(worst, c);
            clearly += changed_fraction(image, full[v], 8) / views;
            triangles += double(s.terrain_lod.triangles) / views;
        }
        std::printf("  %6.2f %12.0f %9.0fx %15.2f%% %11.2f%% %17.2f%%\n", tau, triangles,
                    double(full_triangles) / triangles, 100.0 * changed, 100.0 * worst, 100.0 * clearly);
    }
}

void bench_fog_valley(int frames, int width, int height) {
    const std::string path = std::string(CELLFX_SOURCE_DIR) + "/content/scenes/fog_valley.json";
    const terrain::Scene scene = terrain::load_scene(path);
    std::printf("\nfog valley (%s) at %dx%d: %d frames per path, the camera moving 3 m per frame\n",
                "content/scenes/fog_valley.json", width, height, frames);
    std::printf("  %-10s %9s %9s %10s %9s %9s %9s %9s %9s %8s\n", "path", "ms/frame", "fps", "LOD ms", "prisms ms",
                "upload ms", "draw ms", "triangles", "prisms", "caps");
    // Reference without fog: the fog must change the picture (verified after timing).
    terrain::Scene bare = scene;
    bare.fog.reset();
    fx::Image no_fog;
    {
        terrain::SceneRenderer r(bare);
        no_fog = r.render_to_image(scene.camera, width, height);
    }
    for (fx::RenderPath p : fx::kRenderPaths) {
        terrain::SceneRenderer renderer(scene);
        renderer.set_fog_path(p);
        renderer.render_to_image(scene.camera, width, height); // warm-up: first-frame LOD build, programs
        std::vector<double> frame_ms, lod, mesh, upload, draw;
        terrain::FrameStats last;
        fx::Image image;
        for (int f = 0; f < frames; ++f) {
            fx::Camera cam = scene.camera;
            cam.eye.x += 3.0 * (f + 1);
            cam.target.x += 3.0 * (f + 1);
            image = renderer.render_to_image(cam, width, height, &last);
            frame_ms.push_back(last.frame_ms);
            lod.push_back(last.lod_ms), mesh.push_back(last.mesh_ms), upload.push_back(last.upload_ms),
                draw.push_back(last.draw_ms);
        }
        // Verify after timing: finite, opaque, and the fog visibly there.
        double difference = 0.0;
        for (std::size_t i = 0; i < image.pixels.size(); ++i) {
            const glm::vec4 a = image.pixels[i];
            if (!std::isfinite(a.r + a.g + a.b + a.a)) throw fx::Error("bench terrain: non-finite pixel in the fog valley");
            difference += std::abs(a.r - no_fog.pixels[i].r);
        }
        if (!(difference > 1e-3 * double(image.pixels.size())))
            throw fx::Error(std::string("bench terrain: the fog valley shows no fog with path ") + fx::render_path_name(p));
        const double ms = median(frame_ms);
        std::printf("  %-10s %9.1f %9.2f %10.2f %9.2f %9.2f %9.1f %9zu %9zu %8zu\n", fx::render_path_name(p), ms,
                    1000.0 / ms, median(lod), median(mesh), median(upload), median(draw), last.terrain_lod.triangles,
                    last.fog_prisms.prisms, last.fog.caps);
    }
}

} // namespace

int bench_terrain(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"skip-lod", "skip-pixels", "skip-fps"});
    require_known(parsed, {"skip-lod", "skip-pixels", "skip-fps", "lod-frames", "frames", "views", "sizes", "size"});
    if (!parsed.positional.empty()) throw fx::Error("bench terrain: unexpected argument '" + parsed.positional[0] + "'");
    const int lod_frames = int_option(parsed, "bench terrain", "lod-frames", 300);
    const int frames = int_option(parsed, "bench terrain", "frames", 5);
    const int views = int_option(parsed, "bench terrain", "views", 3);
    int width = 1024, height = 768; // the screen the LOD refines for and the frames' size
    if (parsed.has("size")) parse_size(parsed.get("size"), width, height);
    const std::vector<int> sizes = int_list_option(parsed, "bench terrain", "sizes", "1025,2049");
    for (const int s : sizes)
        if (!terrain::is_lod_size(s)) throw fx::Error("bench terrain --sizes: " + std::to_string(s) + " is not 2^n + 1");
    const std::vector<double> bounds = {1.0, 2.0, 4.0, 8.0};

    const fx::HeadlessContext context;
    std::printf("terrain: continuous LOD (Roettger et al. 1998), ground fog as prisms (Roettger & Ertl 2003 §5)\n");
    std::printf("  gl: %s\n", context.description().c_str());
    std::printf("  paper figures: libMini ~20 M geomorphed vertices/s (2004 hardware); Lindstrom et al. 1996 100x\n"
                "  fewer polygons at < 5%% of pixels changed; Roettger & Ertl ~25 Hz PCP fog (Yukon), > 50 Hz MIP fog\n"
                "  at 512x384 (2003 hardware). Ours follow, measured in this run.\n");
    if (!parsed.has("skip-lod"))
        for (int s : sizes) bench_lod(s, bounds, lod_frames, width, height);
    if (!parsed.has("skip-pixels"))
        for (int s : sizes) bench_pixels(s, bounds, s > 1025 ? 1 : views, lod_frames, width, height);
    if (!parsed.has("skip-fps")) bench_fog_valley(frames, width, height);
    std::printf("\n  morph v/s: vertex heights geomorphed per second of LOD update; mesh v/s: LOD mesh vertices\n"
                "  produced per second of update + extraction. live/examined/woken/morphing: nodes per frame\n"
                "  (live: the active quadtree; examined: looked at, = woken + morphing + new children).\n");
    return 0;
}

} // namespace cellfx_cli
