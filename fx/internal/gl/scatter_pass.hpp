// cellfx — writes scattered values into a GL buffer: the parts that changed are uploaded as one
// block of records and a compute pass (shaders/scatter.comp) writes each where it belongs. For
// buffers that change in small scattered parts every frame — a terrain LOD's vertices and fans, a
// mesh's moved points and rewired cells — so that the CPU copies only what changed, whatever the
// buffer's size, and never maps a buffer the GPU may still be reading.
//
// A record is up to words_per_record 32-bit words written at a word offset of the target and,
// optionally, an index of a stamp buffer set to the run's stamp (what changed when: the
// projector rebuilds the cells whose points carry a newer stamp than its last build).
//
// Ownership: owns its staging buffer and storage (kept between frames: a frame of no more records
// than one before allocates nothing). Preconditions: a GL 4.5 core context current for every call
// but add(); the target and stamp buffers large enough for every offset and index written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "gl/gl_object.hpp"

namespace cellfx::fx::gl {

class ProgramCache;

class ScatterPass {
public:
    static constexpr std::uint32_t kNoStamp = 0xFFFFFFFFu;

    // Links (or finds, in the context's shared cache) its program: the context must be current.
    explicit ScatterPass(std::uint32_t words_per_record);
    ~ScatterPass();
    ScatterPass(ScatterPass&&) noexcept;
    ScatterPass& operator=(ScatterPass&&) noexcept;

    // Starts a new set of records.
    void clear() { used_ = 0, count_ = 0; }
    // Adds a record of `words` (≤ words_per_record) words written from word `at` of the target;
    // `stamp_index` names the stamp buffer's entry to set (kNoStamp: none). Returns where to put
    // the words. CPU only.
    std::uint32_t* add(std::uint32_t at, std::uint32_t words, std::uint32_t stamp_index = kNoStamp);
    std::size_t size() const { return count_; }
    // Room for this many records (then a frame of no more allocates nothing).
    void reserve(std::size_t records);

    // Uploads the records and writes them into `target` (a buffer name), setting the named stamps
    // of `stamps` (0: none) to `stamp`. Saves and restores the GL state it touches.
    void run(GLuint target, GLuint stamps = 0, std::uint32_t stamp = 0);

private:
    std::shared_ptr<ProgramCache> cache_; // keeps the program alive
    const Program* program_ = nullptr;
    std::uint32_t words_per_record_;
    // The records, in records_[0, used_): the vector only grows (its size is the room kept), so
    // add() writes in place instead of resizing, the one call a record made.
    std::vector<std::uint32_t> records_;
    std::size_t used_ = 0;
    std::size_t count_ = 0;
    GrowingBuffer staging_;
};

} // namespace cellfx::fx::gl
