#include "cellfx_vtk.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <glm/common.hpp>

#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGridBase.h>

#include "fx/error.hpp"
#include "fx/mesh_validation.hpp"

namespace cellfx_vtk {

namespace {

// ---- transfer function ------------------------------------------------------------------

constexpr double kTolerance = 1e-3; // colour and opacity, both in [0, 1]
constexpr int kMaxHalvings = 16;     // per interval between breakpoints (1/65536 of it)
constexpr double kSideOffset = 1e-7; // of the domain: "just below / just above" a breakpoint

struct Value {
    glm::dvec3 color{0.0};
    double opacity = 0.0;
};

double deviation(const Value& a, const Value& b) {
    const glm::dvec3 d = glm::abs(a.color - b.color);
    return std::max({d.x, d.y, d.z, std::abs(a.opacity - b.opacity)});
}

Value lerp(const Value& a, const Value& b, double t) {
    return {a.color + (b.color - a.color) * t, a.opacity + (b.opacity - a.opacity) * t};
}

class FunctionSampler {
public:
    FunctionSampler(vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity, double unit_distance, double lo,
                    double hi)
        : color_(color), opacity_(opacity), unit_distance_(unit_distance), lo_(lo), hi_(hi) {
        // VTK computes a CIEDE2000 path on every GetColor call (~0.2 s each here): one
        // GetTable call samples the whole map instead, read back with linear interpolation.
        if (color->GetColorSpace() == VTK_CTF_LAB_CIEDE2000 && hi > lo) {
            table_.resize(3 * kCiede2000Samples);
            color->GetTable(lo, hi, kCiede2000Samples, table_.data());
        }
    }

    Value at(double s) const {
        double rgb[3] = {0.0, 0.0, 0.0};
        if (table_.empty()) {
            // The map's own interpolation, not its bins when ParaView discretizes it (see the header).
            color_->vtkColorTransferFunction::GetColor(s, rgb);
        } else {
            const double x = std::clamp((s - lo_) / (hi_ - lo_), 0.0, 1.0) * (kCiede2000Samples - 1);
            const int i = std::min(int(x), kCiede2000Samples - 2);
            for (int k = 0; k < 3; ++k) rgb[k] = table_[3 * i + k] + (x - i) * (table_[3 * i + 3 + k] - table_[3 * i + k]);
        }
        return {glm::dvec3(rgb[0], rgb[1], rgb[2]), opacity_->GetValue(s)};
    }

    void add(double s, const Value& v) {
        // GetColor clamps to [0, 1]; an opacity function may be edited below 0.
        points_.push_back({s, glm::max(v.color, glm::dvec3(0.0)), std::max(v.opacity, 0.0) / unit_distance_});
    }

    // Points strictly inside (a, b) until the function is within kTolerance of straight lines
    // at the eighths of every piece.
    void refine(double a, const Value& fa, double b, const Value& fb, int depth) {
        const double m = 0.5 * (a + b);
        const Value fm = at(m);
        bool straight = deviation(fm, lerp(fa, fb, 0.5)) <= kTolerance;
        for (int k = 1; k < 8 && straight; ++k) {
            if (k != 4) straight = deviation(at(a + k * 0.125 * (b - a)), lerp(fa, fb, k * 0.125)) <= kTolerance;
        }
        if (straight || depth >= kMaxHalvings || !(a < m && m < b)) return;
        refine(a, fa, m, fm, depth + 1);
        add(m, fm);
        refine(m, fm, b, fb, depth + 1);
    }

    // The values just below and just above breakpoint b. A component that is continuous at b
    // (its two sides within kTolerance) takes its value at b on both; one that jumps takes its
    // one-sided limits, extrapolated linearly from two samples `offset` and 2·`offset` inside
    // each side (exact for the linear and constant pieces VTK's functions are made of). At the
    // domain's ends the missing side is the value at b.
    void sides(double b, double offset, bool has_below, bool has_above, Value& below, Value& above) const {
        const Value here = at(b);
        below = has_below ? extrapolate(at(b - offset), at(b - 2.0 * offset)) : here;
        above = has_above ? extrapolate(at(b + offset), at(b + 2.0 * offset)) : here;
        for (int k = 0; k < 3; ++k) {
            if (std::abs(below.color[k] - above.color[k]) <= kTolerance) below.color[k] = above.color[k] = here.color[k];
        }
        if (std::abs(below.opacity - above.opacity) <= kTolerance) below.opacity = above.opacity = here.opacity;
    }

    std::vector<fx::TransferPoint> take() { return std::move(points_); }

private:
    static Value extrapolate(const Value& near, const Value& far) {
        return {2.0 * near.color - far.color, 2.0 * near.opacity - far.opacity};
    }

    static constexpr int kCiede2000Samples = 4097;
    vtkColorTransferFunction* color_;
    vtkPiecewiseFunction* opacity_;
    double unit_distance_, lo_, hi_;
    std::vector<double> table_; // CIEDE2000 only
    std::vector<fx::TransferPoint> points_;
};

// ---- mesh --------------------------------------------------------------------------------

// VTK_VOXEL's vertex order (x fastest, then y, then z) → VTK_HEXAHEDRON's (counter-clockwise).
constexpr int kVoxelToHexahedron[8] = {0, 1, 3, 2, 4, 5, 7, 6};

constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();

} // namespace

fx::TransferFunction transfer_function_from_vtk(vtkColorTransferFunction* color, vtkPiecewiseFunction* opacity,
                                                double unit_distance, double data_lo, double data_hi) {
    if (!color || !opacity) throw fx::Error("transfer function: no colour map or no opacity function");
    if (!(unit_distance > 0.0) || !std::isfinite(unit_distance)) {
        throw fx::Error("transfer function: the scalar opacity unit distance must be positive and finite, got " +
                        std::to_string(unit_distance));
    }
    if (color->GetSize() == 0) throw fx::Error("transfer function: the colour map has no points");
    if (opacity->GetSize() == 0) throw fx::Error("transfer function: the opacity function has no points");

    std::set<double> breakpoints;
    double node[6];
    for (int i = 0; i < color->GetSize(); ++i) color->GetNodeValue(i, node), breakpoints.insert(node[0]);
    for (int i = 0; i < opacity->GetSize(); ++i) opacity->GetNodeValue(i, node), breakpoints.insert(node[0]);
    if (std::isfinite(data_lo) && std::isfinite(data_hi)) breakpoints.insert({data_lo, data_hi});

    const double lo = *breakpoints.begin(), hi = *breakpoints.rbegin();
    FunctionSampler sampler(color, opacity, unit_distance, lo, hi);
    if (!(hi > lo)) {
        sampler.add(lo, sampler.at(lo));
        return fx::TransferFunction(sampler.take());
    }
    const double offset = kSideOffset * (hi - lo);
    std::vector<double> s; // breakpoints at least 4 offsets apart (so at least lo and one more)
    for (double b : breakpoints) {
        if (s.empty() || b - s.back() >= 4.0 * offset) s.push_back(b);
    }

    Value from_right; // the value leaving the previous breakpoint to the right
    for (std::size_t i = 0; i < s.size(); ++i) {
        Value below, above;
        sampler.sides(s[i], offset, i > 0, i + 1 < s.size(), below, above);
        if (i > 0) sampler.refine(s[i - 1], from_right, s[i], below, 0);
        sampler.add(s[i], below);
        if (deviation(below, above) > 0.0) sampler.add(s[i], above); // a step
        from_right = above;
    }
    return fx::TransferFunction(sampler.take());
}

std::string ConversionReport::summary() const {
    std::string s = std::to_string(cells) + " cells";
    if (ghost_cells) s += ", " + std::to_string(ghost_cells) + " ghost cells left out";
    if (flat_cells) s += ", " + std::to_string(flat_cells) + " 0/1/2-D cells left out";
    if (unsupported_cells) {
        s += ", " + std::to_string(unsupported_cells) + " cells of 3-D types cellfx does not draw left out (the first: cell " +
             std::to_string(first_unsupported) + ", VTK type " + std::to_string(first_unsupported_type) + ")";
    }
    if (flipped_cells) s += ", " + std::to_string(flipped_cells) + " inverted cells re-oriented";
    return s;
}

fx::CellMesh MeshConverter::convert(vtkUnstructuredGridBase* grid, const double* m, const ScalarSelection& selection,
                                    const std::string& field_name, ConversionReport& report) {
    report = {};
    const vtkIdType cell_count = grid->GetNumberOfCells(), point_count = grid->GetNumberOfPoints();
    if (point_count >= vtkIdType(kUnused)) throw fx::Error("mesh: more points than cellfx indexes (2^32 - 1)");
    vtkUnsignedCharArray* ghosts = grid->GetCellGhostArray();
    const unsigned char ghost_mask = vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL;

    std::vector<std::uint32_t> mesh_index(std::size_t(point_count), kUnused);
    kept_point_ids_.clear();
    kept_cell_ids_.clear();
    fx::CellMesh mesh;
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < cell_count; ++c) {
        if (ghosts && (ghosts->GetValue(c) & ghost_mask)) {
            ++report.ghost_cells;
            continue;
        }
        const int vtk_type = grid->GetCellType(c);
        fx::CellType type = fx::CellType::Hexahedron;
        if (vtk_type != VTK_VOXEL && !fx::cell_type_from_vtk(vtk_type, type)) {
            if (vtkCellTypes::GetDimension(static_cast<unsigned char>(vtk_type)) < 3) {
                ++report.flat_cells;
            } else if (report.unsupported_cells++ == 0) {
                report.first_unsupported = c;
                report.first_unsupported_type = vtk_type;
            }
            continue;
        }
        grid->GetCellPoints(c, ids);
        const int count = fx::cell_vertex_count(type);
        if (ids->GetNumberOfIds() != count) {
            throw fx::Error("mesh: cell " + std::to_string(c) + ": a " + fx::cell_type_name(type) + " with " +
                            std::to_string(ids->GetNumberOfIds()) + " points");
        }
        std::uint32_t v[fx::kMaxCellVertices];
        for (int k = 0; k < count; ++k) {
            const vtkIdType p = ids->GetId(vtk_type == VTK_VOXEL ? kVoxelToHexahedron[k] : k);
            if (p < 0 || p >= point_count) {
                throw fx::Error("mesh: cell " + std::to_string(c) + ": point id " + std::to_string(p) +
                                " is outside the " + std::to_string(point_count) + " points");
            }
            std::uint32_t& index = mesh_index[std::size_t(p)];
            if (index == kUnused) {
                index = std::uint32_t(kept_point_ids_.size());
                kept_point_ids_.push_back(std::uint32_t(p));
            }
            v[k] = index;
        }
        mesh.add_cell(type, v);
        kept_cell_ids_.push_back(c);
    }

    mesh.points.resize(kept_point_ids_.size());
    for (std::size_t i = 0; i < kept_point_ids_.size(); ++i) {
        double x[3];
        grid->GetPoint(kept_point_ids_[i], x);
        glm::dvec3 p(x[0], x[1], x[2]);
        if (m) { // row-major, as vtkMatrix4x4 stores it
            const double w = m[12] * x[0] + m[13] * x[1] + m[14] * x[2] + m[15];
            p = glm::dvec3(m[0] * x[0] + m[1] * x[1] + m[2] * x[2] + m[3], m[4] * x[0] + m[5] * x[1] + m[6] * x[2] + m[7],
                           m[8] * x[0] + m[9] * x[1] + m[10] * x[2] + m[11]) / w;
        }
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw fx::Error("mesh: point " + std::to_string(kept_point_ids_[i]) + " is not finite");
        }
        mesh.points[i] = p;
    }
    report.flipped_cells = fx::orient_cells(mesh).flipped;
    report.cells = mesh.cell_count();
    connectivity_ = mesh.connectivity;
    offsets_ = mesh.cell_offsets;
    mesh.scalars.push_back({field_name, scalars(grid, selection)});
    return mesh;
}

std::vector<float> MeshConverter::scalars(vtkUnstructuredGridBase* grid, const ScalarSelection& selection) const {
    std::vector<float> values(kept_point_ids_.size(), 0.0f);
    vtkDataArray* a = selection.array;
    if (!a) return values;
    const int components = a->GetNumberOfComponents();
    if (selection.component >= components) {
        throw fx::Error("scalars: array '" + std::string(a->GetName() ? a->GetName() : "") + "' has " +
                        std::to_string(components) + " components, component " +
                        std::to_string(selection.component) + " was asked for");
    }
    const vtkIdType needed = selection.cell_data ? grid->GetNumberOfCells() : grid->GetNumberOfPoints();
    if (a->GetNumberOfTuples() < needed) {
        throw fx::Error("scalars: array '" + std::string(a->GetName() ? a->GetName() : "") + "' has " +
                        std::to_string(a->GetNumberOfTuples()) + " values for " + std::to_string(needed) +
                        (selection.cell_data ? " cells" : " points"));
    }
    auto value = [&](vtkIdType tuple) {
        if (selection.component >= 0) return a->GetComponent(tuple, selection.component);
        double sum = 0.0;
        for (int k = 0; k < components; ++k) sum += a->GetComponent(tuple, k) * a->GetComponent(tuple, k);
        return std::sqrt(sum);
    };
    auto check = [&](double v, const char* what, vtkIdType id) {
        if (!std::isfinite(v)) {
            throw fx::Error("scalars: array '" + std::string(a->GetName() ? a->GetName() : "") + "': " + what + " " +
                            std::to_string(id) + " is not finite (cellfx draws finite values only)");
        }
        return v;
    };
    if (!selection.cell_data) {
        for (std::size_t i = 0; i < values.size(); ++i) {
            values[i] = float(check(value(kept_point_ids_[i]), "point", kept_point_ids_[i]));
        }
        return values;
    }
    // Cell data: the mean over the kept cells using each point.
    std::vector<double> sum(values.size(), 0.0);
    std::vector<std::uint32_t> count(values.size(), 0);
    for (std::size_t k = 0; k < kept_cell_ids_.size(); ++k) {
        const double v = check(value(kept_cell_ids_[k]), "cell", kept_cell_ids_[k]);
        for (std::uint32_t j = offsets_[k]; j < offsets_[k + 1]; ++j) sum[connectivity_[j]] += v, ++count[connectivity_[j]];
    }
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(sum[i] / std::max<std::uint32_t>(count[i], 1));
    return values;
}

} // namespace cellfx_vtk
