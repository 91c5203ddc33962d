// cellfx terrain — how a fog or aurora layer's prisms get their density (the prism builders in
// fog_layer.hpp take them; that header says what each density does). A value header: scenes
// include this, not the builders.
#pragma once

#include <string>

#include "terrain/height_field.hpp"

namespace cellfx::terrain {

enum class LayerDensity { LayerHeight, Noise, LowerBorder };

struct LayerPrismOptions {
    LayerDensity density = LayerDensity::LayerHeight;
    double density_scale = 1.0;
    HeightGenerator noise;             // LayerDensity::Noise: world (x, y) → density before scaling
    double fade_height = 0.0;          // LayerDensity::LowerBorder: where the density reaches 0 (> 0)
    std::string scalar_name = "density";
};

} // namespace cellfx::terrain
