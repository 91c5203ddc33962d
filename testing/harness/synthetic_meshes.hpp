// cellfx — synthetic curvilinear meshes for tests and benchmarks.
//
// append_curvilinear_block() adds one structured grid (a block of hexahedra in VTK order, its
// own points, dims = node counts) whose nodes come from a mapping of the unit cube; tests
// build slabs, boxes and C-shapes with it. make_nine_grid_mesh() builds a stand-in for the
// NASA space-shuttle data set of Wilhelms, Tarantino & Van Gelder 1995, Table 3: nine
// intersecting, curved grids with the table's node counts (941,159 points at resolution 1)
// and a smooth scalar field "density" in [0, 1]. The real data set is not redistributable;
// this one has its size and structure (several blocks that overlap in space), not its shape.
// make_curved_duct() builds a finite-element-like, non-convex mesh of any size for benchmarks.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include <glm/vec3.hpp>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

// Appends a block of (ni−1)(nj−1)(nk−1) hexahedra; node (i, j, k) is at
// map(i/(ni−1), j/(nj−1), k/(nk−1)). Every dimension must be ≥ 2 (throws fx::Error).
// Existing scalar fields are extended with zeros for the new points.
void append_curvilinear_block(CellMesh& mesh, const std::string& name, std::array<std::uint32_t, 3> dims,
                              const std::function<glm::dvec3(double u, double v, double w)>& map);

// Adds (or replaces) a scalar field with value fn(point) at every point.
void set_scalar_field(CellMesh& mesh, const std::string& name, const std::function<double(const glm::dvec3&)>& fn);

// Table 3's grid dimensions (node counts), grids 1 to 9.
const std::array<std::array<std::uint32_t, 3>, 9>& shuttle_grid_dimensions();

// The nine-grid data set inside roughly [−1, 1]³. `resolution` scales every node count
// (at least 2 per axis): 1.0 gives Table 3's dimensions, 0.1 a small mesh for tests.
CellMesh make_nine_grid_mesh(double resolution = 1.0);

// A curved duct: a 240° sector of a thick cylindrical shell around the z axis (radius 1 to
// 1.7, height about 1, its top undulating), one curvilinear block of positively oriented
// hexahedra with a smooth field "temperature" (two waves and a hot spot, about 0.1 to 1.1).
// Non-convex: a view into the sector's gap sees rays cross one arm, leave the mesh and enter
// the far side. `tetrahedra`: the grid cut into consistent tetrahedra (tetrahedralize(), 5 or
// 6 per hexahedron), a stand-in for an FEM mesh. Node spacing is chosen so that the mesh has
// about `cells` cells (at least 6 tetrahedra or 1 hexahedron).
CellMesh make_curved_duct(std::size_t cells, bool tetrahedra);

} // namespace cellfx::fx
