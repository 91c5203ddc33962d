// A steady frame costs the game's heap and threads nothing: for every shipped scene and render
// path, cellfx::Module::update() and render() with a moving camera, after warm-up frames, are
// counted by a replaced global operator new (every C++ allocation in the process) and an
// interposed pthread_create (every thread started, std::thread included). Its own executable
// (fx_budget_tests), so that the replaced allocator counts nothing else. Mesa's own memory is
// C's malloc, which is not counted: the point is cellfx's.
//
// update() and render() must allocate nothing and start nothing on every scene and path: new
// scalars every frame (campfire, lasers: CellRenderer::set_scalars) and meshes changed every
// frame (fog and aurora prisms: CellRenderer::update_mesh, whose absorption paths rebuild their
// sorts' state in place) included. fx::CellRenderer on its own (every path, tetrahedra and mixed
// cells, inside and outside the mesh, with and without a scene depth) is held to 0 by the last
// case.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include <dlfcn.h>
#include <execinfo.h>
#include <pthread.h>

#include "cellfx/cellfx.hpp"
#include "fx/cell_renderer.hpp"
#include "mesh/tetrahedralize.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace {

std::atomic<bool> counting{false};
std::atomic<std::uint64_t> allocations{0}, threads_started{0};

// CELLFX_BUDGET_TRACE=<scene>[:<path>]: runs only that scene (and path) and prints a backtrace on
// stderr for every allocation counted in its measured frames (addr2line -C -f -e fx_budget_tests
// ADDRESS names the frames).
std::atomic<bool> tracing{false};

void trace_allocation() {
    tracing = false; // backtrace() may allocate on its first call
    void* frames[32];
    backtrace_symbols_fd(frames, backtrace(frames, 32), 2);
    std::fputs("----\n", stderr);
    tracing = true;
}

void* counted(std::size_t size) {
    if (counting.load(std::memory_order_relaxed)) {
        allocations.fetch_add(1, std::memory_order_relaxed);
        if (tracing.load(std::memory_order_relaxed)) trace_allocation();
    }
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}

void* counted_aligned(std::size_t size, std::align_val_t align) {
    if (counting.load(std::memory_order_relaxed)) {
        allocations.fetch_add(1, std::memory_order_relaxed);
        if (tracing.load(std::memory_order_relaxed)) trace_allocation();
    }
    const std::size_t a = std::max(std::size_t(align), sizeof(void*));
    if (void* p = std::aligned_alloc(a, (std::max<std::size_t>(size, 1) + a - 1) / a * a)) return p;
    throw std::bad_alloc();
}

} // namespace

void* operator new(std::size_t size) { return counted(size); }
void* operator new[](std::size_t size) { return counted(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return counted(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    try {
        return counted(size);
    } catch (...) {
        return nullptr;
    }
}
void* operator new(std::size_t size, std::align_val_t align) { return counted_aligned(size, align); }
void* operator new[](std::size_t size, std::align_val_t align) { return counted_aligned(size, align); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

// Every thread the process starts passes here (std::thread calls pthread_create).
extern "C" int pthread_create(pthread_t* thread, const pthread_attr_t* attr, void* (*start)(void*), void* arg) {
    using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);
    static const Create real = reinterpret_cast<Create>(dlsym(RTLD_NEXT, "pthread_create"));
    if (counting.load(std::memory_order_relaxed)) threads_started.fetch_add(1, std::memory_order_relaxed);
    return real(thread, attr, start, arg);
}

namespace {

constexpr int kW = 160, kH = 120;
// The camera sweeps back and forth over kPoses poses, one step per frame, the simulation's
// clock running on: two sweeps there and back warm up (buffers and lists grow to what these
// views need, programs link, sorts build their state), the third is counted. A steady frame is
// one that needs no more room than a frame before it; a camera that keeps finding larger views
// grows storage geometrically, which is not counted here.
constexpr int kPoses = 6, kSweep = 2 * (kPoses - 1), kWarmup = 2 * kSweep, kMeasured = kSweep;
int pose_of_frame(int frame) {
    const int f = frame % kSweep;
    return f < kPoses ? f : kSweep - f;
}

struct Count {
    std::uint64_t allocations = 0, threads = 0;
};

template <class F>
Count count(F&& f) {
    const std::uint64_t a = allocations.load(), t = threads_started.load();
    counting = true;
    f();
    counting = false;
    return {allocations.load() - a, threads_started.load() - t};
}

// Pose `frame`: 1/30 s apart along the scene's camera path, or the eye moving sideways by 1% of
// its distance to the target per pose (the terrain LODs refine, the fog and aurora rebuild).
fx::Camera moving_camera(const terrain::Scene& scene, int frame) {
    if (scene.camera_path) return scene.camera_path->at(frame / 30.0, scene.camera);
    fx::Camera cam = scene.camera;
    const glm::dvec3 side = glm::normalize(glm::cross(cam.forward(), cam.up)) * (0.01 * glm::length(cam.target - cam.eye));
    cam.eye += side * double(frame);
    cam.target += side * double(frame);
    return cam;
}

} // namespace

TEST_CASE("A steady frame with a moving camera allocates nothing and starts no thread", "[gl][budget]") {
    fx_test::gl_context();
    const char* trace = std::getenv("CELLFX_BUDGET_TRACE");
    const std::string trace_row = trace ? trace : "";
    const std::string trace_scene = trace_row.substr(0, trace_row.find(':'));
    const std::string trace_path = trace_row.find(':') == std::string::npos ? "" : trace_row.substr(trace_row.find(':') + 1);
    std::string table = "scene        path              update allocs  render allocs  threads  (per frame, after warm-up)\n";
    for (const char* name : {"campfire", "searchlight", "laser", "fog_valley", "aurora"}) {
        const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/" + std::string(name) + ".json"));
        if (!trace_scene.empty() && trace_scene != name) continue;
        for (fx::RenderPath path : fx::kRenderPaths) {
            if (!trace_path.empty() && trace_path != fx::render_path_name(path)) continue;
            INFO(name << " [" << fx::render_path_name(path) << "]");
            cellfx::Module fx;
            fx.init(cellfx::Config::from_scene(scene, kW, kH));
            for (const std::string& e : fx.effect_names()) fx.set_path(e, path);
            fx.set_time(1.0);
            GLuint framebuffer = 0, color = 0, depth = 0;
            glCreateFramebuffers(1, &framebuffer);
            glCreateTextures(GL_TEXTURE_2D, 1, &color);
            glTextureStorage2D(color, 1, GL_RGBA8, kW, kH);
            glCreateTextures(GL_TEXTURE_2D, 1, &depth);
            glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT24, kW, kH);
            glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
            glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth, 0);
            const cellfx::Target target{framebuffer, {0, 0, kW, kH}, depth};
            Count update, render;
            for (int f = 0; f < kWarmup + kMeasured; ++f) {
                const fx::Camera cam = moving_camera(scene, pose_of_frame(f));
                tracing = f >= kWarmup && !trace_scene.empty();
                const Count u = count([&] { fx.update(1.0 / 30.0, cam); });
                const Count r = count([&] { fx.render(target); });
                if (tracing) std::fprintf(stderr, "==== frame %d: update %llu, render %llu allocations\n", f,
                                          (unsigned long long)u.allocations, (unsigned long long)r.allocations);
                tracing = false;
                if (f < kWarmup) continue;
                update.allocations += u.allocations, update.threads += u.threads;
                render.allocations += r.allocations, render.threads += r.threads;
            }
            glFinish();
            glDeleteFramebuffers(1, &framebuffer);
            glDeleteTextures(1, &color);
            glDeleteTextures(1, &depth);
            fx_test::require_no_gl_error();

            const std::string path_name = fx::render_path_name(path);
            char row[160];
            std::snprintf(row, sizeof row, "%-12s %-17s %13.1f %14.1f %8.1f", name, path_name.c_str(),
                          double(update.allocations) / kMeasured, double(render.allocations) / kMeasured,
                          double(update.threads + render.threads) / kMeasured);
            table += row;
            table += "\n";
            CHECK(update.allocations == 0);
            CHECK(update.threads == 0);
            CHECK(render.allocations == 0);
            CHECK(render.threads == 0);
        }
    }
    WARN(table);
}

TEST_CASE("A steady frame of the one medium (volumes overlapping on screen) allocates nothing and starts no thread",
          "[gl][budget][medium]") {
    // Two constant volume boxes, one in front of the other (tests/data/medium), and the night
    // valley (terrain fog, fire, smoke, beam): every frame goes through the medium — the exact
    // compositor (plan, appends, resolve) or the froxel grid (injection, integration, apply, the
    // emission pass) — at each fx scale (the reduced layer, its depth and its upsample), and
    // uploads nothing that did not change.
    fx_test::gl_context();
    struct Row {
        const char* scene;
        fx::MediumMethod method;
        double scale;
    };
    std::vector<Row> rows;
    for (fx::MediumMethod method : {fx::MediumMethod::Exact, fx::MediumMethod::Froxel})
        for (double scale : {1.0, 0.5, 0.25}) rows.push_back({"tests/data/medium/emission_behind_fog.json", method, scale});
    for (double scale : {1.0, 0.5}) rows.push_back({"content/scenes/fog_valley_night.json", fx::MediumMethod::Froxel, scale});
    for (const Row& row : rows) {
        INFO(row.scene << ", " << fx::medium_method_name(row.method) << ", fx scale " << row.scale);
        const terrain::Scene scene = terrain::load_scene(fx_test::source_path(row.scene));
        cellfx::Config config = cellfx::Config::from_scene(scene, kW, kH);
        config.medium = row.method;
        config.fx_scale = row.scale;
        cellfx::Module fx;
        fx.init(config);
        GLuint framebuffer = 0, color = 0, depth = 0;
        glCreateFramebuffers(1, &framebuffer);
        glCreateTextures(GL_TEXTURE_2D, 1, &color);
        glTextureStorage2D(color, 1, GL_RGBA8, kW, kH);
        glCreateTextures(GL_TEXTURE_2D, 1, &depth);
        glTextureStorage2D(depth, 1, GL_DEPTH_COMPONENT24, kW, kH);
        glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
        glNamedFramebufferTexture(framebuffer, GL_DEPTH_ATTACHMENT, depth, 0);
        const cellfx::Target target{framebuffer, {0, 0, kW, kH}, depth};
        Count update, render;
        for (int f = 0; f < kWarmup + kMeasured; ++f) {
            const fx::Camera cam = moving_camera(scene, pose_of_frame(f));
            const Count u = count([&] { fx.update(1.0 / 30.0, cam); });
            const Count r = count([&] { fx.render(target); });
            if (f < kWarmup) continue;
            REQUIRE(fx.stats().medium.pixels > 0);
            REQUIRE(fx.stats().medium.method == row.method);
            update.allocations += u.allocations, update.threads += u.threads;
            render.allocations += r.allocations, render.threads += r.threads;
        }
        glFinish();
        glDeleteFramebuffers(1, &framebuffer);
        glDeleteTextures(1, &color);
        glDeleteTextures(1, &depth);
        fx_test::require_no_gl_error();
        CHECK(update.allocations == 0);
        CHECK(render.allocations == 0);
        CHECK(update.threads + render.threads == 0);
    }
}

namespace {

fx::TransferFunction glow() {
    return fx::TransferFunction({{0.0, {0.2, 0.4, 1.0}, 0.5}, {0.5, {0.3, 0.9, 0.4}, 1.0}, {1.0, {1.0, 0.6, 0.2}, 2.0}},
                                /*normalized=*/true);
}

// Frames of every view, three rounds: the first two warm up (buffers grow to their sizes,
// programs link, the sort builds its state); returns what the third allocated and started.
Count steady_renderer_frames(fx::CellRenderer& renderer, const std::vector<fx::Camera>& views, fx::RenderPath path,
                             const fx::CellRenderOptions& options) {
    const fx::gl::RenderTarget target = fx::gl::RenderTarget::create(48, 40, fx::gl::ColorFormat::RGBA8, false);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer());
    Count counted;
    for (int round = 0; round < 3; ++round)
        for (const fx::Camera& camera : views) {
            const Count c = count([&] { renderer.render(camera, {0, 0, 48, 40}, path, options); });
            if (round == 2) counted.allocations += c.allocations, counted.threads += c.threads;
        }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    return counted;
}

} // namespace

TEST_CASE("A steady frame of fx::CellRenderer allocates nothing on every path", "[gl][budget]") {
    // A mesh of tetrahedra and one of mixed cells, from outside and from inside the mesh
    // (near-plane caps), with and without a scene depth.
    fx_test::gl_context();
    const fx::CellMesh mixed = fx_test::mixed_box_with_tets(4);
    const fx::CellMesh tets = fx::tetrahedralize(fx_test::hex_box(4, 4, 4));
    fx::Camera outside = fx::Camera::framing(glm::dvec3(0.0), glm::dvec3(1.0));
    fx::Camera moved = outside;
    moved.eye += glm::dvec3(0.3, -0.2, 0.1);
    fx::Camera inside;
    inside.eye = {0.5, 0.45, 0.55}, inside.target = {1.5, 1.2, 0.9}, inside.up = {0, 0, 1}, inside.near_distance = 0.05;
    // A scene depth: a depth texture cleared to a plane part way into the mesh.
    fx::gl::Texture depth = fx::gl::make_texture_2d(GL_DEPTH_COMPONENT32F, 48, 40);
    const float half = 0.995f;
    glClearTexImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &half);

    for (const fx::CellMesh* mesh : {&tets, &mixed}) {
        const char* mesh_name = mesh == &tets ? "tetrahedra" : "mixed cells";
        fx::CellRenderer renderer(*mesh, "", glow());
        for (fx::RenderPath path : fx::kRenderPaths)
            for (unsigned int scene_depth : {0u, depth.id()}) {
                fx::CellRenderOptions options;
                options.scene_depth = scene_depth;
                options.fog = path == fx::RenderPath::PcpExact;
                INFO(mesh_name << ", " << fx::render_path_name(path) << (scene_depth ? ", scene depth" : ""));
                const Count c = steady_renderer_frames(renderer, {outside, moved, inside}, path, options);
                CHECK(c.allocations == 0);
                CHECK(c.threads == 0);
            }
    }
    fx_test::require_no_gl_error();
}
