// Single scattering of the one medium's lights (fx/medium.hpp), shared by the exact
// compositor's resolve (medium_resolve.frag) and the froxel grid's lighting
// (froxel_integrate.comp) and emission pass (froxel_emission.frag): the Henyey–Greenstein
// phase and the point lights (a fire's glow). The includer defines
//     float scatter_sigma(float t);
// the extinction along the ray of the medium that scatters (point_light_scatter weighs by it).
// Uniform locations and sizes from the interface table (fx/src/projector/gl_interface.hpp).
#include "projector_interface.glsl"
const int kMaxPointLights = MEDIUM_POINT_LIGHTS;
layout(location = UNIFORM_POINT_COUNT) uniform int u_point_count;
layout(location = UNIFORM_POINT_POSITION) uniform vec4 u_point_position[kMaxPointLights]; // eye-relative, core radius r0
layout(location = UNIFORM_POINT_COLOR) uniform vec4 u_point_color[kMaxPointLights];       // rgb, radius R
layout(location = UNIFORM_POINT_G) uniform float u_point_g[kMaxPointLights];

// Henyey–Greenstein relative to isotropic scattering (fx::relative_phase): 4π·p.
float relative_phase(float g, float mu) {
    float d = max(1.0 + g * g - 2.0 * g * mu, 1e-6);
    return (1.0 - g * g) / (d * sqrt(d));
}

float scatter_sigma(float t);

// Light scattered towards the eye over [a, b] of the ray origin + dir·t (eye-relative frame, dir
// unit) by point light l: ∫ σ(t) · r0²/(r0² + r²)(1 − r²/R²)² · 4π·p(μ) dt, σ = scatter_sigma.
// With u = t − t_c (t_c nearest the light, h its distance) substituted by u = √q·tan φ,
// q = r0² + h², the falloff's inverse-square part becomes constant in φ and what is left is
// smooth, except that the phase turns from forward to backward over |u| ≲ h: 4-point
// Gauss–Legendre in φ on |u| < 3h and beyond, on each side of t_c; each node dimmed by the
// span's optical depth `tau` from a to it (spread evenly).
const float kGaussX[4] = float[4](-0.861136312, -0.339981044, 0.339981044, 0.861136312);
const float kGaussW[4] = float[4](0.347854845, 0.652145155, 0.652145155, 0.347854845);
float point_light_scatter(int l, vec3 origin, vec3 dir, float a, float b, float tau) {
    vec3 c = u_point_position[l].xyz;
    float r0 = u_point_position[l].w, R = u_point_color[l].w;
    float tc = dot(c - origin, dir);
    vec3 closest = origin + dir * tc - c;
    float h2 = dot(closest, closest);
    if (h2 >= R * R) return 0.0;
    float w2 = R * R - h2, w = sqrt(w2);
    float u0 = max(a, tc - w) - tc, u1 = min(b, tc + w) - tc;
    if (!(u1 > u0)) return 0.0;
    float q = r0 * r0 + h2, sq = sqrt(q), turn = 3.0 * sqrt(h2);
    float g = u_point_g[l];
    // The pieces' ends in u: [u0, −turn, 0, turn, u1], each clamped to [u0, u1].
    float ends[5] = float[5](u0, clamp(-turn, u0, u1), clamp(0.0, u0, u1), clamp(turn, u0, u1), u1);
    float sum = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (!(ends[k + 1] > ends[k])) continue;
        float p0 = atan(ends[k] / sq), p1 = atan(ends[k + 1] / sq);
        for (int j = 0; j < 4; ++j) {
            float u = sq * tan(mix(p0, p1, 0.5 + 0.5 * kGaussX[j]));
            float window = max(w2 - u * u, 0.0) / (R * R);
            float mu = -u / sqrt(h2 + u * u + 1e-30); // the light's direction · back to the eye
            float dim = exp(-tau * clamp((tc + u - a) / (b - a), 0.0, 1.0));
            // f·du/dφ = r0²/(q + u²)·window²·(q + u²)/√q
            sum += kGaussW[j] * 0.5 * (p1 - p0) * scatter_sigma(tc + u) * window * window * relative_phase(g, mu) * dim;
        }
    }
    return sum * r0 * r0 / sq;
}
