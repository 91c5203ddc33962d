// Helpers for the visibility-sort tests: an order oracle that follows viewing rays through
// the cells, a small Delaunay tetrahedraliser with an independent empty-sphere check, a
// convexity witness count, and non-convex test meshes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_validation.hpp"
#include "harness/synthetic_meshes.hpp"
#include "mesh/tetrahedralize.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace sort_test {

inline glm::dvec3 cell_centroid(const fx::CellMesh& mesh, std::size_t c) {
    const int n = fx::cell_vertex_count(mesh.cell_types[c]);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) sum += mesh.points[mesh.cell_vertices(c)[i]];
    return sum / double(n);
}

// True when `order` holds every cell index exactly once.
inline bool is_permutation_of_cells(const std::vector<std::uint32_t>& order, std::size_t cells) {
    if (order.size() != cells) return false;
    std::vector<char> seen(cells, 0);
    for (std::uint32_t c : order) {
        if (c >= cells || seen[c]) return false;
        seen[c] = 1;
    }
    return true;
}

// ---------------------------------------------------------------------------------------
// Order oracle: rays through the image, each intersected with every cell it may meet
// (Cyrus–Beck against the cell's face planes, double precision). Along each ray the cells
// are taken nearest first; a cell drawn after (later in back_to_front than) a cell it lies
// behind is a violation. Only what is in front of the near plane counts, as in the render
// paths. Faces must be planar (tetrahedra, boxes, planar hexahedra).

struct RayOrderCheck {
    std::size_t rays = 0;          // rays cast
    std::size_t rays_crossing = 0; // rays meeting at least two cells
    std::size_t bad_rays = 0;      // rays with at least one violation
    std::size_t pairs = 0;         // consecutive cell pairs along the rays
    std::size_t bad_pairs = 0;     // ... in the wrong order
    RayOrderCheck& operator+=(const RayOrderCheck& o) {
        rays += o.rays, rays_crossing += o.rays_crossing, bad_rays += o.bad_rays;
        pairs += o.pairs, bad_pairs += o.bad_pairs;
        return *this;
    }
    double bad_pair_fraction() const { return pairs ? double(bad_pairs) / double(pairs) : 0.0; }
    double bad_ray_fraction() const { return rays_crossing ? double(bad_rays) / double(rays_crossing) : 0.0; }
};

// Outward face planes (n, d) with n·x + d > 0 outside, per cell: first[c] .. first[c + 1].
struct CellPlanes {
    std::vector<glm::dvec4> planes;
    std::vector<std::uint32_t> first{0};
};

inline CellPlanes cell_planes(const fx::CellMesh& mesh) {
    CellPlanes cp;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const glm::dvec3 centre = cell_centroid(mesh, c);
        const fx::CellFace* faces = fx::cell_faces(mesh.cell_types[c]);
        for (int f = 0; f < fx::cell_face_count(mesh.cell_types[c]); ++f) {
            const glm::dvec3 a = mesh.points[mesh.cell_vertices(c)[faces[f].v[0]]];
            const glm::dvec3 b = mesh.points[mesh.cell_vertices(c)[faces[f].v[1]]];
            const glm::dvec3 d = mesh.points[mesh.cell_vertices(c)[faces[f].v[2]]];
            glm::dvec3 n = glm::normalize(glm::cross(b - a, d - a));
            if (glm::dot(n, centre - a) > 0.0) n = -n;
            cp.planes.emplace_back(n, -glm::dot(n, a));
        }
        cp.first.push_back(static_cast<std::uint32_t>(cp.planes.size()));
    }
    return cp;
}

inline RayOrderCheck check_order_along_rays(const fx::CellMesh& mesh, const CellPlanes& cp, const fx::Camera& cam,
                                            const std::vector<std::uint32_t>& back_to_front, int width, int height,
                                            std::uint32_t seed) {
    const std::size_t n = mesh.cell_count();
    std::vector<std::uint32_t> position(n);
    for (std::uint32_t i = 0; i < back_to_front.size(); ++i) position[back_to_front[i]] = i;

    // Bin cells by the pixels their projected vertices span; cells reaching the near plane
    // go to every pixel.
    const glm::dvec3 f = cam.forward();
    const glm::dvec3 r = glm::normalize(glm::cross(f, cam.up));
    const glm::dvec3 u = glm::cross(r, f);
    const double aspect = double(width) / height;
    const double half_h = cam.orthographic() ? 0.5 * cam.ortho_height : std::tan(0.5 * glm::radians(cam.fov_y_degrees));
    std::vector<std::vector<std::uint32_t>> bins(std::size_t(width) * height);
    std::vector<std::uint32_t> everywhere;
    for (std::uint32_t c = 0; c < n; ++c) {
        double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300;
        bool near_cell = false;
        for (int i = 0; i < fx::cell_vertex_count(mesh.cell_types[c]); ++i) {
            const glm::dvec3 d = mesh.points[mesh.cell_vertices(c)[i]] - cam.eye;
            const double depth = glm::dot(d, f);
            if (!cam.orthographic() && depth < 0.5 * cam.near_distance) near_cell = true;
            const double s = cam.orthographic() ? 1.0 : 1.0 / depth;
            const double px = (glm::dot(d, r) * s / (half_h * aspect) + 1.0) * 0.5 * width;
            const double py = (glm::dot(d, u) * s / half_h + 1.0) * 0.5 * height;
            lo_x = std::min(lo_x, px), hi_x = std::max(hi_x, px), lo_y = std::min(lo_y, py), hi_y = std::max(hi_y, py);
        }
        if (near_cell) {
            everywhere.push_back(c);
            continue;
        }
        const int x0 = std::max(0, int(std::floor(lo_x))), x1 = std::min(width - 1, int(std::floor(hi_x)));
        const int y0 = std::max(0, int(std::floor(lo_y))), y1 = std::min(height - 1, int(std::floor(hi_y)));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) bins[std::size_t(y) * width + x].push_back(c);
    }

    const fx::Bounds bounds = fx::mesh_bounds(mesh);
    const double min_length = 1e-9 * glm::length(bounds.size());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(0.02, 0.98);
    RayOrderCheck check;
    struct Hit {
        double t0, t1;
        std::uint32_t cell;
    };
    std::vector<Hit> hits;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const fx::Ray ray = cam.pixel_ray(x + jitter(rng), y + jitter(rng), width, height);
            const double t_near = cam.orthographic() ? cam.near_distance
                                                     : cam.near_distance / glm::dot(ray.direction, f);
            hits.clear();
            auto intersect = [&](std::uint32_t c) {
                double t0 = t_near, t1 = 1e300;
                for (std::uint32_t p = cp.first[c]; p < cp.first[c + 1] && t0 < t1; ++p) {
                    const glm::dvec3 nrm(cp.planes[p]);
                    const double dist = glm::dot(nrm, ray.origin) + cp.planes[p].w; // > 0 outside
                    const double denom = glm::dot(nrm, ray.direction);
                    if (denom == 0.0) {
                        if (dist > 0.0) t1 = -1e300;
                        continue;
                    }
                    const double t = -dist / denom;
                    if (denom > 0.0) t1 = std::min(t1, t); else t0 = std::max(t0, t);
                }
                if (t1 - t0 > min_length) hits.push_back({t0, t1, c});
            };
            for (std::uint32_t c : bins[std::size_t(y) * width + x]) intersect(c);
            for (std::uint32_t c : everywhere) intersect(c);
            ++check.rays;
            if (hits.size() < 2) continue;
            ++check.rays_crossing;
            std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t0 + a.t1 < b.t0 + b.t1; });
            bool bad = false;
            for (std::size_t i = 1; i < hits.size(); ++i) {
                ++check.pairs;
                // hits[i - 1] is nearer: it must be drawn later.
                if (position[hits[i - 1].cell] < position[hits[i].cell]) {
                    ++check.bad_pairs;
                    bad = true;
                }
            }
            if (bad) ++check.bad_rays;
        }
    }
    return check;
}

// Random views of a mesh: perspective from outside, perspective from inside its bounding box,
// and orthographic, in turn.
inline std::vector<fx::Camera> random_views(const fx::CellMesh& mesh, int count, std::uint32_t seed) {
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const double radius = 0.5 * glm::length(b.size());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), zero_one(0.0, 1.0);
    auto direction = [&] {
        for (;;) {
            const glm::dvec3 d(unit(rng), unit(rng), unit(rng));
            const double l = glm::length(d);
            if (l > 0.1 && l <= 1.0) return d / l;
        }
    };
    std::vector<fx::Camera> views;
    for (int i = 0; i < count; ++i) {
        fx::Camera cam;
        cam.near_distance = 1e-3 * radius;
        cam.far_distance = 100.0 * radius;
        cam.up = direction();
        const int kind = i % 3;
        if (kind == 1) { // inside the bounding box, looking anywhere
            cam.eye = b.lo + b.size() * glm::dvec3(0.1 + 0.8 * zero_one(rng), 0.1 + 0.8 * zero_one(rng),
                                                   0.1 + 0.8 * zero_one(rng));
            cam.target = cam.eye + direction();
            cam.fov_y_degrees = 90.0;
        } else {
            cam.eye = b.center() + direction() * radius * (1.3 + 2.0 * zero_one(rng));
            cam.target = b.center() + direction() * radius * 0.2 * zero_one(rng);
            cam.fov_y_degrees = 2.0 * glm::degrees(std::asin(std::min(1.0, radius / glm::length(cam.eye - b.center()))));
            if (kind == 2) cam.ortho_height = 2.2 * radius;
        }
        if (glm::length(glm::cross(cam.target - cam.eye, cam.up)) < 1e-3) cam.up = glm::dvec3(cam.up.y, cam.up.z, cam.up.x);
        views.push_back(cam);
    }
    return views;
}

// ---------------------------------------------------------------------------------------
// Convexity: boundary faces whose plane has mesh vertices in front of it by more than 1e-6 of
// the mesh's diagonal (files store float coordinates: coplanar hull faces of tetraMesh.vtk
// are off by 5e-7). Zero for a mesh with a convex boundary.
inline std::size_t boundary_witness_faces(const fx::CellMesh& mesh) {
    const fx::FaceTopology topo = fx::build_face_topology(mesh);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const double tol = 1e-6 * glm::length(b.size());
    std::vector<char> used(mesh.point_count(), 0);
    for (std::uint32_t v : mesh.connectivity) used[v] = 1;
    std::size_t witnesses = 0;
    for (std::uint32_t slot : topo.boundary_faces) {
        const std::uint32_t c = topo.slot_cell[slot];
        std::uint32_t tris[2][3];
        const int nt = fx::triangulate_face(fx::cell_faces(mesh.cell_types[c])[slot - topo.first_face[c]],
                                            mesh.cell_vertices(c), tris);
        bool witness = false;
        for (int t = 0; t < nt && !witness; ++t) {
            const glm::dvec3 a = mesh.points[tris[t][0]];
            glm::dvec3 nrm = glm::cross(mesh.points[tris[t][1]] - a, mesh.points[tris[t][2]] - a);
            if (glm::dot(nrm, cell_centroid(mesh, c) - a) > 0.0) nrm = -nrm;
            nrm = glm::normalize(nrm);
            for (std::size_t p = 0; p < mesh.point_count() && !witness; ++p)
                witness = used[p] && glm::dot(nrm, mesh.points[p] - a) > tol;
        }
        if (witness) ++witnesses;
    }
    return witnesses;
}

// ---------------------------------------------------------------------------------------
// Delaunay tetrahedralisation by Bowyer–Watson (brute-force cavity search: test sizes only),
// inside a huge enclosing tetrahedron whose cells are dropped at the end. What remains is a
// subset of a Delaunay tetrahedralisation, which is all the power sort's exactness needs; it
// is the convex hull's Delaunay tetrahedralisation unless hull cells went with the enclosure
// (check with boundary_witness_faces). Use delaunay_violations() to confirm the result.
inline fx::CellMesh delaunay_mesh(const std::vector<glm::dvec3>& points) {
    struct Tet {
        std::array<std::uint32_t, 4> v;
        glm::dvec3 centre;
        double r2;
    };
    std::vector<glm::dvec3> p = points;
    glm::dvec3 lo = p[0], hi = p[0];
    for (const glm::dvec3& q : p) lo = glm::min(lo, q), hi = glm::max(hi, q);
    const glm::dvec3 c = 0.5 * (lo + hi);
    const double k = 1e4 * glm::length(hi - lo);
    const std::uint32_t s0 = static_cast<std::uint32_t>(p.size());
    p.push_back(c + k * glm::dvec3(1, 1, 1));
    p.push_back(c + k * glm::dvec3(1, -1, -1));
    p.push_back(c + k * glm::dvec3(-1, 1, -1));
    p.push_back(c + k * glm::dvec3(-1, -1, 1));
    auto make = [&](std::array<std::uint32_t, 4> v) {
        const glm::dvec3 a = p[v[0]];
        glm::dvec3 e1 = p[v[1]] - a, e2 = p[v[2]] - a, e3 = p[v[3]] - a;
        double det = glm::dot(e1, glm::cross(e2, e3));
        if (det < 0.0) std::swap(v[1], v[2]), std::swap(e1, e2), det = -det;
        const glm::dvec3 num = glm::dot(e1, e1) * glm::cross(e2, e3) + glm::dot(e2, e2) * glm::cross(e3, e1) +
                               glm::dot(e3, e3) * glm::cross(e1, e2);
        const glm::dvec3 off = num / (2.0 * det);
        return Tet{v, a + off, glm::dot(off, off)};
    };
    std::vector<Tet> tets{make({s0, s0 + 1, s0 + 2, s0 + 3})};
    for (std::uint32_t i = 0; i < s0; ++i) {
        std::map<std::array<std::uint32_t, 3>, int> faces;
        std::vector<Tet> kept;
        for (const Tet& t : tets) {
            const glm::dvec3 d = p[i] - t.centre;
            if (glm::dot(d, d) < t.r2) {
                static const int fv[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
                for (const auto& f : fv) {
                    std::array<std::uint32_t, 3> key{t.v[f[0]], t.v[f[1]], t.v[f[2]]};
                    std::sort(key.begin(), key.end());
                    ++faces[key];
                }
            } else {
                kept.push_back(t);
            }
        }
        for (const auto& [key, count] : faces) {
            if (count == 1) kept.push_back(make({key[0], key[1], key[2], i}));
        }
        tets = std::move(kept);
    }
    fx::CellMesh mesh;
    mesh.points = points;
    mesh.begin_block("delaunay");
    for (const Tet& t : tets) {
        if (t.v[0] >= s0 || t.v[1] >= s0 || t.v[2] >= s0 || t.v[3] >= s0) continue;
        mesh.add_cell(fx::CellType::Tetra, t.v.data());
    }
    fx::orient_cells(mesh);
    return mesh;
}

// Tetrahedra whose circumsphere holds another mesh point strictly inside (relative tolerance
// 1e-9 of the radius): zero for a Delaunay tetrahedralisation. Brute force.
inline std::size_t delaunay_violations(const fx::CellMesh& mesh) {
    std::size_t bad = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* v = mesh.cell_vertices(c);
        const glm::dvec3 a = mesh.points[v[0]];
        const glm::dvec3 e1 = mesh.points[v[1]] - a, e2 = mesh.points[v[2]] - a, e3 = mesh.points[v[3]] - a;
        const glm::dvec3 num = glm::dot(e1, e1) * glm::cross(e2, e3) + glm::dot(e2, e2) * glm::cross(e3, e1) +
                               glm::dot(e3, e3) * glm::cross(e1, e2);
        const glm::dvec3 centre = a + num / (2.0 * glm::dot(e1, glm::cross(e2, e3)));
        const double r = glm::length(a - centre);
        for (std::uint32_t q = 0; q < mesh.point_count(); ++q) {
            if (q == v[0] || q == v[1] || q == v[2] || q == v[3]) continue;
            if (glm::length(mesh.points[q] - centre) < r * (1.0 - 1e-9)) {
                ++bad;
                break;
            }
        }
    }
    return bad;
}

// ---------------------------------------------------------------------------------------
// Test meshes.

// A C: an annular sector of 300 degrees (gap centred on +x), inner radius 1, outer 2,
// height 0.6, as one curvilinear block, optionally cut into consistent tetrahedra.
inline fx::CellMesh c_shape(int around, int radial, int vertical, bool tetrahedra) {
    fx::CellMesh hexes;
    fx::append_curvilinear_block(hexes, "c", {std::uint32_t(around + 1), std::uint32_t(radial + 1), std::uint32_t(vertical + 1)},
                                 [](double u, double v, double w) {
                                     const double theta = glm::radians(30.0 + 300.0 * u);
                                     const double r = 1.0 + v;
                                     return glm::dvec3(r * std::cos(theta), r * std::sin(theta), 0.6 * w);
                                 });
    fx::orient_cells(hexes);
    return tetrahedra ? fx::tetrahedralize(hexes) : hexes;
}

// An n³ box of hexahedra with the central m³ cells removed: a closed cavity.
inline fx::CellMesh hollow_box(int n, int m) {
    const fx::CellMesh full = fx_test::hex_box(n, n, n);
    fx::CellMesh mesh;
    mesh.points = full.points;
    mesh.begin_block("hollow");
    const int lo = (n - m) / 2, hi = lo + m;
    for (std::size_t c = 0; c < full.cell_count(); ++c) {
        const int i = int(c) % n, j = (int(c) / n) % n, k = int(c) / (n * n);
        if (i >= lo && i < hi && j >= lo && j < hi && k >= lo && k < hi) continue;
        mesh.add_cell(fx::CellType::Hexahedron, full.cell_vertices(c));
    }
    return mesh;
}

// Two separate boxes of hexahedra side by side along x, with a gap between them.
inline fx::CellMesh two_boxes() {
    fx::CellMesh mesh = fx_test::hex_box(3, 3, 3);
    const fx::CellMesh second = fx_test::hex_box(2, 3, 4, {1.4, 0.2, -0.3}, {2.2, 0.9, 1.2});
    const std::uint32_t base = static_cast<std::uint32_t>(mesh.point_count());
    mesh.points.insert(mesh.points.end(), second.points.begin(), second.points.end());
    mesh.begin_block("second");
    for (std::size_t c = 0; c < second.cell_count(); ++c) {
        std::uint32_t v[8];
        for (int i = 0; i < 8; ++i) v[i] = second.cell_vertices(c)[i] + base;
        mesh.add_cell(fx::CellType::Hexahedron, v);
    }
    return mesh;
}

// Three sticks, each lying on the next around a triangle: seen from above (+z) every stick
// hides part of the next, a visibility cycle no order can satisfy. One planar hexahedron each.
inline fx::CellMesh three_sticks() {
    fx::CellMesh mesh;
    mesh.begin_block("sticks");
    const glm::dvec3 corner[3] = {{0, 1, 0}, {-0.866, -0.5, 0}, {0.866, -0.5, 0}};
    for (int s = 0; s < 3; ++s) {
        const glm::dvec3 a = corner[s], b = corner[(s + 1) % 3];
        const glm::dvec3 along = glm::normalize(b - a);
        const glm::dvec3 side = glm::dvec3(-along.y, along.x, 0.0) * 0.12;
        const double len = glm::length(b - a);
        // From 0.4 before a to 0.4 past b; height rises from 0 at a to 1 at b.
        auto at = [&](double t, double across, double up) {
            const glm::dvec3 p = a + along * t + side * across;
            return glm::dvec3(p.x, p.y, t / len + 0.1 * up);
        };
        const double t0 = -0.4, t1 = len + 0.4;
        const std::uint32_t base = static_cast<std::uint32_t>(mesh.point_count());
        const glm::dvec3 corners[8] = {at(t0, -1, 0), at(t1, -1, 0), at(t1, 1, 0), at(t0, 1, 0),
                                       at(t0, -1, 1), at(t1, -1, 1), at(t1, 1, 1), at(t0, 1, 1)};
        for (const glm::dvec3& q : corners) mesh.points.push_back(q);
        std::uint32_t v[8];
        for (int i = 0; i < 8; ++i) v[i] = base + i;
        mesh.add_cell(fx::CellType::Hexahedron, v);
    }
    fx::orient_cells(mesh);
    return mesh;
}

// Tetrahedralised n³ grid of the unit cube with interior points moved at random by up to
// `jitter` cell widths: convex, not Delaunay.
inline fx::CellMesh jittered_tets(int n, double jitter, std::uint32_t seed) {
    fx::CellMesh mesh = fx::tetrahedralize(fx_test::hex_box(n, n, n));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-jitter / n, jitter / n);
    for (glm::dvec3& p : mesh.points) {
        bool boundary = false;
        for (int a = 0; a < 3; ++a) boundary = boundary || p[a] <= 0.0 || p[a] >= 1.0;
        if (!boundary) p += glm::dvec3(d(rng), d(rng), d(rng));
    }
    return mesh;
}

} // namespace sort_test
