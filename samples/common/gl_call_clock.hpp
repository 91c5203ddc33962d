// cellfx samples — how much of a frame's CPU is the GL driver's: a clock around the GL calls
// that make the driver work on the calling thread.
//
// cellfx calls GL through libepoxy, whose entry points are global function pointers. install()
// points those of the calls below that have been resolved (called once: run a warm-up frame
// first, and install() again whenever new calls may have been made) at wrappers that add the
// calling thread's CPU time spent inside the call to one of two totals:
//   driver    draws, compute dispatches, clears, copies and blits done by the GL, queries'
//             results, reads back, glFinish / glFlush, shader compiles and links, storage
//             allocation: work a GPU driver does on the GPU or its own threads, but llvmpipe
//             (vertex stage, binning, set-up of every draw) does on the caller's thread;
//   uploads   glNamedBufferSubData and glTextureSubImage*: the driver's copy of data cellfx
//             built (counted as cellfx's own CPU by the benchmarks: its uploads).
// Every other GL call (state, binding, uniforms: a few microseconds a frame) stays with the
// caller's time. The clock counts only while running(); GL calls are made on one thread, the one
// whose clock it reads. Nothing is allocated per call. The thread CPU clock excludes waiting, so a glFinish that blocks costs
// what the driver computed meanwhile on this thread, not the wait.
//
// For benchmarks and the samples' frame-time graph, never for a library: a game's own GL
// calls through epoxy in the same process are counted too when it makes them while running.
#pragma once

namespace cellfx_samples {

class GlCallClock {
public:
    // Wraps the resolved entry points not wrapped yet (cheap to repeat between frames).
    static void install();
    // Totals since the last reset(), in milliseconds of the calling thread's CPU.
    static void reset();
    static void set_running(bool running);
    static bool running();
    static double driver_ms();
    static double upload_ms();
    static double thread_cpu_ms(); // the calling thread's CPU clock now
};

} // namespace cellfx_samples
