// The frame tests' one image comparison: cellfx_verify (testing/verify) measured, printed and
// checked under Catch2, with the failure images written into the test output folder.
//
//     const verify::Tolerance tol = verify::stated(verify::Path::PcpExact);   // the path's own
//     fx_test::check_frame("box", actual, expected, tol);   // the reference must show something
//     fx_test::check_image("tiles", tiled, whole, tol);     // any two pictures
//
// Both print the figures (WARN), CHECK that `tol` holds (naming what broke it and why the bound
// is what it is), and on failure write <name>_actual/expected/diff.png under build/tests/output.
// Images of different sizes fail the test with both sizes named.
#pragma once

#include <string>

#include <catch2/catch.hpp>

#include "test_paths.hpp"
#include "verify/image_difference.hpp"
#include "verify/tolerances.hpp"
#include "cellfx_names.hpp"

namespace verify = cellfx::verify;

namespace fx_test {

inline verify::Difference check_image(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                                      const verify::Tolerance& tol, const verify::Options& options = {}) {
    const verify::Difference d = verify::measure(actual, expected, tol, options);
    WARN(name << ": " << verify::describe(d));
    const std::string broken = verify::failures(d, tol);
    if (!broken.empty()) {
        const std::string prefix = verify::write_images(output_path(name), actual, expected, tol, options);
        FAIL_CHECK(name << ": " << broken << " (" << tol.why << "); images " << prefix << "_*.png");
    }
    return d;
}

// check_image against a reference that must show something (peak > 0): a blank reference
// would let any blank frame pass.
inline verify::Difference check_frame(const std::string& name, const fx::Image& actual, const fx::Image& expected,
                                      const verify::Tolerance& tol, const verify::Options& options = {}) {
    const verify::Difference d = check_image(name, actual, expected, tol, options);
    INFO(name << ": the reference is blank");
    REQUIRE(d.peak > 0.0);
    return d;
}

} // namespace fx_test
