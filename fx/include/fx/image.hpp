// cellfx — float RGBA images and their files.
//
// Pixels are linear, premultiplied RGBA floats; row 0 is the BOTTOM row (GL and PFM order).
// write_png() flips to PNG's top-down order and clamps to 8 bits; write_pfm() writes the
// standard colour PFM ("PF", little-endian, scale −1) so results can be checked numerically.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace cellfx::fx {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<glm::vec4> pixels; // width * height, row-major, bottom row first

    Image() = default;
    Image(int w, int h, glm::vec4 fill = glm::vec4(0.0f));
    glm::vec4& at(int x, int y) { return pixels[index(x, y)]; }
    const glm::vec4& at(int x, int y) const { return pixels[index(x, y)]; }
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
    }
};

// Composites premultiplied `image` over an opaque background colour, in place (alpha → 1).
void composite_over(Image& image, const glm::vec3& background);

// Writers and readers throw fx::Error naming the path on any failure.
void write_png(const Image& image, const std::string& path);
void write_pfm(const Image& image, const std::string& path); // RGB only
Image read_pfm(const std::string& path);                     // alpha set to 1
// Chooses the writer from the extension (.png or .pfm).
void write_image(const Image& image, const std::string& path);

} // namespace cellfx::fx
