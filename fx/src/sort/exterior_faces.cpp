// Based on: Max, Williams & Silva 2000, §III (XMPVO: "adding directed edges between two
// boundary cells whenever there is a viewing ray crossing them both", Silva, Mitchell &
// Williams 1998).
//
// Why this makes the sort exact (docs/visibility_sort.md has the long form): let a ray meet
// cell X before cell Y. Between them it runs through cells joined by shared faces, each
// crossing an MPVO edge pointing the right way, and through gaps outside the mesh, each
// entered through a boundary face g of a cell B that faces away from the eye and left through
// a boundary face f of a cell A that faces it, g nearer. An edge A → B for every such pair
// closes every chain, so Y precedes X.
//
// Finding the pairs per view: every boundary triangle facing away from the eye (g) or towards
// it (f) is clipped to the near plane and projected. Projections are binned into a uniform
// grid of tiles sized from the median projection (the few that cover many tiles are tested
// against all others instead); each (g, f) pair sharing a tile is tested once: depth ranges
// (lists in depth order, so the scan stops early), bounding boxes, then the exact
// intersection of the two convex projections. If it has positive area, which side of each
// other's plane the triangles lie on decides. Two boundary faces of a valid mesh do not
// cross, so one is in front over the whole overlap.
// Coincident faces (a quad against two triangles, non-manifold faces) count as g nearer: the
// ray leaves B and enters A at the same point.
#include "exterior_faces.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "frame_storage.hpp"

namespace cellfx::fx::sort_detail {
using Projection = ExteriorProjection;

namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

// A projected boundary triangle: counter-clockwise convex polygon (≤ 4 vertices after the
// near-plane clip) in image coordinates (x/depth, y/depth; x, y for orthographic cameras).
// Keeps the part of triangle q (eye space: x, y, depth) with depth ≥ near.
int clip_to_near(const glm::dvec3 q[3], double near, glm::dvec3 out[4]) {
    int count = 0;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3& a = q[i];
        const glm::dvec3& b = q[(i + 1) % 3];
        const bool a_in = a.z >= near, b_in = b.z >= near;
        if (a_in) out[count++] = a;
        if (a_in != b_in) out[count++] = a + (b - a) * ((near - a.z) / (b.z - a.z));
    }
    return count;
}

double polygon_area(const double* x, const double* y, int n) {
    double twice = 0.0;
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        twice += x[i] * y[j] - x[j] * y[i];
    }
    return 0.5 * twice;
}

// Sutherland–Hodgman: the part of convex polygon p inside convex counter-clockwise polygon q.
// Output has at most pn + qn vertices.
int clip_polygon(const Projection& p, const Projection& q, double* ox, double* oy) {
    double ax[12], ay[12], bx[12], by[12];
    int n = p.count;
    for (int i = 0; i < n; ++i) ax[i] = p.x[i], ay[i] = p.y[i];
    for (int e = 0; e < q.count && n > 0; ++e) {
        const double ex = q.x[e], ey = q.y[e];
        const double dx = q.x[(e + 1) % q.count] - ex, dy = q.y[(e + 1) % q.count] - ey;
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const int j = (i + 1) % n;
            const double si = dx * (ay[i] - ey) - dy * (ax[i] - ex);
            const double sj = dx * (ay[j] - ey) - dy * (ax[j] - ex);
            if (si >= 0.0) bx[m] = ax[i], by[m] = ay[i], ++m;
            if ((si >= 0.0) != (sj >= 0.0)) {
                const double t = si / (si - sj);
                bx[m] = ax[i] + (ax[j] - ax[i]) * t;
                by[m] = ay[i] + (ay[j] - ay[i]) * t;
                ++m;
            }
        }
        n = m;
        for (int i = 0; i < n; ++i) ax[i] = bx[i], ay[i] = by[i];
    }
    for (int i = 0; i < n; ++i) ox[i] = ax[i], oy[i] = ay[i];
    return n;
}

} // namespace

ExteriorFaces::ExteriorFaces(const CellMesh& mesh, const FaceTopology& topology) { build(mesh, topology); }

void ExteriorFaces::build(const CellMesh& mesh, const FaceTopology& topology) {
    mesh_ = &mesh;
    triangles_.clear();
    for (std::uint32_t slot : topology.boundary_faces) {
        const std::uint32_t c = topology.slot_cell[slot];
        const CellType type = mesh.cell_types[c];
        const std::uint32_t* cv = mesh.cell_vertices(c);
        glm::dvec3 centroid(0.0);
        for (int i = 0; i < cell_vertex_count(type); ++i) centroid += mesh.points[cv[i]];
        centroid /= double(cell_vertex_count(type));
        std::uint32_t tris[2][3];
        const int count = triangulate_face(cell_faces(type)[slot - topology.first_face[c]], cv, tris);
        for (int t = 0; t < count; ++t) {
            Triangle tri{{tris[t][0], tris[t][1], tris[t][2]}, c};
            const glm::dvec3 a = mesh.points[tri.v[0]];
            const glm::dvec3 n = glm::cross(mesh.points[tri.v[1]] - a, mesh.points[tri.v[2]] - a);
            if (glm::dot(n, centroid - a) > 0.0) std::swap(tri.v[1], tri.v[2]); // make it outward
            triangles_.push_back(tri);
        }
    }
}

void ExteriorFaces::edges(const Camera& camera, ExteriorEdges& out, SortStats& stats) const {
    const auto t0 = clock_type::now();
    const bool ortho = camera.orthographic();
    const glm::dvec3 f = camera.forward();
    const glm::dvec3 r = camera.right();
    const glm::dvec3 u = glm::cross(r, f);
    const double near = camera.near_distance;

    // Project the triangles that face towards (front) or away from (back) the eye.
    std::vector<Projection>& front = front_;
    std::vector<Projection>& back = back_;
    front.clear(), back.clear();
    for (const Triangle& tri : triangles_) {
        const glm::dvec3 a = mesh_->points[tri.v[0]];
        const glm::dvec3 normal = glm::cross(mesh_->points[tri.v[1]] - a, mesh_->points[tri.v[2]] - a);
        const double side = ortho ? -glm::dot(normal, f) : glm::dot(normal, camera.eye - a);
        if (side == 0.0) continue; // edge-on: covers no area
        glm::dvec3 q[3];
        for (int i = 0; i < 3; ++i) {
            const glm::dvec3 d = mesh_->points[tri.v[i]] - camera.eye;
            q[i] = glm::dvec3(glm::dot(d, r), glm::dot(d, u), glm::dot(d, f));
        }
        glm::dvec3 clipped[4];
        const int count = clip_to_near(q, near, clipped);
        if (count < 3) continue;
        Projection p;
        p.count = count;
        p.depth_lo = p.depth_hi = clipped[0].z;
        for (int i = 0; i < count; ++i) {
            const double s = ortho ? 1.0 : 1.0 / clipped[i].z;
            p.x[i] = clipped[i].x * s;
            p.y[i] = clipped[i].y * s;
            p.depth_lo = std::min(p.depth_lo, clipped[i].z);
            p.depth_hi = std::max(p.depth_hi, clipped[i].z);
        }
        p.area = polygon_area(p.x, p.y, count);
        if (p.area < 0.0) {
            std::reverse(p.x, p.x + count);
            std::reverse(p.y, p.y + count);
            p.area = -p.area;
        }
        if (!(p.area > 0.0) || !std::isfinite(p.area)) continue;
        p.lo_x = *std::min_element(p.x, p.x + count), p.hi_x = *std::max_element(p.x, p.x + count);
        p.lo_y = *std::min_element(p.y, p.y + count), p.hi_y = *std::max_element(p.y, p.y + count);
        p.triangle = static_cast<std::uint32_t>(&tri - triangles_.data());
        p.cell = tri.cell;
        p.big = false;
        (side > 0.0 ? front : back).push_back(p);
    }
    stats.exterior_faces = front.size() + back.size();
    // Depth order lets the scans below stop early: a g that starts behind h's far end cannot
    // be nearer than h anywhere.
    std::sort(front.begin(), front.end(), [](const Projection& a, const Projection& b) { return a.depth_hi > b.depth_hi; });
    std::sort(back.begin(), back.end(), [](const Projection& a, const Projection& b) { return a.depth_lo < b.depth_lo; });
    auto depth_rules_out = [](const Projection& g, const Projection& h) { return g.depth_lo > h.depth_hi * (1.0 + 1e-9); };

    // Over their overlap, is g (facing away) nearer than h (facing the eye)? Decided by which
    // side of each other's plane the triangles lie (Newell's tests 4 and 5, §III): the eye is
    // on h's outer side and g's inner side, so g lies nearer wherever g is on h's outer side or
    // h on g's outer side. Plane-side tests stay well conditioned for faces seen nearly
    // edge-on, whose depth along a ray does not. Only if the triangles straddle each other's
    // planes are the depths along the ray through the centroid of the overlap compared.
    auto g_is_nearer = [&](const Projection& g, const Projection& h, const double* px, const double* py, int count,
                           double area) {
        const Triangle& tg = triangles_[g.triangle];
        const Triangle& th = triangles_[h.triangle];
        const glm::dvec3 vg[3] = {mesh_->points[tg.v[0]], mesh_->points[tg.v[1]], mesh_->points[tg.v[2]]};
        const glm::dvec3 vh[3] = {mesh_->points[th.v[0]], mesh_->points[th.v[1]], mesh_->points[th.v[2]]};
        const glm::dvec3 ng = glm::normalize(glm::cross(vg[1] - vg[0], vg[2] - vg[0]));
        const glm::dvec3 nh = glm::normalize(glm::cross(vh[1] - vh[0], vh[2] - vh[0]));
        double size = 0.0;
        for (int i = 0; i < 3; ++i) {
            size = std::max({size, glm::length(vg[(i + 1) % 3] - vg[i]), glm::length(vh[(i + 1) % 3] - vh[i])});
        }
        const double eps = 1e-9 * size;
        // all_out: every vertex of `v` on the outer side of the plane (n, a); all_in: inner.
        auto sides = [&](const glm::dvec3* v, const glm::dvec3& n, const glm::dvec3& a, bool& all_out, bool& all_in) {
            all_out = all_in = true;
            for (int i = 0; i < 3; ++i) {
                const double d = glm::dot(n, v[i] - a);
                all_out = all_out && d >= -eps;
                all_in = all_in && d <= eps;
            }
        };
        bool g_out_of_h, g_in_h, h_out_of_g, h_in_g;
        sides(vg, nh, vh[0], g_out_of_h, g_in_h);
        sides(vh, ng, vg[0], h_out_of_g, h_in_g);
        const bool nearer = g_out_of_h || h_out_of_g;
        const bool farther = g_in_h || h_in_g;
        if (nearer != farther) return nearer;
        if (nearer) return true; // coplanar and coincident: B is left where A is entered
        // Both straddle: compare where the ray through the overlap's centroid meets the planes.
        double cx = 0.0, cy = 0.0;
        for (int i = 0; i < count; ++i) {
            const int j = (i + 1) % count;
            const double w = px[i] * py[j] - px[j] * py[i];
            cx += (px[i] + px[j]) * w;
            cy += (py[i] + py[j]) * w;
        }
        cx /= 6.0 * area, cy /= 6.0 * area;
        const glm::dvec3 origin = ortho ? camera.eye + r * cx + u * cy : camera.eye;
        const glm::dvec3 dir = ortho ? f : r * cx + u * cy + f; // unit depth per unit parameter
        const double dg = glm::dot(ng, vg[0] - origin) / glm::dot(ng, dir);
        const double dh = glm::dot(nh, vh[0] - origin) / glm::dot(nh, dir);
        return dg <= dh + 1e-9 * std::abs(dh);
    };

    std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs = pairs_;
    pairs.clear();
    std::size_t tested = 0;
    // A valid mesh has a few overlapping boundary-face pairs per face; cells that overlap one
    // another (n copies of a cell: n² pairs) would make this quadratic. The sort-pairs budget
    // stops that with an error instead of a hang.
    const std::uint64_t per_face = limit_value(resource_limits(), Limit::SortPairs);
    const std::uint64_t faces = front.size() + back.size();
    const std::uint64_t max_tested = per_face * faces + (std::uint64_t(1) << 20);
    double ox[12], oy[12];
    // The exact test of a pair whose bounding boxes overlap and depths allow g nearer.
    auto test_pair = [&](const Projection& g, const Projection& h) {
        if (++tested > max_tested) {
            throw Error("visibility sort (xmpvo): " +
                        over_limit(Limit::SortPairs, per_face + 1,
                                   "the " + with_commas(faces) + " boundary faces in view overlap on screen in more than " +
                                       with_commas(max_tested) + " pairs; each face") +
                        ". Cells that overlap one another (duplicates: `cellfx info` lists them) have no back-to-front "
                        "order; fix the mesh, or use --sort centroid");
        }
        const int count = clip_polygon(g, h, ox, oy);
        if (count < 3) return;
        const double area = polygon_area(ox, oy, count);
        // Positive area well above rounding: faces that only touch give slivers.
        if (!(area > 1e-9 * std::min(g.area, h.area))) return;
        if (g_is_nearer(g, h, ox, oy, count, area)) pairs.emplace_back(h.cell, g.cell);
    };
    auto boxes_overlap = [](const Projection& a, const Projection& b) {
        return std::max(a.lo_x, b.lo_x) < std::min(a.hi_x, b.hi_x) && std::max(a.lo_y, b.lo_y) < std::min(a.hi_y, b.hi_y);
    };

    std::vector<std::uint32_t>(&tile_first)[2] = tile_first_;
    std::vector<std::uint32_t>(&tile_items)[2] = tile_items_;
    std::vector<std::uint32_t>& big_front = big_front_;
    std::vector<std::uint32_t>& big_back = big_back_;
    big_front.clear(), big_back.clear();
    for (int l = 0; l < 2; ++l) tile_first[l].clear(), tile_items[l].clear();
    if (!front.empty() && !back.empty()) {
        // Tiles: about twice the median projection, at most ~2 tiles per projection. A
        // projection over more than kBigTiles tiles (near the eye) is kept out of the tiles
        // and tested against every opposite projection in depth order instead.
        constexpr int kBigTiles = 16;
        const std::size_t m = front.size() + back.size();
        double lo_x = front[0].lo_x, lo_y = front[0].lo_y, hi_x = front[0].hi_x, hi_y = front[0].hi_y;
        std::vector<double>& extent = extent_;
        extent.clear();
        for (const auto* list : {&front, &back}) {
            for (const Projection& p : *list) {
                lo_x = std::min(lo_x, p.lo_x), lo_y = std::min(lo_y, p.lo_y);
                hi_x = std::max(hi_x, p.hi_x), hi_y = std::max(hi_y, p.hi_y);
                extent.push_back(std::max(p.hi_x - p.lo_x, p.hi_y - p.lo_y));
            }
        }
        std::nth_element(extent.begin(), extent.begin() + m / 2, extent.end());
        const double width = std::max(hi_x - lo_x, hi_y - lo_y);
        double tile = std::max(2.0 * extent[m / 2], width * 1e-6);
        const double max_tiles = 2.0 * double(m) + 64.0;
        const double tiles = std::ceil((hi_x - lo_x) / tile + 1.0) * std::ceil((hi_y - lo_y) / tile + 1.0);
        if (tiles > max_tiles) tile *= std::sqrt(tiles / max_tiles);
        const int nx = std::max(1, static_cast<int>(std::ceil((hi_x - lo_x) / tile)));
        const int ny = std::max(1, static_cast<int>(std::ceil((hi_y - lo_y) / tile)));
        auto tile_x = [&](double x) { return std::clamp(static_cast<int>((x - lo_x) / tile), 0, nx - 1); };
        auto tile_y = [&](double y) { return std::clamp(static_cast<int>((y - lo_y) / tile), 0, ny - 1); };
        std::vector<Projection>* lists[2] = {&back, &front};
        std::vector<std::uint32_t>* bigs[2] = {&big_back, &big_front};
        for (int l = 0; l < 2; ++l) {
            // Compressed rows: tile t holds items[first[t] .. first[t + 1]), in depth order.
            std::vector<std::uint32_t>& first = tile_first[l];
            std::vector<std::uint32_t>& items = tile_items[l];
            assign_kept(first, std::size_t(nx) * ny + 1, 0u);
            for (std::uint32_t i = 0; i < lists[l]->size(); ++i) {
                Projection& p = (*lists[l])[i];
                const int tx0 = tile_x(p.lo_x), tx1 = tile_x(p.hi_x), ty0 = tile_y(p.lo_y), ty1 = tile_y(p.hi_y);
                if ((tx1 - tx0 + 1) * (ty1 - ty0 + 1) > kBigTiles) {
                    p.big = true;
                    bigs[l]->push_back(i);
                    continue;
                }
                for (int ty = ty0; ty <= ty1; ++ty)
                    for (int tx = tx0; tx <= tx1; ++tx) ++first[std::size_t(ty) * nx + tx + 1];
            }
            for (std::size_t t = 1; t < first.size(); ++t) first[t] += first[t - 1];
            resize_kept(items, first.back());
            std::vector<std::uint32_t>& cursor = cursor_;
            assign_range_kept(cursor, first.begin(), first.end() - 1);
            for (std::uint32_t i = 0; i < lists[l]->size(); ++i) {
                const Projection& p = (*lists[l])[i];
                if (p.big) continue;
                for (int ty = tile_y(p.lo_y); ty <= tile_y(p.hi_y); ++ty)
                    for (int tx = tile_x(p.lo_x); tx <= tile_x(p.hi_x); ++tx) items[cursor[std::size_t(ty) * nx + tx]++] = i;
            }
        }

        // Small against small, in shared tiles; each pair once, in the tile holding the low
        // corner of the overlap of their bounding boxes.
        for (int ty = 0; ty < ny; ++ty) {
            for (int tx = 0; tx < nx; ++tx) {
                const std::size_t t = std::size_t(ty) * nx + tx;
                for (std::uint32_t bi = tile_first[0][t]; bi < tile_first[0][t + 1]; ++bi) {
                    const Projection& g = back[tile_items[0][bi]];
                    for (std::uint32_t fi = tile_first[1][t]; fi < tile_first[1][t + 1]; ++fi) {
                        const Projection& h = front[tile_items[1][fi]];
                        if (depth_rules_out(g, h)) break; // and every later h, farther ends first
                        if (g.cell == h.cell || !boxes_overlap(g, h)) continue;
                        if (tile_x(std::max(g.lo_x, h.lo_x)) != tx || tile_y(std::max(g.lo_y, h.lo_y)) != ty) continue;
                        test_pair(g, h);
                    }
                }
            }
        }
        // Big against everything opposite (big against big once: from the back side).
        for (std::uint32_t gi : big_back) {
            const Projection& g = back[gi];
            for (const Projection& h : front) {
                if (depth_rules_out(g, h)) break;
                if (g.cell != h.cell && boxes_overlap(g, h)) test_pair(g, h);
            }
        }
        for (std::uint32_t hi : big_front) {
            const Projection& h = front[hi];
            for (const Projection& g : back) {
                if (depth_rules_out(g, h)) break; // backs nearest first
                if (!g.big && g.cell != h.cell && boxes_overlap(g, h)) test_pair(g, h);
            }
        }
    }
    stats.exterior_pairs = tested;
    const std::size_t pair_bytes = pairs.capacity() * sizeof(pairs[0]);
    out.build(pairs);
    stats.exterior_edges = out.by_source.size();
    stats.seconds_keys += seconds_since(t0);
    stats.working_bytes += (front.capacity() + back.capacity()) * sizeof(Projection) + pair_bytes +
                           (tile_first[0].capacity() + tile_first[1].capacity() + tile_items[0].capacity() +
                            tile_items[1].capacity() + big_front.capacity() + big_back.capacity()) *
                               sizeof(std::uint32_t) +
                           out.memory_bytes();
}

} // namespace cellfx::fx::sort_detail
