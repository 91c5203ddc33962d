#version 450 core
// Based on: Max, Williams & Silva 2000, §II — classic Absorption: the polygons of the CPU's
// projected subdivisions (fx/src/absorption/absorption_classic.hpp), indexed triangles of their
// vertices as vertex attributes (fx::ClassicVertex). Interpolation is linear on screen, as on
// the paper's hardware: exact for orthographic views, an approximation under perspective (§II).
//   location 0  position_uv = (NDC x, NDC y, u, v)
//   location 1  color = C/α
//   location 2  depth = (view depth of the ray's entry, of its exit)
layout(location = 0) in vec4 a_position_uv;
layout(location = 1) in vec3 a_color;
layout(location = 2) in vec2 a_depth;

layout(location = 0) noperspective out vec2 v_uv;
layout(location = 1) noperspective out vec3 v_color;
layout(location = 2) noperspective out vec2 v_depth;

void main() {
    gl_Position = vec4(a_position_uv.xy, 0.0, 1.0);
    v_uv = a_position_uv.zw;
    v_color = a_color;
    v_depth = a_depth;
}
