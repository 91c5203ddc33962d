#include "gl_call_clock.hpp"

#include <ctime>
#include <cstring>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <dlfcn.h>
#include <epoxy/gl.h>

namespace cellfx_samples {
namespace {

enum class Kind { Driver, Upload, State };

bool g_running = false;
double g_driver_ms = 0.0, g_upload_ms = 0.0, g_state_ms = 0.0, g_overhead_ms = 0.0;
// The most one state call counts (see Hook::account): ten times a program bind on llvmpipe.
constexpr double kStateCallCapMs = 0.05;
std::uint64_t g_state_calls = 0, g_calls = 0;

// What timing one call costs, per clock (calibrate()): `inside` lands between the two clock
// reads and is taken off the call's figure; `total` (inside and out) is the caller's CPU the
// wrapper adds (GlCallClock::overhead_ms()). On some machines the thread CPU clock is a system
// call of microseconds: without this, every wrapped call would move that much into the figures.
struct ClockCost {
    double inside = 0.0, total = 0.0;
};
ClockCost g_cost[3];

double now_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// The state calls' clock: the monotonic clock, read in user space (vDSO), ten to a hundred times
// cheaper than the thread CPU clock, whose read costs more than most state calls take. A state
// call does not wait, so its wall time is its CPU time unless the thread is preempted inside it.
double state_now_ms() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// Per entry point: its name, calls and time since the last reset() (GlCallClock::entry_points()).
std::vector<GlCallClock::EntryPoint>& registry() {
    static std::vector<GlCallClock::EntryPoint> list;
    return list;
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
    static inline std::size_t entry = 0; // in entry_points()

    static void install(const char* name) {
        if (*Slot == &call || unresolved(reinterpret_cast<const void*>(*Slot))) return;
        driver = *Slot;
        entry = registry().size();
        registry().push_back({name, K == Kind::State, 0, 0.0});
        *Slot = &call;
    }
    static double clock() { return K == Kind::State ? state_now_ms() : now_ms(); }
    static void account(double start) {
        if (start < 0.0) return;
        double ms = clock() - start - g_cost[int(K)].inside;
        // A state call never waits, so a long one on the monotonic clock was preempted (llvmpipe's
        // compile and fragment threads share the cores): it counts at most kStateCallCapMs, and
        // the rest of its CPU, if it had any, stays in cellfx's figure rather than a wait leaving it.
        if (K == Kind::State && ms > kStateCallCapMs) ms = kStateCallCapMs;
        g_overhead_ms += g_cost[int(K)].total;
        (K == Kind::Driver ? g_driver_ms : K == Kind::Upload ? g_upload_ms : g_state_ms) += ms;
        GlCallClock::EntryPoint& e = registry()[entry];
        ++e.calls, e.ms += ms;
        ++g_calls;
        if (K == Kind::State) ++g_state_calls;
    }
    static R call(A... a) {
        const double start = g_running ? clock() : -1.0;
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

#define CELLFX_HOOK(name, kind) Hook<&name, Kind::kind, decltype(name)>::install(#name)

// Calibration: a wrapped call of a function that does nothing, against the same call unwrapped.
void nothing() {}
void (*g_probe_thread_clock)() = &nothing;
void (*g_probe_monotonic_clock)() = &nothing;

template <Kind K, auto* Probe>
ClockCost calibrate() {
    constexpr int kCalls = 2000;
    void (*const direct)() = *Probe;
    Hook<Probe, K, void (*)()>::install(K == Kind::State ? "(calibration, monotonic clock)" : "(calibration, thread clock)");
    const bool was_running = g_running;
    const double driver = g_driver_ms, upload = g_upload_ms, state = g_state_ms, overhead = g_overhead_ms;
    const std::uint64_t calls = g_calls, state_calls = g_state_calls;
    double best = 1e300;
    ClockCost cost;
    for (int round = 0; round < 5; ++round) { // the least disturbed round
        const double t0 = now_ms();
        for (int i = 0; i < kCalls; ++i) direct();
        const double t1 = now_ms();
        g_running = true;
        double& figure = K == Kind::Driver ? g_driver_ms : K == Kind::Upload ? g_upload_ms : g_state_ms;
        const double before = figure;
        for (int i = 0; i < kCalls; ++i) (*Probe)();
        const double measured = figure - before;
        g_running = false;
        const double t2 = now_ms();
        const double total = ((t2 - t1) - (t1 - t0)) / kCalls;
        if (total < best) best = total, cost = {measured / kCalls + g_cost[int(K)].inside, total};
    }
    g_running = was_running;
    g_driver_ms = driver, g_upload_ms = upload, g_state_ms = state, g_overhead_ms = overhead;
    g_calls = calls, g_state_calls = state_calls;
    return cost;
}

} // namespace

void GlCallClock::install() {
    static const bool calibrated = [] {
        g_cost[int(Kind::Driver)] = g_cost[int(Kind::Upload)] = calibrate<Kind::Driver, &g_probe_thread_clock>();
        g_cost[int(Kind::State)] = calibrate<Kind::State, &g_probe_monotonic_clock>();
        return true;
    }();
    (void)calibrated;
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
    // A compile's or link's status waits for it: llvmpipe compiles on its own threads, and
    // the monotonic clock would count the wait.
    CELLFX_HOOK(glGetProgramiv, Driver);
    CELLFX_HOOK(glGetProgramInfoLog, Driver);
    CELLFX_HOOK(glGetShaderiv, Driver);
    CELLFX_HOOK(glGetShaderInfoLog, Driver);
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
    // Everything else cellfx calls: state, bindings, uniforms, queries of state, object
    // creation. Each takes well under a microsecond; together they are the driver's share of a
    // frame that draws little (tests/test_gl_call_clock.cpp checks that every GL function fx/ and
    // terrain/ call is listed here or above).
    CELLFX_HOOK(glActiveTexture, State); CELLFX_HOOK(glAttachShader, State); CELLFX_HOOK(glBeginQuery, State);
    CELLFX_HOOK(glBindBuffer, State); CELLFX_HOOK(glBindBufferBase, State);
    CELLFX_HOOK(glBindBufferRange, State); CELLFX_HOOK(glBindFramebuffer, State);
    CELLFX_HOOK(glBindImageTexture, State); CELLFX_HOOK(glBindSampler, State);
    CELLFX_HOOK(glBindTexture, State); CELLFX_HOOK(glBindTextureUnit, State);
    CELLFX_HOOK(glBindVertexArray, State); CELLFX_HOOK(glBlendColor, State);
    CELLFX_HOOK(glBlendEquation, State); CELLFX_HOOK(glBlendEquationSeparate, State);
    CELLFX_HOOK(glBlendEquationSeparatei, State); CELLFX_HOOK(glBlendFunc, State);
    CELLFX_HOOK(glBlendFuncSeparate, State); CELLFX_HOOK(glBlendFuncSeparatei, State);
    CELLFX_HOOK(glCheckNamedFramebufferStatus, State); CELLFX_HOOK(glClampColor, State);
    CELLFX_HOOK(glClearColor, State); CELLFX_HOOK(glClearDepth, State); CELLFX_HOOK(glClipControl, State);
    CELLFX_HOOK(glColorMask, State); CELLFX_HOOK(glColorMaski, State); CELLFX_HOOK(glCreateBuffers, State);
    CELLFX_HOOK(glCreateFramebuffers, State); CELLFX_HOOK(glCreateProgram, State);
    CELLFX_HOOK(glCreateQueries, State); CELLFX_HOOK(glCreateRenderbuffers, State);
    CELLFX_HOOK(glCreateSamplers, State); CELLFX_HOOK(glCreateShader, State);
    CELLFX_HOOK(glCreateTextures, State); CELLFX_HOOK(glCreateVertexArrays, State);
    CELLFX_HOOK(glCullFace, State); CELLFX_HOOK(glDeleteBuffers, State);
    CELLFX_HOOK(glDeleteFramebuffers, State); CELLFX_HOOK(glDeleteProgram, State);
    CELLFX_HOOK(glDeleteQueries, State); CELLFX_HOOK(glDeleteRenderbuffers, State);
    CELLFX_HOOK(glDeleteSamplers, State); CELLFX_HOOK(glDeleteShader, State);
    CELLFX_HOOK(glDeleteTextures, State); CELLFX_HOOK(glDeleteVertexArrays, State);
    CELLFX_HOOK(glDepthFunc, State); CELLFX_HOOK(glDepthMask, State); CELLFX_HOOK(glDepthRange, State);
    CELLFX_HOOK(glDepthRangeIndexed, State); CELLFX_HOOK(glDetachShader, State);
    CELLFX_HOOK(glDisable, State); CELLFX_HOOK(glDisablei, State); CELLFX_HOOK(glEnable, State);
    CELLFX_HOOK(glEnableVertexArrayAttrib, State); CELLFX_HOOK(glEnablei, State);
    CELLFX_HOOK(glEndQuery, State); CELLFX_HOOK(glFrontFace, State); CELLFX_HOOK(glGetBooleani_v, State);
    CELLFX_HOOK(glGetBooleanv, State); CELLFX_HOOK(glGetDoublei_v, State); CELLFX_HOOK(glGetDoublev, State);
    CELLFX_HOOK(glGetError, State); CELLFX_HOOK(glGetFloati_v, State); CELLFX_HOOK(glGetFloatv, State);
    CELLFX_HOOK(glGetInteger64i_v, State); CELLFX_HOOK(glGetIntegeri_v, State);
    CELLFX_HOOK(glGetIntegerv, State); CELLFX_HOOK(glGetObjectLabel, State);
    CELLFX_HOOK(glGetString, State); CELLFX_HOOK(glGetTextureLevelParameteriv, State);
    CELLFX_HOOK(glGetTextureParameteriv, State); CELLFX_HOOK(glIsBuffer, State);
    CELLFX_HOOK(glIsEnabled, State); CELLFX_HOOK(glIsEnabledi, State); CELLFX_HOOK(glIsTexture, State);
    CELLFX_HOOK(glNamedFramebufferDrawBuffer, State); CELLFX_HOOK(glNamedFramebufferParameteri, State);
    CELLFX_HOOK(glNamedFramebufferReadBuffer, State); CELLFX_HOOK(glNamedFramebufferTexture, State);
    CELLFX_HOOK(glObjectLabel, State); CELLFX_HOOK(glPixelStorei, State); CELLFX_HOOK(glPolygonMode, State);
    CELLFX_HOOK(glPolygonOffset, State); CELLFX_HOOK(glPrimitiveRestartIndex, State);
    CELLFX_HOOK(glProgramUniform1d, State); CELLFX_HOOK(glProgramUniform1f, State);
    CELLFX_HOOK(glProgramUniform1fv, State); CELLFX_HOOK(glProgramUniform1i, State);
    CELLFX_HOOK(glProgramUniform1ui, State); CELLFX_HOOK(glProgramUniform2f, State);
    CELLFX_HOOK(glProgramUniform2i, State); CELLFX_HOOK(glProgramUniform3f, State);
    CELLFX_HOOK(glProgramUniform3fv, State); CELLFX_HOOK(glProgramUniform3i, State);
    CELLFX_HOOK(glProgramUniform4f, State); CELLFX_HOOK(glProgramUniform4fv, State);
    CELLFX_HOOK(glProgramUniform4i, State); CELLFX_HOOK(glProgramUniformMatrix4fv, State);
    CELLFX_HOOK(glProvokingVertex, State); CELLFX_HOOK(glSamplerParameteri, State);
    CELLFX_HOOK(glScissor, State); CELLFX_HOOK(glScissorIndexed, State);
    CELLFX_HOOK(glScissorIndexedv, State); CELLFX_HOOK(glShaderSource, State);
    CELLFX_HOOK(glTextureBuffer, State); CELLFX_HOOK(glTextureParameteri, State);
    CELLFX_HOOK(glUniform1f, State); CELLFX_HOOK(glUseProgram, State);
    CELLFX_HOOK(glVertexArrayAttribBinding, State); CELLFX_HOOK(glVertexArrayAttribFormat, State);
    CELLFX_HOOK(glVertexArrayElementBuffer, State); CELLFX_HOOK(glVertexArrayVertexBuffer, State);
    CELLFX_HOOK(glViewportIndexedf, State); CELLFX_HOOK(glViewportIndexedfv, State);
}

#undef CELLFX_HOOK

void GlCallClock::reset() {
    g_driver_ms = g_upload_ms = g_state_ms = g_overhead_ms = 0.0;
    g_state_calls = g_calls = 0;
    for (EntryPoint& e : registry()) e.calls = 0, e.ms = 0.0;
}
void GlCallClock::set_running(bool running) { g_running = running; }
bool GlCallClock::running() { return g_running; }
double GlCallClock::driver_ms() { return g_driver_ms; }
double GlCallClock::upload_ms() { return g_upload_ms; }
double GlCallClock::state_ms() { return g_state_ms; }
double GlCallClock::overhead_ms() { return g_overhead_ms; }
double GlCallClock::thread_clock_read_ms() { return g_cost[int(Kind::Driver)].inside; }
std::uint64_t GlCallClock::state_calls() { return g_state_calls; }
std::uint64_t GlCallClock::calls() { return g_calls; }
const std::vector<GlCallClock::EntryPoint>& GlCallClock::entry_points() { return registry(); }
double GlCallClock::thread_cpu_ms() { return now_ms(); }

} // namespace cellfx_samples
