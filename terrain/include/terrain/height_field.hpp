// cellfx terrain — height fields: a square grid of heights, from greyscale PNGs or generators.
//
// A HeightField holds size × size samples with size = 2^n + 1 (3 ≤ size ≤ 16385), the form the
// continuous-LOD quadtree (continuous_lod.hpp) needs. Sample (i, j) lies at world
// (origin.x + spacing·i, origin.y + spacing·j) with height heights[j·size + i]; +z is up, +y is
// north. PNG rows run from north (top row, j = size − 1) to south (bottom row, j = 0).
//
// The same type carries the ground, a fog map (the fog layer's thickness above the ground,
// Roettger & Ertl 2003 §5) and an aurora's penetration depth.
//
// Ownership: a plain value type. Heights are floats (metres at 30 m spacing keep ~0.1 mm);
// positions are doubles so fields far from the origin keep their precision.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace cellfx::terrain {

struct HeightField {
    int size = 0;            // samples per side, 2^n + 1
    double spacing = 1.0;    // world units between neighbouring samples, > 0
    glm::dvec2 origin{0.0};  // world (x, y) of sample (0, 0)
    std::vector<float> heights; // size * size, row-major in j (y), i (x) fastest

    float at(int i, int j) const { return heights[std::size_t(j) * std::size_t(size) + std::size_t(i)]; }
    float& at(int i, int j) { return heights[std::size_t(j) * std::size_t(size) + std::size_t(i)]; }
    double x(int i) const { return origin.x + spacing * i; }
    double y(int j) const { return origin.y + spacing * j; }
    double extent() const { return spacing * (size - 1); } // side length in world units
    // Bilinear height at world (x, y); positions outside the field are clamped onto its edge.
    double sample(double x, double y) const;
    float min_height() const;
    float max_height() const;
};

// True for 2^n + 1 with n ≥ 1.
bool is_lod_size(int size);

// Throws fx::Error starting with `what` unless a size × size field fits the height-samples
// budget (fx/resource_limits.hpp) and its grid, spacing·(size − 1) from `origin`, and the
// heights [lowest, highest] lie within ±fx::kMaxCoordinate (the coordinates cellfx renders).
// Checked before anything of that size is allocated.
void check_height_field(int size, double spacing, glm::dvec2 origin, double lowest, double highest,
                        const std::string& what);
// The smallest 2^n + 1 ≥ size (n ≥ 1).
int lod_size_at_least(int size);

struct HeightFieldOptions {
    double spacing = 1.0;         // world units between samples
    double vertical_scale = 1.0;  // world units per grey level (8-bit: 0..255, 16-bit: 0..65535)
    double vertical_offset = 0.0; // height of grey level 0
    glm::dvec2 origin{0.0};
    // An image that is not a (2^n + 1)² square is extended to the smallest one containing it
    // by repeating its last column and top row. Without `pad` such an image is an error.
    bool pad = false;
};

// Reads an 8- or 16-bit greyscale PNG: height = vertical_offset + vertical_scale · grey.
// Throws fx::Error naming the file for: an unreadable or non-PNG file, colour or grey+alpha
// images ("not greyscale"), a size that is not (2^n + 1)² without `pad`, fewer than 3 samples
// per side, more than 16385, or options that are not finite and positive where required.
HeightField read_height_field_png(const std::string& path, const HeightFieldOptions& options = {});
// The same from the bytes of a PNG file in memory (fuzzers, archives); `name` is used in messages.
HeightField parse_height_field_png(const std::vector<char>& bytes, const std::string& name,
                                   const HeightFieldOptions& options = {});

// A height (or thickness) at world (x, y). Generators must be deterministic.
using HeightGenerator = std::function<double(double x, double y)>;

// size × size samples of `generator` at origin + spacing·(i, j). Throws fx::Error for a size
// that is not 2^n + 1, a spacing that is not finite and positive, or a generator value that
// is not finite (naming the sample and its position).
HeightField make_height_field(int size, double spacing, const HeightGenerator& generator,
                              glm::dvec2 origin = glm::dvec2(0.0));

// A field on the same grid as `like` with values generator(x, y) (fog maps over a ground).
HeightField make_height_field_like(const HeightField& like, const HeightGenerator& generator);

// Throws fx::Error("<what>: ...") unless `a` and `b` have the same size, spacing and origin.
void require_same_grid(const HeightField& a, const HeightField& b, const std::string& what);

} // namespace cellfx::terrain
