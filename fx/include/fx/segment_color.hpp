// cellfx — the colour of a ray segment under the volume density model (Williams & Max 1992):
// what fx::Medium::integrate_span returns and cellfx's exact segment integrals compute.
#pragma once

#include <glm/vec3.hpp>

namespace cellfx::fx {

// Premultiplied front-to-back colour ∫₀ˡ c(t)σ(t)·exp(−∫₀ᵗ σ) dt, alpha = 1 − exp(−τ) and the
// optical depth τ = ∫₀ˡ σ.
struct SegmentColor {
    glm::dvec3 color{0.0};
    double alpha = 0.0;
    double optical_depth = 0.0; // τ
};

} // namespace cellfx::fx
