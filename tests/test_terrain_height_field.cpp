// Height fields: 8- and 16-bit greyscale PNGs (real data: Mount St. Helens), padding,
// procedural generators, and clear errors for bad images.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include <stb_image_write.h>

#include "fx/error.hpp"
#include "terrain/height_field.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

namespace {

std::string write_png(const std::string& name, int w, int h, int channels, const std::vector<unsigned char>& data) {
    const std::string path = fx_test::output_path(name);
    REQUIRE(stbi_write_png(path.c_str(), w, h, channels, data.data(), w * channels));
    return path;
}

} // namespace

TEST_CASE("Mount St. Helens 16-bit PNG reads with its documented range", "[terrain][height_field]") {
    const std::string path = fx_test::source_path("content/terrain/st_helens_257.png");
    terrain::HeightFieldOptions options;
    options.spacing = 30.0;
    const terrain::HeightField field = terrain::read_height_field_png(path, options);
    CHECK(field.size == 257);
    CHECK(field.spacing == 30.0);
    CHECK(field.extent() == 7680.0);
    // content/terrain/README.md: elevations 944 .. 2543 m (16-bit samples are metres).
    CHECK(field.min_height() == 944.0f);
    CHECK(field.max_height() == 2543.0f);
    // 16-bit precision kept: not all heights are multiples of 256.
    std::size_t odd = 0;
    for (float h : field.heights) odd += (int(h) % 256) != 0;
    CHECK(odd > field.heights.size() / 2);
    // Vertical scale and offset apply to the grey levels.
    options.vertical_scale = 0.5;
    options.vertical_offset = -100.0;
    const terrain::HeightField scaled = terrain::read_height_field_png(path, options);
    CHECK(scaled.at(10, 20) == Approx(-100.0 + 0.5 * field.at(10, 20)));
}

TEST_CASE("8-bit PNGs: rows run north to south, padding repeats the edges", "[terrain][height_field]") {
    // 5x5: grey = 10·col + row (row 0 = top = north).
    std::vector<unsigned char> grey(25);
    for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 5; ++c) grey[r * 5 + c] = static_cast<unsigned char>(10 * c + r);
    const terrain::HeightField f = terrain::read_height_field_png(write_png("hf_5x5.png", 5, 5, 1, grey));
    CHECK(f.size == 5);
    CHECK(f.at(0, 4) == 0.0f);  // north-west corner is the image's top-left
    CHECK(f.at(3, 0) == 34.0f); // south: the image's bottom row (row 4)

    // 6x4 is not 2^n + 1: an error without pad, padded to 9x9 with it.
    std::vector<unsigned char> small(24);
    for (int k = 0; k < 24; ++k) small[k] = static_cast<unsigned char>(k);
    const std::string odd = write_png("hf_6x4.png", 6, 4, 1, small);
    CHECK_THROWS_WITH(terrain::read_height_field_png(odd), Catch::Contains("hf_6x4.png") && Catch::Contains("6x4") &&
                                                               Catch::Contains("2^n + 1"));
    terrain::HeightFieldOptions pad;
    pad.pad = true;
    const terrain::HeightField p = terrain::read_height_field_png(odd, pad);
    CHECK(p.size == 9);
    CHECK(p.at(0, 0) == 18.0f);  // bottom-left = last image row, first column
    CHECK(p.at(8, 0) == 23.0f);  // columns beyond the image repeat the last one
    CHECK(p.at(8, 8) == 5.0f);   // rows beyond the image repeat the top row
}

TEST_CASE("Bad height maps give errors naming the file", "[terrain][height_field]") {
    std::vector<unsigned char> rgb(5 * 5 * 3, 100);
    CHECK_THROWS_WITH(terrain::read_height_field_png(write_png("hf_rgb.png", 5, 5, 3, rgb)),
                      Catch::Contains("hf_rgb.png") && Catch::Contains("not greyscale"));
    std::vector<unsigned char> ga(5 * 5 * 2, 100);
    CHECK_THROWS_WITH(terrain::read_height_field_png(write_png("hf_ga.png", 5, 5, 2, ga)),
                      Catch::Contains("grey + alpha"));
    CHECK_THROWS_WITH(terrain::read_height_field_png(fx_test::output_path("does_not_exist.png")),
                      Catch::Contains("does_not_exist.png") && Catch::Contains("cannot open"));
    const std::string text = fx_test::output_path("hf_text.png");
    std::ofstream(text) << "this is not an image";
    CHECK_THROWS_WITH(terrain::read_height_field_png(text), Catch::Contains("hf_text.png") && Catch::Contains("not a PNG"));
    // A PNG cut short after its header.
    std::ifstream in(fx_test::source_path("content/terrain/st_helens_257.png"), std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = fx_test::output_path("hf_truncated.png");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), 200);
    CHECK_THROWS_WITH(terrain::read_height_field_png(cut), Catch::Contains("hf_truncated.png"));
    std::vector<unsigned char> one(4, 0);
    terrain::HeightFieldOptions pad;
    pad.pad = true;
    CHECK_THROWS_WITH(terrain::read_height_field_png(write_png("hf_1x4.png", 1, 4, 1, one), pad),
                      Catch::Contains("at least 2"));
    terrain::HeightFieldOptions zero;
    zero.spacing = 0.0;
    CHECK_THROWS_WITH(terrain::read_height_field_png(text, zero), Catch::Contains("spacing"));
}

TEST_CASE("Procedural height fields sample their generator on the grid", "[terrain][height_field]") {
    const terrain::HeightField f =
        terrain::make_height_field(17, 2.5, [](double x, double y) { return 3.0 * x - y; }, {100.0, -50.0});
    CHECK(f.size == 17);
    CHECK(f.at(4, 2) == Approx(3.0 * (100.0 + 10.0) - (-50.0 + 5.0)));
    // Bilinear sampling reproduces a linear field, and clamps outside.
    CHECK(f.sample(103.7, -47.1) == Approx(3.0 * 103.7 + 47.1).epsilon(1e-6));
    CHECK(f.sample(0.0, -50.0) == Approx(f.at(0, 0)));
    CHECK(terrain::is_lod_size(1025));
    CHECK_FALSE(terrain::is_lod_size(1024));
    CHECK(terrain::lod_size_at_least(300) == 513);
    CHECK_THROWS_WITH(terrain::make_height_field(16, 1.0, [](double, double) { return 0.0; }), Catch::Contains("2^n + 1"));
    CHECK_THROWS_WITH(terrain::make_height_field(5, 1.0, [](double x, double) { return x > 2 ? NAN : 0.0; }),
                      Catch::Contains("sample (3, 0)"));
    const terrain::HeightField other = terrain::make_height_field(9, 1.0, [](double, double) { return 0.0; });
    CHECK_THROWS_WITH(terrain::require_same_grid(f, other, "fog map"), Catch::Contains("fog map") && Catch::Contains("9x9"));
}
