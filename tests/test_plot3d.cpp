#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "fx/cell_mesh.hpp"
#include "fx/plot3d.hpp"
#include "io_test_helpers.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

using Catch::Matchers::Contains;

namespace {

std::string mesh_path(const std::string& relative) { return fx_test::source_path("content/meshes/" + relative); }

fx::ScalarRange range_of(const fx::CellMesh& mesh, const char* name) {
    const fx::ScalarField* f = mesh.find_scalar(name);
    REQUIRE(f);
    return fx::scalar_range(*f);
}

// Two small curved blocks with q data; block 0 has one blanked interior node.
std::vector<fx::Plot3dBlock> synthetic_blocks() {
    std::vector<fx::Plot3dBlock> blocks(2);
    blocks[0].dims = {3, 4, 2};
    blocks[1].dims = {2, 2, 5};
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        fx::Plot3dBlock& block = blocks[b];
        const auto& d = block.dims;
        for (std::uint32_t k = 0; k < d[2]; ++k)
            for (std::uint32_t j = 0; j < d[1]; ++j)
                for (std::uint32_t i = 0; i < d[0]; ++i) {
                    const double x = i + 0.1 * std::sin(j + 0.3 * k) + 10.0 * b, y = j * 1.25, z = k * 0.5 - 0.01 * i * j;
                    block.points.push_back({x, y, z});
                    block.iblank.push_back(b == 0 && i == 1 && j == 1 && k == 0 ? 0 : (i % 2 ? -1 : 1));
                    block.q[0].push_back(1.0 + 0.01 * (i + j + k));
                    block.q[1].push_back(3.0 * x);
                    block.q[2].push_back(-4.0 * y);
                    block.q[3].push_back(0.5 * z);
                    block.q[4].push_back(2.5 + b);
                }
        block.reference = {0.5 + b, 2.0, 1e6 * (b + 1), 0.25 * b};
    }
    return blocks;
}

double rounded(double v, bool double_precision) { return double_precision ? v : double(float(v)); }

} // namespace

TEST_CASE("PLOT3D blunt fin: big-endian single-block float grid and q with trailing bytes", "[io][plot3d]") {
    std::vector<std::string> notes;
    const auto start = std::chrono::steady_clock::now();
    const fx::Plot3dData data = fx::read_plot3d(mesh_path("blunt_fin/bluntfinxyz.bin"), mesh_path("blunt_fin/bluntfinq.bin"), &notes);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    WARN("blunt fin xyz+q read in " << ms << " ms");
    const fx::CellMesh& mesh = data.mesh;
    CHECK(data.format == fx::Plot3dFormat{true, false, false, false, false});
    CHECK(mesh.point_count() == 40960);
    CHECK(mesh.cell_count() == 37479);
    REQUIRE(mesh.blocks.size() == 1);
    CHECK(mesh.blocks[0].dims == std::array<std::uint32_t, 3>{40, 32, 32});
    CHECK(mesh.blocks[0].cell_count == 37479);
    const fx::Bounds b = fx::mesh_bounds(mesh);
    CHECK(b.lo.x == Approx(-7.816).margin(1e-3));
    CHECK(b.hi.x == Approx(14.362).margin(1e-3));
    CHECK(b.lo.y == Approx(0.0).margin(1e-3));
    CHECK(b.hi.y == Approx(8.328).margin(1e-3));
    CHECK(b.hi.z == Approx(5.724).margin(1e-3));
    REQUIRE(data.references.size() == 1);
    CHECK(data.references[0].mach == Approx(2.95));
    CHECK(data.references[0].alpha == Approx(0.0));
    CHECK(data.references[0].reynolds == Approx(2.1e6));
    CHECK(data.references[0].time == Approx(1.3911).margin(1e-4));
    const fx::ScalarRange density = range_of(mesh, "density");
    CHECK(density.lo == Approx(0.1926).margin(1e-4));
    CHECK(density.hi == Approx(4.9775).margin(1e-4));
    const fx::ScalarRange energy = range_of(mesh, "energy");
    CHECK(energy.lo == Approx(0.769).margin(1e-3));
    CHECK(energy.hi == Approx(25.161).margin(1e-3));
    CHECK(range_of(mesh, "momentum_x").hi == Approx(5.79).margin(0.01));
    CHECK(range_of(mesh, "momentum_z").lo == Approx(-3.73).margin(0.01));
    CHECK(mesh.find_scalar("momentum_magnitude"));
    CHECK(fx_test::notes_contain(notes, "ignored 484 trailing bytes (0 non-zero)"));
    CHECK(fx_test::notes_contain(notes, "Mach 2.95"));
    // The first cell is the i-fastest VTK hexahedron on nodes 0, 1, 41, 40, 1280, ...
    const std::uint32_t* v = mesh.cell_vertices(0);
    CHECK(v[0] == 0);
    CHECK(v[1] == 1);
    CHECK(v[2] == 41);
    CHECK(v[3] == 40);
    CHECK(v[4] == 1280);
    CHECK(v[6] == 1321);
}

TEST_CASE("PLOT3D multi-bin: little-endian, record markers, float64, two blocks", "[io][plot3d]") {
    std::vector<std::string> notes;
    const fx::Plot3dData data =
        fx::read_plot3d(mesh_path("blunt_fin_2block/multi-bin.xyz"), mesh_path("blunt_fin_2block/multi-bin.q"), &notes);
    CHECK(data.format == fx::Plot3dFormat{false, true, true, false, true});
    const fx::CellMesh& mesh = data.mesh;
    REQUIRE(mesh.blocks.size() == 2);
    for (const fx::Block& block : mesh.blocks) {
        CHECK(block.dims == std::array<std::uint32_t, 3>{8, 12, 12});
        CHECK(block.cell_count == 7 * 11 * 11);
    }
    CHECK(mesh.blocks[1].first_cell == 7 * 11 * 11);
    CHECK(mesh.point_count() == 2 * 8 * 12 * 12);
    // Block 0 and block 1 overlap in x; check each block's own x range.
    double lo0 = 1e9, hi0 = -1e9, lo1 = 1e9, hi1 = -1e9;
    for (std::size_t p = 0; p < 1152; ++p) lo0 = std::min(lo0, mesh.points[p].x), hi0 = std::max(hi0, mesh.points[p].x);
    for (std::size_t p = 1152; p < 2304; ++p) lo1 = std::min(lo1, mesh.points[p].x), hi1 = std::max(hi1, mesh.points[p].x);
    CHECK(lo0 == Approx(-7.816).margin(1e-3));
    CHECK(hi0 == Approx(0.444).margin(1e-3));
    CHECK(lo1 == Approx(-1.002).margin(1e-3));
    CHECK(hi1 == Approx(14.362).margin(1e-3));
    REQUIRE(data.references.size() == 2);
    CHECK(mesh.find_scalar("density")->values.size() == 2304);
    CHECK(!fx_test::notes_contain(notes, "trailing"));
}

TEST_CASE("PLOT3D combustor and LOx post (shared data, with IBLANK)", "[io][plot3d][shared-data]") {
    // 5.4 MB of PLOT3D between them: read from the shared data rather than shipped in content/.
    const std::string comb = fx_test::shared_data_path("combustor/combxyz.bin");
    const std::string post = fx_test::shared_data_path("lox_post/postxyz.bin");
    const fx::Plot3dData c = fx::read_plot3d(comb, fx_test::shared_data_path("combustor/combq.bin"));
    CHECK(c.mesh.cell_count() == 43008);
    CHECK(c.mesh.blocks[0].dims == std::array<std::uint32_t, 3>{57, 33, 25});
    CHECK(range_of(c.mesh, "density").lo == Approx(0.198).margin(1e-3));
    CHECK(range_of(c.mesh, "density").hi == Approx(0.710).margin(1e-3));
    CHECK(range_of(c.mesh, "energy").hi == 0.0f);

    std::vector<std::string> notes;
    const fx::Plot3dData p = fx::read_plot3d(post, fx_test::shared_data_path("lox_post/postq.bin"), &notes);
    CHECK(p.format == fx::Plot3dFormat{true, false, false, true, false});
    CHECK(p.mesh.point_count() == 109744);
    CHECK(p.blanked_cells == 0); // IBLANK values are -1 and 1 only
    CHECK(p.mesh.cell_count() == 37 * 75 * 37);
    CHECK(fx_test::notes_contain(notes, "IBLANK: dropped 0 cells"));
    REQUIRE(p.references.size() == 1);
    CHECK(p.references[0].mach == Approx(1.0));
    CHECK(p.references[0].alpha == Approx(1.0));
    CHECK(p.references[0].reynolds == Approx(1000.0));
    CHECK(p.references[0].time == Approx(46.0));
    CHECK(range_of(p.mesh, "density").lo == Approx(1.0));
    CHECK(range_of(p.mesh, "density").hi == Approx(1.0));
    CHECK(range_of(p.mesh, "energy").lo == Approx(-0.54).margin(0.01));
    CHECK(range_of(p.mesh, "energy").hi == Approx(4.40).margin(0.01));
}

TEST_CASE("PLOT3D every variant written by write_plot3d is detected and read back", "[io][plot3d]") {
    const std::vector<fx::Plot3dBlock> all = synthetic_blocks();
    int variants = 0;
    for (bool big_endian : {true, false})
        for (bool markers : {true, false})
            for (bool double_precision : {true, false})
                for (bool iblank : {true, false})
                    for (bool multi : {true, false}) {
                        const fx::Plot3dFormat format{big_endian, markers, double_precision, iblank, multi};
                        CAPTURE(fx::describe(format));
                        const std::vector<fx::Plot3dBlock> blocks(all.begin(), all.begin() + (multi ? 2 : 1));
                        const std::string xyz = fx_test::output_path("io_variant.xyz"), q = fx_test::output_path("io_variant.q");
                        fx::write_plot3d(blocks, format, xyz, q);
                        const fx::Plot3dData data = fx::read_plot3d(xyz, q);
                        CHECK(data.format == format);
                        const fx::CellMesh& mesh = data.mesh;
                        REQUIRE(mesh.blocks.size() == blocks.size());
                        std::size_t base = 0;
                        for (std::size_t b = 0; b < blocks.size(); ++b) {
                            CHECK(mesh.blocks[b].dims == blocks[b].dims);
                            for (std::size_t p = 0; p < blocks[b].points.size(); ++p) {
                                const glm::dvec3& want = blocks[b].points[p];
                                const glm::dvec3& got = mesh.points[base + p];
                                REQUIRE(got.x == rounded(want.x, double_precision));
                                REQUIRE(got.y == rounded(want.y, double_precision));
                                REQUIRE(got.z == rounded(want.z, double_precision));
                                REQUIRE(mesh.find_scalar("density")->values[base + p] == float(blocks[b].q[0][p]));
                                REQUIRE(mesh.find_scalar("momentum_y")->values[base + p] == float(blocks[b].q[2][p]));
                                REQUIRE(mesh.find_scalar("energy")->values[base + p] == float(blocks[b].q[4][p]));
                            }
                            REQUIRE(data.references.size() == blocks.size());
                            CHECK(data.references[b].mach == rounded(blocks[b].reference.mach, double_precision));
                            CHECK(data.references[b].reynolds == rounded(blocks[b].reference.reynolds, double_precision));
                            base += blocks[b].points.size();
                        }
                        // Block 0 has 6 cells, 4 of which touch its blanked node; block 1 has 4 cells.
                        CHECK(mesh.blocks[0].cell_count == (iblank ? 2u : 6u));
                        CHECK(data.blanked_cells == (iblank ? 4u : 0u));
                        CHECK(mesh.cell_count() == (iblank ? 2u : 6u) + (multi ? 4u : 0u));
                        ++variants;
                    }
    CHECK(variants == 32);
}

TEST_CASE("PLOT3D bad input: errors name the file, the byte or block, and the problem", "[io][plot3d]") {
    const std::vector<fx::Plot3dBlock> blocks = synthetic_blocks();

    SECTION("NaN coordinate names the block, point and byte") {
        std::vector<fx::Plot3dBlock> bad = blocks;
        bad[1].points[3].y = std::numeric_limits<double>::quiet_NaN();
        const std::string xyz = fx_test::output_path("io_nan.xyz");
        fx::write_plot3d(bad, fx::Plot3dFormat{true, false, false, false, true}, xyz);
        const std::string m = fx_test::error_message([&] { fx::read_plot3d(xyz); });
        CHECK_THAT(m, Contains(xyz) && Contains("byte") && Contains("block 1: point 3") && Contains("non-finite"));
    }
    SECTION("negative and absurd dims are not a PLOT3D header") {
        for (std::int32_t bad : {-5, 0, 1 << 30}) {
            std::string bytes;
            for (std::int32_t v : {bad, 4, 4}) {
                for (int i = 3; i >= 0; --i) bytes += char((std::uint32_t(v) >> (8 * i)) & 0xff);
            }
            bytes += std::string(4 * 3 * 16, '\0');
            const std::string path = fx_test::write_temp_file("bad_dims.xyz", bytes);
            const std::string m = fx_test::error_message([&] { fx::read_plot3d(path); });
            CHECK_THAT(m, Contains(path) && Contains("byte 0") && Contains("not a PLOT3D grid file"));
        }
    }
    SECTION("q file for another grid") {
        const std::string xyz = fx_test::output_path("io_mismatch.xyz"), q = fx_test::output_path("io_mismatch.q");
        const std::vector<fx::Plot3dBlock> first(blocks.begin(), blocks.begin() + 1);
        fx::write_plot3d(first, fx::Plot3dFormat{}, xyz);
        std::vector<fx::Plot3dBlock> other = first;
        other[0].dims = {4, 3, 2}; // same node count, different shape
        fx::write_plot3d(other, fx::Plot3dFormat{}, fx_test::output_path("io_other.xyz"), q);
        const std::string m = fx_test::error_message([&] { fx::read_plot3d(xyz, q); });
        CHECK_THAT(m, Contains(q) && Contains("block 0") && Contains("differ"));
    }
    SECTION("truncated q file") {
        const std::string full = fx_test::read_bytes(mesh_path("blunt_fin/bluntfinq.bin"));
        const std::string q = fx_test::write_temp_file("cut.q", full.substr(0, 500000));
        const std::string m = fx_test::error_message([&] { fx::read_plot3d(mesh_path("blunt_fin/bluntfinxyz.bin"), q); });
        CHECK_THAT(m, Contains(q) && Contains("byte 500000") && Contains("truncated q file in block 0"));
    }
    SECTION("truncated grid names the block") {
        const std::string full = fx_test::read_bytes(mesh_path("blunt_fin_2block/multi-bin.xyz"));
        const std::string xyz = fx_test::write_temp_file("cut2.xyz", full.substr(0, 40000));
        const std::string m = fx_test::error_message([&] { fx::read_plot3d(xyz); });
        CHECK_THAT(m, Contains(xyz) && Contains("byte 40000") && Contains("truncated grid file in block 1"));
    }
}

TEST_CASE("PLOT3D a record marker that lies is named at its byte, not read as another layout", "[io][plot3d]") {
    // The multi-block grid with record markers, float64 (the markers are what tells the
    // precision): its header and size fit one variant only, so a marker that disagrees is the
    // file's fault, said at its byte — before, the reader said "not a PLOT3D grid file: no
    // reading of the header gives plausible block dimensions" and only then the marker.
    const std::vector<fx::Plot3dBlock> blocks = synthetic_blocks();
    const fx::Plot3dFormat format{false, true, true, false, true};
    const std::string good = fx_test::output_path("io_marked.xyz");
    fx::write_plot3d(blocks, format, good);
    const std::string bytes = fx_test::read_bytes(good);
    // Little-endian: the low byte of a marker is its first. Header: 4 + 4 + 4 (count record),
    // 4 + 24 + 4 (dims record, closing marker at byte 40); block 0's coordinates: marker at
    // byte 44, 3·24·8 bytes.
    const std::size_t open0 = 44, close0 = open0 + 4 + 3 * 24 * 8;
    struct Lie {
        const char* name;
        std::size_t byte;
        const char* says;
    };
    for (const Lie& lie : {Lie{"opening block 0's coordinates", open0, "says 592 bytes, but the record holds 576"},
                           Lie{"closing them", close0, "says 592 bytes, but the record holds 576"},
                           Lie{"closing the dims record", 40, "(closing the header's dims) says 40 bytes, but the record holds 24"}}) {
        INFO(lie.name);
        std::string damaged = bytes;
        damaged[lie.byte] = char(damaged[lie.byte] + 16);
        const std::string path = fx_test::write_temp_file("lying.xyz", damaged);
        const std::string m = fx_test::error_message([&] { fx::read_plot3d(path); });
        CHECK_THAT(m, Contains(path + ": byte " + std::to_string(lie.byte) + ": a damaged or lying record marker") &&
                          Contains(lie.says) && Contains("every other record marker agrees"));
        CHECK_THAT(m, !Contains("not a PLOT3D grid file"));
    }
}

TEST_CASE("PLOT3D truncated at many offsets always throws with a location", "[io][plot3d]") {
    for (const char* file : {"blunt_fin/bluntfinxyz.bin", "blunt_fin_2block/multi-bin.xyz"}) {
        const std::string bytes = fx_test::read_bytes(mesh_path(file));
        const std::vector<std::size_t> cuts = fx_test::cut_points(bytes.size(), 100, 200);
        const std::size_t errors = fx_test::sweep_truncations("cut.xyz", bytes, cuts, [](const std::string& p) { fx::read_plot3d(p); });
        CHECK(errors == cuts.size()); // a grid file must be complete
    }
}

TEST_CASE("PLOT3D corrupted bytes never crash", "[io][plot3d]") {
    std::mt19937 rng(99);
    const std::string xyz = fx_test::read_bytes(mesh_path("blunt_fin_2block/multi-bin.xyz"));
    const std::string q = fx_test::read_bytes(mesh_path("blunt_fin_2block/multi-bin.q"));
    for (int trial = 0; trial < 200; ++trial) {
        std::string a = xyz, b = q;
        std::string& target = trial % 2 ? a : b;
        for (int k = 0; k < 3; ++k) target[trial < 100 ? rng() % 64 : rng() % target.size()] = char(rng() % 256);
        const std::vector<char> av(a.begin(), a.end()), bv(b.begin(), b.end());
        try {
            fx::parse_plot3d(av, "corrupt.xyz", &bv, "corrupt.q");
        } catch (const fx::Error& e) {
            CHECK_THAT(std::string(e.what()), Contains("corrupt."));
        }
    }
}
