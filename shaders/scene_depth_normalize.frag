#version 450 core
// The game's depth, whatever its convention, as cellfx's canonical depth (terrain::
// DepthNormalizer): window depth of the camera's standard projection (GL's default depth range
// and clip control) — what the render paths read. Both are affine in 1/z (perspective) or z
// (orthographic), so one affine map u_map converts them; a multisampled depth resolves to its
// nearest sample. Every fragment of a full-screen triangle (shaders/fullscreen.vert) writes the
// depth under its pixel; drawn with GL_DEPTH_TEST on, glDepthFunc(GL_ALWAYS), colour writes off.
#ifdef MULTISAMPLE
layout(binding = 0) uniform sampler2DMS u_depth; // the game's depth texture
#else
layout(binding = 0) uniform sampler2D u_depth;   // the game's depth texture (compare mode NONE by sampler)
#endif
#include "terrain_interface.glsl"
layout(location = UNIFORM_NORMALIZE_OFFSET) uniform ivec2 u_offset; // the game's texel = this fragment's pixel + u_offset
layout(location = UNIFORM_NORMALIZE_MAP) uniform vec2 u_map;        // canonical = u_map.x + u_map.y · game (clamped to [0, 1])
layout(location = UNIFORM_NORMALIZE_SAMPLES) uniform int u_samples; // MULTISAMPLE: samples per texel

layout(location = 0) in vec2 v_uv;

float canonical(float game) { return clamp(u_map.x + u_map.y * game, 0.0, 1.0); }

void main() {
    const ivec2 texel = ivec2(gl_FragCoord.xy) + u_offset;
#ifdef MULTISAMPLE
    float d = 1.0;
    for (int i = 0; i < u_samples; ++i) d = min(d, canonical(texelFetch(u_depth, texel, i).r));
    gl_FragDepth = d;
#else
    gl_FragDepth = canonical(texelFetch(u_depth, texel, 0).r);
#endif
}
