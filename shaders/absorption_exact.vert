#version 450 core
// Based on: Max, Williams & Silva 2000, §III–§V — exact Absorption: the cells' triangles in
// visibility order (one draw; GL blends primitives in order), pulled by gl_VertexID.
// frame_data (BINDING_FRAME) holds one item per cell, back to front:
//   (cell, 0xFFFFFFFF, 0, 0)   a whole cell of the mesh: its triangles from bindings 1–2
//   (p0, p1, p2, p3)           a tetrahedron of a cell subdivided for this view (§V)
// Item k owns vertices [k·u_slot_vertices, (k + 1)·u_slot_vertices): 3 per triangle, as many
// as the largest item has; slots past an item's own triangles are placed beyond the far
// plane and clipped away.
#include "project.glsl"
#include "absorption_items.glsl"

layout(location = UNIFORM_SLOT_VERTICES) uniform int u_slot_vertices;

layout(location = 0) out vec3 v_position; // relative frame
layout(location = 1) out float v_scalar;
layout(location = 2) flat out uvec4 v_item;

void main() {
    int slot = gl_VertexID / u_slot_vertices, local = gl_VertexID - slot * u_slot_vertices;
    int k = local / 3, corner = local - 3 * k;
    uvec4 item = frame_data[slot];
    if (k >= item_triangle_count(item)) {
        gl_Position = vec4(0.0, 0.0, 2.0, 1.0); // beyond the far plane: clipped
        return;
    }
    vec4 p = points[item_triangle_points(item, k)[corner]];
    gl_Position = u_view_projection * vec4(p.xyz, 1.0);
    v_position = p.xyz;
    v_scalar = p.w;
    v_item = item;
}
