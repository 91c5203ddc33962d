// One medium per scene (fx/medium.hpp, medium/medium_compositor.hpp, terrain's scene renderer):
// an emissive box behind, inside and in front of an absorbing box against the closed form — from
// the command line as a user renders it, for every path of the emission–absorption model and
// the scan-line reference — whole frames against the scan-line reference of intersecting grids,
// the mixing and scattering model on the CPU, and that a scene whose volumes do not overlap on
// screen does no more work than before.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "harness/headless_context.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "medium/froxel_medium.hpp"
#include "medium/medium_compositor.hpp"
#include "fx/image.hpp"
#include "fx/medium.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_reference.hpp"
#include "terrain/scene_renderer.hpp"
#include "test_effects_support.hpp"
#include "test_paths.hpp"
#include "transfer/segment_integral.hpp"
#include "cellfx_names.hpp"

namespace {

const glm::dvec3 kGlowColor{1.0, 0.6, 0.2}, kFogColor{0.3, 0.35, 0.4};
constexpr double kGlowSigma = 2.0, kFogSigma = 1.5; // per metre; both boxes 1 m deep along the centre ray

// A homogeneous slab of colour c and extinction σ, length l: its radiance c·(1 − e^(−σl)) and
// transmittance e^(−σl).
glm::dvec3 slab(const glm::dvec3& c, double sigma, double l) { return c * -std::expm1(-sigma * l); }
double through(double sigma, double l) { return std::exp(-sigma * l); }

// The centre pixel of tests/data/medium/*.json over black, in closed form.
glm::dvec3 closed_form(const std::string& name) {
    const glm::dvec3 glow = slab(kGlowColor, kGlowSigma, 1.0), fog = slab(kFogColor, kFogSigma, 1.0);
    if (name == "emission_behind_fog") return glow * through(kFogSigma, 1.0) + fog; // E·e^(−τ) + c·(1 − e^(−τ))
    if (name == "emission_in_front_of_fog") return glow + through(kGlowSigma, 1.0) * fog;
    // inside: 1 m of fog, 1 m of the two media mixed (σ and emission add), 1 m of fog.
    const double sigma = kGlowSigma + kFogSigma;
    const glm::dvec3 mixed = slab((kGlowColor * kGlowSigma + kFogColor * kFogSigma) / sigma, sigma, 1.0);
    return fog + through(kFogSigma, 1.0) * (mixed + through(sigma, 1.0) * fog);
}

std::string scene_file(const std::string& name) { return fx_test::source_path("tests/data/medium/" + name + ".json"); }

// Renders a scene with every effect on `path` through the same classes the command line uses,
// over the scene's background — or, with `reference`, its scan-line reference with each effect's
// model as that path draws it ("scanline": as the scene declares). `method`: how the medium is
// integrated where volumes overlap.
fx::Image render_scene(const std::string& file, const std::string& path, int size, terrain::FrameStats* stats = nullptr,
                       bool reference = false, fx::MediumMethod method = fx::MediumMethod::Exact) {
    fx_test::gl_context();
    terrain::Scene scene = terrain::load_scene(file);
    scene.medium = method;
    terrain::SceneRenderer renderer(scene);
    fx::RenderPath p;
    if (path != "scanline") {
        REQUIRE(fx::parse_render_path(path, p));
        for (const std::string& name : renderer.effect_names()) renderer.set_path(name, p);
    }
    if (path == "scanline" || reference) {
        renderer.update(0.0, scene.camera, size, size);
        fx::Image image = terrain::render_scene_reference(renderer, scene.camera, size, size);
        fx::composite_over(image, glm::vec3(scene.background));
        return image;
    }
    fx::Image image = renderer.render_to_image(scene.camera, size, size, stats);
    fx_test::require_no_gl_error();
    return image;
}

glm::dvec3 centre(const fx::Image& image) { return glm::dvec3(image.at(image.width / 2, image.height / 2)); }

void check_closed_form(const glm::dvec3& actual, const glm::dvec3& expected, const std::string& what) {
    INFO(what << ": actual (" << actual.r << ", " << actual.g << ", " << actual.b << "), closed form (" << expected.r << ", "
              << expected.g << ", " << expected.b << ")");
    // Both media are constant, so every path integrates them exactly: what is left is float32
    // (tables, GPU arithmetic) against double — measured ≤ 2e-6 relative; 2e-5 allows for drivers.
    for (int c = 0; c < 3; ++c) CHECK(actual[c] == Approx(expected[c]).epsilon(2e-5));
}

} // namespace

TEST_CASE("Emission behind a box of fog, from the command line: E·e^(−τ) + c·(1 − e^(−τ)) on every path of the model",
          "[gl][medium][cli]") {
    const glm::dvec3 expected = closed_form("emission_behind_fog");
    for (const char* path : {"scanline", "pcp-exact", "absorption", "absorption-exact"}) {
        const std::string out = fx_test::output_path(std::string("medium_behind_") + path + ".pfm");
        const std::string command = std::string("'") + CELLFX_CLI + "' render '" + scene_file("emission_behind_fog") +
                                    "' --path " + path + " --medium exact --out '" + out + "' > '" + out + ".log' 2>&1";
        INFO(command);
        REQUIRE(std::system(command.c_str()) == 0);
        const fx::Image image = fx::read_pfm(out);
        REQUIRE(image.width == 65);
        check_closed_form(centre(image), expected, path);
    }
}

TEST_CASE("Emission inside and in front of fog: the closed forms on every path of the model", "[gl][medium]") {
    for (const char* name : {"emission_inside_fog", "emission_in_front_of_fog"}) {
        const glm::dvec3 expected = closed_form(name);
        for (const char* path : {"scanline", "pcp-exact", "absorption", "absorption-exact"})
            check_closed_form(centre(render_scene(scene_file(name), path, 65)), expected, std::string(name) + " " + path);
    }
}

TEST_CASE("The compositor's frames equal the scan-line reference of intersecting grids", "[gl][medium]") {
    for (const char* name : {"emission_behind_fog", "emission_inside_fog", "emission_in_front_of_fog"}) {
        const fx::Image reference = render_scene(scene_file(name), "scanline", 96);
        for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
            terrain::FrameStats stats;
            const fx::Image actual = render_scene(scene_file(name), fx::render_path_name(path), 96, &stats);
            CHECK(stats.medium.pixels > 0); // the boxes overlap on screen: integrated together
            // Outside the region each box is drawn by its own path: the tolerances of those
            // paths against the same reference (test_effects_support.hpp).
            effects_test::check_frame(std::string("medium_") + name, actual, reference, path, 2);
        }
    }
}

TEST_CASE("Light in the mist: a beam and a fire's glow scatter as the scan-line reference has it", "[gl][medium]") {
    const std::string file = scene_file("lights_in_mist");
    const fx::Image reference = render_scene(file, "scanline", 128);
    for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
        // The sorted paths always absorb (the beam and the fire too): their own reference.
        const fx::Image expected = path == fx::RenderPath::PcpExact ? reference : render_scene(file, "absorption-exact", 128, nullptr, true);
        terrain::FrameStats stats;
        const fx::Image actual = render_scene(file, fx::render_path_name(path), 128, &stats);
        CHECK(stats.medium.pixels > 0);
        // The scattering integrals: Simpson (beams) and Gauss–Legendre (point lights) per span on
        // the GPU against adaptive quadrature in pieces of optical depth 0.02 on the CPU — measured
        // 0.05% of peak; the paths' own tolerances (test_effects_support.hpp) hold.
        effects_test::check_frame("medium_lights_in_mist", actual, expected, path, 8);
    }
    // Without the mist the beam and the fire only glow: the light in the mist is what it adds.
    terrain::Scene clear = terrain::load_scene(file);
    clear.effects.erase(clear.effects.begin());
    fx_test::gl_context();
    terrain::SceneRenderer renderer(clear);
    const fx::Image glow_only = renderer.render_to_image(clear.camera, 128, 128);
    double lit = 0.0, clear_air = 0.0;
    for (std::size_t i = 0; i < reference.pixels.size(); ++i)
        lit += reference.pixels[i].r, clear_air += glow_only.pixels[i].r;
    CHECK(lit > 1.5 * clear_air);
}

TEST_CASE("The night valley's volumes on every GPU path against the scan-line reference of intersecting grids",
          "[gl][medium][showcase]") {
    // content/scenes/fog_valley_night.json at t = 0 and t = 8 s (the beam swung, the camera
    // moved): fog, campfire, smoke and search light, the terrain not drawn (the reference cannot
    // draw it), each path against the reference of the model it draws with.
    fx_test::gl_context();
    const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/fog_valley_night.json"));
    constexpr int kW = 128, kH = 96;
    for (double time : {0.0, 8.0}) {
        const fx::Camera camera = scene.camera_path->at(time, scene.camera);
        for (fx::RenderPath path : fx::kRenderPaths) {
            terrain::SceneRenderer renderer(scene);
            renderer.set_medium_method(fx::MediumMethod::Exact);
            renderer.set_terrain_drawn(false);
            renderer.set_background(glm::dvec3(0.0));
            renderer.set_time(time);
            for (const std::string& name : renderer.effect_names()) renderer.set_path(name, path);
            terrain::FrameStats stats;
            const fx::Image actual = renderer.render_to_image(camera, kW, kH, &stats);
            fx_test::require_no_gl_error();
            fx::Image expected = terrain::render_scene_reference(renderer, camera, kW, kH);
            fx::composite_over(expected, glm::vec3(0.0f));
            // pcp and mip keep their own models (emission, maximum) and draw no medium.
            const bool medium = path != fx::RenderPath::Pcp && path != fx::RenderPath::Mip;
            CHECK((stats.medium.pixels > 0) == medium);
            // Tolerances of each path (test_effects_support.hpp; pcp against the reference clamped to
            // its 8-bit target's range): the medium is exact to the
            // paths' own tolerances inside the mask (measured: 0.1% of peak at most), the paths
            // draw the fog outside it. pcp: up to ~40 fog prisms and fire cells on a ray, each
            // rounded to 8 bits.
            effects_test::check_frame("night_valley_t" + std::to_string(int(time)), actual, expected, path, 40);
        }
    }
}

TEST_CASE("Long lists: a pool that overflows grows, more segments than the sorted array are walked in order",
          "[gl][medium]") {
    // A noise box of 128 cells along the view, so every ray crosses ~128 of its cells (more than
    // MediumCompositor::kSortedSegments), behind a fog box: the first frame's pool (4 segments a
    // pixel) overflows and is drawn again; the picture still equals the reference.
    fx_test::gl_context();
    terrain::Scene scene = terrain::load_scene(scene_file("emission_behind_fog"));
    fx::VolumeParams& glow = std::get<fx::VolumeParams>(scene.effects[0].params);
    glow.size = {1.0, 4.0, 1.0};
    glow.cells = 128;
    glow.density_mode = fx::VolumeDensity::Noise;
    glow.noise.frequency = 2.0;
    scene.medium = fx::MediumMethod::Exact;
    terrain::SceneRenderer renderer(scene);
    terrain::FrameStats stats;
    const fx::Image actual = renderer.render_to_image(scene.camera, 128, 128, &stats);
    fx_test::require_no_gl_error();
    CHECK(stats.medium.redraws >= 1);
    CHECK(stats.medium.segments > std::size_t(fx::MediumCompositor::kSortedSegments) * 100); // > 96 at 100+ pixels
    CHECK(stats.medium.capacity >= stats.medium.segments);
    fx::Image expected = terrain::render_scene_reference(renderer, scene.camera, 128, 128);
    fx::composite_over(expected, glm::vec3(scene.background));
    effects_test::check_frame("medium_long_lists", actual, expected, fx::RenderPath::PcpExact, 130);
    // The next frame fits the grown pool.
    renderer.render_to_image(scene.camera, 128, 128, &stats);
    CHECK(stats.medium.redraws == 0);
}

TEST_CASE("The medium over a game's frame leaves the game's GL state as it found it", "[gl][medium]") {
    fx_test::gl_context();
    terrain::SceneRenderer renderer(terrain::load_scene(scene_file("emission_behind_fog")));
    renderer.set_medium_method(fx::MediumMethod::Exact);
    const int w = 64, h = 64;
    fx::gl::RenderTarget host = fx::gl::RenderTarget::create(w, h, fx::gl::ColorFormat::RGBA32F, false);
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        host.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
    }
    renderer.update(0.0, terrain::load_scene(scene_file("emission_behind_fog")).camera, w, h);
    effects_test::HostLeftovers leftovers;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, host.framebuffer());
    const std::vector<double> before = effects_test::host_state();
    const terrain::FrameStats stats = renderer.render(terrain::Target{host.framebuffer(), {0, 0, w, h}, 0});
    CHECK(stats.medium.pixels > 0);
    CHECK(effects_test::host_state() == before);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    fx_test::require_no_gl_error();
    // And the picture over the game's frame is the closed form.
    const fx::Image frame = host.read();
    const glm::dvec3 c = centre(frame);
    for (int k = 0; k < 3; ++k) CHECK(c[k] == Approx(closed_form("emission_behind_fog")[k]).epsilon(2e-5));
}

TEST_CASE("Volumes that do not overlap on screen cost nothing more: no region, each drawn by its own path",
          "[gl][medium]") {
    fx_test::gl_context();
    terrain::Scene scene = terrain::load_scene(scene_file("emission_behind_fog"));
    // The fog box moved aside, still in view: the two no longer share a pixel.
    std::get<fx::VolumeParams>(scene.effects[1].params).position = {2.0, 0.0, 0.0};
    scene.medium = fx::MediumMethod::Exact;
    terrain::SceneRenderer renderer(scene);
    terrain::FrameStats stats;
    renderer.render_to_image(scene.camera, 96, 96, &stats);
    INFO(stats.summary());
    CHECK(stats.medium.pixels == 0);
    CHECK(stats.medium.segments == 0);
    for (const terrain::EffectFrameStats& e : stats.effects) {
        CHECK(e.status == terrain::EffectStatus::Simulated);
        CHECK_FALSE(e.in_medium);
    }

    // Overlapping: the glow lies wholly inside the region, so it is drawn there only.
    terrain::SceneRenderer overlapping(terrain::load_scene(scene_file("emission_behind_fog")));
    overlapping.set_medium_method(fx::MediumMethod::Exact);
    overlapping.render_to_image(scene.camera, 96, 96, &stats);
    CHECK(stats.medium.pixels > 0);
    CHECK(stats.medium.pixels < 96u * 96u / 2u); // the glow's rectangle, not the frame
    CHECK(stats.find("glow")->in_medium);
    CHECK(stats.find("glow")->render.draw_calls == 0); // its own path was not run
    CHECK(stats.find("fog")->in_medium);
    CHECK(stats.find("fog")->render.draw_calls > 0); // the fog outside the region is
}

TEST_CASE("Medium spans: one volume alone is its exact integral, media mix, emission-only media do not absorb",
          "[medium]") {
    const fx::TransferFunction glow = fx::TransferFunction::constant(kGlowColor, kGlowSigma);
    const fx::TransferFunction fog = fx::TransferFunction::constant(kFogColor, kFogSigma);
    fx::MediumVolume a{glow, true, 0.0, {}}, b{fog, true, 0.0, {}}, c{glow, false, 0.0, {}};
    const fx::Medium medium({a, b, c});
    fx::RaySpan span;
    span.t_front = 2.0, span.t_back = 2.7;
    const fx::SpanVolume only_a{0, 0.3, 0.9};
    const fx::SegmentColor one = medium.integrate_span(&only_a, 1, span);
    const fx::SegmentColor exact = fx::emission_absorption(glow, 0.3, 0.9, 0.7);
    CHECK(one.alpha == Approx(exact.alpha));
    CHECK(one.color.r == Approx(exact.color.r));

    // Two homogeneous media over one span: σ and emission add.
    const fx::SpanVolume both[2] = {{0, 0.0, 1.0}, {1, 0.5, 0.5}};
    const fx::SegmentColor mixed = medium.integrate_span(both, 2, span);
    const double sigma = kGlowSigma + kFogSigma;
    const glm::dvec3 expected = slab((kGlowColor * kGlowSigma + kFogColor * kFogSigma) / sigma, sigma, 0.7);
    CHECK(mixed.alpha == Approx(-std::expm1(-sigma * 0.7)));
    for (int k = 0; k < 3; ++k) CHECK(mixed.color[k] == Approx(expected[k]).epsilon(1e-9));
    CHECK(mixed.optical_depth == Approx(sigma * 0.7));

    // An emission-only medium adds its light, dimmed by the other over the span, and absorbs nothing.
    const fx::SpanVolume glow_in_fog[2] = {{2, 0.0, 1.0}, {1, 0.5, 0.5}};
    const fx::SegmentColor lit = medium.integrate_span(glow_in_fog, 2, span);
    const double tau = kFogSigma * 0.7;
    const glm::dvec3 want = (kGlowColor * kGlowSigma + kFogColor * kFogSigma) * (-std::expm1(-tau) / kFogSigma);
    CHECK(lit.alpha == Approx(-std::expm1(-tau)));
    for (int k = 0; k < 3; ++k) CHECK(lit.color[k] == Approx(want[k]).epsilon(1e-9));
}

TEST_CASE("Medium spans: a beam scatters in proportion to the medium's density, with the phase function",
          "[medium]") {
    // A parallel beam along +x of constant strength 1 crossing a homogeneous fog; the eye looks
    // along +y, so θ = 90° everywhere: the fog glows ρ·σ·L·4π·p(0) per unit length, dimmed by itself.
    const double rho = 0.8, g = 0.4;
    fx::MediumLight beam;
    beam.kind = fx::MediumLight::Kind::Beam;
    beam.axis = {1, 0, 0};
    beam.color = glm::dvec3(2.0, 1.5, 1.0);
    beam.phase_g = g;
    beam.strength_per_scalar = 1.0;
    const fx::TransferFunction air = fx::TransferFunction::constant(glm::dvec3(0.0), 1e-9); // carries the light only
    for (double sigma : {0.05, 0.5, 3.0}) {
        const fx::TransferFunction fog = fx::TransferFunction::constant(glm::dvec3(0.0), sigma);
        const fx::Medium medium({fx::MediumVolume{air, false, 0.0, beam}, fx::MediumVolume{fog, true, rho, {}}});
        fx::RaySpan span;
        span.dir = {0, 1, 0};
        span.t_front = 1.0, span.t_back = 3.0;
        const fx::SpanVolume in[2] = {{0, 1.0, 1.0}, {1, 0.0, 0.0}};
        const fx::SegmentColor c = medium.integrate_span(in, 2, span);
        const double p = fx::relative_phase(g, 0.0);
        const glm::dvec3 expected = rho * p * beam.color * -std::expm1(-sigma * 2.0); // ρσL·4πp·(1 − e^(−σl))/σ
        INFO("sigma " << sigma);
        for (int k = 0; k < 3; ++k) CHECK(c.color[k] == Approx(expected[k]).epsilon(1e-6));
    }
    // Henyey–Greenstein integrates to 1 over the sphere and favours the forward direction.
    double integral = 0.0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const double mu = -1.0 + (i + 0.5) * 2.0 / n;
        integral += 2.0 * M_PI * fx::henyey_greenstein(0.7, mu) * 2.0 / n;
    }
    CHECK(integral == Approx(1.0).epsilon(1e-4));
    CHECK(fx::henyey_greenstein(0.0, 0.3) == Approx(1.0 / (4.0 * M_PI)));
    CHECK(fx::henyey_greenstein(0.6, 1.0) > 10.0 * fx::henyey_greenstein(0.6, -1.0));
}

namespace {

// The froxel model of one ray through piecewise-constant media (fx/internal/medium/
// froxel_medium.hpp), in double precision: the ray cut at the slices' ends z_k = near·(far /
// near)^(k/64), each slice's emission and optical depth summed and composited as an even mix,
// E·(1 − e^(−τ))/τ, front to back. `media`: (t0, t1, colour, σ) along the centre ray (t = view
// depth there), every one absorbing. Also returns `bound`, what the even mix may differ from the
// exact integral by: in a slice of emission E and depth τ every unit of light is dimmed by
// between e^(−τ) and 1 whichever way the media lie, so the exact and the mixed slice both lie in
// [E·e^(−τ), E] — |Δ| ≤ E·(1 − e^(−τ)), times the transmittance in front, summed over the
// slices holding more than one colour (one colour alone is exact however it lies).
struct Medium1d {
    double t0, t1;
    glm::dvec3 colour;
    double sigma;
};
glm::dvec3 froxel_model(const std::vector<Medium1d>& media, double near, double far, glm::dvec3& bound) {
    const int slices = fx::FroxelMedium::kSlices;
    glm::dvec3 light(0.0);
    double depth = 0.0;
    bound = glm::dvec3(0.0);
    for (int k = 0; k < slices; ++k) {
        const double a = near * std::pow(far / near, double(k) / slices);
        const double b = k == slices - 1 ? HUGE_VAL : near * std::pow(far / near, double(k + 1) / slices);
        glm::dvec3 e(0.0);
        double tau = 0.0;
        int colours = 0;
        for (const Medium1d& m : media) {
            const double l = std::max(0.0, std::min(b, m.t1) - std::max(a, m.t0));
            if (!(l > 0.0)) continue;
            e += m.colour * m.sigma * l, tau += m.sigma * l, ++colours;
        }
        if (!(tau > 0.0)) continue;
        light += std::exp(-depth) * e * (-std::expm1(-tau) / tau);
        if (colours > 1) bound += std::exp(-depth) * e * -std::expm1(-tau);
        depth += tau;
    }
    return light;
}

} // namespace

TEST_CASE("The froxel grid: the closed forms within what its slices' even mix allows, and its own model to half floats",
          "[gl][medium][froxel]") {
    // The three boxes along the centre ray (t = y + 6: the eye at y = −6 looking along +y),
    // each file's fog and glow; the slices run from the near plane (0.1) to the farthest corner
    // of the volumes. The centre pixel is a tile's centre ray (65 px, tiles of 65/9 px), with no
    // scene depth: the whole column, no interpolation across tiles or slices.
    const Medium1d glow{5.5, 6.5, kGlowColor, kGlowSigma};
    const struct {
        const char* name;
        Medium1d fog;
    } cases[] = {{"emission_behind_fog", {3.5, 4.5, kFogColor, kFogSigma}},
                 {"emission_inside_fog", {4.5, 7.5, kFogColor, kFogSigma}},
                 {"emission_in_front_of_fog", {7.5, 8.5, kFogColor, kFogSigma}}};
    for (const auto& c : cases) {
        glm::dvec3 bound;
        const double far = std::max(glow.t1, c.fog.t1);
        const glm::dvec3 model = froxel_model({glow, c.fog}, 0.1, far, bound);
        const glm::dvec3 exact = closed_form(c.name);
        for (const char* path : {"pcp-exact", "absorption-exact"}) {
            terrain::FrameStats stats;
            const glm::dvec3 actual = centre(render_scene(scene_file(c.name), path, 65, &stats, false, fx::MediumMethod::Froxel));
            REQUIRE(stats.medium.method == fx::MediumMethod::Froxel);
            REQUIRE(stats.medium.froxels == 9u * 9u * 64u);
            INFO(c.name << " " << path << ": actual (" << actual.r << ", " << actual.g << ", " << actual.b << "), the froxel model ("
                        << model.r << ", " << model.g << ", " << model.b << "), closed form (" << exact.r << ", " << exact.g << ", "
                        << exact.b << "), bound of the even mix (" << bound.r << ", " << bound.g << ", " << bound.b << ")");
            for (int k = 0; k < 3; ++k) {
                // The GPU grid is its model: the integrated grid is stored as half floats (11
                // significant bits: 4.9e-4 relative, once), the rest float; 1e-3 relative.
                CHECK(actual[k] == Approx(model[k]).epsilon(1e-3));
                // The model is the closed form within the even mix's bound (0 where no slice
                // holds two colours: the fog and the glow 1 m apart), and the same half floats.
                CHECK(std::abs(actual[k] - exact[k]) <= bound[k] + 1e-3 * exact[k]);
            }
        }
    }
}

TEST_CASE("The froxel grid's memory is bounded by the grid: at most 27.6 MB at 1920x1080, however many segments",
          "[gl][medium][froxel]") {
    // 160 × 90 tiles × 64 slices: 5 floats injected, RGBA16F integrated, R16F scattering.
    CHECK(fx::FroxelMedium::grid_size(1920, 1080) == glm::ivec3(160, 90, 64));
    CHECK(fx::FroxelMedium::gpu_bytes_for(1920, 1080) == 160u * 90u * 64u * 30u);
    CHECK(fx::FroxelMedium::gpu_bytes_for(1920, 1080) <= 32u * 1000u * 1000u);
    CHECK(fx::FroxelMedium::grid_size(3840, 2160) == glm::ivec3(160, 90, 64)); // larger views: larger tiles
    CHECK(fx::FroxelMedium::grid_size(640, 480) == glm::ivec3(80, 60, 64));
    // A frame at 1920x1080 allocates that and no more; the long-list scene (128 segments a
    // pixel, test "Long lists" above) needs no more than two boxes.
    fx_test::gl_context();
    terrain::Scene scene = terrain::load_scene(scene_file("emission_behind_fog"));
    fx::VolumeParams& glow = std::get<fx::VolumeParams>(scene.effects[0].params);
    glow.size = {1.0, 4.0, 1.0};
    glow.cells = 128;
    terrain::SceneRenderer renderer(scene);
    terrain::FrameStats stats;
    renderer.render_to_image(scene.camera, 1920, 1080, &stats);
    fx_test::require_no_gl_error();
    CHECK(stats.medium.method == fx::MediumMethod::Froxel);
    CHECK(stats.medium.gpu_bytes == fx::FroxelMedium::gpu_bytes_for(1920, 1080));
}

namespace {

// A frame of the froxel grid against the scan-line reference (RGB): the mean error and the share
// of pixels beyond `pixel_tolerance` (both in parts of the reference's peak); the pixels beyond
// lie in the band where the grid interpolates between tile centres, each within the bound of the
// values the reference takes within one tile (`tile` pixels) of it.
void check_froxel_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected, double mean_bound,
                        double pixel_tolerance, double share_bound, int tile) {
    verify::Tolerance t;
    t.pixel.of_peak = pixel_tolerance, t.share_beyond = share_bound, t.mean.of_peak = mean_bound;
    t.outlier_radius = tile;
    t.why = "the froxel grid: exact per tile column, interpolated between tile centres";
    verify::Options rgb;
    rgb.channels = 3;
    fx_test::check_frame(name + "_froxel", actual, expected, t, rgb);
}

} // namespace

TEST_CASE("The froxel grid: the night valley and light in the mist against the scan-line reference",
          "[gl][medium][froxel]") {
    fx_test::gl_context();
    {
        const terrain::Scene scene = terrain::load_scene(fx_test::source_path("content/scenes/fog_valley_night.json"));
        constexpr int kW = 128, kH = 96;
        for (double time : {0.0, 8.0}) {
            const fx::Camera camera = scene.camera_path->at(time, scene.camera);
            terrain::SceneRenderer renderer(scene);
            renderer.set_medium_method(fx::MediumMethod::Froxel);
            renderer.set_terrain_drawn(false);
            renderer.set_background(glm::dvec3(0.0));
            renderer.set_time(time);
            terrain::FrameStats stats;
            const fx::Image actual = renderer.render_to_image(camera, kW, kH, &stats);
            fx_test::require_no_gl_error();
            REQUIRE(stats.medium.method == fx::MediumMethod::Froxel);
            fx::Image expected = terrain::render_scene_reference(renderer, camera, kW, kH);
            fx::composite_over(expected, glm::vec3(0.0f));
            // The grid is exact per tile column to its even mix in a slice (the closed forms
            // above); between tile centres it is interpolated, so where the volumes change across
            // a tile — the smoke's outline, the fog layer's top, the glow's fall-off near the
            // fire — a band about a tile wide differs: at 128×96 the grid is 16 × 12 tiles, the
            // band ~5% of the frame (measured 3.0% and 5.3% of the pixels beyond 2% of peak, mean
            // 0.18% and 0.28% of peak). Bounds: 10% of the pixels, mean 1% of peak — a slice, a
            // light or a volume missing from the grid moves most of the frame.
            check_froxel_frame("night_valley_t" + std::to_string(int(time)), actual, expected, 0.01, 0.02, 0.10,
                               fx::FroxelMedium::kTilePixels);
        }
    }
    // The beam (drawn per pixel, lighting the grid's mist) and the glow (lit per froxel): the
    // band along the beam's and the fire's outlines (measured 0.87% of the pixels beyond 2% of
    // peak, mean 0.08%); bounds 3% and 0.5%.
    const std::string file = scene_file("lights_in_mist");
    const fx::Image reference = render_scene(file, "scanline", 128);
    const fx::Image actual = render_scene(file, "pcp-exact", 128, nullptr, false, fx::MediumMethod::Froxel);
    check_froxel_frame("lights_in_mist", actual, reference, 0.005, 0.02, 0.03, fx::FroxelMedium::kTilePixels);
}
