// cellfx samples — the one table of uniform locations between the samples' own GL drawing
// (samples/common/sample_gl.cpp: the frame-stats text, the props' boxes) and their shaders
// (shaders/sample_text.*, shaders/sample_props.*), as the libraries have theirs
// (fx/src/projector/gl_interface.hpp, terrain/src/render/terrain_interface.hpp).
//
// Every number is written once, in SAMPLE_INTERFACE below. C++ sees each entry as an enumerator
// (kUniformTextScale, ...); GLSL sees it as a #define of the same name in upper case
// (UNIFORM_TEXT_SCALE, ...) from the generated include "sample_interface.glsl", which
// sample_shaders() carries. Shaders never write a bare location.
#pragma once

#include <string>

namespace cellfx_samples {

// X(c++ name, GLSL name, value). Locations are unique across the table (sample_gl.cpp checks at
// compile time), so the two programs could share any of them.
#define SAMPLE_INTERFACE(X)                                                                        \
    /* the frame-stats text (sample_text.vert) */                                                  \
    X(kUniformTextViewportSize, UNIFORM_TEXT_VIEWPORT_SIZE, 0) /* pixels */                        \
    X(kUniformTextOffset, UNIFORM_TEXT_OFFSET, 1)              /* pixels from the top left */      \
    X(kUniformTextScale, UNIFORM_TEXT_SCALE, 2)                                                    \
    /* the props' boxes (sample_props.vert, sample_props.frag) */                                  \
    X(kUniformPropsClipFromLocal, UNIFORM_PROPS_CLIP_FROM_LOCAL, 3)                                \
    X(kUniformPropsWorldNormal, UNIFORM_PROPS_WORLD_NORMAL, 4)                                     \
    X(kUniformPropsColor, UNIFORM_PROPS_COLOR, 5)                                                  \
    X(kUniformPropsLight, UNIFORM_PROPS_LIGHT, 6) /* unit, towards the light */                    \
    X(kUniformPropsAmbient, UNIFORM_PROPS_AMBIENT, 7)

#define SAMPLE_INTERFACE_ENUMERATOR(name, glsl, value) name = value,
enum SampleInterface : int { SAMPLE_INTERFACE(SAMPLE_INTERFACE_ENUMERATOR) };
#undef SAMPLE_INTERFACE_ENUMERATOR

// The text of "sample_interface.glsl": every entry above as a #define.
std::string sample_interface_glsl();

} // namespace cellfx_samples
