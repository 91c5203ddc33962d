#version 450 core
// Based on: Roettger & Ertl 2003, §2 — the mesh's faces for maximum intensity projection, each
// face two cells share once (GlProjector::unique_face_triangles, UNIT_UNIQUE_FACES: three point
// ids per triangle): vertex gl_VertexID % 3 of triangle gl_VertexID / 3.
// v_scalar_bounds: the smallest and largest scalar of the triangle's corners. An interpolated
// value lies between them; rasterisers extrapolate at pixel centres barely inside slivers seen
// edge-on, so mip.frag clamps v_scalar to this range.
#include "project.glsl"

layout(binding = UNIT_POINTS) uniform samplerBuffer u_points;
layout(binding = UNIT_UNIQUE_FACES) uniform usamplerBuffer u_unique_faces;

layout(location = 1) out float v_scalar;
layout(location = 2) flat out vec2 v_scalar_bounds;

void main() {
    int face = gl_VertexID / 3;
    uvec3 ids = texelFetch(u_unique_faces, face).xyz;
    vec4 a = texelFetch(u_points, int(ids.x)), b = texelFetch(u_points, int(ids.y)), c = texelFetch(u_points, int(ids.z));
    int corner = gl_VertexID - 3 * face;
    vec4 p = corner == 0 ? a : (corner == 1 ? b : c);
    gl_Position = u_view_projection * vec4(p.xyz, 1.0);
    v_scalar = p.w;
    v_scalar_bounds = vec2(min(a.w, min(b.w, c.w)), max(a.w, max(b.w, c.w)));
}
