// The plugin's conversions without GL: ParaView's colour map and opacity function into a cellfx
// transfer function (against VTK's own GetColor/GetValue at many scalars), and VTK grids into
// cellfx meshes (against cellfx's own reader of the same file, and on hand-made cells).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <vtkCellType.h>
#include <vtkColorTransferFunction.h>
#include <vtkDiscretizableColorTransferFunction.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkCellData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>

#include "cellfx_vtk.hpp"
#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"

namespace {

struct Worst {
    double color = 0.0, sigma = 0.0;
    double color_at = 0.0, sigma_at = 0.0; // where
};

std::ostream& operator<<(std::ostream& os, const Worst& w) {
    return os << "colour off by " << w.color << " at s = " << w.color_at << ", extinction off by " << w.sigma
              << " at s = " << w.sigma_at;
}

// The largest difference between the cellfx function and VTK's answer at n scalars spread over
// [lo, hi], skipping those within `skip` of any value in `avoid` (steps, where "the value at"
// depends on the side).
Worst compare(const fx::TransferFunction& tf, vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity,
              double unit, double lo, double hi, int n = 2001, const std::vector<double>& avoid = {}, double skip = 0.0) {
    Worst w;
    for (int i = 0; i < n; ++i) {
        const double s = lo + (hi - lo) * (i + 0.37) / n;
        if (std::any_of(avoid.begin(), avoid.end(), [&](double a) { return std::abs(s - a) < skip; })) continue;
        double rgb[3];
        color->GetColor(s, rgb);
        const glm::dvec3 c = tf.color(s);
        const double dc = std::max({std::abs(c.x - rgb[0]), std::abs(c.y - rgb[1]), std::abs(c.z - rgb[2])});
        const double ds = std::abs(tf.sigma(s) - opacity->GetValue(s) / unit);
        if (dc > w.color) w.color = dc, w.color_at = s;
        if (ds > w.sigma) w.sigma = ds, w.sigma_at = s;
    }
    return w;
}

vtkNew<vtkPiecewiseFunction> ramp_opacity() {
    vtkNew<vtkPiecewiseFunction> o;
    o->AddPoint(-1.0, 0.0);
    o->AddPoint(0.3, 0.8);
    o->AddPoint(2.0, 0.1);
    return o;
}

} // namespace

TEST_CASE("an RGB colour map and a piecewise-linear opacity convert exactly, on the nodes alone", "[convert]") {
    vtkNew<vtkColorTransferFunction> color;
    color->SetColorSpaceToRGB();
    color->AddRGBPoint(-1.0, 0.0, 0.0, 1.0);
    color->AddRGBPoint(0.5, 0.2, 0.9, 0.3);
    color->AddRGBPoint(2.0, 1.0, 0.0, 0.0);
    auto opacity = ramp_opacity();
    const double unit = 2.5;
    const fx::TransferFunction tf = cellfx_vtk::transfer_function_from_vtk(color, opacity, unit, -1.0, 2.0);
    // Nodes -1, 0.3, 0.5, 2: nothing between them needs a point.
    CHECK(tf.points().size() == 4);
    const Worst w = compare(tf, color, opacity, unit, -1.0, 2.0);
    CHECK(w.color < 1e-12);
    CHECK(w.sigma < 1e-12);
    // Extinction is opacity / unit distance: 0.8 / 2.5 at the opacity peak.
    CHECK(tf.sigma(0.3) == Approx(0.32));
}

TEST_CASE("Lab, diverging and HSV colour maps and shaped opacity nodes convert within 1.5e-3", "[convert]") {
    // Pieces are halved until straight within 1e-3 at their eighths; between those the curve
    // may stray a little further.
    for (int space : {VTK_CTF_LAB, VTK_CTF_DIVERGING, VTK_CTF_HSV, VTK_CTF_LAB_CIEDE2000}) {
        // VTK takes ~0.2 s per CIEDE2000 GetColor: fewer samples there.
        const int samples = space == VTK_CTF_LAB_CIEDE2000 ? 13 : 2001;
        vtkNew<vtkColorTransferFunction> color;
        color->SetColorSpace(space);
        color->AddRGBPoint(0.0, 0.23, 0.30, 0.75);
        color->AddRGBPoint(10.0, 0.87, 0.87, 0.87);
        color->AddRGBPoint(20.0, 0.71, 0.02, 0.15);
        vtkNew<vtkPiecewiseFunction> opacity;
        opacity->AddPoint(0.0, 0.0, 0.5, 0.0);
        opacity->AddPoint(12.0, 1.0, 0.2, 0.8); // midpoint and sharpness: a curve, not a line
        opacity->AddPoint(20.0, 0.3);
        const fx::TransferFunction tf = cellfx_vtk::transfer_function_from_vtk(color, opacity, 1.0, 0.0, 20.0);
        const Worst w = compare(tf, color, opacity, 1.0, 0.0, 20.0, samples);
        INFO("colour space " << space << ": " << tf.points().size() << " points; " << w);
        // CIEDE2000 is sampled once through GetTable, whose path differs from GetColor's by
        // up to ~2e-3 (half an 8-bit step).
        CHECK(w.color < (space == VTK_CTF_LAB_CIEDE2000 ? 3e-3 : 1.5e-3));
        CHECK(w.sigma < 1.5e-3);
        CHECK(tf.points().size() < 2000);
    }
}

TEST_CASE("a discretized colour map (ParaView's default) converts to its continuous map", "[convert]") {
    // Its 256 bins would band the volume (VTK's unstructured-grid mappers interpolate between
    // vertices or nodes, so none shows them) and cost a transfer-function point each.
    vtkNew<vtkDiscretizableColorTransferFunction> color;
    color->SetColorSpaceToRGB();
    color->AddRGBPoint(1.0, 0.0, 0.0, 1.0);
    color->AddRGBPoint(40.0, 0.2, 0.9, 0.3);
    color->AddRGBPoint(100.0, 1.0, 1.0, 0.0);
    color->DiscretizeOn();
    color->SetNumberOfValues(8);
    color->Build();
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AddPoint(1.0, 0.1);
    opacity->AddPoint(100.0, 0.9);
    const fx::TransferFunction tf = cellfx_vtk::transfer_function_from_vtk(color, opacity, 0.5, 1.0, 100.0);
    CHECK(tf.points().size() == 3);
    double worst = 0.0;
    for (int i = 0; i < 1000; ++i) {
        const double s = 1.0 + 99.0 * (i + 0.5) / 1000.0;
        double rgb[3];
        color->vtkColorTransferFunction::GetColor(s, rgb);
        worst = std::max({worst, std::abs(tf.color(s).x - rgb[0]), std::abs(tf.color(s).y - rgb[1]),
                          std::abs(tf.color(s).z - rgb[2])});
    }
    CHECK(worst < 1e-12);
}

TEST_CASE("clamping off, above-range colours and duplicate opacity nodes become steps", "[convert]") {
    vtkNew<vtkColorTransferFunction> color;
    color->AddRGBPoint(0.0, 1.0, 0.0, 0.0);
    color->AddRGBPoint(1.0, 0.0, 1.0, 0.0);
    color->SetUseAboveRangeColor(true);
    color->SetAboveRangeColor(0.0, 0.0, 1.0);
    vtkNew<vtkPiecewiseFunction> opacity;
    opacity->AllowDuplicateScalarsOn();
    opacity->AddPoint(0.0, 0.2);
    opacity->AddPoint(0.5, 0.2);
    opacity->AddPoint(0.5, 0.9); // a step up at 0.5
    opacity->AddPoint(1.0, 0.9);
    opacity->ClampingOff();      // zero outside [0, 1]
    // The data reach 1.5: above the map's range.
    const fx::TransferFunction tf = cellfx_vtk::transfer_function_from_vtk(color, opacity, 1.0, 0.0, 1.5);
    const Worst w = compare(tf, color, opacity, 1.0, 0.0, 1.5, 3001, {0.5, 1.0}, 1e-5);
    CHECK(w.color < 1e-12);
    CHECK(w.sigma < 1e-12);
    CHECK(tf.sigma(0.49) == Approx(0.2));
    CHECK(tf.sigma(0.51) == Approx(0.9));
    CHECK(tf.color(1.2).z == Approx(1.0));
    CHECK(tf.sigma(1.2) == 0.0);
}

TEST_CASE("bad transfer-function input is an error that says what is wrong", "[convert]") {
    vtkNew<vtkColorTransferFunction> color;
    auto opacity = ramp_opacity();
    CHECK_THROWS_WITH(cellfx_vtk::transfer_function_from_vtk(color, opacity, 1.0, 0.0, 1.0),
                      Catch::Contains("colour map has no points"));
    color->AddRGBPoint(0.0, 1.0, 1.0, 1.0);
    CHECK_THROWS_WITH(cellfx_vtk::transfer_function_from_vtk(color, opacity, 0.0, 0.0, 1.0),
                      Catch::Contains("unit distance must be positive"));
    vtkNew<vtkPiecewiseFunction> empty;
    CHECK_THROWS_WITH(cellfx_vtk::transfer_function_from_vtk(color, empty, 1.0, 0.0, 1.0),
                      Catch::Contains("opacity function has no points"));
}

TEST_CASE("a VTK file converts to the mesh cellfx's own reader makes of it", "[convert]") {
    const std::string path = std::string(CELLFX_SOURCE_DIR) + "/content/meshes/lox_post/post.vtk";
    vtkNew<vtkUnstructuredGridReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    const fx::CellMesh expected = fx::read_mesh(path);
    REQUIRE(!expected.scalars.empty());
    const std::string field = expected.scalars[0].name;
    vtkDataArray* array = grid->GetPointData()->GetArray(field.c_str());
    REQUIRE(array);

    cellfx_vtk::MeshConverter converter;
    cellfx_vtk::ConversionReport report;
    const fx::CellMesh mesh = converter.convert(grid, nullptr, {array, false, 0}, field, report);
    INFO(report.summary());
    REQUIRE(mesh.cell_count() == expected.cell_count());
    CHECK(report.unsupported_cells == 0);
    // Points are renumbered in order of first use; compare cell by cell through them.
    double worst_point = 0.0, worst_value = 0.0;
    std::size_t different_types = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        different_types += mesh.cell_types[c] != expected.cell_types[c];
        const int n = fx::cell_vertex_count(mesh.cell_types[c]);
        // Orientation fixes may reorder a cell's vertices; compare as sets of points.
        for (int k = 0; k < n; ++k) {
            const glm::dvec3 p = mesh.points[mesh.cell_vertices(c)[k]];
            double best = 1e300, value = 0.0;
            for (int j = 0; j < n; ++j) {
                const std::uint32_t q = expected.cell_vertices(c)[j];
                const double d = glm::length(p - expected.points[q]);
                if (d < best) best = d, value = expected.scalars[0].values[q];
            }
            worst_point = std::max(worst_point, best);
            worst_value = std::max(worst_value, double(std::abs(mesh.scalars[0].values[mesh.cell_vertices(c)[k]] - value)));
        }
    }
    CHECK(different_types == 0);
    CHECK(worst_point < 1e-6);
    CHECK(worst_value == 0.0);
}

TEST_CASE("cells: every volume type kept, voxels reordered, ghosts and flat or quadratic cells left out", "[convert]") {
    vtkNew<vtkPoints> points;
    // A unit cube's corners (ids 0..7, x fastest) and an apex above it (8).
    for (int k = 0; k < 8; ++k) points->InsertNextPoint(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    points->InsertNextPoint(0.5, 0.5, 2.0);
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(points);
    const vtkIdType voxel[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const vtkIdType hexahedron[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    const vtkIdType inverted_tetra[4] = {0, 2, 1, 4}; // faces wound inwards
    const vtkIdType pyramid[5] = {4, 5, 7, 6, 8};
    const vtkIdType wedge[6] = {0, 1, 4, 2, 3, 6};
    const vtkIdType triangle[3] = {0, 1, 2};
    const vtkIdType quadratic_tetra[10] = {0, 1, 2, 4, 0, 1, 2, 3, 4, 5};
    grid->InsertNextCell(VTK_VOXEL, 8, voxel);
    grid->InsertNextCell(VTK_HEXAHEDRON, 8, hexahedron);
    grid->InsertNextCell(VTK_TETRA, 4, inverted_tetra);
    grid->InsertNextCell(VTK_PYRAMID, 5, pyramid);
    grid->InsertNextCell(VTK_WEDGE, 6, wedge);
    grid->InsertNextCell(VTK_TRIANGLE, 3, triangle);
    grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, quadratic_tetra);
    grid->InsertNextCell(VTK_HEXAHEDRON, 8, hexahedron); // marked a ghost below
    vtkNew<vtkUnsignedCharArray> ghosts;
    ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
    for (int c = 0; c < 8; ++c) ghosts->InsertNextValue(c == 7 ? vtkDataSetAttributes::DUPLICATECELL : 0);
    grid->GetCellData()->AddArray(ghosts);
    // Cell data 1..8, and a 2-component point array (3, 4) everywhere: magnitude 5.
    vtkNew<vtkDoubleArray> per_cell;
    for (int c = 0; c < 8; ++c) per_cell->InsertNextValue(c + 1.0);
    vtkNew<vtkFloatArray> vectors;
    vectors->SetNumberOfComponents(2);
    for (int p = 0; p < 9; ++p) vectors->InsertNextTuple2(3.0, 4.0);

    cellfx_vtk::MeshConverter converter;
    cellfx_vtk::ConversionReport report;
    const double shift[16] = {1, 0, 0, 10, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; // x + 10
    const fx::CellMesh mesh = converter.convert(grid, shift, {per_cell, true, 0}, "s", report);
    INFO(report.summary());
    CHECK(report.cells == 5);
    CHECK(report.ghost_cells == 1);
    CHECK(report.flat_cells == 1);
    CHECK(report.unsupported_cells == 1);
    CHECK(report.first_unsupported == 6);
    CHECK(report.flipped_cells == 1);
    // The voxel became a positive hexahedron and the tetra was turned: no cell is inverted,
    // flat or twisted. (The cells all sit on one cube, so validation reports the hexahedron as
    // the voxel's duplicate and the others as overlapping it; that is this test's set-up.)
    for (const fx::MeshProblem& problem : fx::validate_mesh(mesh)) {
        INFO(problem.message);
        CHECK((problem.kind == fx::MeshProblemKind::Duplicate || problem.kind == fx::MeshProblemKind::Overlapping));
    }
    CHECK(mesh.point_count() == 9);
    CHECK(fx::mesh_bounds(mesh).lo.x == 10.0);
    // Point 8 (the apex) is used by the pyramid (cell value 4) alone; point 0 by the voxel,
    // the hexahedron, the tetra and the wedge: (1 + 2 + 3 + 5) / 4.
    const auto value_at = [&](glm::dvec3 p) {
        for (std::size_t i = 0; i < mesh.point_count(); ++i) {
            if (glm::length(mesh.points[i] - p) < 1e-12) return mesh.scalars[0].values[i];
        }
        return -1.0f;
    };
    CHECK(value_at({10.5, 0.5, 2.0}) == 4.0f);
    CHECK(value_at({10.0, 0.0, 0.0}) == Approx(11.0 / 4.0));

    const std::vector<float> magnitude = converter.scalars(grid, {vectors, false, -1});
    CHECK(std::all_of(magnitude.begin(), magnitude.end(), [](float v) { return v == 5.0f; }));
    const std::vector<float> second = converter.scalars(grid, {vectors, false, 1});
    CHECK(std::all_of(second.begin(), second.end(), [](float v) { return v == 4.0f; }));
    CHECK_THROWS_WITH(converter.scalars(grid, {vectors, false, 2}), Catch::Contains("has 2 components"));
    vectors->SetTuple2(3, std::nan(""), 0.0);
    CHECK_THROWS_WITH(converter.scalars(grid, {vectors, false, 0}), Catch::Contains("point 3 is not finite"));
}
