// cellfx terrain — scene files: a terrain, its ground fog, an aurora, a camera and how to render
// them, as one JSON document (content/scenes/*.json; format in docs/terrain.md).
//
//     {
//       "description": "...",                              // optional
//       "terrain":  {"height_map": "../terrain/st_helens_257.png", "spacing": 30,
//                    "vertical_scale": 1, "vertical_offset": 0, "pad": false}
//                or {"procedural": {"size": 257, "spacing": 30, "noise": NOISE}},
//       "lod":      {"pixel_error": 2, "min_resolution": 4, "triangle_budget": 0, "geomorph": true},
//       "fog":      {"thickness_map": {"file": "fog.png", "vertical_scale": 1, "pad": false}
//                    or "valley": {"level": 1300, "max_thickness": 250, "radius": 0, "noise": NOISE},
//                    (radius > 0: level relative to the ground averaged over ±radius),
//                    "density": "layer_height" | "noise", "density_scale": 1, "density_noise": NOISE,
//                    "transfer_function": "../transfer_functions/fog.json", "extinction_scale": 0.01,
//                    "path": "pcp-exact", "absorb": true},
//       "aurora":   {"ceiling": 12000, "size": 129, "spacing": 120, "origin": [x, y],
//                    "curtains": {"count": 3, "max_depth": 3000, "width": 250, "wander": 1500,
//                                 "cutoff": 0.02, "seed": 1},
//                    "transfer_function": "...", "extinction_scale": 1, "path": "mip",
//                    "pixel_error": 4},
//       "camera":   {"eye": [x, y, z], "target": [x, y, z], "up": [0, 0, 1], "fov": 50,
//                    "near": 5, "far": 60000},
//       "render":   {"width": 1024, "height": 768, "background": [r, g, b]},
//       "surface":  {"sun": [x, y, z], "ambient": 0.35}
//     }
//     NOISE = {"amplitude": 40, "offset": 0, "frequency": 0.002, "octaves": 4, "lacunarity": 2,
//              "gain": 0.5, "seed": 1}   (fBm of 2-D gradient noise: offset + amplitude·fbm(x, y))
// "terrain" and "camera" are required; "fog" and "aurora" are optional (absent: not built, not
// drawn). File names are relative to the scene file's folder. Unknown keys are errors, as are
// wrong types and values out of range; every message names the file and the key path
// ("fog_valley.json: fog.path: unknown render path 'pcp-exakt' (expected pcp, pcp-exact, mip)").
// Later sections (effects) extend this one loader: scene_file.cpp is its only parser.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "terrain/aurora.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/height_field.hpp"
#include "terrain/surface_renderer.hpp"

namespace terrain {

// Fractal 2-D noise as scenes describe it: offset + amplitude · fbm(frequency·(x, y)).
struct NoiseSpec {
    double amplitude = 1.0;
    double offset = 0.0;
    double frequency = 1.0;
    int octaves = 4;
    double lacunarity = 2.0;
    double gain = 0.5;
    std::uint32_t seed = 1;
};
// A generator for the spec (deterministic; fbm in [−1, 1]).
HeightGenerator make_noise_generator(const NoiseSpec& spec);

struct FogSpec {
    HeightField thickness;            // on the ground's grid
    LayerPrismOptions prisms;
    fx::TransferFunction transfer_function;
    fx::RenderPath path = fx::RenderPath::PcpExact;
    bool absorb = true;               // pcp-exact: fog dims what is behind it
};

struct AuroraSpec {
    AuroraLayer layer;                // lower border and depth, on the aurora's own grid
    double ceiling = 0.0;
    fx::TransferFunction transfer_function;
    fx::RenderPath path = fx::RenderPath::Mip;
    double pixel_error = 4.0;
};

struct Scene {
    std::string source;               // the file it came from ("" for scenes built in code)
    std::string description;
    HeightField ground;
    LodSettings lod;
    double pixel_error = 2.0;
    std::size_t triangle_budget = 0;
    std::optional<FogSpec> fog;
    std::optional<AuroraSpec> aurora;
    fx::Camera camera;
    int width = 1024, height = 768;
    glm::dvec3 background{0.55, 0.66, 0.80};
    SurfaceStyle surface;
};

// Reads and builds a scene (height maps, fog maps, transfer functions). Throws fx::Error naming
// the file and the key (and, for files it refers to, their own errors).
Scene load_scene(const std::string& path);
// The same from text; `source` names it in messages, `base_dir` resolves relative file names.
Scene parse_scene(std::string_view json, const std::string& source, const std::string& base_dir);

} // namespace terrain
