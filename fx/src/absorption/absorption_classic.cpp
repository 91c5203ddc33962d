// Based on: Max, Williams & Silva 2000, §II (2-D exponential texture, analytic vertex colour
// divided by α) and §V (slicing cells at transfer-function breakpoints).
#include "absorption/absorption_classic.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"
#include "frame_storage.hpp"
#include "mesh/tetrahedralize.hpp"

namespace cellfx::fx {

OpacityTable build_opacity_table(int size, double max_product) {
    if (size < 2) throw Error("opacity table: size must be at least 2, got " + std::to_string(size));
    if (!(max_product > 0.0) || !std::isfinite(max_product))
        throw Error("opacity table: the largest product must be finite and positive");
    OpacityTable t;
    t.size = size;
    t.max_product = max_product;
    t.values.resize(std::size_t(size) * std::size_t(size));
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const double u = double(i) / (size - 1), v = double(j) / (size - 1);
            t.values[std::size_t(j) * size + i] = float(-std::expm1(-max_product * u * v));
        }
    return t;
}

double lookup_opacity(const OpacityTable& t, double u, double v) {
    const double x = std::clamp(u, 0.0, 1.0) * (t.size - 1), y = std::clamp(v, 0.0, 1.0) * (t.size - 1);
    const int i = std::min(int(x), t.size - 2), j = std::min(int(y), t.size - 2);
    const double fx = x - i, fy = y - j;
    auto at = [&](int a, int b) { return double(t.values[std::size_t(b) * t.size + a]); };
    return (at(i, j) * (1 - fx) + at(i + 1, j) * fx) * (1 - fy) + (at(i, j + 1) * (1 - fx) + at(i + 1, j + 1) * fx) * fy;
}

void ClassicGeometry::clear() {
    vertices.clear(), indices.clear();
    pieces = polygons = sliced_cells = clipped_pieces = culled_cells = 0;
}

void ClassicGeometry::append(const ClassicGeometry& o) {
    const std::uint32_t base = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), o.vertices.begin(), o.vertices.end());
    indices.reserve(indices.size() + o.indices.size());
    for (std::uint32_t i : o.indices) indices.push_back(base + i);
    pieces += o.pieces, polygons += o.polygons, sliced_cells += o.sliced_cells;
    clipped_pieces += o.clipped_pieces, culled_cells += o.culled_cells;
}

ClassicAbsorptionBuilder::ClassicAbsorptionBuilder(const ProjectorGeometry& geometry, const TransferFunction& tf,
                                                   const ClassicSettings& settings)
    : geometry_(geometry), tf_(tf), settings_(settings) {
    transfer_function_changed();
}

void ClassicAbsorptionBuilder::transfer_function_changed() {
    breakpoints_.clear();
    for (const TransferPoint& p : tf_.points())
        if (breakpoints_.empty() || p.s != breakpoints_.back()) breakpoints_.push_back(p.s);
}

void ClassicAbsorptionBuilder::set_view(const ProjectorView& view, const ProjectionFrame& frame) {
    view_ = view;
    frame_ = frame;
}

ClassicAbsorptionBuilder::Sample ClassicAbsorptionBuilder::sample(double s, double lo, double hi) const {
    if (s >= hi && hi > lo) {
        // A step at s is two points with that s: the first is the value from below.
        const std::vector<TransferPoint>& p = tf_.points();
        const auto it = std::lower_bound(p.begin(), p.end(), s, [](const TransferPoint& q, double v) { return q.s < v; });
        if (it != p.end() && it->s == s && it + 1 != p.end() && (it + 1)->s == s) return {it->color, it->sigma};
    }
    return {tf_.color(s), tf_.sigma(s)};
}

PolyVertex ClassicAbsorptionBuilder::vertex(std::uint32_t point) const {
    return {glm::dvec3(geometry_.positions[point]), double(geometry_.scalars[point])};
}

void ClassicAbsorptionBuilder::append(const CellMesh& cells, const std::uint32_t* order, std::size_t count,
                                      ClassicGeometry& out) {
    for (std::size_t i = 0; i < count; ++i) append_cell(cells, order[i], out);
}

void ClassicAbsorptionBuilder::append_cell(const CellMesh& cells, std::uint32_t cell, ClassicGeometry& out) {
    const CellType type = cells.cell_types[cell];
    const std::uint32_t* cv = cells.cell_vertices(cell);
    const int n = cell_vertex_count(type);
    double dmin = 1e300, dmax = -1e300, smin = 1e300, smax = -1e300;
    for (int i = 0; i < n; ++i) {
        const double d = view_.depth(glm::dvec3(geometry_.positions[cv[i]]));
        const double s = geometry_.scalars[cv[i]];
        dmin = std::min(dmin, d), dmax = std::max(dmax, d), smin = std::min(smin, s), smax = std::max(smax, s);
    }
    if (!(dmax > 0.0)) {
        ++out.culled_cells; // wholly behind the near plane
        return;
    }
    bool slice = false;
    if (settings_.slice_breakpoints)
        for (double b : breakpoints_) slice |= smin < b && b < smax;

    if (slice) ++out.sliced_cells;
    if (type == CellType::Tetra) {
        append_tetrahedron({cv[0], cv[1], cv[2], cv[3]}, slice, out);
        return;
    }

    // Other cells: their consistent tetrahedra (§IV), ordered back to front among themselves
    // through their shared faces, each projected as a tetrahedron (Shirley–Tuchman, or sliced).
    // A hexahedron then costs what its five or six tetrahedra cost; the overlay of its up to
    // 6 × 6 front and back triangles took 1.4 times the instructions. A cell with a problem
    // face is already cut for this view (view_dependent_subdivision.hpp); in the others no ray
    // from the eye leaves the cell and enters it again, so this local order (MPVO on at most
    // six tetrahedra) is exact.
    std::uint32_t tets[kMaxCellTetrahedra][4];
    const int nt = subdivide_cell(type, cv, tets);
    int in_degree[kMaxCellTetrahedra] = {};
    bool before[kMaxCellTetrahedra][kMaxCellTetrahedra] = {}; // before[i][j]: i is drawn before j
    const glm::dvec3 eye = view_.eye, towards_eye = -view_.forward;
    for (int i = 0; i < nt; ++i)
        for (int j = i + 1; j < nt; ++j) {
            std::uint32_t shared[4], off_i = 0;
            int m = 0;
            for (int a = 0; a < 4; ++a) {
                if (std::find(tets[j], tets[j] + 4, tets[i][a]) != tets[j] + 4) shared[m++] = tets[i][a];
                else off_i = tets[i][a];
            }
            if (m != 3) continue;
            const glm::dvec3 a = vertex(shared[0]).position, b = vertex(shared[1]).position,
                             c = vertex(shared[2]).position;
            const glm::dvec3 normal = glm::cross(b - a, c - a);
            const double side_i = glm::dot(normal, vertex(off_i).position - a);
            const double side_eye = glm::dot(normal, view_.orthographic ? towards_eye : eye - a);
            if (side_i * side_eye > 0.0) before[j][i] = true, ++in_degree[i]; // i is nearer: drawn after j
            else if (side_i * side_eye < 0.0) before[i][j] = true, ++in_degree[j];
        }
    bool done[kMaxCellTetrahedra] = {};
    for (int emitted = 0; emitted < nt; ++emitted) {
        int next = -1;
        for (int i = 0; i < nt && next < 0; ++i)
            if (!done[i] && in_degree[i] == 0) next = i;
        if (next < 0) // a cycle (only in badly warped cells): take the rest in index order
            for (int i = 0; i < nt && next < 0; ++i)
                if (!done[i]) next = i;
        done[next] = true;
        for (int j = 0; j < nt; ++j)
            if (before[next][j]) --in_degree[j];
        append_tetrahedron({tets[next][0], tets[next][1], tets[next][2], tets[next][3]}, slice, out);
    }
}

void ClassicAbsorptionBuilder::append_tetrahedron(const std::array<std::uint32_t, 4>& tet, bool slice,
                                                  ClassicGeometry& out) {
    std::array<PolyVertex, 4> v;
    double dmin = 1e300, dmax = -1e300, smin = 1e300, smax = -1e300;
    for (int i = 0; i < 4; ++i) {
        v[i] = vertex(tet[i]);
        const double d = view_.depth(v[i].position);
        dmin = std::min(dmin, d), dmax = std::max(dmax, d);
        smin = std::min(smin, v[i].scalar), smax = std::max(smax, v[i].scalar);
    }
    if (!(dmax > 0.0)) return;
    // Breakpoints strictly inside this tetrahedron's scalar range.
    double cuts[64];
    int m = 0;
    if (slice)
        for (double b : breakpoints_)
            if (smin < b && b < smax && m < 64) cuts[m++] = b;
    // The scalar's gradient (linear in a tetrahedron); a flat tetrahedron is not sliced.
    const glm::dvec3 e1 = v[1].position - v[0].position, e2 = v[2].position - v[0].position,
                     e3 = v[3].position - v[0].position;
    const double det = glm::dot(e1, glm::cross(e2, e3));
    const double size = std::max({glm::length(e1), glm::length(e2), glm::length(e3)});
    if (m > 0 && !(std::abs(det) > 1e-12 * size * size * size)) m = 0;

    if (m == 0 && dmin >= 0.0) {
        subdivision_.clear();
        builder_.tetrahedron(frame_, v, subdivision_);
        ++out.pieces;
        emit(smin, smax, out);
        return;
    }
    poly_.clear();
    assign_range_kept(poly_.vertices, v.begin(), v.end());
    for (int k = 0; k < cell_face_count(CellType::Tetra); ++k) {
        const CellFace& face = cell_faces(CellType::Tetra)[k];
        poly_.triangles.push_back({face.v[0], face.v[1], face.v[2]});
    }
    // A tetrahedron of an inverted (negatively wound) cell: flip so faces wind outward.
    if (det < 0.0)
        for (auto& t : poly_.triangles) std::swap(t[1], t[2]);
    if (m == 0) {
        append_piece(poly_, smin, smax, dmin < 0.0, out);
        return;
    }

    const glm::dvec3 gradient = ((v[1].scalar - v[0].scalar) * glm::cross(e2, e3) +
                                 (v[2].scalar - v[0].scalar) * glm::cross(e3, e1) +
                                 (v[3].scalar - v[0].scalar) * glm::cross(e1, e2)) /
                                det;
    // Slabs between consecutive cuts, by successive clipping (each cut vertex carries the
    // breakpoint's value exactly).
    thread_local std::vector<ConvexPolyhedron> slabs; // never shrunk: each slab keeps its storage
    if (slabs.size() < std::size_t(m) + 1) slabs.resize(std::size_t(m) + 1);
    rest_ = poly_;
    for (int k = 0; k < m; ++k) {
        resize_kept(f_, rest_.vertices.size());
        for (std::size_t i = 0; i < f_.size(); ++i) f_[i] = cuts[k] - rest_.vertices[i].scalar;
        clip_polyhedron(rest_, f_, -gradient, slabs[k], cuts[k]);
        for (double& x : f_) x = -x;
        clip_polyhedron(rest_, f_, gradient, slab_, cuts[k]);
        std::swap(rest_, slab_);
    }
    slabs[m] = rest_;
    // Back to front: slabs are separated by parallel planes, so along any ray from the eye the
    // scalar moves monotonically away from its value at the eye; farther in s is farther.
    int order[65];
    for (int k = 0; k <= m; ++k) order[k] = k;
    auto lo_of = [&](int k) { return k == 0 ? smin : cuts[k - 1]; };
    auto hi_of = [&](int k) { return k == m ? smax : cuts[k]; };
    if (view_.orthographic) {
        // Rays share one direction: where s grows away from the eye the highest slab is farthest.
        if (glm::dot(gradient, view_.forward) > 0.0) std::reverse(order, order + m + 1);
    } else {
        const double s_eye = v[0].scalar + glm::dot(gradient, view_.eye - v[0].position);
        auto distance = [&](int k) {
            return lo_of(k) >= s_eye ? lo_of(k) - s_eye : (hi_of(k) <= s_eye ? s_eye - hi_of(k) : 0.0);
        };
        // Stable, farthest first; an insertion sort of at most 65 slabs (std::stable_sort takes a
        // heap buffer per call).
        for (int i = 1; i <= m; ++i) {
            const int k = order[i];
            const double dk = distance(k);
            int j = i;
            for (; j > 0 && distance(order[j - 1]) < dk; --j) order[j] = order[j - 1];
            order[j] = k;
        }
    }
    for (int i = 0; i <= m; ++i) append_piece(slabs[order[i]], lo_of(order[i]), hi_of(order[i]), dmin < 0.0, out);
}

void ClassicAbsorptionBuilder::append_piece(const ConvexPolyhedron& piece, double lo, double hi, bool cut_by_near,
                                            ClassicGeometry& out) {
    const ConvexPolyhedron* p = &piece;
    if (cut_by_near) {
        resize_kept(f_, piece.vertices.size());
        for (std::size_t i = 0; i < f_.size(); ++i) f_[i] = view_.depth(piece.vertices[i].position);
        clip_polyhedron(piece, f_, view_.forward, clipped_);
        if (clipped_.triangles.empty()) return;
        p = &clipped_;
        ++out.clipped_pieces;
    }
    subdivision_.clear();
    builder_.polyhedron(frame_, *p, subdivision_);
    ++out.pieces;
    emit(lo, hi, out);
}

void ClassicAbsorptionBuilder::emit(double lo, double hi, ClassicGeometry& out) {
    const std::size_t nv = subdivision_.vertices.size();
    if (subdivision_.polygon_count() == 0 || nv == 0) return;
    const std::uint32_t base = static_cast<std::uint32_t>(out.vertices.size());
    double l_max = 0.0, tau_max = 0.0;
    resize_kept(tau_, nv);
    resize_kept(color_, nv);
    for (std::size_t i = 0; i < nv; ++i) {
        // The piece's scalar lies in [lo, hi] by construction; interpolation may round past
        // an end, which at a step would pick the other side's value.
        SubdivisionVertex sv = subdivision_.vertices[i];
        sv.s_front = std::clamp(sv.s_front, lo, hi), sv.s_back = std::clamp(sv.s_back, lo, hi);
        const Sample f = sample(sv.s_front, lo, hi), b = sample(sv.s_back, lo, hi);
        const double tau_mean = 0.5 * (f.sigma + b.sigma);
        glm::dvec3 color(0.0);
        bool analytic = false;
        if (sv.thickness > 0.0 && sv.s_front == sv.s_back) {
            color = f.color; // constant medium: C = c·α
            analytic = true;
        } else if (sv.thickness > 0.0) {
            const SegmentColor seg = emission_absorption(tf_, sv.s_front, sv.s_back, sv.thickness);
            if (seg.alpha > 0.0) color = seg.color / seg.alpha, analytic = true;
        }
        if (!analytic) {
            // Profile vertex (l = 0) or a ray with no extinction: the limit of C/α, the
            // extinction-weighted mean glow colour (the glow colour itself where s_f = s_b).
            const double w = f.sigma + b.sigma;
            color = w > 0.0 ? (f.color * (2.0 * f.sigma + b.sigma) + b.color * (f.sigma + 2.0 * b.sigma)) / (3.0 * w)
                            : 0.5 * (f.color + b.color);
        }
        l_max = std::max(l_max, sv.thickness);
        tau_max = std::max(tau_max, tau_mean);
        tau_[i] = tau_mean;
        color_[i] = color;
    }
    // Joint scaling of thickness and extinction for this piece (only u·v = l·τ_a/K matters).
    const double k = settings_.max_product;
    const double a = l_max > 0.0 && tau_max > 0.0 ? std::sqrt(l_max * k / tau_max) : 1.0;
    for (std::size_t i = 0; i < nv; ++i) {
        const SubdivisionVertex& sv = subdivision_.vertices[i];
        const glm::dvec2 ndc = frame_.snap(sv.ndc);
        out.vertices.push_back({glm::vec4(float(ndc.x), float(ndc.y), float(sv.thickness / a), float(tau_[i] * a / k)),
                                glm::vec3(color_[i]), glm::vec2(float(sv.depth_front), float(sv.depth_back))});
    }
    for (std::size_t q = 0; q < subdivision_.polygon_count(); ++q) {
        const std::uint32_t b = subdivision_.polygon_start[q], e = subdivision_.polygon_start[q + 1];
        for (std::uint32_t i = b + 1; i + 1 < e; ++i) {
            out.indices.push_back(base + subdivision_.polygon_vertices[b]);
            out.indices.push_back(base + subdivision_.polygon_vertices[i]);
            out.indices.push_back(base + subdivision_.polygon_vertices[i + 1]);
        }
    }
    out.polygons += subdivision_.polygon_count();
}

} // namespace cellfx::fx
