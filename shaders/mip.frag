#version 450 core
// Based on: Roettger & Ertl 2003, §2 and §5 — maximum intensity projection: every face (and
// every near-plane cap) in any order with GL_MAX blending, one pass, no sort. With the scalar
// linear inside a cell, a segment's maximum emission is on its entry or exit face whenever
// c·σ is monotonic between the two scalars (see docs/render_paths.md for the exception).
#include "project.glsl"

layout(location = 0) in vec3 v_position;
layout(location = 1) in float v_scalar;
layout(location = 6) flat in vec2 v_scalar_bounds;

layout(location = 0) out vec4 o_color;

void main() {
    // Scene depth: faces behind the scene's surface are hidden (caps lie on the near plane).
    if (dot(v_position - u_eye, u_forward) > scene_view_depth(gl_FragCoord.xy)) discard;
    o_color = vec4(emission_at(clamp(v_scalar, v_scalar_bounds.x, v_scalar_bounds.y)).rgb, 0.0);
}
