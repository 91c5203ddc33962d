// Based on: Roettger & Ertl 2003, §3 and §5 — the polyhedron projector's GPU half, shared by
// the PCP, PCP-exact and MIP paths (shaders/project.vert and the three fragment shaders).
//
// Mesh data, uploaded once per mesh (fx/src/projector/gl_projector.cpp); binding numbers, units
// and uniform locations come from the generated projector_interface.glsl (gl_interface.hpp):
//   binding 0  points:    xyz relative to the mesh centre, w = scalar
//   binding 1  triangles: v.xyz point ids (CCW seen from outside), v.w owning cell;
//                         plane = outward unit normal, w = n·p (zero for a zero-area triangle)
//   binding 2  cells:     first triangle of each cell (cell_count + 1 entries)
// Per-frame data (classic PCP batches and near-plane caps), binding 3: see project.vert.
// Tables (texture unit 0, texelFetch only, linear interpolation done here in full float):
//   row 0: cumulative emission E(s) (rgb) and cumulative extinction T(s) = ∫σ ds (a),
//          from fx::build_emission_table — a segment's emission is l·(E(s_b) − E(s_f))/(s_b − s_f)
//   row 1: emission c·σ (rgb) and σ (a) at the same samples (MIP, classic vertex colours,
//          and the held end values outside the table's range)

#include "projector_interface.glsl"

struct Triangle {
    uvec4 v;
    vec4 plane;
};
layout(std430, binding = BINDING_POINTS) readonly buffer PointBuffer { vec4 points[]; };
layout(std430, binding = BINDING_TRIANGLES) readonly buffer TriangleBuffer { Triangle triangles[]; };
layout(std430, binding = BINDING_CELLS) readonly buffer CellBuffer { uint cell_first_triangle[]; };
layout(std430, binding = BINDING_FRAME) readonly buffer FrameBuffer { uvec4 frame_data[]; };

layout(location = UNIFORM_VIEW_PROJECTION) uniform mat4 u_view_projection; // relative frame → clip space
layout(location = UNIFORM_EYE) uniform vec3 u_eye;       // relative frame (orthographic: on the eye plane)
layout(location = UNIFORM_FORWARD) uniform vec3 u_forward; // unit view direction
layout(location = UNIFORM_NEAR) uniform float u_near;
layout(location = UNIFORM_ORTHOGRAPHIC) uniform int u_orthographic;
layout(location = UNIFORM_TABLE) uniform vec4 u_table;   // s_lo, s_hi, sample count, samples per unit s

layout(binding = UNIT_TABLES) uniform sampler2D u_tables;

// Scene depth (CellRenderOptions::scene_depth): the host's window-space depth.
layout(location = UNIFORM_SCENE_DEPTH_MODE) uniform int u_scene_depth_mode;   // 0 none, 1 perspective, 2 orthographic
layout(location = UNIFORM_SCENE_DEPTH_RANGE) uniform vec2 u_scene_depth_range; // the projection's near and far distances
layout(location = UNIFORM_SCENE_ORIGIN) uniform ivec2 u_scene_origin;          // viewport origin in the depth texture
layout(binding = UNIT_SCENE_DEPTH) uniform sampler2D u_scene_depth;

// d: distance beyond the near plane along the view direction (Roettger & Ertl's d).
float near_plane_distance(vec3 p) { return dot(p - u_eye, u_forward) - u_near; }

struct Ray {
    vec3 origin;
    vec3 dir; // unit
};
Ray pixel_ray(vec3 p) {
    Ray r;
    if (u_orthographic != 0) {
        r.dir = u_forward;
        r.origin = p - u_forward * dot(p - u_eye, u_forward);
    } else {
        r.origin = u_eye;
        r.dir = normalize(p - u_eye);
    }
    return r;
}
// Ray parameter where the ray meets the near plane.
float near_plane_t(Ray r) { return u_orthographic != 0 ? u_near : u_near / max(dot(r.dir, u_forward), 1e-6); }

// ---- transfer-function tables -------------------------------------------------------------
int table_size() { return int(u_table.z); }
float table_x(float s) { return (s - u_table.x) * u_table.w; }

// Emission (rgb) and sigma (a) at s: row 1 interpolated linearly, end values held.
vec4 emission_at(float s) {
    float x = clamp(table_x(s), 0.0, u_table.z - 1.0);
    int i = min(int(x), table_size() - 2);
    return mix(texelFetch(u_tables, ivec2(i, 1), 0), texelFetch(u_tables, ivec2(i + 1, 1), 0), x - float(i));
}

// Cumulative (E rgb, T a) at s, with the held end values continuing it linearly outside.
vec4 cumulative_at(float s) {
    float x = table_x(s);
    int n = table_size();
    if (x <= 0.0) return texelFetch(u_tables, ivec2(0, 0), 0) + texelFetch(u_tables, ivec2(0, 1), 0) * (s - u_table.x);
    if (x >= float(n - 1))
        return texelFetch(u_tables, ivec2(n - 1, 0), 0) + texelFetch(u_tables, ivec2(n - 1, 1), 0) * (s - u_table.y);
    int i = int(x);
    return mix(texelFetch(u_tables, ivec2(i, 0), 0), texelFetch(u_tables, ivec2(i + 1, 0), 0), x - float(i));
}

// Table cell of s: -1 below the table, n-1 above it.
int table_cell(float s) {
    float x = table_x(s);
    int n = table_size();
    return x < 0.0 ? -1 : (x >= float(n - 1) ? n - 1 : int(x));
}
// dE/ds (and dT/ds) on a table cell: exactly the slope of the linear interpolation.
vec4 cell_slope(int i) {
    int n = table_size();
    if (i < 0) return texelFetch(u_tables, ivec2(0, 1), 0);
    if (i >= n - 1) return texelFetch(u_tables, ivec2(n - 1, 1), 0);
    return (texelFetch(u_tables, ivec2(i + 1, 0), 0) - texelFetch(u_tables, ivec2(i, 0), 0)) * u_table.w;
}

// Emission (rgb) and optical depth (a) of a segment of length l with scalar s_front → s_back,
// linear along it: l·(E(s_b) − E(s_f))/(s_b − s_f), E interpolated linearly between samples.
// Ends in one table cell (s_f ≈ s_b included): that cell's slope. Ends in adjacent cells:
// the two slopes weighted by the scalar fractions on either side of the sample between them.
// Neither case subtracts nearly equal E values or divides by a tiny Δs; further apart, the E
// difference spans at least a whole cell, so its float cancellation stays bounded.
vec4 segment_integral(float s_front, float s_back, float l) {
    int cf = table_cell(s_front), cb = table_cell(s_back);
    if (cf == cb) return cell_slope(cf) * l;
    if (abs(cf - cb) == 1) {
        int lower = min(cf, cb);
        float x_lo = table_x(min(s_front, s_back)), x_hi = table_x(max(s_front, s_back));
        float w = clamp((float(lower + 1) - x_lo) / max(x_hi - x_lo, 1e-30), 0.0, 1.0);
        return (cell_slope(lower) * w + cell_slope(lower + 1) * (1.0 - w)) * l;
    }
    return (cumulative_at(s_back) - cumulative_at(s_front)) * (l / (s_back - s_front));
}

// ---- scene depth ----------------------------------------------------------------------------
// View depth (distance from the eye plane along u_forward) of the scene surface behind the
// pixel at frag_coord (a fragment shader's gl_FragCoord.xy); 3.4e38 without a scene depth. Perspective: window depth w gives
// z_e = n·f / (f·(1 − w) + w·n) (GL's default depth range; 1 − w is exact near w = 1, so far
// surfaces keep what precision the depth buffer has).
float scene_view_depth(vec2 frag_coord) {
    if (u_scene_depth_mode == 0) return 3.4e38;
    float w = texelFetch(u_scene_depth, ivec2(frag_coord) + u_scene_origin, 0).r;
    float n = u_scene_depth_range.x, f = u_scene_depth_range.y;
    if (u_scene_depth_mode == 2) return n + w * (f - n);
    return n * f / (f * (1.0 - w) + w * n);
}
// The same as a parameter along a ray from pixel_ray().
float scene_ray_t(Ray r, float view_depth) {
    return u_orthographic != 0 ? view_depth : view_depth / max(dot(r.dir, u_forward), 1e-6);
}
