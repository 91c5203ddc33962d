// Based on: Roettger & Ertl 2003, Figure 2 and Table 4 (a search light of 16×4×32 nodes and a
// laser cone, both projected as convex cells).
#include "effects/cone_mesh.hpp"

#include <cmath>
#include <cstdint>

namespace cellfx::fx::effects {

namespace {
constexpr double kTwoPi = 6.283185307179586;
} // namespace

double cone_radius(const ConeShape& shape, double z) { return shape.lens_radius + z * std::tan(shape.half_angle); }

Bounds cone_bounds(const ConeShape& shape) {
    const double r = cone_radius(shape, shape.range);
    return {glm::dvec3(-r, -r, 0.0), glm::dvec3(r, r, shape.range)};
}

ConeMesh build_cone_mesh(const ConeShape& shape) {
    ConeMesh out;
    CellMesh& mesh = out.mesh;
    const int per_slice = 1 + shape.rings * shape.segments;
    mesh.points.reserve(std::size_t(per_slice) * (shape.slices + 1));
    for (int k = 0; k <= shape.slices; ++k) {
        const double u = double(k) / shape.slices;
        const double z = shape.range * u;
        const double radius = cone_radius(shape, z);
        mesh.points.emplace_back(0.0, 0.0, z);
        out.along.push_back(u);
        out.across.push_back(0.0);
        for (int r = 1; r <= shape.rings; ++r) {
            const double v = double(r) / shape.rings;
            for (int s = 0; s < shape.segments; ++s) {
                const double a = kTwoPi * s / shape.segments;
                mesh.points.emplace_back(radius * v * std::cos(a), radius * v * std::sin(a), z);
                out.along.push_back(u);
                out.across.push_back(v);
            }
        }
    }
    auto centre = [&](int k) { return std::uint32_t(k * per_slice); };
    auto ring = [&](int k, int r, int s) { // r ≥ 1; s taken modulo segments
        return std::uint32_t(k * per_slice + 1 + (r - 1) * shape.segments + (s % shape.segments));
    };
    mesh.begin_block("cone");
    for (int k = 0; k < shape.slices; ++k) {
        for (int s = 0; s < shape.segments; ++s) {
            // Wedge base (0, 1, 2) wound clockwise seen from +z, so it faces down, away from the top.
            const std::uint32_t w[6] = {centre(k),     ring(k, 1, s + 1),     ring(k, 1, s),
                                        centre(k + 1), ring(k + 1, 1, s + 1), ring(k + 1, 1, s)};
            mesh.add_cell(CellType::Wedge, w);
        }
        for (int r = 1; r < shape.rings; ++r) {
            for (int s = 0; s < shape.segments; ++s) {
                // Hexahedron bottom quad counter-clockwise seen from +z: out, around, in.
                const std::uint32_t h[8] = {ring(k, r, s),         ring(k, r + 1, s),
                                            ring(k, r + 1, s + 1), ring(k, r, s + 1),
                                            ring(k + 1, r, s),     ring(k + 1, r + 1, s),
                                            ring(k + 1, r + 1, s + 1), ring(k + 1, r, s + 1)};
                mesh.add_cell(CellType::Hexahedron, h);
            }
        }
    }
    return out;
}

MediumLight cone_light(const ConeShape& shape, double intensity) {
    MediumLight light;
    light.kind = MediumLight::Kind::Beam;
    const double spread = std::tan(shape.half_angle);
    light.apex_distance = spread > 0.0 ? shape.lens_radius / spread : 0.0;
    light.strength_per_scalar = intensity > 0.0 ? 1.0 / intensity : 0.0;
    return light;
}

} // namespace cellfx::fx::effects
