#version 450 core
// Flat colour of a glyph quad or of the panel behind the text (blended with its alpha).

layout(location = 0) in vec4 v_color;
layout(location = 0) out vec4 o_color;

void main() { o_color = v_color; }
