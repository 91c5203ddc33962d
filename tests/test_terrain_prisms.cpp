// Fog maps as prisms (Roettger & Ertl 2003 §5): valid wedges in VTK order, only non-zero
// thickness emitted, the column thickness integral against the analytic one (volume and, per
// pixel, through the scan-line reference), density set-ups, valley fog maps and the aurora.
#include <catch2/catch.hpp>

#include <cmath>
#include <set>

#include "fx/error.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/scanline_renderer.hpp"
#include "image_check.hpp"
#include "terrain/aurora.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain_test_support.hpp"
#include "cellfx_names.hpp"

namespace {

terrain::LodView close_view(glm::dvec3 eye, double pixel_error) {
    terrain::LodView v;
    v.eye = eye;
    v.projection_scale = 800.0;
    v.pixel_error = pixel_error;
    return v;
}

// Analytic fog thickness on [0, 640]²: positive, smooth, with closed-form integral.
double fog_thickness(double x, double y) { return 20.0 + 10.0 * std::sin(x / 50.0) * std::cos(y / 40.0); }
double fog_volume_exact(double L) {
    // ∫∫ 20 + 10 sin(x/50) cos(y/40) = 20 L² + 10 · 50(1 − cos(L/50)) · 40 sin(L/40)
    return 20.0 * L * L + 10.0 * 50.0 * (1.0 - std::cos(L / 50.0)) * 40.0 * std::sin(L / 40.0);
}

} // namespace

TEST_CASE("Prisms are valid VTK wedges sharing points, one per thick LOD triangle", "[terrain][prisms]") {
    const terrain::HeightField ground = terrain_test::hills(65);
    // Fog only on the western half, so some triangles have none and some a zero edge.
    const terrain::HeightField fog = terrain::make_height_field_like(
        ground, [](double x, double y) { return x < 320.0 ? 15.0 + 5.0 * std::sin(y / 30.0) : 0.0; });
    terrain::ContinuousLod lod(ground, fog);
    lod.update(close_view({300, 300, 80}, 1.0));
    const terrain::LodMesh mesh = lod.mesh();
    terrain::LayerPrismStats stats;
    const fx::CellMesh prisms = terrain::build_layer_prisms(mesh, {}, &stats);
    CHECK(stats.triangles == mesh.triangles.size());
    CHECK(stats.prisms + stats.empty == stats.triangles);
    CHECK(stats.prisms > 100);
    CHECK(stats.empty > 100);
    CHECK(prisms.cell_count() == stats.prisms);
    for (fx::CellType t : prisms.cell_types) CHECK(t == fx::CellType::Wedge);
    const std::vector<fx::MeshProblem> problems = fx::validate_mesh(prisms);
    for (std::size_t k = 0; k < std::min<std::size_t>(problems.size(), 5); ++k) INFO(problems[k].message);
    CHECK(problems.empty());
    // Points are shared: two per LOD vertex used, not six per prism.
    CHECK(prisms.point_count() < 3 * prisms.cell_count());
    // Every emitted prism has thickness; every skipped triangle has none.
    for (std::size_t c = 0; c < prisms.cell_count(); ++c) {
        const std::uint32_t* v = prisms.cell_vertices(c);
        double t = 0.0;
        for (int k = 0; k < 3; ++k) {
            CHECK(prisms.points[v[k + 3]].x == prisms.points[v[k]].x);
            CHECK(prisms.points[v[k + 3]].y == prisms.points[v[k]].y);
            t += prisms.points[v[k + 3]].z - prisms.points[v[k]].z;
        }
        CHECK(t > 0.0);
    }
    // Layer-height density: 0 at the ground, the thickness at the top.
    const std::vector<float>& d = prisms.find_scalar("density")->values;
    for (std::size_t p = 0; p + 1 < prisms.point_count(); p += 2) {
        CHECK(d[p] == 0.0f);
        CHECK(d[p + 1] == Approx(prisms.points[p + 1].z - prisms.points[p].z).margin(1e-3));
    }
}

TEST_CASE("Prism volume and columns integrate the analytic fog thickness", "[terrain][prisms]") {
    const double L = 640.0;
    const terrain::HeightField ground = terrain_test::hills(65);
    const terrain::HeightField fog = terrain::make_height_field_like(ground, fog_thickness);
    terrain::ContinuousLod lod(ground, fog);
    lod.update(close_view({320, 320, 10}, 1e-9)); // every sample: the piecewise-linear interpolant
    REQUIRE(lod.triangle_count() == lod.full_resolution_triangles());
    const terrain::LodMesh mesh = lod.mesh();
    const fx::CellMesh prisms = terrain::build_layer_prisms(mesh);
    REQUIRE(fx::validate_mesh(prisms).empty());

    // Volume: Σ prism volumes = ∫∫ of the linear interpolant of the thickness. Interpolation
    // error per triangle ≤ h²/8 · (|T_xx| + 2|T_xy| + |T_yy|) ≤ 100/8 · 10·(1/2500 + 2/2000 + 1/1600)
    // = 0.25 units of a thickness ~20, i.e. ≤ 1.3% pointwise and far less on average (the
    // errors of a sinusoid cancel): allow 0.5% of the volume.
    double volume = 0.0;
    for (std::size_t c = 0; c < prisms.cell_count(); ++c) volume += fx::cell_signed_volume(prisms, c);
    const double exact = fog_volume_exact(L);
    WARN("prism volume " << volume << ", analytic " << exact << " (relative error " << (volume - exact) / exact << ")");
    CHECK(std::abs(volume - exact) < 5e-3 * exact);

    // Columns: the scan-line reference, looking straight down with σ = 1 and colour 1 under the
    // emission model, gives ∫σ ds = the fog thickness of each pixel's column.
    fx::Camera top;
    top.eye = {L / 2, L / 2, 2000.0};
    top.target = {L / 2, L / 2, 0.0};
    top.up = {0, 1, 0};
    top.ortho_height = L;
    top.near_distance = 1.0;
    fx::ScanlineOptions options;
    options.model = fx::OpticalModel::Emission;
    const int n = 48;
    const fx::Image image = fx::ScanlineRenderer(prisms).render(top, n, n, *prisms.find_scalar("density"),
                                                                fx::TransferFunction::constant({1, 1, 1}, 1.0), options);
    fx::Image expected(n, n);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            const fx::Ray ray = top.pixel_ray(x + 0.5, y + 0.5, n, n);
            expected.at(x, y) = glm::vec4(glm::vec3(float(fog_thickness(ray.origin.x, ray.origin.y))), 0.0f);
        }
    }
    // The interpolation bound above (float rounding is ~1e-5 of this).
    verify::Options rgb;
    rgb.channels = 3;
    fx_test::check_image("prism_column_thickness", image, expected,
                         verify::same_picture(0.26, "the fog map interpolated linearly over each LOD triangle"), rgb);
}

TEST_CASE("Density set-ups: layer height, 2-D noise, lower border", "[terrain][prisms]") {
    const terrain::HeightField ground = terrain_test::hills(17);
    const terrain::HeightField fog = terrain::make_height_field_like(ground, [](double, double) { return 12.0; });
    terrain::ContinuousLod lod(ground, fog);
    lod.update(close_view({80, 80, 30}, 1e-9));
    const terrain::LodMesh mesh = lod.mesh();
    terrain::LayerPrismOptions noise;
    noise.density = terrain::LayerDensity::Noise;
    noise.density_scale = 2.0;
    noise.noise = [](double x, double y) { return std::sin(x / 20.0) * std::cos(y / 30.0); };
    const fx::CellMesh a = terrain::build_layer_prisms(mesh, noise);
    const std::vector<float>& da = a.scalars[0].values;
    for (std::size_t p = 0; p + 1 < a.point_count(); p += 2) {
        const double expected = 2.0 * std::max(0.0, std::sin(a.points[p].x / 20.0) * std::cos(a.points[p].y / 30.0));
        CHECK(da[p] == Approx(expected).margin(1e-6));
        CHECK(da[p + 1] == da[p]);
    }
    terrain::LayerPrismOptions border;
    border.density = terrain::LayerDensity::LowerBorder;
    border.scalar_name = "emission";
    CHECK_THROWS_WITH(terrain::build_layer_prisms(mesh, border), Catch::Contains("fade height"));
    border.fade_height = 40.0;
    const fx::CellMesh b = terrain::build_layer_prisms(mesh, border);
    REQUIRE(b.find_scalar("emission"));
    for (std::size_t p = 0; p + 1 < b.point_count(); p += 2) {
        // 1 at the bottom, falling by 1 per fade height: linear in height, whatever the column's.
        const double t = b.points[p + 1].z - b.points[p].z;
        CHECK(b.scalars[0].values[p] == 1.0f);
        CHECK(b.scalars[0].values[p + 1] == Approx(std::max(0.0, 1.0 - t / 40.0)).margin(1e-6));
    }
    terrain::LayerPrismOptions missing;
    missing.density = terrain::LayerDensity::Noise;
    CHECK_THROWS_WITH(terrain::build_layer_prisms(mesh, missing), Catch::Contains("noise generator"));
}

TEST_CASE("Valley fog maps fill the ground up to a level", "[terrain][prisms]") {
    const terrain::HeightField ground = terrain_test::hills(33);
    const terrain::HeightField fog = terrain::make_valley_fog_map(ground, 0.0, 25.0);
    std::size_t wet = 0, dry = 0;
    for (int j = 0; j < 33; ++j) {
        for (int i = 0; i < 33; ++i) {
            const double expected = std::clamp(0.0 - ground.at(i, j), 0.0, 25.0);
            CHECK(fog.at(i, j) == Approx(expected).margin(1e-5));
            (fog.at(i, j) > 0.0f ? wet : dry) += 1;
        }
    }
    CHECK(wet > 100);
    CHECK(dry > 100);
    const terrain::HeightField waves =
        terrain::make_valley_fog_map(ground, 0.0, 1e9, [](double x, double) { return x / 100.0; });
    CHECK(waves.at(20, 3) == Approx(std::max(0.0, 200.0 / 100.0 - ground.at(20, 3))).margin(1e-4));
    CHECK_THROWS_WITH(terrain::make_valley_fog_map(ground, 0.0, -1.0), Catch::Contains("max_thickness"));
}

TEST_CASE("Aurora curtains hang from the ceiling by the penetration depth", "[terrain][prisms][aurora]") {
    terrain::AuroraCurtains curtains;
    curtains.count = 2;
    curtains.max_depth = 800.0;
    curtains.width = 60.0;
    curtains.wander = 200.0;
    const terrain::HeightField depth = terrain::make_aurora_depth(65, 20.0, {-640.0, -640.0}, curtains);
    std::size_t empty = 0;
    for (float d : depth.heights) {
        CHECK(d >= 0.0f);
        CHECK(d <= 800.0f);
        empty += d == 0.0f;
    }
    CHECK(empty > depth.heights.size() / 3); // sky between the curtains makes no prisms
    const double ceiling = 9000.0;
    const terrain::AuroraLayer layer = terrain::make_aurora_layer(depth, ceiling);
    terrain::ContinuousLod lod(layer.lower_border, layer.depth);
    lod.update(close_view({0, -3000, 500}, 1.0));
    terrain::LayerPrismOptions options;
    options.density = terrain::LayerDensity::LowerBorder;
    options.fade_height = depth.max_height();
    terrain::LayerPrismStats stats;
    const fx::CellMesh prisms = terrain::build_layer_prisms(lod.mesh(), options, &stats);
    CHECK(stats.prisms > 50);
    CHECK(stats.empty > 50);
    CHECK(fx::validate_mesh(prisms).empty());
    for (std::size_t p = 1; p < prisms.point_count(); p += 2) CHECK(prisms.points[p].z == Approx(ceiling));
    CHECK_THROWS_WITH(terrain::make_aurora_layer(depth, NAN), Catch::Contains("ceiling"));
    terrain::AuroraCurtains bad;
    bad.count = 0;
    CHECK_THROWS_WITH(terrain::make_aurora_depth(65, 20.0, {0, 0}, bad), Catch::Contains("count"));
}

TEST_CASE("Relative valley fog collects in hollows at their own height", "[terrain][prisms]") {
    // Two bowls at very different heights: an absolute level fills one, a relative one both.
    const terrain::HeightField ground = terrain::make_height_field(65, 10.0, [](double x, double y) {
        const double a = (x - 160) * (x - 160) + (y - 320) * (y - 320), b = (x - 480) * (x - 480) + (y - 320) * (y - 320);
        return 500.0 - 60.0 * std::exp(-a / 8000.0) - 60.0 * std::exp(-b / 8000.0) + (x > 320 ? 300.0 : 0.0);
    });
    const terrain::HeightField absolute = terrain::make_valley_fog_map(ground, 470.0, 100.0);
    const terrain::HeightField relative = terrain::make_valley_fog_map(ground, -15.0, 100.0, {}, 150.0);
    CHECK(absolute.at(16, 32) > 10.0f);  // the low bowl's floor
    CHECK(absolute.at(48, 32) == 0.0f);  // the high bowl is above 470
    CHECK(relative.at(16, 32) > 10.0f);
    CHECK(relative.at(48, 32) > 10.0f);
    CHECK(relative.at(2, 2) == 0.0f);    // flat ground far from both stays clear
    CHECK_THROWS_WITH(terrain::make_valley_fog_map(ground, 0.0, 1.0, {}, -1.0), Catch::Contains("radius"));
}
