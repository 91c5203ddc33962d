#include "fx/cell_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

namespace cellfx::fx {
namespace {

// Face tables in VTK's vertex order, every face wound counter-clockwise seen from outside.
constexpr CellFace kTetraFaces[] = {
    {3, {0, 1, 3, 0}}, {3, {1, 2, 3, 0}}, {3, {2, 0, 3, 0}}, {3, {0, 2, 1, 0}},
};
constexpr CellFace kPyramidFaces[] = {
    {4, {0, 3, 2, 1}}, {3, {0, 1, 4, 0}}, {3, {1, 2, 4, 0}}, {3, {2, 3, 4, 0}}, {3, {3, 0, 4, 0}},
};
constexpr CellFace kWedgeFaces[] = {
    {3, {0, 1, 2, 0}}, {3, {3, 5, 4, 0}}, {4, {0, 3, 4, 1}}, {4, {1, 4, 5, 2}}, {4, {2, 5, 3, 0}},
};
constexpr CellFace kHexahedronFaces[] = {
    {4, {0, 4, 7, 3}}, {4, {1, 2, 6, 5}}, {4, {0, 1, 5, 4}},
    {4, {3, 7, 6, 2}}, {4, {0, 3, 2, 1}}, {4, {4, 5, 6, 7}},
};

} // namespace

int cell_vertex_count(CellType type) {
    switch (type) {
    case CellType::Tetra: return 4;
    case CellType::Pyramid: return 5;
    case CellType::Wedge: return 6;
    case CellType::Hexahedron: return 8;
    }
    return 0;
}

int cell_face_count(CellType type) {
    switch (type) {
    case CellType::Tetra: return 4;
    case CellType::Pyramid: return 5;
    case CellType::Wedge: return 5;
    case CellType::Hexahedron: return 6;
    }
    return 0;
}

const CellFace* cell_faces(CellType type) {
    switch (type) {
    case CellType::Tetra: return kTetraFaces;
    case CellType::Pyramid: return kPyramidFaces;
    case CellType::Wedge: return kWedgeFaces;
    case CellType::Hexahedron: return kHexahedronFaces;
    }
    return nullptr;
}

const char* cell_type_name(CellType type) {
    switch (type) {
    case CellType::Tetra: return "tetra";
    case CellType::Pyramid: return "pyramid";
    case CellType::Wedge: return "wedge";
    case CellType::Hexahedron: return "hexahedron";
    }
    return "unknown";
}

bool cell_type_from_vtk(int vtk_type, CellType& type) {
    switch (vtk_type) {
    case 10: type = CellType::Tetra; return true;
    case 12: type = CellType::Hexahedron; return true;
    case 13: type = CellType::Wedge; return true;
    case 14: type = CellType::Pyramid; return true;
    default: return false;
    }
}

int triangulate_face_local(const CellFace& face, const std::uint32_t* cell_vertices, std::uint8_t out[2][3]) {
    if (face.count == 3) {
        out[0][0] = face.v[0], out[0][1] = face.v[1], out[0][2] = face.v[2];
        return 1;
    }
    // Start the fan at the smallest vertex: its diagonal is the only one through it.
    int k = 0;
    for (int i = 1; i < 4; ++i) {
        if (cell_vertices[face.v[i]] < cell_vertices[face.v[k]]) k = i;
    }
    const std::uint8_t a = face.v[k], b = face.v[(k + 1) % 4], c = face.v[(k + 2) % 4], d = face.v[(k + 3) % 4];
    out[0][0] = a, out[0][1] = b, out[0][2] = c;
    out[1][0] = a, out[1][1] = c, out[1][2] = d;
    return 2;
}

int triangulate_face(const CellFace& face, const std::uint32_t* cell_vertices, std::uint32_t out[2][3]) {
    std::uint8_t local[2][3];
    const int n = triangulate_face_local(face, cell_vertices, local);
    for (int t = 0; t < n; ++t)
        for (int i = 0; i < 3; ++i) out[t][i] = cell_vertices[local[t][i]];
    return n;
}

void CellMesh::add_cell(CellType type, const std::uint32_t* vertices) {
    if (blocks.empty()) {
        blocks.push_back(Block{"0", static_cast<std::uint32_t>(cell_count()), 0, {0, 0, 0}});
    }
    cell_types.push_back(type);
    connectivity.insert(connectivity.end(), vertices, vertices + cell_vertex_count(type));
    cell_offsets.push_back(static_cast<std::uint32_t>(connectivity.size()));
    blocks.back().cell_count++;
}

void CellMesh::begin_block(std::string name, std::array<std::uint32_t, 3> dims) {
    blocks.push_back(Block{std::move(name), static_cast<std::uint32_t>(cell_count()), 0, dims});
}

const ScalarField* CellMesh::find_scalar(std::string_view name) const {
    for (const ScalarField& f : scalars) {
        if (f.name == name) return &f;
    }
    return nullptr;
}

std::size_t CellMesh::memory_bytes() const {
    std::size_t bytes = points.capacity() * sizeof(glm::dvec3) + cell_types.capacity() * sizeof(CellType) +
                        cell_offsets.capacity() * sizeof(std::uint32_t) +
                        connectivity.capacity() * sizeof(std::uint32_t) + blocks.capacity() * sizeof(Block);
    for (const ScalarField& f : scalars) bytes += f.values.capacity() * sizeof(float) + f.name.capacity();
    return bytes;
}

Bounds mesh_bounds(const CellMesh& mesh) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    Bounds b{glm::dvec3(inf), glm::dvec3(-inf)};
    const std::size_t n = mesh.point_count();
    for (std::uint32_t v : mesh.connectivity) {
        if (v >= n) continue;
        const glm::dvec3& p = mesh.points[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

ScalarRange scalar_range(const ScalarField& field) {
    ScalarRange r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
    for (float v : field.values) {
        if (!std::isfinite(v)) continue;
        r.lo = std::min(r.lo, v);
        r.hi = std::max(r.hi, v);
    }
    if (r.lo > r.hi) r = ScalarRange{0.0f, 0.0f};
    return r;
}

} // namespace cellfx::fx
