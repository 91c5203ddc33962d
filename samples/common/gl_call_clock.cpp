#include "gl_call_clock.hpp"

#include <ctime>
#include <cstring>
#include <type_traits>

#include <dlfcn.h>
#include <epoxy/gl.h>

namespace cellfx_samples {
namespace {

enum class Kind { Driver, Upload };

bool g_running = false;
double g_driver_ms = 0.0, g_upload_ms = 0.0;

double now_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// True while epoxy's pointer still holds its own resolving stub: that stub calls through the
// pointer again, so wrapping it would recurse. Such entry points are wrapped by a later
// install(), once their first call has resolved them.
bool unresolved(const void* function) {
    Dl_info info{};
    return !function || (dladdr(function, &info) && info.dli_fname && std::strstr(info.dli_fname, "libepoxy"));
}

// The wrapper of one epoxy entry point. `Slot` is epoxy's global pointer (the macro glX names
// it), holding the driver's function once resolved.
template <auto* Slot, Kind K, class Fn>
struct Hook;

template <auto* Slot, Kind K, class R, class... A>
struct Hook<Slot, K, R (*)(A...)> {
    static inline R (*driver)(A...) = nullptr;

    static void install() {
        if (*Slot == &call || unresolved(reinterpret_cast<const void*>(*Slot))) return;
        driver = *Slot;
        *Slot = &call;
    }
    static void account(double start) {
        if (start < 0.0) return;
        (K == Kind::Driver ? g_driver_ms : g_upload_ms) += now_ms() - start;
    }
    static R call(A... a) {
        const double start = g_running ? now_ms() : -1.0;
        if constexpr (std::is_void_v<R>) {
            driver(a...);
            account(start);
        } else {
            R r = driver(a...);
            account(start);
            return r;
        }
    }
};

#define CELLFX_HOOK(name, kind) Hook<&name, Kind::kind, decltype(name)>::install()

} // namespace

void GlCallClock::install() {
    // Draws, dispatches and what the GL computes or waits for.
    CELLFX_HOOK(glDrawArrays, Driver);
    CELLFX_HOOK(glDrawArraysInstanced, Driver);
    CELLFX_HOOK(glDrawArraysIndirect, Driver);
    CELLFX_HOOK(glDrawArraysInstancedBaseInstance, Driver);
    CELLFX_HOOK(glDrawElements, Driver);
    CELLFX_HOOK(glDrawElementsInstanced, Driver);
    CELLFX_HOOK(glDrawElementsBaseVertex, Driver);
    CELLFX_HOOK(glDrawElementsIndirect, Driver);
    CELLFX_HOOK(glDrawElementsInstancedBaseVertexBaseInstance, Driver);
    CELLFX_HOOK(glDrawRangeElements, Driver);
    CELLFX_HOOK(glMultiDrawArrays, Driver);
    CELLFX_HOOK(glMultiDrawElements, Driver);
    CELLFX_HOOK(glMultiDrawArraysIndirect, Driver);
    CELLFX_HOOK(glMultiDrawElementsIndirect, Driver);
    CELLFX_HOOK(glDispatchCompute, Driver);
    CELLFX_HOOK(glDispatchComputeIndirect, Driver);
    CELLFX_HOOK(glClear, Driver);
    CELLFX_HOOK(glClearBufferfv, Driver);
    CELLFX_HOOK(glClearNamedFramebufferfv, Driver);
    CELLFX_HOOK(glClearNamedFramebufferfi, Driver);
    CELLFX_HOOK(glClearNamedFramebufferiv, Driver);
    CELLFX_HOOK(glClearNamedFramebufferuiv, Driver);
    CELLFX_HOOK(glClearTexImage, Driver);
    CELLFX_HOOK(glClearTexSubImage, Driver);
    CELLFX_HOOK(glClearNamedBufferData, Driver);
    CELLFX_HOOK(glClearNamedBufferSubData, Driver);
    CELLFX_HOOK(glCopyImageSubData, Driver);
    CELLFX_HOOK(glCopyNamedBufferSubData, Driver);
    CELLFX_HOOK(glBlitFramebuffer, Driver);
    CELLFX_HOOK(glBlitNamedFramebuffer, Driver);
    CELLFX_HOOK(glGenerateTextureMipmap, Driver);
    CELLFX_HOOK(glReadPixels, Driver);
    CELLFX_HOOK(glGetTextureImage, Driver);
    CELLFX_HOOK(glGetTextureSubImage, Driver);
    CELLFX_HOOK(glGetNamedBufferSubData, Driver);
    CELLFX_HOOK(glGetQueryObjectiv, Driver);
    CELLFX_HOOK(glGetQueryObjectuiv, Driver);
    CELLFX_HOOK(glGetQueryObjectui64v, Driver);
    CELLFX_HOOK(glMapNamedBufferRange, Driver);
    CELLFX_HOOK(glMemoryBarrier, Driver);
    CELLFX_HOOK(glClientWaitSync, Driver);
    CELLFX_HOOK(glFinish, Driver);
    CELLFX_HOOK(glFlush, Driver);
    CELLFX_HOOK(glCompileShader, Driver);
    CELLFX_HOOK(glLinkProgram, Driver);
    CELLFX_HOOK(glNamedBufferData, Driver);
    CELLFX_HOOK(glNamedBufferStorage, Driver);
    CELLFX_HOOK(glNamedRenderbufferStorage, Driver);
    CELLFX_HOOK(glTextureStorage2D, Driver);
    CELLFX_HOOK(glTextureStorage3D, Driver);
    // The driver's copy of data the caller built.
    CELLFX_HOOK(glNamedBufferSubData, Upload);
    CELLFX_HOOK(glBufferSubData, Upload);
    CELLFX_HOOK(glTextureSubImage1D, Upload);
    CELLFX_HOOK(glTextureSubImage2D, Upload);
    CELLFX_HOOK(glTextureSubImage3D, Upload);
    CELLFX_HOOK(glTexSubImage2D, Upload);
}

#undef CELLFX_HOOK

void GlCallClock::reset() { g_driver_ms = g_upload_ms = 0.0; }
void GlCallClock::set_running(bool running) { g_running = running; }
bool GlCallClock::running() { return g_running; }
double GlCallClock::driver_ms() { return g_driver_ms; }
double GlCallClock::upload_ms() { return g_upload_ms; }
double GlCallClock::thread_cpu_ms() { return now_ms(); }

} // namespace cellfx_samples
