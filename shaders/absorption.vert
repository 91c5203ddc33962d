#version 450 core
// Based on: Max, Williams & Silva 2000, §II — classic Absorption: the polygons of the CPU's
// projected subdivisions (fx/include/fx/absorption_classic.hpp), pulled from a storage buffer
// by gl_VertexID (glDrawElements: the index). Interpolation is linear on screen, as on the
// paper's hardware: exact for orthographic views, an approximation under perspective (§II).
//   BINDING_FRAME  vertices: position_uv = (NDC x, NDC y, u, v), color = (C/α, 0),
//              depth = (view depth of the ray's entry, of its exit, unused, unused)
#include "projector_interface.glsl"

struct ClassicVertex {
    vec4 position_uv;
    vec4 color;
    vec4 depth;
};
layout(std430, binding = BINDING_FRAME) readonly buffer ClassicVertices { ClassicVertex vertices[]; };

layout(location = 0) noperspective out vec2 v_uv;
layout(location = 1) noperspective out vec3 v_color;
layout(location = 2) noperspective out vec2 v_depth;

void main() {
    ClassicVertex v = vertices[gl_VertexID];
    gl_Position = vec4(v.position_uv.xy, 0.0, 1.0);
    v_uv = v.position_uv.zw;
    v_color = v.color.rgb;
    v_depth = v.depth.xy;
}
