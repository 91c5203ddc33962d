// `auto` (fx/auto_path.hpp): the choice from injected cost tables (deterministic: the cheapest
// path meeting the accuracy, a clear error when none does or the accuracy is out of range),
// the stated errors against testing/verify's table, and a frame: what auto picks on this
// machine, measured on a real mesh, passes the picked path's own check against the scan-line
// reference.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "fx/auto_path.hpp"
#include "fx/error.hpp"
#include "gl_fixture.hpp"
#include "image_check.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace {

fx::PathCost cost(fx::AutoCandidate candidate, double error, double fixed_ms, double ms_per_pixel) {
    fx::PathCost c;
    c.candidate = candidate, c.stated_error = error, c.fixed_ms = fixed_ms, c.ms_per_pixel = ms_per_pixel;
    return c;
}

const fx::AutoCandidate kAbsExact = fx::gl_candidate(fx::RenderPath::AbsorptionExact);
const fx::AutoCandidate kAbs = fx::gl_candidate(fx::RenderPath::Absorption);

} // namespace

TEST_CASE("auto picks the cheapest path that meets the accuracy", "[auto]") {
    // llvmpipe-like: the scan-line renderer ~10x cheaper at the same error (docs/accuracy.md).
    const std::vector<fx::PathCost> cpu = {cost(fx::kScanlineCandidate, 1e-5, 5.0, 1e-4),
                                           cost(kAbsExact, 5e-4, 40.0, 1.5e-3), cost(kAbs, 4e-3, 80.0, 5e-4)};
    fx::PathChoice c = fx::choose_path(cpu, 1e-3, 512, 512);
    CHECK(c.candidate == fx::kScanlineCandidate);
    CHECK(c.frame_ms == Approx(5.0 + 1e-4 * 512 * 512));
    CHECK(c.reason.find("auto picked scanline") == 0);
    CHECK(c.reason.find("absorption states 0.004") != std::string::npos); // says what was out
    // GPU-like: the GL paths win; a looser accuracy lets classic absorption in and it is cheapest.
    const std::vector<fx::PathCost> gpu = {cost(fx::kScanlineCandidate, 1e-5, 5.0, 1e-4),
                                           cost(kAbsExact, 5e-4, 2.0, 1e-6), cost(kAbs, 4e-3, 1.0, 1e-6)};
    CHECK(fx::choose_path(gpu, 1e-3, 512, 512).candidate == kAbsExact);
    CHECK(fx::choose_path(gpu, 5e-3, 512, 512).candidate == kAbs);
    CHECK(fx::choose_path(gpu, 1e-4, 512, 512).candidate == fx::kScanlineCandidate);
    // The size matters: fixed against per-pixel costs cross over.
    const std::vector<fx::PathCost> cross = {cost(fx::kScanlineCandidate, 1e-5, 1.0, 1e-3), cost(kAbsExact, 5e-4, 50.0, 1e-5)};
    CHECK(fx::choose_path(cross, 1e-3, 64, 64).candidate == fx::kScanlineCandidate);   // 5 ms against 50
    CHECK(fx::choose_path(cross, 1e-3, 1024, 1024).candidate == kAbsExact);           // 1049 ms against 60
}

TEST_CASE("auto's choice is deterministic: ties go to the smaller error, then the first", "[auto]") {
    const std::vector<fx::PathCost> tie = {cost(kAbsExact, 5e-4, 10.0, 0.0), cost(fx::kScanlineCandidate, 1e-5, 10.0, 0.0)};
    CHECK(fx::choose_path(tie, 1e-3, 100, 100).candidate == fx::kScanlineCandidate);
    const std::vector<fx::PathCost> same = {cost(kAbsExact, 5e-4, 10.0, 0.0), cost(fx::gl_candidate(fx::RenderPath::PcpExact), 5e-4, 10.0, 0.0)};
    for (int i = 0; i < 3; ++i) CHECK(fx::choose_path(same, 1e-3, 100, 100).candidate == kAbsExact);
    // A candidate that was never measured (NaN) cannot win, whatever it states.
    const std::vector<fx::PathCost> unmeasured = {cost(fx::kScanlineCandidate, 1e-5, std::nan(""), std::nan("")),
                                                  cost(kAbsExact, 5e-4, 100.0, 0.0)};
    const fx::PathChoice c = fx::choose_path(unmeasured, 1e-3, 10, 10);
    CHECK(c.candidate == kAbsExact);
    CHECK(c.reason.find("scanline not measured") != std::string::npos);
}

TEST_CASE("auto refuses and explains: no path meets the accuracy, a bad accuracy, nothing to choose", "[auto]") {
    const std::vector<fx::PathCost> costs = {cost(kAbsExact, 5e-4, 1.0, 0.0), cost(kAbs, 4e-3, 1.0, 0.0)};
    CHECK_THROWS_WITH(fx::choose_path(costs, 1e-4, 64, 64, "--accuracy"),
                      Catch::Contains("--accuracy: no render path meets accuracy 0.0001") &&
                          Catch::Contains("absorption-exact states 0.0005") && Catch::Contains("absorption states 0.004"));
    for (const double bad : {0.0, -1.0, 1e-7, 1.5, std::nan(""), HUGE_VAL})
        CHECK_THROWS_WITH(fx::choose_path(costs, bad, 64, 64, "--accuracy"),
                          Catch::StartsWith("--accuracy: accuracy") && Catch::Contains("out of range") &&
                              Catch::Contains("[1e-06, 1]"));
    CHECK_THROWS_WITH(fx::choose_path({}, 1e-3, 64, 64, "--accuracy"), Catch::Contains("no render path to choose from"));
    CHECK_THROWS_AS(fx::choose_path(costs, 1e-3, 0, 64), fx::Error);
    CHECK_NOTHROW(fx::check_accuracy(fx::kDefaultAccuracy, "x"));
}

TEST_CASE("auto's stated errors are verify's mean bounds", "[auto]") {
    // stated_mean_error repeats testing/verify/tolerances.cpp for the libraries (which do not
    // link the test support); the two must not drift apart.
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Absorption,
                                      fx::RenderPath::AbsorptionExact}) {
        for (const bool cuts : {false, true}) {
            if (path == fx::RenderPath::Absorption && cuts) continue; // beyond its tolerance there (docs/accuracy.md)
            verify::Case c;
            c.near_plane_cuts = cuts;
            INFO(fx::render_path_name(path) << (cuts ? ", near plane cuts" : ""));
            CHECK(fx::stated_mean_error(fx::gl_candidate(path), cuts) ==
                  Approx(verify::stated(verify::path_of(path), c).mean.of_peak));
        }
    }
    CHECK(fx::stated_mean_error(fx::kScanlineCandidate) == Approx(verify::stated(verify::Path::Scanline).mean.of_peak));
    CHECK(fx::stated_mean_error(fx::gl_candidate(fx::RenderPath::Absorption), true) >
          verify::stated(verify::Path::Absorption, verify::Case{1, 0.15, true, false}).mean.of_peak);
    // Each optical model's candidates compute that model; no GL leaves the scan-line renderer.
    CHECK(fx::auto_candidates(fx::OpticalModel::Maximum).back() == fx::gl_candidate(fx::RenderPath::Mip));
    CHECK(fx::auto_candidates(fx::OpticalModel::Emission).back() == fx::gl_candidate(fx::RenderPath::PcpExact));
    CHECK(fx::auto_candidates(fx::OpticalModel::EmissionAbsorption, false).size() == 1);
}

TEST_CASE("auto near the mesh: the near plane cutting its box raises the stated errors", "[auto]") {
    fx::Camera cam;
    cam.eye = {0.5, 0.5, -2.0}, cam.target = {0.5, 0.5, 0.5}, cam.up = {0, 1, 0};
    cam.near_distance = 0.1;
    const fx::Bounds box{glm::dvec3(0.0), glm::dvec3(1.0)};
    CHECK_FALSE(fx::near_plane_cuts(cam, box));
    cam.near_distance = 2.5;
    CHECK(fx::near_plane_cuts(cam, box));
}

TEST_CASE("auto's picture passes the picked path's check against the scan-line reference", "[auto][gl]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = [] {
        fx::CellMesh m = fx_test::hex_box(6, 6, 6);
        std::vector<float> s;
        for (const glm::dvec3& p : m.points) s.push_back(float(0.5 + 0.4 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y) + 0.1 * p.z));
        m.scalars.push_back({"s", s});
        return m;
    }();
    const fx::TransferFunction varied({{0.0, glm::dvec3(0.1, 0.3, 1.0), 0.5},
                                      {0.5, glm::dvec3(0.2, 1.0, 0.3), 2.0},
                                      {1.0, glm::dvec3(1.0, 0.3, 0.1), 4.0}},
                                     true);
    // mip is exact where c·σ rises monotonically across a cell (its stated case,
    // testing/verify/tolerances.cpp): every channel rises here.
    const fx::TransferFunction rising({{0.0, glm::dvec3(0.1, 0.2, 0.3), 0.5},
                                      {0.5, glm::dvec3(0.4, 0.6, 0.5), 2.0},
                                      {1.0, glm::dvec3(1.0, 0.9, 0.6), 4.0}},
                                     true);
    fx::Camera cam;
    cam.eye = {2.6, 2.2, 1.9}, cam.target = {0.5, 0.5, 0.5}, cam.up = {0, 0, 1};
    cam.fov_y_degrees = 35.0, cam.near_distance = 0.1, cam.far_distance = 100.0;
    const int size = 64;

    for (const fx::OpticalModel model : {fx::OpticalModel::EmissionAbsorption, fx::OpticalModel::Emission,
                                         fx::OpticalModel::Maximum}) {
        const fx::TransferFunction& tf = model == fx::OpticalModel::Maximum ? rising : varied;
        fx::CellRenderer gl(mesh, "s", tf);
        const fx::ScanlineRenderer scanline(mesh);
        fx::CalibrationFrame frame;
        frame.mesh = &mesh, frame.field = &mesh.scalars[0], frame.tf = &tf;
        frame.camera = cam, frame.width = size, frame.height = size, frame.model = model;
        const std::vector<fx::AutoCandidate> candidates = fx::auto_candidates(model);
        const std::vector<fx::PathCost> costs = fx::measure_path_costs(frame, candidates, fx::kDefaultAccuracy, &gl, &scanline);
        REQUIRE(costs.size() == candidates.size());
        for (const fx::PathCost& c : costs) {
            INFO(fx::candidate_name(c.candidate));
            // Measured where it may be picked (finite, never negative), NaN where its error is out.
            if (c.stated_error <= fx::kDefaultAccuracy) CHECK((std::isfinite(c.fixed_ms) && c.fixed_ms >= 0.0 && c.ms_per_pixel >= 0.0));
            else CHECK(std::isnan(c.fixed_ms));
        }
        const fx::PathChoice choice = fx::choose_path(costs, fx::kDefaultAccuracy, size, size);
        WARN(choice.reason);

        fx::ScanlineOptions so;
        so.model = model;
        const fx::Image expected = scanline.render(cam, size, size, mesh.scalars[0], tf, so);
        // Whatever auto picks here, and whatever it would pick on another machine: every
        // candidate it may pick passes its own stated check, the pick included.
        bool picked_checked = false;
        for (const fx::PathCost& c : costs) {
            if (!(c.stated_error <= fx::kDefaultAccuracy)) continue;
            const fx::Image actual = c.candidate.scanline ? scanline.render(cam, size, size, mesh.scalars[0], tf, so)
                                                          : gl.render_to_image(cam, size, size, c.candidate.gl);
            fx_test::require_no_gl_error();
            // The scan-line renderer's stated bound is against closed forms; against itself it
            // gives the same bits (frames do not depend on the thread count).
            const verify::Tolerance tol = c.candidate.scanline
                                              ? verify::same_picture(0.0, "the reference itself")
                                              : verify::stated(verify::path_of(c.candidate.gl), verify::Case{18, 0.15, false, false});
            fx_test::check_frame(std::string("auto_") + fx::candidate_name(c.candidate) + "_model" + std::to_string(int(model)),
                                 actual, expected, tol);
            picked_checked = picked_checked || c.candidate == choice.candidate;
        }
        CHECK(picked_checked);
    }
}
