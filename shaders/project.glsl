// Based on: Roettger & Ertl 2003, §3 and §5 — the polyhedron projector's GPU half, shared by
// every render path's shaders. Binding numbers, units and uniform locations come from the
// generated projector_interface.glsl (fx/src/projector/gl_interface.hpp); the mesh's buffers and
// how they are drawn: fx/src/projector/gl_projector.hpp.
//
// Tables (UNIT_TABLES, a buffer texture of three rows of n + 1 texels; linear interpolation done
// here in full float), n samples of [s_lo, s_hi]:
//   row 0: the cumulative E(s) = ∫c·σ ds (rgb) and T(s) = ∫σ ds (a) at the samples
//   row 1: the mean of c·σ (rgb) and σ (a) over each table cell, entry i + 1 for cell i, entry
//          0 below the table and n above it (the held end values)
//   row 2: c·σ (rgb) and σ (a) at the samples (mip, the classic vertex colours)
#include "projector_interface.glsl"

layout(location = UNIFORM_VIEW_PROJECTION) uniform mat4 u_view_projection; // relative frame → clip space
layout(location = UNIFORM_EYE) uniform vec3 u_eye;       // relative frame (orthographic: on the eye plane)
layout(location = UNIFORM_FORWARD) uniform vec3 u_forward; // unit view direction
layout(location = UNIFORM_NEAR) uniform float u_near;
layout(location = UNIFORM_ORTHOGRAPHIC) uniform int u_orthographic;
layout(location = UNIFORM_TABLE) uniform vec4 u_table;   // s_lo, s_hi, sample count, samples per unit s

layout(binding = UNIT_TABLES) uniform samplerBuffer u_tables;
vec4 table(int row, int i) { return texelFetch(u_tables, row * (int(u_table.z) + 1) + i); }

layout(location = UNIFORM_SCENE_DEPTH_RANGE) uniform vec2 u_scene_depth_range; // the projection's near and far distances
// An orthographic view's window z: near and the far it rasterises with (past the mesh, which
// the camera's far may cut: GlProjector::set_view_uniforms). Perspective passes read 1/w.
layout(location = UNIFORM_RASTER_DEPTH_RANGE) uniform vec2 u_raster_depth_range;
float orthographic_view_depth(float window_z) { return mix(u_raster_depth_range.x, u_raster_depth_range.y, window_z); }
#ifdef SCENE_DEPTH
// Scene depth (CellRenderOptions::scene_depth): the host's window-space depth.
layout(location = UNIFORM_SCENE_DEPTH_MODE) uniform int u_scene_depth_mode;   // 1 perspective, 2 orthographic
layout(location = UNIFORM_SCENE_ORIGIN) uniform ivec2 u_scene_origin;          // viewport origin in the depth texture
layout(binding = UNIT_SCENE_DEPTH) uniform sampler2D u_scene_depth;
#endif

// The ray through a fragment's pixel centre (gl_FragCoord.xy in the pass's target): the same ray
// as fx::Camera::pixel_ray, from uniforms linear in the pixel's offset from u_ray_centre, the
// (window) point whose ray is the view's axis (GlProjector::set_view_uniforms). That point is
// the whole frame's centre however the frame is cut into off-axis tiles, so a tile's offsets
// are the whole frame's less a whole number of pixels, subtracted exactly: a pixel gets the same
// float ray in a tile as in the whole frame (formed from each tile's own corner, they differed
// by rounding).
layout(location = UNIFORM_RAY_CENTRE) uniform vec2 u_ray_centre;
layout(location = UNIFORM_RAY_ORIGIN) uniform vec3 u_ray_origin;
layout(location = UNIFORM_RAY_ORIGIN_DX) uniform vec3 u_ray_origin_dx;
layout(location = UNIFORM_RAY_ORIGIN_DY) uniform vec3 u_ray_origin_dy;
layout(location = UNIFORM_RAY_DIRECTION) uniform vec3 u_ray_direction;
layout(location = UNIFORM_RAY_DIRECTION_DX) uniform vec3 u_ray_direction_dx;
layout(location = UNIFORM_RAY_DIRECTION_DY) uniform vec3 u_ray_direction_dy;

// d: distance beyond the near plane along the view direction (Roettger & Ertl's d).
float near_plane_distance(vec3 p) { return dot(p - u_eye, u_forward) - u_near; }

struct Ray {
    vec3 origin;
    vec3 dir; // unit
};
Ray fragment_ray(vec2 frag_coord) {
    Ray r;
    vec2 q = frag_coord - u_ray_centre;
    r.origin = u_ray_origin + q.x * u_ray_origin_dx + q.y * u_ray_origin_dy;
    r.dir = normalize(u_ray_direction + q.x * u_ray_direction_dx + q.y * u_ray_direction_dy);
    return r;
}
// Ray parameter where the ray meets the near plane.
float near_plane_t(Ray r) { return u_orthographic != 0 ? u_near : u_near / max(dot(r.dir, u_forward), 1e-6); }

// ---- transfer-function tables -------------------------------------------------------------
float table_x(float s) { return (s - u_table.x) * u_table.w; }

// Emission (rgb) and sigma (a) at s: row 2 interpolated linearly, end values held.
vec4 emission_at(float s) {
    float x = clamp(table_x(s), 0.0, u_table.z - 1.0);
    int i = min(int(x), int(u_table.z) - 2);
    return mix(table(2, i), table(2, i + 1), x - float(i));
}

// Emission (rgb) and optical depth (a) of a segment of length l with scalar s_front → s_back,
// linear along it: l times the mean of c·σ (σ) over [s_front, s_back] with E interpolated
// linearly between samples. The cells wholly inside the range come from the cumulative row,
// the partial cells at either end from their means, so nothing subtracts nearly equal values
// or divides by a tiny Δs; within one cell (s_front ≈ s_back included) it is that cell's mean.
vec4 segment_integral(float s_front, float s_back, float l) {
    float last = u_table.z - 1.0;
    float x0 = table_x(min(s_front, s_back)), x1 = table_x(max(s_front, s_back));
    float i0 = clamp(floor(x0), -1.0, last), i1 = clamp(floor(x1), -1.0, last); // −1: below the table
    vec4 mean0 = table(1, int(i0) + 1), mean1 = table(1, int(i1) + 1);
    // E(i1) − E(i0 + 1): the whole cells between the two ends (none for adjacent cells).
    vec4 middle = table(0, int(i1)) - table(0, int(max(i0 + 1.0, 0.0)));
    // In units of x (samples): the partial cells, the whole ones (E per unit s times u_table.w),
    // each weighted by l/(x1 − x0) before the sum: an end far beyond the table (a held value
    // times a huge run) would overflow the sum, while its share of l cannot. The whole cells'
    // weight is formed before it meets E: E times u_table.w alone reaches c·σ times the
    // samples, past float's range where c·σ peaks near 1e38 between two points.
    float per_x = l / (x1 - x0);
    vec4 total = mean0 * ((i0 + 1.0 - x0) * per_x) + middle * (u_table.w * per_x) + mean1 * ((x1 - i1) * per_x);
    return i0 == i1 ? mean0 * l : total;
}

// ---- scene depth ----------------------------------------------------------------------------
// View depth (distance from the eye plane along u_forward) of the scene surface behind the
// pixel at frag_coord (a fragment shader's gl_FragCoord.xy); 3.4e38 without a scene depth
// (SCENE_DEPTH not defined: the programs' variant for frames without one, ProgramVariants).
// Perspective: window depth w gives z_e = n·f / (f·(1 − w) + w·n) (GL's default depth range;
// 1 − w is exact near w = 1, so far surfaces keep what precision the depth buffer has).
float scene_view_depth(vec2 frag_coord) {
#ifndef SCENE_DEPTH
    return 3.4e38;
#else
    float w = texelFetch(u_scene_depth, ivec2(frag_coord) + u_scene_origin, 0).r;
    float n = u_scene_depth_range.x, f = u_scene_depth_range.y;
    if (u_scene_depth_mode == 2) return n + w * (f - n);
    return n * f / (f * (1.0 - w) + w * n);
#endif
}
// The same as a parameter along a ray from fragment_ray().
float scene_ray_t(Ray r, float view_depth) {
    return u_orthographic != 0 ? view_depth : view_depth / max(dot(r.dir, u_forward), 1e-6);
}
