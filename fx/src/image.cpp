#include "fx/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include <stb_image_write.h>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "io/output_file.hpp"

namespace cellfx::fx {

Image::Image(int w, int h, glm::vec4 fill)
    : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

void composite_over(Image& image, const glm::vec3& background) {
    for (glm::vec4& p : image.pixels) {
        const float t = 1.0f - p.a;
        p = glm::vec4(glm::vec3(p) + t * background, 1.0f);
    }
}

void write_png(const Image& image, const std::string& path) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(image.width) * image.height * 4);
    for (int y = 0; y < image.height; ++y) {
        const int row = image.height - 1 - y; // PNG is top-down
        for (int x = 0; x < image.width; ++x) {
            const glm::vec4& p = image.at(x, y);
            std::uint8_t* out = &bytes[(static_cast<std::size_t>(row) * image.width + x) * 4];
            for (int c = 0; c < 4; ++c) {
                const float v = std::isfinite(p[c]) ? std::clamp(p[c], 0.0f, 1.0f) : 0.0f;
                out[c] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
            }
        }
    }
    // Encoded in memory (stb's callback cannot report a failed write), then written whole.
    std::string png;
    const auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    if (!stbi_write_png_to_func(append, &png, image.width, image.height, 4, bytes.data(), image.width * 4) || png.empty())
        throw Error(path + ": cannot encode the " + std::to_string(image.width) + "x" + std::to_string(image.height) + " PNG");
    io::write_output_file(path, png);
}

void write_pfm(const Image& image, const std::string& path) {
    io::OutputFile out(path);
    out.write("PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n");
    std::vector<float> row(static_cast<std::size_t>(image.width) * 3);
    for (int y = 0; y < image.height; ++y) { // PFM stores the bottom row first, like Image
        for (int x = 0; x < image.width; ++x) {
            const glm::vec4& p = image.at(x, y);
            row[x * 3 + 0] = p.r;
            row[x * 3 + 1] = p.g;
            row[x * 3 + 2] = p.b;
        }
        out.write(row.data(), row.size() * sizeof(float));
    }
    out.commit();
}

Image read_pfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::string magic;
    int w = 0, h = 0;
    double scale = 0.0;
    in >> magic >> w >> h >> scale;
    if (!in || magic != "PF") throw Error(path + ": not a colour PFM (expected 'PF' header)");
    if (w <= 0 || h <= 0 || w > 65536 || h > 65536) throw Error(path + ": bad PFM size");
    if (scale >= 0.0) throw Error(path + ": big-endian PFM is not supported (scale must be negative)");
    in.get(); // the single whitespace after the scale
    // The header alone must not decide the allocation: the image budget, then rows as they come.
    check_limit(Limit::ImagePixels, std::uint64_t(w) * std::uint64_t(h), path + ": a " + std::to_string(w) + "x" + std::to_string(h) + " PFM");
    Image image(w, h);
    std::vector<float> row(static_cast<std::size_t>(w) * 3);
    for (int y = 0; y < h; ++y) {
        in.read(reinterpret_cast<char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(float)));
        if (!in) throw Error(path + ": truncated at row " + std::to_string(y));
        for (int x = 0; x < w; ++x) image.at(x, y) = glm::vec4(row[x * 3], row[x * 3 + 1], row[x * 3 + 2], 1.0f);
    }
    return image;
}

void write_image(const Image& image, const std::string& path) {
    auto ends_with = [&](const char* ext) {
        const std::size_t n = std::strlen(ext);
        if (path.size() < n) return false;
        std::string tail = path.substr(path.size() - n);
        std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return std::tolower(c); });
        return tail == ext;
    };
    if (ends_with(".png")) write_png(image, path);
    else if (ends_with(".pfm")) write_pfm(image, path);
    else throw Error(path + ": unknown image type (use .png or .pfm)");
}

} // namespace cellfx::fx
