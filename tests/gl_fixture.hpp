// Headless GL for tests: one context per test process, plus helpers shared by frame tests.
//
// Usage in a [gl] test:
//     TEST_CASE("my frame", "[gl]") {
//         fx_test::gl_context();            // creates the context on first use, makes it current
//         ...
//     }
// The context is fx::HeadlessContext with default options (CELLFX_EGL_PLATFORM may force the
// platform). If it cannot be created, every [gl] test fails with the reason (Catch2 v2 has no
// SKIP). It lives until the process exits; GL objects made by a test must be destroyed by the
// end of that test. Tests that leave unusual GL state behind must restore it (or use their own
// HeadlessContext) so that later tests start from GL defaults.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>
#include <glm/common.hpp>
#include <epoxy/gl.h>

#include "fx/headless_context.hpp"
#include "fx/image.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace fx_test {

inline fx::HeadlessContext& gl_context() {
    // A throwing initialiser is retried on the next call, so each test reports the failure.
    static fx::HeadlessContext context;
    context.make_current();
    return context;
}

// Fails the current test if GL has an error flag set (and clears it).
inline void require_no_gl_error() {
    const GLenum error = glGetError();
    INFO("glGetError() = 0x" << std::hex << error);
    REQUIRE(error == GL_NO_ERROR);
}

struct ImageDifference {
    float max_delta = 0.0f;  // largest |actual − expected| over all channels
    double mean_delta = 0.0; // mean over all channels of all pixels
};

// Per-channel difference of two images of the same size (REQUIREs equal sizes).
inline ImageDifference compare_images(const fx::Image& actual, const fx::Image& expected) {
    REQUIRE(actual.width == expected.width);
    REQUIRE(actual.height == expected.height);
    ImageDifference d;
    double sum = 0.0;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        for (int c = 0; c < 4; ++c) {
            const float delta = std::fabs(actual.pixels[i][c] - expected.pixels[i][c]);
            d.max_delta = std::max(d.max_delta, std::isnan(delta) ? INFINITY : delta);
            sum += delta;
        }
    }
    d.mean_delta = actual.pixels.empty() ? 0.0 : sum / (4.0 * static_cast<double>(actual.pixels.size()));
    return d;
}

// Writes <name>_actual.png, <name>_expected.png and <name>_diff.png (|a − e| scaled by
// `diff_gain`, alpha 1) into the test output folder; returns the folder's "<name>" prefix.
inline std::string write_failure_images(const std::string& name, const fx::Image& actual,
                                        const fx::Image& expected, float diff_gain = 10.0f) {
    fx::Image diff(actual.width, actual.height);
    for (std::size_t i = 0; i < diff.pixels.size() && i < expected.pixels.size(); ++i) {
        const glm::vec4 d = glm::abs(actual.pixels[i] - expected.pixels[i]) * diff_gain;
        diff.pixels[i] = glm::vec4(d.r, d.g, d.b, 1.0f);
    }
    const std::string prefix = output_path(name);
    fx::write_png(actual, prefix + "_actual.png");
    fx::write_png(expected, prefix + "_expected.png");
    fx::write_png(diff, prefix + "_diff.png");
    return prefix;
}

} // namespace fx_test
