#version 450 core
// The terrain surface (terrain/src/gl/surface_renderer.cpp): vertices pulled from a storage
// buffer by the element index (gl_VertexID under glDrawElements), positions relative to the
// field's centre.
layout(std430, binding = 0) readonly buffer VertexBuffer { vec4 vertices[]; };

layout(location = 0) uniform mat4 u_view_projection; // relative frame → clip space

layout(location = 0) out vec3 v_position; // relative frame

void main() {
    vec3 p = vertices[gl_VertexID].xyz;
    v_position = p;
    gl_Position = u_view_projection * vec4(p, 1.0);
}
