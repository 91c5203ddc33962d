#version 450 core
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (a pixel's crossings of every grid) — the
// medium compositor's append pass (fx/internal/medium/medium_compositor.hpp): drawn on the BACK faces of every
// cell of one volume (the renderer's GL projector: cells.vert, its buffers and uniforms) into the compositor's own
// framebuffer (viewport pixels). Each fragment finds its ray's exact segment in the cell
// (cell_segment.glsl: entry through the cell's planes, near plane, scene depth) and pushes it
// onto its pixel's list; the other volumes mark the mask where they cover, the bulk volume
// (the fog) appends only inside it.
#include "project.glsl"
#include "cell_segment.glsl"
#include "medium_lists.glsl"

layout(location = UNIFORM_MEDIUM_VOLUME) uniform uint u_volume;
layout(location = UNIFORM_MEDIUM_CAPACITY) uniform uint u_capacity; // segments the pool holds
// 0: the volume marks the mask where it covers (o_mask = 1); 1: the bulk volume appends only
// where the mask is set (nothing attached to write).
layout(location = UNIFORM_MEDIUM_MASK_MODE) uniform int u_mask_mode;
layout(binding = 1) uniform sampler2D u_mask;

layout(location = 0) out float o_mask;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    o_mask = 1.0;
    if (any(lessThan(p, u_region.xy)) || any(greaterThanEqual(p, u_region.xy + u_region.zw))) return;
    if (u_mask_mode == 1 && texelFetch(u_mask, p, 0).r < 0.5) return;
    CellSegment segment = cell_segment(fragment_ray(gl_FragCoord.xy));
    if (!(segment.length > 0.0)) return;
    uint index = atomicAdd(medium_count, 1u);
    if (index >= u_capacity) return; // counted: the compositor grows the pool and appends again
    uint base = segment_base(index);
    medium_data[base + 0u] = floatBitsToUint(segment.t_in);
    medium_data[base + 1u] = floatBitsToUint(segment.t_in + segment.length);
    medium_data[base + 2u] = floatBitsToUint(segment.s_in);
    medium_data[base + 3u] = floatBitsToUint(segment.s_out);
    uint next = atomicExchange(medium_data[region_pixel(p)], index + 1u);
    medium_data[base + 4u] = (next << kVolumeBits) | u_volume;
}
