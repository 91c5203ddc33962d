#include "fx/mesh_validation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

namespace fx {
namespace {

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

double tet_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::dot(b - a, glm::cross(c - a, d - a)) / 6.0;
}

// Calls visit(signed volume) for every tetrahedron (centroid, face triangle) of the cell; the
// volumes sum to the cell's signed volume. Quads are split through their own centroid.
// Coordinates are taken relative to the cell's first vertex so that cells far from the origin
// keep their precision.
template <class Visit>
void for_each_centroid_tet(const CellMesh& mesh, std::size_t cell, Visit visit) {
    const CellType type = mesh.cell_types[cell];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    const int n = cell_vertex_count(type);
    const glm::dvec3 origin = mesh.points[cv[0]];
    glm::dvec3 p[kMaxCellVertices];
    glm::dvec3 centre(0.0);
    for (int i = 0; i < n; ++i) {
        p[i] = mesh.points[cv[i]] - origin;
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

double cell_extent(const CellMesh& mesh, std::size_t cell) {
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    glm::dvec3 lo = mesh.points[cv[0]], hi = lo;
    for (int i = 1; i < cell_vertex_count(mesh.cell_types[cell]); ++i) {
        lo = glm::min(lo, mesh.points[cv[i]]);
        hi = glm::max(hi, mesh.points[cv[i]]);
    }
    return glm::length(hi - lo);
}

std::string cell_prefix(std::size_t cell) { return "cell " + std::to_string(cell) + ": "; }

} // namespace

const char* mesh_problem_name(MeshProblemKind kind) {
    switch (kind) {
    case MeshProblemKind::IndexOutOfRange: return "index out of range";
    case MeshProblemKind::NonFiniteCoordinate: return "non-finite coordinate";
    case MeshProblemKind::NonFiniteScalar: return "non-finite scalar";
    case MeshProblemKind::RepeatedVertex: return "repeated vertex";
    case MeshProblemKind::ZeroVolume: return "zero volume";
    case MeshProblemKind::Inverted: return "inverted";
    case MeshProblemKind::Twisted: return "twisted";
    }
    return "unknown";
}

double cell_signed_volume(const CellMesh& mesh, std::size_t cell) {
    double volume = 0.0;
    for_each_centroid_tet(mesh, cell, [&](double v) { volume += v; });
    return volume;
}

std::vector<MeshProblem> validate_mesh(const CellMesh& mesh) {
    std::vector<MeshProblem> problems;
    auto report = [&](MeshProblemKind kind, std::size_t cell, std::string text) {
        problems.push_back(MeshProblem{kind, static_cast<std::uint32_t>(cell), cell_prefix(cell) + text});
    };
    const std::size_t n_points = mesh.point_count();
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

        bool geometry_ok = true;
        for (int i = 0; i < n; ++i) {
            for (int j = i + 1; j < n; ++j) {
                if (cv[i] == cv[j]) {
                    report(MeshProblemKind::RepeatedVertex, c,
                           std::string(cell_type_name(type)) + " uses point " + std::to_string(cv[i]) +
                               " twice (vertices " + std::to_string(i) + " and " + std::to_string(j) + ")");
                    geometry_ok = false;
                }
            }
            if (!finite(mesh.points[cv[i]])) {
                report(MeshProblemKind::NonFiniteCoordinate, c,
                       "point " + std::to_string(cv[i]) + " (vertex " + std::to_string(i) + ") has a NaN or infinite coordinate");
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

        double volume = 0.0, most_negative = 0.0;
        for_each_centroid_tet(mesh, c, [&](double v) {
            volume += v;
            most_negative = std::min(most_negative, v);
        });
        const double extent = cell_extent(mesh, c);
        // A volume below 1e-9 of the cell's own bounding cube is a flat cell at any scale.
        if (std::abs(volume) <= 1e-9 * extent * extent * extent) {
            report(MeshProblemKind::ZeroVolume, c,
                   std::string(cell_type_name(type)) + " has zero volume (" + std::to_string(volume) + ")");
        } else if (volume < 0.0) {
            report(MeshProblemKind::Inverted, c,
                   std::string(cell_type_name(type)) + " is inverted (volume " + std::to_string(volume) +
                       "): its faces wind inward");
        } else if (most_negative < -1e-9 * volume) {
            report(MeshProblemKind::Twisted, c,
                   std::string(cell_type_name(type)) + " folds over itself: part of it has negative volume");
        }
    }
    return problems;
}

OrientationReport orient_cells(CellMesh& mesh) {
    OrientationReport report;
    const std::size_t n_points = mesh.point_count();
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const CellType type = mesh.cell_types[c];
        const int n = cell_vertex_count(type);
        std::uint32_t* cv = mesh.cell_vertices(c);
        bool usable = true;
        for (int i = 0; i < n && usable; ++i) {
            usable = cv[i] < n_points && finite(mesh.points[cv[i]]);
            for (int j = i + 1; j < n && usable; ++j) usable = cv[i] != cv[j];
        }
        const double volume = usable ? cell_signed_volume(mesh, c) : 0.0;
        const double extent = usable ? cell_extent(mesh, c) : 0.0;
        if (!usable || std::abs(volume) <= 1e-9 * extent * extent * extent) {
            report.degenerate.push_back(static_cast<std::uint32_t>(c));
            continue;
        }
        if (volume > 0.0) continue;
        switch (type) {
        case CellType::Tetra: std::swap(cv[1], cv[2]); break;
        case CellType::Pyramid: std::swap(cv[1], cv[3]); break;
        case CellType::Wedge: std::swap_ranges(cv, cv + 3, cv + 3); break;
        case CellType::Hexahedron: std::swap_ranges(cv, cv + 4, cv + 4); break;
        }
        ++report.flipped;
    }
    return report;
}

} // namespace fx
