#version 450 core
// The error is inside an include, nested two deep: constants.glsl is included here and
// broken_include.glsl through nested_include.glsl.
#include "constants.glsl"
#include "nested_include.glsl"

layout(location = 0) out vec4 o_color;

void main() {
    o_color = vec4(broken_helper(scaled(1.0)));
}
