// cellfx — the one table of uniform locations between the terrain library's GL passes and their
// shaders (the surface, the fx layer, the scene-depth normalizer), as fx's projector has its own
// (fx/src/projector/gl_interface.hpp).
//
// Every number is written once, in TERRAIN_INTERFACE below. C++ sees each entry as an
// enumerator (kUniformSurfaceSun, ...); GLSL sees it as a #define of the same name in upper case
// (UNIFORM_SURFACE_SUN, ...) from the generated include "terrain_interface.glsl", which
// terrain_shaders() carries. Shaders write
//     #include "terrain_interface.glsl"
//     layout(location = UNIFORM_SURFACE_SUN) uniform vec3 u_sun;
// and never a bare number.
#pragma once

#include <string>

namespace cellfx::terrain {

// X(c++ name, GLSL name, value). Uniform locations (an array's elements included) are unique
// across the table (terrain_shaders.cpp checks at compile time).
#define TERRAIN_INTERFACE(X)                                                                       \
    X(kSurfaceMaxStops, SURFACE_MAX_STOPS, 8) /* the height ramp's stops */                        \
    /* the surface (terrain_surface.vert, terrain_surface.frag) */                                 \
    X(kUniformSurfaceViewProjection, UNIFORM_SURFACE_VIEW_PROJECTION, 0) /* relative frame → clip */ \
    X(kUniformSurfaceFieldOrigin, UNIFORM_SURFACE_FIELD_ORIGIN, 1)                                 \
    X(kUniformSurfaceTexel, UNIFORM_SURFACE_TEXEL, 2)                                              \
    X(kUniformSurfaceHeightRange, UNIFORM_SURFACE_HEIGHT_RANGE, 3)                                 \
    X(kUniformSurfaceSun, UNIFORM_SURFACE_SUN, 4)                                                  \
    X(kUniformSurfaceAmbient, UNIFORM_SURFACE_AMBIENT, 5)                                          \
    X(kUniformSurfaceStops, UNIFORM_SURFACE_STOPS, 6)                                              \
    X(kUniformSurfaceRamp, UNIFORM_SURFACE_RAMP, 8)          /* [SURFACE_MAX_STOPS] */             \
    X(kUniformSurfaceSize, UNIFORM_SURFACE_SIZE, 16)                                               \
    X(kUniformSurfaceFirstSample, UNIFORM_SURFACE_FIRST_SAMPLE, 17)                                \
    X(kUniformSurfaceSpacing, UNIFORM_SURFACE_SPACING, 18)                                         \
    /* the fx layer's depth reduction (fx_layer_depth.frag) and upsampling (fx_layer_upsample.frag) */ \
    X(kUniformLayerDepthOrigin, UNIFORM_LAYER_DEPTH_ORIGIN, 20)                                    \
    X(kUniformLayerDepthSizes, UNIFORM_LAYER_DEPTH_SIZES, 21)                                      \
    X(kUniformLayerViewport, UNIFORM_LAYER_VIEWPORT, 22)                                           \
    X(kUniformLayerUpsampleDepthOrigin, UNIFORM_LAYER_UPSAMPLE_DEPTH_ORIGIN, 23)                   \
    X(kUniformLayerLowSize, UNIFORM_LAYER_LOW_SIZE, 24)                                            \
    X(kUniformLayerDepthModel, UNIFORM_LAYER_DEPTH_MODEL, 25)                                      \
    /* the scene-depth normalizer (scene_depth_normalize.frag) */                                  \
    X(kUniformNormalizeOffset, UNIFORM_NORMALIZE_OFFSET, 30)                                       \
    X(kUniformNormalizeMap, UNIFORM_NORMALIZE_MAP, 31)                                             \
    X(kUniformNormalizeSamples, UNIFORM_NORMALIZE_SAMPLES, 32)

#define TERRAIN_INTERFACE_ENUMERATOR(name, glsl, value) name = value,
enum TerrainInterface : int { TERRAIN_INTERFACE(TERRAIN_INTERFACE_ENUMERATOR) };
#undef TERRAIN_INTERFACE_ENUMERATOR

// The text of "terrain_interface.glsl": every entry above as a #define.
std::string terrain_interface_glsl();

} // namespace cellfx::terrain
