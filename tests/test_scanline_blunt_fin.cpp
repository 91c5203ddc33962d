// Scan-line renderer on the real NASA blunt-fin data (PLOT3D, density) against a stored
// regression frame. tests/data/scanline/README.md says how the frame was made (the `cellfx
// render` command line and the commit); the camera, transfer function and size here are the
// same ones, so any change to what the renderer draws for real data shows up here.
#include <catch2/catch.hpp>

#include "fx/camera.hpp"
#include "fx/image.hpp"
#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "scanline_test_support.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using namespace scanline_test;

namespace {

// Must match tests/data/scanline/README.md.
constexpr const char* kCamera = "eye=-12,16,27,target=3.3,3.4,2.9,up=0,1,0,fov=40,near=0.01";
constexpr int kWidth = 160, kHeight = 100;

// The golden frame is this renderer's own float output (PFM) from an earlier commit, so the
// comparison guards changes to the renderer (speed work, refactoring) rather than its
// agreement with a closed form. Allowed: float rounding in a changed pipeline — screen-space
// vertices stored as float move pixel-centre/edge positions by ~1e-5 px at this size, which
// changes a pixel by far less than 1e-5 away from silhouettes and by ~1e-5 at a silhouette,
// where the ray length through the mesh goes to zero. 1e-4 per channel (the closed-form
// tolerance) leaves room for that; a missed or doubled face, a wrong depth, scalar or
// transfer-function lookup changes pixels here by 1e-3 to 1e-1. (Measured after the
// renderer's speed work: max 6e-7, mean 6e-9.)
constexpr double kRegressionTolerance = 1e-4;
// Mean over all pixels and channels: rounding changes average far below 1e-7; a small
// systematic change (a depth scale off by 1e-4, a shifted transfer function) moves the
// mean by more than 1e-6 even where no single pixel passes the per-pixel limit.
constexpr double kRegressionMeanTolerance = 1e-6;

} // namespace

TEST_CASE("blunt fin (real PLOT3D data) matches the stored regression frame", "[scanline]") {
    const fx::CellMesh mesh = fx::read_mesh(fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin"),
                                            fx_test::source_path("content/meshes/blunt_fin/bluntfinq.bin"));
    const fx::ScalarField* density = mesh.find_scalar("density");
    REQUIRE(density);
    const fx::TransferFunction tf =
        fx::TransferFunction::read_json(fx_test::source_path("tests/data/scanline/blunt_fin_density_tf.json"));
    const fx::Camera camera = fx::Camera::parse(kCamera);
    const fx::ScanlineRenderer renderer(mesh);

    fx::ScanlineOptions options;
    options.model = fx::OpticalModel::EmissionAbsorption;
    for (unsigned threads : {1u, 2u}) {
        options.threads = threads;
        fx::ScanlineStats stats;
        const fx::Image frame = renderer.render(camera, kWidth, kHeight, *density, tf, options, &stats);
        INFO("threads " << threads);
        CHECK(stats.lost_segments == 0);
        CHECK(stats.triangles_active > 50000); // the whole fin is in view, not a corner of it

        // The PFM holds RGB composited over a background; black keeps the premultiplied
        // colour, white adds 1 − alpha, so the pair checks colour and opacity.
        for (const char* background : {"black", "white"}) {
            const std::string name = std::string("blunt_fin_density_") + background;
            const fx::Image golden = fx::read_pfm(fx_test::source_path("tests/data/scanline/" + name + ".pfm"));
            REQUIRE(golden.width == kWidth);
            REQUIRE(golden.height == kHeight);
            fx::Image actual = frame;
            fx::composite_over(actual, background[0] == 'b' ? glm::vec3(0.0f) : glm::vec3(1.0f));
            // The golden is not blank: enough pixels differ from the background to matter.
            std::size_t drawn = 0;
            for (const glm::vec4& p : golden.pixels) {
                const float bg = background[0] == 'b' ? 0.0f : 1.0f;
                drawn += std::abs(p.r - bg) + std::abs(p.g - bg) + std::abs(p.b - bg) > 0.05f ? 1 : 0;
            }
            CHECK(drawn > static_cast<std::size_t>(kWidth * kHeight / 5));
            scanline_test::check_close(actual, golden, kRegressionTolerance, "scanline_" + name, kRegressionMeanTolerance,
                                       "the renderer's own earlier frame: float rounding in a changed pipeline");
        }
    }
}
