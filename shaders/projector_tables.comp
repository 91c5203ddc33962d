#version 450 core
// Based on: Roettger & Ertl 2003, §3 — the projector's per-cell tables, built on the GPU from the
// mesh's points and connectivity (fx/src/projector/gl_projector.hpp), so that a new or changed
// mesh is a copy of its points and cells. One invocation per cell:
//   tables    (every cell with UNIFORM_TABLE_ALL, else those whose connectivity or one of whose
//             points changed since the stamp UNIFORM_TABLE_BUILT) per face triangle — quads cut
//             by their smallest-vertex diagonal, as everywhere — its outward unit plane, its
//             scalar function and, for cells other than tetrahedra of a mesh that has them, its
//             barycentric rows: the same formulas as the CPU's (gl_projector.cpp), in double on
//             the same float positions, rounded to float;
//   elements  (UNIFORM_TABLE_ELEMENTS, or a cell whose tables were rebuilt) the cell's triangles
//             as vertex ids cell·VERTICES_PER_CELL + k; with UNIFORM_TABLE_CULL a cell whose box
//             lies wholly outside one of the view's side or near planes gets three copies of its
//             first vertex instead (nothing is rasterised; the far plane cuts nothing).
#include "projector_interface.glsl"

layout(local_size_x = 64) in;

layout(binding = UNIT_POINTS) uniform samplerBuffer u_points;
layout(binding = UNIT_CONNECTIVITY) uniform usamplerBuffer u_connectivity;
layout(binding = UNIT_CELL_OFFSETS) uniform usamplerBuffer u_cell_offsets;
layout(binding = UNIT_CELL_WORDS) uniform usamplerBuffer u_cell_words;

layout(std430, binding = BINDING_PLANES_OUT) writeonly buffer Planes { vec4 planes[]; };
layout(std430, binding = BINDING_SCALAR_FUNCTIONS_OUT) writeonly buffer Functions { vec4 functions[]; };
layout(std430, binding = BINDING_BARYCENTRICS_OUT) writeonly buffer Barycentrics { vec4 barycentrics[]; };
layout(std430, binding = BINDING_ELEMENTS_OUT) writeonly buffer Elements { uint elements[]; };
layout(std430, binding = BINDING_POINT_STAMPS) readonly buffer PointStamps { uint point_stamps[]; };
layout(std430, binding = BINDING_CELL_STAMPS) readonly buffer CellStamps { uint cell_stamps[]; };

layout(location = UNIFORM_TABLE_CELLS) uniform uint u_cells;
layout(location = UNIFORM_TABLE_BUILT) uniform uint u_built;
layout(location = UNIFORM_TABLE_ALL) uniform int u_all;
layout(location = UNIFORM_TABLE_ELEMENTS) uniform int u_elements;
layout(location = UNIFORM_TABLE_CULL) uniform int u_cull;
layout(location = UNIFORM_TABLE_CULL_PLANES) uniform vec4 u_cull_planes[5];

const uint V = uint(VERTICES_PER_CELL);

vec4 triangle_plane(dvec3 a, dvec3 b, dvec3 c) {
    dvec3 n = cross(b - a, c - a);
    double len = length(n);
    double scale = max(length(b - a), max(length(c - a), length(c - b)));
    if (!(len > 1e-12lf * scale * scale && len > 0.0lf)) return vec4(0.0);
    dvec3 u = n / len;
    return vec4(vec3(u), float(dot(u, (a + b + c) / 3.0lf)));
}

vec4 triangle_function(dvec3 a, double sa, dvec3 b, double sb, dvec3 c, double sc) {
    dvec3 e1 = b - a, e2 = c - a;
    double e11 = dot(e1, e1), e12 = dot(e1, e2), e22 = dot(e2, e2);
    double det = e11 * e22 - e12 * e12;
    if (!(det > 1e-24lf * e11 * e22)) return vec4(0.0, 0.0, 0.0, float((sa + sb + sc) / 3.0lf));
    double db = sb - sa, dc = sc - sa;
    dvec3 g = ((db * e22 - dc * e12) * e1 + (dc * e11 - db * e12) * e2) / det;
    return vec4(vec3(g), float(sa - dot(g, a)));
}

vec4 tetrahedron_function(dvec3 p[8], double s[8]) {
    dvec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
    double det = dot(e1, cross(e2, e3));
    double size = max(length(e1), max(length(e2), length(e3)));
    if (!(abs(det) > 1e-12lf * size * size * size))
        return vec4(0.0, 0.0, 0.0, float(0.25lf * (s[0] + s[1] + s[2] + s[3])));
    dvec3 g = ((s[1] - s[0]) * cross(e2, e3) + (s[2] - s[0]) * cross(e3, e1) + (s[3] - s[0]) * cross(e1, e2)) / det;
    return vec4(vec3(g), float(s[0] - dot(g, p[0])));
}

void barycentric_rows(dvec3 a, dvec3 b, dvec3 c, uint t) {
    dvec3 e1 = b - a, e2 = c - a;
    double e11 = dot(e1, e1), e12 = dot(e1, e2), e22 = dot(e2, e2);
    double det = e11 * e22 - e12 * e12;
    if (!(det > 1e-24lf * e11 * e22)) {
        barycentrics[2u * t] = barycentrics[2u * t + 1u] = vec4(0.0);
        return;
    }
    dvec3 r1 = (e22 * e1 - e12 * e2) / det, r2 = (e11 * e2 - e12 * e1) / det;
    barycentrics[2u * t] = vec4(vec3(r1), float(-dot(r1, a)));
    barycentrics[2u * t + 1u] = vec4(vec3(r2), float(-dot(r2, a)));
}

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= u_cells) return;
    uint offset = texelFetch(u_cell_offsets, int(c)).x;
    uint n = texelFetch(u_cell_offsets, int(c) + 1).x - offset;
    uint first = texelFetch(u_cell_words, int(c)).x >> uint(WORD_COUNT_BITS);
    int type = cell_type_of(n);

    uint ids[8];
    vec4 q[8];
    bool changed = u_all != 0 || cell_stamps[c] > u_built;
    for (uint k = 0u; k < n; ++k) {
        ids[k] = texelFetch(u_connectivity, int(offset + k)).x;
        q[k] = texelFetch(u_points, int(ids[k]));
        changed = changed || point_stamps[ids[k]] > u_built;
    }
    if (!changed && u_elements == 0) return;

    bool visible = true;
    if (u_cull != 0) {
        vec3 lo = q[0].xyz, hi = q[0].xyz;
        for (uint k = 1u; k < n; ++k) lo = min(lo, q[k].xyz), hi = max(hi, q[k].xyz);
        for (int p = 0; p < 5; ++p) {
            vec4 plane = u_cull_planes[p];
            vec3 far_corner = mix(lo, hi, greaterThanEqual(plane.xyz, vec3(0.0)));
            visible = visible && dot(plane.xyz, far_corner) + plane.w >= 0.0;
        }
    }

    dvec3 p[8];
    double s[8];
    for (uint k = 0u; k < n; ++k) p[k] = dvec3(q[k].xyz), s[k] = double(q[k].w);
    vec4 tet = type == 0 && changed ? tetrahedron_function(p, s) : vec4(0.0);

    uint t = first;
    int face0 = kCellFaceFirst[type];
    for (int f = 0; f < kCellFaceCount[type]; ++f) {
        ivec4 face = kCellFaces[face0 + f];
        int halves = face.w < 0 ? 1 : 2;
        int k0 = 0; // a quad's fan starts at its smallest vertex: its diagonal is the only one through it
        if (halves == 2)
            for (int i = 1; i < 4; ++i)
                if (ids[face[i]] < ids[face[k0]]) k0 = i;
        for (int h = 0; h < halves; ++h, ++t) {
            ivec3 tri = halves == 1 ? face.xyz : ivec3(face[k0], face[(k0 + 1 + h) % 4], face[(k0 + 2 + h) % 4]);
            if (changed) {
                dvec3 a = p[tri.x], b = p[tri.y], cc = p[tri.z];
                planes[t] = triangle_plane(a, b, cc);
                functions[t] = type == 0 ? tet : triangle_function(a, s[tri.x], b, s[tri.y], cc, s[tri.z]);
                if (V == 8u) {
                    if (type == 0) barycentrics[2u * t] = barycentrics[2u * t + 1u] = vec4(0.0);
                    else barycentric_rows(a, b, cc, t);
                }
            }
            uint base = c * V;
            uvec3 e = visible ? uvec3(base) + uvec3(tri) : uvec3(base);
            elements[3u * t] = e.x;
            elements[3u * t + 1u] = e.y;
            elements[3u * t + 2u] = e.z;
        }
    }
}
