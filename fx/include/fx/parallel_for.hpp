// cellfx — the host's job system, for the CPU work cellfx can split.
#pragma once

#include <cstddef>

namespace fx {

// The host's job system, for the CPU work cellfx can split: runs task(task_context, i) for
// every i in [0, count), in any order and on any threads, and returns when all have run.
struct ParallelFor {
    using Task = void (*)(void* task_context, std::size_t index);
    void (*run)(void* host_context, std::size_t count, Task task, void* task_context) = nullptr;
    void* host_context = nullptr;
    explicit operator bool() const { return run != nullptr; }
};

} // namespace fx
