#version 450 core
// Turns a path's accumulation target into premultiplied RGBA, drawn over the host's
// framebuffer with blend ONE, ONE_MINUS_SRC_ALPHA (shaders/fullscreen.vert).
//   default        emission / MIP light: (rgb, 0) — added to what lies behind
//   RESOLVE_FOG    rgb = E = ∫c·σ, a = τ = ∫σ: out = (E·(1 − e^−τ)/τ, 1 − e^−τ), i.e.
//                  bg·e^−τ + c·(1 − e^−τ) for a medium of one colour c = E/τ (exact), the
//                  optical-depth-weighted mean colour otherwise.
#include "projector_interface.glsl"

layout(binding = UNIT_ACCUMULATION) uniform sampler2D u_accumulation;
layout(location = UNIFORM_RESOLVE_ORIGIN) uniform ivec2 u_origin; // viewport origin in the host framebuffer

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    vec4 acc = texelFetch(u_accumulation, ivec2(gl_FragCoord.xy) - u_origin, 0);
#ifdef RESOLVE_FOG
    float tau = max(acc.a, 0.0);
    // g = (1 − e^−τ)/τ without cancellation for small τ; opacity = τ·g.
    float g = tau < 1e-3 ? 1.0 - tau * (0.5 - tau / 6.0) : (1.0 - exp(-tau)) / tau;
    float opacity = tau * g;
    o_color = vec4(acc.rgb * g, opacity);
#else
    // Emitted light has no upper bound: a sum past a float's range saturates at its largest
    // value, as the scan-line renderer's does, rather than reaching the host as Inf.
    o_color = vec4(min(acc.rgb, vec3(3.40282347e38)), 0.0);
#endif
}
