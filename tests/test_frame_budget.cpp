// A steady frame costs the game's heap and threads nothing: for every shipped scene and render
// path, cellfx::Module::update() and render() with a moving camera, after warm-up frames, are
// counted by a replaced global operator new (every C++ allocation in the process) and an
// interposed pthread_create (every thread started, std::thread included). Its own executable
// (fx_budget_tests), so that the replaced allocator counts nothing else.
//
// update() must allocate nothing and start nothing on every scene and path. render() must do the
// same except where the frame uploads a new mesh or new scalars through fx::CellRenderer
// (set_mesh, set_scalars) or runs a path whose CellRenderer::render still allocates or starts a
// thread: those rows are listed in kRenderAllocates with the reason and reported, not asserted.
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
#include "gl_fixture.hpp"
#include "cellfx_names.hpp"

namespace {

std::atomic<bool> counting{false};
std::atomic<std::uint64_t> allocations{0}, threads_started{0};

// CELLFX_BUDGET_TRACE=<scene>: a backtrace on stderr for every allocation counted in that
// scene's measured frames (addr2line -C -f -e fx_budget_tests ADDRESS names the frames).
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
constexpr int kWarmup = 16, kMeasured = 6;

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

// Frame f: 1/30 s apart along the scene's camera path, or the eye moving sideways by 1% of its
// distance to the target per frame (the terrain LODs refine, the fog and aurora rebuild).
fx::Camera moving_camera(const terrain::Scene& scene, int frame) {
    if (scene.camera_path) return scene.camera_path->at(frame / 30.0, scene.camera);
    fx::Camera cam = scene.camera;
    const glm::dvec3 side = glm::normalize(glm::cross(cam.forward(), cam.up)) * (0.01 * glm::length(cam.target - cam.eye));
    cam.eye += side * double(frame);
    cam.target += side * double(frame);
    return cam;
}

// Rows whose render() is known to allocate on this branch, and why (reported, not asserted).
struct Known {
    const char* scene;
    const char* path; // nullptr: every path
    const char* reason;
};
const Known kRenderAllocates[] = {
    {"campfire", nullptr, "CellRenderer::set_scalars builds its point buffer in a new vector (the noise moves every frame)"},
    {"fog_valley", nullptr, "CellRenderer::set_mesh rebuilds the projector geometry of the moved LOD's prisms"},
    {"aurora", nullptr, "CellRenderer::set_mesh rebuilds the projector geometry of the moved LOD's prisms"},
    {"laser", nullptr, "CellRenderer::set_scalars: the dust drifts"},
    {nullptr, "pcp", "CellRenderer::render: the classic path's batch lists"},
    {nullptr, "absorption", "CellRenderer::render: sort, subdivision and projection scratch, and a thread per frame"},
    {nullptr, "absorption-exact", "CellRenderer::render: sort and item scratch"},
};

const char* known_reason(const std::string& scene, const std::string& path) {
    for (const Known& k : kRenderAllocates)
        if ((!k.scene || scene == k.scene) && (!k.path || path == k.path)) return k.reason;
    return nullptr;
}

} // namespace

TEST_CASE("A steady frame with a moving camera allocates nothing and starts no thread", "[gl][budget]") {
    fx_test::gl_context();
    const char* trace = std::getenv("CELLFX_BUDGET_TRACE");
    const std::string trace_scene = trace ? trace : "";
    std::string table = "scene        path              update allocs  render allocs  threads  (per frame, after warm-up)\n";
    for (const char* name : {"campfire", "searchlight", "laser", "fog_valley", "aurora"}) {
        const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/" + std::string(name) + ".json"));
        for (fx::RenderPath path : fx::kRenderPaths) {
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
                const fx::Camera cam = moving_camera(scene, f);
                tracing = f >= kWarmup && trace_scene == name;
                const Count u = count([&] { fx.update(1.0 / 30.0, cam); });
                const Count r = count([&] { fx.render(target); });
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
            const char* reason = known_reason(name, path_name);
            if (reason && (render.allocations > 0 || render.threads > 0)) table += std::string("  known: ") + reason;
            table += "\n";
            CHECK(update.allocations == 0);
            CHECK(update.threads == 0);
            if (!reason) {
                CHECK(render.allocations == 0);
                CHECK(render.threads == 0);
            }
        }
    }
    WARN(table);
}

TEST_CASE("A steady frame of the one medium (volumes overlapping on screen) allocates nothing and starts no thread",
          "[gl][budget][medium]") {
    // Two constant volume boxes, one in front of the other (tests/data/medium): every frame goes
    // through the compositor (plan, appends, resolve) and uploads nothing.
    fx_test::gl_context();
    const terrain::Scene scene = terrain::load_scene(fx_test::source_path("tests/data/medium/emission_behind_fog.json"));
    cellfx::Module fx;
    fx.init(cellfx::Config::from_scene(scene, kW, kH));
    GLuint framebuffer = 0, color = 0;
    glCreateFramebuffers(1, &framebuffer);
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA8, kW, kH);
    glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, color, 0);
    const cellfx::Target target{framebuffer, {0, 0, kW, kH}, 0};
    Count update, render;
    for (int f = 0; f < kWarmup + kMeasured; ++f) {
        const fx::Camera cam = moving_camera(scene, f);
        const Count u = count([&] { fx.update(1.0 / 30.0, cam); });
        const Count r = count([&] { fx.render(target); });
        if (f < kWarmup) continue;
        REQUIRE(fx.stats().medium.pixels > 0);
        update.allocations += u.allocations, update.threads += u.threads;
        render.allocations += r.allocations, render.threads += r.threads;
    }
    glFinish();
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &color);
    fx_test::require_no_gl_error();
    CHECK(update.allocations == 0);
    CHECK(render.allocations == 0);
    CHECK(update.threads + render.threads == 0);
}
