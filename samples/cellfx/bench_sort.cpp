// Based on: Max, Williams & Silva 2000, §III (visibility sorting)
//
// `cellfx bench sort`: every visibility sort on ~1M tetrahedra — a tetrahedralised hex grid
// (convex), the same grid with jittered interior points (convex, far from Delaunay) and a
// tetrahedralised C-shaped annular sector (non-convex). Per method: set-up seconds, per-view
// milliseconds (best of --repeat for each view, median over the views) split into keys and
// ordering, cells/s on one core, the ratio to the centroid sort (std::sort of centroid
// depths: the floor), and bytes per tetrahedron for the mesh, the sort's per-mesh state, its
// per-view working memory and the output order. Each order is verified after timing: a
// permutation of the cells, and every shared face's two cells in the order its plane gives.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "commands.hpp"
#include "fx/error.hpp"
#include "fx/face_topology.hpp"
#include "fx/synthetic_meshes.hpp"
#include "fx/tetrahedralize.hpp"
#include "fx/visibility_sort.hpp"
#include "options.hpp"

namespace cellfx_cli {
namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
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
    const int cells = parse_int(parsed.get("cells", "1000000"), "--cells");
    const int view_count = parse_int(parsed.get("views", "8"), "--views");
    const int repeat = parse_int(parsed.get("repeat", "3"), "--repeat");
    const std::string which = parsed.get("mesh", "all");
    if (cells < 6) throw fx::Error("bench sort: --cells must be at least 6");
    if (view_count < 2) throw fx::Error("bench sort: --views must be at least 2");
    if (repeat < 1) throw fx::Error("bench sort: --repeat must be at least 1");
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
        std::printf("  %-9s %8s %9s %8s %8s %9s %8s  %25s %7s %7s %11s\n", "method", "set-up s", "view ms", "keys ms",
                    "order ms", "Mcells/s", "vs floor", "bytes/tet: state+view+out", "total", "cycles", "face errors");
        // cycles and face errors: summed over the views.
        double floor_ms = 0.0;
        for (fx::SortMethod method : fx::all_sort_methods()) {
            const fx::VisibilitySort sorter(mesh, method);
            std::vector<double> view_ms, keys_ms, order_ms;
            std::size_t cycles = 0, working = 0, face_errors = 0, exterior_edges = 0, exterior_pairs = 0;
            std::size_t exterior_faces = 0;
            bool verified = true;
            std::vector<std::uint32_t> order;
            for (const fx::Camera& cam : views) {
                double best = 1e300;
                fx::SortStats best_stats;
                for (int r = 0; r < repeat; ++r) {
                    fx::SortStats stats;
                    sorter.sort(cam, order, &stats);
                    if (stats.seconds < best) best = stats.seconds, best_stats = stats;
                }
                view_ms.push_back(1e3 * best);
                keys_ms.push_back(1e3 * best_stats.seconds_keys);
                order_ms.push_back(1e3 * best_stats.seconds_order);
                cycles += best_stats.cycles;
                exterior_edges += best_stats.exterior_edges;
                exterior_pairs += best_stats.exterior_pairs;
                exterior_faces += best_stats.exterior_faces;
                working = std::max(working, best_stats.working_bytes);
                // Verify after timing.
                verified = verified && is_permutation(order, mesh.cell_count());
                face_errors += shared_face_errors(mesh, topo, cam, order);
            }
            const double ms = median(view_ms);
            if (method == fx::SortMethod::Centroid) floor_ms = ms;
            const double state = sorter.memory_bytes() / n, view = working / n, out = sizeof(std::uint32_t);
            std::printf("  %-9s %8.2f %9.1f %8.1f %8.1f %9.1f %7.2fx  %9.1f + %5.1f + %3.0f %7.1f %7zu %11zu%s\n",
                        fx::sort_method_name(method), sorter.setup_seconds(), ms, median(keys_ms), median(order_ms),
                        n / ms * 1e-3, ms / floor_ms, state, view, out, mesh.memory_bytes() / n + state + view + out,
                        cycles, face_errors, verified ? "" : "  NOT A PERMUTATION");
            if (method == fx::SortMethod::Xmpvo)
                std::printf("  %-9s per view: %zu boundary triangles projected, %zu pairs intersected, %zu exterior edges\n",
                            "", exterior_faces / views.size(), exterior_pairs / views.size(), exterior_edges / views.size());
            // Exact methods must respect every shared face unless a cycle forced a cell out.
            const bool graph_method = method == fx::SortMethod::Mpvo || method == fx::SortMethod::Xmpvo;
            if (!verified || (graph_method && cycles == 0 && face_errors != 0)) all_verified = false;
        }
    }
    std::printf("\n%s\n", all_verified ? "verified: every order is a permutation; mpvo/xmpvo orders respect every shared face"
                                        : "VERIFICATION FAILED");
    return all_verified ? 0 : 1;
}

} // namespace cellfx_cli
