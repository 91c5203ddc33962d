// A truncated cone of cells along local +z, shared by the search light and the laser cone.
//
// Slices k = 0..slices at z_k = range·k/slices; in each, a point on the axis and `rings` rings
// of `segments` points at radius R(z)·r/rings, R(z) = lens_radius + z·tan(half_angle). Between
// consecutive slices: wedges (VTK 13) around the axis and hexahedra (VTK 12) in the outer rings.
// Every point lies on a line through the cone's virtual apex, so every side face is planar and
// every cell convex; all cells are positively oriented (cell_mesh.hpp).
#pragma once

#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/medium.hpp"

namespace cellfx::fx::effects {

struct ConeShape {
    double range = 1.0;       // > 0
    double lens_radius = 0.1; // > 0
    double half_angle = 0.1;  // radians, [0, 89°]
    int segments = 16;        // ≥ 3
    int rings = 4;            // ≥ 1
    int slices = 32;          // ≥ 1
};

struct ConeMesh {
    CellMesh mesh;              // one block "cone", no scalars
    std::vector<double> along;  // per point: z / range ∈ [0, 1]
    std::vector<double> across; // per point: ρ / R(z) ∈ [0, 1]
};

ConeMesh build_cone_mesh(const ConeShape& shape);
// Radius of the cone at local z.
double cone_radius(const ConeShape& shape, double z);
// Local bounds of the whole cone.
Bounds cone_bounds(const ConeShape& shape);
// The cone's beam as a light of the medium (fx/medium.hpp), local frame: along +z from the
// lens, its rays diverging from the cone's apex, strength = scalar / intensity (0 < intensity).
MediumLight cone_light(const ConeShape& shape, double intensity);

} // namespace cellfx::fx::effects
