// The terrain library's shaders (shaders/terrain_*.{vert,frag}, embedded at build time by
// terrain/CMakeLists.txt) and the generated "terrain_interface.glsl" (render/terrain_interface.hpp),
// as a shader library. Private to cellfx::terrain.
#pragma once

#include "gl/shader_library.hpp"

namespace cellfx::terrain {

// Process-wide, immutable; built on first use.
const fx::gl::ShaderLibrary& terrain_shaders();

} // namespace cellfx::terrain
