#include "fx/mesh_validation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "mesh/face_topology.hpp"

namespace cellfx::fx {
namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

bool in_range(const glm::dvec3& p) {
    return std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate && std::abs(p.z) <= kMaxCoordinate;
}

double tet_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a)) / 6.0;
}

// Calls visit(signed volume) for every tetrahedron (centroid, face triangle) of the cell; the
// volumes sum to the cell's signed volume. Quads are split through their own centroid.
// Coordinates are taken relative to the cell's first vertex and divided by `unit`, so that
// cells far from the origin keep their precision and any size gives volumes near 1.
template <class Visit>
void for_each_centroid_tet(const CellMesh& mesh, std::size_t cell, double unit, Visit visit) {
    const CellType type = mesh.cell_types[cell];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    const int n = cell_vertex_count(type);
    const glm::dvec3 origin = mesh.points[cv[0]];
    glm::dvec3 p[kMaxCellVertices];
    glm::dvec3 centre(0.0);
    for (int i = 0; i < n; ++i) {
        p[i] = (mesh.points[cv[i]] - origin) / unit;
        centre += p[i] / double(n);
    }
    const CellFace* faces = cell_faces(type);
    for (int f = 0; f < cell_face_count(type); ++f) {
        const CellFace& face = faces[f];
        if (face.count == 3) {
            visit(tet_volume(centre, p[face.v[0]], p[face.v[1]], p[face.v[2]]));
            continue;
        }
        const glm::dvec3 m = 0.25 * (p[face.v[0]] + p[face.v[1]] + p[face.v[2]] + p[face.v[3]]);
        for (int i = 0; i < 4; ++i) visit(tet_volume(centre, p[face.v[i]], p[face.v[(i + 1) % 4]], m));
    }
}

// The largest side of the cell's bounding box (no squares: finite for any finite points).
double cell_extent(const CellMesh& mesh, std::size_t cell) {
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    glm::dvec3 lo = mesh.points[cv[0]], hi = lo;
    for (int i = 1; i < cell_vertex_count(mesh.cell_types[cell]); ++i) {
        lo = glm::min(lo, mesh.points[cv[i]]);
        hi = glm::max(hi, mesh.points[cv[i]]);
    }
    const glm::dvec3 d = hi - lo;
    return std::max({d.x, d.y, d.z});
}

// Signed volume in units of the cube of the cell's extent, and its positive and negative parts.
struct ScaledVolume {
    double volume = 0.0, positive = 0.0, negative = 0.0;
};
ScaledVolume scaled_volume(const CellMesh& mesh, std::size_t cell, double extent) {
    ScaledVolume v;
    for_each_centroid_tet(mesh, cell, extent, [&](double t) {
        v.volume += t;
        (t > 0.0 ? v.positive : v.negative) += t;
    });
    return v;
}

bool indices_in_range(const CellMesh& mesh, std::size_t cell) {
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int i = 0; i < cell_vertex_count(mesh.cell_types[cell]); ++i) {
        if (cv[i] >= mesh.point_count()) return false;
    }
    return true;
}

CellShape shape_of(const ScaledVolume& v) {
    const double size = v.positive - v.negative;
    if (!(size > 1e-9)) return CellShape::Flat;
    if (std::min(v.positive, -v.negative) > 1e-6 * size) return CellShape::Twisted;
    return v.volume > 0.0 ? CellShape::Positive : CellShape::Inverted;
}

std::string cell_prefix(std::size_t cell) { return "cell " + std::to_string(cell) + ": "; }

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

std::vector<std::uint32_t> block_of_cells(const CellMesh& mesh) {
    std::vector<std::uint32_t> block(mesh.cell_count(), 0);
    for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
        const Block& blk = mesh.blocks[b];
        const std::size_t end = std::min<std::size_t>(std::size_t(blk.first_cell) + blk.cell_count, mesh.cell_count());
        for (std::size_t c = blk.first_cell; c < end; ++c) block[c] = static_cast<std::uint32_t>(b);
    }
    return block;
}

// The point ids of face slot `slot` (cell `cell`, first slot `first`) in the cell's winding.
int face_points(const CellMesh& mesh, std::uint32_t cell, std::uint32_t local_face, std::uint32_t out[4]) {
    const CellFace& face = cell_faces(mesh.cell_types[cell])[local_face];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int i = 0; i < face.count; ++i) out[i] = cv[face.v[i]];
    return face.count;
}

// +1 when face b runs around the same way as face a, −1 the other way, 0 when the faces
// have repeated points (no direction).
int same_direction(const std::uint32_t* a, const std::uint32_t* b, int n) {
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (a[i] == a[j]) return 0;
    int at = -1;
    for (int j = 0; j < n; ++j)
        if (b[j] == a[0]) at = j;
    if (at < 0) return 0;
    if (b[(at + 1) % n] == a[1]) return 1;
    if (b[(at + n - 1) % n] == a[1]) return -1;
    return 0;
}

bool same_points(const CellMesh& mesh, std::uint32_t a, std::uint32_t b) {
    if (mesh.cell_types[a] != mesh.cell_types[b]) return false;
    const int n = cell_vertex_count(mesh.cell_types[a]);
    std::array<std::uint32_t, kMaxCellVertices> pa, pb; // padded, then sorted whole
    pa.fill(0xFFFFFFFFu);
    pb.fill(0xFFFFFFFFu);
    std::copy(mesh.cell_vertices(a), mesh.cell_vertices(a) + n, pa.begin());
    std::copy(mesh.cell_vertices(b), mesh.cell_vertices(b) + n, pb.begin());
    std::sort(pa.begin(), pa.end());
    std::sort(pb.begin(), pb.end());
    return pa == pb;
}

} // namespace

const char* mesh_problem_name(MeshProblemKind kind) {
    switch (kind) {
    case MeshProblemKind::IndexOutOfRange: return "index out of range";
    case MeshProblemKind::NonFiniteCoordinate: return "non-finite coordinate";
    case MeshProblemKind::CoordinateOutOfRange: return "coordinate out of range";
    case MeshProblemKind::NonFiniteScalar: return "non-finite scalar";
    case MeshProblemKind::RepeatedVertex: return "repeated vertex";
    case MeshProblemKind::ZeroVolume: return "zero volume";
    case MeshProblemKind::Inverted: return "inverted";
    case MeshProblemKind::Twisted: return "twisted";
    case MeshProblemKind::Duplicate: return "duplicate";
    case MeshProblemKind::Overlapping: return "overlapping";
    }
    return "unknown";
}

double cell_signed_volume(const CellMesh& mesh, std::size_t cell) {
    double volume = 0.0;
    for_each_centroid_tet(mesh, cell, 1.0, [&](double v) { volume += v; });
    return volume;
}

CellShape classify_cell(const CellMesh& mesh, std::size_t cell) {
    if (!indices_in_range(mesh, cell)) return CellShape::Unusable;
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    for (int i = 0; i < cell_vertex_count(mesh.cell_types[cell]); ++i) {
        if (!finite(mesh.points[cv[i]])) return CellShape::Unusable;
    }
    const double extent = cell_extent(mesh, cell);
    if (!(extent > 0.0)) return CellShape::Flat; // all its points coincide
    if (!std::isfinite(extent)) return CellShape::Unusable;
    return shape_of(scaled_volume(mesh, cell, extent));
}

std::vector<CellOverlap> find_overlapping_cells(const CellMesh& mesh, const FaceTopology& topology,
                                                const std::vector<CellShape>& shapes) {
    std::vector<CellOverlap> out;
    const std::vector<std::uint32_t> block = block_of_cells(mesh);
    auto solid = [&](std::uint32_t c) { return shapes[c] == CellShape::Positive || shapes[c] == CellShape::Inverted; };
    // Direction of slot's face relative to `reference` (points of the reference face), with
    // the cell's orientation folded in: equal values mean the two cells lie on one side.
    auto side = [&](std::uint32_t slot, const std::uint32_t* reference, int n) {
        const std::uint32_t cell = topology.slot_cell[slot];
        std::uint32_t points[4];
        face_points(mesh, cell, slot - topology.first_face[cell], points);
        const int d = same_direction(reference, points, n);
        return shapes[cell] == CellShape::Inverted ? -d : d;
    };
    auto report = [&](std::uint32_t a, std::uint32_t b) {
        if (a > b) std::swap(a, b);
        out.push_back(CellOverlap{a, b, same_points(mesh, a, b)});
    };
    for (std::uint32_t s = 0; s < topology.face_slot_count(); ++s) {
        const std::uint32_t t = topology.neighbour[s];
        if (t == FaceTopology::kBoundary || t < s) continue;
        const std::uint32_t a = topology.slot_cell[s], b = topology.slot_cell[t];
        if (!solid(a) || !solid(b) || block[a] != block[b]) continue;
        std::uint32_t reference[4];
        const int n = face_points(mesh, a, s - topology.first_face[a], reference);
        const int da = side(s, reference, n), db = side(t, reference, n);
        if (da != 0 && da == db) report(a, b);
    }
    for (std::size_t g = 0; g + 1 < topology.non_manifold_first.size(); ++g) {
        // Faces shared by more than two cells: two of one block on one side overlap.
        const std::uint32_t* slots = topology.non_manifold_slots.data() + topology.non_manifold_first[g];
        const std::size_t count = topology.non_manifold_first[g + 1] - topology.non_manifold_first[g];
        const std::uint32_t first_cell = topology.slot_cell[slots[0]];
        std::uint32_t reference[4];
        const int n = face_points(mesh, first_cell, slots[0] - topology.first_face[first_cell], reference);
        // Per block and side, every cell after the first overlaps the first.
        std::vector<std::pair<std::uint32_t, int>> firsts; // (first cell of a block and side, side)
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t c = topology.slot_cell[slots[i]];
            if (!solid(c)) continue;
            const int d = side(slots[i], reference, n);
            if (d == 0) continue;
            const auto first = std::find_if(firsts.begin(), firsts.end(), [&](const std::pair<std::uint32_t, int>& f) {
                return block[f.first] == block[c] && f.second == d;
            });
            if (first == firsts.end()) {
                firsts.emplace_back(c, d);
            } else {
                report(first->first, c);
            }
        }
    }
    // One entry per pair, ordered by the later cell.
    std::sort(out.begin(), out.end(), [](const CellOverlap& x, const CellOverlap& y) {
        return x.cell != y.cell ? x.cell < y.cell : x.other < y.other;
    });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const CellOverlap& x, const CellOverlap& y) { return x.cell == y.cell && x.other == y.other; }),
              out.end());
    return out;
}

std::string describe_overlap(const CellOverlap& o) {
    if (o.duplicate) return "cell " + std::to_string(o.cell) + " has the same points as cell " + std::to_string(o.other);
    return "cells " + std::to_string(o.other) + " and " + std::to_string(o.cell) +
           " lie on the same side of a face they share: they overlap";
}

std::vector<MeshProblem> validate_mesh(const CellMesh& mesh) {
    std::vector<MeshProblem> problems;
    auto report = [&](MeshProblemKind kind, std::size_t cell, std::string text) {
        problems.push_back(MeshProblem{kind, static_cast<std::uint32_t>(cell), cell_prefix(cell) + text});
    };
    const std::size_t n_points = mesh.point_count();
    std::vector<CellShape> shapes(mesh.cell_count(), CellShape::Unusable);
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const CellType type = mesh.cell_types[c];
        const int n = cell_vertex_count(type);
        const std::uint32_t* cv = mesh.cell_vertices(c);

        bool indices_ok = true;
        for (int i = 0; i < n; ++i) {
            if (cv[i] >= n_points) {
                report(MeshProblemKind::IndexOutOfRange, c,
                       "vertex " + std::to_string(i) + " is point " + std::to_string(cv[i]) + " but the mesh has " +
                           std::to_string(n_points) + " points");
                indices_ok = false;
            }
        }
        if (!indices_ok) continue;

        bool geometry_ok = true, repeated = false;
        for (int i = 0; i < n; ++i) {
            for (int j = i + 1; j < n; ++j) {
                if (cv[i] == cv[j]) {
                    report(MeshProblemKind::RepeatedVertex, c,
                           std::string(cell_type_name(type)) + " uses point " + std::to_string(cv[i]) +
                               " twice (vertices " + std::to_string(i) + " and " + std::to_string(j) + ")");
                    repeated = true;
                }
            }
            const glm::dvec3& p = mesh.points[cv[i]];
            if (!finite(p)) {
                report(MeshProblemKind::NonFiniteCoordinate, c,
                       "point " + std::to_string(cv[i]) + " (vertex " + std::to_string(i) + ") has a NaN or infinite coordinate");
                geometry_ok = false;
            } else if (!in_range(p)) {
                report(MeshProblemKind::CoordinateOutOfRange, c,
                       "point " + std::to_string(cv[i]) + " (vertex " + std::to_string(i) + ") has a coordinate beyond ±" +
                           number(kMaxCoordinate) + ", the range cellfx renders (scale the mesh)");
                geometry_ok = false;
            }
            for (const ScalarField& field : mesh.scalars) {
                if (cv[i] < field.values.size() && !std::isfinite(field.values[cv[i]])) {
                    report(MeshProblemKind::NonFiniteScalar, c,
                           "scalar '" + field.name + "' is not finite at point " + std::to_string(cv[i]));
                }
            }
        }
        if (!geometry_ok) continue;

        const double extent = cell_extent(mesh, c);
        const ScaledVolume v = extent > 0.0 ? scaled_volume(mesh, c, extent) : ScaledVolume{};
        shapes[c] = extent > 0.0 ? shape_of(v) : CellShape::Flat;
        const double volume = v.volume * extent * extent * extent; // for the message only
        switch (shapes[c]) {
        case CellShape::Flat:
            // A repeated point that collapses a cell is reported once, as the repeat.
            if (!repeated) report(MeshProblemKind::ZeroVolume, c, std::string(cell_type_name(type)) + " has zero volume");
            break;
        case CellShape::Inverted:
            report(MeshProblemKind::Inverted, c,
                   std::string(cell_type_name(type)) + " is inverted (volume " + number(volume) + "): its faces wind inward");
            break;
        case CellShape::Twisted:
            report(MeshProblemKind::Twisted, c,
                   std::string(cell_type_name(type)) + " folds over itself: parts of it have opposite orientations " +
                       "(a bow-tie, or a face listed the wrong way round)");
            break;
        case CellShape::Positive:
        case CellShape::Unusable: break;
        }
    }
    for (const CellOverlap& o : find_overlapping_cells(mesh, build_face_topology(mesh), shapes)) {
        report(o.duplicate ? MeshProblemKind::Duplicate : MeshProblemKind::Overlapping, o.cell, describe_overlap(o));
    }
    std::stable_sort(problems.begin(), problems.end(), [](const MeshProblem& a, const MeshProblem& b) { return a.cell < b.cell; });
    return problems;
}

std::vector<CellShape> check_renderable(const CellMesh& mesh, const std::string& who) {
    check_limit(Limit::MeshPoints, mesh.point_count(), who + ": the mesh");
    check_limit(Limit::MeshCells, mesh.cell_count(), who + ": the mesh");
    if (mesh.cell_offsets.size() != mesh.cell_count() + 1) {
        throw Error(who + ": the mesh has " + std::to_string(mesh.cell_count()) + " cells but " +
                    std::to_string(mesh.cell_offsets.size()) + " cell offsets");
    }
    std::vector<CellShape> shapes(mesh.cell_count());
    constexpr std::size_t kNamed = 5; // cells named in a message
    std::vector<std::size_t> twisted;
    std::size_t solid = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* cv = mesh.cell_vertices(c);
        for (int i = 0; i < cell_vertex_count(mesh.cell_types[c]); ++i) {
            if (cv[i] >= mesh.point_count()) {
                throw Error(who + ": " + cell_prefix(c) + "vertex " + std::to_string(i) + " is point " + std::to_string(cv[i]) +
                            " but the mesh has " + std::to_string(mesh.point_count()) + " points");
            }
            const glm::dvec3& p = mesh.points[cv[i]];
            if (!finite(p)) {
                throw Error(who + ": point " + std::to_string(cv[i]) + " (cell " + std::to_string(c) +
                            ") has a NaN or infinite coordinate");
            }
            if (!in_range(p)) {
                throw Error(who + ": point " + std::to_string(cv[i]) + " (cell " + std::to_string(c) + ") is at (" +
                            number(p.x) + ", " + number(p.y) + ", " + number(p.z) + "), beyond ±" + number(kMaxCoordinate) +
                            ", the coordinates cellfx renders (scale the mesh)");
            }
        }
        shapes[c] = classify_cell(mesh, c);
        if (shapes[c] == CellShape::Twisted && twisted.size() < kNamed) twisted.push_back(c);
        solid += shapes[c] == CellShape::Positive || shapes[c] == CellShape::Inverted;
    }
    if (!twisted.empty()) {
        std::size_t total = 0;
        for (CellShape s : shapes) total += s == CellShape::Twisted;
        std::string list;
        for (std::size_t c : twisted) list += (list.empty() ? "" : ", ") + std::to_string(c);
        throw Error(who + ": " + with_commas(total) + " cell" + (total > 1 ? "s fold" : " folds") + " over " +
                    (total > 1 ? "themselves" : "itself") + " (cell" + (twisted.size() > 1 ? "s " : " ") + list +
                    (total > twisted.size() ? ", ..." : "") +
                    "): parts of a cell with opposite orientations (a bow-tie, or a face listed the wrong way round) "
                    "have no inside a renderer could agree on; fix the vertex order (`cellfx info` lists them)");
    }
    if (solid == 0 && mesh.cell_count() > 0) {
        throw Error(who + ": all " + with_commas(mesh.cell_count()) + " cells have zero volume (flat or collapsed): " +
                    "there is nothing to render");
    }
    return shapes;
}

void check_scalar_field(const CellMesh& mesh, const ScalarField& field, const std::string& who) {
    if (field.values.size() != mesh.point_count()) {
        throw Error(who + ": field '" + field.name + "' has " + with_commas(field.values.size()) + " values for " +
                    with_commas(mesh.point_count()) + " points");
    }
    for (std::size_t i = 0; i < field.values.size(); ++i) {
        const float v = field.values[i];
        if (std::isfinite(v)) continue;
        std::size_t bad = 0;
        for (float x : field.values) bad += !std::isfinite(x);
        throw Error(who + ": field '" + field.name + "' is " + (std::isnan(v) ? "NaN" : "infinite") + " at point " +
                    std::to_string(i) + (bad > 1 ? " (and " + with_commas(bad - 1) + " more points)" : "") +
                    "; cellfx renders finite fields only (`cellfx info` shows each field's range)");
    }
}

CellShape orient_cell(CellMesh& mesh, std::size_t c) {
    const CellShape shape = classify_cell(mesh, c);
    if (shape != CellShape::Inverted) return shape;
    std::uint32_t* cv = mesh.cell_vertices(c);
    switch (mesh.cell_types[c]) {
    case CellType::Tetra: std::swap(cv[1], cv[2]); break;
    case CellType::Pyramid: std::swap(cv[1], cv[3]); break;
    case CellType::Wedge: std::swap_ranges(cv, cv + 3, cv + 3); break;
    case CellType::Hexahedron: std::swap_ranges(cv, cv + 4, cv + 4); break;
    }
    return shape;
}

OrientationReport orient_cells(CellMesh& mesh) {
    OrientationReport report;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const CellShape shape = orient_cell(mesh, c);
        if (shape == CellShape::Inverted) ++report.flipped;
        else if (shape != CellShape::Positive) report.degenerate.push_back(static_cast<std::uint32_t>(c));
    }
    return report;
}

} // namespace cellfx::fx
