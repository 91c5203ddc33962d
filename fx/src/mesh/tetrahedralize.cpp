// Based on: Max, Williams & Silva 2000, §IV — the smallest-vertex diagonal rule.
#include "mesh/tetrahedralize.hpp"

#include <algorithm>
#include <utility>

#include <glm/geometric.hpp>

namespace cellfx::fx {
namespace {

// Reference cells in VTK order, positively oriented (see cell_mesh.hpp). Used only to orient
// output tetrahedra, never for geometry.
constexpr glm::dvec3 kRefTetra[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
constexpr glm::dvec3 kRefPyramid[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1}};
constexpr glm::dvec3 kRefWedge[] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
constexpr glm::dvec3 kRefHexahedron[] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

const glm::dvec3* reference_cell(CellType type) {
    switch (type) {
    case CellType::Tetra: return kRefTetra;
    case CellType::Pyramid: return kRefPyramid;
    case CellType::Wedge: return kRefWedge;
    case CellType::Hexahedron: return kRefHexahedron;
    }
    return kRefTetra;
}

// Collects tetrahedra as LOCAL vertex indices; decisions compare global indices g[local].
struct Builder {
    const std::uint32_t* g;
    int local[kMaxCellTetrahedra][4];
    int count = 0;

    void tet(int a, int b, int c, int d) {
        int* t = local[count++];
        t[0] = a, t[1] = b, t[2] = c, t[3] = d;
    }

    // Base quad q (cyclic order) and apex: cut the base by the diagonal from its smallest vertex.
    void pyramid(const int q[4], int apex) {
        int k = 0;
        for (int i = 1; i < 4; ++i) {
            if (g[q[i]] < g[q[k]]) k = i;
        }
        tet(q[k], q[(k + 1) % 4], q[(k + 2) % 4], apex);
        tet(q[k], q[(k + 2) % 4], q[(k + 3) % 4], apex);
    }

    // Triangles a and b with edges a[i]–b[i]. The smallest vertex L takes the diagonals of both
    // quads through it; the plane through them cuts off the tetrahedron (L, opposite triangle),
    // leaving a pyramid over the quad face that does not contain L.
    void wedge(const int a[3], const int b[3]) {
        const int* tri[2] = {a, b};
        int side = 0, i = 0;
        for (int s = 0; s < 2; ++s) {
            for (int j = 0; j < 3; ++j) {
                if (g[tri[s][j]] < g[tri[side][i]]) side = s, i = j;
            }
        }
        const int* own = tri[side];
        const int* other = tri[1 - side];
        tet(own[i], other[0], other[1], other[2]);
        const int base[4] = {own[(i + 1) % 3], own[(i + 2) % 3], other[(i + 2) % 3], other[(i + 1) % 3]};
        pyramid(base, own[i]);
    }

    void hexahedron() {
        // Work in cube coordinates (bit 0 = x, 1 = y, 2 = z), reflected so that the smallest
        // vertex A sits at 000 and the opposite vertex G at 111.
        static constexpr int kLocalOfBits[8] = {0, 1, 3, 2, 4, 5, 7, 6};
        static constexpr int kBitsOfLocal[8] = {0, 1, 3, 2, 4, 5, 7, 6};
        int smallest = 0;
        for (int i = 1; i < 8; ++i) {
            if (g[i] < g[smallest]) smallest = i;
        }
        const int a_bits = kBitsOfLocal[smallest];
        auto v = [&](int bits) { return kLocalOfBits[bits ^ a_bits]; };
        const int A = 0, G = 7;
        const int e[3] = {1, 2, 4};
        // On each face through G (coordinate k = 1) the diagonal passes through G exactly when
        // the face's smallest vertex is G or e_k, the face's vertex nearest A.
        for (int k = 0; k < 3; ++k) {
            const int i = (k + 1) % 3, j = (k + 2) % 3;
            const int face[4] = {e[k], e[k] | e[i], G, e[k] | e[j]};
            int least = 0;
            for (int m = 1; m < 4; ++m) {
                if (g[v(face[m])] < g[v(face[least])]) least = m;
            }
            if (face[least] != G && face[least] != e[k]) continue;
            // Slice A, e_k, G, G^e_k (diagonal A–G, A being smallest) into two wedges along k.
            const int b_k = G ^ e[k];
            const int w1a[3] = {v(A), v(e[i]), v(b_k)}, w1b[3] = {v(e[k]), v(e[i] | e[k]), v(G)};
            const int w2a[3] = {v(A), v(e[j]), v(b_k)}, w2b[3] = {v(e[k]), v(e[j] | e[k]), v(G)};
            wedge(w1a, w1b);
            wedge(w2a, w2b);
            return;
        }
        // No diagonal touches G: a central tetrahedron A, B_x, B_y, B_z (B_k = G ^ e_k) and
        // four corners.
        const int bx = G ^ e[0], by = G ^ e[1], bz = G ^ e[2];
        tet(v(A), v(bx), v(by), v(bz));
        tet(v(e[0]), v(A), v(by), v(bz));
        tet(v(e[1]), v(A), v(bx), v(bz));
        tet(v(e[2]), v(A), v(bx), v(by));
        tet(v(G), v(bx), v(by), v(bz));
    }
};

double reference_volume(const glm::dvec3* ref, const int t[4]) {
    return glm::dot(ref[t[1]] - ref[t[0]], glm::cross(ref[t[2]] - ref[t[0]], ref[t[3]] - ref[t[0]]));
}

} // namespace

int subdivide_cell(CellType type, const std::uint32_t* vertices, std::uint32_t out[kMaxCellTetrahedra][4]) {
    Builder b{vertices, {}, 0};
    switch (type) {
    case CellType::Tetra: b.tet(0, 1, 2, 3); break;
    case CellType::Pyramid: {
        const int base[4] = {0, 1, 2, 3};
        b.pyramid(base, 4);
        break;
    }
    case CellType::Wedge: {
        const int a[3] = {0, 1, 2}, top[3] = {3, 4, 5};
        b.wedge(a, top);
        break;
    }
    case CellType::Hexahedron: b.hexahedron(); break;
    }
    const glm::dvec3* ref = reference_cell(type);
    for (int t = 0; t < b.count; ++t) {
        int* l = b.local[t];
        if (reference_volume(ref, l) < 0.0) std::swap(l[1], l[2]);
        for (int i = 0; i < 4; ++i) out[t][i] = vertices[l[i]];
    }
    return b.count;
}

CellMesh tetrahedralize(const CellMesh& mesh, std::vector<std::uint32_t>* parent_cell) {
    CellMesh result;
    result.points = mesh.points;
    result.scalars = mesh.scalars;
    if (parent_cell) parent_cell->clear();
    std::uint32_t tets[kMaxCellTetrahedra][4];
    for (const Block& block : mesh.blocks) {
        result.begin_block(block.name, block.dims);
        for (std::uint32_t c = block.first_cell; c < block.first_cell + block.cell_count; ++c) {
            const int n = subdivide_cell(mesh.cell_types[c], mesh.cell_vertices(c), tets);
            for (int t = 0; t < n; ++t) {
                result.add_cell(CellType::Tetra, tets[t]);
                if (parent_cell) parent_cell->push_back(c);
            }
        }
    }
    return result;
}

} // namespace cellfx::fx
