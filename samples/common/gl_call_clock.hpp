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
//             built (counted as cellfx's own CPU by the benchmarks: its uploads);
//   state     every other GL call cellfx makes (state, bindings, uniforms, queries of state),
//             timed with the monotonic clock: the thread CPU clock is a system call that costs
//             more than most of these calls, and a call that does not wait spends its wall time
//             on the CPU.
// The clock counts only while running(); GL calls are made on one thread, the one whose clock it
// reads. Nothing is allocated per call. The thread CPU clock excludes waiting, so a glFinish that
// blocks costs what the driver computed meanwhile on this thread, not the wait.
//
// For benchmarks and the samples' frame-time graph, never for a library: a game's own GL
// calls through epoxy in the same process are counted too when it makes them while running.
#pragma once

#include <cstdint>
#include <vector>

namespace cellfx_samples {

class GlCallClock {
public:
    // One wrapped entry point and its calls and milliseconds since the last reset().
    struct EntryPoint {
        const char* name;
        bool state;
        std::uint64_t calls;
        double ms;
    };
    // Wraps the resolved entry points not wrapped yet (cheap to repeat between frames).
    static void install();
    // Totals since the last reset(), in milliseconds of the calling thread's CPU.
    static void reset();
    static void set_running(bool running);
    static bool running();
    static double driver_ms();
    static double upload_ms();
    static double state_ms();
    // The caller's CPU the wrappers themselves took (their clock reads, measured once at the
    // first install()): subtract it, with the three totals above, from the caller's clock.
    static double overhead_ms();
    static std::uint64_t state_calls();
    static std::uint64_t calls(); // every wrapped call, state calls included
    static const std::vector<EntryPoint>& entry_points(); // in the order they were wrapped
    static double thread_cpu_ms(); // the calling thread's CPU clock now
    static double thread_clock_read_ms(); // what one read of it costs (a span between two reads holds one)
};

} // namespace cellfx_samples
