#version 450 core
// Based on: Wronski 2014, "Volumetric fog" — the froxel medium's lighting and integration
// (fx/internal/medium/froxel_medium.hpp): one invocation per tile walks its column of froxels
// front to back. Each froxel is a span of the tile's centre ray (its slice's view depths) with
// the injected emission E, optical depth τ and scattering ∫ρσ of the volumes crossing it, taken
// as even over the span: the point lights scatter in it (medium_lights.glsl: Gauss–Legendre
// along the span, dimmed by the span's own depth), and it is composited front to back with
// fx/medium.hpp's span model, L += T·(E·(1 − e^(−τ))/τ + S), T ·= e^(−τ). Layer k of the
// integrated grid holds (L, τ in front of the slice's far end); the scattering grid the span's
// mean scattering coefficient (the emission pass lights beams with it).
layout(local_size_x = 8, local_size_y = 8) in;

#define FROXEL_INJECTION
#include "froxel_grid.glsl"
#include "medium_lights.glsl"

layout(binding = 0, rgba16f) uniform writeonly image3D u_integrated; // L rgb, τ
layout(binding = 1, r16f) uniform writeonly image3D u_scattering;   // ρσ per unit length

// The tile's centre ray in the eye-relative world frame: origin = o + x·o_x + y·o_y, direction =
// normalize(d + x·d_x + y·d_y) for ndc (x, y) (fx::MediumGridRays).
layout(location = UNIFORM_FROXEL_RAY_ORIGIN) uniform vec3 u_origin;
layout(location = UNIFORM_FROXEL_RAY_ORIGIN_X) uniform vec3 u_origin_x;
layout(location = UNIFORM_FROXEL_RAY_ORIGIN_Y) uniform vec3 u_origin_y;
layout(location = UNIFORM_FROXEL_RAY_DIRECTION) uniform vec3 u_direction;
layout(location = UNIFORM_FROXEL_RAY_DIRECTION_X) uniform vec3 u_direction_x;
layout(location = UNIFORM_FROXEL_RAY_DIRECTION_Y) uniform vec3 u_direction_y;
layout(location = UNIFORM_FROXEL_VIEW_FORWARD) uniform vec3 u_view_forward;
layout(location = UNIFORM_FROXEL_ORTHO) uniform int u_ortho;

// The froxel's scattering medium is even along its span (point_light_scatter weighs by it).
float scatter_sigma(float t) { return 1.0; }

const float kHalfMax = 60000.0; // below half float's largest (65504)

void main() {
    ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(tile, u_grid.xy))) return;
    vec2 ndc = (vec2(tile) + 0.5) / vec2(u_grid.xy) * 2.0 - 1.0;
    vec3 origin = u_origin + ndc.x * u_origin_x + ndc.y * u_origin_y;
    vec3 dir = normalize(u_direction + ndc.x * u_direction_x + ndc.y * u_direction_y);
    float per_t = u_ortho != 0 ? 1.0 : dot(dir, u_view_forward); // view depth per unit t
    vec3 light = vec3(0.0);
    float depth = 0.0; // optical depth in front of the slice
    for (int k = 0; k < u_grid.z; ++k) {
        uint base = froxel_base(ivec3(tile, k));
        vec3 e = vec3(uintBitsToFloat(froxel_data[base]), uintBitsToFloat(froxel_data[base + 1u]),
                      uintBitsToFloat(froxel_data[base + 2u]));
        float tau = uintBitsToFloat(froxel_data[base + 3u]), scattering = uintBitsToFloat(froxel_data[base + 4u]);
        float a = slice_start(k) / per_t, b = slice_start(k + 1) / per_t;
        float sigma_s = scattering / (b - a);
        // Behind an optical depth of 80 (transmittance 2e-35) nothing more shows: this also keeps
        // a sum that overflowed to infinity from turning the light into NaN.
        if (depth < 80.0) {
            vec3 s = vec3(0.0);
            if (scattering > 0.0)
                for (int l = 0; l < u_point_count; ++l)
                    s += u_point_color[l].rgb * (sigma_s * point_light_scatter(l, origin, dir, a, b, tau));
            // (1 − e^−τ)/τ without cancellation for small τ.
            float g = tau < 1e-3 ? 1.0 - tau * (0.5 - tau / 6.0) : (1.0 - exp(-tau)) / tau;
            light += exp(-depth) * (e * g + s);
        }
        depth += tau;
        imageStore(u_integrated, ivec3(tile, k), vec4(min(light, vec3(kHalfMax)), min(depth, kHalfMax)));
        imageStore(u_scattering, ivec3(tile, k), vec4(min(sigma_s, kHalfMax)));
    }
}
