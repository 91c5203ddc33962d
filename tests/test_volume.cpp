// Generic volumes (fx/volume.hpp): box, sphere and mesh shapes as valid convex meshes, the
// density formulas (constant, noise, field, soft edge), work done only when needed, placement,
// bad parameters named; and their scene-file form (terrain/scene.hpp), inline transfer
// functions included.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/volume.hpp"
#include "terrain/scene.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using effects_test::look;

namespace {

fx::EffectView view_at(double time) { return fx::EffectView{look({4, -5, 2}, {0, 0, 0}), 96, 96, time}; }

void require_valid(const fx::CellMesh& mesh) {
    const std::vector<fx::MeshProblem> problems = fx::validate_mesh(mesh);
    INFO((problems.empty() ? std::string() : problems.front().message));
    REQUIRE(problems.empty()); // indices, finiteness, no zero-volume, inverted or twisted cells
    REQUIRE(mesh.cell_count() > 0);
    REQUIRE(mesh.scalars.size() == 1);
    REQUIRE(mesh.scalars[0].name == "density");
    REQUIRE(mesh.scalars[0].values.size() == mesh.point_count());
}

double mesh_volume(const fx::CellMesh& mesh) {
    double v = 0.0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) v += fx::cell_signed_volume(mesh, c);
    return v;
}

terrain::Scene parse(const std::string& effects) {
    return terrain::parse_scene(R"({"effects": [)" + effects +
                                    R"(], "camera": {"eye": [0, -5, 1], "target": [0, 0, 0], "near": 0.05, "far": 500}})",
                                "fx.json", fx_test::source_path("content/scenes"));
}

} // namespace

TEST_CASE("A constant box is one hexahedron of its size, a noise box a grid", "[volume]") {
    fx::VolumeParams p;
    p.size = {2.0, 1.0, 0.5};
    p.density = 0.7;
    fx::Volume box(p);
    const fx::EffectChanges first = box.update(view_at(0.0));
    CHECK(first.mesh);
    require_valid(box.mesh());
    CHECK(box.mesh().cell_count() == 1);
    CHECK(mesh_volume(box.mesh()) == Approx(1.0).epsilon(1e-12));
    for (float d : box.mesh().scalars[0].values) CHECK(d == Approx(0.7));
    CHECK(box.scalar_range().lo == 0.0f);
    CHECK(box.scalar_range().hi == Approx(0.7f));
    CHECK_FALSE(box.animated());
    CHECK_FALSE(box.update(view_at(1.0)).any()); // nothing moves, nothing changes

    p.density_mode = fx::VolumeDensity::Noise;
    p.cells = 8;
    fx::Volume noisy(p);
    noisy.update(view_at(0.0));
    require_valid(noisy.mesh());
    CHECK(noisy.mesh().cell_count() == 8 * 4 * 2); // 8 across the largest extent, in proportion
    CHECK(mesh_volume(noisy.mesh()) == Approx(1.0).epsilon(1e-9));
    // The documented formula at every point, within [0, density].
    const std::vector<float>& d = noisy.mesh().scalars[0].values;
    for (std::size_t i = 0; i < d.size(); ++i) {
        CHECK(d[i] >= 0.0f);
        CHECK(d[i] <= 0.7f + 1e-6f);
        CHECK(d[i] == Approx(noisy.density_at(noisy.mesh().points[i], 0.0)).margin(1e-5));
    }
}

TEST_CASE("Noise density moves with the wind and samples only when its time advances", "[volume]") {
    fx::VolumeParams p;
    p.density_mode = fx::VolumeDensity::Noise;
    p.cells = 6;
    fx::Volume still(p);
    still.update(view_at(0.0));
    const std::uint64_t once = still.counters().noise_samples;
    CHECK(once == still.mesh().point_count());
    CHECK_FALSE(still.animated());
    CHECK_FALSE(still.update(view_at(2.0)).any()); // no drift, no evolve: nothing to re-sample
    CHECK(still.counters().noise_samples == once);

    p.noise.drift = {0.5, 0.0, 0.0};
    fx::Volume windy(p);
    CHECK(windy.animated());
    windy.update(view_at(0.0));
    const std::vector<float> before = windy.mesh().scalars[0].values;
    const fx::EffectChanges c = windy.update(view_at(1.0));
    CHECK(c.scalars);
    CHECK_FALSE(c.mesh);
    CHECK(windy.counters().noise_samples == 2 * windy.mesh().point_count());
    CHECK(windy.mesh().scalars[0].values != before);
    // The field moved by the drift: the density at x, time 1 is the density at x − drift, time 0.
    CHECK(windy.density_at({0.3, 0.1, 0.2}, 1.0) == Approx(windy.density_at({-0.2, 0.1, 0.2}, 0.0)).margin(1e-6));
    CHECK_FALSE(windy.update(view_at(1.0)).any()); // same time: nothing
}

TEST_CASE("A sphere is convex cells inside its radius: tetrahedra at the centre, wedges outside", "[volume]") {
    fx::VolumeParams p;
    p.shape = fx::VolumeShape::Sphere;
    p.radius = 1.5;
    p.cells = 8; // level 2 icosphere (320 triangles), 4 shells
    fx::Volume sphere(p);
    sphere.update(view_at(0.0));
    const fx::CellMesh& m = sphere.mesh();
    require_valid(m);
    CHECK(m.cell_count() == 320 * 4);
    std::size_t tets = 0;
    for (fx::CellType t : m.cell_types) tets += t == fx::CellType::Tetra;
    CHECK(tets == 320);
    for (const glm::dvec3& q : m.points) CHECK(glm::length(q) <= 1.5 * (1.0 + 1e-12));
    // The inscribed polyhedron of 320 faces holds about 97% of the ball's volume.
    const double ball = 4.0 / 3.0 * M_PI * 1.5 * 1.5 * 1.5;
    CHECK(mesh_volume(m) < ball);
    CHECK(mesh_volume(m) > 0.95 * ball);

    // A soft rim: full density at the centre, 0 on the surface.
    p.edge_fade = 0.5;
    fx::Volume soft(p);
    soft.update(view_at(0.0));
    CHECK(soft.density_at({0, 0, 0}, 0.0) == Approx(1.0));
    CHECK(soft.density_at({0, 0, 1.5}, 0.0) == Approx(0.0).margin(1e-12));
    CHECK(soft.density_at({0, 0, 1.125}, 0.0) == Approx(0.5)); // half way through the fade
}

TEST_CASE("A mesh volume carries the mesh's field, scaled, and moves without rebuilding", "[volume]") {
    auto mesh = std::make_shared<const fx::CellMesh>(fx::read_mesh(fx_test::source_path("content/meshes/vtk_cells/tetraMesh.vtk")));
    REQUIRE(!mesh->scalars.empty());
    fx::VolumeParams p;
    p.shape = fx::VolumeShape::Mesh;
    p.mesh = mesh;
    p.density_mode = fx::VolumeDensity::Field;
    p.density = 2.0;
    fx::Volume v(p);
    v.update(view_at(0.0));
    require_valid(v.mesh());
    CHECK(v.mesh().cell_count() == mesh->cell_count());
    for (std::size_t i = 0; i < mesh->point_count(); ++i) CHECK(v.mesh().scalars[0].values[i] == Approx(2.0 * mesh->scalars[0].values[i]));
    const fx::ScalarRange field = fx::scalar_range(mesh->scalars[0]);
    CHECK(v.scalar_range().hi == Approx(2.0f * field.hi));

    p.position = {10.0, 0.0, 0.0};
    p.rotation_degrees = {0.0, 0.0, 90.0};
    v.set_params(p);
    const fx::EffectChanges moved = v.update(view_at(0.0));
    CHECK(moved.pose); // moved and turned: nothing rebuilt, nothing re-evaluated
    CHECK_FALSE(moved.mesh);
    CHECK_FALSE(moved.scalars);
    const glm::dvec3 x = glm::dvec3(v.transform() * glm::dvec4(1.0, 0.0, 0.0, 1.0));
    CHECK(x.x == Approx(10.0));
    CHECK(x.y == Approx(1.0)); // +x turned to +y
}

TEST_CASE("Bad volume parameters name the parameter", "[volume]") {
    fx::VolumeParams p;
    p.size = {1.0, 0.0, 1.0};
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("volume: size"));
    p = {};
    p.density = -1.0;
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("volume: density"));
    p = {};
    p.density_mode = fx::VolumeDensity::Field;
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("needs a mesh shape"));
    p = {};
    p.shape = fx::VolumeShape::Mesh;
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("volume: mesh has no cells"));
    p.mesh = std::make_shared<const fx::CellMesh>(fx::read_mesh(fx_test::source_path("content/meshes/vtk_cells/tetraMesh.vtk")));
    p.density_mode = fx::VolumeDensity::Field;
    p.field = "nope";
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("'nope' is not a field of the mesh"));
    p = {};
    p.noise.coverage = 2.0;
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("noise.coverage"));
    p = {};
    p.edge_fade = 1.5;
    CHECK_THROWS_WITH(fx::Volume(p), Catch::Contains("edge_fade"));
}

TEST_CASE("Scene files declare volumes, with transfer functions inline or by file", "[volume][scene]") {
    const terrain::Scene s = parse(R"(
        {"type": "volume", "name": "mist", "shape": "box", "size": [4, 2, 1], "position": [1, 2, 3],
         "transfer_function": {"points": [[0, 0.5, 0.6, 0.7, 0.4], [1, 0.5, 0.6, 0.7, 0.4]]}, "extinction_scale": 2},
        {"type": "volume", "name": "smoke", "shape": "sphere", "radius": 2, "albedo": 0.3, "absorb": true,
         "noise": {"frequency": 1.5, "drift": [0, 0, 0.4], "evolve": 0.2}, "edge_fade": 0.4,
         "transfer_function": "../transfer_functions/fog.json"},
        {"type": "volume", "name": "field", "shape": "mesh", "mesh": "../meshes/vtk_cells/tetraMesh.vtk",
         "transfer_function": "../transfer_functions/cool_warm.json", "absorb": false}
    )");
    REQUIRE(s.effects.size() == 3);
    const auto& mist = std::get<fx::VolumeParams>(s.effects[0].params);
    CHECK(mist.shape == fx::VolumeShape::Box);
    CHECK(mist.size == glm::dvec3(4, 2, 1));
    CHECK(mist.density_mode == fx::VolumeDensity::Constant);
    CHECK(s.effects[0].absorb); // volumes absorb unless told otherwise
    CHECK(s.effects[0].albedo == 0.9);
    CHECK(s.effects[0].transfer_function.points()[1].sigma == Approx(0.4)); // inline, as written
    CHECK(s.effects[0].extinction_scale == 2.0);
    const auto& smoke = std::get<fx::VolumeParams>(s.effects[1].params);
    CHECK(smoke.shape == fx::VolumeShape::Sphere);
    CHECK(smoke.density_mode == fx::VolumeDensity::Noise); // a "noise" object makes it noise
    CHECK(smoke.noise.drift == glm::dvec3(0, 0, 0.4));
    CHECK(s.effects[1].albedo == 0.3);
    const auto& field = std::get<fx::VolumeParams>(s.effects[2].params);
    CHECK(field.density_mode == fx::VolumeDensity::Field); // a mesh carries its field
    REQUIRE(field.mesh);
    CHECK(field.mesh->cell_count() == 160);
    CHECK_FALSE(s.effects[2].absorb);
    CHECK(std::string(terrain::effect_type_name(s.effects[2].params)) == "volume");

    CHECK_THROWS_WITH(parse(R"({"type": "volume", "shape": "cone", "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0].shape: unknown shape 'cone' (expected box, sphere, mesh)"));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "size": [1, -1, 1], "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0].size: must be three positive extents"));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "transfer_function": {"points": [[0, 1, 1, 1, -1]]}})"),
                      Catch::Contains("fx.json: effects[0].transfer_function: points[0]: sigma is negative"));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "shape": "mesh", "mesh": "nowhere.vtk", "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0].mesh: "));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "density_mode": "field", "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0]: volume: density \"field\" needs a mesh shape"));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "noise": {"octaves": 12}, "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0].noise.octaves: must be in 1..8"));
    CHECK_THROWS_WITH(parse(R"({"type": "volume", "light": {}, "transfer_function": "../transfer_functions/fog.json"})"),
                      Catch::Contains("fx.json: effects[0].light: a volume sheds no light"));
    CHECK_THROWS_WITH(parse(R"({"type": "campfire", "light": {"g": 1.5}, "transfer_function": "../transfer_functions/fire.json"})"),
                      Catch::Contains("fx.json: effects[0].light.g: must be in [-0.99, 0.99]"));
}
