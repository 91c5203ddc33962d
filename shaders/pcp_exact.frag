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

layout(location = 0) out vec4 o_color;

void main() {
    CellSegment segment = cell_segment(fragment_ray(gl_FragCoord.xy));
    o_color = segment_integral(segment.s_in, segment.s_out, segment.length);
}
