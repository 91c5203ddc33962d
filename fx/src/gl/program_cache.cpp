#include "gl/program_cache.hpp"

#include <atomic>
#include <vector>

namespace cellfx::fx::gl {
namespace {

std::mutex registry_mutex;
std::vector<std::weak_ptr<ProgramCache>>& registry() {
    static std::vector<std::weak_ptr<ProgramCache>> caches;
    return caches;
}
std::atomic<std::size_t> linked{0};
std::atomic<std::size_t> caches_made{0};

} // namespace

ProgramCache::ProgramCache() : marker_(make_buffer(16, nullptr)) {
    label_ = "cellfx program cache " + std::to_string(caches_made++) + " of process " +
             std::to_string(reinterpret_cast<std::uintptr_t>(&registry_mutex));
    glObjectLabel(GL_BUFFER, marker_.id(), GLsizei(label_.size()), label_.c_str());
    FX_GL_CHECK("program cache marker");
}

ProgramCache::~ProgramCache() = default;

bool ProgramCache::is_current() const {
    // Names are per share group: the marker's name may be some other buffer in another context,
    // but not one with this label.
    if (!glIsBuffer(marker_.id())) return false;
    char label[128] = {};
    GLsizei length = 0;
    glGetObjectLabel(GL_BUFFER, marker_.id(), GLsizei(sizeof label), &length, label);
    return std::string_view(label, std::size_t(length)) == label_;
}

std::shared_ptr<ProgramCache> ProgramCache::for_current_context() {
    std::lock_guard<std::mutex> lock(registry_mutex);
    auto& caches = registry();
    for (std::size_t i = 0; i < caches.size();) {
        std::shared_ptr<ProgramCache> cache = caches[i].lock();
        if (!cache) {
            caches.erase(caches.begin() + std::ptrdiff_t(i));
            continue;
        }
        if (cache->is_current()) return cache;
        ++i;
    }
    std::shared_ptr<ProgramCache> cache(new ProgramCache());
    caches.push_back(cache);
    return cache;
}

const Program& ProgramCache::program(const ShaderLibrary& library, std::initializer_list<std::string_view> stages,
                                     const Defines& defines) {
    std::string key = std::to_string(reinterpret_cast<std::uintptr_t>(&library));
    for (std::string_view s : stages) key.append("|").append(s);
    key += "|" + defines.summary();
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = programs_.find(key);
    if (it == programs_.end()) {
        it = programs_.emplace(std::move(key), library.link(stages, defines)).first;
        ++linked;
    }
    return it->second;
}

std::size_t ProgramCache::program_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return programs_.size();
}

std::size_t ProgramCache::programs_linked() { return linked; }

} // namespace cellfx::fx::gl
