// Small synthetic meshes for tests: structured hexahedral boxes and a mixed-cell box.
#pragma once

#include <cstdint>
#include <random>

#include "fx/cell_mesh.hpp"
#include "mesh/tetrahedralize.hpp"
#include "cellfx_names.hpp"

namespace fx_test {

// An nx × ny × nz grid of hexahedra spanning [lo, hi], points numbered i fastest.
inline fx::CellMesh hex_box(int nx, int ny, int nz, glm::dvec3 lo = glm::dvec3(0.0), glm::dvec3 hi = glm::dvec3(1.0)) {
    fx::CellMesh mesh;
    auto id = [&](int i, int j, int k) { return std::uint32_t((k * (ny + 1) + j) * (nx + 1) + i); };
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i)
                mesh.points.push_back(lo + (hi - lo) * glm::dvec3(double(i) / nx, double(j) / ny, double(k) / nz));
    mesh.begin_block("box", {std::uint32_t(nx + 1), std::uint32_t(ny + 1), std::uint32_t(nz + 1)});
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                const std::uint32_t v[8] = {id(i, j, k),         id(i + 1, j, k),     id(i + 1, j + 1, k),
                                            id(i, j + 1, k),     id(i, j, k + 1),     id(i + 1, j, k + 1),
                                            id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                mesh.add_cell(fx::CellType::Hexahedron, v);
            }
    return mesh;
}

// A conforming box of all four cell types: columns of wedges (each hexahedron of the column
// cut by the same vertical diagonal plane), hexahedra cut into six pyramids around an added
// centre point, and plain hexahedra.
inline fx::CellMesh mixed_box(int n) {
    fx::CellMesh grid = hex_box(n, n, n);
    fx::CellMesh mesh;
    mesh.points = grid.points;
    mesh.begin_block("mixed");
    for (std::size_t c = 0; c < grid.cell_count(); ++c) {
        const std::uint32_t* h = grid.cell_vertices(c);
        const int i = int(c) % n, j = (int(c) / n) % n;
        if ((i + j) % 3 == 0) {
            // Column of wedges: cut along the vertical plane through edges 0–4 and 2–6.
            const std::uint32_t w1[6] = {h[0], h[2], h[1], h[4], h[6], h[5]};
            const std::uint32_t w2[6] = {h[0], h[3], h[2], h[4], h[7], h[6]};
            mesh.add_cell(fx::CellType::Wedge, w1);
            mesh.add_cell(fx::CellType::Wedge, w2);
        } else if ((i + j) % 3 == 1 && (c / (n * n)) % 2 == 0) {
            glm::dvec3 centre(0.0);
            for (int v = 0; v < 8; ++v) centre += grid.points[h[v]] / 8.0;
            const std::uint32_t apex = std::uint32_t(mesh.points.size());
            mesh.points.push_back(centre);
            for (int f = 0; f < 6; ++f) {
                const fx::CellFace& face = fx::cell_faces(fx::CellType::Hexahedron)[f];
                // Pyramid base winds counter-clockwise seen from the apex (inward for the hex face).
                const std::uint32_t p[5] = {h[face.v[0]], h[face.v[3]], h[face.v[2]], h[face.v[1]], apex};
                mesh.add_cell(fx::CellType::Pyramid, p);
            }
        } else {
            mesh.add_cell(fx::CellType::Hexahedron, h);
        }
    }
    return mesh;
}

// mixed_box(n) with every fourth hexahedron replaced by its consistent tetrahedra: all four
// cell types and tetrahedra sharing faces with them. No scalar field.
inline fx::CellMesh mixed_box_with_tets(int n) {
    const fx::CellMesh base = mixed_box(n);
    fx::CellMesh mesh;
    mesh.points = base.points;
    mesh.begin_block("mixed");
    int hexes = 0;
    for (std::size_t c = 0; c < base.cell_count(); ++c) {
        const fx::CellType t = base.cell_types[c];
        if (t == fx::CellType::Hexahedron && hexes++ % 4 == 0) {
            std::uint32_t tets[fx::kMaxCellTetrahedra][4];
            const int k = fx::subdivide_cell(t, base.cell_vertices(c), tets);
            for (int i = 0; i < k; ++i) mesh.add_cell(fx::CellType::Tetra, tets[i]);
        } else {
            mesh.add_cell(t, base.cell_vertices(c));
        }
    }
    return mesh;
}

// Renumbers the points of a mesh by a random permutation (cells keep their shape).
inline void shuffle_point_ids(fx::CellMesh& mesh, std::mt19937& rng) {
    std::vector<std::uint32_t> perm(mesh.point_count());
    for (std::uint32_t i = 0; i < perm.size(); ++i) perm[i] = i;
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<glm::dvec3> points(mesh.point_count());
    for (std::size_t i = 0; i < perm.size(); ++i) points[perm[i]] = mesh.points[i];
    for (fx::ScalarField& f : mesh.scalars) {
        std::vector<float> values(f.values.size());
        for (std::size_t i = 0; i < perm.size(); ++i) values[perm[i]] = f.values[i];
        f.values = std::move(values);
    }
    mesh.points = std::move(points);
    for (std::uint32_t& v : mesh.connectivity) v = perm[v];
}

// Mirrors the vertex order of every other cell (the inverse of fx::orient_cells: tetra swap
// 1 and 2, pyramid reverse the base, wedge and hexahedron swap the end faces), so their faces
// wind inward, as in a file written with the other convention.
inline void invert_every_other_cell(fx::CellMesh& mesh) {
    for (std::size_t c = 0; c < mesh.cell_count(); c += 2) {
        std::uint32_t* v = mesh.cell_vertices(c);
        switch (mesh.cell_types[c]) {
        case fx::CellType::Tetra: std::swap(v[1], v[2]); break;
        case fx::CellType::Pyramid: std::swap(v[1], v[3]); break;
        case fx::CellType::Wedge: std::swap_ranges(v, v + 3, v + 3); break;
        case fx::CellType::Hexahedron: std::swap_ranges(v, v + 4, v + 4); break;
        }
    }
}

} // namespace fx_test
