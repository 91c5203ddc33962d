#version 450 core
// Lambert shading of a box under one directional light, plus ambient.
#include "sample_interface.glsl"

layout(location = 0) in vec3 v_normal;
layout(location = UNIFORM_PROPS_COLOR) uniform vec3 u_color;
layout(location = UNIFORM_PROPS_LIGHT) uniform vec3 u_light; // unit, towards the light
layout(location = UNIFORM_PROPS_AMBIENT) uniform float u_ambient;
layout(location = 0) out vec4 o_color;

void main() {
    float lambert = max(dot(normalize(v_normal), u_light), 0.0);
    o_color = vec4(u_color * (u_ambient + (1.0 - u_ambient) * lambert), 1.0);
}
