#version 450 core
// Based on: Roettger & Ertl 2003, §3 (emission model, no sort), made exact per fragment.
// Drawn on the BACK faces of every cell (front faces culled), additive blending into a float
// target, one draw per mesh. Each fragment finds its ray's segment inside the cell
// (cell_segment.glsl: exact entry through the cell's planes, clamped to the near plane and the
// scene's surface) and integrates its emission exactly through the cumulative table
// (segment_integral in project.glsl).
// Output: rgb = emission ∫c·σ, a = optical depth ∫σ (used by the fog resolve; ignored otherwise).
#include "project.glsl"
#include "cell_segment.glsl"

layout(location = 0) in vec3 v_position;
layout(location = 1) in float v_scalar;
layout(location = 2) flat in uint v_cell;
layout(location = 6) flat in vec2 v_scalar_bounds;

layout(location = 0) out vec4 o_color;

int cell_triangle_count() { return int(cell_first_triangle[v_cell + 1u] - cell_first_triangle[v_cell]); }
CellTriangle cell_triangle(int k) {
    Triangle t = triangles[cell_first_triangle[v_cell] + uint(k)];
    CellTriangle c;
    c.v = t.v.xyz;
    c.plane = t.plane;
    return c;
}

void main() {
    Ray ray = pixel_ray(v_position);
    float t_exit = dot(v_position - ray.origin, ray.dir);
    float s_exit = clamp(v_scalar, v_scalar_bounds.x, v_scalar_bounds.y); // see project.vert
    CellSegment segment = cell_segment(ray, t_exit, s_exit);
    o_color = segment_integral(segment.s_in, segment.s_out, segment.length);
}
