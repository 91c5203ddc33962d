// `cellfx bench flicker`: how much the effects at a reduced resolution (Scene::fx_scale) change
// from frame to frame along depth edges, against full resolution — flicker is what players
// notice first. A flight of --frames frames 1/30 s apart along the scene's camera path (the
// night valley's by default: fog, fire, smoke and a sweeping beam over the terrain), each frame
// whole (terrain drawn), once per scale. Per frame pair, the mean absolute change of the
// displayed colour (RGB, linear) over the pixels on a depth edge of either frame (a 4-neighbour
// whose view depth differs by more than 10%: the terrain's silhouettes against the sky and
// against farther ground), and over the others for comparison. Per scale: the mean of those
// per-pair figures (the flight's change per frame) and their median, and both against full
// resolution's. The camera moves and the fire, smoke and beam are animated, so part of the
// change is real: it is the same at every scale, and what a reduced scale adds shows as a ratio
// above 1.
//
// Options: --scene FILE (content/scenes/fog_valley_night.json), --frames N (60), --time T (the
//          flight's start on the scene clock, 0), --size WxH (the scene's), --fx-scale a,b,c
//          (1,0.5,0.25), --medium froxel|exact (the scene's), --disable a,b (effects switched
//          off), --json FILE (a row per scale).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_json.hpp"
#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "options.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_renderer.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

// View depth of window depth w (the camera's standard projection).
double view_depth(const fx::Camera& cam, double w) {
    const double n = cam.near_distance, f = cam.far_distance;
    return cam.orthographic() ? n + w * (f - n) : n * f / (f * (1.0 - w) + w * n);
}

// Pixels on a depth edge: a 4-neighbour whose view depth differs by more than 10%.
std::vector<bool> depth_edges(const fx::Image& depth, const fx::Camera& cam) {
    const int w = depth.width, h = depth.height;
    std::vector<double> z(std::size_t(w) * std::size_t(h));
    for (std::size_t i = 0; i < z.size(); ++i) z[i] = view_depth(cam, depth.pixels[i].r);
    std::vector<bool> edge(z.size(), false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double a = z[std::size_t(y) * w + x];
            const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
            for (int k = 0; k < 4; ++k) {
                if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
                const double b = z[std::size_t(ny[k]) * w + nx[k]];
                if (std::abs(a - b) > 0.1 * std::min(a, b)) edge[std::size_t(y) * w + x] = true;
            }
        }
    return edge;
}

struct Flight {
    std::vector<double> edge, other; // per frame pair: mean |change| on and off depth edges
    double edge_fraction = 0.0;      // of the pixels, mean over frames
    double ms = 0.0;                 // median ms per frame
};

Flight fly(const terrain::Scene& scene, double scale, int frames, double start, double dt,
           const std::vector<std::string>& disabled) {
    terrain::SceneRenderer renderer(scene);
    renderer.set_fx_scale(scale);
    for (const std::string& name : disabled) renderer.set_enabled(name, false);
    Flight flight;
    fx::Image previous;
    std::vector<bool> previous_edges;
    std::vector<double> ms;
    for (int f = 0; f < frames; ++f) {
        const double t = start + f * dt;
        renderer.set_time(t);
        const fx::Camera cam = scene.camera_path ? scene.camera_path->at(t, scene.camera) : scene.camera;
        const auto t0 = Clock::now();
        const fx::Image frame = renderer.render_to_image(cam, scene.width, scene.height);
        ms.push_back(ms_since(t0));
        std::vector<bool> edges = depth_edges(renderer.depth_image(), cam);
        std::size_t on = 0;
        for (bool e : edges) on += e;
        flight.edge_fraction += double(on) / double(edges.size()) / frames;
        if (f > 0) {
            // Mean |change| in RGB over the pixels on a depth edge in either frame, and off them.
            std::vector<std::uint8_t> skip_off_edge(frame.pixels.size()), skip_on_edge(frame.pixels.size());
            for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
                skip_on_edge[i] = edges[i] || previous_edges[i];
                skip_off_edge[i] = !skip_on_edge[i];
            }
            verify::Options o;
            o.channels = 3;
            o.skip = &skip_off_edge;
            const verify::Difference edge = verify::measure(frame, previous, o);
            o.skip = &skip_on_edge;
            const verify::Difference other = verify::measure(frame, previous, o);
            flight.edge.push_back(edge.compared ? edge.mean : 0.0);
            flight.other.push_back(other.compared ? other.mean : 0.0);
        }
        for (const glm::vec4& p : frame.pixels)
            if (!std::isfinite(p.r + p.g + p.b)) throw fx::Error("bench flicker: a frame at scale " + std::to_string(scale) + " is not finite");
        previous = frame;
        previous_edges = std::move(edges);
    }
    flight.ms = median(ms);
    return flight;
}

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / double(v.size());
}

} // namespace

int bench_flicker(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"scene", "frames", "time", "size", "fx-scale", "medium", "disable", "json"});
    if (!parsed.positional.empty()) throw fx::Error("bench flicker: unexpected argument '" + parsed.positional[0] + "'");
    const std::string file = parsed.get("scene", std::string(CELLFX_SOURCE_DIR) + "/content/scenes/fog_valley_night.json");
    terrain::Scene scene = terrain::load_scene(file);
    if (parsed.has("size")) parse_size(parsed.get("size"), scene.width, scene.height);
    if (parsed.has("medium")) scene.medium = parse_medium_option(parsed.get("medium"));
    const int frames = int_option(parsed, "bench flicker", "frames", 60);
    const std::string json_file = output_file_option(parsed, "json", {}, false); // tried before the work
    const double start = number_option(parsed, "bench flicker", "time", 0.0);
    std::vector<double> scales;
    for (const std::string& item : split_list(parsed.get("fx-scale", "1,0.5,0.25"))) scales.push_back(parse_fx_scale(item));
    if (scales.empty()) throw fx::Error("bench flicker: --fx-scale lists no scale");
    constexpr double kDt = 1.0 / 30.0;

    const fx::HeadlessContext context;
    std::printf("flicker: frame-to-frame change along depth edges at each fx scale\n  gl: %s\n", context.description().c_str());
    std::printf("  %s, %dx%d, %d frames %.0f ms apart from t = %g s, medium %s (where volumes overlap)\n", file.c_str(),
                scene.width, scene.height, frames, 1000.0 * kDt, start, fx::medium_method_name(scene.medium));
    std::printf("\n  %-8s %10s %12s %12s %12s %12s %10s %12s %10s\n", "fx scale", "edge px %", "edge mean", "edge median",
                "other mean", "other median", "edge vs 1", "median vs 1", "ms/frame");
    std::vector<BenchJsonRow> json;
    double full_mean = -1.0, full_median = -1.0;
    for (double scale : scales) {
        const Flight f = fly(scene, scale, frames, start, kDt, split_list(parsed.get("disable")));
        const double edge = mean(f.edge), edge_median = median(f.edge);
        if (scale == 1.0) full_mean = edge, full_median = edge_median;
        const double ratio = full_mean > 0.0 ? edge / full_mean : NAN, median_ratio = full_median > 0.0 ? edge_median / full_median : NAN;
        std::printf("  %-8g %10.2f %12.3e %12.3e %12.3e %12.3e %10.3f %12.3f %10.1f\n", scale, 100.0 * f.edge_fraction, edge,
                    edge_median, mean(f.other), median(f.other), ratio, median_ratio, f.ms);
        std::fflush(stdout);
        BenchJsonRow row;
        row["scene"] = file;
        row["fx_scale"] = scale;
        row["medium"] = fx::medium_method_name(scene.medium);
        row["frames"] = frames;
        row["edge_pixels_percent"] = 100.0 * f.edge_fraction;
        row["edge_change_mean"] = edge;
        row["edge_change_median"] = edge_median;
        row["other_change_mean"] = mean(f.other);
        row["other_change_median"] = median(f.other);
        if (std::isfinite(ratio)) row["edge_change_vs_full"] = ratio, row["edge_median_vs_full"] = median_ratio;
        row["ms_per_frame"] = f.ms;
        json.push_back(row);
    }
    std::printf("\n  change: mean |Δ| of the displayed colour between consecutive frames (RGB, linear, 1 = white) over\n"
                "  the pixels on a depth edge of either frame (edge) and over the rest (other), the mean and the\n"
                "  median over the frame pairs; vs 1: against full resolution's (list 1 first for them).\n");
    if (!json_file.empty()) {
        write_scenes_json(json_file, json);
        std::printf("  wrote %s\n", json_file.c_str());
    }
    return 0;
}

} // namespace cellfx_cli
