// The items of the exact Absorption path (shaders/absorption_exact.vert): a whole cell of the
// mesh, or a tetrahedron of a cell subdivided for this view. Needs project.glsl first.
// kWholeCell and kTetraFaces (the faces of a tetrahedron, outward, in VTK order: tetrahedra
// from fx::subdivide_cell keep their cell's positive orientation) come from the generated
// projector_interface.glsl.

int item_triangle_count(uvec4 item) {
    return item.y == kWholeCell ? int(cell_first_triangle[item.x + 1u] - cell_first_triangle[item.x]) : 4;
}

// Point ids of triangle k, counter-clockwise seen from outside.
uvec3 item_triangle_points(uvec4 item, int k) {
    if (item.y == kWholeCell) return triangles[cell_first_triangle[item.x] + uint(k)].v.xyz;
    ivec3 f = kTetraFaces[k];
    return uvec3(item[f.x], item[f.y], item[f.z]);
}
