#version 450 core
// Based on: Roettger & Ertl 2003, §3 — the projector's per-cell tables, built on the GPU from the
// mesh's points and connectivity (fx/src/projector/gl_projector.hpp), so that a new or changed
// mesh is a copy of its points and cells. One invocation per cell:
//   tables    (every cell with UNIFORM_TABLE_ALL, else those whose connectivity or one of whose
//             points changed since the stamp UNIFORM_TABLE_BUILT) in the cell's triangle slots:
//             for a planar cell (gl_interface.hpp, kPlanarTolerance; meshes with cells other than
//             tetrahedra) its F faces' planes and then its Q quads' diagonal planes (the side of
//             a quad's first half), the scalar function of each face's first half and then of
//             each quad's second half — F + Q is its triangle count; for any other cell, per face
//             triangle — quads cut by their smallest-vertex diagonal, as everywhere — its outward
//             unit plane, its scalar function and, for cells other than tetrahedra of a mesh that
//             has them, its barycentric rows; its word with the planar bit. The same formulas as
//             the CPU's (gl_projector.cpp, build_projector_tables), in double on the same float
//             positions, rounded to float;
//   rows      (meshes with cells other than tetrahedra) a cell that is not planar has its two
//             barycentric rows per triangle from row pair fold_bases[c]: by UNIFORM_TABLE_LAYOUT,
//             TABLE_LAYOUT_FULL: every cell's at its own slots (fold base = its first triangle,
//             written here; a planar cell's zero), the bits decided here (a renderer that takes
//             in-place updates); the compact layouts, where only cells that are not planar have
//             rows, packed in the order of the cells: TABLE_LAYOUT_DECIDE: the bits decided, no
//             rows (the CPU reads the bits back and lays the rows out), then
//             TABLE_LAYOUT_ROWS_ONLY: the rows alone at the CPU's fold bases, the bits kept;
//             TABLE_LAYOUT_KEPT: everything with the bits and fold bases kept (new scalars);
//   elements  (UNIFORM_TABLE_ELEMENTS, or a cell whose tables were rebuilt) the cell's triangles
//             as vertex ids cell·VERTICES_PER_CELL + k; with UNIFORM_TABLE_CULL a cell whose box
//             lies wholly outside one of the view's side or near planes gets three copies of its
//             first vertex instead (nothing is rasterised; the far plane cuts nothing).
#include "projector_interface.glsl"

layout(local_size_x = 64) in;

layout(binding = UNIT_POINTS) uniform samplerBuffer u_points;
layout(binding = UNIT_CONNECTIVITY) uniform usamplerBuffer u_connectivity;
layout(binding = UNIT_CELL_OFFSETS) uniform usamplerBuffer u_cell_offsets;

layout(std430, binding = BINDING_PLANES_OUT) writeonly buffer Planes { vec4 planes[]; };
layout(std430, binding = BINDING_SCALAR_FUNCTIONS_OUT) writeonly buffer Functions { vec4 functions[]; };
layout(std430, binding = BINDING_BARYCENTRICS_OUT) writeonly buffer Barycentrics { vec4 barycentrics[]; };
layout(std430, binding = BINDING_ELEMENTS_OUT) writeonly buffer Elements { uint elements[]; };
layout(std430, binding = BINDING_POINT_STAMPS) readonly buffer PointStamps { uint point_stamps[]; };
layout(std430, binding = BINDING_CELL_STAMPS) readonly buffer CellStamps { uint cell_stamps[]; };
layout(std430, binding = BINDING_CELL_WORDS_OUT) buffer CellWords { uint cell_words[]; };
layout(std430, binding = BINDING_FOLD_BASES_OUT) buffer FoldBases { uint fold_bases[]; };

layout(location = UNIFORM_TABLE_CELLS) uniform uint u_cells;
layout(location = UNIFORM_TABLE_BUILT) uniform uint u_built;
layout(location = UNIFORM_TABLE_ALL) uniform int u_all;
layout(location = UNIFORM_TABLE_ELEMENTS) uniform int u_elements;
layout(location = UNIFORM_TABLE_CULL) uniform int u_cull;
layout(location = UNIFORM_TABLE_CULL_PLANES) uniform vec4 u_cull_planes[5];
layout(location = UNIFORM_TABLE_PLANAR_TOLERANCE) uniform double u_planar_tolerance; // kPlanarTolerance
layout(location = UNIFORM_TABLE_LAYOUT) uniform int u_layout;

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

// Row pair t (rows 2t, 2t + 1).
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

// A face's plane for the planar test and layout: unit normal along b−a × c−a (a triangle) or
// along the cross product of the diagonals (a quad), through the mean of its corners; zero
// for a face with no area.
dvec4 face_plane(dvec3 p[8], ivec4 face) {
    bool quad = face.w >= 0;
    dvec3 n = quad ? cross(p[face.z] - p[face.x], p[face.w] - p[face.y]) : cross(p[face.y] - p[face.x], p[face.z] - p[face.x]);
    dvec3 centre = quad ? 0.25lf * (p[face.x] + p[face.y] + p[face.z] + p[face.w]) : (p[face.x] + p[face.y] + p[face.z]) / 3.0lf;
    double len = length(n);
    double scale = max(length(p[face.z] - p[face.x]), length(p[quad ? face.w : face.z] - p[face.y]));
    if (!(len > 1e-12lf * scale * scale && len > 0.0lf)) return dvec4(0.0lf);
    dvec3 u = n / len;
    return dvec4(u, dot(u, centre));
}

// Whether the cell (its n points p, `type`) is planar (gl_interface.hpp: kPlanarTolerance).
bool planar_cell(dvec3 p[8], uint n, int type) {
    dvec3 lo = p[0], hi = p[0];
    for (uint k = 1u; k < n; ++k) lo = min(lo, p[k]), hi = max(hi, p[k]);
    double slack = u_planar_tolerance * length(hi - lo);
    bool planar = true;
    for (int f = 0; f < kCellFaceCount[type]; ++f) {
        ivec4 face = kCellFaces[kCellFaceFirst[type] + f];
        dvec4 plane = face_plane(p, face);
        planar = planar && plane.xyz != dvec3(0.0lf);
        for (uint k = 0u; k < n; ++k) {
            double d = dot(plane.xyz, p[k]) - plane.w;
            bool on_face = int(k) == face.x || int(k) == face.y || int(k) == face.z || int(k) == face.w;
            planar = planar && (on_face ? abs(d) : d) <= slack;
        }
    }
    return planar && u_planar_tolerance >= 0.0lf; // a negative tolerance: nothing is planar
}

void write_elements(uint t, uvec3 e) {
    elements[3u * t] = e.x;
    elements[3u * t + 1u] = e.y;
    elements[3u * t + 2u] = e.z;
}

void main() {
    uint c = gl_GlobalInvocationID.x;
    if (c >= u_cells) return;
    uint offset = texelFetch(u_cell_offsets, int(c)).x;
    uint n = texelFetch(u_cell_offsets, int(c) + 1).x - offset;
    uint word = cell_words[c];
    uint first = word >> uint(WORD_FIRST_SHIFT);
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
    // Tetrahedra-only meshes keep the triangle layout (the same for a tetrahedron) and no bit.
    bool decide = u_layout == TABLE_LAYOUT_FULL || u_layout == TABLE_LAYOUT_DECIDE;
    bool full = u_layout == TABLE_LAYOUT_FULL, rows_only = u_layout == TABLE_LAYOUT_ROWS_ONLY;
    bool planar = V == 8u && changed && (decide ? planar_cell(p, n, type) : (word & (1u << uint(WORD_PLANAR_BIT))) != 0u);
    vec4 tet = type == 0 && changed && !rows_only ? tetrahedron_function(p, s) : vec4(0.0);
    if (V == 8u && changed && decide)
        cell_words[c] = planar ? word | (1u << uint(WORD_PLANAR_BIT)) : word & ~(1u << uint(WORD_PLANAR_BIT));
    if (V == 8u && changed && full) fold_bases[c] = first;
    // Where its row pairs go: triangle t's at fold + (t − first); none in TABLE_LAYOUT_DECIDE.
    bool rows = V == 8u && changed && u_layout != TABLE_LAYOUT_DECIDE;
    uint fold = full || !rows || planar ? first : fold_bases[c];
    if (rows_only && (planar || !changed)) return;

    uint t = first;
    int face0 = kCellFaceFirst[type], faces = kCellFaceCount[type];
    for (int f = 0; f < faces; ++f) {
        ivec4 face = kCellFaces[face0 + f];
        int halves = face.w < 0 ? 1 : 2;
        int k0 = 0; // a quad's fan starts at its smallest vertex: its diagonal is the only one through it
        if (halves == 2)
            for (int i = 1; i < 4; ++i)
                if (ids[face[i]] < ids[face[k0]]) k0 = i;
        if (planar && !rows_only) {
            // Face f's plane and first half's function in slot f, a quad's diagonal plane and
            // second half's function in slot F + (its index among the quads).
            uint slot = first + uint(f), second = first + uint(faces + kFaceQuad[face0 + f]);
            dvec4 plane = face_plane(p, face);
            planes[slot] = vec4(plane);
            if (halves == 2) {
                dvec3 a = p[face[k0]], b = p[face[(k0 + 1) % 4]], cc = p[face[(k0 + 2) % 4]], d = p[face[(k0 + 3) % 4]];
                // The diagonal plane, b's side positive, told by whichever of b and d lies farther
                // from it: a half with no area (an edge collapsed, as at a fog layer's rim) has
                // its corner on the diagonal, where the sign is rounding's.
                dvec3 m = cross(plane.xyz, cc - a);
                double side_b = dot(m, b - a), side_d = dot(m, d - a);
                m = (abs(side_b) >= abs(side_d) ? side_b < 0.0lf : side_d > 0.0lf) ? -m : m;
                double len = length(m);
                m = len > 0.0lf ? m / len : m;
                planes[second] = vec4(vec3(m), float(dot(m, a)));
                // A half with next to no area (below 1e-6 of the other's) takes the other's
                // function: its points lie on the diagonal, where the two agree.
                vec4 f1 = triangle_function(a, s[face[k0]], b, s[face[(k0 + 1) % 4]], cc, s[face[(k0 + 2) % 4]]);
                vec4 f2 = triangle_function(a, s[face[k0]], cc, s[face[(k0 + 2) % 4]], d, s[face[(k0 + 3) % 4]]);
                double area1 = length(cross(b - a, cc - a)), area2 = length(cross(cc - a, d - a));
                functions[slot] = area1 < 1e-6lf * area2 ? f2 : f1;
                functions[second] = area2 < 1e-6lf * area1 ? f1 : f2;
                if (full) barycentrics[2u * second] = barycentrics[2u * second + 1u] = vec4(0.0);
            } else {
                functions[slot] = type == 0 ? tet : triangle_function(p[face.x], s[face.x], p[face.y], s[face.y], p[face.z], s[face.z]);
            }
            if (full) barycentrics[2u * slot] = barycentrics[2u * slot + 1u] = vec4(0.0);
        }
        for (int h = 0; h < halves; ++h, ++t) {
            ivec3 tri = halves == 1 ? face.xyz : ivec3(face[k0], face[(k0 + 1 + h) % 4], face[(k0 + 2 + h) % 4]);
            if (changed && !planar) {
                dvec3 a = p[tri.x], b = p[tri.y], cc = p[tri.z];
                if (!rows_only) {
                    planes[t] = triangle_plane(a, b, cc);
                    functions[t] = type == 0 ? tet : triangle_function(a, s[tri.x], b, s[tri.y], cc, s[tri.z]);
                }
                if (rows) {
                    uint r = fold + (t - first);
                    if (type == 0) barycentrics[2u * r] = barycentrics[2u * r + 1u] = vec4(0.0);
                    else barycentric_rows(a, b, cc, r);
                }
            }
            if (!rows_only) write_elements(t, visible ? uvec3(c * V) + uvec3(tri) : uvec3(c * V));
        }
    }
}
