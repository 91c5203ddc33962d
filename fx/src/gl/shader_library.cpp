#include "gl/shader_library.hpp"

#include <cctype>
#include <set>

namespace cellfx::fx::gl {
namespace {

std::string_view trim_left(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t'))
        ++i;
    return s.substr(i);
}

// If `line` is a preprocessor directive named `directive` ("version", "include"), returns the
// rest of the line after it; otherwise returns false.
bool directive_rest(std::string_view line, std::string_view directive, std::string_view& rest) {
    line = trim_left(line);
    if (line.empty() || line[0] != '#')
        return false;
    line = trim_left(line.substr(1));
    if (line.substr(0, directive.size()) != directive)
        return false;
    rest = line.substr(directive.size());
    return rest.empty() || rest[0] == ' ' || rest[0] == '\t' || rest[0] == '"';
}

// Splits keeping line structure: the last piece has no '\n' (it may be empty).
std::vector<std::string_view> split_lines(std::string_view text) {
    std::vector<std::string_view> lines;
    std::size_t start = 0;
    for (;;) {
        const std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) {
            lines.push_back(text.substr(start));
            return lines;
        }
        std::string_view line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);
        lines.push_back(line);
        start = end + 1;
    }
}

bool parse_uint(std::string_view s, std::size_t& pos, unsigned long& value) {
    const std::size_t begin = pos;
    value = 0;
    while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos])))
        value = value * 10 + static_cast<unsigned long>(s[pos++] - '0');
    return pos > begin;
}

bool eat(std::string_view s, std::size_t& pos, std::string_view token) {
    if (s.substr(pos, token.size()) != token)
        return false;
    pos += token.size();
    return true;
}

// Recognises one info-log line; fills source string, line and the message after the location.
bool parse_log_line(std::string_view line, unsigned long& string_no, unsigned long& line_no, std::string& message) {
    std::size_t pos = 0;
    unsigned long column = 0;
    // Mesa: "0:42(7): error: ..."
    if (parse_uint(line, pos, string_no) && eat(line, pos, ":") && parse_uint(line, pos, line_no) &&
        eat(line, pos, "(") && parse_uint(line, pos, column) && eat(line, pos, "):")) {
        message = std::string(trim_left(line.substr(pos)));
        return true;
    }
    // NVIDIA: "0(42) : error C1008: ..."
    pos = 0;
    if (parse_uint(line, pos, string_no) && eat(line, pos, "(") && parse_uint(line, pos, line_no) &&
        eat(line, pos, ")") && (eat(line, pos, " :") || eat(line, pos, ":"))) {
        message = std::string(trim_left(line.substr(pos)));
        return true;
    }
    // glslang / AMD: "ERROR: 0:42: ..."
    for (std::string_view kind : {std::string_view("ERROR: "), std::string_view("WARNING: ")}) {
        pos = 0;
        if (eat(line, pos, kind) && parse_uint(line, pos, string_no) && eat(line, pos, ":") &&
            parse_uint(line, pos, line_no) && eat(line, pos, ":")) {
            message = (kind[0] == 'E' ? "error: " : "warning: ") + std::string(trim_left(line.substr(pos)));
            return true;
        }
    }
    return false;
}

std::string info_log(GLuint object, bool program) {
    GLint length = 0;
    if (program)
        glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    else
        glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
    GLsizei written = 0;
    if (program)
        glGetProgramInfoLog(object, static_cast<GLsizei>(log.size()), &written, log.data());
    else
        glGetShaderInfoLog(object, static_cast<GLsizei>(log.size()), &written, log.data());
    log.resize(static_cast<std::size_t>(written));
    return log;
}

// Appends `text` of file number `file_no` to `out`, expanding includes (see the header).
struct Assembler {
    const ShaderLibrary& library;
    AssembledSource out;
    std::set<std::string, std::less<>> included;

    int file_number(const std::string& path) {
        out.files.push_back(path);
        return static_cast<int>(out.files.size()) - 1;
    }

    // `skip_line` (1-based, 0 for none) is emitted empty: the main file's #version, hoisted.
    void append(std::string_view name, int file_no, std::size_t skip_line) {
        const std::string& path = library.path(name);
        const std::vector<std::string_view> lines = split_lines(library.source(name));
        out.text += "#line 1 " + std::to_string(file_no) + "\n";
        for (std::size_t i = 0; i < lines.size(); ++i) {
            const std::string location = path + ":" + std::to_string(i + 1);
            std::string_view rest;
            if (i + 1 == skip_line) {
                out.text += "\n";
            } else if (directive_rest(lines[i], "include", rest)) {
                rest = trim_left(rest);
                const std::size_t close = rest.size() > 1 && rest[0] == '"' ? rest.find('"', 1) : std::string_view::npos;
                if (close == std::string_view::npos)
                    throw Error(location + ": malformed #include (expected #include \"file\")");
                const std::string_view target = rest.substr(1, close - 1);
                if (!library.contains(target))
                    throw Error(location + ": #include \"" + std::string(target) + "\": no such shader in the library");
                if (included.insert(std::string(target)).second) {
                    append(target, file_number(library.path(target)), 0);
                    // Back in this file: the next line is i + 2.
                    out.text += "#line " + std::to_string(i + 2) + " " + std::to_string(file_no) + "\n";
                } else {
                    out.text += "\n"; // already included once: nothing to add, numbering kept
                }
            } else if (skip_line == 0 && directive_rest(lines[i], "version", rest)) {
                throw Error(location + ": #version is only allowed in the main shader file, not in an include");
            } else {
                out.text.append(lines[i].data(), lines[i].size());
                out.text += "\n";
            }
        }
    }
};

} // namespace

Defines::Defines(std::initializer_list<std::pair<std::string, std::string>> items) {
    for (const auto& [name, value] : items)
        set(name, value);
}

Defines& Defines::set(const std::string& name, const std::string& value) {
    for (auto& item : items_) {
        if (item.first == name) {
            item.second = value;
            return *this;
        }
    }
    items_.emplace_back(name, value);
    return *this;
}

std::string Defines::prelude() const {
    std::string s;
    for (const auto& [name, value] : items_)
        s += "#define " + name + " " + value + "\n";
    return s;
}

std::string Defines::summary() const {
    std::string s;
    for (const auto& [name, value] : items_)
        s += (s.empty() ? "" : " ") + name + "=" + value;
    return s;
}

GLenum shader_stage(std::string_view name) {
    const std::size_t dot = name.rfind('.');
    const std::string_view ext = dot == std::string_view::npos ? std::string_view() : name.substr(dot);
    if (ext == ".vert") return GL_VERTEX_SHADER;
    if (ext == ".frag") return GL_FRAGMENT_SHADER;
    if (ext == ".geom") return GL_GEOMETRY_SHADER;
    if (ext == ".comp") return GL_COMPUTE_SHADER;
    if (ext == ".tesc") return GL_TESS_CONTROL_SHADER;
    if (ext == ".tese") return GL_TESS_EVALUATION_SHADER;
    throw Error("shader \"" + std::string(name) +
                "\": unknown stage (expected .vert, .frag, .geom, .comp, .tesc or .tese)");
}

std::string rewrite_info_log(std::string_view log, const std::vector<std::string>& files) {
    std::string out;
    for (std::string_view line : split_lines(log)) {
        unsigned long string_no = 0, line_no = 0;
        std::string message;
        if (parse_log_line(line, string_no, line_no, message)) {
            const std::string file =
                string_no < files.size() ? files[string_no] : "source string " + std::to_string(string_no);
            out += file + ":" + std::to_string(line_no) + ": " + message;
        } else {
            out.append(line.data(), line.size());
        }
        out += "\n";
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == '\0'))
        out.pop_back();
    return out;
}

Shader compile_shader(GLenum stage, const AssembledSource& source, const std::string& what) {
    Shader shader = Shader::create(stage);
    const GLchar* text = source.text.c_str();
    const auto length = static_cast<GLint>(source.text.size());
    glShaderSource(shader.id(), 1, &text, &length);
    glCompileShader(shader.id());
    FX_GL_CHECK("glCompileShader");
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE)
        throw Error("compiling " + what + " failed:\n" + rewrite_info_log(info_log(shader.id(), false), source.files));
    return shader;
}

Program link_program(const std::vector<Shader>& shaders, const std::string& what) {
    Program program = Program::create();
    for (const Shader& s : shaders)
        glAttachShader(program.id(), s.id());
    glLinkProgram(program.id());
    // Detached shaders are freed with their wrappers; the program keeps its binary.
    for (const Shader& s : shaders)
        glDetachShader(program.id(), s.id());
    FX_GL_CHECK("glLinkProgram");
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE)
        throw Error("linking " + what + " failed:\n" + info_log(program.id(), true));
    return program;
}

const ShaderLibrary& ShaderLibrary::builtin() {
    static const ShaderLibrary library = [] {
        ShaderLibrary lib;
        std::size_t count = 0;
        const EmbeddedShader* shaders = embedded_shaders(count);
        for (std::size_t i = 0; i < count; ++i)
            lib.add(shaders[i].name, shaders[i].text, shaders[i].path);
        return lib;
    }();
    return library;
}

void ShaderLibrary::add(const std::string& name, std::string text, std::string path) {
    if (path.empty())
        path = name;
    entries_[name] = Entry{std::move(text), std::move(path)};
}

bool ShaderLibrary::contains(std::string_view name) const { return entries_.find(name) != entries_.end(); }

const ShaderLibrary::Entry& ShaderLibrary::entry(std::string_view name) const {
    auto it = entries_.find(name);
    if (it == entries_.end())
        throw Error("shader library: no shader named \"" + std::string(name) + "\"");
    return it->second;
}

const std::string& ShaderLibrary::source(std::string_view name) const { return entry(name).text; }
const std::string& ShaderLibrary::path(std::string_view name) const { return entry(name).path; }

std::vector<std::string> ShaderLibrary::names() const {
    std::vector<std::string> result;
    for (const auto& item : entries_)
        result.push_back(item.first);
    return result;
}

AssembledSource ShaderLibrary::assemble(std::string_view name, const Defines& defines) const {
    const Entry& main = entry(name);
    Assembler assembler{*this, {}, {}};
    AssembledSource& out = assembler.out;
    out.files.push_back(main.path); // number 0: errors before any #line land in the main file

    // #version must come first; it may follow comments and blank lines in the file.
    std::size_t version_line = 0;
    const std::vector<std::string_view> lines = split_lines(main.text);
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::string_view t = trim_left(lines[i]);
        std::string_view rest;
        if (directive_rest(t, "version", rest)) {
            version_line = i + 1;
            out.text.append(t.data(), t.size());
            out.text += "\n";
            break;
        }
        if (!t.empty() && t.substr(0, 2) != "//")
            break;
    }
    if (version_line == 0)
        out.text += "#version 450 core\n";
    if (!defines.empty()) {
        const int prelude_no = assembler.file_number("<defines>");
        out.text += "#line 1 " + std::to_string(prelude_no) + "\n" + defines.prelude();
    }
    // version_line 0 would mean "no skip" to append(); use an impossible line instead.
    assembler.included.insert(std::string(name));
    assembler.append(name, 0, version_line == 0 ? lines.size() + 1 : version_line);
    return out;
}

Shader ShaderLibrary::compile(std::string_view name, const Defines& defines) const {
    const AssembledSource source = assemble(name, defines);
    std::string what = path(name);
    if (!defines.empty())
        what += " (" + defines.summary() + ")";
    return compile_shader(shader_stage(name), source, what);
}

Program ShaderLibrary::link(std::initializer_list<std::string_view> names, const Defines& defines) const {
    std::vector<Shader> shaders;
    std::string what;
    for (std::string_view n : names) {
        shaders.push_back(compile(n, defines));
        what += (what.empty() ? "" : " + ") + path(n);
    }
    if (!defines.empty())
        what += " (" + defines.summary() + ")";
    return link_program(shaders, what);
}

} // namespace cellfx::fx::gl
