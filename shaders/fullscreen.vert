#version 450 core
// One triangle that covers the viewport, from gl_VertexID alone (draw 3 vertices, no buffers):
// vertices (-1,-1), (3,-1), (-1,3) in clip space; v_uv is 0..1 across the viewport.

layout(location = 0) out vec2 v_uv;

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)); // (0,0) (2,0) (0,2)
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
