// Visibility sorts: every cell once, farthest first; exactness checked by following viewing
// rays through the cells (sort_test_support.hpp) on convex, non-convex and Delaunay meshes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <thread>

#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/visibility_sort.hpp"
#include "mesh_builders.hpp"
#include "sort_test_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

using fx::SortMethod;

// Rays per view: 40 × 40 over the image, jittered inside each pixel.
constexpr int kRays = 40;

struct MethodResult {
    sort_test::RayOrderCheck rays;
    std::size_t cycles = 0;
};

// Sorts `mesh` with `method` for every view, checks that each order is a permutation, and
// follows rays through the cells.
MethodResult run_views(const fx::CellMesh& mesh, SortMethod method, const std::vector<fx::Camera>& views) {
    const fx::VisibilitySort sorter(mesh, method);
    const sort_test::CellPlanes planes = sort_test::cell_planes(mesh);
    MethodResult result;
    std::vector<std::uint32_t> order;
    for (std::size_t v = 0; v < views.size(); ++v) {
        fx::SortStats stats;
        sorter.sort(views[v], order, &stats);
        REQUIRE(sort_test::is_permutation_of_cells(order, mesh.cell_count()));
        REQUIRE(stats.cells == mesh.cell_count());
        result.cycles += stats.cycles;
        result.rays += sort_test::check_order_along_rays(mesh, planes, views[v], order, kRays, kRays,
                                                          static_cast<std::uint32_t>(v + 1));
    }
    return result;
}

std::string describe(const char* mesh, SortMethod method, const MethodResult& r) {
    return std::string(mesh) + " " + fx::sort_method_name(method) + ": " + std::to_string(r.rays.bad_pairs) + " of " +
           std::to_string(r.rays.pairs) + " cell pairs along " + std::to_string(r.rays.rays_crossing) +
           " rays out of order (" + std::to_string(100.0 * r.rays.bad_ray_fraction()) + "% of rays), cycles " +
           std::to_string(r.cycles);
}

// An exact method: no pair out of order along any ray, and enough rays crossed cells for
// that to mean something.
void require_exact(const char* name, const fx::CellMesh& mesh, SortMethod method, const std::vector<fx::Camera>& views) {
    const MethodResult r = run_views(mesh, method, views);
    INFO(describe(name, method, r));
    CHECK(r.cycles == 0);
    CHECK(r.rays.pairs > 20 * views.size());
    CHECK(r.rays.bad_pairs == 0);
}

// An approximate method: its error rate is reported, not required.
MethodResult report(const char* name, const fx::CellMesh& mesh, SortMethod method, const std::vector<fx::Camera>& views) {
    const MethodResult r = run_views(mesh, method, views);
    WARN(describe(name, method, r));
    return r;
}

// Reads a mesh from content/ as it is: inverted cells are allowed (the sorts orient planes
// from each cell's own centroid), any other problem is not. Returns the inverted count.
fx::CellMesh read_content_mesh(const std::string& relative, std::size_t* inverted = nullptr) {
    fx::CellMesh mesh = fx::read_mesh(fx_test::source_path(relative));
    std::size_t count = 0;
    for (const fx::MeshProblem& p : fx::validate_mesh(mesh)) {
        INFO(p.message);
        REQUIRE(p.kind == fx::MeshProblemKind::Inverted);
        ++count;
    }
    if (inverted) *inverted = count;
    return mesh;
}

} // namespace

TEST_CASE("sort methods have names that parse back", "[sort]") {
    for (SortMethod m : fx::all_sort_methods()) {
        SortMethod parsed = SortMethod::Centroid;
        REQUIRE(fx::parse_sort_method(fx::sort_method_name(m), parsed));
        CHECK(parsed == m);
    }
    CHECK(fx::all_sort_methods().size() == 4);
    SortMethod method;
    CHECK_FALSE(fx::parse_sort_method("bogus", method));
    CHECK_FALSE(fx::parse_sort_method("", method));
    CHECK_FALSE(fx::parse_sort_method("MPVO", method));
}

TEST_CASE("centroid sort gives every cell once, farthest centroid first", "[sort]") {
    const fx::CellMesh mesh = fx_test::hex_box(4, 3, 2);
    const fx::VisibilitySort sorter(mesh, SortMethod::Centroid);
    fx::Camera camera;
    camera.eye = {5.0, -4.0, 3.0};
    camera.target = {0.5, 0.5, 0.5};
    std::vector<std::uint32_t> order;
    fx::SortStats stats;
    sorter.sort(camera, order, &stats);
    REQUIRE(sort_test::is_permutation_of_cells(order, mesh.cell_count()));
    CHECK(stats.cells == mesh.cell_count());
    auto distance = [&](std::uint32_t c) { return glm::length(sort_test::cell_centroid(mesh, c) - camera.eye); };
    for (std::size_t i = 1; i < order.size(); ++i) CHECK(distance(order[i - 1]) >= distance(order[i]));
}

TEST_CASE("every method gives every cell exactly once", "[sort]") {
    const std::vector<std::pair<const char*, fx::CellMesh>> meshes = {
        {"hex box", fx_test::hex_box(5, 4, 3)},
        {"mixed box", fx_test::mixed_box(3)},
        {"three sticks", sort_test::three_sticks()},
        {"jittered tets", sort_test::jittered_tets(4, 0.3, 5)},
        {"empty", fx::CellMesh{}},
    };
    for (const auto& [name, mesh] : meshes) {
        for (SortMethod m : fx::all_sort_methods()) {
            INFO(name << " " << fx::sort_method_name(m));
            const fx::VisibilitySort sorter(mesh, m);
            CHECK(sorter.method() == m);
            CHECK((mesh.cell_count() == 0 || sorter.memory_bytes() > 0));
            for (const fx::Camera& cam : sort_test::random_views(mesh.cell_count() ? mesh : fx_test::hex_box(1, 1, 1), 6, 3)) {
                std::vector<std::uint32_t> order{7, 7, 7}; // stale contents are replaced
                fx::SortStats stats;
                sorter.sort(cam, order, &stats);
                REQUIRE(sort_test::is_permutation_of_cells(order, mesh.cell_count()));
                CHECK(stats.cells == mesh.cell_count());
                CHECK(stats.seconds >= 0.0);
            }
        }
    }
}

TEST_CASE("mpvo is exact along viewing rays on convex meshes", "[sort]") {
    const std::vector<fx::Camera> box_views = sort_test::random_views(fx_test::hex_box(1, 1, 1), 9, 11);
    require_exact("hex box", fx_test::hex_box(6, 5, 4), SortMethod::Mpvo, box_views);
    require_exact("tetrahedralised box", fx::tetrahedralize(fx_test::hex_box(5, 4, 4)), SortMethod::Mpvo, box_views);
    require_exact("mixed box", fx_test::mixed_box(4), SortMethod::Mpvo, box_views);
    // Jittered points: convex but far from Delaunay; no cycles arise in these views.
    require_exact("jittered tets", sort_test::jittered_tets(5, 0.25, 2), SortMethod::Mpvo, box_views);

    // tetraMesh.vtk wound both ways (its file has 80 inverted cells; the reader orients them):
    // every third cell inverted again, so that the sort sees mixed winding.
    fx::CellMesh tetra_mesh = read_content_mesh("content/meshes/vtk_cells/tetraMesh.vtk");
    for (std::size_t c = 0; c < tetra_mesh.cell_count(); c += 3) std::swap(tetra_mesh.cell_vertices(c)[1], tetra_mesh.cell_vertices(c)[2]);
    std::size_t inverted = 0;
    for (const fx::MeshProblem& p : fx::validate_mesh(tetra_mesh)) inverted += p.kind == fx::MeshProblemKind::Inverted;
    CHECK(inverted > 0);
    REQUIRE(sort_test::boundary_witness_faces(tetra_mesh) == 0); // the README: convex
    require_exact("tetraMesh.vtk", tetra_mesh, SortMethod::Mpvo, sort_test::random_views(tetra_mesh, 9, 12));

    // Far from the origin: planes are stored relative to the mesh's centre.
    fx::CellMesh far = fx::tetrahedralize(fx_test::hex_box(4, 4, 4));
    for (glm::dvec3& p : far.points) p += glm::dvec3(3.0e6, -2.0e6, 1.0e6);
    require_exact("box far from the origin", far, SortMethod::Mpvo, sort_test::random_views(far, 9, 13));

    // centroid and power on the same convex meshes, for comparison.
    report("jittered tets", sort_test::jittered_tets(5, 0.25, 2), SortMethod::Centroid, box_views);
    report("jittered tets", sort_test::jittered_tets(5, 0.25, 2), SortMethod::Power, box_views);
}

TEST_CASE("mpvo orders both cells of every shared face, eye on a face plane included", "[sort]") {
    const fx::CellMesh mesh = fx::tetrahedralize(fx_test::hex_box(4, 4, 4));
    const fx::FaceTopology topo = fx::build_face_topology(mesh);
    const fx::VisibilitySort sorter(mesh, SortMethod::Mpvo);
    std::vector<fx::Camera> views = sort_test::random_views(mesh, 6, 21);
    fx::Camera on_planes; // eye on the grid planes x = 0.5 and y = 0.25, looking along them
    on_planes.eye = {0.5, 0.25, 3.0};
    on_planes.target = {0.5, 0.25, 0.0};
    views.push_back(on_planes);
    on_planes.ortho_height = 2.0;
    views.push_back(on_planes);
    for (const fx::Camera& cam : views) {
        std::vector<std::uint32_t> order;
        fx::SortStats stats;
        sorter.sort(cam, order, &stats);
        REQUIRE(stats.cycles == 0);
        std::vector<std::uint32_t> position(order.size());
        for (std::uint32_t i = 0; i < order.size(); ++i) position[order[i]] = i;
        std::size_t checked = 0, wrong = 0;
        for (std::uint32_t c = 0; c < mesh.cell_count(); ++c) {
            for (std::uint32_t s = topo.first_face[c]; s < topo.first_face[c + 1]; ++s) {
                if (topo.neighbour[s] == fx::FaceTopology::kBoundary) continue;
                const std::uint32_t nc = topo.slot_cell[topo.neighbour[s]];
                // The eye on c's outer side of the face: the neighbour is nearer, drawn later.
                const fx::CellFace& face = fx::cell_faces(mesh.cell_types[c])[s - topo.first_face[c]];
                const glm::dvec3 a = mesh.points[mesh.cell_vertices(c)[face.v[0]]];
                glm::dvec3 n = glm::cross(mesh.points[mesh.cell_vertices(c)[face.v[1]]] - a,
                                          mesh.points[mesh.cell_vertices(c)[face.v[2]]] - a);
                if (glm::dot(n, sort_test::cell_centroid(mesh, c) - a) > 0.0) n = -n;
                const double side = cam.orthographic() ? -glm::dot(n, cam.forward()) : glm::dot(n, cam.eye - a);
                if (std::abs(side) < 1e-12) continue; // eye on the plane: either order is right
                ++checked;
                if ((side > 0.0) != (position[c] < position[nc])) ++wrong;
            }
        }
        CHECK(checked > 500);
        CHECK(wrong == 0);
    }
}

TEST_CASE("xmpvo is exact on non-convex meshes, where mpvo is not", "[sort]") {
    const fx::CellMesh c_tets = sort_test::c_shape(24, 3, 2, true);
    REQUIRE(fx::validate_mesh(c_tets).empty());
    REQUIRE(sort_test::boundary_witness_faces(c_tets) > 0);
    const std::vector<fx::Camera> c_views = sort_test::random_views(c_tets, 12, 31);
    require_exact("C-shape (tetrahedra)", c_tets, SortMethod::Xmpvo, c_views);
    // The oracle sees what MPVO misses: rays leaving one arm and entering the other.
    const MethodResult mpvo_c = report("C-shape (tetrahedra)", c_tets, SortMethod::Mpvo, c_views);
    CHECK(mpvo_c.rays.bad_pairs > 0);

    const fx::CellMesh c_hexes = sort_test::c_shape(20, 2, 2, false);
    require_exact("C-shape (hexahedra)", c_hexes, SortMethod::Xmpvo, sort_test::random_views(c_hexes, 9, 32));

    const fx::CellMesh hollow = sort_test::hollow_box(6, 2);
    std::vector<fx::Camera> hollow_views = sort_test::random_views(hollow, 9, 33);
    // Eye on the plane of the cavity's floor (z = 2/6, the same double as the mesh's points):
    // boundary faces seen exactly edge-on, perspective and orthographic.
    fx::Camera edge_on;
    edge_on.eye = {-1.5, 0.45, 2.0 / 6.0};
    edge_on.target = {0.5, 0.55, 2.0 / 6.0};
    edge_on.up = {0.0, 0.0, 1.0};
    edge_on.near_distance = 1e-3;
    hollow_views.push_back(edge_on);
    edge_on.ortho_height = 1.6;
    hollow_views.push_back(edge_on);
    require_exact("box with a cavity", hollow, SortMethod::Xmpvo, hollow_views);
    const fx::CellMesh two = sort_test::two_boxes();
    require_exact("two boxes", two, SortMethod::Xmpvo, sort_test::random_views(two, 9, 34));

    // On a convex mesh xmpvo finds no exterior edges and is mpvo.
    const fx::CellMesh box = fx::tetrahedralize(fx_test::hex_box(3, 3, 3));
    const fx::VisibilitySort x(box, SortMethod::Xmpvo), m(box, SortMethod::Mpvo);
    for (const fx::Camera& cam : sort_test::random_views(box, 6, 35)) {
        std::vector<std::uint32_t> ox, om;
        fx::SortStats stats;
        x.sort(cam, ox, &stats);
        m.sort(cam, om);
        CHECK(stats.exterior_edges == 0);
        CHECK(ox == om);
    }
}

TEST_CASE("xmpvo is exact on the real non-convex meshes", "[sort]") {
    // LOx post (8,750 tetrahedra; the data README counts 630 non-convex witness faces) and the
    // linear cylinder (1,522 tetrahedra, 569).
    const fx::CellMesh post = read_content_mesh("content/meshes/lox_post/post.vtk");
    CHECK(sort_test::boundary_witness_faces(post) == 630);
    const std::vector<fx::Camera> post_views = sort_test::random_views(post, 9, 41);
    require_exact("post.vtk", post, SortMethod::Xmpvo, post_views);
    report("post.vtk", post, SortMethod::Mpvo, post_views);
    report("post.vtk", post, SortMethod::Centroid, post_views);
    report("post.vtk", post, SortMethod::Power, post_views);

    const fx::CellMesh cylinder = read_content_mesh("content/meshes/cylinder_tets/CylinderLinear.vtk");
    CHECK(sort_test::boundary_witness_faces(cylinder) == 569);
    const std::vector<fx::Camera> cylinder_views = sort_test::random_views(cylinder, 12, 42);
    require_exact("CylinderLinear.vtk", cylinder, SortMethod::Xmpvo, cylinder_views);
    report("CylinderLinear.vtk", cylinder, SortMethod::Mpvo, cylinder_views);
    report("CylinderLinear.vtk", cylinder, SortMethod::Centroid, cylinder_views);
}

TEST_CASE("power sort is exact on a Delaunay tetrahedralisation", "[sort]") {
    std::mt19937 rng(51);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<glm::dvec3> points(300);
    for (glm::dvec3& p : points) p = glm::dvec3(unit(rng), unit(rng), 0.6 * unit(rng));
    const fx::CellMesh mesh = sort_test::delaunay_mesh(points);
    REQUIRE(mesh.cell_count() > 1000);
    REQUIRE(fx::validate_mesh(mesh).empty());
    REQUIRE(sort_test::delaunay_violations(mesh) == 0); // the empty-sphere property, by brute force
    const std::vector<fx::Camera> views = sort_test::random_views(mesh, 12, 52);
    require_exact("Delaunay", mesh, SortMethod::Power, views);
    require_exact("Delaunay", mesh, SortMethod::Xmpvo, views);
    if (sort_test::boundary_witness_faces(mesh) == 0) require_exact("Delaunay", mesh, SortMethod::Mpvo, views);
    report("Delaunay", mesh, SortMethod::Centroid, views);
}

TEST_CASE("cycles are broken and counted, never looped on", "[sort]") {
    const fx::CellMesh sticks = sort_test::three_sticks();
    REQUIRE(fx::validate_mesh(sticks).empty());
    fx::Camera above;
    above.eye = {0.05, 0.02, 6.0};
    above.target = {0.0, 0.0, 0.5};
    std::vector<fx::Camera> views{above};
    above.ortho_height = 3.0;
    views.push_back(above);
    const fx::VisibilitySort xmpvo(sticks, SortMethod::Xmpvo);
    const fx::VisibilitySort mpvo(sticks, SortMethod::Mpvo);
    const sort_test::CellPlanes planes = sort_test::cell_planes(sticks);
    for (const fx::Camera& cam : views) {
        std::vector<std::uint32_t> order;
        fx::SortStats stats;
        xmpvo.sort(cam, order, &stats);
        REQUIRE(sort_test::is_permutation_of_cells(order, 3));
        CHECK(stats.exterior_edges == 3); // each stick over the next
        CHECK(stats.cycles == 1);
        // No order satisfies a cycle: the oracle must see exactly the broken edge.
        const sort_test::RayOrderCheck r = sort_test::check_order_along_rays(sticks, planes, cam, order, 64, 64, 1);
        CHECK(r.bad_pairs > 0);
        mpvo.sort(cam, order, &stats); // no shared faces: nothing to order, no cycle seen
        REQUIRE(sort_test::is_permutation_of_cells(order, 3));
        CHECK(stats.cycles == 0);
    }
    // Strongly twisted hexahedra (non-planar faces): whatever the planes say, every cell once.
    fx::CellMesh twisted = fx_test::hex_box(5, 5, 5);
    std::mt19937 rng(61);
    std::uniform_real_distribution<double> d(-0.09, 0.09);
    for (glm::dvec3& p : twisted.points) p += glm::dvec3(d(rng), d(rng), d(rng));
    std::size_t cycles = 0;
    for (SortMethod m : {SortMethod::Mpvo, SortMethod::Xmpvo}) {
        const fx::VisibilitySort sorter(twisted, m);
        for (const fx::Camera& cam : sort_test::random_views(twisted, 30, 62)) {
            std::vector<std::uint32_t> order;
            fx::SortStats stats;
            sorter.sort(cam, order, &stats);
            REQUIRE(sort_test::is_permutation_of_cells(order, twisted.cell_count()));
            cycles += stats.cycles;
        }
    }
    WARN("twisted hexahedra: " << cycles << " cycles broken over 60 sorts");
}

TEST_CASE("sort() may run on several threads at once", "[sort]") {
    const fx::CellMesh mesh = sort_test::c_shape(24, 3, 2, true);
    const std::vector<fx::Camera> views = sort_test::random_views(mesh, 4, 71);
    for (SortMethod m : fx::all_sort_methods()) {
        const fx::VisibilitySort sorter(mesh, m);
        std::vector<std::vector<std::uint32_t>> expected(views.size());
        for (std::size_t v = 0; v < views.size(); ++v) sorter.sort(views[v], expected[v]);
        std::vector<std::vector<std::uint32_t>> got[2];
        auto work = [&](int t) {
            got[t].resize(views.size());
            for (int round = 0; round < 3; ++round)
                for (std::size_t v = 0; v < views.size(); ++v) sorter.sort(views[v], got[t][v]);
        };
        std::thread a(work, 0), b(work, 1);
        a.join();
        b.join();
        CHECK(got[0] == expected);
        CHECK(got[1] == expected);
    }
}

TEST_CASE("visibility sort rejects vertex indices out of range", "[sort]") {
    fx::CellMesh mesh = fx_test::hex_box(2, 1, 1);
    mesh.connectivity[11] = 999;
    for (SortMethod m : fx::all_sort_methods()) {
        try {
            const fx::VisibilitySort sorter(mesh, m);
            FAIL("no error for " << fx::sort_method_name(m));
        } catch (const fx::Error& e) {
            CHECK(std::string(e.what()).find("cell 1: vertex 3 is point 999") != std::string::npos);
        }
    }
}

TEST_CASE("rebuild() gives the orders of a sort made for the new mesh, and a copy keeps the old one", "[sort]") {
    // A C-shape (non-convex: xmpvo adds exterior edges) replaced by a hollow box and by mixed
    // cells: another size, other cell types, other boundary faces.
    const fx::CellMesh first = sort_test::c_shape(24, 3, 2, true);
    const fx::CellMesh hollow = sort_test::hollow_box(6, 2);
    const fx::CellMesh mixed = fx_test::mixed_box_with_tets(3);
    for (SortMethod m : fx::all_sort_methods()) {
        INFO(fx::sort_method_name(m));
        fx::VisibilitySort sorter(first, m);
        const fx::VisibilitySort copy = sorter;
        for (const fx::CellMesh* mesh : {&hollow, &mixed, &first}) {
            sorter.rebuild(*mesh);
            const fx::VisibilitySort fresh(*mesh, m);
            for (const fx::Camera& cam : sort_test::random_views(*mesh, 4, 81)) {
                std::vector<std::uint32_t> got, want;
                sorter.sort(cam, got);
                fresh.sort(cam, want);
                CHECK(got == want);
            }
        }
        // The copy was made before the rebuilds: it still sorts the first mesh.
        const fx::VisibilitySort fresh_first(first, m);
        for (const fx::Camera& cam : sort_test::random_views(first, 3, 82)) {
            std::vector<std::uint32_t> got, want;
            copy.sort(cam, got);
            fresh_first.sort(cam, want);
            CHECK(got == want);
        }
    }
    // A bad mesh is refused before anything changes.
    fx::VisibilitySort sorter(hollow, SortMethod::Xmpvo);
    fx::CellMesh bad = fx_test::hex_box(2, 1, 1);
    bad.connectivity[11] = 999;
    CHECK_THROWS_WITH(sorter.rebuild(bad), Catch::Contains("cell 1: vertex 3 is point 999"));
    std::vector<std::uint32_t> order;
    sorter.sort(sort_test::random_views(hollow, 1, 83)[0], order);
    CHECK(sort_test::is_permutation_of_cells(order, hollow.cell_count()));
}
