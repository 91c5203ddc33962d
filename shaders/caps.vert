#version 450 core
// Based on: Roettger & Ertl 2003, §5 — near-plane cap triangles (each cell the near plane cuts,
// closed on the plane), pulled from the frame's storage buffer by gl_VertexID:
// frame_data[2·gl_VertexID] = (x, y, z, scalar bits), frame_data[2·gl_VertexID + 1] =
// (d_min bits, Δd bits, 0, 0) (GlProjector::append_cap_vertices). They lie on the near plane:
// their clip z is set to 0 so that rounding cannot clip them. Outputs match cells.vert's
// CLASSIC ones (classic PCP) and faces.vert's (mip).
#include "project.glsl"

layout(std430, binding = BINDING_FRAME) readonly buffer FrameBuffer { uvec4 frame_data[]; };

layout(location = 1) out float v_scalar;
layout(location = 2) flat out vec2 v_scalar_bounds;
layout(location = 3) out float v_alpha;
layout(location = 4) out vec3 v_color;
layout(location = 5) flat out vec2 v_range;

void main() {
    uvec4 a = frame_data[2 * gl_VertexID];
    vec2 range = uintBitsToFloat(frame_data[2 * gl_VertexID + 1].xy);
    vec3 p = uintBitsToFloat(a.xyz);
    float s = uintBitsToFloat(a.w);
    int first = gl_VertexID - gl_VertexID % 3; // cap fans are drawn as separate triangles
    vec3 corner_scalars;
    for (int k = 0; k < 3; ++k) corner_scalars[k] = uintBitsToFloat(frame_data[2 * (first + k)].w);
    gl_Position = u_view_projection * vec4(p, 1.0);
    gl_Position.z = 0.0;
    v_scalar = s;
    v_scalar_bounds = vec2(min(corner_scalars.x, min(corner_scalars.y, corner_scalars.z)),
                           max(corner_scalars.x, max(corner_scalars.y, corner_scalars.z)));
    v_range = range;
    v_alpha = range.y > 0.0 ? clamp((0.0 - range.x) / range.y, 0.0, 1.0) : 0.0; // d = 0 on the near plane
    v_color = min(emission_at(s).rgb * (0.5 * range.y), vec3(1e30)); // finite, as in cells.vert
}
