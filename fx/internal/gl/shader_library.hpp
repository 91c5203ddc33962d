// cellfx — GLSL sources embedded at build time, assembled with includes, defines and #line.
//
// Shader files live in shaders/ and are listed in fx/CMakeLists.txt; cmake/EmbedShaders.cmake
// turns them into a generated .cpp registered by file name ("pcp.frag"). assemble() builds
// the text handed to GL:
//   1. the main file's `#version` line (or "#version 450 core" if it has none);
//   2. the caller's prelude of `#define`s (render paths pick features from a small config);
//   3. the main file, with every `#include "name"` line replaced by that library entry's text
//      (recursively; each file is included at most once per shader, like #pragma once).
// Each piece starts with `#line N S`. GLSL's core #line takes a source-string NUMBER S, so
// AssembledSource::files maps S → file path, and compile errors are rewritten through it to
// "shaders/pcp.frag:42: error: ...". Mesa ("0:42(7): error: ..."), NVIDIA ("0(42) : error
// C1008: ...") and glslang/AMD ("ERROR: 0:42: ...") logs are understood.
// `#include` lines are recognised anywhere (block comments included): keep them out of comments.
//
// Ownership: a ShaderLibrary owns copies of its sources; builtin() is a process-wide
// immutable instance. compile()/link() need a current GL 4.5 context and throw fx::Error.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gl/gl_object.hpp"

namespace cellfx::fx::gl {

// One embedded file, as the generated .cpp lists it.
struct EmbeddedShader {
    const char* name; // "composite.frag": the library key and #include name
    const char* path; // "shaders/composite.frag": what error messages print
    const char* text;
};
// Generated from the shader list in fx/CMakeLists.txt (build tree: embedded_shaders.cpp).
const EmbeddedShader* embedded_shaders(std::size_t& count);

// An ordered set of `#define NAME VALUE` lines; set() replaces an existing name.
class Defines {
public:
    Defines() = default;
    Defines(std::initializer_list<std::pair<std::string, std::string>> items);
    Defines& set(const std::string& name, const std::string& value = "1");
    Defines& set(const std::string& name, int value) { return set(name, std::to_string(value)); }
    bool empty() const { return items_.empty(); }
    std::string prelude() const;  // "#define A 1\n#define B 2\n"
    std::string summary() const;  // "A=1 B=2" for error messages
private:
    std::vector<std::pair<std::string, std::string>> items_;
};

struct AssembledSource {
    std::string text;               // for glShaderSource
    std::vector<std::string> files; // GLSL source-string number → file path ("<defines>" for the prelude)
};

// GL_VERTEX_SHADER for ".vert", and .frag .geom .comp .tesc .tese; throws for anything else.
GLenum shader_stage(std::string_view name);

// Rewrites each "S:L(C): msg" / "S(L) : msg" / "ERROR: S:L: msg" line of an info log to
// "files[S]:L: msg"; other lines are kept as they are.
std::string rewrite_info_log(std::string_view log, const std::vector<std::string>& files);

// Compiles assembled text; on failure throws fx::Error "compiling <what> failed:\n<rewritten log>".
Shader compile_shader(GLenum stage, const AssembledSource& source, const std::string& what);
// Links; on failure throws fx::Error "linking <what> failed:\n<log>". Shaders are detached.
Program link_program(const std::vector<Shader>& shaders, const std::string& what);

class ShaderLibrary {
public:
    ShaderLibrary() = default; // empty
    // The shaders embedded from shaders/ at build time.
    static const ShaderLibrary& builtin();

    // Adds or replaces `name`. `path` is what errors print (defaults to name). Lets tests
    // and hosts extend a copy of builtin() with their own files.
    void add(const std::string& name, std::string text, std::string path = {});
    bool contains(std::string_view name) const;
    const std::string& source(std::string_view name) const; // throws if absent
    const std::string& path(std::string_view name) const;   // throws if absent
    std::vector<std::string> names() const;

    // Throws fx::Error naming file and line for an unknown #include or a #version in an include.
    AssembledSource assemble(std::string_view name, const Defines& defines = {}) const;
    // Stage from the extension of `name`.
    Shader compile(std::string_view name, const Defines& defines = {}) const;
    // Compiles each named stage with the same defines and links them.
    Program link(std::initializer_list<std::string_view> names, const Defines& defines = {}) const;

private:
    struct Entry {
        std::string text;
        std::string path;
    };
    const Entry& entry(std::string_view name) const;
    std::map<std::string, Entry, std::less<>> entries_;
};

} // namespace cellfx::fx::gl
