// The resource budget: names, overrides, messages, and what readers check against it before
// they allocate (docs/robustness.md, "Resource limits").
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/resource_limits.hpp"
#include "fx/transfer_function.hpp"
#include "io/input_file.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

// Sets limits for one scope and puts the old ones back.
struct ScopedLimits {
    fx::ResourceLimits saved = fx::resource_limits();
    explicit ScopedLimits(const std::string& assignment) {
        fx::ResourceLimits l = saved;
        fx::apply_limit(l, assignment);
        fx::set_resource_limits(l);
    }
    ~ScopedLimits() { fx::set_resource_limits(saved); }
};

} // namespace

TEST_CASE("limits parse by name and explain themselves", "[limits]") {
    fx::ResourceLimits l;
    fx::apply_limit(l, "mesh-cells=1e9");
    CHECK(l.mesh_cells == 1000000000u);
    fx::apply_limit(l, "input-wait=3");
    CHECK(l.input_wait_seconds == 3u);
    CHECK_THROWS_WITH(fx::apply_limit(l, "cells=5"), Catch::Contains("unknown limit 'cells'") && Catch::Contains("mesh-cells"));
    CHECK_THROWS_WITH(fx::apply_limit(l, "mesh-cells=-1"), Catch::Contains("not a whole number of cells"));
    CHECK_THROWS_WITH(fx::apply_limit(l, "mesh-cells=2.5"), Catch::Contains("not a whole number"));
    CHECK_THROWS_WITH(fx::apply_limit(l, "mesh-cells"), Catch::Contains("needs a value"));
    for (int i = 0; i < fx::kLimitCount; ++i) {
        const auto limit = static_cast<fx::Limit>(i);
        CHECK_THAT(fx::describe_limits(l), Catch::Contains(fx::limit_name(limit)));
    }
    CHECK(fx::over_limit(fx::Limit::MeshPoints, 40000000, "big.vtk: line 5: POINTS") ==
          "big.vtk: line 5: POINTS needs 40,000,000 points, over the mesh-points limit of 16,777,216 (raise it with "
          "--limit mesh-points=N or fx::ResourceLimits::mesh_points)");
}

TEST_CASE("inputs are read within their byte budget, regular files before reading", "[limits][io]") {
    const std::string path = fx_test::output_path("limits_tf.json");
    std::ofstream(path) << R"({"points": [[0, 1, 1, 1, 1]]})";
    CHECK_NOTHROW(fx::TransferFunction::read_json(path));
    {
        const ScopedLimits small("json-bytes=10");
        CHECK_THROWS_WITH(fx::TransferFunction::read_json(path),
                          Catch::StartsWith(path + ": the transfer function file needs 29 bytes, over the json-bytes limit of 10"));
    }
    {
        // A device is read up to the budget, no further.
        const ScopedLimits small("file-bytes=4096");
        CHECK_THROWS_WITH(fx::io::read_input_file("/dev/urandom", fx::Limit::FileBytes, "mesh file"),
                          Catch::Contains("not a regular file") && Catch::Contains("file-bytes limit of 4,096"));
    }
    CHECK_THROWS_WITH(fx::io::read_input_file("/dev/zero", fx::Limit::JsonBytes, "scene file",
                                              [](std::string_view head) { fx::io::check_json_encoding(head, "z"); }),
                      Catch::StartsWith("z: byte 0 is a NUL"));
}

TEST_CASE("readers check counts against the budget before allocating", "[limits][io]") {
    const ScopedLimits small("mesh-cells=1000");
    CHECK_THROWS_WITH(fx::read_mesh(fx_test::source_path("content/meshes/hexa_grid/hexa.vtk")),
                      Catch::Contains("hexa.vtk: line") && Catch::Contains("CELLS needs 10,648 cells, over the mesh-cells limit of 1,000"));
    CHECK_THROWS_WITH(fx::read_mesh(fx_test::source_path("content/meshes/blunt_fin/bluntfinxyz.bin")),
                      Catch::Contains("bluntfinxyz.bin: byte 0: the grid's cells needs 37,479 cells"));
}
