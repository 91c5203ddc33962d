#include <catch2/catch.hpp>

#include <set>

#include <glm/geometric.hpp>

#include "fx/cell_mesh.hpp"
#include "cellfx_names.hpp"

namespace {

// Reference (undeformed) coordinates of each VTK cell type's vertices.
std::vector<glm::dvec3> reference_cell(fx::CellType type) {
    switch (type) {
    case fx::CellType::Tetra: return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    case fx::CellType::Pyramid: return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
    case fx::CellType::Wedge: return {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
    case fx::CellType::Hexahedron:
        return {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    }
    return {};
}

} // namespace

TEST_CASE("face tables wind outward and close every cell type", "[cell_mesh]") {
    for (fx::CellType type : {fx::CellType::Tetra, fx::CellType::Pyramid, fx::CellType::Wedge, fx::CellType::Hexahedron}) {
        CAPTURE(fx::cell_type_name(type));
        const auto p = reference_cell(type);
        REQUIRE(int(p.size()) == fx::cell_vertex_count(type));
        glm::dvec3 centre(0.0);
        for (const auto& q : p) centre += q / double(p.size());
        const fx::CellFace* faces = fx::cell_faces(type);
        std::multiset<std::pair<int, int>> edges;
        for (int f = 0; f < fx::cell_face_count(type); ++f) {
            const fx::CellFace& face = faces[f];
            const glm::dvec3 n = glm::cross(p[face.v[1]] - p[face.v[0]], p[face.v[2]] - p[face.v[0]]);
            CHECK(glm::dot(n, p[face.v[0]] - centre) > 0.0); // outward
            for (int i = 0; i < face.count; ++i) edges.insert({face.v[i], face.v[(i + 1) % face.count]});
        }
        // Closed and consistently wound: every directed edge appears once, reversed once.
        for (const auto& [a, b] : edges) {
            CHECK(edges.count({a, b}) == 1);
            CHECK(edges.count({b, a}) == 1);
        }
    }
}

TEST_CASE("cells go into blocks, bounds skip unreferenced points", "[cell_mesh]") {
    fx::CellMesh mesh;
    mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {100, 100, 100}};
    const std::uint32_t tet[] = {0, 1, 2, 3};
    mesh.add_cell(fx::CellType::Tetra, tet);
    mesh.begin_block("second");
    mesh.add_cell(fx::CellType::Tetra, tet);
    mesh.add_cell(fx::CellType::Tetra, tet);
    REQUIRE(mesh.blocks.size() == 2);
    CHECK(mesh.blocks[0].cell_count == 1);
    CHECK(mesh.blocks[1].first_cell == 1);
    CHECK(mesh.blocks[1].cell_count == 2);
    CHECK(mesh.cell_vertices(2)[3] == 3);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    CHECK(b.hi == glm::dvec3(1, 1, 1));
    CHECK(mesh.memory_bytes() > 0);
}
