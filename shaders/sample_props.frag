#version 450 core
// Lambert shading of a box under one directional light, plus ambient.

layout(location = 0) in vec3 v_normal;
layout(location = 2) uniform vec3 u_color;
layout(location = 3) uniform vec3 u_light; // unit, towards the light
layout(location = 4) uniform float u_ambient;
layout(location = 0) out vec4 o_color;

void main() {
    float lambert = max(dot(normalize(v_normal), u_light), 0.0);
    o_color = vec4(u_color * (u_ambient + (1.0 - u_ambient) * lambert), 1.0);
}
