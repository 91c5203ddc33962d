#version 450 core
// The effects' reduced-resolution layer over the full-resolution frame (terrain's FxLayer,
// fx_layer.hpp), upsampled against the scene's full-resolution depth, premultiplied "over"
// (glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA)). Each low-resolution pixel was drawn against
// the nearest or the farthest depth of its block, in a checkerboard (fx_layer_depth.frag); a
// full-resolution pixel takes:
//   - the bilinear mix of the four low-resolution pixels around it, leaving out those whose
//     depth differs from its own by more than kSameSurface (relative): smooth where the
//     surface is, and nothing from the far side of an edge;
//   - where none of the four is on its surface (a pixel at an edge), the one of the 3 × 3 around
//     it whose depth is nearest to its own (nearest-depth upsampling; equal depths: the nearest
//     on screen) — the checkerboard puts one drawn at either side of the edge among them.
// So a fire behind an object's edge shows neither on the object nor with a hole along the edge
// (tests/test_fx_scale.cpp measures both). Without a scene depth: bilinear.
layout(binding = 0) uniform sampler2D u_layer;     // premultiplied, low resolution
layout(binding = 1) uniform sampler2D u_low_depth; // the layer's depth (nearest or farthest of each block)
layout(binding = 2) uniform sampler2D u_depth;     // full-resolution canonical window depth
#include "terrain_interface.glsl"
layout(location = UNIFORM_LAYER_VIEWPORT) uniform vec4 u_viewport;                 // x, y, width, height (full resolution, in the framebuffer)
layout(location = UNIFORM_LAYER_UPSAMPLE_DEPTH_ORIGIN) uniform ivec2 u_depth_origin; // u_depth's texel of the viewport's pixel (0, 0)
layout(location = UNIFORM_LAYER_LOW_SIZE) uniform ivec2 u_low_size;
layout(location = UNIFORM_LAYER_DEPTH_MODEL) uniform vec3 u_depth_model;           // near, far, 0 no depth / 1 perspective / 2 orthographic

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

// Two depths belong to one surface when they differ by less than this fraction: far more than
// a smooth surface changes across a low-resolution pixel, far less than an object's edge.
const float kSameSurface = 0.1;

float view_depth(float w) {
    float n = u_depth_model.x, f = u_depth_model.y;
    return u_depth_model.z > 1.5 ? n + w * (f - n) : n * f / (f * (1.0 - w) + w * n);
}
float low_depth(ivec2 p) { return view_depth(texelFetch(u_low_depth, clamp(p, ivec2(0), u_low_size - 1), 0).r); }
vec4 low_color(ivec2 p) { return texelFetch(u_layer, clamp(p, ivec2(0), u_low_size - 1), 0); }

void main() {
    vec2 pixel = gl_FragCoord.xy - u_viewport.xy;
    // The pixel's centre in low-resolution pixels (their centres at i + 0.5).
    vec2 q = pixel / u_viewport.zw * vec2(u_low_size);
    if (u_depth_model.z < 0.5) {
        o_color = texture(u_layer, q / vec2(u_low_size));
        return;
    }
    float z = view_depth(texelFetch(u_depth, ivec2(pixel) + u_depth_origin, 0).r);
    ivec2 base = ivec2(floor(q - 0.5));
    vec2 f = q - 0.5 - vec2(base);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            ivec2 p = base + ivec2(i, j);
            float w = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
            if (abs(low_depth(p) - z) <= kSameSurface * z && w > 0.0) sum += w * low_color(p), weight += w;
        }
    if (weight > 0.0) {
        o_color = sum / weight;
        return;
    }
    ivec2 centre = ivec2(floor(q));
    ivec2 best = centre;
    float best_gap = 3.4e38, best_distance = 3.4e38;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            ivec2 p = centre + ivec2(i, j);
            float gap = abs(low_depth(p) - z);
            float distance = dot(vec2(p) + 0.5 - q, vec2(p) + 0.5 - q);
            if (gap < best_gap || (gap == best_gap && distance < best_distance)) best = p, best_gap = gap, best_distance = distance;
        }
    o_color = low_color(best);
}
