#version 450 core
// Based on: Max, Williams & Silva 2000, §II (the volume density model, composited back to
// front with "over") made exact per fragment. Drawn on the BACK faces of every item (front
// faces culled), items in visibility order: each fragment is where its ray leaves the cell.
// The entry is the last front-facing plane the ray crosses (checked against its triangle, for
// the two triangles of a quad and slightly curved cells), clamped to the near plane — so a camera inside the mesh composites only what lies ahead.
// The scalar is face-linear at both ends (barycentric on the entry triangle, interpolated on
// the exit one) and linear along the ray, and it ends at the scene's surface where one is given
// (CellRenderOptions::scene_depth); colour and opacity of the segment come from the
// pre-integration table over (s_front, s_back, length) built by fx::build_preintegration_table
// from the exact integrals, interpolated trilinearly here in full float. Output premultiplied,
// into a float target with glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA).
#include "project.glsl"
#include "absorption_items.glsl"

layout(location = 0) in vec3 v_position;
layout(location = 1) in float v_scalar;
layout(location = 2) flat in uvec4 v_item;

// x = s_front, y = s_back (n_s samples of [s_lo, s_hi]), z = length (n_l samples of [0, max]).
layout(binding = 2) uniform sampler3D u_preintegration;
layout(location = 7) uniform vec3 u_preint;        // s_lo, samples per unit s, samples per unit length
layout(location = 8) uniform ivec3 u_preint_size; // n_s, n_s, n_l

layout(location = 0) out vec4 o_color;

vec4 preintegrated(float s_front, float s_back, float l) {
    vec3 x = vec3((s_front - u_preint.x) * u_preint.y, (s_back - u_preint.x) * u_preint.y, l * u_preint.z);
    x = clamp(x, vec3(0.0), vec3(u_preint_size - 1)); // held end values; longer than any cell: the last
    ivec3 i = min(ivec3(x), u_preint_size - 2);
    vec3 f = x - vec3(i);
    vec4 c00 = mix(texelFetch(u_preintegration, i, 0), texelFetch(u_preintegration, i + ivec3(1, 0, 0), 0), f.x);
    vec4 c10 = mix(texelFetch(u_preintegration, i + ivec3(0, 1, 0), 0), texelFetch(u_preintegration, i + ivec3(1, 1, 0), 0), f.x);
    vec4 c01 = mix(texelFetch(u_preintegration, i + ivec3(0, 0, 1), 0), texelFetch(u_preintegration, i + ivec3(1, 0, 1), 0), f.x);
    vec4 c11 = mix(texelFetch(u_preintegration, i + ivec3(0, 1, 1), 0), texelFetch(u_preintegration, i + ivec3(1, 1, 1), 0), f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

// Barycentric coordinates of q (on the triangle's plane) with respect to triangle (a, b, c).
vec3 barycentric(vec3 a, vec3 b, vec3 c, vec3 q) {
    vec3 e0 = b - a, e1 = c - a, e2 = q - a;
    float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(e2, e0), d21 = dot(e2, e1);
    float den = d00 * d11 - d01 * d01;
    if (!(den > 0.0)) return vec3(1.0, 0.0, 0.0);
    float wb = (d11 * d20 - d01 * d21) / den, wc = (d00 * d21 - d01 * d20) / den;
    return vec3(1.0 - wb - wc, wb, wc);
}

void main() {
    Ray ray = pixel_ray(v_position);
    float t_exit = dot(v_position - ray.origin, ray.dir);
    float s_exit = v_scalar;

    // Entry: for a convex cell, the last front-facing plane the ray crosses (Cyrus–Beck: one
    // dot product per triangle). The two triangles of a planar quad tie; a curved cell can make
    // the last plane one whose triangle the ray misses. So the winner's hit point must lie in
    // its triangle; if it does not, all candidates are searched by containment (a triangle that
    // contains its hit point beats one that does not, then the larger parameter wins).
    const float kInside = -1e-4; // barycentric slack for hits on shared edges
    int n = item_triangle_count(v_item);
    float t_front = -3.4e38;
    int front = -1;
    for (int k = 0; k < n; ++k) {
        vec4 plane = item_triangle(v_item, k).plane;
        float denom = dot(plane.xyz, ray.dir);
        if (denom >= -1e-6) continue; // back-facing for this ray, or grazing: cannot bound it
        float tt = (plane.w - dot(plane.xyz, ray.origin)) / denom;
        if (tt > t_front) t_front = tt, front = k;
    }
    float s_front = s_exit;
    if (front >= 0) {
        ItemTriangle tri = item_triangle(v_item, front);
        vec3 bary = barycentric(points[tri.v.x].xyz, points[tri.v.y].xyz, points[tri.v.z].xyz,
                                ray.origin + ray.dir * t_front);
        uvec3 best = tri.v;
        if (min(bary.x, min(bary.y, bary.z)) < kInside) {
            bool front_inside = false;
            t_front = -3.4e38;
            for (int k = 0; k < n; ++k) {
                ItemTriangle c = item_triangle(v_item, k);
                float denom = dot(c.plane.xyz, ray.dir);
                if (denom >= -1e-6) continue;
                float tt = (c.plane.w - dot(c.plane.xyz, ray.origin)) / denom;
                vec3 b = barycentric(points[c.v.x].xyz, points[c.v.y].xyz, points[c.v.z].xyz, ray.origin + ray.dir * tt);
                bool inside = min(b.x, min(b.y, b.z)) >= kInside;
                if ((inside && !front_inside) || (inside == front_inside && tt > t_front)) {
                    t_front = tt, front_inside = inside, bary = b, best = c.v;
                }
            }
        }
        t_front = min(t_front, t_exit);
        bary = max(bary, vec3(0.0)); // the entry can stray outside by rounding
        bary /= max(bary.x + bary.y + bary.z, 1e-20);
        s_front = dot(bary, vec3(points[best.x].w, points[best.y].w, points[best.z].w));
    } else {
        t_front = t_exit; // degenerate cell: no entry plane, no thickness
    }

    // Near plane: the segment starts there if the entry lies in front of it.
    float t_near = near_plane_t(ray);
    float t_in = t_front, s_in = s_front;
    if (t_near > t_front) {
        float span = t_exit - t_front;
        float f = span > 0.0 ? clamp((t_near - t_front) / span, 0.0, 1.0) : 1.0;
        s_in = mix(s_front, s_exit, f);
        t_in = min(t_near, t_exit);
    }
    // Scene depth: the segment ends at the opaque surface.
    float t_scene = scene_ray_t(ray, scene_view_depth(gl_FragCoord.xy));
    if (t_scene < t_exit) {
        float span = t_exit - t_in;
        float f = span > 0.0 ? clamp((t_scene - t_in) / span, 0.0, 1.0) : 0.0;
        s_exit = mix(s_in, s_exit, f);
        t_exit = max(t_scene, t_in);
    }
    o_color = preintegrated(s_in, s_exit, max(t_exit - t_in, 0.0));
}
