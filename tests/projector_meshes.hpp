// Test meshes for the projector and the PCP/MIP frame tests: one cell of each type, a mixed
// mesh with tetrahedra, pyramids, wedges and hexahedra, and deterministic noise fields.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

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

// Cells the projector's planar test tells apart (gl_interface.hpp, kPlanarTolerance), side by
// side and apart from each other: a regular box of hexahedra (planar), a bent block (an annular
// sector with a rising floor: curvilinear hexahedra whose faces stay flat within the tolerance),
// a block whose quads fold (its inner nodes moved by up to 12% of the spacing: far beyond it),
// and a layer of terrain-fog wedges (vertical prisms over a triangulated height field, thicker
// in the middle and of no thickness on the layer's rim, as terrain fog thins out: flat by
// construction; a wedge with one corner on the rim has a side quad collapsed to a triangle,
// planar, one with two has a side of no area, not planar). Scalar "s": smooth over the whole, in
// about [0, 1].
inline fx::CellMesh planar_and_folded_grid() {
    fx::CellMesh m = hex_box(4, 4, 3, {0.0, 0.0, 0.0}, {1.0, 1.0, 0.75});
    const auto append_block = [&](const fx::CellMesh& block) {
        const std::uint32_t base = std::uint32_t(m.points.size());
        m.points.insert(m.points.end(), block.points.begin(), block.points.end());
        m.begin_block("block");
        for (std::size_t c = 0; c < block.cell_count(); ++c) {
            std::uint32_t v[8];
            for (int k = 0; k < fx::cell_vertex_count(block.cell_types[c]); ++k) v[k] = base + block.cell_vertices(c)[k];
            m.add_cell(block.cell_types[c], v);
        }
    };
    // Bent: node (i, j, k) of a 4 × 3 × 3 grid at angle 40°·i/4, radius 1 + 0.1·j, height
    // 0.25·k + 0.03·angle: quads on a cylinder or a helix, flat within 1e-3 of their size.
    fx::CellMesh bent = hex_box(4, 3, 3);
    for (glm::dvec3& p : bent.points) {
        const double a = glm::radians(40.0) * p.x, r = 1.0 + 0.3 * p.y;
        p = glm::dvec3(1.6 + r * std::cos(a), r * std::sin(a) - 0.4, 0.75 * p.z + 0.03 * a);
    }
    append_block(bent);
    // Folded: a 4 × 4 × 3 box beside the first whose inner nodes move by a fixed pattern.
    fx::CellMesh folded = hex_box(4, 4, 3, {0.0, 1.3, 0.0}, {1.0, 2.3, 0.75});
    for (std::size_t i = 0; i < folded.points.size(); ++i) {
        glm::dvec3& p = folded.points[i];
        const bool inner = p.x > 0.01 && p.x < 0.99 && p.y > 1.31 && p.y < 2.29 && p.z > 0.01 && p.z < 0.74;
        if (inner) p += 0.03 * glm::dvec3(std::sin(7.1 * double(i)), std::cos(5.3 * double(i)), std::sin(3.7 * double(i) + 1.0));
    }
    append_block(folded);
    // Fog: prisms over a 4 × 4 grid of squares cut into triangles, ground undulating, the layer
    // 0.4 thick in the middle and exactly 0 on the grid's border (the top point on the ground
    // point, as fx's terrain layers make it); the two wedges with every corner there have no
    // volume and are left out, as the terrain leaves them.
    fx::CellMesh fog;
    const auto ground = [](double x, double y) { return 0.1 * std::sin(3.0 * x) * std::cos(2.0 * y); };
    const auto thickness = [](int i, int j) { return 0.4 * double(i * (4 - i) * j * (4 - j)) / 16.0; };
    for (int layer = 0; layer < 2; ++layer)
        for (int j = 0; j <= 4; ++j)
            for (int i = 0; i <= 4; ++i) {
                const double x = 1.3 + 0.25 * i, y = 1.3 + 0.25 * j, g = ground(x, y);
                fog.points.emplace_back(x, y, layer == 0 ? g : g + thickness(i, j));
            }
    const auto node = [](int i, int j, int layer) { return std::uint32_t(layer * 25 + j * 5 + i); };
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const std::uint32_t a = node(i, j, 0), b = node(i + 1, j, 0), c = node(i + 1, j + 1, 0), d = node(i, j + 1, 0);
            const std::uint32_t w1[6] = {a, b, c, a + 25, b + 25, c + 25}, w2[6] = {a, c, d, a + 25, c + 25, d + 25};
            for (const std::uint32_t* w : {w1, w2}) {
                const double volume = thickness(int(w[0] % 5), int(w[0] / 5)) + thickness(int(w[1] % 5), int(w[1] / 5)) +
                                      thickness(int(w[2] % 5), int(w[2] / 5));
                if (volume > 0.0) fog.add_cell(fx::CellType::Wedge, w);
            }
        }
    append_block(fog);
    fx::ScalarField s{"s", {}};
    for (const glm::dvec3& p : m.points)
        s.values.push_back(float(0.5 + 0.3 * std::sin(2.0 * p.x + 1.0) * std::cos(1.5 * p.y) + 0.4 * (p.z - 0.3)));
    m.scalars.push_back(std::move(s));
    return m;
}

} // namespace fx_test
