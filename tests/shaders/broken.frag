#version 450 core
// A fragment shader that fails to compile only when the prelude defines BREAK_IT, so the test
// also proves the caller's #define prelude arrives and does not shift line numbers.

layout(location = 0) out vec4 o_color;

void main() {
    o_color = vec4(1.0);
#ifdef BREAK_IT
    o_color = undeclared_on_purpose; // ERROR HERE
#endif
}
