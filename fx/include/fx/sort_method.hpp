// cellfx — the visibility sorts by name (fx::VisibilitySort runs them; visibility_sort.hpp
// says what each does). A value header: render options that only pick a sort include this, not
// the sorter.
#pragma once

#include <string_view>
#include <vector>

namespace cellfx::fx {

enum class SortMethod {
    Centroid,
    Mpvo,
    Xmpvo,
    Power,
};
const char* sort_method_name(SortMethod method); // "centroid", "mpvo", "xmpvo", "power"
// Parses a name given by sort_method_name(); false for anything else.
bool parse_sort_method(std::string_view name, SortMethod& method);
// Every method, in the order above (for benchmarks and tests).
const std::vector<SortMethod>& all_sort_methods();

} // namespace cellfx::fx
