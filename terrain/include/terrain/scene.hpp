// cellfx terrain — scene files: a terrain, its ground fog, an aurora, free-standing effects
// (campfire, search light, laser cone), a camera (and a path for it) and how to render them, as
// one JSON document (content/scenes/*.json; format in docs/terrain.md and docs/effects.md).
//
//     {
//       "description": "...",                              // optional
//       "terrain":  {"height_map": "../terrain/st_helens_257.png", "spacing": 30,
//                    "vertical_scale": 1, "vertical_offset": 0, "pad": false, "draw": true}
//                or {"procedural": {"size": 257, "spacing": 30, "noise": NOISE}, "draw": true},
//                   ("draw": false — the game draws its own ground and hands cellfx its depth;
//                    the terrain still carries the fog)
//       "lod":      {"pixel_error": 2, "min_resolution": 4, "triangle_budget": 0, "geomorph": true},
//       "fog":      {"thickness_map": {"file": "fog.png", "vertical_scale": 1, "pad": false}
//                    or "valley": {"level": 1300, "max_thickness": 250, "radius": 0, "noise": NOISE},
//                    (radius > 0: level relative to the ground averaged over ±radius),
//                    "density": "layer_height" | "noise", "density_scale": 1, "density_noise": NOISE,
//                    "transfer_function": "../transfer_functions/fog.json", "extinction_scale": 0.01,
//                    "path": "pcp-exact", "absorb": true, "enabled": true},
//       "aurora":   {"ceiling": 12000, "size": 129, "spacing": 120, "origin": [x, y],
//                    "curtains": {"count": 3, "max_depth": 3000, "width": 250, "wander": 1500,
//                                 "cutoff": 0.02, "seed": 1},
//                    "transfer_function": "...", "extinction_scale": 1, "path": "mip",
//                    "pixel_error": 4, "enabled": true},
//       "effects":  [{"type": "campfire" | "search_light" | "laser_cone" | "volume", "name": "fire",
//                     "enabled": true, "path": "pcp-exact", "absorb": false (volume: true),
//                     "transfer_function": "../transfer_functions/fire.json" or inline
//                     {"points": [[s, r, g, b, sigma], ...]}, "extinction_scale": 1,
//                     ... the type's parameters under their C++ names (fx/campfire.hpp,
//                     fx/search_light.hpp, fx/laser_cone.hpp, fx/volume.hpp), e.g. "position": [x, y, z],
//                     "base_radius": 0.45, "sweep": {"axis": [0, 0, 1], "amplitude_degrees": 30,
//                     "period": 8, "phase_degrees": 0}}, ...],
//                   volume: {"type": "volume", "shape": "box" | "sphere" | "mesh", "size": [x, y, z],
//                     "radius": r, "mesh": "file", "q_file": "file" (PLOT3D), "field": "name",
//                     "rotation_degrees": [x, y, z], "cells": n, "density": d,
//                     "density_mode": "constant" | "noise" | "field" (default: noise with a "noise"
//                     object, field for a mesh, else constant), "edge_fade": f,
//                     "noise": {"frequency", "octaves", "coverage", "contrast", "drift": [x, y, z],
//                     "evolve", "seed"}}
//       "camera":   {"eye": [x, y, z], "target": [x, y, z], "up": [0, 0, 1], "fov": 50,
//                    "near": 5, "far": 60000},
//       "camera_path": {"loop": false, "keys": [{"time": 0, "eye": [x, y, z], "target": [x, y, z]}, ...]},
//       "render":   {"width": 1024, "height": 768, "background": [r, g, b],
//                    "fx_scale": 1 | 0.5 | 0.25, "medium": "froxel" | "exact"},
//       "surface":  {"sun": [x, y, z], "ambient": 0.35, "ramp": [[0, [r, g, b]], ..., [1, [r, g, b]]]}
//     }
//     NOISE = {"amplitude": 40, "offset": 0, "frequency": 0.002, "octaves": 4, "lacunarity": 2,
//              "gain": 0.5, "seed": 1}   (fBm of 2-D gradient noise: offset + amplitude·fbm(x, y))
// "camera" is required, and "terrain" unless the scene has effects; "fog" needs a terrain;
// everything else is optional (absent: not built, not drawn). Effect names are unique ("fog"
// and "aurora" name those sections). File names are relative to the scene file's folder.
// Unknown keys are errors, as are wrong types and values out of range; every message names the
// file and the key path ("campfire.json: effects[0].base_radius: must be positive").
// scene_file.cpp is the only parser.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "fx/campfire.hpp"
#include "fx/laser_cone.hpp"
#include "fx/medium.hpp"
#include "fx/render_path.hpp"
#include "fx/search_light.hpp"
#include "fx/transfer_function.hpp"
#include "fx/volume.hpp"
#include "terrain/aurora.hpp"
#include "terrain/height_field.hpp"
#include "terrain/layer_prism_options.hpp"
#include "terrain/lod_settings.hpp"
#include "terrain/surface_style.hpp"

namespace cellfx::terrain {

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

// How an effect's light scatters in the scene's absorbing media (fog, smoke volumes): a search
// light's or laser's beam, a campfire's glow (fx::MediumLight, docs/effects.md "One medium").
struct LightSpec {
    glm::dvec3 color{1.0, 1.0, 1.0}; // times strength: the scattered radiance of a unit optical
    double strength = 1.0;           // depth of albedo-1 medium at full light and phase 1; 0: off
    double phase_g = 0.5;            // Henyey–Greenstein g, (−1, 1): > 0 brightest looking into the light
    double radius = 0.0;             // campfire: how far its glow reaches (m; 0: 6 × its height)
};

struct FogSpec {
    HeightField thickness;            // on the ground's grid
    LayerPrismOptions prisms;
    fx::TransferFunction transfer_function; // as read; drawn with its sigma × extinction_scale
    double extinction_scale = 1.0;
    fx::RenderPath path = fx::RenderPath::PcpExact;
    bool absorb = true;               // pcp-exact: fog dims what is behind it
    double albedo = 0.9;              // how much of a light crossing it the fog scatters (0..1)
    bool enabled = true;              // false: declared but neither built nor drawn (until enabled)
};

struct AuroraSpec {
    AuroraLayer layer;                // lower border and depth, on the aurora's own grid
    double ceiling = 0.0;
    fx::TransferFunction transfer_function; // as read; drawn with its sigma × extinction_scale
    double extinction_scale = 1.0;
    fx::RenderPath path = fx::RenderPath::Mip;
    double pixel_error = 4.0;
    bool enabled = true;
};

// The transfer function an effect is drawn with: `tf` with its sigma × extinction_scale, a
// normalized one mapped once onto `range` (the effect's scalar_range()), so colours do not
// shift as the frame's scalars (LOD, noise) vary. Throws fx::Error for a negative or
// non-finite scale.
fx::TransferFunction drawn_transfer_function(const fx::TransferFunction& tf, double extinction_scale, fx::ScalarRange range);

// A free-standing effect the scene calls for (one entry of "effects").
using EffectParams = std::variant<fx::CampfireParams, fx::SearchLightParams, fx::LaserConeParams, fx::VolumeParams>;
const char* effect_type_name(const EffectParams& params); // "campfire", "search_light", "laser_cone", "volume"
// The effect those parameters describe (throws fx::Error as its constructor does).
std::unique_ptr<fx::Effect> make_effect(const EffectParams& params);

struct EffectSpec {
    std::string name;                       // unique within the scene
    EffectParams params;
    fx::TransferFunction transfer_function; // as read (normalized ones are mapped onto the
                                            // effect's scalar_range()); drawn with sigma × extinction_scale
    double extinction_scale = 1.0;          // ≥ 0
    fx::RenderPath path = fx::RenderPath::PcpExact;
    bool absorb = false;                    // pcp-exact: also dims what is behind it (volumes: true)
    double albedo = 0.0;                    // absorbing effects: how much light they scatter (volumes: 0.9)
    LightSpec light;                        // campfire, search light, laser cone: their light in the media
    bool enabled = true;
};

// Key frames of a camera flight: eye and target follow Catmull–Rom curves through the keys
// (uniform in time between keys); before the first key and after the last they hold (or, with
// `loop`, time wraps over [first time, last time] — repeat the first key last for a closed loop).
struct CameraKey {
    double time = 0.0; // seconds, strictly increasing along the path
    glm::dvec3 eye{0.0}, target{0.0, 0.0, -1.0};
};
struct CameraPath {
    std::vector<CameraKey> keys; // at least 2
    bool loop = false;
    double duration() const { return keys.size() < 2 ? 0.0 : keys.back().time - keys.front().time; }
    // `base` (up, fov, near, far) with eye and target at time t.
    fx::Camera at(double t, const fx::Camera& base) const;
};

// The effects' resolution as a fraction of the view's (Scene::fx_scale): 1, 0.5 or 0.25.
inline bool valid_fx_scale(double scale) { return scale == 1.0 || scale == 0.5 || scale == 0.25; }

struct Scene {
    std::string source;               // the file it came from ("" for scenes built in code)
    std::string description;
    HeightField ground;               // size 0: no terrain (a scene of effects only)
    bool draw_terrain = true;         // false: the game draws the ground; cellfx uses it for fog only
    LodSettings lod;
    double pixel_error = 2.0;
    std::size_t triangle_budget = 0;
    std::optional<FogSpec> fog;
    std::optional<AuroraSpec> aurora;
    std::vector<EffectSpec> effects;
    fx::Camera camera;
    std::optional<CameraPath> camera_path;
    int width = 1024, height = 768;
    glm::dvec3 background{0.55, 0.66, 0.80};
    // Every effect path and the one medium draw at this fraction of the view's resolution (1,
    // 0.5 or 0.25), upsampled against the scene's depth (docs/effects.md, "Resolution").
    double fx_scale = 1.0;
    // How volumes that overlap on screen are integrated as one medium (fx/medium.hpp).
    fx::MediumMethod medium = fx::MediumMethod::Froxel;
    SurfaceStyle surface;

    bool has_terrain() const { return ground.size > 0; }
};

// Reads and builds a scene (height maps, fog maps, transfer functions). Throws fx::Error naming
// the file and the key (and, for files it refers to, their own errors).
Scene load_scene(const std::string& path);
// The same from text; `source` names it in messages, `base_dir` resolves relative file names.
Scene parse_scene(std::string_view json, const std::string& source, const std::string& base_dir);

// The scene file `scene` was loaded from, updated with what a program changed at run time (a
// tuning panel's "save"): `original` is that file's text (scene.source names it), and from
// `scene` come each effect's parameters (fx/effect_parameters.hpp), "enabled", "path", "absorb"
// and "extinction_scale" (fog, aurora and effects, matched by name), lod.pixel_error and
// render.fx_scale and render.medium. Every other key stays as written, and keys that still hold
// their default stay left out; file names (height and fog maps, transfer functions, meshes)
// are rewritten for a file saved in the folder `save_dir`. parse_scene of the result gives a
// scene drawn like `scene`. Throws fx::Error naming the source for a scene built in code, a
// text that is not that scene's JSON, or an effect the file does not declare (added at run time).
std::string updated_scene_json(std::string_view original, const Scene& scene, const std::string& save_dir);

} // namespace cellfx::terrain
