#include "gl/scatter_pass.hpp"

#include <string>

#include "fx/error.hpp"
#include "gl/gl_check.hpp"
#include "gl/program_cache.hpp"
#include "gl/shader_library.hpp"
#include "gl/state_guard.hpp"

namespace cellfx::fx::gl {
namespace {

// scatter.comp's interface: its bindings (within those StateGuard saves) and uniform locations,
// written once here and passed to GLSL as #defines.
constexpr GLuint kRecordsBinding = 13, kTargetBinding = 14, kStampsBinding = 15;
constexpr GLint kUniformCount = 0, kUniformStamp = 1;

Defines scatter_defines(std::uint32_t words_per_record) {
    return Defines{{"WORDS_PER_RECORD", std::to_string(words_per_record)}}
        .set("BINDING_RECORDS", int(kRecordsBinding))
        .set("BINDING_TARGET", int(kTargetBinding))
        .set("BINDING_STAMPS", int(kStampsBinding))
        .set("UNIFORM_COUNT", kUniformCount)
        .set("UNIFORM_STAMP", kUniformStamp);
}

} // namespace

ScatterPass::ScatterPass(std::uint32_t words_per_record)
    : cache_(ProgramCache::for_current_context()), words_per_record_(words_per_record) {
    if (words_per_record == 0 || words_per_record > 64) throw Error("scatter pass: 1 to 64 words per record");
    program_ = &cache_->program(ShaderLibrary::builtin(), {"scatter.comp"}, scatter_defines(words_per_record_));
}

ScatterPass::~ScatterPass() = default;
ScatterPass::ScatterPass(ScatterPass&&) noexcept = default;
ScatterPass& ScatterPass::operator=(ScatterPass&&) noexcept = default;

std::uint32_t* ScatterPass::add(std::uint32_t at, std::uint32_t words, std::uint32_t stamp_index) {
    const std::size_t stride = 4 + words_per_record_;
    if (records_.size() < used_ + stride) records_.resize(std::max(used_ + stride, records_.size() * 3 / 2 + 64));
    std::uint32_t* record = records_.data() + used_;
    record[0] = at;
    record[1] = words;
    record[2] = stamp_index;
    record[3] = 0;
    used_ += stride;
    ++count_;
    return record + 4; // words past `words` keep older values: the pass copies only `words`
}

void ScatterPass::reserve(std::size_t records) {
    const std::size_t words = records * (4 + words_per_record_);
    if (records_.size() < words) records_.resize(words + words / 2);
}

void ScatterPass::run(GLuint target, GLuint stamps, std::uint32_t stamp) {
    if (count_ == 0) return;
    staging_.upload(records_.data(), used_ * 4);
    StateGuard guard;
    const GLuint p = program_->id();
    glUseProgram(p);
    glProgramUniform1ui(p, kUniformCount, GLuint(count_));
    glProgramUniform1ui(p, kUniformStamp, GLuint(stamp));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRecordsBinding, staging_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kTargetBinding, target);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kStampsBinding, stamps ? stamps : target);
    glDispatchCompute(GLuint((count_ + 63) / 64), 1, 1);
    // Readers of the target: buffer textures, element and vertex pulls, storage buffers.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT |
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT);
    FX_GL_CHECK("scatter pass");
}

} // namespace cellfx::fx::gl
