// cellfx terrain — how the terrain surface is shaded (terrain::SurfaceRenderer draws it;
// surface_renderer.hpp). A value header: scenes include this, not the renderer.
#pragma once

#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace cellfx::terrain {

struct SurfaceStyle {
    glm::dvec3 sun_direction{-0.45, -0.35, 0.82}; // towards the sun (normalised when used)
    double ambient = 0.35;                         // light from the sky, as a fraction of full
    // Colour by height fraction (0 = lowest, 1 = highest sample), linear between stops; at
    // most 8 stops, fractions non-decreasing.
    std::vector<std::pair<double, glm::dvec3>> ramp = {
        {0.00, {0.18, 0.32, 0.14}}, {0.35, {0.34, 0.44, 0.22}}, {0.60, {0.45, 0.38, 0.28}},
        {0.82, {0.55, 0.53, 0.50}}, {1.00, {0.96, 0.96, 0.98}}};
};

} // namespace cellfx::terrain
