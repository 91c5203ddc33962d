#version 450 core
// The samples' own opaque geometry (samples/common/sample_gl.cpp): boxes in world space.
#include "sample_interface.glsl"

layout(location = 0) in vec3 a_position; // unit cube corner, [-0.5, 0.5]^3
layout(location = 1) in vec3 a_normal;
layout(location = UNIFORM_PROPS_CLIP_FROM_LOCAL) uniform mat4 u_clip_from_local;
layout(location = UNIFORM_PROPS_WORLD_NORMAL) uniform mat3 u_world_normal;

layout(location = 0) out vec3 v_normal;

void main() {
    gl_Position = u_clip_from_local * vec4(a_position, 1.0);
    v_normal = u_world_normal * a_normal;
}
