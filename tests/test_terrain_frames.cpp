// Frame tests of the ground fog (Roettger & Ertl 2003 §5) against the CPU scan-line reference:
// a fog valley over a continuous-LOD terrain seen from above and from inside the fog, every GPU
// path, with the terrain's depth as the scene depth; the picture stays continuous as the camera
// descends through the fog top; the terrain's depth matches the LOD surface; fog dims the
// terrain behind it.
//
// The valley is a bowl (a convex ground, z = a·r²): a ray that enters the ground never comes
// out again, so the terrain hides no fog and the scan-line reference (which has no terrain)
// sees exactly what the GPU should. The fog is a lens filling the bowl up to a level, its top
// moved by a smooth ripple.
//
// Tolerances: each path's stated one (testing/verify/tolerances.cpp, where each number is
// derived). The scene depth clamp ends rays at the ground a depth-buffer ulp early at worst
// (≈1e-6 of the distance), far below them. The camera inside the fog with the density varying
// inside the prisms states near_plane_cuts (pcp-exact interpolates the cut's scalar along the
// ray, the reference over a fan of the cap); with a density that does not vary (σ constant) the
// two agree to the exact tolerance.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "fx/cell_renderer.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/scanline_renderer.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "gl_fixture.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/surface_renderer.hpp"
#include "terrain_test_support.hpp"
#include "cellfx_names.hpp"

namespace {

constexpr int kSize = 64;
constexpr double kCenter = 160.0; // the bowl's centre, the field is 320 x 320 (33², spacing 10)

terrain::HeightField bowl() {
    return terrain::make_height_field(33, 10.0, [](double x, double y) {
        const double dx = x - kCenter, dy = y - kCenter;
        return 0.0012 * (dx * dx + 0.7 * dy * dy);
    });
}
terrain::HeightField fog_lens(const terrain::HeightField& ground) {
    return terrain::make_valley_fog_map(ground, 30.0, 40.0,
                                        [](double x, double y) { return 3.0 * std::sin(x / 23.0) * std::cos(y / 17.0); });
}

fx::Camera camera(glm::dvec3 eye, glm::dvec3 target) {
    fx::Camera c;
    c.eye = eye;
    c.target = target;
    c.up = {0, 0, 1};
    c.fov_y_degrees = 50.0;
    c.near_distance = 0.05;
    c.far_distance = 5000.0;
    return c;
}

struct Valley {
    terrain::ContinuousLod lod;
    terrain::LodMesh mesh;
    fx::CellMesh prisms;
};

Valley make_valley(const fx::Camera& cam, double pixel_error = 1.0) {
    const terrain::HeightField ground = bowl();
    Valley v{terrain::ContinuousLod(ground, fog_lens(ground)), {}, {}};
    v.lod.update(terrain::LodView::from_camera(cam, kSize, pixel_error));
    v.lod.extract(v.mesh);
    v.prisms = terrain::build_layer_prisms(v.mesh);
    REQUIRE(fx::validate_mesh(v.prisms).empty());
    return v;
}

// The fog only (premultiplied), drawn by `path` with the terrain surface's depth as scene depth.
fx::Image gpu_fog(const Valley& v, const fx::Camera& cam, const fx::TransferFunction& tf, fx::RenderPath path,
                  fx::Image* terrain_then_fog = nullptr, fx::Image* terrain_alone = nullptr) {
    fx_test::gl_context();
    fx::gl::RenderTarget scene = fx::gl::RenderTarget::create(kSize, kSize, fx::gl::ColorFormat::RGBA32F, true);
    fx::gl::RenderTarget fog = fx::gl::RenderTarget::create(kSize, kSize, fx::gl::ColorFormat::RGBA32F, false);
    terrain::SurfaceRenderer surface(v.lod.ground());
    fx::CellRenderer renderer(v.prisms, "density", tf);
    fx::CellRenderOptions options;
    options.fog = path == fx::RenderPath::PcpExact;
    options.scene_depth = scene.depth_texture();
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        scene.clear(glm::vec4(0.0f), 1.0f);
        scene.bind_for_drawing();
        surface.draw(v.mesh, cam, fx::Viewport{0, 0, kSize, kSize});
        fog.clear(glm::vec4(0.0f));
        fog.bind_for_drawing();
        renderer.render(cam, fx::Viewport{0, 0, kSize, kSize}, path, options);
    }
    if (terrain_alone) *terrain_alone = scene.read();
    if (terrain_then_fog) {
        fx::gl::StateGuard guard;
        scene.bind_for_drawing();
        renderer.render(cam, fx::Viewport{0, 0, kSize, kSize}, path, options);
    }
    fx_test::require_no_gl_error();
    if (terrain_then_fog) *terrain_then_fog = scene.read();
    return fog.read();
}

fx::Image scanline_fog(const Valley& v, const fx::Camera& cam, const fx::TransferFunction& tf, fx::RenderPath path) {
    fx::ScanlineOptions so;
    so.model = path == fx::RenderPath::Mip ? fx::OpticalModel::Maximum
                                           : (path == fx::RenderPath::Pcp ? fx::OpticalModel::Emission
                                                                          : fx::OpticalModel::EmissionAbsorption);
    return fx::ScanlineRenderer(v.prisms).render(cam, kSize, kSize, *v.prisms.find_scalar("density"), tf, so);
}

verify::Tolerance tolerance_for(fx::RenderPath path, bool near_cuts_varying, int cells_on_ray) {
    verify::Case c;
    c.cells_on_ray = cells_on_ray, c.near_plane_cuts = near_cuts_varying;
    return verify::stated(verify::path_of(path), c);
}

// Compares (fx_test::check_frame: printed, checked, PNGs written on failure).
void check_against_reference(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                             fx::RenderPath path, const verify::Tolerance& t) {
    fx_test::check_frame(name + "_" + fx::render_path_name(path), actual, expected, t);
}

// One-colour fog, extinction rising with the layer height (0 .. 40 units of thickness).
fx::TransferFunction layer_fog(double sigma_at_40) {
    return fx::TransferFunction({{0.0, {0.9, 0.92, 1.0}, 0.0}, {40.0, {0.9, 0.92, 1.0}, sigma_at_40}});
}
// MIP set-up of the paper: emission rising with the layer height, monotonic.
fx::TransferFunction mip_glow() {
    return fx::TransferFunction({{0.0, {0.2, 0.25, 0.3}, 0.0}, {40.0, {1.0, 1.0, 1.0}, 1.0}});
}

} // namespace

TEST_CASE("Fog valley from above matches the scan-line reference", "[gl][terrain][frames]") {
    const fx::Camera cam = camera({160, -60, 190}, {160, 170, 10});
    const Valley v = make_valley(cam);
    INFO("LOD triangles " << v.mesh.triangles.size() << ", prisms " << v.prisms.cell_count());
    REQUIRE(v.prisms.cell_count() > 200);
    REQUIRE(v.mesh.triangles.size() < v.lod.full_resolution_triangles()); // a real LOD, several levels
    struct Case {
        fx::RenderPath path;
        fx::TransferFunction tf;
        int cells_on_ray;
    };
    // Emission for pcp kept ≤ 1 per pixel (its 8-bit range): σ·c·length ≲ 0.004·40·... small.
    const Case cases[] = {{fx::RenderPath::PcpExact, layer_fog(0.08), 0},
                          {fx::RenderPath::Mip, mip_glow(), 0},
                          {fx::RenderPath::Pcp, layer_fog(0.004), 8}};
    for (const Case& c : cases) {
        const fx::Image actual = gpu_fog(v, cam, c.tf, c.path);
        const fx::Image expected = scanline_fog(v, cam, c.tf, c.path);
        check_against_reference("fog_valley_above", actual, expected, c.path, tolerance_for(c.path, false, c.cells_on_ray));
    }
}

TEST_CASE("Fog valley from inside the fog matches the scan-line reference", "[gl][terrain][frames]") {
    // Eye 6 units above the bowl floor, inside the ~30-unit lens, looking across the valley.
    const double floor_z = 0.0;
    const fx::Camera cam = camera({160, 80, floor_z + 6.0}, {160, 260, floor_z + 2.0});
    const Valley v = make_valley(cam);
    // Constant σ: both renderers exact, caps included.
    {
        const fx::TransferFunction flat = fx::TransferFunction::constant({0.9, 0.92, 1.0}, 0.02);
        const fx::Image actual = gpu_fog(v, cam, flat, fx::RenderPath::PcpExact);
        const fx::Image expected = scanline_fog(v, cam, flat, fx::RenderPath::PcpExact);
        check_against_reference("fog_valley_inside_flat", actual, expected, fx::RenderPath::PcpExact,
                                tolerance_for(fx::RenderPath::PcpExact, false, 0));
    }
    // Density rising with the layer height: the near-plane modelling difference applies.
    const fx::Image actual = gpu_fog(v, cam, layer_fog(0.05), fx::RenderPath::PcpExact);
    const fx::Image expected = scanline_fog(v, cam, layer_fog(0.05), fx::RenderPath::PcpExact);
    check_against_reference("fog_valley_inside", actual, expected, fx::RenderPath::PcpExact,
                            tolerance_for(fx::RenderPath::PcpExact, true, 0));
    const fx::Image mip = gpu_fog(v, cam, mip_glow(), fx::RenderPath::Mip);
    const fx::Image mip_ref = scanline_fog(v, cam, mip_glow(), fx::RenderPath::Mip);
    check_against_reference("fog_valley_inside", mip, mip_ref, fx::RenderPath::Mip,
                            tolerance_for(fx::RenderPath::Mip, true, 0));
}

TEST_CASE("Descending through the fog top keeps the picture continuous", "[gl][terrain][frames]") {
    // The bowl's centre is the quadtree root's centre: its height and thickness are exact at
    // every LOD, so the fog top there is known: ground 0 + thickness.
    const terrain::HeightField ground = bowl();
    const terrain::HeightField fog = fog_lens(ground);
    const double top = double(ground.at(16, 16)) + fog.at(16, 16);
    const fx::TransferFunction tf = layer_fog(0.05);
    std::vector<double> heights;
    for (int k = -6; k <= 6; ++k) heights.push_back(top + 0.5 * k); // 0.5-unit steps through the top
    for (double e : {1e-2, 1e-3}) heights.push_back(top + e), heights.push_back(top - e); // either side of it
    std::sort(heights.begin(), heights.end(), std::greater<double>());
    std::vector<fx::Image> frames;
    terrain::ContinuousLod lod(ground, fog); // one LOD, updated along the descent (geomorphed)
    for (double z : heights) {
        const fx::Camera cam = camera({kCenter, kCenter, z}, {kCenter, kCenter + 100.0, z - 12.0});
        lod.update(terrain::LodView::from_camera(cam, kSize, 1.0));
        Valley v{terrain::ContinuousLod(ground, fog), lod.mesh(), {}};
        v.prisms = terrain::build_layer_prisms(v.mesh);
        frames.push_back(gpu_fog(v, cam, tf, fx::RenderPath::PcpExact));
        if (std::abs(z - top) < 0.6) { // near the top: against the reference as well
            const fx::Image expected = scanline_fog(v, cam, tf, fx::RenderPath::PcpExact);
            check_against_reference("fog_top_descent", frames.back(), expected, fx::RenderPath::PcpExact,
                                    tolerance_for(fx::RenderPath::PcpExact, true, 0));
        }
    }
    // Mean change between consecutive frames, per unit of height: no jump at the top.
    std::vector<double> change;
    for (std::size_t k = 1; k < frames.size(); ++k) {
        const double dz = heights[k - 1] - heights[k];
        change.push_back(verify::measure(frames[k], frames[k - 1]).mean / dz);
    }
    std::vector<double> sorted = change;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    for (std::size_t k = 0; k < change.size(); ++k) {
        INFO("step " << k << " from z = " << heights[k] << " to " << heights[k + 1] << ": mean change per unit "
                     << change[k] << ", median " << median);
        // A popping cap or a missing one would change a large part of the image at once; the
        // rate of change stays within a few times the typical one (the view's content changes
        // smoothly with the eye height: fog below, clear air above).
        CHECK(change[k] <= 4.0 * median + 1e-4);
    }
    // Across the top itself: the difference between the frames at top ± ε shrinks with ε
    // (continuity). Rays grazing the fog top change their path in the fog fastest, so the largest
    // pixel change is steep but still goes to zero; a missing or popping cap would not.
    auto across = [&](double e) {
        const auto at = [&](double z) { return std::size_t(std::find(heights.begin(), heights.end(), z) - heights.begin()); };
        return verify::measure(frames[at(top + e)], frames[at(top - e)]);
    };
    const verify::Difference wide = across(1e-2), narrow = across(1e-3);
    INFO("across the top: ±1e-2 max " << wide.worst.delta << " mean " << wide.mean << "; ±1e-3 max "
                                      << narrow.worst.delta << " mean " << narrow.mean);
    CHECK(narrow.worst.delta < 0.5 * wide.worst.delta + 1e-4);
    CHECK(narrow.mean < 0.5 * wide.mean + 1e-7);
    CHECK(narrow.mean < 1e-3);
}

TEST_CASE("The terrain's depth is the LOD surface's, and fog dims the terrain behind it", "[gl][terrain][frames]") {
    const fx::Camera cam = camera({160, -60, 190}, {160, 170, 10});
    const Valley v = make_valley(cam);
    fx::Image terrain_then_fog, terrain_alone;
    const fx::TransferFunction tf = layer_fog(0.08);
    const fx::Image fog = gpu_fog(v, cam, tf, fx::RenderPath::PcpExact, &terrain_then_fog, &terrain_alone);
    // Composite: terrain·e^−τ + fog, i.e. fog + (1 − α_fog)·terrain.
    fx::Image composited = fog;
    std::size_t dimmed = 0, covered = 0;
    for (std::size_t i = 0; i < fog.pixels.size(); ++i) {
        composited.pixels[i] = fog.pixels[i] + (1.0f - fog.pixels[i].a) * terrain_alone.pixels[i];
        if (fog.pixels[i].a > 0.2f) ++dimmed;
        covered += terrain_alone.pixels[i].a > 0.5f;
    }
    fx_test::check_image("fog_over_terrain", terrain_then_fog, composited,
                         verify::same_picture(1e-4, "one blend in float: a few roundings of values ≤ 1"));
    CHECK(dimmed > 100);
    CHECK(covered > fog.pixels.size() / 2);

    // Depth: the surface renderer's depth buffer against the ray ∩ LOD surface, per pixel.
    fx_test::gl_context();
    fx::gl::RenderTarget scene = fx::gl::RenderTarget::create(kSize, kSize, fx::gl::ColorFormat::RGBA32F, true);
    terrain::SurfaceRenderer surface(v.lod.ground());
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        scene.clear(glm::vec4(0.0f), 1.0f);
        scene.bind_for_drawing();
        surface.draw(v.mesh, cam, fx::Viewport{0, 0, kSize, kSize});
    }
    std::vector<float> depth(kSize * kSize);
    {
        fx::gl::StateGuard guard;
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        glGetTextureImage(scene.depth_texture(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depth.size() * 4), depth.data());
    }
    fx_test::require_no_gl_error();
    // Window depth where pixel (x, y)'s ray meets the LOD surface (bisection on the height above
    // the convex surface), or -1 when it misses.
    auto true_depth = [&](int x, int y) {
        const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, kSize, kSize);
        auto above = [&](double t) {
            const glm::dvec3 p = ray.origin + t * ray.direction;
            const double z = terrain_test::surface_height(v.mesh, p.x, p.y);
            return std::isnan(z) || p.z > z;
        };
        // March to the first point below the surface (2-unit steps: the bowl is smooth), then bisect.
        double t0 = 0.0, t1 = 2.0;
        while (t1 < 800.0 && above(t1)) t0 = t1, t1 += 2.0;
        if (t1 >= 800.0) return -1.0;
        for (int it = 0; it < 50; ++it) (above(0.5 * (t0 + t1)) ? t0 : t1) = 0.5 * (t0 + t1);
        const glm::dvec3 hit = ray.origin + t1 * ray.direction;
        if (std::isnan(terrain_test::surface_height(v.mesh, hit.x, hit.y))) return -1.0;
        const double z_e = glm::dot(hit - cam.eye, cam.forward());
        const double n = cam.near_distance, f = cam.far_distance;
        return f * (z_e - n) / (z_e * (f - n));
    };
    std::size_t hits = 0, off = 0;
    for (int y = 1; y < kSize - 1; y += 3) {
        for (int x = 1; x < kSize - 1; x += 3) {
            const double w = true_depth(x, y), wx = true_depth(x + 1, y), wy = true_depth(x, y + 1);
            if (w < 0.0 || wx < 0.0 || wy < 0.0) continue;
            ++hits;
            // The rasteriser interpolates depth at the pixel centre: equal up to float rounding
            // (~1e-7 in window depth) and, where the pixel centre lies on a triangle edge, a
            // fraction of the change to the next pixel.
            const double slope = std::abs(wx - w) + std::abs(wy - w);
            const double got = depth[y * kSize + x];
            if (!(std::abs(got - w) <= 0.25 * slope + 3e-7)) {
                ++off;
                WARN("pixel (" << x << ", " << y << "): depth " << got << ", surface " << w << ", slope " << slope);
            }
        }
    }
    WARN("terrain depth checked at " << hits << " pixels, " << off << " off");
    CHECK(hits > 150);
    CHECK(off == 0);
}

TEST_CASE("MIP over a real valley has no extrapolated spikes", "[gl][terrain][frames]") {
    // The shipped fog valley (Mount St. Helens, ~36k prisms) at 512x384, fog only, against the
    // scan-line reference. Rasterisers cover a pixel centre that lies within their sub-pixel
    // precision outside a triangle, and a sliver seen edge-on then extrapolates its scalar far
    // beyond its vertices (this showed as single white pixels: +58% of peak). The paths clamp the
    // interpolated scalar to the triangle's own range; what remains is a pixel centre grazing an
    // edge-on side face taking a value of that face: no pixel may lie outside the reference's
    // range over its 3x3 neighbourhood by 10% of peak, and at most 5 of 196,608 by 1%.
    fx_test::gl_context();
    const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/fog_valley_mip.json"));
    terrain::ContinuousLod lod(scene.ground, scene.fog->thickness, scene.lod);
    lod.update(terrain::LodView::from_camera(scene.camera, 384, scene.pixel_error));
    const fx::CellMesh prisms = terrain::build_layer_prisms(lod.mesh(), scene.fog->prisms);
    const fx::TransferFunction tf = terrain::drawn_transfer_function(
        scene.fog->transfer_function, scene.fog->extinction_scale, {0.0f, float(scene.fog->thickness.max_height())});
    fx::CellRenderer renderer(prisms, "density", tf);
    const fx::Image gpu = renderer.render_to_image(scene.camera, 512, 384, fx::RenderPath::Mip);
    fx::ScanlineOptions so;
    so.model = fx::OpticalModel::Maximum;
    const fx::Image ref = fx::ScanlineRenderer(prisms).render(scene.camera, 512, 384, *prisms.find_scalar("density"), tf, so);
    verify::Tolerance spikes;
    spikes.pixel.of_peak = 0.1, spikes.share_beyond = 1.0, spikes.mean.of_peak = 1.0;
    spikes.why = "a pixel centre grazing an edge-on side face takes a value of that face";
    verify::Options rgb;
    rgb.channels = 3;
    const verify::Difference d = fx_test::check_frame("fog_valley_mip_spikes", gpu, ref, spikes, rgb);
    CHECK(d.peak > 0.1);
    verify::Tolerance small = spikes;
    small.pixel.of_peak = 0.01;
    const verify::Difference near = verify::measure(gpu, ref, small, rgb);
    INFO(near.outliers << " pixels outside the reference's neighbourhood by > 1% of peak");
    CHECK(near.outliers <= 5);
}
