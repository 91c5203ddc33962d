#version 450 core
// Composites a premultiplied RGBA image (what the render paths accumulate) over what lies
// behind it:
//   default:                   out = c + (1 - a) * u_background, alpha 1 (opaque result);
//   COMPOSITE_OVER_FRAMEBUFFER: out = (c, a), to be drawn with blend ONE, ONE_MINUS_SRC_ALPHA
//                               so the framebuffer's own colour is the background.

layout(binding = 0) uniform sampler2D u_image; // premultiplied, linear
#ifndef COMPOSITE_OVER_FRAMEBUFFER
layout(location = UNIFORM_BACKGROUND) uniform vec3 u_background; // gl/composite_pass.cpp
#endif

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    vec4 c = texture(u_image, v_uv);
#ifdef COMPOSITE_OVER_FRAMEBUFFER
    o_color = c;
#else
    o_color = vec4(c.rgb + (1.0 - c.a) * u_background, 1.0);
#endif
}
