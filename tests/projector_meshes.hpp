// Test meshes for the projector and the PCP/MIP frame tests: one cell of each type, a mixed
// mesh with tetrahedra, pyramids, wedges and hexahedra, and deterministic noise fields.
#pragma once

#include <cmath>
#include <cstdint>

#include "fx/cell_mesh.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace fx_test {

// Four separate cells side by side along x: tetra, pyramid, wedge, hexahedron (VTK order,
// positively oriented), scalar "s" = x + 2y + 3z over [0, 1]-ish.
inline fx::CellMesh one_of_each_cell() {
    fx::CellMesh m;
    auto add_points = [&](std::initializer_list<glm::dvec3> pts, double dx) {
        const std::uint32_t base = std::uint32_t(m.points.size());
        for (const glm::dvec3& p : pts) m.points.push_back(p + glm::dvec3(dx, 0, 0));
        return base;
    };
    std::uint32_t b = add_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, 0.0);
    const std::uint32_t tet[4] = {b, b + 1, b + 2, b + 3};
    m.add_cell(fx::CellType::Tetra, tet);
    b = add_points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}}, 1.5);
    const std::uint32_t pyr[5] = {b, b + 1, b + 2, b + 3, b + 4};
    m.add_cell(fx::CellType::Pyramid, pyr);
    // VTK wedge: (0,1,2) bottom triangle facing away from (3,4,5).
    b = add_points({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}}, 3.0);
    const std::uint32_t wedge[6] = {b, b + 1, b + 2, b + 3, b + 4, b + 5};
    m.add_cell(fx::CellType::Wedge, wedge);
    b = add_points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, 4.5);
    const std::uint32_t hex[8] = {b, b + 1, b + 2, b + 3, b + 4, b + 5, b + 6, b + 7};
    m.add_cell(fx::CellType::Hexahedron, hex);
    fx::ScalarField s{"s", {}};
    for (const glm::dvec3& p : m.points) s.values.push_back(float((p.x / 5.5 + 2.0 * p.y + 3.0 * p.z) / 6.0));
    m.scalars.push_back(std::move(s));
    return m;
}

} // namespace fx_test
