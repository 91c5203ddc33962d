// Every input that once crashed, hung or misled a reader (tests/data/fuzz_regressions/<target>/,
// see its README), and every seed of the fuzz corpus (tests/fuzz/corpus/<target>/), fed to
// its reader with the fuzz targets' own checks (tests/fuzz/fuzz_checks.hpp): each must parse
// to a well-formed result or throw fx::Error naming the source. Under CELLFX_SANITIZE=1 the
// same inputs run with AddressSanitizer and UBSan.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "fuzz/fuzz_checks.hpp"
#include "io_test_helpers.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using Check = std::function<std::string(const std::uint8_t*, std::size_t)>;

// Files of a folder in name order, README excepted.
std::vector<fs::path> inputs_in(const std::string& relative) {
    std::vector<fs::path> files;
    const fs::path dir = fx_test::source_path(relative);
    if (!fs::is_directory(dir)) return files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string check_file(const Check& check, const fs::path& path) {
    const std::string bytes = fx_test::read_bytes(path.string());
    return check(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

void check_folder(const std::string& target, const Check& check, std::size_t at_least) {
    std::size_t files = 0;
    for (const char* root : {"tests/data/fuzz_regressions/", "tests/fuzz/corpus/"}) {
        for (const fs::path& path : inputs_in(root + target)) {
            INFO(path.string());
            CHECK(check_file(check, path) == "");
            ++files;
        }
    }
    CHECK(files >= at_least); // the folders are there and were read
}

} // namespace

TEST_CASE("Fuzz regressions and seeds: VTK legacy", "[io][vtk][fuzz]") {
    check_folder("vtk_legacy", fx_fuzz::check_vtk_legacy, 30);
}

TEST_CASE("Fuzz regressions and seeds: PLOT3D grid and q", "[io][plot3d][fuzz]") {
    check_folder("plot3d", fx_fuzz::check_plot3d, 60);
}

TEST_CASE("Fuzz regressions and seeds: AVS UCD", "[io][ucd][fuzz]") {
    check_folder("avs_ucd", fx_fuzz::check_avs_ucd, 8);
}

TEST_CASE("Fuzz regressions and seeds: transfer-function JSON", "[transfer][fuzz]") {
    check_folder("transfer_function", fx_fuzz::check_transfer_function, 7);
}

TEST_CASE("Fuzz regressions and seeds: PNG height fields", "[terrain][fuzz]") {
    check_folder("height_field_png", fx_fuzz::check_height_field_png, 8);
}

TEST_CASE("Fuzz regressions and seeds: scene files", "[terrain][fuzz]") {
    const std::string scenes = fx_test::source_path("content/scenes");
    check_folder("scene", [&](const std::uint8_t* d, std::size_t n) { return fx_fuzz::check_scene(d, n, scenes); }, 5);
}

TEST_CASE("A folder where a file belongs is an fx::Error, not bad_alloc", "[io][fuzz]") {
    const std::string folder = fx_test::source_path("content");
    CHECK_THAT(fx_test::error_message([&] { fx::read_mesh(folder); }), Contains(folder + ": is a folder, not a mesh file"));
    CHECK_THAT(fx_test::error_message([&] { fx::TransferFunction::read_json(folder); }), Contains(folder + ": is a folder"));
    CHECK_THAT(fx_test::error_message([&] { terrain::read_height_field_png(folder); }), Contains(folder + ": is a folder"));
}

TEST_CASE("Fuzz regressions: what each input must now say", "[io][fuzz]") {
    const std::function<void(const std::vector<char>&)> parse[] = {
        [](const std::vector<char>& d) { fx::parse_vtk_legacy(d, "f.vtk"); },
        [](const std::vector<char>& d) { fx::parse_avs_ucd(d, "f.inp"); },
        [](const std::vector<char>& d) {
            const fx_fuzz::Plot3dInput in = fx_fuzz::split_plot3d_input(reinterpret_cast<const std::uint8_t*>(d.data()), d.size());
            fx::parse_plot3d(in.xyz, "f.xyz", in.q ? &*in.q : nullptr, "f.q");
        },
        [](const std::vector<char>& d) { fx::TransferFunction::parse_json(std::string_view(d.data(), d.size()), "f.json"); },
        [](const std::vector<char>& d) {
            terrain::HeightFieldOptions pad;
            pad.pad = true;
            terrain::parse_height_field_png(d, "f.png", pad);
        },
        [](const std::vector<char>& d) {
            terrain::parse_scene(std::string_view(d.data(), d.size()), "f.scene", fx_test::source_path("content/scenes"));
        },
    };
    enum { Vtk, Ucd, Plot3d, Json, Png, Scene };
    struct Expected {
        int reader;
        const char* file;
        const char* message;
    };
    const char* const kNoPlot3dReading = "byte 0: not a PLOT3D grid file: no reading of the header";
    const Expected expected[] = {
        // Found bugs (see the README beside the files).
        {Vtk, "vtk_legacy/point_data_before_points.vtk", "f.vtk: line 8: POINTS 4 does not match the earlier POINT_DATA 2"},
        {Vtk, "vtk_legacy/point_data_before_points_structured.vtk", "f.vtk: line 9: POINTS 4 does not match the earlier POINT_DATA 2"},
        {Json, "transfer_function/deeply_nested_point.json", "f.json: points[0]: expected 5 numbers [s, r, g, b, sigma], got an array of 1 entry"},
        {Json, "transfer_function/deeply_nested_sigma.json", "f.json: points[0]: sigma is not a number (an array of 1 entry)"},
        {Plot3d, "plot3d/dims_product_wraps_to_zero.grid", kNoPlot3dReading},
        // Its header and size fit one variant whose two data markers both claim 2 GiB.
        {Plot3d, "plot3d/record_marker_claims_2gib.grid",
         "f.xyz: byte 20: a damaged or lying record marker: the record marker at byte 20 (opening a block's coordinates) "
         "says 2147483647 bytes, but the record holds 96"},
        {Png, "height_field_png/chunk_claims_1gib.png", "f.png: byte 33: truncated PNG: chunk \"IDAT\" claims 1090519170 bytes"},
        {Scene, "scene/number_overflow_1e999.json", "(at surface.sun[0]): the number -0.351e999 is beyond the range of a double"},
        {Scene, "scene/height_map_is_a_folder.json", "is a folder, not a height map"},
        {Scene, "scene/camera_path_without_keys.json", "f.scene: camera_path.keys: is required"},
        {Vtk, "vtk_legacy/claims_2e63_cell_data.vtk", "f.vtk: line 7: SCALARS \"s\": absurd count 9223372036854775807"},
        // Headers that claim far more than the file holds: an error before anything is allocated
        // (under AddressSanitizer an allocation of that size would abort the test).
        {Vtk, "vtk_legacy/claims_2e31_points_ascii.vtk", "f.vtk: line 6: truncated POINTS: 6442450944 values announced"},
        {Vtk, "vtk_legacy/claims_2e31_points_binary.vtk", "f.vtk: byte 90: truncated POINTS: needs 51539607552 bytes, 9 left"},
        {Vtk, "vtk_legacy/claims_2e31_cells.vtk", "f.vtk: line 8: truncated CELLS: 4294967296 values announced"},
        {Vtk, "vtk_legacy/claims_2e32_connectivity.vtk", "f.vtk: line 11: truncated CONNECTIVITY: 4294967296 values announced"},
        {Vtk, "vtk_legacy/claims_2e31_lookup_entries.vtk", "f.vtk: line 9: truncated LOOKUP_TABLE"},
        {Vtk, "vtk_legacy/claims_2e31_field_arrays.vtk", "f.vtk: line 5: FIELD array count 2147483648 is more than the file can hold"},
        {Vtk, "vtk_legacy/claims_2e93_structured_nodes.vtk", "f.vtk: line 7: DIMENSIONS 2147483648 x 2147483648 x 2147483648 do not match the 8 points"},
        {Ucd, "avs_ucd/claims_2e31_nodes.inp", "f.inp: line 2: number of nodes 2147483648 is more than the rest of the file can hold"},
        {Ucd, "avs_ucd/claims_2e31_node_data.inp", "f.inp: line 1: node data length 2147483648 is more than the rest of the file can hold"},
        {Plot3d, "plot3d/claims_int32_max_dims.grid", kNoPlot3dReading},
        {Plot3d, "plot3d/claims_int32_max_blocks.grid", kNoPlot3dReading},
        {Plot3d, "plot3d/q_claims_2e90_nodes.grid_q", "f.q: byte 0: q file header does not read as big-endian"},
        {Png, "height_field_png/claims_16385x16385.png", "f.png: truncated PNG: 12 bytes of pixel data cannot hold the 268468225 bytes"},
    };
    for (const Expected& e : expected) {
        INFO(e.file);
        const std::string bytes = fx_test::read_bytes(fx_test::source_path(std::string("tests/data/fuzz_regressions/") + e.file));
        REQUIRE(!bytes.empty());
        const std::vector<char> data(bytes.begin(), bytes.end());
        CHECK_THAT(fx_test::error_message([&] { parse[e.reader](data); }), Contains(e.message));
    }
}

TEST_CASE("Fuzz regression: rescaling onto a narrow range merges points into a step", "[transfer][fuzz]") {
    // s = 0, 1, 1, 2.1e94 onto [1e-7, 2e-7]: the first three land on s = 1e-7, which used to make
    // rescaled() throw "appears more than twice". The first and last of the run form a step.
    const std::string text = fx_test::read_bytes(fx_test::source_path("tests/data/fuzz_regressions/transfer_function/rescaled_points_merge.json"));
    const fx::TransferFunction tf = fx::TransferFunction::parse_json(text, "merge.json").rescaled(1e-7, 2e-7);
    REQUIRE(tf.points().size() == 3);
    CHECK(tf.points()[0].s == 1e-7);
    CHECK(tf.points()[1].s == 1e-7);
    CHECK(tf.points()[2].s == 2e-7);
    CHECK(tf.sigma(0.5e-7) == 0.0); // below the step: the first point's value
    CHECK(tf.sigma(1e-7) == 3.0);   // from above: the run's last point
}
