// cellfx ⇄ VTK: what the ParaView plugin converts, kept free of GL and of ParaView so that it is
// tested on its own (paraview/tests/test_convert.cpp).
//
//   transfer_function_from_vtk  ParaView's colour map and opacity function and the volume's
//                               scalar-opacity unit distance → fx::TransferFunction, read as
//                               VTK's unstructured-grid volume mappers read them.
//   MeshConverter               a vtkUnstructuredGridBase (what ParaView hands a volume mapper)
//                               → fx::CellMesh with one scalar field, cells kept as they are.
//
// Transfer function. VTK's unstructured-grid mappers (projected tetrahedra, Bunyk, Z sweep and
// their ray integrators) all take colour = ctf.GetColor(s) and extinction per unit length
// = opacity.GetValue(s) / unit_distance, emission = colour × extinction (the volume density
// model, cellfx's own): the projected-tetrahedra mapper draws 1 − exp(−A·l/u) for a cell of
// thickness l; vtkUnstructuredGridLinearRayIntegrator and PartialPreIntegration build the same
// piecewise-linear function from both functions' nodes (and, for HSV, the hue bends). Here the
// same calls are made, at breakpoints that make the piecewise-linear result exact where VTK's
// functions are piecewise linear in RGB, and within about 10⁻³ elsewhere:
//   - every node of both functions and the data range's ends;
//   - at each breakpoint the one-sided limits (extrapolated from just inside each side): where
//     they differ (duplicate nodes, Clamping off, above/below-range colours) the point is
//     written twice, a step;
//   - between breakpoints, pieces are halved until straight within 10⁻³ at their eighths (Lab,
//     Diverging — ParaView's default "Cool to Warm" — and HSV colour spaces, node midpoints and
//     sharpness), at most 16 times. Lab/CIEDE2000, for which VTK computes a path on every
//     GetColor (~0.2 s), is sampled once through GetTable (4097 values).
// A discretized colour map (ParaView's default, 256 bins) is read through its continuous map:
// VTK's unstructured-grid mappers interpolate the map between vertices or nodes, so none shows
// the bins, which would only band the volume and add a point each to the transfer function.
// Where cellfx differs from the projected-tetrahedra mapper is what is done with the function:
// that mapper evaluates it at the cell's vertices (8-bit colours) and interpolates colour and
// A across the cell; cellfx integrates the function along each ray segment.
//
// Mesh. Cells of types tetra (10), voxel (11, reordered to a hexahedron), hexahedron (12),
// wedge (13) and pyramid (14) are kept; ghost cells (duplicate or hidden) are left out, and so
// are cells of other types (counted in the report: 0-, 1- and 2-D cells, which have no volume,
// and 3-D types cellfx does not draw: quadratic cells, polyhedra). Points used by no kept cell
// are dropped; the model matrix (the actor's Position/Orientation/Scale) is applied to the points
// in double. Cell scalars are turned into point scalars by averaging over the kept cells around
// each point (as ParaView's Cell Data to Point Data does), because cellfx interpolates a point
// field inside each cell. Multi-component arrays give one component or the magnitude, as the
// colour map's vector mode says. Inverted cells are re-oriented (fx::orient_cells).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fx/cell_mesh.hpp"
#include "fx/transfer_function.hpp"

class vtkColorTransferFunction;
class vtkDataArray;
class vtkPiecewiseFunction;
class vtkUnstructuredGridBase;

// The plugin calls cellfx::fx by its short name (the plugin's own alias: cellfx declares
// everything under cellfx::).
namespace fx = cellfx::fx;

namespace cellfx_vtk {

// Throws fx::Error when unit_distance is not positive and finite or a function has no nodes.
// data_lo..data_hi (the scalar range being drawn) extends the function's domain so that values
// outside the maps' ranges get VTK's answer there.
fx::TransferFunction transfer_function_from_vtk(vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity,
                                                double unit_distance, double data_lo, double data_hi);

// Which values of a scalar array to use.
struct ScalarSelection {
    vtkDataArray* array = nullptr; // nullptr: the mesh gets a field of zeros
    bool cell_data = false;        // the array holds one value per cell
    int component = 0;             // < 0: the magnitude of all components
};

struct ConversionReport {
    std::size_t cells = 0;                 // cells converted
    std::size_t ghost_cells = 0;           // left out: duplicate or hidden ghost cells
    std::size_t flat_cells = 0;            // left out: 0-, 1- and 2-D cells (no volume)
    std::size_t unsupported_cells = 0;     // left out: other 3-D types
    long long first_unsupported = -1;      // id of the first of those, and its VTK type
    int first_unsupported_type = 0;
    std::size_t flipped_cells = 0;         // inverted cells re-oriented
    std::string summary() const;           // one line for logs
};

// Converts once and keeps the point mapping, so that a new scalar array on the same geometry
// (a time step, another array) costs one pass over the points.
class MeshConverter {
public:
    // `model_to_world`: 16 values, row-major (vtkMatrix4x4's layout), or nullptr for identity.
    // Throws fx::Error (naming the point or cell) for non-finite coordinates.
    fx::CellMesh convert(vtkUnstructuredGridBase* grid, const double* model_to_world, const ScalarSelection& scalars,
                         const std::string& field_name, ConversionReport& report);
    // The field of the last converted mesh for another selection on the same grid. Throws
    // fx::Error for an array whose length does not fit the grid.
    std::vector<float> scalars(vtkUnstructuredGridBase* grid, const ScalarSelection& scalars) const;

private:
    std::vector<std::uint32_t> kept_point_ids_; // VTK point id of each mesh point
    std::vector<long long> kept_cell_ids_;      // VTK cell id of each mesh cell
    std::vector<std::uint32_t> connectivity_;   // mesh point indices, as in the mesh
    std::vector<std::uint32_t> offsets_;
};

} // namespace cellfx_vtk
