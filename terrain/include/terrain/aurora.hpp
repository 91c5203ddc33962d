// cellfx terrain — aurora: the fog layer's prism stack hung in the sky (Roettger & Ertl 2003, §5:
// "a height field that corresponds to the penetration depth of the particles into the earth's
// ionosphere"), emissive.
//
// The penetration depth is a height field (≥ 0) over a horizontal grid; the curtains hang from
// a flat ceiling down by the depth. For the LOD and the prisms this is a layer whose "ground"
// is the lower border (ceiling − depth) and whose thickness is the depth, so the same
// ContinuousLod + build_layer_prisms (with LayerDensity::LowerBorder) make the cells; render
// them with an emission path (pcp, pcp-exact without fog, or mip) and add them over the sky.
#pragma once

#include <cstdint>

#include "terrain/height_field.hpp"

namespace cellfx::terrain {

// Procedural curtains: `count` bands running along x, each a Gaussian ridge of width `width`
// across y whose centre line wanders by `wander` (a smooth generator of x and the band index
// gives the shape; `brightness` modulates the depth along it). Depth below `cutoff`·max_depth
// is set to exactly 0 so that empty sky makes no prisms.
struct AuroraCurtains {
    int count = 3;
    double max_depth = 3000.0; // world units from the ceiling down
    double width = 250.0;      // Gaussian sigma across the curtain
    double wander = 1500.0;    // amplitude of the centre line's sideways wander
    double cutoff = 0.02;
    std::uint32_t seed = 1;
};

// A penetration-depth field on a size × size grid. `wave(x, k)` ∈ [−1, 1] gives band k's
// sideways offset at x (scaled by wander) and `brightness(x, y)` ∈ [0, 1] scales the depth; with
// empty generators built-in smooth sinusoids are used. Throws fx::Error for bad sizes or
// parameters (non-finite, non-positive depth or width, count < 1).
HeightField make_aurora_depth(int size, double spacing, glm::dvec2 origin, const AuroraCurtains& curtains,
                              const std::function<double(double x, int band)>& wave = {},
                              const HeightGenerator& brightness = {});

// The layer for ContinuousLod: lower border = ceiling − depth (as the "ground"), thickness =
// depth. Throws fx::Error for a negative or non-finite depth or a non-finite ceiling.
struct AuroraLayer {
    HeightField lower_border;
    HeightField depth;
};
AuroraLayer make_aurora_layer(const HeightField& penetration_depth, double ceiling);

} // namespace cellfx::terrain
