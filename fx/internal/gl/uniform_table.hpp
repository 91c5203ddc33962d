// cellfx — compile-time checks of an interface table's uniform locations (the projector's in
// fx/src/projector/gl_interface.hpp, the terrain's in terrain/src/render/terrain_interface.hpp):
// no two overlap, so any program may use any set of them, and all lie within GL 4.5's
// guaranteed GL_MAX_UNIFORM_LOCATIONS.
#pragma once

#include <cstddef>
#include <string_view>

namespace cellfx::fx::gl {

// One entry of a table: its constant's name and value (uniform locations are the kUniform ones).
struct UniformEntry {
    std::string_view name;
    int location = 0;
};

constexpr bool is_uniform_location(std::string_view name) { return name.substr(0, 8) == "kUniform"; }

// `taken(name)`: how many locations the uniform takes (an array's elements).
template <std::size_t N>
constexpr bool uniform_locations_apart(const UniformEntry (&entries)[N], int (*taken)(std::string_view)) {
    for (const UniformEntry& a : entries)
        for (const UniformEntry& b : entries)
            if (is_uniform_location(a.name) && is_uniform_location(b.name) && a.name != b.name &&
                a.location <= b.location && b.location < a.location + taken(a.name))
                return false;
    return true;
}

// One past the highest location the table's uniforms take.
template <std::size_t N>
constexpr int uniform_locations_end(const UniformEntry (&entries)[N], int (*taken)(std::string_view)) {
    int end = 0;
    for (const UniformEntry& a : entries)
        if (is_uniform_location(a.name) && a.location + taken(a.name) > end) end = a.location + taken(a.name);
    return end;
}

constexpr int kGuaranteedUniformLocations = 1024; // GL 4.5's minimum GL_MAX_UNIFORM_LOCATIONS

} // namespace cellfx::fx::gl
