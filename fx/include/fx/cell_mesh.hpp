// cellfx — unstructured cell meshes: points, per-point scalar fields, mixed convex cells, blocks.
//
// Cells use VTK's vertex order and type ids (tetra 10, hexahedron 12, wedge 13, pyramid 14).
// A cell is "positively oriented" when its faces, as listed by cell_faces(), wind
// counter-clockwise seen from outside (outward normals by the right-hand rule); for VTK
// hexahedra and tetrahedra that is the usual order, for wedges VTK's (0,1,2) base faces away
// from (3,4,5). orient_cells() in mesh_validation.hpp fixes meshes with mixed winding.
//
// A mesh is split into blocks (grids): consecutive ranges of cells, e.g. the zones of a
// PLOT3D file. Renderers that handle intersecting grids (scan-line) toggle inside/outside per
// block. Points are doubles so that meshes far from the origin keep their precision on the
// CPU; scalars are floats, as in the files they come from.
//
// Ownership: CellMesh is a plain value type. Indices in `connectivity` must reference
// `points` (check with validate_mesh() before trusting a mesh from a file).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

namespace cellfx::fx {

enum class CellType : std::uint8_t {
    Tetra = 10,
    Hexahedron = 12,
    Wedge = 13,
    Pyramid = 14,
};

// Coordinates cellfx renders (meshes, effects, terrain): |x|, |y|, |z| at most this. Beyond
// it lengths lose their meaning in the GPU paths' float arithmetic (squares overflow near
// 1.8e19). Readers accept any finite coordinate; renderers and effects refuse larger ones.
constexpr double kMaxCoordinate = 1.0e18;

constexpr int kMaxCellVertices = 8;
constexpr int kMaxCellFaces = 6;

// Vertex indices (local to the cell) of one face, outward winding. count is 3 or 4.
struct CellFace {
    std::uint8_t count;
    std::uint8_t v[4];
};

int cell_vertex_count(CellType type);
int cell_face_count(CellType type);
const CellFace* cell_faces(CellType type); // cell_face_count(type) entries
const char* cell_type_name(CellType type);  // "tetra", "hexahedron", ...
// VTK cell type id → CellType. Returns false for types cellfx does not render (2-D/1-D/0-D
// cells, quadratic cells). VTK_VOXEL (11) is accepted by readers after reordering to a
// hexahedron, not here.
bool cell_type_from_vtk(int vtk_type, CellType& type);

// One value per point.
struct ScalarField {
    std::string name;
    std::vector<float> values;
};

// A grid inside the mesh: cells [first_cell, first_cell + cell_count). For structured blocks
// (PLOT3D, VTK STRUCTURED_GRID) dims holds the node counts ni, nj, nk; otherwise all zero.
struct Block {
    std::string name;
    std::uint32_t first_cell = 0;
    std::uint32_t cell_count = 0;
    std::array<std::uint32_t, 3> dims{0, 0, 0};
};

struct Bounds {
    glm::dvec3 lo{0.0};
    glm::dvec3 hi{0.0};
    bool empty() const { return lo.x > hi.x; }
    glm::dvec3 center() const { return 0.5 * (lo + hi); }
    glm::dvec3 size() const { return hi - lo; }
    // Corner k of 8: bit 0 of k picks hi.x over lo.x, bit 1 hi.y, bit 2 hi.z.
    glm::dvec3 corner(int k) const { return {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z}; }
};

struct CellMesh {
    std::vector<glm::dvec3> points;
    std::vector<ScalarField> scalars;
    std::vector<CellType> cell_types;
    std::vector<std::uint32_t> cell_offsets{0}; // cell c uses connectivity[offsets[c], offsets[c+1])
    std::vector<std::uint32_t> connectivity;
    std::vector<Block> blocks; // cover all cells in order; add_cell() extends the last block

    std::size_t point_count() const { return points.size(); }
    std::size_t cell_count() const { return cell_types.size(); }
    const std::uint32_t* cell_vertices(std::size_t cell) const { return &connectivity[cell_offsets[cell]]; }
    std::uint32_t* cell_vertices(std::size_t cell) { return &connectivity[cell_offsets[cell]]; }

    // Appends a cell to the last block (a first block named "0" is made if there is none).
    void add_cell(CellType type, const std::uint32_t* vertices);
    // Starts a new, empty block; following add_cell() calls fill it.
    void begin_block(std::string name, std::array<std::uint32_t, 3> dims = {0, 0, 0});

    const ScalarField* find_scalar(std::string_view name) const; // nullptr if absent
    // Bytes held by points, scalars, cells and blocks (capacity, not size).
    std::size_t memory_bytes() const;
};

// What changed in a mesh since someone last took it (an effect's mesh between two uploads, for
// fx::CellRenderer::update_mesh): the ids of the points whose position or scalars changed and of
// the cells whose points changed, each cell keeping its type; ids at or past the previous counts
// are new, and the mesh may have fewer cells than before (the last ones gone). `whole`: anything
// may have changed (a mesh to take anew).
struct MeshChanges {
    bool whole = true;
    std::vector<std::uint32_t> points;
    std::vector<std::uint32_t> cells;
    // The changed cells are positively oriented or flat, as their maker built them (terrain
    // prisms): a renderer need not check and flip them (fx::orient_cells).
    bool oriented = false;
    // Back to "nothing changed", keeping the lists' storage.
    void clear() { whole = false, points.clear(), cells.clear(); }
};

// Splits a cell face into triangles with global vertex indices, outward winding kept. A quad
// is cut by the diagonal from its smallest global vertex index (Max, Williams & Silva 2000,
// §IV), so the two cells sharing it always agree. Returns the number of triangles (1 or 2).
int triangulate_face(const CellFace& face, const std::uint32_t* cell_vertices, std::uint32_t out[2][3]);
// The same triangles as the cell's local vertex numbers (0 .. cell_vertex_count − 1).
int triangulate_face_local(const CellFace& face, const std::uint32_t* cell_vertices, std::uint8_t out[2][3]);

// Bounds of the points referenced by cells (unreferenced points are ignored). Empty bounds
// (lo > hi) for a mesh with no cells.
Bounds mesh_bounds(const CellMesh& mesh);

struct ScalarRange {
    float lo = 0.0f;
    float hi = 0.0f;
};
// Range of the finite values of a field.
ScalarRange scalar_range(const ScalarField& field);

} // namespace cellfx::fx
