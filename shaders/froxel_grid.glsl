// The froxel grid of the one medium (fx/internal/medium/froxel_medium.hpp), shared by its
// passes: froxel_inject.frag, froxel_integrate.comp, froxel_apply.frag, froxel_emission.frag.
//
// Froxel (i, j, k): screen tile (i, j) of a u_grid.x × u_grid.y division of the view (tile
// (i, j) is the ray through its centre, ndc ((i + 0.5)/x·2 − 1, (j + 0.5)/y·2 − 1)) and depth
// slice k of u_grid.z, exponential in view depth z (along the view direction, not the ray):
// slice k covers [z_k, z_k+1), z_k = z_near·e^(k·step), z_near the camera's near plane and
// z_64 the farthest depth of the volumes injected (what lies beyond goes to the last
// slice). Uniform locations from the interface table (fx/src/projector/gl_interface.hpp).
#include "projector_interface.glsl"
layout(location = UNIFORM_FROXEL_GRID) uniform ivec3 u_grid;   // tiles across, tiles up, slices
layout(location = UNIFORM_FROXEL_SLICING) uniform vec2 u_slicing; // z_near, step = ln(z_far / z_near) / slices

float slice_start(int k) { return u_slicing.x * exp(float(k) * u_slicing.y); }
// The slice holding view depth z (0 in front of z_near, the last one beyond z_far).
int slice_of(float z) {
    float x = log(max(z, 1e-30) / u_slicing.x) / u_slicing.y;
    return int(clamp(floor(x), 0.0, float(u_grid.z - 1)));
}
// Where view depth z lies among the slices' far ends as a continuous index b ∈ [0, slices]:
// b = k + (z − z_k)/(z_k+1 − z_k) in slice k, linear in z inside a slice. The integrated grid
// holds at layer k the medium in front of z_k+1, so the medium in front of z is that grid
// interpolated between layers at b − 1 (and between nothing and layer 0 in front of z_1).
float far_end_index(float z) {
    int k = slice_of(z);
    float z0 = slice_start(k), z1 = slice_start(k + 1);
    return float(k) + clamp((z - z0) / (z1 - z0), 0.0, 1.0);
}

// Injection (froxel_inject.frag → froxel_integrate.comp): per froxel five floats, as bits,
// added with atomic compare-and-swap (core GL 4.5; no float atomics needed):
//   emission ∫c·σ (rgb), optical depth τ = ∫σ of the absorbing volumes, scattering ∫ρ·σ.
const int kFroxelWords = 5;
#ifdef FROXEL_INJECTION
layout(std430, binding = 4) coherent buffer FroxelInjection { uint froxel_data[]; };
uint froxel_base(ivec3 f) { return uint(((f.z * u_grid.y + f.y) * u_grid.x + f.x) * kFroxelWords); }
#endif

// Reading the integrated grid (froxel_apply.frag, froxel_emission.frag): FROXEL_INTEGRATED_UNIT
// names the texture unit of the layers (L rgb, τ), sampled with linear filtering (between tile
// centres and between layers).
#ifdef FROXEL_INTEGRATED_UNIT
layout(binding = FROXEL_INTEGRATED_UNIT) uniform sampler3D u_integrated;
// The light (rgb) and optical depth (a) of the medium in front of view depth z on the ray of
// screen position uv ∈ [0, 1]² (the grid's own mapping: ndc = 2·uv − 1).
vec4 medium_in_front(vec2 uv, float z) {
    float b = far_end_index(z);
    vec4 v = texture(u_integrated, vec3(uv, (max(b, 1.0) - 0.5) / float(u_grid.z)));
    return b < 1.0 ? v * b : v;
}
#endif
