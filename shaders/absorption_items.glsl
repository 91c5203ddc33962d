// The items of the exact Absorption path (shaders/absorption_exact.vert): a whole cell of the
// mesh, or a tetrahedron of a cell subdivided for this view. Needs project.glsl first.
const uint kWholeCell = 0xFFFFFFFFu;
// Faces of a tetrahedron wound outward, in VTK order (fx/src/cell_mesh.cpp, kTetraFaces);
// tetrahedra from fx::subdivide_cell keep their cell's positive orientation.
const ivec3 kTetraFaces[4] = ivec3[4](ivec3(0, 1, 3), ivec3(1, 2, 3), ivec3(2, 0, 3), ivec3(0, 2, 1));

int item_triangle_count(uvec4 item) {
    return item.y == kWholeCell ? int(cell_first_triangle[item.x + 1u] - cell_first_triangle[item.x]) : 4;
}

// Point ids of triangle k, counter-clockwise seen from outside (no plane: for the vertex stage).
uvec3 item_triangle_points(uvec4 item, int k) {
    if (item.y == kWholeCell) return triangles[cell_first_triangle[item.x] + uint(k)].v.xyz;
    ivec3 f = kTetraFaces[k];
    return uvec3(item[f.x], item[f.y], item[f.z]);
}

struct ItemTriangle {
    uvec3 v;    // point ids, counter-clockwise seen from outside
    vec4 plane; // outward unit normal, w = n·p; zero for a zero-area triangle
};
ItemTriangle item_triangle(uvec4 item, int k) {
    ItemTriangle t;
    if (item.y == kWholeCell) {
        Triangle tri = triangles[cell_first_triangle[item.x] + uint(k)];
        t.v = tri.v.xyz;
        t.plane = tri.plane;
    } else {
        ivec3 f = kTetraFaces[k];
        t.v = uvec3(item[f.x], item[f.y], item[f.z]);
        vec3 a = points[t.v.x].xyz, b = points[t.v.y].xyz, c = points[t.v.z].xyz;
        vec3 n = cross(b - a, c - a);
        float len = length(n);
        t.plane = len > 0.0 ? vec4(n / len, dot(n / len, (a + b + c) / 3.0)) : vec4(0.0);
    }
    return t;
}
