// Helpers for the terrain tests: procedural fields, LOD mesh checks and surface sampling.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "terrain/continuous_lod.hpp"
#include "terrain/height_field.hpp"
#include "cellfx_names.hpp"

namespace terrain_test {

// Rolling hills with a few sharp features, deterministic; heights of order ±60 world units
// over a field `size` samples wide at `spacing`.
inline terrain::HeightField hills(int size, double spacing = 10.0) {
    return terrain::make_height_field(size, spacing, [&](double x, double y) {
        const double u = x / (spacing * (size - 1)), v = y / (spacing * (size - 1));
        return 40.0 * std::sin(7.0 * u) * std::cos(5.0 * v) + 15.0 * std::sin(23.0 * u + 11.0 * v) +
               60.0 * std::exp(-80.0 * ((u - 0.3) * (u - 0.3) + (v - 0.6) * (v - 0.6))) +
               8.0 * std::cos(41.0 * u * v);
    });
}

// Results of checking that a LOD mesh tiles the square without cracks or T-junctions.
struct TilingReport {
    std::size_t triangles = 0;
    std::size_t bad_orientation = 0;  // triangles not counter-clockwise from above
    std::size_t interior_edges_not_shared_twice = 0;
    std::size_t border_edges_not_once = 0;
    std::size_t t_junctions = 0;      // a mesh vertex strictly inside some edge
    double area = 0.0;                // sum of triangle areas in grid units²
};

inline TilingReport check_tiling(const terrain::LodMesh& mesh, int size) {
    TilingReport r;
    r.triangles = mesh.triangles.size();
    auto gi = [&](std::uint32_t v) { return int(mesh.grid_index[v] % std::uint32_t(size)); };
    auto gj = [&](std::uint32_t v) { return int(mesh.grid_index[v] / std::uint32_t(size)); };
    std::set<std::uint32_t> used;
    for (std::uint32_t g : mesh.grid_index) used.insert(g);
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& t : mesh.triangles) {
        const long ax = gi(t[0]), ay = gj(t[0]), bx = gi(t[1]), by = gj(t[1]), cx = gi(t[2]), cy = gj(t[2]);
        const long cross = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        if (cross <= 0) ++r.bad_orientation;
        r.area += 0.5 * double(cross);
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = mesh.grid_index[t[e]], b = mesh.grid_index[t[(e + 1) % 3]];
            ++directed[{a, b}];
        }
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
    for (const auto& [edge, count] : directed) {
        const std::uint32_t a = std::min(edge.first, edge.second), b = std::max(edge.first, edge.second);
        if (!seen.insert({a, b}).second) continue;
        const int forward = directed.count({a, b}) ? directed.at({a, b}) : 0;
        const int backward = directed.count({b, a}) ? directed.at({b, a}) : 0;
        const int ai = int(a % size), aj = int(a / size), bi = int(b % size), bj = int(b / size);
        const bool border = (ai == bi && (ai == 0 || ai == size - 1)) || (aj == bj && (aj == 0 || aj == size - 1));
        if (border) {
            if (forward + backward != 1) ++r.border_edges_not_once;
        } else if (forward != 1 || backward != 1) {
            ++r.interior_edges_not_shared_twice;
        }
        // Grid points strictly between a and b on the segment.
        const int di = bi - ai, dj = bj - aj;
        const int g = std::gcd(std::abs(di), std::abs(dj));
        for (int k = 1; k < g; ++k) {
            const std::uint32_t p = std::uint32_t(aj + dj / g * k) * std::uint32_t(size) + std::uint32_t(ai + di / g * k);
            if (used.count(p)) ++r.t_junctions;
        }
    }
    return r;
}

// Height of the mesh's surface (or of its layer top when `top`) above world (x, y); NaN if no
// triangle contains the point.
inline double surface_height(const terrain::LodMesh& mesh, double x, double y, bool top = false) {
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (det == 0.0) continue;
        const double wb = ((x - a.x) * (c.y - a.y) - (y - a.y) * (c.x - a.x)) / det;
        const double wc = ((b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)) / det;
        const double wa = 1.0 - wb - wc;
        const double eps = -1e-9;
        if (wa < eps || wb < eps || wc < eps) continue;
        double z = wa * a.z + wb * b.z + wc * c.z;
        if (top) z += wa * mesh.thickness[t[0]] + wb * mesh.thickness[t[1]] + wc * mesh.thickness[t[2]];
        return z;
    }
    return NAN;
}

} // namespace terrain_test
