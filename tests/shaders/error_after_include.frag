#version 450 core
// The include is fine; the error is in this file after it, so #line must return to this
// file with the right number once the include ends.
#include "constants.glsl"

layout(location = 0) out vec4 o_color;

void main() {
    float v = scaled(2.0);
    o_color = vec4(v) * not_declared_either; // ERROR HERE
}
