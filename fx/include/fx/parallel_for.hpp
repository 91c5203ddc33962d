// cellfx — the host's job system, for the CPU work cellfx splits across threads.
//
// A game hands cellfx its own job system so that cellfx's CPU work (the classic absorption
// path's projected subdivisions, the exact path's per-frame index lists) runs on the game's
// worker threads rather than on threads of its own. Without one, cellfx uses a pool of its own:
// started once, on first use, with one thread per hardware thread beyond the caller's, kept
// for the life of the process (fx::default_parallel_for()). Either way no thread is started in
// a steady frame.
//
// A ParallelFor must run task(task_context, i) exactly once for every i in [0, count), on any
// threads and in any order, and return when all have run. Tasks cellfx gives it do not throw
// and do not call back into it.
#pragma once

#include <cstddef>

namespace cellfx::fx {

// The host's job system, for the CPU work cellfx can split: runs task(task_context, i) for
// every i in [0, count), in any order and on any threads, and returns when all have run.
struct ParallelFor {
    using Task = void (*)(void* task_context, std::size_t index);
    void (*run)(void* host_context, std::size_t count, Task task, void* task_context) = nullptr;
    void* host_context = nullptr;
    explicit operator bool() const { return run != nullptr; }
};

// cellfx's own persistent pool (threads started on the first call that has work for them).
// A call made while the pool is busy with another caller's work runs on the calling thread.
ParallelFor default_parallel_for();
// How many tasks default_parallel_for() runs at once: hardware threads (at least 1).
std::size_t default_parallel_for_threads();

} // namespace cellfx::fx
