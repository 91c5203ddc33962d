#version 450 core
// Based on: Roettger & Ertl 2003, §3 — the projector's vertex stage for every GPU path.
// Vertices are pulled from storage buffers by gl_VertexID; no vertex attributes.
//
// u_source selects what is drawn:
//   SOURCE_MESH    every cell triangle: vertex k of triangle gl_VertexID / 3 (pcp-exact, mip)
//   SOURCE_BATCH classic PCP: slot gl_VertexID / SLOT_VERTICES of the frame's cell list, frame_data[slot] =
//            (cell, d_min bits, Δd bits, 0); local triangle (gl_VertexID % SLOT_VERTICES) / 3 of that cell
//            (slots past the cell's own triangle count are degenerate and clipped away)
//   SOURCE_CAPS  near-plane cap triangles: frame_data[u_cap_base + 2·gl_VertexID] =
//            (x, y, z, scalar bits), frame_data[… + 1] = (d_min bits, Δd bits, 0, 0)
// Caps lie on the near plane: their clip z is set to 0 so that rounding cannot clip them.
#include "project.glsl"

layout(location = UNIFORM_SOURCE) uniform int u_source;
layout(location = UNIFORM_CAP_BASE) uniform int u_cap_base;

layout(location = 0) out vec3 v_position; // relative frame
layout(location = 1) out float v_scalar;
layout(location = 2) flat out uint v_cell;
layout(location = 3) out float v_alpha;   // classic PCP: (d − d_min)/Δd
layout(location = 4) out vec3 v_color;    // classic PCP: κ(S)·Δd/2
layout(location = 5) flat out vec2 v_range; // classic PCP: d_min, Δd (scene-depth clamp)
// Smallest and largest scalar of the triangle's three vertices. An interpolated value lies
// between them; rasterisers extrapolate at pixel centres barely inside slivers seen edge-on,
// so the paths clamp v_scalar to this range.
layout(location = 6) flat out vec2 v_scalar_bounds;

void main() {
    vec3 p;
    float s;
    uint cell = 0u;
    vec2 range = vec2(0.0); // d_min, Δd
    bool cap = false;
    vec3 corner_scalars;
    if (u_source == SOURCE_CAPS) {
        uvec4 a = frame_data[u_cap_base + 2 * gl_VertexID];
        uvec4 b = frame_data[u_cap_base + 2 * gl_VertexID + 1];
        p = uintBitsToFloat(a.xyz);
        s = uintBitsToFloat(a.w);
        range = uintBitsToFloat(b.xy);
        cap = true;
        int first = gl_VertexID - gl_VertexID % 3; // cap fans are drawn as separate triangles
        for (int k = 0; k < 3; ++k) corner_scalars[k] = uintBitsToFloat(frame_data[u_cap_base + 2 * (first + k)].w);
    } else {
        uint t;
        int corner;
        if (u_source == SOURCE_BATCH) {
            int slot = gl_VertexID / SLOT_VERTICES, local = gl_VertexID - slot * SLOT_VERTICES;
            uvec4 entry = frame_data[slot];
            cell = entry.x;
            range = uintBitsToFloat(entry.yz);
            uint first = cell_first_triangle[cell];
            uint k = uint(local / 3);
            if (first + k >= cell_first_triangle[cell + 1u]) {
                gl_Position = vec4(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
                return;
            }
            t = first + k;
            corner = local % 3;
        } else {
            t = uint(gl_VertexID / 3);
            corner = gl_VertexID % 3;
        }
        Triangle tri = triangles[t];
        cell = tri.v.w;
        vec4 point = points[tri.v[corner]];
        p = point.xyz;
        s = point.w;
        corner_scalars = vec3(points[tri.v.x].w, points[tri.v.y].w, points[tri.v.z].w);
    }
    v_scalar_bounds = vec2(min(corner_scalars.x, min(corner_scalars.y, corner_scalars.z)),
                           max(corner_scalars.x, max(corner_scalars.y, corner_scalars.z)));
    gl_Position = u_view_projection * vec4(p, 1.0);
    if (cap) gl_Position.z = 0.0;
    v_position = p;
    v_scalar = s;
    v_cell = cell;
    float d = cap ? 0.0 : near_plane_distance(p);
    v_range = range;
    v_alpha = range.y > 0.0 ? clamp((d - range.x) / range.y, 0.0, 1.0) : 0.0;
    // Classic colour I = κ(S)·Δd/2 (§3); pcp.frag turns view depth into length along the ray.
    v_color = emission_at(s).rgb * (0.5 * range.y);
}
