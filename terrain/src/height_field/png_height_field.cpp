// Height fields from 8- and 16-bit greyscale PNG files (stb_image).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <stb_image.h>

#include "fx/error.hpp"
#include "io/input_file.hpp"
#include "terrain/height_field.hpp"

namespace cellfx::terrain {

namespace {

const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

const char* channel_words(int channels) {
    switch (channels) {
    case 2: return "grey + alpha";
    case 3: return "RGB";
    case 4: return "RGBA";
    default: return "unknown";
    }
}

std::uint32_t be32(const std::vector<char>& bytes, std::size_t at) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + at;
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 | p[3];
}

// Checks the chunk structure before stb_image sees the file, because stb allocates what the
// file claims before reading it: a chunk's stated length (a 70-byte file with a 1 GiB IDAT
// length cost 1 GiB), and the whole decoded image before inflating the pixel data. Every chunk
// must lie inside the file, and the IDAT bytes must be able to inflate to at least
// `min_pixel_bytes` (deflate expands at most 1032:1).
void check_png_chunks(const std::vector<char>& bytes, const std::string& path, std::uint64_t min_pixel_bytes) {
    std::uint64_t idat = 0;
    std::size_t at = 8;
    while (at + 8 <= bytes.size()) {
        const std::uint64_t length = be32(bytes, at);
        const std::string type(bytes.data() + at + 4, 4);
        if (length > bytes.size() - at - 8 || bytes.size() - at - 8 - length < 4) {
            throw fx::Error(path + ": byte " + std::to_string(at) + ": truncated PNG: chunk \"" + type + "\" claims " +
                            std::to_string(length) + " bytes, the file has " + std::to_string(bytes.size() - at - 8) + " left");
        }
        if (type == "IDAT") idat += length;
        if (type == "IEND") break;
        at += 12 + std::size_t(length);
    }
    if (min_pixel_bytes > 1032 * idat + 1024) {
        throw fx::Error(path + ": truncated PNG: " + std::to_string(idat) + " bytes of pixel data cannot hold the " +
                        std::to_string(min_pixel_bytes) + " bytes of its image");
    }
}

void check_options(const std::string& path, const HeightFieldOptions& options) {
    if (!(options.spacing > 0.0) || !std::isfinite(options.spacing))
        throw fx::Error(path + ": spacing must be a finite positive number");
    if (!std::isfinite(options.vertical_scale) || options.vertical_scale == 0.0)
        throw fx::Error(path + ": vertical scale must be finite and non-zero");
    if (!std::isfinite(options.vertical_offset)) throw fx::Error(path + ": vertical offset must be finite");
}

} // namespace

HeightField read_height_field_png(const std::string& path, const HeightFieldOptions& options) {
    check_options(path, options);
    // The signature first: a device or pipe of anything else is refused before it is read.
    const auto check_signature = [&](std::string_view head) {
        if (head.substr(0, 8) != std::string_view(reinterpret_cast<const char*>(kPng), 8)) throw fx::Error(path + ": not a PNG file");
    };
    return parse_height_field_png(fx::io::read_input_file(path, fx::Limit::FileBytes, "height map", check_signature), path,
                                  options);
}

HeightField parse_height_field_png(const std::vector<char>& bytes, const std::string& path, const HeightFieldOptions& options) {
    check_options(path, options);

    if (bytes.size() < 8 || !std::equal(kPng, kPng + 8, reinterpret_cast<const unsigned char*>(bytes.data())))
        throw fx::Error(path + ": not a PNG file");
    if (bytes.size() > std::size_t(std::numeric_limits<int>::max())) throw fx::Error(path + ": file too large for a height map");
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = int(bytes.size());

    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(data, length, &w, &h, &channels))
        throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
    if (channels != 1)
        throw fx::Error(path + ": the height map is " + channel_words(channels) +
                        ", not greyscale (save it as an 8- or 16-bit single-channel PNG)");
    const bool sixteen = stbi_is_16_bit_from_memory(data, length) != 0;

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

    // Nothing of the header's size is allocated before the file is known to hold it (a
    // 69-byte file claiming 16385 x 16385 used to cost 2 GiB here, and stb's own buffers),
    // and before it is known to be within the budget and the coordinates cellfx renders.
    check_png_chunks(bytes, path, std::uint64_t(w) * std::uint64_t(h) * (sixteen ? 2 : 1));
    const double top = sixteen ? 65535.0 : 255.0;
    check_height_field(size, options.spacing, options.origin, options.vertical_offset,
                       options.vertical_offset + options.vertical_scale * top, path + ": the height map");
    std::vector<double> grey;
    int rw = 0, rh = 0, rc = 0;
    if (sixteen) {
        stbi_us* pixels = stbi_load_16_from_memory(data, length, &rw, &rh, &rc, 1);
        if (!pixels) throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
        if (rw == w && rh == h) grey.assign(pixels, pixels + std::size_t(w) * std::size_t(h));
        stbi_image_free(pixels);
    } else {
        stbi_uc* pixels = stbi_load_from_memory(data, length, &rw, &rh, &rc, 1);
        if (!pixels) throw fx::Error(path + ": unreadable PNG (" + std::string(stbi_failure_reason()) + ")");
        if (rw == w && rh == h) grey.assign(pixels, pixels + std::size_t(w) * std::size_t(h));
        stbi_image_free(pixels);
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

} // namespace cellfx::terrain
