#version 450 core
// The froxel medium over the frame (fx/internal/medium/froxel_medium.hpp): every pixel reads
// the integrated grid at its own scene depth — the light of the volumes in front of its
// surface and their optical depth τ — and is composited premultiplied "over" what is drawn
// (glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA)): L + e^(−τ)·frame. So an edge against geometry
// is as sharp as the depth buffer, whatever the tile size. Drawn as one full-screen triangle
// (fullscreen.vert) at the target's full resolution.
#define FROXEL_INTEGRATED_UNIT 0
#include "froxel_grid.glsl"

layout(binding = 1) uniform sampler2D u_scene_depth; // canonical window depth (0: none, see u_depth)
layout(location = UNIFORM_FROXEL_APPLY_VIEWPORT) uniform vec4 u_viewport;         // x, y, width, height in the framebuffer
layout(location = UNIFORM_FROXEL_APPLY_DEPTH_ORIGIN) uniform ivec2 u_depth_origin; // texel of the viewport's pixel (0, 0)
layout(location = UNIFORM_FROXEL_APPLY_DEPTH) uniform vec3 u_depth;                // near, far, 0 none / 1 perspective / 2 orthographic

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    vec2 pixel = gl_FragCoord.xy - u_viewport.xy;
    float z = 3.4e38; // no scene depth: the whole column
    if (u_depth.z > 0.5) {
        float w = texelFetch(u_scene_depth, ivec2(pixel) + u_depth_origin, 0).r, n = u_depth.x, f = u_depth.y;
        z = u_depth.z > 1.5 ? n + w * (f - n) : n * f / (f * (1.0 - w) + w * n);
    }
    vec4 m = medium_in_front(pixel / u_viewport.zw, z);
    o_color = vec4(m.rgb, 1.0 - exp(-m.a));
}
