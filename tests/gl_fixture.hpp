// Headless GL for tests: one context per test process; frame tests compare through image_check.hpp.
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

#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include "harness/headless_context.hpp"
#include "image_check.hpp"
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

} // namespace fx_test
