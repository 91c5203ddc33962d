// The medium compositor's per-pixel lists of ray segments (fx/internal/medium/medium_compositor.hpp), shared by
// medium_append.frag and medium_resolve.frag. One storage buffer at binding 3:
//   medium_count          segments appended this frame (may exceed the pool: overflow)
//   medium_data[0 .. n)   one list head per pixel of the region (row by row, viewport pixels): 0 = empty,
//                         else the first segment's index + 1
//   medium_data[n + 5i ..] segment i: t_in, t_out, s_in, s_out (float bits), and
//                         (next segment's index + 1) << 5 | volume
// Binding 3 is the projector's per-frame buffer (BINDING_FRAME: near-plane caps), which the
// append pass's cells.vert does not use.
#include "projector_interface.glsl"
layout(std430, binding = 3) coherent buffer MediumLists {
    uint medium_count;
    uint medium_pad[3];
    uint medium_data[];
};

layout(location = UNIFORM_MEDIUM_REGION) uniform ivec4 u_region; // x, y, width, height in viewport pixels
const uint kVolumeBits = 5u;                                     // MEDIUM_VOLUMES = 32 = 1 << 5

int region_pixel(ivec2 p) { return (p.y - u_region.y) * u_region.z + (p.x - u_region.x); }
uint segment_base(uint index) { return uint(u_region.z * u_region.w) + 5u * index; }
