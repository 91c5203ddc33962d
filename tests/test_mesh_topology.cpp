#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

#include "mesh/face_topology.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "mesh/tetrahedralize.hpp"
#include "mesh_builders.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

std::size_t boundary_triangles(const fx::CellMesh& mesh, const fx::FaceTopology& topo) {
    std::size_t n = 0;
    for (std::uint32_t slot : topo.boundary_faces) {
        const std::uint32_t cell = topo.slot_cell[slot];
        const fx::CellFace& face = fx::cell_faces(mesh.cell_types[cell])[slot - topo.first_face[cell]];
        n += face.count == 4 ? 2 : 1;
    }
    return n;
}

// Volume enclosed by the cell's faces cut along their smallest-vertex diagonals: the shape the
// tetrahedra fill exactly, even when quads are not planar.
double volume_by_face_triangles(const fx::CellMesh& mesh, std::size_t cell) {
    const fx::CellType type = mesh.cell_types[cell];
    const std::uint32_t* cv = mesh.cell_vertices(cell);
    const glm::dvec3 o = mesh.points[cv[0]];
    double v = 0.0;
    for (int f = 0; f < fx::cell_face_count(type); ++f) {
        std::uint32_t tri[2][3];
        const int n = fx::triangulate_face(fx::cell_faces(type)[f], cv, tri);
        for (int t = 0; t < n; ++t) {
            const glm::dvec3 a = mesh.points[tri[t][0]] - o, b = mesh.points[tri[t][1]] - o, c = mesh.points[tri[t][2]] - o;
            v += glm::dot(a, glm::cross(b, c)) / 6.0;
        }
    }
    return v;
}

double total_volume(const fx::CellMesh& mesh) {
    double v = 0.0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) v += fx::cell_signed_volume(mesh, c);
    return v;
}

} // namespace

TEST_CASE("face topology of a hexahedral box", "[mesh]") {
    const fx::CellMesh mesh = fx_test::hex_box(3, 2, 4);
    const fx::FaceTopology topo = fx::build_face_topology(mesh);
    CHECK(topo.face_slot_count() == 6 * 24);
    CHECK(topo.boundary_faces.size() == 2 * (3 * 2 + 2 * 4 + 3 * 4));
    CHECK(topo.non_manifold_faces == 0);
    for (std::uint32_t s = 0; s < topo.face_slot_count(); ++s) {
        if (topo.neighbour[s] != fx::FaceTopology::kBoundary) CHECK(topo.neighbour[topo.neighbour[s]] == s);
    }
}

TEST_CASE("validation names the cell and the problem", "[mesh]") {
    fx::CellMesh mesh = fx_test::hex_box(3, 1, 1);
    mesh.scalars.push_back({"density", std::vector<float>(mesh.point_count(), 1.0f)});
    CHECK(fx::validate_mesh(mesh).empty());

    SECTION("index out of range") {
        mesh.cell_vertices(1)[5] = 999;
        const auto problems = fx::validate_mesh(mesh);
        REQUIRE(problems.size() == 1);
        CHECK(problems[0].kind == fx::MeshProblemKind::IndexOutOfRange);
        CHECK(problems[0].message == "cell 1: vertex 5 is point 999 but the mesh has 16 points");
    }
    SECTION("NaN coordinate and scalar") {
        mesh.points[0].y = std::numeric_limits<double>::quiet_NaN();
        mesh.scalars[0].values[1] = std::numeric_limits<float>::infinity();
        const auto problems = fx::validate_mesh(mesh);
        // Point 0 belongs to cell 0 only; point 1 to cells 0 and 1.
        REQUIRE(problems.size() == 3);
        CHECK(problems[0].kind == fx::MeshProblemKind::NonFiniteCoordinate);
        CHECK(problems[0].cell == 0);
        CHECK(problems[1].kind == fx::MeshProblemKind::NonFiniteScalar);
        CHECK_THAT(problems[1].message, Catch::Contains("'density'") && Catch::Contains("point 1"));
        CHECK(problems[2].kind == fx::MeshProblemKind::NonFiniteScalar);
        CHECK(problems[2].cell == 1);
    }
    SECTION("inverted, flat, repeated and twisted cells") {
        std::uint32_t* h = mesh.cell_vertices(0);
        std::swap_ranges(h, h + 4, h + 4); // inverted
        for (int i = 4; i < 8; ++i) mesh.points[mesh.cell_vertices(2)[i]].z = 0.0; // flattens cell 2
        mesh.cell_vertices(1)[6] = mesh.cell_vertices(1)[0];
        const auto problems = fx::validate_mesh(mesh);
        REQUIRE(problems.size() >= 3);
        CHECK(problems[0].kind == fx::MeshProblemKind::Inverted);
        CHECK(problems[0].cell == 0);
        CHECK(problems[1].kind == fx::MeshProblemKind::RepeatedVertex);
        CHECK(problems[1].cell == 1);
        CHECK(problems.back().kind == fx::MeshProblemKind::ZeroVolume);
        CHECK(problems.back().cell == 2);
    }
    SECTION("twisted hexahedron") {
        std::uint32_t* h = mesh.cell_vertices(0);
        std::swap(h[4], h[5]); // top face crossed: half of the cell inside out
        const auto problems = fx::validate_mesh(mesh);
        REQUIRE_FALSE(problems.empty());
        CHECK((problems[0].kind == fx::MeshProblemKind::Twisted || problems[0].kind == fx::MeshProblemKind::ZeroVolume));
    }
}

TEST_CASE("orient_cells makes every cell type positive and reports degenerate cells", "[mesh]") {
    fx::CellMesh mesh = fx_test::mixed_box(3);
    const double volume = total_volume(mesh);
    CHECK(volume == Approx(1.0));
    std::mt19937 rng(7);
    std::size_t inverted = 0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        if (rng() % 2) continue;
        std::uint32_t* v = mesh.cell_vertices(c);
        switch (mesh.cell_types[c]) {
        case fx::CellType::Tetra: std::swap(v[0], v[1]); break;
        case fx::CellType::Pyramid: std::swap(v[0], v[2]); break;
        case fx::CellType::Wedge: std::swap_ranges(v, v + 3, v + 3); break;
        case fx::CellType::Hexahedron: std::swap_ranges(v, v + 4, v + 4); break;
        }
        ++inverted;
    }
    const std::uint32_t flat[4] = {0, 1, 1, 2};
    mesh.add_cell(fx::CellType::Tetra, flat);
    const fx::OrientationReport report = fx::orient_cells(mesh);
    CHECK(report.flipped == inverted);
    REQUIRE(report.degenerate.size() == 1);
    CHECK(report.degenerate[0] == mesh.cell_count() - 1);
    for (std::size_t c = 0; c + 1 < mesh.cell_count(); ++c) CHECK(fx::cell_signed_volume(mesh, c) > 0.0);
    CHECK(total_volume(mesh) == Approx(volume));
}

TEST_CASE("consistent tetrahedra: shared quads agree, volumes add up, nothing inverted", "[mesh][tetrahedralize]") {
    std::mt19937 rng(1234);
    for (int trial = 0; trial < 20; ++trial) {
        CAPTURE(trial);
        fx::CellMesh mesh = fx_test::mixed_box(4);
        // Curvilinear: jitter interior points a little so quads are non-planar.
        std::uniform_real_distribution<double> jitter(-0.04, 0.04);
        for (glm::dvec3& p : mesh.points) {
            for (int a = 0; a < 3; ++a) {
                if (p[a] > 1e-9 && p[a] < 1.0 - 1e-9) p[a] += jitter(rng);
            }
        }
        fx_test::shuffle_point_ids(mesh, rng);
        const fx::FaceTopology before = fx::build_face_topology(mesh);

        std::vector<std::uint32_t> parent;
        const fx::CellMesh tets = fx::tetrahedralize(mesh, &parent);
        REQUIRE(parent.size() == tets.cell_count());
        const fx::FaceTopology after = fx::build_face_topology(tets);
        // Every internal triangle found its partner: only the outer surface is left.
        CHECK(after.non_manifold_faces == 0);
        CHECK(boundary_triangles(tets, after) == boundary_triangles(mesh, before));

        std::vector<double> sum(mesh.cell_count(), 0.0);
        for (std::size_t t = 0; t < tets.cell_count(); ++t) {
            const double v = fx::cell_signed_volume(tets, t);
            CHECK(v > 0.0);
            sum[parent[t]] += v;
        }
        for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
            CHECK(sum[c] == Approx(volume_by_face_triangles(mesh, c)).epsilon(1e-9));
        }
    }
}

TEST_CASE("hexahedra give 5 or 6 tetrahedra, pyramids 2, wedges 3", "[mesh][tetrahedralize]") {
    std::uint32_t out[fx::kMaxCellTetrahedra][4];
    const std::uint32_t pyramid[5] = {3, 1, 2, 0, 4};
    CHECK(fx::subdivide_cell(fx::CellType::Pyramid, pyramid, out) == 2);
    const std::uint32_t wedge[6] = {5, 2, 3, 0, 4, 1};
    CHECK(fx::subdivide_cell(fx::CellType::Wedge, wedge, out) == 3);
    // Every numbering of a hexahedron: count how often each case occurs.
    std::uint32_t v[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    int five = 0, six = 0;
    do {
        const int n = fx::subdivide_cell(fx::CellType::Hexahedron, v, out);
        REQUIRE((n == 5 || n == 6));
        (n == 5 ? five : six)++;
    } while (std::next_permutation(v, v + 8));
    CHECK(five > 0);
    CHECK(six > 0);
    CHECK(five + six == 40320);
}

TEST_CASE("consistent tetrahedra on whole real meshes: no internal triangle left unmatched", "[mesh][tetrahedralize]") {
    struct RealMesh {
        const char* xyz;
        const char* q;
    };
    for (const RealMesh& file : {RealMesh{"content/meshes/blunt_fin/bluntfinxyz.bin", "content/meshes/blunt_fin/bluntfinq.bin"},
                                 RealMesh{"content/meshes/hexa_grid/hexa.vtk", ""}}) {
        CAPTURE(file.xyz);
        const fx::CellMesh mesh = fx::read_mesh(fx_test::source_path(file.xyz), file.q[0] ? fx_test::source_path(file.q) : "");
        REQUIRE(fx::validate_mesh(mesh).empty());
        const fx::FaceTopology before = fx::build_face_topology(mesh);
        std::vector<std::uint32_t> parent;
        const fx::CellMesh tets = fx::tetrahedralize(mesh, &parent);
        const fx::FaceTopology after = fx::build_face_topology(tets);
        // Each quad shared by two hexahedra was cut the same way from both sides, so all its
        // triangles pair up: what is left unmatched is exactly the outer surface.
        CHECK(after.non_manifold_faces == 0);
        CHECK(boundary_triangles(tets, after) == boundary_triangles(mesh, before));
        // The blunt fin's leading edge is collapsed (distinct points at one position), so a
        // tetrahedron using two of them is flat; every other one must be positive.
        auto has_coincident_points = [&tets](std::size_t t) {
            const std::uint32_t* v = tets.cell_vertices(t);
            for (int i = 0; i < 4; ++i)
                for (int j = i + 1; j < 4; ++j)
                    if (tets.points[v[i]] == tets.points[v[j]]) return true;
            return false;
        };
        double parents = 0.0, children = 0.0;
        std::size_t inverted = 0, flat_without_reason = 0;
        for (std::size_t t = 0; t < tets.cell_count(); ++t) {
            const double v = fx::cell_signed_volume(tets, t);
            inverted += v < 0.0;
            flat_without_reason += v == 0.0 && !has_coincident_points(t);
            children += v;
        }
        CHECK(flat_without_reason == 0);
        for (std::size_t c = 0; c < mesh.cell_count(); ++c) parents += volume_by_face_triangles(mesh, c);
        CHECK(inverted == 0);
        CHECK(children == Approx(parents).epsilon(1e-9));
    }
}

TEST_CASE("cell shapes are judged at any scale: positive, inverted, flat, twisted", "[mesh]") {
    for (const double scale : {1e-25, 1e-9, 1.0, 1e9, 1e17}) {
        INFO("scale " << scale);
        fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
        for (glm::dvec3& p : mesh.points) p = p * scale + glm::dvec3(3.0 * scale);
        CHECK(fx::classify_cell(mesh, 0) == fx::CellShape::Positive);
        std::uint32_t* h = mesh.cell_vertices(0);
        std::swap_ranges(h, h + 4, h + 4);
        CHECK(fx::classify_cell(mesh, 0) == fx::CellShape::Inverted);
        std::swap_ranges(h, h + 4, h + 4);
        std::swap(h[4], h[6]); // the top face half a turn round: a bow-tie
        CHECK(fx::classify_cell(mesh, 0) == fx::CellShape::Twisted);
        std::swap(h[4], h[6]);
        for (int i = 4; i < 8; ++i) mesh.points[h[i]].z = mesh.points[h[0]].z;
        CHECK(fx::classify_cell(mesh, 0) == fx::CellShape::Flat);
    }
}

TEST_CASE("validation reports duplicates and cells on the same side of a shared face", "[mesh]") {
    fx::CellMesh mesh = fx_test::hex_box(2, 1, 1);
    CHECK(fx::validate_mesh(mesh).empty());
    SECTION("a duplicate (any vertex order) and three copies of one cell") {
        std::uint32_t v[8];
        std::copy(mesh.cell_vertices(1), mesh.cell_vertices(1) + 8, v);
        std::swap_ranges(v, v + 4, v + 4); // the same points, inverted: still the same cell
        mesh.add_cell(fx::CellType::Hexahedron, v);
        mesh.add_cell(fx::CellType::Hexahedron, mesh.cell_vertices(1));
        const auto problems = fx::validate_mesh(mesh);
        std::vector<std::string> duplicates;
        for (const fx::MeshProblem& p : problems)
            if (p.kind == fx::MeshProblemKind::Duplicate) duplicates.push_back(p.message);
        REQUIRE(duplicates.size() == 2);
        CHECK(duplicates[0] == "cell 2: cell 2 has the same points as cell 1");
        CHECK(duplicates[1] == "cell 3: cell 3 has the same points as cell 1");
    }
    SECTION("a cell folded back onto its neighbour across their shared face") {
        // Cell 1 mirrored through the face it shares with cell 0 (x = 0.5), kept positive.
        fx::CellMesh folded = mesh;
        std::uint32_t* h = folded.cell_vertices(1);
        for (int i : {1, 2, 5, 6}) folded.points[h[i]].x = 0.0;
        std::swap(h[0], h[1]), std::swap(h[3], h[2]), std::swap(h[4], h[5]), std::swap(h[7], h[6]);
        REQUIRE(fx::classify_cell(folded, 1) == fx::CellShape::Positive);
        const auto problems = fx::validate_mesh(folded);
        bool overlapping = false;
        for (const fx::MeshProblem& p : problems)
            overlapping = overlapping || (p.kind == fx::MeshProblemKind::Overlapping && p.cell == 1);
        CHECK(overlapping);
    }
    SECTION("overlapping blocks are not a problem: their media add") {
        fx::CellMesh two = mesh;
        two.begin_block("copy");
        two.add_cell(fx::CellType::Hexahedron, two.cell_vertices(0));
        CHECK(fx::validate_mesh(two).empty());
    }
}

TEST_CASE("check_renderable refuses what no path can draw, naming the cells", "[mesh]") {
    fx::CellMesh mesh = fx_test::hex_box(2, 1, 1);
    CHECK(fx::check_renderable(mesh, "m").size() == 2);
    fx::CellMesh twisted = mesh;
    std::swap(twisted.cell_vertices(1)[4], twisted.cell_vertices(1)[6]);
    CHECK_THROWS_WITH(fx::check_renderable(twisted, "m.vtk"), Catch::StartsWith("m.vtk: 1 cell folds over itself (cell 1)"));
    fx::CellMesh flat = mesh;
    for (glm::dvec3& p : flat.points) p.y = 0.0;
    CHECK_THROWS_WITH(fx::check_renderable(flat, "m.vtk"), Catch::Contains("all 2 cells have zero volume"));
    fx::CellMesh far = mesh;
    far.points[3].z = 2e18;
    CHECK_THROWS_WITH(fx::check_renderable(far, "m.vtk"), Catch::Contains("point 3") && Catch::Contains("beyond ±1e+18"));
    fx::CellMesh one_flat = mesh; // a flat cell among solid ones: drawn as nothing, not refused
    const std::uint32_t flat_tet[4] = {0, 1, 1, 2};
    one_flat.add_cell(fx::CellType::Tetra, flat_tet);
    const auto shapes = fx::check_renderable(one_flat, "m");
    CHECK(shapes[2] == fx::CellShape::Flat);
    fx::CellMesh nan_field = mesh;
    nan_field.scalars = {{"p", std::vector<float>(mesh.point_count(), 1.0f)}};
    nan_field.scalars[0].values[5] = std::nanf("");
    CHECK_THROWS_WITH(fx::check_scalar_field(nan_field, nan_field.scalars[0], "m.vtk"),
                      Catch::StartsWith("m.vtk: field 'p' is NaN at point 5;"));
}
