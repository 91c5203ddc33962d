#version 450 core
// Based on: Roettger & Ertl 2003, §2 and §5 — maximum intensity projection: every face once
// (faces.vert) and every near-plane cap (caps.vert, CAPS defined) in any order with GL_MAX
// blending, one pass, no sort. With the scalar linear inside a cell, a segment's maximum
// emission is on its entry or exit face whenever c·σ is monotonic between the two scalars
// (see docs/render_paths.md for the exception).
#include "project.glsl"

layout(location = 1) in float v_scalar;
layout(location = 2) flat in vec2 v_scalar_bounds;

layout(location = 0) out vec4 o_color;

void main() {
#ifndef CAPS
    // Scene depth: faces behind the scene's surface are hidden (caps lie on the near plane). The
    // fragment's own view depth: 1/w of a perspective projection, linear in window z otherwise.
    float view_depth = u_orthographic != 0 ? orthographic_view_depth(gl_FragCoord.z)
                                           : 1.0 / gl_FragCoord.w;
    if (view_depth > scene_view_depth(gl_FragCoord.xy)) discard;
#endif
    o_color = vec4(emission_at(clamp(v_scalar, v_scalar_bounds.x, v_scalar_bounds.y)).rgb, 0.0);
}
