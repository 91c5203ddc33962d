// `cellfx bench`: how many C++ allocations a piece of work makes. The command replaces the
// global operator new (allocation_counter.cpp) to count every allocation in the process — cellfx's
// and the C++ standard library's on its behalf; Mesa's own memory is C's malloc and not counted.
#pragma once

#include <cstdint>

namespace cellfx_cli {

// Allocations made by the process since it started.
std::uint64_t allocations_so_far();

} // namespace cellfx_cli
