#version 450 core
// gl::ScatterPass (fx/internal/gl/scatter_pass.hpp): record i is a header (word offset, word
// count, stamp index or 0xFFFFFFFF, unused) and WORDS_PER_RECORD words; its words go to the
// target from that offset, and the stamp buffer's entry to the run's stamp.
layout(local_size_x = 64) in;

// Bindings and uniform locations: #defines from gl/scatter_pass.cpp, where they are written once.
layout(std430, binding = BINDING_RECORDS) readonly buffer Records { uint records[]; };
layout(std430, binding = BINDING_TARGET) writeonly buffer Target { uint target[]; };
layout(std430, binding = BINDING_STAMPS) writeonly buffer Stamps { uint stamps[]; };

layout(location = UNIFORM_COUNT) uniform uint u_count;
layout(location = UNIFORM_STAMP) uniform uint u_stamp;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    uint base = i * uint(4 + WORDS_PER_RECORD);
    uint at = records[base], words = min(records[base + 1u], uint(WORDS_PER_RECORD)), stamp = records[base + 2u];
    for (uint k = 0u; k < words; ++k) target[at + k] = records[base + 4u + k];
    if (stamp != 0xFFFFFFFFu) stamps[stamp] = u_stamp;
}
