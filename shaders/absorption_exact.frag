#version 450 core
// Based on: Max, Williams & Silva 2000, §II (the volume density model, composited back to
// front with "over") made exact per fragment. Drawn on the BACK faces of every cell (front
// faces culled), cells in visibility order (the frame's triangle list and words: absorption
// pass), so each pixel a cell covers gets one fragment, in order.
// The segment inside the cell comes from cell_segment.glsl (exact entry through the cell's
// planes, clamped to the near plane — so a camera inside the mesh composites only what lies
// ahead — and to the scene's surface where one is given); colour and opacity come from the
// pre-integration table over (s_front, s_back, length) built by fx::build_preintegration_table
// from the exact integrals, as M and mean extinction σ̄ (fx::PreintegrationTable) interpolated
// trilinearly here in full float: τ = σ̄·l is then exact along l, alpha = 1 − e^−τ, colour =
// M·alpha/σ̄ (a short segment through dense matter stays opaque). Output premultiplied,
// into a float target with glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA).
#include "project.glsl"
#include "cell_segment.glsl"

// Entry (il·n_s + ib)·n_s + if: s_front = if, s_back = ib (n_s samples of [s_lo, s_hi]), length
// = il (n_l samples of [0, max]); a buffer texture, so that each of the eight texels of the
// trilinear interpolation costs one add.
layout(binding = UNIT_PREINTEGRATION) uniform samplerBuffer u_preintegration;
layout(location = UNIFORM_PREINTEGRATION) uniform vec3 u_preint;        // s_lo, samples per unit s, samples per unit length
layout(location = UNIFORM_PREINTEGRATION_SIZE) uniform ivec3 u_preint_size; // n_s, n_s, n_l

layout(location = 0) out vec4 o_color;

vec4 preintegrated(float s_front, float s_back, float l) {
    vec3 x = vec3((s_front - u_preint.x) * u_preint.y, (s_back - u_preint.x) * u_preint.y, l * u_preint.z);
    x = clamp(x, vec3(0.0), vec3(u_preint_size - 1)); // held end values; longer than any cell: the last
    ivec3 i = min(ivec3(x), u_preint_size - 2);
    vec3 f = x - vec3(i);
    int n = u_preint_size.x, nn = n * u_preint_size.y;
    int b = (i.z * u_preint_size.y + i.y) * n + i.x;
    vec4 c00 = mix(texelFetch(u_preintegration, b), texelFetch(u_preintegration, b + 1), f.x);
    vec4 c10 = mix(texelFetch(u_preintegration, b + n), texelFetch(u_preintegration, b + n + 1), f.x);
    vec4 c01 = mix(texelFetch(u_preintegration, b + nn), texelFetch(u_preintegration, b + nn + 1), f.x);
    vec4 c11 = mix(texelFetch(u_preintegration, b + nn + n), texelFetch(u_preintegration, b + nn + n + 1), f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

void main() {
    CellSegment segment = cell_segment(fragment_ray(gl_FragCoord.xy));
    vec4 entry = preintegrated(segment.s_in, segment.s_out, segment.length); // M, σ̄
    float tau = entry.a * segment.length;
    // alpha/σ̄ = (1 − e^−τ)/σ̄: l·(1 − τ/2 + τ²/6) for small τ (no cancellation, and σ̄ may be 0
    // there); e^−τ underflows to 0 for huge τ, leaving 1/σ̄.
    float alpha_per_sigma = tau < 1e-3 ? segment.length * (1.0 - tau * (0.5 - tau / 6.0)) : (1.0 - exp(-tau)) / entry.a;
    o_color = vec4(entry.rgb * alpha_per_sigma, entry.a * alpha_per_sigma);
}
