#version 450 core
// Based on: Roettger & Ertl 2003, §3 (emission model, no sort), made exact per fragment.
// Drawn on the BACK faces of every cell (front faces culled), additive blending into a float
// target, one draw per mesh: each pixel a cell covers gets one fragment, which finds its ray's
// segment inside the cell (cell_segment.glsl: exact entry and exit through the cell's planes,
// clamped to the near plane and the scene's surface) and integrates its emission exactly
// through the cumulative table (segment_integral in project.glsl).
// Output: rgb = emission ∫c·σ, a = optical depth ∫σ (used by the fog resolve; ignored otherwise).
#include "project.glsl"
#include "cell_segment.glsl"

// With fog, each cell's optical depth is capped here (PcpExactPass: 1e30, opaque many times
// over, and far from a float's 3.4e38 even after hundreds of such cells are summed) and its
// emission scaled alike, so that a huge extinction over a huge cell keeps the ratio the fog
// resolve divides out instead of overflowing both to Inf; emission alone is not capped (+Inf),
// and a sum past a float's range saturates in the resolve.
layout(location = UNIFORM_MAX_OPTICAL_DEPTH) uniform float u_max_optical_depth;

layout(location = 0) out vec4 o_color;

void main() {
    CellSegment segment = cell_segment(fragment_ray(gl_FragCoord.xy));
    vec4 per_length = segment_integral(segment.s_in, segment.s_out, 1.0); // linear in the length
    float l = min(segment.length, u_max_optical_depth / max(per_length.a, 1e-30));
    o_color = per_length * l;
}
