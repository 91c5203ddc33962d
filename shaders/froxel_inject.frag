#version 450 core
// Based on: Wronski 2014, "Volumetric fog" (froxels: screen tiles × exponential depth slices),
// with each volume's exact per-cell segment integrals in place of density samples — the froxel
// medium's injection (fx/internal/medium/froxel_medium.hpp). Drawn on the BACK faces of every
// cell of one absorbing volume (the renderer's GL projector: cells.vert, its buffers and
// tables) into a framebuffer of the grid's size without attachments: each fragment is a tile's
// centre ray leaving a cell. Its segment in the cell (cell_segment.glsl: entry through the
// cell's planes, clamped to the near plane; not cut by the scene's depth — the grid is read at
// each pixel's own depth) is cut at the slices' boundaries and every piece's exact integral
// (project.glsl's segment_integral: emission, optical depth) is added to its froxel.
#define FROXEL_INJECTION
#include "project.glsl"
#include "cell_segment.glsl"
#include "froxel_grid.glsl"

layout(location = UNIFORM_FROXEL_ALBEDO) uniform float u_albedo; // the fraction of the volume's extinction that scatters light

// froxel_data[i] += v as floats, by compare-and-swap.
void add_float(uint i, float v) {
    uint seen = froxel_data[i], expected;
    do {
        expected = seen;
        seen = atomicCompSwap(froxel_data[i], expected, floatBitsToUint(uintBitsToFloat(expected) + v));
    } while (seen != expected);
}

void main() {
    Ray ray = fragment_ray(gl_FragCoord.xy);
    CellSegment segment = cell_segment(ray);
    if (!(segment.length > 0.0)) return;
    // View depth per unit of t: slices are in view depth, the segment in t along the ray.
    float per_t = u_orthographic != 0 ? 1.0 : dot(ray.dir, u_forward);
    float t0 = segment.t_in, t1 = segment.t_in + segment.length;
    int k0 = slice_of(t0 * per_t), k1 = slice_of(t1 * per_t);
    ivec2 tile = ivec2(gl_FragCoord.xy);
    // Slice ends along the ray, each the last times e^step (one exp for the segment).
    float growth = exp(u_slicing.y), end = slice_start(k0 + 1) / per_t;
    for (int k = k0; k <= k1; ++k, end *= growth) {
        float a = k == k0 ? t0 : end / growth;
        float b = k == k1 ? t1 : end;
        if (!(b > a)) continue;
        float s_a = mix(segment.s_in, segment.s_out, (a - t0) / segment.length);
        float s_b = mix(segment.s_in, segment.s_out, (b - t0) / segment.length);
        // Emission (rgb) and optical depth (a); capped as pcp-exact caps a cell's, so that a
        // huge extinction over a huge cell stays a finite, opaque sum.
        vec4 m = min(segment_integral(s_a, s_b, b - a), vec4(1e30));
        uint base = froxel_base(ivec3(tile, k));
        if (m.r > 0.0) add_float(base + 0u, m.r);
        if (m.g > 0.0) add_float(base + 1u, m.g);
        if (m.b > 0.0) add_float(base + 2u, m.b);
        if (m.a > 0.0) {
            add_float(base + 3u, m.a);
            if (u_albedo > 0.0) add_float(base + 4u, u_albedo * m.a);
        }
    }
}
