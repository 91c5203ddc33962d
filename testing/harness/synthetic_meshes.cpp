// Based on: Wilhelms, Tarantino & Van Gelder 1995, §4.1 and Table 3 (data-set dimensions)
#include "harness/synthetic_meshes.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"
#include "mesh/tetrahedralize.hpp"

namespace cellfx::fx {

void append_curvilinear_block(CellMesh& mesh, const std::string& name, std::array<std::uint32_t, 3> dims,
                              const std::function<glm::dvec3(double u, double v, double w)>& map) {
    const std::uint32_t ni = dims[0], nj = dims[1], nk = dims[2];
    if (ni < 2 || nj < 2 || nk < 2) {
        throw Error("synthetic mesh: block '" + name + "' needs at least 2 nodes per axis");
    }
    const auto base = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.reserve(mesh.points.size() + std::size_t(ni) * nj * nk);
    for (std::uint32_t k = 0; k < nk; ++k) {
        for (std::uint32_t j = 0; j < nj; ++j) {
            for (std::uint32_t i = 0; i < ni; ++i) {
                mesh.points.push_back(map(double(i) / (ni - 1), double(j) / (nj - 1), double(k) / (nk - 1)));
            }
        }
    }
    for (ScalarField& f : mesh.scalars) f.values.resize(mesh.points.size(), 0.0f);
    mesh.begin_block(name, dims);
    auto node = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return base + (k * nj + j) * ni + i; };
    for (std::uint32_t k = 0; k + 1 < nk; ++k) {
        for (std::uint32_t j = 0; j + 1 < nj; ++j) {
            for (std::uint32_t i = 0; i + 1 < ni; ++i) {
                const std::uint32_t v[8] = {node(i, j, k),         node(i + 1, j, k),     node(i + 1, j + 1, k),
                                            node(i, j + 1, k),     node(i, j, k + 1),     node(i + 1, j, k + 1),
                                            node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)};
                mesh.add_cell(CellType::Hexahedron, v);
            }
        }
    }
}

void set_scalar_field(CellMesh& mesh, const std::string& name, const std::function<double(const glm::dvec3&)>& fn) {
    ScalarField* field = nullptr;
    for (ScalarField& f : mesh.scalars) {
        if (f.name == name) field = &f;
    }
    if (!field) {
        mesh.scalars.push_back(ScalarField{name, {}});
        field = &mesh.scalars.back();
    }
    field->values.resize(mesh.points.size());
    for (std::size_t i = 0; i < mesh.points.size(); ++i) field->values[i] = static_cast<float>(fn(mesh.points[i]));
}

const std::array<std::array<std::uint32_t, 3>, 9>& shuttle_grid_dimensions() {
    static const std::array<std::array<std::uint32_t, 3>, 9> dims = {{
        {88, 39, 60}, {92, 57, 28}, {98, 77, 48}, {24, 33, 23}, {33, 33, 22},
        {25, 40, 21}, {75, 37, 33}, {14, 25, 30}, {53, 23, 50},
    }};
    return dims;
}

CellMesh make_nine_grid_mesh(double resolution) {
    if (!(resolution > 0.0) || !std::isfinite(resolution)) throw Error("synthetic mesh: resolution must be > 0");
    // Per grid: centre, half extents, rotation about z (radians), bend of the middle
    // surface, twist about the grid's own k axis. Grids overlap their neighbours.
    struct Shape {
        glm::dvec3 centre, half;
        double yaw, bend, twist;
    };
    static const Shape shapes[9] = {
        {{0.0, 0.0, 0.0}, {0.95, 0.35, 0.45}, 0.00, 0.15, 0.25},   // the fuselage-like core
        {{0.15, 0.0, 0.45}, {0.80, 0.40, 0.18}, 0.10, -0.12, 0.10},
        {{-0.1, 0.1, -0.35}, {0.90, 0.55, 0.30}, -0.15, 0.10, -0.20},
        {{0.75, 0.45, 0.10}, {0.22, 0.25, 0.20}, 0.50, 0.05, 0.30},
        {{0.70, -0.45, 0.05}, {0.25, 0.25, 0.20}, -0.45, -0.05, -0.25},
        {{-0.75, 0.40, 0.20}, {0.20, 0.30, 0.18}, 0.80, 0.08, 0.20},
        {{-0.30, -0.55, 0.10}, {0.55, 0.22, 0.25}, 0.25, 0.10, 0.15},
        {{-0.85, -0.30, -0.25}, {0.12, 0.22, 0.28}, -0.60, 0.03, -0.30},
        {{0.35, 0.60, -0.30}, {0.40, 0.18, 0.35}, -0.30, -0.08, 0.20},
    };
    CellMesh mesh;
    const auto& dims = shuttle_grid_dimensions();
    for (int g = 0; g < 9; ++g) {
        std::array<std::uint32_t, 3> d;
        for (int a = 0; a < 3; ++a) {
            d[a] = std::max<std::uint32_t>(2, static_cast<std::uint32_t>(std::lround(dims[g][a] * resolution)));
        }
        const Shape s = shapes[g];
        append_curvilinear_block(mesh, "grid" + std::to_string(g + 1), d, [s](double u, double v, double w) {
            const double x = (2.0 * u - 1.0) * s.half.x;
            double y = (2.0 * v - 1.0) * s.half.y;
            double z = (2.0 * w - 1.0) * s.half.z;
            // Bend: the block's middle surface arches along x; twist: rotate (y, z) with x.
            z += s.bend * (1.0 - (2.0 * u - 1.0) * (2.0 * u - 1.0));
            const double a = s.twist * (2.0 * u - 1.0);
            const double yr = y * std::cos(a) - z * std::sin(a);
            const double zr = y * std::sin(a) + z * std::cos(a);
            y = yr;
            z = zr;
            const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
            return s.centre + glm::dvec3(c * x - sn * y, sn * x + c * y, z);
        });
    }
    set_scalar_field(mesh, "density", [](const glm::dvec3& p) {
        const double v = 0.5 + 0.25 * std::sin(3.0 * p.x + 1.0) * std::cos(2.0 * p.y) + 0.2 * std::sin(2.5 * p.z + p.x);
        return std::clamp(v, 0.0, 1.0);
    });
    return mesh;
}

CellMesh make_curved_duct(std::size_t cells, bool tetrahedra) {
    // Node spacing h from the wanted count: arc (at mid radius) 5.65, radial 0.7, height 1.0;
    // a hexahedron gives 5.5 tetrahedra on average.
    const double hexes = std::max(1.0, double(cells) / (tetrahedra ? 5.5 : 1.0));
    const double h = std::cbrt(5.65 * 0.7 * 1.0 / hexes);
    const auto nodes = [h](double length) { return std::max(1u, std::uint32_t(std::lround(length / h))) + 1; };
    CellMesh mesh;
    append_curvilinear_block(mesh, "duct", {std::max(3u, nodes(5.65)), nodes(0.7), nodes(1.0)},
                             [](double u, double v, double w) {
                                 // Angle falling with u, radius growing with v, height with w:
                                 // right-handed, so the cells are positively oriented.
                                 const double a = glm::radians(210.0 - 240.0 * u), r = 1.0 + 0.7 * v;
                                 return glm::dvec3(r * std::cos(a), r * std::sin(a), w * (1.0 + 0.15 * std::sin(2.0 * a)));
                             });
    set_scalar_field(mesh, "temperature", [](const glm::dvec3& p) {
        const glm::dvec3 hot(-0.9, 1.0, 0.5);
        return 0.35 + 0.25 * std::sin(2.5 * p.x + 1.0) * std::cos(2.0 * p.y) + 0.3 * p.z +
               0.45 * std::exp(-glm::dot(p - hot, p - hot) / 0.15);
    });
    return tetrahedra ? tetrahedralize(mesh) : mesh;
}

} // namespace cellfx::fx
