#version 450 core
// The samples' frame-stats line (samples/common/sample_gl.cpp): stb_easy_font quads in pixels
// with the origin at the top left of the viewport, scaled, to clip space.
#include "sample_interface.glsl"

layout(location = 0) in vec2 a_position; // pixels, y down
layout(location = 1) in vec4 a_color;    // unorm RGBA
layout(location = UNIFORM_TEXT_VIEWPORT_SIZE) uniform vec2 u_viewport_size;
layout(location = UNIFORM_TEXT_OFFSET) uniform vec2 u_offset;
layout(location = UNIFORM_TEXT_SCALE) uniform float u_scale;

layout(location = 0) out vec4 v_color;

void main() {
    vec2 p = u_offset + a_position * u_scale;
    gl_Position = vec4(2.0 * p.x / u_viewport_size.x - 1.0, 1.0 - 2.0 * p.y / u_viewport_size.y, 0.0, 1.0);
    v_color = a_color;
}
