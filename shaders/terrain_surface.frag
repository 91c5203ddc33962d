#version 450 core
// The terrain surface: colour by height (a ramp of up to 8 stops over the field's height
// range), Lambert light from the sun plus ambient, normals from the full-resolution field's
// gradients (texture unit 0, linear filtering). Output premultiplied and opaque.
layout(binding = 0) uniform sampler2D u_gradients; // (dz/dx, dz/dy) per sample

#include "terrain_interface.glsl"
layout(location = UNIFORM_SURFACE_FIELD_ORIGIN) uniform vec2 u_field_origin;  // relative frame xy of sample (0, 0)
layout(location = UNIFORM_SURFACE_TEXEL) uniform vec2 u_texel;                // (1 / spacing, 1 / size)
layout(location = UNIFORM_SURFACE_HEIGHT_RANGE) uniform vec2 u_height_range;  // lowest height (relative frame), 1 / (highest − lowest)
layout(location = UNIFORM_SURFACE_SUN) uniform vec3 u_sun;                    // unit, towards the sun
layout(location = UNIFORM_SURFACE_AMBIENT) uniform float u_ambient;
layout(location = UNIFORM_SURFACE_STOPS) uniform int u_stops;
layout(location = UNIFORM_SURFACE_RAMP) uniform vec4 u_ramp[SURFACE_MAX_STOPS]; // (fraction, r, g, b)

layout(location = 0) in vec3 v_position;
layout(location = 0) out vec4 o_color;

vec3 ramp(float h) {
    if (h <= u_ramp[0].x) return u_ramp[0].yzw;
    for (int k = 1; k < u_stops; ++k) {
        if (h <= u_ramp[k].x) {
            float w = (h - u_ramp[k - 1].x) / max(u_ramp[k].x - u_ramp[k - 1].x, 1e-12);
            return mix(u_ramp[k - 1].yzw, u_ramp[k].yzw, w);
        }
    }
    return u_ramp[u_stops - 1].yzw;
}

void main() {
    // Sample centres sit at texel centres: uv = (grid coordinate + 0.5) / size.
    vec2 uv = ((v_position.xy - u_field_origin) * u_texel.x + 0.5) * u_texel.y;
    vec2 g = texture(u_gradients, uv).xy;
    vec3 n = normalize(vec3(-g, 1.0));
    float light = u_ambient + (1.0 - u_ambient) * max(dot(n, u_sun), 0.0);
    float h = clamp((v_position.z - u_height_range.x) * u_height_range.y, 0.0, 1.0);
    o_color = vec4(ramp(h) * light, 1.0);
}
