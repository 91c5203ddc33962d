#version 450 core
// Absorption paths: the accumulation target already holds premultiplied colour and alpha
// ("over" of every cell, back to front); drawn over the host's framebuffer with blend
// ONE, ONE_MINUS_SRC_ALPHA (shaders/fullscreen.vert), so the host's frame is the background.
#include "projector_interface.glsl"

layout(binding = UNIT_ACCUMULATION) uniform sampler2D u_accumulation;
layout(location = UNIFORM_RESOLVE_ORIGIN) uniform ivec2 u_origin; // viewport origin in the host framebuffer

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() { o_color = texelFetch(u_accumulation, ivec2(gl_FragCoord.xy) - u_origin, 0); }
