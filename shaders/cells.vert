#version 450 core
// Based on: Roettger & Ertl 2003, §3 — the projector's vertex stage for a mesh's cells: vertex
// id slot·VERTICES_PER_CELL + k is vertex k of the cell in `slot` (fx/src/projector/
// gl_projector.hpp), fetched from buffer textures; the element buffer makes the cell's face
// triangles of them, so each vertex of a cell is transformed once.
//   default     slot = the cell (the mesh's own numbering)
//   CELL_LIST   slot → entry of a frame's list (UNIT_CELL_LIST): a cell, or, with
//               PIECE_BIT_INDEX set, a tetrahedron made for the frame (UNIT_PIECE_POINTS)
//   CLASSIC     classic PCP: per vertex α = (d − d_min)/Δd and κ(S)·Δd/2 from the slot's
//               (d_min, Δd) (UNIT_SLOT_DATA)
// The cell's word goes to the fragment shader as one flat integer, and with cells other than
// tetrahedra the first of its barycentric row pairs (UNIT_FOLD_BASES: read by cells that are
// not planar only) as another.
#include "project.glsl"

layout(binding = UNIT_POINTS) uniform samplerBuffer u_points;
layout(binding = UNIT_CONNECTIVITY) uniform usamplerBuffer u_connectivity;
layout(binding = UNIT_CELL_OFFSETS) uniform usamplerBuffer u_cell_offsets;
layout(binding = UNIT_CELL_WORDS) uniform usamplerBuffer u_cell_words;
#ifdef CELL_LIST
layout(binding = UNIT_CELL_LIST) uniform usamplerBuffer u_cell_list;
layout(binding = UNIT_PIECE_POINTS) uniform usamplerBuffer u_piece_points;
layout(location = UNIFORM_PIECE_BASE) uniform uint u_piece_base;
#endif

layout(location = 0) flat out uint v_word;
#if VERTICES_PER_CELL == 8
layout(binding = UNIT_FOLD_BASES) uniform usamplerBuffer u_fold_bases;
layout(location = 1) flat out uint v_fold;
#endif
#ifdef CLASSIC
layout(binding = UNIT_SLOT_DATA) uniform samplerBuffer u_slot_ranges; // d_min, Δd
layout(location = 3) out float v_alpha;     // (d − d_min)/Δd
layout(location = 4) out vec3 v_color;      // κ(S)·Δd/2
layout(location = 5) flat out vec2 v_range; // d_min, Δd (scene-depth clamp)
#endif

void main() {
    int slot = gl_VertexID / VERTICES_PER_CELL, k = gl_VertexID - slot * VERTICES_PER_CELL;
    uint cell = uint(slot), point, word, fold = 0u;
#ifdef CELL_LIST
    cell = texelFetch(u_cell_list, slot).x;
    if ((cell & (1u << PIECE_BIT_INDEX)) != 0u) {
        uint piece = cell & ~(1u << PIECE_BIT_INDEX);
        point = texelFetch(u_piece_points, int(piece))[min(k, 3)];
        word = ((u_piece_base + 4u * piece) << WORD_FIRST_SHIFT) | (1u << WORD_PLANAR_BIT) | 3u; // a tetrahedron: planar
    } else
#endif
    {
        point = texelFetch(u_connectivity, int(texelFetch(u_cell_offsets, int(cell)).x) + k).x;
        word = texelFetch(u_cell_words, int(cell)).x;
#if VERTICES_PER_CELL == 8
        fold = texelFetch(u_fold_bases, int(cell)).x;
#endif
    }
    vec4 p = texelFetch(u_points, int(point));
    gl_Position = u_view_projection * vec4(p.xyz, 1.0);
    v_word = word;
#if VERTICES_PER_CELL == 8
    v_fold = fold;
#endif
#ifdef CLASSIC
    vec2 range = texelFetch(u_slot_ranges, slot).xy;
    float d = near_plane_distance(p.xyz);
    v_range = range;
    v_alpha = range.y > 0.0 ? clamp((d - range.x) / range.y, 0.0, 1.0) : 0.0;
    // Classic colour I = κ(S)·Δd/2 (§3); pcp.frag turns view depth into length along the ray.
    // Its 8-bit target saturates at 1: bounded here so that a huge cell's colour is never Inf,
    // which interpolation would turn into NaN (Inf·0).
    v_color = min(emission_at(p.w).rgb * (0.5 * range.y), vec3(1e30));
#endif
}
