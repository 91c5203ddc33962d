#version 450 core
// Based on: Roettger & Ertl 2003, §3 (emission model, no sort), made exact per fragment.
// Drawn on the BACK faces of every cell (front faces culled), additive blending into a float
// target, one draw per mesh. Each fragment is where its ray leaves the cell; the ray is
// intersected with the cell's front-facing planes for the entry (the largest entry parameter),
// clamped to the near plane — so the near-plane cap comes for free. The scalar at the entry
// is interpolated barycentrically on the entry triangle (face-linear, as the scan-line
// reference does) and is linear along the ray; the segment's emission is integrated exactly
// through the cumulative table (segment_integral in project.glsl). With a scene depth the
// segment ends at the scene's surface (its exit scalar interpolated to the cut).
// Output: rgb = emission ∫c·σ, a = optical depth ∫σ (used by the fog resolve; ignored otherwise).
#include "project.glsl"

layout(location = 0) in vec3 v_position;
layout(location = 1) in float v_scalar;
layout(location = 2) flat in uint v_cell;
layout(location = 6) flat in vec2 v_scalar_bounds;

layout(location = 0) out vec4 o_color;

// Barycentric coordinates of q (on the triangle's plane) with respect to triangle t.
vec3 entry_barycentric(uint t, vec3 q) {
    uvec4 v = triangles[t].v;
    vec3 a = points[v.x].xyz, b = points[v.y].xyz, c = points[v.z].xyz;
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
    float s_exit = clamp(v_scalar, v_scalar_bounds.x, v_scalar_bounds.y); // see project.vert

    // Entry: for a convex cell, the last front-facing plane the ray crosses. Ties (the two
    // triangles of a planar quad) and slightly non-convex cells (curvilinear grids, whose quads
    // are not planar) are settled by containment: a candidate whose triangle contains its hit
    // point beats one that does not; then the larger parameter wins. Each triangle carries its
    // own linear scalar, so the triangle actually crossed matters.
    // Fast path: when the latest crossing lies inside its own triangle it wins that rule
    // outright, so the containment of the others is only looked at when it does not.
    const float kInside = -1e-4; // barycentric slack for hits on shared edges
    uint first = cell_first_triangle[v_cell], last = cell_first_triangle[v_cell + 1u];
    float t_front = -3.4e38;
    uint front = 0xFFFFFFFFu;
    for (uint t = first; t < last; ++t) {
        vec4 plane = triangles[t].plane;
        float denom = dot(plane.xyz, ray.dir);
        if (denom >= -1e-6) continue; // back-facing for this ray, or grazing: cannot bound it
        float tt = (plane.w - dot(plane.xyz, ray.origin)) / denom;
        if (tt > t_front) {
            t_front = tt;
            front = t;
        }
    }
    vec3 best_bary = vec3(1.0, 0.0, 0.0);
    if (front != 0xFFFFFFFFu) {
        best_bary = entry_barycentric(front, ray.origin + ray.dir * t_front);
        if (min(best_bary.x, min(best_bary.y, best_bary.z)) < kInside) {
            bool front_inside = false;
            t_front = -3.4e38;
            for (uint t = first; t < last; ++t) {
                vec4 plane = triangles[t].plane;
                float denom = dot(plane.xyz, ray.dir);
                if (denom >= -1e-6) continue;
                float tt = (plane.w - dot(plane.xyz, ray.origin)) / denom;
                vec3 bary = entry_barycentric(t, ray.origin + ray.dir * tt);
                bool inside = min(bary.x, min(bary.y, bary.z)) >= kInside;
                if ((inside && !front_inside) || (inside == front_inside && tt > t_front)) {
                    t_front = tt;
                    front_inside = inside;
                    best_bary = bary;
                    front = t;
                }
            }
        }
    }
    float s_front = s_exit;
    if (front != 0xFFFFFFFFu) {
        t_front = min(t_front, t_exit);
        uvec4 v = triangles[front].v;
        // Clamped to the triangle: the entry can stray outside it by rounding.
        vec3 bary = max(best_bary, vec3(0.0));
        bary /= max(bary.x + bary.y + bary.z, 1e-20);
        s_front = dot(bary, vec3(points[v.x].w, points[v.y].w, points[v.z].w));
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
    // Scene depth: the segment ends at the opaque surface (fog stops at the ground).
    float t_scene = scene_ray_t(ray, scene_view_depth(gl_FragCoord.xy));
    if (t_scene < t_exit) {
        float span = t_exit - t_in;
        float f = span > 0.0 ? clamp((t_scene - t_in) / span, 0.0, 1.0) : 0.0;
        s_exit = mix(s_in, s_exit, f);
        t_exit = max(t_scene, t_in);
    }
    float l = max(t_exit - t_in, 0.0);
    o_color = segment_integral(s_in, s_exit, l);
}
