// The effects (fx/effect.hpp, campfire.hpp, search_light.hpp, laser_cone.hpp; terrain's ground
// fog and aurora in layer_effects.hpp): valid convex meshes, the documented scalar formulas,
// work done only when needed (counted on the effect), placement, and frames of each effect
// against the scan-line reference.
#include <catch2/catch.hpp>

#include <set>

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/campfire.hpp"
#include "fx/effect.hpp"
#include "fx/error.hpp"
#include "fx/laser_cone.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/search_light.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/layer_effects.hpp"
#include "terrain_test_support.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using effects_test::look;

namespace {

fx::EffectView view_at(double time, const fx::Camera& cam = look({3, -4, 2}, {0, 0, 0.6})) {
    return fx::EffectView{cam, 96, 96, time};
}

void require_valid(const fx::CellMesh& mesh) {
    const std::vector<fx::MeshProblem> problems = fx::validate_mesh(mesh);
    INFO((problems.empty() ? std::string() : problems.front().message));
    REQUIRE(problems.empty()); // indices, finiteness, no zero-volume, inverted or twisted cells
    REQUIRE(mesh.cell_count() > 0);
    REQUIRE(mesh.scalars.size() == 1);
    REQUIRE(mesh.scalars[0].values.size() == mesh.point_count());
}

bool inside(const fx::Bounds& b, const glm::dvec3& p, double eps = 1e-9) {
    return glm::all(glm::greaterThanEqual(p, b.lo - eps)) && glm::all(glm::lessThanEqual(p, b.hi + eps));
}

fx::TransferFunction fire_tf(double extinction) {
    const fx::TransferFunction tf = fx::TransferFunction::read_json(fx_test::source_path("content/transfer_functions/fire.json"));
    std::vector<fx::TransferPoint> points = tf.points();
    for (fx::TransferPoint& p : points) p.sigma *= extinction;
    return fx::TransferFunction(points, true).rescaled(0.0, 1.0);
}

fx::TransferFunction beam_tf(double sigma, double hi) {
    return fx::TransferFunction({{0.0, {0.75, 0.85, 1.0}, 0.0}, {1.0, {1.0, 0.97, 0.9}, sigma}}, true).rescaled(0.0, hi);
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Placement helpers

TEST_CASE("rigid_part keeps rotation and translation, and rejects what is not a motion", "[effects]") {
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(5, -2, 7));
    m = glm::rotate(m, 0.7, glm::normalize(glm::dvec3(1, 2, 3)));
    const glm::dmat4 scaled = glm::scale(m, glm::dvec3(2.0, 3.0, 0.5));
    const glm::dmat4 r = fx::rigid_part(scaled, "test");
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) CHECK(r[c][k] == Approx(m[c][k]).margin(1e-12)); // the scale is removed
    CHECK_THROWS_WITH(fx::rigid_part(glm::scale(glm::dmat4(1.0), glm::dvec3(1, 1, -1)), "parent"),
                      Catch::Contains("parent: mirrors"));
    CHECK_THROWS_WITH(fx::rigid_part(glm::scale(glm::dmat4(1.0), glm::dvec3(1, 0, 1)), "parent"),
                      Catch::Contains("parent: singular"));
    glm::dmat4 projective(1.0);
    projective[2][3] = -1.0;
    CHECK_THROWS_WITH(fx::rigid_part(projective, "parent"), Catch::Contains("bottom row"));
    glm::dmat4 nan(1.0);
    nan[3][0] = NAN;
    CHECK_THROWS_WITH(fx::rigid_part(nan, "parent"), Catch::Contains("not finite"));
}

TEST_CASE("camera_in_frame sees a local mesh as the camera sees it moved into the world", "[effects]") {
    const glm::dmat4 m = fx::frame_along({300.0, -120.0, 45.0}, {0.3, -0.8, 0.5});
    const fx::Camera world = look({310, -140, 60}, {300, -120, 45}, 50.0);
    const fx::Camera local = fx::camera_in_frame(world, m);
    for (int k = 0; k < 20; ++k) {
        const double x = 3.0 + 9.0 * k, y = 90.0 - 4.0 * k;
        const fx::Ray a = world.pixel_ray(x, y, 100, 100), b = local.pixel_ray(x, y, 100, 100);
        const glm::dvec3 origin(m * glm::dvec4(b.origin, 1.0)), direction(m * glm::dvec4(b.direction, 0.0));
        CHECK(glm::length(origin - a.origin) < 1e-9);
        CHECK(glm::length(direction - a.direction) < 1e-12);
    }
    // Depth along the view (what a scene depth buffer holds) is unchanged.
    const glm::dvec3 p(302, -119, 44);
    const glm::dvec3 q(glm::inverse(m) * glm::dvec4(p, 1.0));
    CHECK(glm::dot(p - world.eye, world.forward()) == Approx(glm::dot(q - local.eye, local.forward())));
}

TEST_CASE("bounds_in_view: the frustum test", "[effects]") {
    const fx::Camera cam = look({0, -10, 0}, {0, 0, 0}, 40.0);
    auto box = [](glm::dvec3 c, double r) { return fx::Bounds{c - r, c + r}; };
    CHECK(fx::bounds_in_view(box({0, 0, 0}, 1), cam, 1.0));
    CHECK(fx::bounds_in_view(box({0, -10, 0}, 0.5), cam, 1.0));    // around the eye
    CHECK_FALSE(fx::bounds_in_view(box({0, -20, 0}, 1), cam, 1.0)); // behind
    CHECK_FALSE(fx::bounds_in_view(box({30, 0, 0}, 1), cam, 1.0));  // far to the side
    CHECK(fx::bounds_in_view(box({30, 0, 0}, 1), cam, 20.0));       // ... inside a very wide view
    CHECK_FALSE(fx::bounds_in_view(box({0, 6000, 0}, 1), cam, 1.0)); // beyond the far plane
    CHECK_FALSE(fx::bounds_in_view(fx::Bounds{glm::dvec3(1.0), glm::dvec3(-1.0)}, cam, 1.0)); // empty
}

// ---------------------------------------------------------------------------------------------
// Campfire

TEST_CASE("Campfire: a valid hexahedral grid without the cells outside the envelope", "[effects][campfire]") {
    fx::Campfire fire;
    const fx::EffectChanges c = fire.update(view_at(0.0));
    CHECK(c.mesh);
    CHECK(c.pose);
    require_valid(fire.mesh());
    for (fx::CellType t : fire.mesh().cell_types) CHECK(t == fx::CellType::Hexahedron);
    const fx::CampfireParams& p = fire.params();
    const std::size_t full = std::size_t(p.cells_across) * p.cells_across * p.cells_up;
    CHECK(fire.mesh().cell_count() < full * 3 / 4); // the envelope's outside is never built
    CHECK(fire.active_nodes() > 0);
    CHECK(fire.active_nodes() < fire.mesh().point_count());
    // The scalars are the documented formula (the batch noise equals the single-sample noise).
    const fx::ScalarField& t = fire.mesh().scalars[0];
    std::size_t hot = 0;
    for (std::size_t i = 0; i < fire.mesh().point_count(); ++i) {
        CHECK(t.values[i] == float(fire.temperature_at(fire.mesh().points[i], 0.0)));
        CHECK(t.values[i] >= 0.0f);
        CHECK(t.values[i] <= 1.0f);
        if (t.values[i] > 0.5f) ++hot;
    }
    CHECK(hot > 20);
    // Bounds hold every point.
    const fx::Bounds b = fire.world_bounds(0.0);
    for (const glm::dvec3& q : fire.mesh().points) CHECK(inside(b, q));
}

TEST_CASE("Campfire: noise is sampled only when time advanced, only at its own grid's active nodes", "[effects][campfire]") {
    fx::Campfire fire;
    fire.update(view_at(0.0));
    const std::size_t active = fire.active_nodes();
    CHECK(fire.counters().noise_samples == active);
    CHECK(fire.counters().mesh_builds == 1);
    // Same time (another camera): nothing at all.
    const fx::EffectChanges same = fire.update(view_at(0.0, look({-3, 4, 1}, {0, 0, 0.5})));
    CHECK_FALSE(same.any());
    CHECK(fire.counters().noise_samples == active);
    // Time advanced: one batch of samples, scalars only.
    const std::vector<float> before = fire.mesh().scalars[0].values;
    const fx::EffectChanges later = fire.update(view_at(0.25));
    CHECK(later.scalars);
    CHECK_FALSE(later.mesh);
    CHECK_FALSE(later.pose);
    CHECK(fire.counters().noise_samples == 2 * active);
    CHECK(fire.counters().mesh_builds == 1);
    CHECK(fire.counters().scalar_updates == 1);
    CHECK(fire.mesh().scalars[0].values != before); // it flickers
    for (std::size_t i = 0; i < fire.mesh().point_count(); i += 37)
        CHECK(fire.mesh().scalars[0].values[i] == float(fire.temperature_at(fire.mesh().points[i], 0.25)));

    // A still fire (no rise, no flicker) samples once, whatever the time.
    fx::CampfireParams still;
    still.rise_speed = 0.0;
    still.flicker_rate = 0.0;
    fx::Campfire frozen(still);
    CHECK_FALSE(frozen.animated());
    for (double t : {0.0, 1.0, 2.0, 3.5}) frozen.update(view_at(t));
    CHECK(frozen.counters().noise_samples == frozen.active_nodes());
    CHECK(frozen.counters().scalar_updates == 0);
}

TEST_CASE("Campfire: parameter changes rebuild only what they change, and bad ones are named", "[effects][campfire]") {
    fx::Campfire fire;
    fire.update(view_at(0.0));
    fx::CampfireParams p = fire.params();
    p.intensity = 1.0;
    fire.set_params(p);
    fx::EffectChanges c = fire.update(view_at(0.0));
    CHECK(c.scalars);
    CHECK_FALSE(c.mesh);
    CHECK(fire.counters().mesh_builds == 1);
    p.position = {4.0, 1.0, 0.0}; // moves: nothing rebuilt
    fire.set_params(p);
    c = fire.update(view_at(0.0));
    CHECK(c.pose);
    CHECK(fire.counters().mesh_builds == 1);
    p.cells_up = 12; // a new grid
    fire.set_params(p);
    c = fire.update(view_at(0.0));
    CHECK(c.mesh);
    CHECK(fire.counters().mesh_builds == 2);
    require_valid(fire.mesh());

    p = fx::CampfireParams{};
    p.base_radius = 0.0;
    CHECK_THROWS_WITH(fx::Campfire(p), Catch::Contains("campfire: base_radius must be positive"));
    p = fx::CampfireParams{};
    p.cells_across = 1;
    CHECK_THROWS_WITH(fx::Campfire(p), Catch::Contains("cells_across"));
    p = fx::CampfireParams{};
    p.rise_speed = INFINITY;
    CHECK_THROWS_WITH(fire.set_params(p), Catch::Contains("rise_speed"));
    CHECK(fire.params().cells_up == 12); // kept
    CHECK_THROWS_WITH(fire.update(view_at(NAN)), Catch::Contains("time is not finite"));
}

// ---------------------------------------------------------------------------------------------
// Search light and laser cone

TEST_CASE("SearchLight: a cone of convex cells with quadratic falloff along and across", "[effects][search_light]") {
    for (int rings : {1, 4}) {
        fx::SearchLightParams p;
        p.rings = rings;
        fx::SearchLight light(p);
        light.update(view_at(0.0));
        require_valid(light.mesh());
        CHECK(light.mesh().cell_count() == std::size_t(p.segments * p.rings * p.slices));
        const fx::ScalarField& s = light.mesh().scalars[0];
        const double tan_spread = std::tan(p.spread_degrees * 0.017453292519943295);
        for (std::size_t i = 0; i < light.mesh().point_count(); ++i) {
            const glm::dvec3 q = light.mesh().points[i];
            const double u = q.z / p.range, rho = std::hypot(q.x, q.y), radius = p.lens_radius + q.z * tan_spread;
            const double v = rho / radius;
            REQUIRE(v <= 1.0 + 1e-9); // every node inside the cone
            CHECK(s.values[i] == Approx(p.intensity * (1 - u) * (1 - u) * (1 - v * v)).margin(1e-6));
        }
        CHECK(s.values[0] == Approx(p.intensity)); // on the axis at the lens
    }
}

TEST_CASE("SearchLight: moving, turning, sweeping and riding a parent rebuild nothing", "[effects][search_light]") {
    fx::SearchLightParams p;
    p.position = {0, 0, 3};
    p.direction = {1, 0, 0.2};
    fx::SearchLight light(p);
    light.update(view_at(0.0));
    const std::vector<glm::dvec3> points = light.mesh().points;
    CHECK(light.counters().mesh_builds == 1);
    // Nothing changed: no change at all.
    CHECK_FALSE(light.update(view_at(1.0)).any());
    // Pose, parent and sweep changes are pose changes only.
    light.set_pose({1, 2, 3}, {0, 1, 0});
    fx::EffectChanges c = light.update(view_at(1.0));
    CHECK(c.pose);
    CHECK_FALSE((c.mesh || c.scalars));
    const glm::dmat4 truck = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(100, 50, 0)), 0.5, glm::dvec3(0, 0, 1));
    light.set_parent_transform(truck);
    c = light.update(view_at(1.0));
    CHECK(c.pose);
    CHECK_FALSE((c.mesh || c.scalars));
    // transform() = parent · frame_along(position, direction).
    const glm::dmat4 expect = truck * fx::frame_along({1, 2, 3}, {0, 1, 0});
    for (int col = 0; col < 4; ++col)
        for (int k = 0; k < 4; ++k) CHECK(light.transform()[col][k] == Approx(expect[col][k]).margin(1e-12));
    p = light.params();
    p.sweep.amplitude_degrees = 30.0;
    p.sweep.period = 4.0;
    light.set_params(p);
    CHECK(light.animated());
    for (double t : {1.5, 2.0, 2.5}) {
        c = light.update(view_at(t));
        CHECK(c.pose);
        CHECK_FALSE((c.mesh || c.scalars));
    }
    // The sweep turns the beam about its axis by amplitude·sin(2πt/period).
    const glm::dvec3 d0 = light.direction_at(0.0), d1 = light.direction_at(1.0); // 0 and the full amplitude
    CHECK(std::acos(glm::dot(d0, d1)) == Approx(30.0 * 0.017453292519943295));
    CHECK(light.counters().mesh_builds == 1);
    CHECK(light.mesh().points == points); // the mesh itself never moved
    // Intensity re-evaluates the scalars, the spread rebuilds.
    p.intensity = 2.0;
    light.set_params(p);
    c = light.update(view_at(2.5));
    CHECK(c.scalars);
    CHECK_FALSE(c.mesh);
    p.spread_degrees = 10.0;
    light.set_params(p);
    CHECK(light.update(view_at(2.5)).mesh);
    CHECK(light.counters().mesh_builds == 2);
    // World bounds hold the moved mesh.
    const fx::Bounds b = light.world_bounds(2.5);
    for (const glm::dvec3& q : effects_test::world_mesh(light).points) CHECK(inside(b, q, 1e-6));
    p.direction = {0, 0, 0};
    CHECK_THROWS_WITH(light.set_params(p), Catch::Contains("search_light: direction"));
    CHECK_THROWS_WITH(light.set_parent_transform(glm::scale(glm::dmat4(1.0), glm::dvec3(-1, 1, 1))),
                      Catch::Contains("mirrors"));
}

TEST_CASE("LaserCone: dust is sampled at build and then only when it drifts", "[effects][laser]") {
    fx::LaserConeParams p;
    fx::LaserCone clean(p);
    clean.update(view_at(0.0));
    require_valid(clean.mesh());
    for (fx::CellType t : clean.mesh().cell_types) CHECK(t == fx::CellType::Wedge);
    CHECK_FALSE(clean.animated());
    clean.update(view_at(1.0));
    CHECK(clean.counters().noise_samples == 0);
    // Profile: full on the axis, 0 at the rim, fading over the last end_fade of the range.
    const fx::ScalarField& s = clean.mesh().scalars[0];
    for (std::size_t i = 0; i < clean.mesh().point_count(); ++i) {
        const glm::dvec3 q = clean.mesh().points[i];
        const double u = q.z / p.range;
        const double fade = std::min(1.0, (1.0 - u) / p.end_fade);
        const double v = std::hypot(q.x, q.y) / (p.radius + q.z * std::tan(p.divergence_degrees * 0.017453292519943295));
        CHECK(s.values[i] == Approx(p.intensity * (1 - v * v) * fade).margin(1e-5));
    }

    p.dust_amount = 0.8;
    fx::LaserCone still_dust(p);
    for (double t : {0.0, 1.0, 2.0}) still_dust.update(view_at(t));
    CHECK(still_dust.counters().noise_samples == still_dust.mesh().point_count()); // once

    p.dust_drift = {0.0, 0.0, 1.5};
    fx::LaserCone drifting(p);
    CHECK(drifting.animated());
    drifting.update(view_at(0.0));
    drifting.update(view_at(0.0));
    CHECK(drifting.counters().noise_samples == drifting.mesh().point_count());
    const std::vector<float> before = drifting.mesh().scalars[0].values;
    const fx::EffectChanges c = drifting.update(view_at(0.5));
    CHECK(c.scalars);
    CHECK_FALSE(c.mesh);
    CHECK(drifting.counters().noise_samples == 2 * drifting.mesh().point_count());
    CHECK(drifting.mesh().scalars[0].values != before);
    for (float v : drifting.mesh().scalars[0].values) {
        CHECK(v >= 0.0f);
        CHECK(v <= float(p.intensity));
    }
}

// ---------------------------------------------------------------------------------------------
// Ground fog and aurora as effects

TEST_CASE("GroundFog: prisms follow the shared LOD, only what it changed rewritten and listed", "[effects][terrain]") {
    const terrain::HeightField ground = terrain_test::hills(65, 10.0);
    const terrain::HeightField fog_map = terrain::make_valley_fog_map(ground, 0.0, 40.0, {}, 120.0);
    auto lod = std::make_shared<terrain::TerrainLod>(ground, fog_map);
    terrain::LayerPrismOptions prisms;
    terrain::GroundFog fog(lod, fog_map, prisms);
    const fx::Camera cam = look({320, -150, 180}, {320, 320, 0}, 50.0);
    CHECK(fog.update(view_at(0.0, cam)).mesh);
    require_valid(fog.mesh());
    CHECK(fog.counters().mesh_builds == 1);
    CHECK(fog.mesh_changes().whole); // the first mesh is new
    fog.clear_mesh_changes();
    // The prisms of the fog are build_layer_prisms' of the extracted LOD (as sets: the order
    // and the point numbering differ), but those thinner than a millionth of the field's size
    // whose edges alone changed (LayerPrismTracker); every one of them, not just those in view.
    auto key = [](const fx::CellMesh& m, std::size_t c) {
        std::vector<double> k;
        for (int v = 0; v < 6; ++v) {
            const glm::dvec3& q = m.points[m.cell_vertices(c)[v]];
            k.insert(k.end(), {q.x, q.y, q.z});
        }
        return k;
    };
    const double thin = 1e-6 * 2.0 * 640.0 * std::sqrt(2.0) * 2.0; // above the LOD's thin-layer bound
    auto thick = [&](const std::vector<double>& k) {
        return std::max({k[11] - k[2], k[14] - k[5], k[17] - k[8]}) > thin;
    };
    auto same_prisms = [&] {
        std::set<std::vector<double>> built, all;
        for (std::size_t c = 0; c < fog.mesh().cell_count(); ++c)
            if (const auto k = key(fog.mesh(), c); thick(k)) built.insert(k);
        const fx::CellMesh full = terrain::build_layer_prisms(lod->mesh(), prisms);
        for (std::size_t c = 0; c < full.cell_count(); ++c)
            if (const auto k = key(full, c); thick(k)) all.insert(k);
        CHECK(all.size() > 100);
        CHECK(built == all);
    };
    same_prisms();
    CHECK(fog.prism_stats().culled == 0);
    // The same view again, and a camera that only turns: the LOD does not refine, nothing is
    // rebuilt or listed.
    CHECK_FALSE(fog.update(view_at(0.05, cam)).any());
    fx::Camera turned = cam;
    turned.target = {200, 300, 10};
    CHECK_FALSE(fog.update(view_at(0.1, turned)).any());
    CHECK(fog.counters().mesh_builds == 1);
    CHECK(fog.mesh_changes().cells.empty());
    CHECK(fog.mesh_changes().points.empty());
    // The eye moves: the LOD refines and the prisms follow, rewriting (and listing) only what
    // changed.
    const std::uint64_t cells_before = fog.counters().cells_built;
    fx::Camera moved = cam;
    moved.eye = {330, -130, 175};
    CHECK(fog.update(view_at(0.2, moved)).mesh);
    CHECK(fog.counters().mesh_builds == 2);
    CHECK_FALSE(fog.mesh_changes().whole);
    CHECK(fog.mesh_changes().oriented);
    CHECK(fog.mesh_changes().points.size() + fog.mesh_changes().cells.size() > 0);
    CHECK(fog.mesh_changes().cells.size() < fog.mesh().cell_count() / 2);
    CHECK(fog.counters().cells_built - cells_before == fog.mesh_changes().cells.size());
    for (std::uint32_t c : fog.mesh_changes().cells) CHECK(c < fog.mesh().cell_count());
    for (std::uint32_t p : fog.mesh_changes().points) CHECK(p < fog.mesh().point_count());
    same_prisms();
    require_valid(fog.mesh());
    // A flight on, each step listing its own changes: still the same prisms.
    for (int k = 1; k <= 6; ++k) {
        fog.clear_mesh_changes();
        moved.eye += glm::dvec3(15.0, 40.0, -10.0);
        fog.update(view_at(0.2 + 0.1 * k, moved));
    }
    same_prisms();
    // The range covers every density the prisms carry; the bounds every point.
    const fx::ScalarRange r = fog.scalar_range();
    for (float v : fog.mesh().scalars[0].values) CHECK(v <= r.hi);
    const fx::Bounds b = fog.world_bounds(0.0);
    for (const glm::dvec3& q : fog.mesh().points) CHECK(inside(b, q, 1e-3));
    CHECK(fog.counters().noise_samples == 0); // layer-height density uses no noise
}

// ---------------------------------------------------------------------------------------------
// Frames against the scan-line reference (tolerances: tests/test_effects_support.hpp)

TEST_CASE("Campfire frames match the scan-line reference", "[gl][effects][campfire]") {
    fx::CampfireParams p;
    p.position = {2.0, -1.0, 0.5};
    fx::Campfire fire(p);
    const fx::Camera cam = look({3.9, -3.2, 1.6}, {2.0, -1.0, 1.1}, 45.0);
    fire.update(view_at(0.7, cam));
    // extinction 0.04: the brightest ray stays below 1 in classic pcp's 8-bit target. A ray
    // crosses up to ~20 cells of the grid.
    const fx::TransferFunction tf = fire_tf(0.04);
    for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Pcp})
        effects_test::effect_vs_scanline("effect_campfire", fire, tf, cam, path, 20);
    // Sorted emission–absorption, the fire dense enough to dim its own far side (the core's
    // optical depth ~1). Both with their stated tolerances (testing/verify/tolerances.cpp). The
    // noise makes the temperature cross up to four of fire.json's breakpoints inside one cell, σ
    // rising ×1.5 to ×5 from one to the next; classic absorption slices cells at breakpoints (§V)
    // but its per-vertex colour and α (§II) are linear across each slice, so where the exact
    // picture bends that steeply within a pixel's neighbourhood (measured: 1.6% of the pixels,
    // worst 13.7% of peak) a pixel is bounded by the reference's values around it, not by the 4%;
    // away from such bends none lies beyond 4% (1% allowed).
    const fx::TransferFunction dense = fire_tf(0.15);
    effects_test::effect_vs_scanline("effect_campfire", fire, dense, cam, fx::RenderPath::AbsorptionExact, 20);
    effects_test::effect_vs_scanline("effect_campfire", fire, dense, cam, fx::RenderPath::Absorption, 20);
}

TEST_CASE("Search light frames match the scan-line reference, far from the origin and turned", "[gl][effects][search_light]") {
    fx::SearchLightParams p;
    p.position = {5000.0, -3000.0, 40.0};
    p.direction = {0.4, 0.5, 0.6};
    p.range = 30.0;
    p.spread_degrees = 8.0;
    p.lens_radius = 0.5;
    fx::SearchLight light(p);
    const fx::Camera cam = look({5010.0, -3030.0, 52.0}, {5006.0, -2992.0, 52.0}, 45.0);
    light.update(view_at(0.0, cam));
    REQUIRE(light.transform()[3][0] == 5000.0); // the mesh stays local, the camera moves
    // Beam rays cross up to ~8 cells; σ small enough for 8-bit pcp.
    for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Pcp,
                                fx::RenderPath::AbsorptionExact, fx::RenderPath::Absorption})
        effects_test::effect_vs_scanline("effect_search_light", light, beam_tf(0.08, 1.0), cam, path, 8);
}

TEST_CASE("Laser cone frames (with dust) match the scan-line reference", "[gl][effects][laser]") {
    fx::LaserConeParams p;
    p.position = {0, 0, 1};
    p.direction = {0.2, 1, 0.05};
    p.range = 40.0;
    p.radius = 0.3;
    p.divergence_degrees = 1.0;
    p.dust_amount = 0.7;
    p.dust_drift = {0, 0, 1};
    fx::LaserCone laser(p);
    const fx::Camera cam = look({-4, -3, 2}, {3, 15, 1.5}, 50.0);
    laser.update(view_at(1.3, cam));
    for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Pcp})
        effects_test::effect_vs_scanline("effect_laser", laser, beam_tf(0.25, 1.0), cam, path, 4);
}

TEST_CASE("Ground fog and aurora effects' frames match the scan-line reference", "[gl][effects][terrain]") {
    const terrain::HeightField ground = terrain_test::hills(65, 10.0);
    const terrain::HeightField fog_map = terrain::make_valley_fog_map(ground, 0.0, 40.0, {}, 120.0);
    auto lod = std::make_shared<terrain::TerrainLod>(ground, fog_map);
    terrain::GroundFog fog(lod, fog_map, {});
    const fx::Camera cam = look({320, -250, 260}, {320, 320, 0}, 45.0);
    fog.update(view_at(0.0, cam));
    // One colour (white), σ rising with the layer height: fog = true is exact absorption. Rays
    // cross up to ~30 prisms at this slant.
    const fx::TransferFunction fog_tf =
        fx::TransferFunction({{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 0.02}}, true).rescaled(0.0, fog.scalar_range().hi);
    effects_test::effect_vs_scanline("effect_ground_fog", fog, fog_tf, cam, fx::RenderPath::PcpExact, 30, true);
    effects_test::effect_vs_scanline("effect_ground_fog", fog, fog_tf, cam, fx::RenderPath::Mip, 30);

    terrain::AuroraCurtains curtains;
    curtains.max_depth = 300.0;
    curtains.width = 30.0;
    curtains.wander = 80.0;
    const terrain::HeightField depth = terrain::make_aurora_depth(65, 10.0, {0.0, 0.0}, curtains);
    terrain::Aurora aurora(terrain::make_aurora_layer(depth, 1200.0));
    const fx::Camera sky = look({320, -500, 300}, {320, 320, 1000}, 50.0);
    aurora.update(view_at(0.0, sky));
    require_valid(aurora.mesh());
    const fx::TransferFunction glow =
        fx::TransferFunction({{0.0, {0.6, 0.1, 0.2}, 0.0}, {1.0, {0.3, 1.0, 0.5}, 0.002}}, true).rescaled(0.0, 1.0);
    effects_test::effect_vs_scanline("effect_aurora", aurora, glow, sky, fx::RenderPath::PcpExact, 10);
}

TEST_CASE("CellRenderer::set_scalars draws what a renderer made with the new scalars draws", "[gl][effects]") {
    fx_test::gl_context();
    fx::Campfire fire;
    const fx::Camera cam = look({1.8, -2.2, 1.2}, {0, 0, 0.6}, 45.0);
    fire.update(view_at(0.0, cam));
    // A normalized function: its tables must follow the new range too.
    const fx::TransferFunction tf = fx::TransferFunction::read_json(fx_test::source_path("content/transfer_functions/fire.json"));
    fx::CellRenderer reused(fire.mesh(), fire.scalar_name(), tf);
    reused.render_to_image(cam, 64, 64, fx::RenderPath::PcpExact);
    fire.update(view_at(0.6, cam));
    reused.set_scalars(fire.mesh().scalars[0].values);
    fx::CellRenderer fresh(fire.mesh(), fire.scalar_name(), tf);
    for (fx::RenderPath path : fx::kRenderPaths) {
        fx_test::check_image(std::string("set_scalars_") + fx::render_path_name(path),
                             reused.render_to_image(cam, 64, 64, path), fresh.render_to_image(cam, 64, 64, path),
                             verify::same_picture(0.0, "the same mesh and scalars: the same bits"));
    }
    fx_test::require_no_gl_error();
    CHECK_THROWS_WITH(reused.set_scalars({1.0f, 2.0f}), Catch::Contains("set_scalars got 2 values"));
    std::vector<float> bad = fire.mesh().scalars[0].values;
    bad[7] = NAN;
    CHECK_THROWS_WITH(reused.set_scalars(bad), Catch::Contains("value 7 is not finite"));
}
