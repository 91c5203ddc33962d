// `cellfx bench effects --only-cpu` (and the last table of the full bench): what a game's frame
// costs cellfx's CPU. Each shipped scene through cellfx::Module as a game calls it — update(),
// then render() over the game's RGBA8 frame with a DEPTH24 depth texture — at its render size,
// the camera flying: along the scene's camera path, 1/30 s a frame, or (scenes without one: the
// fog valley, the aurora) the eye sliding sideways by 1% of its distance to the target a frame,
// so the terrain LODs refine every frame.
//
// Per frame, on the game's thread (the thread CPU clock: time spent waiting is not counted):
//   cellfx CPU   update() and render() minus the GL driver's part: everything cellfx computes,
//                builds and copies, its uploads (the driver's copy of its data) included;
//   driver CPU   the GL calls that make the driver work on this thread (draws, dispatches,
//                clears, copies, queries, compiles: GlCallClock). A GPU's driver queues them;
//                llvmpipe runs each draw's vertex stage and binning here, so on llvmpipe this
//                grows with the cells drawn and says little about a GPU machine;
//   GL state     the driver's time in every other GL call (state, bindings, uniforms, queries of
//                state), and how many GL calls cellfx made: small each, many a frame.
// and the C++ allocations of the two calls (allocation_counter.hpp). Medians and 95th
// percentiles over the steady frames of the flight; allocations: the most any steady frame made.
//
// After the flight, what a game does now and then, each the frame it happens (warm frames around
// it, reported apart from the steady ones): the camera teleports across the scene, the window is
// resized (render at 3/4 size), an effect is switched off and on, the scene is reloaded. A
// change cellfx cannot apply in place falls back to rebuilding that effect, and these rows say
// what that costs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include "allocation_counter.hpp"
#include "bench_json.hpp"
#include "bench_support.hpp"
#include "cellfx/cellfx.hpp"
#include "fx/error.hpp"
#include "gl/state_guard.hpp"
#include "gl_call_clock.hpp"
#include "options.hpp"
#include "terrain/scene.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

using cellfx_samples::GlCallClock;

namespace {

// Warm-up frames of a flight: the first frames build whole, the next ones take the first
// incremental updates (whose compute programs the GL driver compiles on their first use).
constexpr int kFlightWarmup = 5;

// The p-th percentile (nearest rank) of the samples; 0 for none.
double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t rank = std::size_t(std::ceil(p / 100.0 * double(v.size())));
    return v[std::min(v.size() - 1, rank > 0 ? rank - 1 : 0)];
}

// Frame f of the flight (see the header comment).
fx::Camera flight_camera(const terrain::Scene& scene, int frame) {
    if (scene.camera_path) return scene.camera_path->at(1.0 + frame / 30.0, scene.camera);
    fx::Camera cam = scene.camera;
    const glm::dvec3 side = cam.right() * (0.01 * glm::length(cam.target - cam.eye));
    cam.eye += side * double(frame);
    cam.target += side * double(frame);
    return cam;
}

// A game's frame: RGBA8 colour and a DEPTH24 depth texture.
struct GameFrame {
    GLuint framebuffer = 0, color = 0, depth = 0;
    int width = 0, height = 0;
    GameFrame(int w, int h) : width(w), height(h) {
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glTextureStorage2D(color, 1, GL_RGBA8, w, h);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT24, w, h);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth, 0);
    }
    ~GameFrame() {
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
    }
    GameFrame(const GameFrame&) = delete;
    GameFrame& operator=(const GameFrame&) = delete;
    void clear() const {
        const GLfloat sky[4] = {0.5f, 0.6f, 0.7f, 1.0f};
        glClearNamedFramebufferfv(framebuffer, GL_COLOR, 0, sky);
        glClearNamedFramebufferfi(framebuffer, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    }
};

// One frame's figures.
struct FrameCost {
    double update_cpu = 0.0, render_cpu = 0.0, driver = 0.0, uploads = 0.0, state = 0.0;
    double measuring = 0.0; // what the clocks' reads added to update_cpu + render_cpu
    std::uint64_t allocations = 0, gl_calls = 0;
    double cellfx() const { return update_cpu + render_cpu - measuring - driver - state; }
};

// update() and render() of one frame, measured (the game's clears and glFinish are not).
FrameCost measured_frame(cellfx::Module& fx, const fx::Camera& camera, const GameFrame& frame) {
    frame.clear();
    GlCallClock::install(); // entry points first called in the frames before
    GlCallClock::reset();
    GlCallClock::set_running(true);
    FrameCost c;
    const std::uint64_t a0 = allocations_so_far();
    const double t0 = GlCallClock::thread_cpu_ms();
    fx.update(1.0 / 30.0, camera);
    const double t1 = GlCallClock::thread_cpu_ms();
    fx.render({frame.framebuffer, {0, 0, frame.width, frame.height}, frame.depth});
    const double t2 = GlCallClock::thread_cpu_ms();
    c.allocations = allocations_so_far() - a0;
    GlCallClock::set_running(false);
    c.update_cpu = t1 - t0;
    c.render_cpu = t2 - t1;
    c.driver = GlCallClock::driver_ms();
    c.uploads = GlCallClock::upload_ms();
    c.state = GlCallClock::state_ms();
    c.measuring = GlCallClock::overhead_ms() + 2.0 * GlCallClock::thread_clock_read_ms(); // t1, and t0's and t2's halves
    c.gl_calls = GlCallClock::calls();
    glFinish();
    return c;
}

struct Spread {
    double median = 0.0, p95 = 0.0;
};
Spread spread(const std::vector<double>& v) { return {median(v), percentile(v, 95.0)}; }

struct EventCost {
    std::string event;
    FrameCost cost;
};

struct FlightRow {
    std::string scene, path, size;
    int frames = 0;
    Spread cellfx, driver, update, uploads, state, gl_calls;
    std::uint64_t allocations = 0;            // the most of any steady frame (the second pass)
    std::uint64_t first_pass_allocations = 0; // the most of any frame after the warm-up of the first pass
    std::size_t prisms = 0;        // fog and aurora prisms of the last steady frame
    std::vector<GlCallClock::EntryPoint> gl_entry_points; // calls and ms summed over the steady frames
    std::vector<EventCost> events;
};

// The flight of one scene, every effect with `path` (empty: the scene's own paths).
FlightRow fly(const std::string& name, const std::string& path_name, int frames, int warmup, const ParsedArgs& parsed) {
    const std::string file = std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + name + ".json";
    terrain::Scene scene = terrain::load_scene(file);
    if (parsed.has("size")) parse_size(parsed.get("size"), scene.width, scene.height);
    const int w = scene.width, h = scene.height;
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, w, h));
    if (!path_name.empty()) {
        fx::RenderPath path;
        if (!fx::parse_render_path(path_name, path)) throw fx::Error("bench effects: unknown render path '" + path_name + "'");
        for (const std::string& e : fx.effect_names()) fx.set_path(e, path);
    }
    FlightRow row;
    row.scene = name;
    row.path = path_name.empty() ? "scene's own" : path_name;
    row.size = std::to_string(w) + "x" + std::to_string(h);
    row.frames = frames;
    GameFrame frame(w, h);
    std::vector<double> cellfx_ms, driver_ms, update_ms, upload_ms, state_ms, gl_calls;
    // The flight twice: the first pass is where storage grows to what the flight needs and the
    // driver compiles its shader variants (its allocations reported apart); the second is the
    // steady state a game sees once it has flown there.
    int f = 0;
    for (int pass = 0; pass < 2; ++pass) {
        for (f = 0; f < warmup + frames; ++f) {
            const FrameCost c = measured_frame(fx, flight_camera(scene, f), frame);
            if (pass == 0) {
                if (f >= warmup) row.first_pass_allocations = std::max(row.first_pass_allocations, c.allocations);
                continue;
            }
            if (f < warmup) continue;
            cellfx_ms.push_back(c.cellfx()), driver_ms.push_back(c.driver), update_ms.push_back(c.update_cpu),
                upload_ms.push_back(c.uploads), state_ms.push_back(c.state), gl_calls.push_back(double(c.gl_calls));
            row.allocations = std::max(row.allocations, c.allocations);
            const std::vector<GlCallClock::EntryPoint>& entry_points = GlCallClock::entry_points();
            row.gl_entry_points.resize(entry_points.size(), GlCallClock::EntryPoint{"", false, 0, 0.0});
            for (std::size_t k = 0; k < entry_points.size(); ++k) {
                row.gl_entry_points[k].name = entry_points[k].name, row.gl_entry_points[k].state = entry_points[k].state;
                row.gl_entry_points[k].calls += entry_points[k].calls, row.gl_entry_points[k].ms += entry_points[k].ms;
            }
            row.prisms = fx.stats().fog_prisms.prisms + fx.stats().aurora_prisms.prisms;
        }
    }
    row.cellfx = spread(cellfx_ms), row.driver = spread(driver_ms), row.update = spread(update_ms),
    row.uploads = spread(upload_ms), row.state = spread(state_ms), row.gl_calls = spread(gl_calls);

    // The events, each followed by two frames back on the flight.
    auto event = [&](const std::string& what, const fx::Camera& camera, const GameFrame& target) {
        row.events.push_back({what, measured_frame(fx, camera, target)});
        for (int k = 0; k < 2; ++k, ++f) measured_frame(fx, flight_camera(scene, f), frame);
    };
    {
        // Across the scene: the camera path 10 s on, or the eye moved by the terrain's extent.
        fx::Camera far_away = scene.camera_path ? scene.camera_path->at(11.0 + f / 30.0, scene.camera) : flight_camera(scene, f);
        if (!scene.camera_path) {
            const double jump = scene.has_terrain() ? 0.5 * scene.ground.extent() : 100.0;
            const glm::dvec3 side = far_away.right();
            far_away.eye -= side * jump, far_away.target -= side * jump;
        }
        event("teleport", far_away, frame);
        event("teleport back", flight_camera(scene, f), frame);
    }
    {
        const GameFrame smaller(3 * w / 4, 3 * h / 4);
        event("resize", flight_camera(scene, f), smaller);
        event("resize back", flight_camera(scene, f), frame);
    }
    {
        const std::string first = fx.effect_names().front();
        fx.set_enabled(first, false);
        event("'" + first + "' off", flight_camera(scene, f), frame);
        fx.set_enabled(first, true);
        event("'" + first + "' on", flight_camera(scene, f), frame);
    }
    fx.reload(file);
    event("reload", flight_camera(scene, f), frame);
    return row;
}

BenchJsonRow spread_json(const Spread& s) {
    BenchJsonRow j;
    j["median"] = s.median;
    j["p95"] = s.p95;
    return j;
}

BenchJsonRow row_json(const FlightRow& r) {
    BenchJsonRow events = BenchJsonRow::array();
    for (const EventCost& e : r.events) {
        BenchJsonRow event;
        event["event"] = e.event;
        event["cellfx_cpu_ms"] = e.cost.cellfx();
        event["driver_cpu_ms"] = e.cost.driver;
        event["gl_state_ms"] = e.cost.state;
        event["allocations"] = e.cost.allocations;
        events.push_back(event);
    }
    BenchJsonRow j;
    j["scene"] = r.scene;
    j["path"] = r.path;
    j["size"] = r.size;
    j["frames"] = r.frames;
    j["cellfx_cpu_ms"] = spread_json(r.cellfx);
    j["driver_cpu_ms"] = spread_json(r.driver);
    j["update_cpu_ms"] = spread_json(r.update);
    j["upload_cpu_ms"] = spread_json(r.uploads);
    j["gl_state_ms"] = spread_json(r.state);
    j["gl_calls_per_frame"] = spread_json(r.gl_calls);
    j["allocations_per_frame"] = r.allocations;
    j["first_pass_allocations_per_frame"] = r.first_pass_allocations;
    j["prisms"] = r.prisms;
    j["events"] = events;
    return j;
}

} // namespace

void bench_game_cpu(const std::vector<std::string>& scenes, const std::vector<std::string>& paths, int frames, int warmup,
                    const ParsedArgs& parsed, std::vector<BenchJsonRow>& json) {
    std::printf("\n  CPU per frame in a game: cellfx::Module update + render over a game's RGBA8 + DEPTH24 frame, the\n"
                "  camera flying, thread CPU ms (waiting excluded), median / 95th percentile of %d steady frames after\n"
                "  %d warm-up frames, on a second pass over the flight\n",
                frames, std::max(warmup, kFlightWarmup));
    std::printf("  %-17s %-12s %9s %15s %15s %13s %13s %13s %8s %7s %9s %8s\n", "scene", "path", "size", "cellfx cpu",
                "driver cpu", "GL state", "update cpu", "uploads", "GL calls", "allocs", "1st pass", "prisms");
    std::vector<FlightRow> rows;
    const std::vector<std::string> own = {""};
    for (const std::string& name : scenes) {
        for (const std::string& path : paths.empty() ? own : paths) {
            FlightRow r = fly(name, path, frames, std::max(warmup, kFlightWarmup), parsed);
            std::printf("  %-17s %-12s %9s %7.3f /%6.3f %7.3f /%6.3f %6.3f /%5.3f %6.3f /%5.3f %6.3f /%5.3f %8.0f %7llu %9llu %8zu\n",
                        r.scene.c_str(), r.path.c_str(), r.size.c_str(), r.cellfx.median, r.cellfx.p95, r.driver.median,
                        r.driver.p95, r.state.median, r.state.p95, r.update.median, r.update.p95, r.uploads.median,
                        r.uploads.p95, r.gl_calls.median,
                        static_cast<unsigned long long>(r.allocations),
                        static_cast<unsigned long long>(r.first_pass_allocations), r.prisms);
            std::fflush(stdout);
            rows.push_back(std::move(r));
        }
    }
    std::printf("\n  events (each one frame, after the flight): cellfx cpu / driver cpu (GL state included) ms, allocations\n");
    for (const FlightRow& r : rows) {
        std::printf("  %-17s %-12s", r.scene.c_str(), r.path.c_str());
        for (const EventCost& e : r.events)
            std::printf("  %s %.2f/%.2f/%llu", e.event.c_str(), e.cost.cellfx(), e.cost.driver + e.cost.state,
                        static_cast<unsigned long long>(e.cost.allocations));
        std::printf("\n");
    }
    // The one state save and restore a frame makes (fx::gl::StateGuard), timed alone.
    std::vector<double> guard;
    for (int k = 0; k < 9; ++k) {
        const double c0 = GlCallClock::thread_cpu_ms();
        for (int i = 0; i < 100; ++i) {
            fx::gl::StateGuard g;
            fx::gl::StateGuard::set_render_defaults();
        }
        guard.push_back((GlCallClock::thread_cpu_ms() - c0) / 100.0);
    }
    if (parsed.has("gl-calls")) {
        // Where the driver's time goes, per GL entry point: a list to read when a frame makes
        // more GL calls than it should.
        for (const FlightRow& r : rows) {
            std::vector<GlCallClock::EntryPoint> e = r.gl_entry_points;
            std::sort(e.begin(), e.end(), [](const auto& a, const auto& b) { return a.ms > b.ms; });
            std::printf("\n  GL calls per steady frame, %s (%s): calls, microseconds, kind\n", r.scene.c_str(), r.path.c_str());
            for (const GlCallClock::EntryPoint& x : e)
                if (x.calls > 0)
                    std::printf("    %-34s %8.1f %9.1f  %s\n", x.name, double(x.calls) / r.frames, 1e3 * x.ms / r.frames,
                                x.state ? "state" : "driver work / upload");
        }
    }
    std::printf("  cellfx cpu: update + render minus the driver's calls (uploads, the driver's copy of cellfx's data,\n"
                "  included); driver cpu: draws, dispatches, clears, copies, queries on the game's thread (llvmpipe runs\n"
                "  the vertex stage there; a GPU's driver does not); GL state: the driver's time in cellfx's other GL\n"
                "  calls (state, bindings, uniforms; the monotonic clock); GL calls: every GL call of update + render\n"
                "  (--gl-calls lists them); update cpu: update() alone (no GL); uploads: the\n"
                "  buffer and texture writes; allocs: the most C++ allocations (cellfx's and the driver's) of any steady\n"
                "  frame; 1st pass: the same over the first pass of the flight (storage growing to what the flight\n"
                "  needs, the driver compiling shader variants); prisms: fog and aurora prisms drawn. The frame's GL\n"
                "  state save + restore (StateGuard): %.3f ms.\n",
                median(guard));
    for (const FlightRow& r : rows) json.push_back(row_json(r));
}

} // namespace cellfx_cli
