// The segment of a pixel's ray inside one convex cell, shared by the exact per-fragment paths
// (pcp_exact.frag, absorption_exact.frag). Needs project.glsl first. Drawn on a cell's BACK
// faces, a fragment is where its ray leaves the cell; the including shader says which
// triangles bound the cell by defining the two functions declared here.
//
// Entry: for a convex cell, the last front-facing plane the ray crosses (Cyrus–Beck: one dot
// product per triangle). The two triangles of a planar quad tie, and a curvilinear cell (quads
// not planar) can make the last plane one whose triangle the ray misses: so the winner's hit
// point must lie in its triangle, and only if it does not are all candidates searched by
// containment (a triangle that contains its hit point beats one that does not, then the
// larger parameter wins). The scalar at the entry is barycentric on the entry triangle (face-
// linear, as the scan-line reference does) and linear along the ray. The segment then starts
// at the near plane if the entry lies in front of it (caps for free) and ends at the scene's
// opaque surface (CellRenderOptions::scene_depth), the scalar interpolated to each cut.

struct CellTriangle {
    uvec3 v;    // point ids, counter-clockwise seen from outside
    vec4 plane; // outward unit normal, w = n·p; zero for a zero-area triangle
};
int cell_triangle_count();            // of the fragment's cell (defined by the including shader)
CellTriangle cell_triangle(int k);    // k in [0, cell_triangle_count())

// Barycentric coordinates of q (on the triangle's plane) with respect to triangle (a, b, c).
vec3 barycentric(vec3 a, vec3 b, vec3 c, vec3 q) {
    vec3 e0 = b - a, e1 = c - a, e2 = q - a;
    float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(e2, e0), d21 = dot(e2, e1);
    float den = d00 * d11 - d01 * d01;
    if (!(den > 0.0)) return vec3(1.0, 0.0, 0.0);
    float wb = (d11 * d20 - d01 * d21) / den, wc = (d00 * d21 - d01 * d20) / den;
    return vec3(1.0 - wb - wc, wb, wc);
}
vec3 triangle_barycentric(uvec3 v, vec3 q) { return barycentric(points[v.x].xyz, points[v.y].xyz, points[v.z].xyz, q); }

struct CellSegment {
    float s_in, s_out; // scalar where the segment starts and ends
    float length;      // along the ray, ≥ 0
    float t_in;        // ray parameter where it starts (t_in + length: where it ends)
};

// The segment of `ray` from its entry into the cell to (t_exit, s_exit), where it leaves.
CellSegment cell_segment(Ray ray, float t_exit, float s_exit) {
    const float kInside = -1e-4; // barycentric slack for hits on shared edges
    int n = cell_triangle_count();
    float t_front = -3.4e38;
    int front = -1;
    for (int k = 0; k < n; ++k) {
        vec4 plane = cell_triangle(k).plane;
        float denom = dot(plane.xyz, ray.dir);
        if (denom >= -1e-6) continue; // back-facing for this ray, or grazing: cannot bound it
        float tt = (plane.w - dot(plane.xyz, ray.origin)) / denom;
        if (tt > t_front) t_front = tt, front = k;
    }
    float s_front = s_exit;
    if (front >= 0) {
        uvec3 best = cell_triangle(front).v;
        vec3 bary = triangle_barycentric(best, ray.origin + ray.dir * t_front);
        if (min(bary.x, min(bary.y, bary.z)) < kInside) {
            bool front_inside = false;
            t_front = -3.4e38;
            for (int k = 0; k < n; ++k) {
                CellTriangle c = cell_triangle(k);
                float denom = dot(c.plane.xyz, ray.dir);
                if (denom >= -1e-6) continue;
                float tt = (c.plane.w - dot(c.plane.xyz, ray.origin)) / denom;
                vec3 b = triangle_barycentric(c.v, ray.origin + ray.dir * tt);
                bool inside = min(b.x, min(b.y, b.z)) >= kInside;
                if ((inside && !front_inside) || (inside == front_inside && tt > t_front)) {
                    t_front = tt, front_inside = inside, bary = b, best = c.v;
                }
            }
        }
        t_front = min(t_front, t_exit);
        bary = max(bary, vec3(0.0)); // the entry can stray outside its triangle by rounding
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
    CellSegment segment;
    segment.s_in = s_in;
    segment.s_out = s_exit;
    segment.length = max(t_exit - t_in, 0.0);
    segment.t_in = t_in;
    return segment;
}
