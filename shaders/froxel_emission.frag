#version 450 core
// The froxel medium's emission-only volumes (fire, search lights, lasers: they glow and dim
// nothing), drawn per pixel so that their detail stays as sharp as their own path draws it
// (fx/internal/medium/froxel_medium.hpp). On the BACK faces of every cell (the renderer's GL
// projector: cells.vert), each fragment's exact segment in its cell (cell_segment.glsl, cut at
// the near plane and the scene's depth) gives the volume's emission (segment_integral), dimmed
// by the grid's transmittance in front of it; a beam also lights the grid's scattering medium
// along the segment (fx/medium.hpp: ρσ·L·4π·p(cos θ), L the beam's strength from the cell's
// scalar). Output rgb, alpha 0, blended additively (they absorb nothing).
#define FROXEL_INTEGRATED_UNIT 1
#include "project.glsl"
#include "cell_segment.glsl"
#include "froxel_grid.glsl"
#include "medium_lights.glsl"

layout(binding = 2) uniform sampler3D u_scattering; // ρσ per unit length, per froxel
// The viewport drawn into (x, y, width, height in the framebuffer): pixel (i, j) is the begin()
// view's pixel at that size; the scene depth's texel is the framebuffer pixel (gl_FragCoord).
layout(location = UNIFORM_FROXEL_VIEWPORT) uniform vec4 u_viewport;
layout(location = UNIFORM_FROXEL_BEAM) uniform vec4 u_beam;             // beam (0/1), phase g, strength per scalar, apex distance (0: parallel)
layout(location = UNIFORM_FROXEL_BEAM_ORIGIN) uniform vec3 u_beam_origin; // the lens centre, relative frame
layout(location = UNIFORM_FROXEL_BEAM_AXIS) uniform vec3 u_beam_axis;     // unit direction of travel, relative frame
layout(location = UNIFORM_FROXEL_BEAM_COLOR) uniform vec3 u_beam_color;

layout(location = 0) out vec4 o_color;

float scatter_sigma(float t) { return 1.0; } // (medium_lights.glsl's point lights are not used here)

// The grid's scattering coefficient at view depth z (between slice centres).
float scattering_at(vec2 uv, float z) {
    float x = log(max(z, 1e-30) / u_slicing.x) / u_slicing.y; // continuous slice index
    return texture(u_scattering, vec3(uv, clamp(x, 0.0, float(u_grid.z)) / float(u_grid.z))).r;
}

void main() {
    vec2 pixel = gl_FragCoord.xy - u_viewport.xy;
    Ray ray = fragment_ray(pixel);
    CellSegment segment = cell_segment(ray);
    if (!(segment.length > 0.0)) discard;
    vec2 uv = pixel / u_viewport.zw;
    float per_t = u_orthographic != 0 ? 1.0 : dot(ray.dir, u_forward);
    // The grid at the segment's middle: a cell's segment is short against a slice, and the
    // transmittance and scattering vary slowly along it (the midpoint rule's error is
    // (σ·l)²/24 of the transmittance: 1.5e-4 for an optical depth of 0.06 across a cell).
    float t_mid = segment.t_in + 0.5 * segment.length, z_mid = t_mid * per_t;
    float transmittance = exp(-medium_in_front(uv, z_mid).a);
    vec3 light = segment_integral(segment.s_in, segment.s_out, segment.length).rgb;
    if (u_beam.x > 0.5) {
        // ∫ ρσ · L · 4π·p dt with L and the phase from the cell's scalar and the beam's
        // geometry: Simpson's rule over the segment's ends and middle.
        float sum = 0.0;
        for (int j = 0; j < 3; ++j) {
            float t = segment.t_in + 0.5 * float(j) * segment.length;
            vec3 x = ray.origin + ray.dir * t;
            vec3 light_dir = u_beam.w > 0.0 ? normalize(x - (u_beam_origin - u_beam_axis * u_beam.w)) : u_beam_axis;
            float strength = max(mix(segment.s_in, segment.s_out, 0.5 * float(j)), 0.0) * u_beam.z;
            sum += (j == 1 ? 4.0 : 1.0) * strength * relative_phase(u_beam.y, dot(light_dir, -ray.dir));
        }
        light += scattering_at(uv, z_mid) * sum * (segment.length / 6.0) * u_beam_color;
    }
    o_color = vec4(light * transmittance, 0.0);
}
