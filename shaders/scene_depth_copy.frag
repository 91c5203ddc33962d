#version 450 core
// Copies the game's depth into cellfx's own target (terrain::SceneRenderer), so that the terrain
// surface and the effects are depth-tested against the game's opaque geometry: every fragment
// of a full-screen triangle (shaders/fullscreen.vert) writes the game's depth under its pixel.
// Drawn with GL_DEPTH_TEST on, glDepthFunc(GL_ALWAYS), colour writes off.
layout(binding = 0) uniform sampler2D u_depth;  // the game's depth texture (compare mode NONE by sampler)
layout(location = 0) uniform ivec2 u_origin;    // viewport origin in the game's depth texture

layout(location = 0) in vec2 v_uv;

void main() {
    gl_FragDepth = texelFetch(u_depth, ivec2(gl_FragCoord.xy) + u_origin, 0).r;
}
