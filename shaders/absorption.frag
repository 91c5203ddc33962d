#version 450 core
// Based on: Max, Williams & Silva 2000, §II — classic Absorption: α = 1 − exp(−l·τ_a) from
// the 2-D texture of 1 − exp(−K·u·v) (u ∝ thickness, v ∝ mean extinction, scaled jointly per
// piece on the CPU), read with bilinear interpolation done here in full float (texelFetch):
// near α = 0 the table is bilinear in u·v, so thin cells keep their relative accuracy, which
// fixed-point texture filtering would lose. Output premultiplied, composited back to front
// with glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA) ("over", Eq. 1). With a scene depth
// (project.glsl) only the part of the ray in front of the scene's surface counts: the
// thickness coordinate u is scaled by it (the polygon colour is kept, an approximation).
#include "project.glsl"

layout(binding = UNIT_OPACITY) uniform samplerBuffer u_opacity; // R32F, size × size, u along x
layout(location = UNIFORM_OPACITY_SIZE) uniform int u_opacity_size;

layout(location = 0) noperspective in vec2 v_uv;
layout(location = 1) noperspective in vec3 v_color;
layout(location = 2) noperspective in vec2 v_depth; // view depths of the entry and the exit

layout(location = 0) out vec4 o_color;

float opacity(vec2 uv) {
    // Clamped at the ends, never wrapped (§II: "care must be taken ... to clamp the address").
    vec2 x = clamp(uv, 0.0, 1.0) * float(u_opacity_size - 1);
    ivec2 i = min(ivec2(x), ivec2(u_opacity_size - 2));
    vec2 f = x - vec2(i);
    int k = i.y * u_opacity_size + i.x;
    float a = texelFetch(u_opacity, k).r, b = texelFetch(u_opacity, k + 1).r;
    float c = texelFetch(u_opacity, k + u_opacity_size).r, d = texelFetch(u_opacity, k + u_opacity_size + 1).r;
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

void main() {
    float keep = 1.0; // fraction of the segment in front of the scene
    float z_scene = scene_view_depth(gl_FragCoord.xy);
    if (z_scene < v_depth.y) {
        float span = v_depth.y - v_depth.x;
        keep = span > 0.0 ? clamp((z_scene - v_depth.x) / span, 0.0, 1.0) : 0.0;
    }
    float alpha = opacity(vec2(v_uv.x * keep, v_uv.y));
    o_color = vec4(v_color * alpha, alpha);
}
