#version 450 core
// Based on: Roettger & Ertl 2003, §3 and §5 — classic PCP, three passes per batch of cells
// (cells.vert with CELL_LIST and CLASSIC, caps.vert; fx/src/passes/pcp_pass.cpp sets blending
// and colour masks per pass):
//   pass 1  back faces  → alpha = (d − d_min)/Δd          (blend off, alpha only)
//   pass 2  front faces → alpha −= (d − d_min)/Δd          (reverse subtract, alpha only)
//           caps        → alpha −= (d_near − d_min)/Δd     (same, drawn after the front faces)
//   pass 3  all faces and caps → rgb += κ(S)·Δd/2 · dst alpha (glBlendFunc(GL_DST_ALPHA, GL_ONE))
// into an 8-bit RGBA target: the quantisation is the point of this path. With a scene depth,
// passes 1 and 2 clamp each face's d to the scene's, so the α difference ends at the surface.
// One addition to the paper: α·Δd is a difference of view depths; under perspective the ray
// through this pixel covers it over a length α·Δd / cos θ, so pass 3 divides by cos θ of the
// pixel's ray (1 for orthographic cameras). Without it the corners of a 40° view come out
// ~12% too dark, an error that would swamp the 8-bit one this path is kept to show.
#include "project.glsl"

layout(location = 3) in float v_alpha;
layout(location = 4) in vec3 v_color;
layout(location = 5) flat in vec2 v_range; // d_min, Δd

layout(location = UNIFORM_PASS) uniform int u_pass;

layout(location = 0) out vec4 o_color;

void main() {
    if (u_pass == 3) {
        float cos_theta = u_orthographic != 0 ? 1.0 : max(dot(fragment_ray(gl_FragCoord.xy).dir, u_forward), 1e-3);
        o_color = vec4(v_color / cos_theta, 0.0);
    } else {
        o_color = vec4(0.0, 0.0, 0.0, v_alpha);
#ifdef SCENE_DEPTH
        // Scene depth: d clamped to the surface's, so back minus front is the length in front of
        // it (caps, at d = 0, are never behind a surface beyond the near plane).
        float d = v_alpha * v_range.y + v_range.x;
        float d_scene = scene_view_depth(gl_FragCoord.xy) - u_near;
        if (v_range.y > 0.0) o_color.a = clamp((min(d, d_scene) - v_range.x) / v_range.y, 0.0, 1.0);
#endif
    }
}
