#version 450 core
// The terrain surface (terrain/src/render/surface_renderer.cpp): the element index is a sample of
// the height field (j·size + i, gl_VertexID under glDrawElements); its position comes from the
// grid and its height (as the LOD morphed it) from a storage buffer, relative to the field's
// centre.
layout(std430, binding = 0) readonly buffer Heights { float heights[]; }; // per sample, relative frame

#include "terrain_interface.glsl"
layout(location = UNIFORM_SURFACE_VIEW_PROJECTION) uniform mat4 u_view_projection; // relative frame → clip space
layout(location = UNIFORM_SURFACE_SIZE) uniform int u_size;                        // samples per side
layout(location = UNIFORM_SURFACE_FIRST_SAMPLE) uniform vec2 u_first_sample;       // relative frame xy of sample (0, 0)
layout(location = UNIFORM_SURFACE_SPACING) uniform float u_spacing;

layout(location = 0) out vec3 v_position; // relative frame

void main() {
    int i = gl_VertexID % u_size, j = gl_VertexID / u_size;
    vec3 p = vec3(u_first_sample + vec2(i, j) * u_spacing, heights[gl_VertexID]);
    v_position = p;
    gl_Position = u_view_projection * vec4(p, 1.0);
}
