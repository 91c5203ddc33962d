// The projector's per-triangle tables are built on the GPU (shaders/projector_tables.comp) from
// the mesh's points and connectivity, whole for a new mesh and in part after update_mesh(): here
// they are held to the CPU's build of the same formulas on the same float positions
// (fx::build_projector_tables), table by table, for every kind of cell, inverted and folded
// cells, flat and sliver cells, and after in-place updates that move points, rewire cells, add
// cells and drop the last ones.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "fx/cell_renderer.hpp"
#include "fx/mesh_validation.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "projector/gl_interface.hpp"
#include "projector/gl_projector.hpp"
#include "projector_meshes.hpp"
#include "cellfx_names.hpp"

namespace {

// Within float rounding: both sides compute in double from the same floats and round once, so
// they differ only where the GPU's double division or square root rounds differently (at most an
// ulp or two of double, then the same or the neighbouring float): 4 float ulps of the larger
// magnitude, and an absolute floor of 1e-6 of the table's largest entry for values that cancel
// to nearly zero (a gradient component of a plane or function seen edge-on). Entries for which
// `skip` is true are not compared.
void check_close(const std::vector<glm::vec4>& gpu, const std::vector<glm::vec4>& cpu, const char* what,
                 const std::vector<bool>& skip = {}) {
    INFO(what);
    REQUIRE(gpu.size() == cpu.size());
    float largest = 0.0f;
    for (const glm::vec4& v : cpu)
        for (int k = 0; k < 4; ++k) largest = std::max(largest, std::abs(v[k]));
    std::size_t bad = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i)
        for (int k = 0; k < 4 && !(i < skip.size() && skip[i]); ++k) {
            const float a = gpu[i][k], b = cpu[i][k];
            const float bound = 4.0f * 1.2e-7f * std::max(std::abs(a), std::abs(b)) + 1e-6f * largest;
            if (!(std::abs(a - b) <= bound)) {
                if (bad++ < 5) UNSCOPED_INFO("entry " << i << "[" << k << "]: gpu " << a << " cpu " << b);
            }
        }
    CHECK(bad == 0);
}

struct TableCounts {
    std::size_t planar = 0, folded = 0;
};

// The GPU's tables against the CPU's for what the projector now holds. A cell whose planar test
// the CPU passes or fails by less than 1e-9 of the tolerance (fx::ProjectorTables::planar_margins)
// may be decided the other way by the GPU's rounding: its word and slots are not compared.
TableCounts check_tables(fx::GlProjector& projector) {
    const fx::ProjectorTables gpu = projector.read_tables();
    const fx::ProjectorTables cpu =
        fx::build_projector_tables(projector.mesh(), projector.geometry(), projector.vertices_per_cell(), projector.planar_tolerance());
    const std::vector<std::uint32_t>& first = projector.cell_first_triangle();
    std::vector<bool> skip_triangle(first.back(), false), skip_row(2 * first.back(), false);
    TableCounts counts;
    REQUIRE(gpu.words.size() == cpu.words.size());
    std::size_t border = 0, words_differ = 0;
    for (std::size_t c = 0; c < cpu.words.size(); ++c) {
        const bool planar = (cpu.words[c] & fx::kWordPlanar) != 0;
        (planar ? counts.planar : counts.folded)++;
        if (std::abs(cpu.planar_margins[c]) < 1e-9) {
            ++border;
            for (std::uint32_t t = first[c]; t < first[c + 1]; ++t) skip_triangle[t] = skip_row[2 * t] = skip_row[2 * t + 1] = true;
        } else if (gpu.words[c] != cpu.words[c]) {
            if (words_differ++ < 5) UNSCOPED_INFO("cell " << c << ": gpu word " << gpu.words[c] << " cpu " << cpu.words[c]);
        }
    }
    CHECK(words_differ == 0);
    CHECK(border == 0); // none of these meshes has a cell on the border: the check above holds every word
    check_close(gpu.planes, cpu.planes, "planes", skip_triangle);
    check_close(gpu.scalar_functions, cpu.scalar_functions, "scalar functions", skip_triangle);
    if (!cpu.barycentrics.empty()) check_close(gpu.barycentrics, cpu.barycentrics, "barycentric rows", skip_row);
    CHECK(gpu.elements == cpu.elements);
    // The CPU's own planes (geometry(), for the CPU passes) are every face triangle's.
    const fx::ProjectorGeometry& geometry = projector.geometry();
    std::vector<glm::vec4> triangle_planes;
    for (const auto& tri : geometry.triangles)
        triangle_planes.push_back(fx::triangle_plane(glm::dvec3(geometry.positions[tri[0]]), glm::dvec3(geometry.positions[tri[1]]),
                                                     glm::dvec3(geometry.positions[tri[2]])));
    check_close(geometry.triangle_planes, triangle_planes, "CPU geometry planes");
    return counts;
}

fx::TransferFunction ramp() { return fx::TransferFunction({{0.0, {1, 1, 1}, 1.0}, {1.0, {1, 0.5, 0.2}, 2.0}}, true); }

void add_field(fx::CellMesh& mesh) {
    fx::ScalarField s{"s", {}};
    for (const glm::dvec3& p : mesh.points) s.values.push_back(float(0.3 + p.x - 0.5 * p.y + 0.25 * p.z * p.x));
    mesh.scalars.push_back(s);
}

// A curvilinear hexahedral grid whose quads fold (a twist and a bump), offset far from the origin.
fx::CellMesh folded_grid() {
    fx::CellMesh mesh = fx_test::hex_box(5, 4, 3, glm::dvec3(1e4, 2e4, -3e3), glm::dvec3(1e4 + 5, 2e4 + 4, -3e3 + 3));
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (glm::dvec3& p : mesh.points) p += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
    return mesh;
}

} // namespace

TEST_CASE("the GPU builds the projector's tables as the CPU does, for every kind of cell", "[gl][projector]") {
    fx_test::gl_context();
    SECTION("one of each cell") {
        fx::CellMesh mesh = fx_test::one_of_each_cell();
        fx::GlProjector projector(mesh, "s", ramp());
        CHECK(check_tables(projector).planar == 4);
    }
    SECTION("planar and folded cells side by side: regular, bent and folded hexahedra, terrain-fog wedges") {
        const fx::CellMesh mesh = fx_test::planar_and_folded_grid();
        fx::GlProjector projector(mesh, "s", ramp());
        // 48 regular, 36 bent (flat within the tolerance), 16 wedges (8 with a corner on the
        // fog's rim): planar; the folded block's 48 beyond it, and 14 wedges with an edge on the
        // rim (a side of no area).
        const TableCounts counts = check_tables(projector);
        CHECK(counts.planar == 48 + 36 + 16);
        CHECK(counts.folded == 48 + 14);
        // Tighter, the bent block's quads fold too; negative, nothing is planar.
        projector.set_planar_tolerance(1e-5);
        CHECK(check_tables(projector).planar == 48 + 16);
        projector.set_planar_tolerance(-1.0);
        CHECK(check_tables(projector).planar == 0);
    }
    SECTION("mixed cells with tetrahedra, every other one inverted, points shuffled") {
        fx::CellMesh mesh = fx_test::mixed_box_with_tets(4);
        std::mt19937 rng(3);
        fx_test::shuffle_point_ids(mesh, rng);
        fx_test::invert_every_other_cell(mesh);
        add_field(mesh);
        fx::GlProjector projector(mesh, "s", ramp());
        check_tables(projector);
    }
    SECTION("tetrahedra only") {
        fx::CellMesh grid = fx_test::hex_box(3, 3, 3);
        fx::CellMesh mesh;
        mesh.points = grid.points;
        for (std::size_t c = 0; c < grid.cell_count(); ++c) {
            std::uint32_t tets[fx::kMaxCellTetrahedra][4];
            const int k = fx::subdivide_cell(grid.cell_types[c], grid.cell_vertices(c), tets);
            for (int i = 0; i < k; ++i) mesh.add_cell(fx::CellType::Tetra, tets[i]);
        }
        add_field(mesh);
        fx::GlProjector projector(mesh, "s", ramp());
        CHECK(projector.all_tetrahedra());
        CHECK(check_tables(projector).planar == 0); // the tetrahedra's own path: no planar bit
    }
    SECTION("folded curvilinear hexahedra far from the origin") {
        fx::CellMesh mesh = folded_grid();
        add_field(mesh);
        fx::GlProjector projector(mesh, "s", ramp());
        check_tables(projector);
    }
    SECTION("flat and sliver cells") {
        fx::CellMesh mesh = fx_test::hex_box(2, 2, 1);
        // Collapse the top of one hexahedron onto its bottom (flat: zero planes on its sides),
        // and lift another's by a hair (a sliver).
        for (std::size_t i = 0; i < mesh.points.size(); ++i)
            if (mesh.points[i].z > 0.5 && mesh.points[i].x < 0.6) mesh.points[i].z = mesh.points[i].x < 0.1 ? 0.0 : 1e-6;
        add_field(mesh);
        fx::GlProjector projector(mesh, "s", ramp());
        check_tables(projector);
    }
}

TEST_CASE("in-place mesh updates rebuild exactly the tables a new mesh would have", "[gl][projector]") {
    fx_test::gl_context();
    fx::CellMesh mesh = fx_test::mixed_box(4);
    add_field(mesh);
    fx::GlProjector projector(mesh, "s", ramp());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> move(-0.03, 0.03);
    fx::MeshChanges changes;
    for (int round = 0; round < 4; ++round) {
        INFO("round " << round);
        changes.clear();
        // Move a few points (their scalars too) ...
        for (std::uint32_t p = std::uint32_t(round); p < mesh.point_count(); p += 7) {
            mesh.points[p] += glm::dvec3(move(rng), move(rng), move(rng));
            mesh.scalars[0].values[p] += 0.1f;
            changes.points.push_back(p);
        }
        // ... rewire a cell to points of its own shape elsewhere (its mirror: inverted, so the
        // renderer orients it) ...
        const std::uint32_t c = std::uint32_t(3 * round + 1);
        std::uint32_t* v = mesh.cell_vertices(c);
        if (mesh.cell_types[c] == fx::CellType::Hexahedron) std::swap_ranges(v, v + 4, v + 4);
        changes.cells.push_back(c);
        // ... add a wedge made of new points, and drop the last cell in the second round.
        const std::uint32_t base = std::uint32_t(mesh.point_count());
        const glm::dvec3 o(2.0 + round, 0.0, 0.0);
        for (const glm::dvec3& q : {o, o + glm::dvec3(1, 0, 0), o + glm::dvec3(0, 1, 0), o + glm::dvec3(0, 0, 1),
                                     o + glm::dvec3(1, 0, 1), o + glm::dvec3(0, 1, 1)}) {
            changes.points.push_back(std::uint32_t(mesh.point_count()));
            mesh.points.push_back(q);
            mesh.scalars[0].values.push_back(float(q.x));
        }
        if (round == 1) {
            mesh.cell_types.pop_back();
            mesh.cell_offsets.pop_back();
            mesh.connectivity.resize(mesh.cell_offsets.back());
            mesh.blocks.back().cell_count--;
        }
        const std::uint32_t wedge[6] = {base, base + 1, base + 2, base + 3, base + 4, base + 5};
        mesh.add_cell(fx::CellType::Wedge, wedge);
        changes.cells.push_back(std::uint32_t(mesh.cell_count() - 1));
        CHECK(projector.update_mesh(mesh, "s", changes));
        check_tables(projector);

        // The same as a mesh taken whole.
        fx::CellMesh oriented = mesh;
        fx::orient_cells(oriented);
        CHECK(projector.mesh().connectivity == oriented.connectivity);
        CHECK(projector.mesh().points == mesh.points);
    }
    // A change the renderer cannot apply in place is taken whole.
    changes.clear();
    changes.whole = true;
    CHECK_FALSE(projector.update_mesh(mesh, "s", changes));
    check_tables(projector);
}

TEST_CASE("barycentric rows only for cells that are not planar, by slot once the renderer is updated in place",
          "[gl][projector]") {
    fx_test::gl_context();
    fx::CellMesh mesh = fx_test::planar_and_folded_grid();
    const fx::CellMesh original = mesh;
    // The regular box's inner node (2, 2, 1) moved off its lattice: its 8 hexahedra fold.
    const std::uint32_t moved = 37;
    REQUIRE(mesh.points[moved] == glm::dvec3(0.5, 0.5, 0.25));
    fx::CellMesh bent = mesh;
    bent.points[moved] += glm::dvec3(0.04, -0.03, 0.05);
    bent.scalars[0].values[moved] += 0.2f;

    const auto folded_triangles = [](const fx::ProjectorTables& t) {
        std::size_t n = 0;
        for (std::uint32_t w : t.words)
            if (!(w & fx::kWordPlanar)) n += (w & ((1u << fx::kWordCountBits) - 1u)) + 1u;
        return n;
    };
    fx::GlProjector projector(mesh, "s", ramp());
    // A new mesh: the 48 folded hexahedra's and 14 folded wedges' rows, 32 bytes a triangle.
    const TableCounts counts = check_tables(projector);
    CHECK(counts.folded == 48 + 14);
    const std::size_t folded = folded_triangles(projector.read_tables());
    CHECK(folded == 48 * 12 + 14 * 8);
    CHECK(projector.memory().barycentric_rows == 32 * folded);
    // New scalars keep the layout; a new tolerance lays the rows out again.
    std::vector<float> values = mesh.scalars[0].values;
    for (float& v : values) v = 1.0f - v;
    projector.set_scalars(values);
    check_tables(projector);
    CHECK(projector.memory().barycentric_rows == 32 * folded);
    projector.set_planar_tolerance(1e-5); // the bent block's 36 fold too
    CHECK(check_tables(projector).folded == 48 + 14 + 36);
    CHECK(projector.memory().barycentric_rows == 32 * folded_triangles(projector.read_tables()));
    projector.set_planar_tolerance(fx::kPlanarTolerance);
    projector.set_scalars(mesh.scalars[0].values);

    // In place: the moved node folds 8 planar hexahedra, then unfolds them. The rows go by slot,
    // and the tables are a new mesh's (check_tables: the CPU's build from scratch).
    fx::MeshChanges changes;
    changes.clear(); // in place: only `moved` changed
    changes.points = {moved};
    CHECK(projector.update_mesh(bent, "s", changes));
    CHECK(check_tables(projector).folded == 48 + 14 + 8);
    CHECK(projector.memory().barycentric_rows >= 32 * projector.cell_first_triangle().back());
    {
        fx::GlProjector fresh(bent, "s", ramp());
        CHECK(fresh.read_tables().words == projector.read_tables().words);
    }
    CHECK(projector.update_mesh(original, "s", changes));
    CHECK(check_tables(projector).folded == 48 + 14);
    // A mesh taken whole afterwards keeps the layout by slot (the renderer takes updates).
    projector.set_mesh(bent, "s");
    CHECK(check_tables(projector).folded == 48 + 14 + 8);
    CHECK(projector.memory().barycentric_rows >= 32 * projector.cell_first_triangle().back());
}
