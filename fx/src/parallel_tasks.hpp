// cellfx — running a C++ callable through a fx::ParallelFor (the host's job system or
// cellfx's own pool), with exceptions carried back to the caller.
#pragma once

#include <cstddef>
#include <exception>
#include <vector>

#include "fx/parallel_for.hpp"

namespace cellfx::fx {

// Calls fn(i) for every i in [0, count) through `parallel_for` and rethrows, on the calling
// thread, the exception of the lowest i that threw. `errors` is scratch the caller keeps so
// that a steady frame allocates nothing (resized to `count` only when it grows).
template <class Fn>
void parallel_for_each(const ParallelFor& parallel_for, std::size_t count, Fn&& fn,
                       std::vector<std::exception_ptr>& errors) {
    if (errors.size() < count) errors.resize(count);
    struct Context {
        Fn* fn;
        std::exception_ptr* errors;
    } context{&fn, errors.data()};
    const ParallelFor::Task task = [](void* c, std::size_t i) {
        Context& ctx = *static_cast<Context*>(c);
        try {
            (*ctx.fn)(i);
        } catch (...) {
            ctx.errors[i] = std::current_exception();
        }
    };
    if (parallel_for && count > 1)
        parallel_for.run(parallel_for.host_context, count, task, &context);
    else
        for (std::size_t i = 0; i < count; ++i) task(&context, i);
    for (std::size_t i = 0; i < count; ++i)
        if (errors[i]) {
            const std::exception_ptr e = errors[i];
            for (std::size_t j = i; j < count; ++j) errors[j] = nullptr;
            std::rethrow_exception(e);
        }
}

} // namespace cellfx::fx
