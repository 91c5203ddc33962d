// Height fields from 8- and 16-bit greyscale PNG files (stb_image).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include <stb_image.h>

#include "fx/error.hpp"
#include "terrain/height_field.hpp"

namespace terrain {

namespace {

const char* channel_words(int channels) {
    switch (channels) {
    case 2: return "grey + alpha";
    case 3: return "RGB";
    case 4: return "RGBA";
    default: return "unknown";
    }
}

} // namespace

HeightField read_height_field_png(const std::string& path, const HeightFieldOptions& options) {
    if (!(options.spacing > 0.0) || !std::isfinite(options.spacing))
        throw fx::Error(path + ": spacing must be a finite positive number");
    if (!std::isfinite(options.vertical_scale) || options.vertical_scale == 0.0)
        throw fx::Error(path + ": vertical scale must be finite and non-zero");
    if (!std::isfinite(options.vertical_offset)) throw fx::Error(path + ": vertical offset must be finite");

    FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) throw fx::Error(path + ": cannot open the height map");
    std::unique_ptr<FILE, int (*)(FILE*)> closer(file, &std::fclose);
    unsigned char signature[8] = {};
    const std::size_t got = std::fread(signature, 1, 8, file);
    static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (got != 8 || !std::equal(signature, signature + 8, kPng)) throw fx::Error(path + ": not a PNG file");
    std::fseek(file, 0, SEEK_SET);

    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_file(file, &w, &h, &channels))
        throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
    if (channels != 1)
        throw fx::Error(path + ": the height map is " + channel_words(channels) +
                        ", not greyscale (save it as an 8- or 16-bit single-channel PNG)");
    const bool sixteen = stbi_is_16_bit_from_file(file) != 0;
    std::fseek(file, 0, SEEK_SET);

    const bool square_lod = w == h && is_lod_size(w);
    if (!square_lod) {
        if (!options.pad)
            throw fx::Error(path + ": the height map is " + std::to_string(w) + "x" + std::to_string(h) +
                            "; the continuous-LOD quadtree needs a square of 2^n + 1 samples (e.g. 257x257 or "
                            "1025x1025), or set pad to extend it");
        if (std::min(w, h) < 2)
            throw fx::Error(path + ": the height map is " + std::to_string(w) + "x" + std::to_string(h) +
                            "; at least 2 samples per side are needed");
    }
    const int size = square_lod ? w : lod_size_at_least(std::max(w, h));
    if (!is_lod_size(size))
        throw fx::Error(path + ": the height map is " + std::to_string(w) + "x" + std::to_string(h) +
                        "; at most 16385x16385 samples are supported");

    std::vector<double> grey(std::size_t(w) * std::size_t(h));
    int rw = 0, rh = 0, rc = 0;
    if (sixteen) {
        stbi_us* data = stbi_load_from_file_16(file, &rw, &rh, &rc, 1);
        if (!data) throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
        for (std::size_t k = 0; k < grey.size(); ++k) grey[k] = data[k];
        stbi_image_free(data);
    } else {
        stbi_uc* data = stbi_load_from_file(file, &rw, &rh, &rc, 1);
        if (!data) throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
        for (std::size_t k = 0; k < grey.size(); ++k) grey[k] = data[k];
        stbi_image_free(data);
    }
    if (rw != w || rh != h) throw fx::Error(path + ": the PNG's size changed while reading it");

    HeightField field;
    field.size = size;
    field.spacing = options.spacing;
    field.origin = options.origin;
    field.heights.resize(std::size_t(size) * std::size_t(size));
    for (int j = 0; j < size; ++j) {
        // Image row 0 is the north edge (j = h − 1); rows beyond the image repeat its top row.
        const int row = std::max(h - 1 - j, 0);
        for (int i = 0; i < size; ++i) {
            const int col = std::min(i, w - 1);
            field.at(i, j) = float(options.vertical_offset + options.vertical_scale * grey[std::size_t(row) * w + col]);
        }
    }
    return field;
}

} // namespace terrain
