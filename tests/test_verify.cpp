// The one image comparison (testing/verify): what it measures, what it lets pass and what not.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "fx/error.hpp"
#include "image_check.hpp"
#include "cellfx_names.hpp"

namespace {

// A bright disc of radius 6 on black, 16×16, its edge at `shift` px to the right.
fx::Image disc(float shift) {
    fx::Image img(16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const float dx = x + 0.5f - 8.0f - shift, dy = y + 0.5f - 8.0f;
            if (dx * dx + dy * dy < 36.0f) img.at(x, y) = glm::vec4(0.8f, 0.4f, 0.2f, 0.5f);
        }
    return img;
}

verify::Tolerance exactish() {
    verify::Tolerance t;
    t.pixel.of_peak = 0.005, t.mean.of_peak = 0.01, t.share_beyond = 0.1;
    return t;
}

} // namespace

TEST_CASE("verify: images of different sizes are refused, naming both", "[verify]") {
    CHECK_THROWS_WITH(verify::measure(fx::Image(4, 3), fx::Image(3, 4)),
                      Catch::Contains("the frame is 4x3, the reference 3x4"));
}

TEST_CASE("verify: figures relative to the reference's peak", "[verify]") {
    fx::Image expected(4, 4, glm::vec4(0.0f)), actual(4, 4, glm::vec4(0.0f));
    expected.at(1, 1) = glm::vec4(2.0f, 0.0f, 0.0f, 0.0f);
    actual.at(1, 1) = glm::vec4(1.9f, 0.0f, 0.0f, 0.0f);
    actual.at(3, 2) = glm::vec4(0.0f, 0.0f, 0.0f, 0.02f);
    const verify::Difference d = verify::measure(actual, expected);
    CHECK(d.peak == 2.0);
    CHECK(verify::peak(expected) == 2.0);
    verify::Options alpha_left_out;
    alpha_left_out.channels = 3;
    CHECK(verify::peak(actual, alpha_left_out) == Approx(1.9)); // its alpha 0.02 is not compared
    CHECK(d.worst.x == 1);
    CHECK(d.worst.y == 1);
    CHECK(d.worst.delta == Approx(0.1).epsilon(1e-6));
    CHECK(d.mean == Approx((0.1 + 0.02) / 64.0).epsilon(1e-6));
    CHECK(d.of_peak(d.mean) == Approx(d.mean / 2.0));
    CHECK(d.rms == Approx(std::sqrt((0.01 + 0.0004) / 64.0)).epsilon(1e-5));
    CHECK(d.beyond == 0); // no bound: figures only
}

TEST_CASE("verify: NaN and Inf are counted and fail any tolerance", "[verify]") {
    fx::Image expected = disc(0.0f), actual = expected;
    actual.at(8, 8).g = NAN;
    actual.at(2, 2).a = INFINITY;
    verify::Tolerance loose;
    loose.pixel.absolute = 1e9, loose.mean.absolute = 1e9, loose.share_beyond = 1.0;
    const verify::Difference d = verify::measure(actual, expected, loose);
    CHECK(d.nonfinite == 2);
    CHECK(std::isinf(d.worst.delta));
    CHECK_THAT(verify::failures(d, loose), Catch::Contains("2 values NaN or infinite"));
}

TEST_CASE("verify: a silhouette a fraction of a pixel away passes, a stray pixel does not", "[verify]") {
    const fx::Image expected = disc(0.0f);
    // The edge moved by 0.3 px: pixels along one side change by the disc's whole value, but each
    // shows what the reference shows next to it.
    const verify::Difference shifted = verify::measure(disc(0.3f), expected, exactish());
    CHECK(shifted.beyond > 0);
    CHECK(shifted.outliers == 0);
    CHECK(verify::within(shifted, exactish()));
    // One pixel inside the disc twice as bright: beyond the bound and outside the reference's
    // range around it — a wrong pixel however few share it.
    fx::Image stray = expected;
    stray.at(8, 8) *= 2.0f;
    const verify::Difference d = verify::measure(stray, expected, exactish());
    CHECK(d.beyond == 1);
    CHECK(d.outliers == 1);
    CHECK(d.worst_outlier.x == 8);
    CHECK_THAT(verify::failures(d, exactish()), Catch::Contains("1 pixels beyond the bound and outside"));
    // Away from edges a share beyond the stated one fails, even within the reference's range.
    fx::Image patch = expected;
    for (int y = 6; y < 10; ++y)
        for (int x = 6; x < 10; ++x) patch.at(x, y) *= 0.98f; // 1.6% of peak: beyond 0.5%, inside the disc
    verify::Tolerance lenient = exactish();
    lenient.worst.relative = 0.05; // within 5% of its value: not an outlier
    const verify::Difference flat = verify::measure(patch, expected, lenient);
    CHECK(flat.beyond == 16);
    CHECK(flat.beyond_flat == 16);
    CHECK(flat.outliers == 0);
    CHECK(verify::within(flat, lenient));
    lenient.share_beyond = 0.01;
    CHECK_THAT(verify::failures(flat, lenient), Catch::Contains("of the pixels beyond the per-pixel bound away from any edge"));
    // Edge pixels do not count against the share: they are bounded by the range alone.
    CHECK(shifted.beyond_flat == 0);
}

TEST_CASE("verify: the mean bound, the unit range, skipped pixels and an 8-bit reference", "[verify]") {
    const fx::Image expected = disc(0.0f);
    fx::Image dimmer = expected;
    for (glm::vec4& p : dimmer.pixels) p *= 0.99f;
    verify::Tolerance t = exactish();
    t.pixel.of_peak = 0.02, t.mean.of_peak = 1e-4;
    CHECK_THAT(verify::failures(verify::measure(dimmer, expected, t), t), Catch::Contains("mean"));

    fx::Image bright = expected;
    bright.at(8, 8).r = 1.5f;
    verify::Tolerance unit = verify::same_picture(1.0, "test");
    unit.unit_range = true;
    CHECK_THAT(verify::failures(verify::measure(bright, expected, unit), unit), Catch::Contains("outside [0, 1]"));

    std::vector<std::uint8_t> skip(expected.pixels.size(), 0);
    skip[expected.index(8, 8)] = 1;
    verify::Options o;
    o.skip = &skip;
    const verify::Tolerance same = verify::same_picture(0.0, "test");
    const verify::Difference masked = verify::measure(bright, expected, same, o);
    CHECK(masked.compared == expected.pixels.size() - 1);
    CHECK(verify::within(masked, same));

    fx::Image hdr = expected, clamped = expected;
    hdr.at(8, 8).r = 3.0f, clamped.at(8, 8).r = 1.0f;
    verify::Options eight_bit;
    eight_bit.clamp_expected = true;
    CHECK(verify::within(verify::measure(clamped, hdr, same, eight_bit), same));
    CHECK_FALSE(verify::within(verify::measure(clamped, hdr, same), same));
}

TEST_CASE("verify: the stated tolerances say why, and the failure images are written", "[verify]") {
    for (verify::Path p : verify::kPaths) {
        INFO(verify::path_name(p));
        const verify::Tolerance t = verify::stated(p);
        CHECK_FALSE(t.why.empty());
        CHECK(t.outlier_radius == 1);
        CHECK(t.share_beyond <= 0.01);
        CHECK(t.pixel.at(1.0, 1.0) > 0.0);
        CHECK(t.mean.at(1.0, 0.0) > 0.0);
    }
    // Classic pcp rounds per cell: its bound grows with the cells on a ray.
    verify::Case many;
    many.cells_on_ray = 40;
    CHECK(verify::stated(verify::Path::Pcp, many).pixel.at(1.0, 0.0) >
          verify::stated(verify::Path::Pcp).pixel.at(1.0, 0.0));
    CHECK(verify::path_of(fx::RenderPath::PcpExact, true) == verify::Path::PcpExactFog);
    CHECK(verify::model_of(verify::Path::Mip) == fx::OpticalModel::Maximum);

    const std::string prefix = verify::write_images(fx_test::output_path("verify_selftest"), disc(0.5f), disc(0.0f),
                                                    verify::stated(verify::Path::PcpExact));
    for (const char* suffix : {"_actual.png", "_expected.png", "_diff.png"})
        CHECK(std::filesystem::exists(prefix + suffix));
}
