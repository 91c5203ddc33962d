// Based on: Max, Williams & Silva 2000, §III (visibility sorting)
//
// `cellfx bench sort`: every visibility sort on ~1M tetrahedra — a tetrahedralised hex grid
// (convex), the same grid with jittered interior points (convex, far from Delaunay) and a
// tetrahedralised C-shaped annular sector (non-convex). Per method: set-up seconds, per-view
// milliseconds (best of --repeat for each view, the methods taking turns, median over the
// views) in wall and thread-CPU time, split into keys and ordering, cells/s per core (CPU
// time), the ratio to the centroid sort (std::sort of centroid depths: the floor), and bytes
// per tetrahedron for the mesh, the sort's per-mesh state, its per-view working memory and
// the output order. Each order is verified after timing: a permutation of the cells, and
// every shared face's two cells in the order its plane gives.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "harness/synthetic_meshes.hpp"
#include "mesh/tetrahedralize.hpp"
#include "fx/visibility_sort.hpp"
#include "options.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

// CPU seconds of the calling thread: on a shared machine, wall time also counts the moments
// other processes hold the core.
double thread_cpu_seconds() {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void shrink(fx::CellMesh& mesh) {
    mesh.points.shrink_to_fit();
    mesh.cell_types.shrink_to_fit();
    mesh.cell_offsets.shrink_to_fit();
    mesh.connectivity.shrink_to_fit();
    for (fx::ScalarField& f : mesh.scalars) f.values.shrink_to_fit();
}

struct BenchMesh {
    std::string name;
    fx::CellMesh mesh;
    bool convex;
};

// n³ hexahedra → 6n³ tetrahedra (the smallest-vertex rule cuts every cell of a regular grid
// into six), with a scalar field as a real mesh would carry.
BenchMesh grid_mesh(std::size_t target_cells, double jitter) {
    const std::uint32_t n = std::max<std::uint32_t>(1, std::uint32_t(std::lround(std::cbrt(target_cells / 6.0))));
    fx::CellMesh hexes;
    fx::append_curvilinear_block(hexes, "grid", {n + 1, n + 1, n + 1},
                                 [](double u, double v, double w) { return glm::dvec3(u, v, w); });
    if (jitter > 0.0) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> d(-jitter / n, jitter / n);
        for (glm::dvec3& p : hexes.points) {
            const bool boundary = p.x <= 0.0 || p.x >= 1.0 || p.y <= 0.0 || p.y >= 1.0 || p.z <= 0.0 || p.z >= 1.0;
            if (!boundary) p += glm::dvec3(d(rng), d(rng), d(rng));
        }
    }
    BenchMesh m{jitter > 0.0 ? "jittered grid" : "grid", fx::tetrahedralize(hexes), true};
    fx::set_scalar_field(m.mesh, "density", [](const glm::dvec3& p) { return p.x * p.y + p.z; });
    shrink(m.mesh);
    return m;
}

// A 300-degree annular sector (gap on +x), radii 1..2, height 0.6: non-convex.
BenchMesh c_mesh(std::size_t target_cells) {
    // around : radial : vertical = 8 : 2 : 1 cells.
    const std::uint32_t k = std::max<std::uint32_t>(1, std::uint32_t(std::lround(std::cbrt(target_cells / 6.0 / 16.0))));
    fx::CellMesh hexes;
    fx::append_curvilinear_block(hexes, "c", {8 * k + 1, 2 * k + 1, k + 1}, [](double u, double v, double w) {
        const double theta = glm::radians(30.0 + 300.0 * u);
        return glm::dvec3((1.0 + v) * std::cos(theta), (1.0 + v) * std::sin(theta), 0.6 * w);
    });
    BenchMesh m{"C-shape", fx::tetrahedralize(hexes), false};
    fx::set_scalar_field(m.mesh, "density", [](const glm::dvec3& p) { return p.z; });
    shrink(m.mesh);
    return m;
}

// Views: perspective from around and above the mesh, one from inside, one orthographic.
std::vector<fx::Camera> bench_views(const fx::CellMesh& mesh, int count) {
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const double radius = 0.5 * glm::length(b.size());
    std::vector<fx::Camera> views;
    for (int i = 0; i < count; ++i) {
        fx::Camera cam;
        const double a = 2.0 * 3.14159265358979 * (i + 0.3) / count;
        const double elevation = 0.9 * std::sin(1.7 * i + 0.4);
        cam.target = b.center();
        cam.eye = b.center() + 2.5 * radius * glm::dvec3(std::cos(a) * std::cos(elevation),
                                                         std::sin(a) * std::cos(elevation), std::sin(elevation));
        cam.up = {0.0, 0.0, 1.0};
        cam.near_distance = 1e-3 * radius;
        if (i == count - 2) cam.eye = b.center() + 0.1 * b.size(); // inside (or in the C's hole)
        if (i == count - 1) cam.ortho_height = 2.2 * radius;
        views.push_back(cam);
    }
    return views;
}

// Shared faces whose two cells are in the wrong order for their plane (eye strictly off it).
std::size_t shared_face_errors(const fx::CellMesh& mesh, const fx::FaceTopology& topo, const fx::Camera& cam,
                               const std::vector<std::uint32_t>& order) {
    std::vector<std::uint32_t> position(order.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) position[order[i]] = i;
    std::size_t errors = 0;
    for (std::uint32_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* cv = mesh.cell_vertices(c);
        const glm::dvec3 centre = 0.25 * (mesh.points[cv[0]] + mesh.points[cv[1]] + mesh.points[cv[2]] + mesh.points[cv[3]]);
        for (std::uint32_t s = topo.first_face[c]; s < topo.first_face[c + 1]; ++s) {
            if (topo.neighbour[s] == fx::FaceTopology::kBoundary) continue;
            const std::uint32_t nc = topo.slot_cell[topo.neighbour[s]];
            if (nc < c) continue;
            const fx::CellFace& face = fx::cell_faces(mesh.cell_types[c])[s - topo.first_face[c]];
            const glm::dvec3 a = mesh.points[cv[face.v[0]]];
            glm::dvec3 n = glm::cross(mesh.points[cv[face.v[1]]] - a, mesh.points[cv[face.v[2]]] - a);
            if (glm::dot(n, centre - a) > 0.0) n = -n;
            const double side = cam.orthographic() ? -glm::dot(n, cam.forward()) : glm::dot(n, cam.eye - a);
            if (std::abs(side) <= 1e-12 * glm::dot(n, n)) continue;
            // Eye outside c: the neighbour is nearer and must come later.
            if ((side > 0.0) != (position[c] < position[nc])) ++errors;
        }
    }
    return errors;
}

bool is_permutation(const std::vector<std::uint32_t>& order, std::size_t cells) {
    if (order.size() != cells) return false;
    std::vector<char> seen(cells, 0);
    for (std::uint32_t c : order) {
        if (c >= cells || seen[c]) return false;
        seen[c] = 1;
    }
    return true;
}

} // namespace

int bench_sort(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {});
    require_known(parsed, {"cells", "views", "repeat", "mesh"});
    if (!parsed.positional.empty()) throw fx::Error("bench sort: unexpected argument '" + parsed.positional[0] + "'");
    const int cells = int_option(parsed, "bench sort", "cells", 1000000);
    const int view_count = int_option(parsed, "bench sort", "views", 8);
    const int repeat = int_option(parsed, "bench sort", "repeat", 5);
    const std::string which = parsed.get("mesh", "all");
    if (which != "all" && which != "grid" && which != "jittered" && which != "c-shape")
        throw fx::Error("bench sort: --mesh must be all, grid, jittered or c-shape (got '" + which + "')");

    std::printf("visibility sorts, one thread; per view: best of %d, median over %d views\n", repeat, view_count);
    bool all_verified = true;
    for (const std::string& kind : {std::string("grid"), std::string("jittered"), std::string("c-shape")}) {
        if (which != "all" && which != kind) continue;
        const BenchMesh bm = kind == "grid" ? grid_mesh(cells, 0.0) : kind == "jittered" ? grid_mesh(cells, 0.25) : c_mesh(cells);
        const fx::CellMesh& mesh = bm.mesh;
        const double n = static_cast<double>(mesh.cell_count());
        const std::vector<fx::Camera> views = bench_views(mesh, view_count);
        const fx::FaceTopology topo = fx::build_face_topology(mesh);
        std::printf("\n%s: %zu tetrahedra, %zu points, %zu boundary faces, %s; mesh %.1f bytes/tet\n", bm.name.c_str(),
                    mesh.cell_count(), mesh.point_count(), topo.boundary_faces.size(), bm.convex ? "convex" : "non-convex",
                    mesh.memory_bytes() / n);
        std::printf("  %-9s %8s %8s %7s %7s %7s %9s %8s  %25s %7s %7s %11s\n", "method", "set-up s", "wall ms", "cpu ms",
                    "keys ms", "order ms", "Mcells/s", "vs floor", "bytes/tet: state+view+out", "total", "cycles",
                    "face errors");
        // Per view: wall and thread-CPU milliseconds (keys and order: wall); Mcells/s per core
        // and the ratio to the centroid floor from CPU time. Cycles and face errors: summed
        // over the views.
        // All sorters side by side; per view the methods take turns, so that the machine's
        // slow moments fall on all of them alike.
        std::vector<fx::VisibilitySort> sorters;
        for (fx::SortMethod method : fx::all_sort_methods()) sorters.emplace_back(mesh, method);
        struct Result {
            std::vector<double> view_ms, cpu_ms, keys_ms, order_ms;
            std::size_t cycles = 0, working = 0, face_errors = 0, exterior_edges = 0, exterior_pairs = 0,
                        exterior_faces = 0;
            bool verified = true;
        };
        std::vector<Result> results(sorters.size());
        std::vector<std::uint32_t> order;
        for (const fx::Camera& cam : views) {
            std::vector<fx::SortStats> best(sorters.size());
            std::vector<double> best_cpu(sorters.size(), 1e300);
            for (fx::SortStats& b : best) b.seconds = 1e300;
            for (int r = 0; r < repeat; ++r) {
                for (std::size_t m = 0; m < sorters.size(); ++m) {
                    fx::SortStats stats;
                    const double c0 = thread_cpu_seconds();
                    sorters[m].sort(cam, order, &stats);
                    best_cpu[m] = std::min(best_cpu[m], thread_cpu_seconds() - c0);
                    if (stats.seconds < best[m].seconds) best[m] = stats;
                    // Verify after timing (on the last repeat).
                    if (r + 1 == repeat) {
                        results[m].verified = results[m].verified && is_permutation(order, mesh.cell_count());
                        results[m].face_errors += shared_face_errors(mesh, topo, cam, order);
                    }
                }
            }
            for (std::size_t m = 0; m < sorters.size(); ++m) {
                Result& res = results[m];
                const fx::SortStats& b = best[m];
                res.view_ms.push_back(1e3 * b.seconds);
                res.cpu_ms.push_back(1e3 * best_cpu[m]);
                res.keys_ms.push_back(1e3 * b.seconds_keys);
                res.order_ms.push_back(1e3 * b.seconds_order);
                res.cycles += b.cycles;
                res.exterior_edges += b.exterior_edges;
                res.exterior_pairs += b.exterior_pairs;
                res.exterior_faces += b.exterior_faces;
                res.working = std::max(res.working, b.working_bytes);
            }
        }
        const double floor_cpu_ms = median(results[0].cpu_ms); // centroid: all_sort_methods() starts with it
        for (std::size_t m = 0; m < sorters.size(); ++m) {
            const fx::SortMethod method = sorters[m].method();
            const Result& res = results[m];
            const double cpu = median(res.cpu_ms);
            const double state = sorters[m].memory_bytes() / n, view = res.working / n, out = sizeof(std::uint32_t);
            std::printf("  %-9s %8.2f %8.1f %7.1f %7.1f %7.1f %9.1f %7.2fx  %9.1f + %5.1f + %3.0f %7.1f %7zu %11zu%s\n",
                        fx::sort_method_name(method), sorters[m].setup_seconds(), median(res.view_ms), cpu,
                        median(res.keys_ms), median(res.order_ms), n / cpu * 1e-3, cpu / floor_cpu_ms, state, view, out,
                        mesh.memory_bytes() / n + state + view + out, res.cycles, res.face_errors,
                        res.verified ? "" : "  NOT A PERMUTATION");
            if (method == fx::SortMethod::Xmpvo)
                std::printf("  %-9s per view: %zu boundary triangles projected, %zu pairs intersected, %zu exterior edges\n",
                            "", res.exterior_faces / views.size(), res.exterior_pairs / views.size(),
                            res.exterior_edges / views.size());
            // Exact methods must respect every shared face unless a cycle forced a cell out.
            const bool graph_method = method == fx::SortMethod::Mpvo || method == fx::SortMethod::Xmpvo;
            if (!res.verified || (graph_method && res.cycles == 0 && res.face_errors != 0)) all_verified = false;
        }
    }
    std::printf("\n%s\n", all_verified ? "verified: every order is a permutation; mpvo/xmpvo orders respect every shared face"
                                        : "VERIFICATION FAILED");
    return all_verified ? 0 : 1;
}

} // namespace cellfx_cli
