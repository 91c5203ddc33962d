#version 450 core
// The control of ctest's uniform_locations_named: a uniform at a bare location, which the check
// must refuse. Never compiled.
layout(location = 3) uniform vec3 u_color;
layout(location = 0) out vec4 o_color;
void main() { o_color = vec4(u_color, 1.0); }
