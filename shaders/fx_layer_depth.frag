#version 450 core
// The scene's depth at the effects' reduced resolution (terrain's FxLayer, fx_layer.hpp), in a
// checkerboard: each low-resolution pixel takes the NEAREST depth of the full-resolution pixels
// it covers where x + y is even, the FARTHEST where it is odd. Where a block straddles an
// object's edge, one of every two such pixels is drawn stopped at the object and the other
// behind it, so within one low-resolution pixel of any full-resolution one there is a pixel
// drawn at either surface — even for an object thinner than a block — and
// fx_layer_upsample.frag gives each full-resolution pixel one drawn at its own depth. (Nearest
// alone leaves the far side of every straddling block without the volumes behind the object: a
// hole up to a block wide along its edge; farthest alone lets them through a thin object.)
// Drawn as one full-screen triangle (fullscreen.vert) into the layer's depth (GL_DEPTH_TEST on,
// GL_ALWAYS, colour writes off).
layout(binding = 0) uniform sampler2D u_depth; // canonical window depth, full resolution
#include "terrain_interface.glsl"
layout(location = UNIFORM_LAYER_DEPTH_ORIGIN) uniform ivec2 u_origin; // texel of the full view's pixel (0, 0)
layout(location = UNIFORM_LAYER_DEPTH_SIZES) uniform ivec4 u_sizes;   // full width, height; low width, height

layout(location = 0) in vec2 v_uv;

void main() {
    ivec2 low = ivec2(gl_FragCoord.xy);
    // The full-resolution pixels whose centres fall in this low-resolution pixel.
    ivec2 first = ivec2(ceil(vec2(low) * vec2(u_sizes.xy) / vec2(u_sizes.zw) - 0.5));
    ivec2 last = ivec2(ceil(vec2(low + 1) * vec2(u_sizes.xy) / vec2(u_sizes.zw) - 0.5)) - 1;
    first = clamp(first, ivec2(0), u_sizes.xy - 1), last = clamp(last, first, u_sizes.xy - 1);
    float nearest = 1.0, farthest = 0.0;
    for (int y = first.y; y <= last.y; ++y)
        for (int x = first.x; x <= last.x; ++x) {
            float d = texelFetch(u_depth, ivec2(x, y) + u_origin, 0).r;
            nearest = min(nearest, d), farthest = max(farthest, d);
        }
    gl_FragDepth = ((low.x + low.y) & 1) == 0 ? nearest : farthest;
}
