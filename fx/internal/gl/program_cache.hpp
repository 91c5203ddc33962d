// cellfx — GL programs linked once per context and shared by everything that draws in it.
//
// A scene may hold thousands of renderers (one per laser beam); each linking its own programs
// costs megabytes of driver memory and link time per renderer. A ProgramCache belongs to one
// GL share group: for_current_context() finds the cache of the context current on the calling
// thread — it recognises its own contexts by a labelled marker buffer, so it works with any
// window system (EGL, GLX, WGL) — or makes one. Renderers hold a std::shared_ptr to it; the
// last holder to let go deletes the programs.
//
// Ownership: the cache owns its programs and marker; a returned Program reference stays valid
// while the cache lives. Preconditions: the context the cache was made in (or one sharing
// objects with it) is current for every call and when the last holder releases it. Calls
// from several threads are safe (each with its own context current).
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "gl/gl_object.hpp"
#include "gl/shader_library.hpp"

namespace cellfx::fx::gl {

class ProgramCache {
public:
    static std::shared_ptr<ProgramCache> for_current_context();
    ~ProgramCache();
    ProgramCache(const ProgramCache&) = delete;
    ProgramCache& operator=(const ProgramCache&) = delete;

    // The program linked from `stages` of `library` with `defines`: linked on the first request
    // (throws fx::Error with file:line like ShaderLibrary::link), the same object afterwards.
    const Program& program(const ShaderLibrary& library, std::initializer_list<std::string_view> stages,
                           const Defines& defines = {});
    std::size_t program_count() const;
    // How many programs this process has linked through any cache (tests check sharing with it).
    static std::size_t programs_linked();

private:
    ProgramCache();
    bool is_current() const; // is this the cache of the current context?

    Buffer marker_;
    std::string label_;
    mutable std::mutex mutex_;
    std::map<std::string, Program, std::less<>> programs_;
};

} // namespace cellfx::fx::gl
