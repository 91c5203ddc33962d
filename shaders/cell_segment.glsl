// The segment of a pixel's ray inside one cell, shared by the exact per-fragment paths
// (pcp_exact.frag, absorption_exact.frag). Needs project.glsl first. Drawn on a cell's BACK
// faces, a fragment is where its pixel's ray (fragment_ray) leaves the cell.
//
// The cell's word comes from cells.vert (flat): where its triangles' data start and how many
// there are. No other varying is interpolated: the ray is the pixel's, and where the
// fragment's own back face lies along it comes from gl_FragCoord (its depth).
//
// A tetrahedron is convex with one plane per face: clipping the ray by its four planes
// (Cyrus–Beck: one dot product each) gives the entry, the last front-facing plane crossed, and
// the exit, the first back-facing one. So does every planar cell (the planar bit of its word:
// convex, its faces flat within kPlanarTolerance of its size, gl_interface.hpp), clipped by its
// faces' planes (F of them: 5 or 6, not 12 triangles), with the scalar at either end from the
// half of the quad crossed (one side of its diagonal plane or the other). Other cells need more
// care: a curvilinear cell's folded quads can make the winning plane one whose triangle the ray
// misses, and a cell that folds inwards can be left and re-entered by one ray (two back faces
// on one pixel, each of which must count its own part only). So there the exit is the
// back-facing crossing nearest the fragment's own depth, and the entry the last front-facing
// crossing before it (or, by rounding, just after it: then there is no segment); each must lie
// in its triangle (barycentric rows, UNIT_BARYCENTRICS: triangle k's row pair v_fold + k, only
// such cells have rows), else the other half of its quad is
// tried, else every triangle facing the ray that way (one containing its crossing beats one
// that does not). A batch of fragments (of one triangle, so of one cell) takes one road or the
// other, so a mesh pays the search only for its folded cells.
//
// The scalar at either end is face-linear on the triangle crossed (as the scan-line reference
// has it), from that triangle's scalar function g·q + s0 — for a tetrahedron the cell's own
// linear function: no barycentrics. Between entry and exit the scalar is linear along the ray.
// The segment then starts at the near plane if the entry lies in front of it (caps for free)
// and ends at the scene's opaque surface (CellRenderOptions::scene_depth), the scalar
// interpolated to each cut.

layout(location = 0) flat in uint v_word;
#if VERTICES_PER_CELL != 4
layout(location = 1) flat in uint v_fold; // the cell's first barycentric row pair (cells.vert)
#endif
layout(binding = UNIT_PLANES) uniform samplerBuffer u_planes;                     // outward unit normal, n·p
layout(binding = UNIT_SCALAR_FUNCTIONS) uniform samplerBuffer u_scalar_functions; // g, s0
layout(binding = UNIT_BARYCENTRICS) uniform samplerBuffer u_barycentrics;         // 2 rows per triangle

// Below this |n·d| a plane is parallel to the ray (unit vectors: a sine of 1e-6 rad).
const float kGrazing = 1e-6;
// Barycentric slack for crossings on shared edges.
const float kInside = -1e-4;

struct CellSegment {
    float s_in, s_out; // scalar where the segment starts and ends
    float length;      // along the ray, ≥ 0
    float t_in;        // ray parameter where it starts (t_in + length: where it ends)
};

// Whether q lies in the triangle of row pair `rows`.
bool contains(int rows, vec3 q) {
    vec4 r1 = texelFetch(u_barycentrics, 2 * rows), r2 = texelFetch(u_barycentrics, 2 * rows + 1);
    float b1 = dot(r1.xyz, q) + r1.w, b2 = dot(r2.xyz, q) + r2.w;
    return min(1.0 - b1 - b2, min(b1, b2)) >= kInside;
}

// Parameter where `ray` crosses the plane of `triangle`, if it faces the ray the `side` way
// (−1 front, +1 back); false if not (or grazing).
bool crossing(int triangle, float side, Ray ray, out float t) {
    vec4 plane = texelFetch(u_planes, triangle);
    float den = dot(plane.xyz, ray.dir);
    t = (plane.w - dot(plane.xyz, ray.origin)) / den;
    return den * side > kGrazing;
}

// Makes (k, t), the winner by planes alone, a crossing that lies in its triangle, among the
// cell's triangles facing the ray the `side` way: an entry (side −1) the last one before `limit`
// (the exit), an exit (side +1) the one nearest `limit` (the fragment's own depth). False if
// none does (the ray misses the cell). The cell's triangle k has plane first + k, row pair
// fold + k.
bool resolve_crossing(int first, int fold, int triangles, float side, Ray ray, float limit, inout int k, inout float t) {
    if (contains(fold + k, ray.origin + ray.dir * t)) return true;
    float t_other;
    if (quad_half(triangles, k) && crossing(first + (k ^ 1), side, ray, t_other) &&
        contains(fold + (k ^ 1), ray.origin + ray.dir * t_other)) {
        k ^= 1, t = t_other;
        return true;
    }
    bool best_inside = false;
    float best_t = t;
    for (int j = 0; j < triangles; ++j) {
        float tj;
        if (!crossing(first + j, side, ray, tj) || (side < 0.0 && tj > limit)) continue;
        bool inside = contains(fold + j, ray.origin + ray.dir * tj);
        bool better = side < 0.0 ? tj > best_t : abs(tj - limit) < abs(best_t - limit);
        if ((inside && !best_inside) || (inside == best_inside && better)) best_inside = inside, best_t = tj, k = j;
    }
    t = best_t;
    return best_inside;
}

float face_scalar(int triangle, Ray ray, float t) {
    vec4 f = texelFetch(u_scalar_functions, triangle);
    return dot(f.xyz, ray.origin + ray.dir * t) + f.w;
}

// Where this fragment lies along its pixel's ray: 1/w of a perspective projection, linear in
// window depth for an orthographic one (whose rays start on the eye plane).
float fragment_t(Ray ray) {
    if (u_orthographic != 0) return orthographic_view_depth(gl_FragCoord.z);
    return (1.0 / gl_FragCoord.w) / max(dot(ray.dir, u_forward), 1e-6);
}

// The segment of this fragment's pixel ray in its cell, from the entry and exit parameters
// t_front < t_back and the scalar there: cut to the near plane and to the scene's surface.
CellSegment clipped_segment(Ray ray, float t_front, float t_back, float s_front, float s_back) {
    float t_in = max(t_front, near_plane_t(ray));
    float t_out = min(t_back, scene_ray_t(ray, scene_view_depth(gl_FragCoord.xy)));
    float span = t_back - t_front;
    CellSegment segment;
    segment.length = max(t_out - t_in, 0.0);
    segment.s_in = mix(s_front, s_back, span > 0.0 ? clamp((t_in - t_front) / span, 0.0, 1.0) : 0.0);
    segment.s_out = mix(s_front, s_back, span > 0.0 ? clamp((t_out - t_front) / span, 0.0, 1.0) : 1.0);
    segment.t_in = t_in;
    return segment;
}

#if VERTICES_PER_CELL == 4
// Every cell a tetrahedron: Cyrus–Beck through its four planes, the scalar its linear function
// along the ray (s = g·(o + t·d) + s0). No branch: Mesa's llvmpipe runs both sides of every
// branch some fragment of a batch takes.
CellSegment cell_segment(Ray ray) {
    int first = int(v_word >> uint(WORD_FIRST_SHIFT));
    float t_front = -3.4e38, t_back = 3.4e38;
    for (int k = 0; k < 4; ++k) {
        vec4 plane = texelFetch(u_planes, first + k);
        float den = dot(plane.xyz, ray.dir);
        float t = (plane.w - dot(plane.xyz, ray.origin)) / den;
        t_front = den < -kGrazing ? max(t_front, t) : t_front;
        t_back = den > kGrazing ? min(t_back, t) : t_back;
    }
    vec4 f = texelFetch(u_scalar_functions, first);
    float s_origin = dot(f.xyz, ray.origin) + f.w, s_step = dot(f.xyz, ray.dir);
    float t_in = max(t_front, near_plane_t(ray));
    float t_out = min(t_back, scene_ray_t(ray, scene_view_depth(gl_FragCoord.xy)));
    CellSegment segment;
    segment.length = t_back > t_front ? max(t_out - t_in, 0.0) : 0.0; // empty: degenerate, or missed by rounding
    segment.s_in = s_origin + s_step * t_in;
    segment.s_out = s_origin + s_step * max(t_out, t_in);
    segment.t_in = t_in;
    return segment;
}
#else
// The scalar where the ray crosses face f of a planar cell at t: from the function of the
// face's first half (slot f) or, for a quad crossed on the other side of its diagonal, of its
// second half (slot F + its index among the quads, where its diagonal plane is too).
float planar_face_scalar(int first, int faces, int face0, int f, Ray ray, float t) {
    vec3 q = ray.origin + ray.dir * t;
    int quad = kFaceQuad[face0 + f];
    int second = first + faces + max(quad, 0);
    vec4 diagonal = texelFetch(u_planes, second);
    int slot = quad >= 0 && dot(diagonal.xyz, q) < diagonal.w ? second : first + f;
    vec4 g = texelFetch(u_scalar_functions, slot);
    return dot(g.xyz, q) + g.w;
}

// A planar cell: Cyrus–Beck through its faces' planes, as a tetrahedron's.
CellSegment planar_cell_segment(Ray ray, int first, int triangles) {
    int type = cell_type_of_triangles(triangles), faces = kCellFaceCount[type], face0 = kCellFaceFirst[type];
    float t_front = -3.4e38, t_back = 3.4e38;
    int front = -1, back = -1;
    for (int f = 0; f < faces; ++f) {
        vec4 plane = texelFetch(u_planes, first + f);
        float den = dot(plane.xyz, ray.dir);
        float t = (plane.w - dot(plane.xyz, ray.origin)) / den;
        bool enters = den < -kGrazing && t > t_front, leaves = den > kGrazing && t < t_back;
        t_front = enters ? t : t_front, front = enters ? f : front;
        t_back = leaves ? t : t_back, back = leaves ? f : back;
    }
    if (front < 0 || back < 0 || !(t_back > t_front)) { // degenerate, or missed by rounding
        CellSegment none;
        none.s_in = none.s_out = none.length = none.t_in = 0.0;
        return none;
    }
    return clipped_segment(ray, t_front, t_back, planar_face_scalar(first, faces, face0, front, ray, t_front),
                           planar_face_scalar(first, faces, face0, back, ray, t_back));
}

// A cell that is not planar: the search of the header comment.
CellSegment folded_cell_segment(Ray ray, int first, int triangles) {
    float t_front = -3.4e38, t_back = 3.4e38;
    int front = -1, back = -1;
    // The exit nearest the fragment, then the last entry before it (for a convex cell: the
    // first back-facing and the last front-facing plane crossed).
    float t_own = fragment_t(ray);
    float fronts[12]; // crossing of each front-facing plane, −3.4e38 for the others
    for (int k = 0; k < triangles; ++k) {
        vec4 plane = texelFetch(u_planes, first + k);
        float den = dot(plane.xyz, ray.dir);
        float t = (plane.w - dot(plane.xyz, ray.origin)) / den;
        fronts[k] = den < -kGrazing ? t : -3.4e38;
        if (den > kGrazing && abs(t - t_own) < abs(t_back - t_own)) t_back = t, back = k;
    }
    int fold = int(v_fold);
    if (back >= 0) resolve_crossing(first, fold, triangles, 1.0, ray, t_own, back, t_back);
    // The last entry before the exit (one beyond it by no more than rounding still counts: a
    // ray that grazes the cell's edge), and it must lie in its triangle: a ray that misses the
    // cell by rounding crosses planes before the exit too, outside their triangles.
    float limit = t_back + 1e-5 * abs(t_back);
    for (int k = 0; k < triangles; ++k)
        if (fronts[k] > t_front && fronts[k] <= limit) t_front = fronts[k], front = k;
    if (front >= 0 && !resolve_crossing(first, fold, triangles, -1.0, ray, limit, front, t_front)) front = -1;
    if (front < 0 || back < 0 || !(t_back > t_front)) { // degenerate, or missed by rounding
        CellSegment none;
        none.s_in = none.s_out = none.length = none.t_in = 0.0;
        return none;
    }
    return clipped_segment(ray, t_front, t_back, face_scalar(first + front, ray, t_front),
                           face_scalar(first + back, ray, t_back));
}

CellSegment cell_segment(Ray ray) {
    int first = int(v_word >> uint(WORD_FIRST_SHIFT)), triangles = int(v_word & ((1u << uint(WORD_COUNT_BITS)) - 1u)) + 1;
    if ((v_word & (1u << uint(WORD_PLANAR_BIT))) != 0u) return planar_cell_segment(ray, first, triangles);
    return folded_cell_segment(ray, first, triangles);
}
#endif
