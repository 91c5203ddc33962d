// The installed headers (fx/include, terrain/include: cmake/Install.cmake) declare nothing at
// the top level but namespace cellfx, so a game's own fx, terrain or Scene cannot clash with
// them, and include no internal header. tests/consumer builds a game with its own fx::Error
// and terrain::Scene against them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_paths.hpp"

namespace {

namespace fs = std::filesystem;

// Every header installed from the source tree, with its path relative to the include root.
struct PublicHeader {
    fs::path file;
    std::string name; // "fx/camera.hpp", "cellfx/cellfx.hpp"
};

std::vector<PublicHeader> public_headers() {
    std::vector<PublicHeader> headers;
    for (const char* root : {"fx/include", "terrain/include"}) {
        const fs::path dir = fx_test::source_path(root);
        for (const auto& entry : fs::recursive_directory_iterator(dir))
            if (entry.is_regular_file() && entry.path().extension() == ".hpp")
                headers.push_back({entry.path(), fs::relative(entry.path(), dir).generic_string()});
    }
    return headers;
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The text with comments, string and character literals and preprocessor lines blanked out
// (newlines kept, so positions still give line numbers).
std::string code_only(const std::string& text) {
    std::string out = text;
    std::size_t i = 0;
    bool line_start = true;
    auto blank = [&](std::size_t from, std::size_t to) {
        for (std::size_t k = from; k < to && k < out.size(); ++k)
            if (out[k] != '\n') out[k] = ' ';
    };
    while (i < text.size()) {
        const char c = text[i];
        if (line_start && c == '#') { // a directive, with its continuation lines
            std::size_t end = i;
            while (end < text.size() && !(text[end] == '\n' && text[end - 1] != '\\')) ++end;
            blank(i, end);
            i = end;
            continue;
        }
        if (c == '\n') line_start = true;
        else if (c != ' ' && c != '\t') line_start = false;
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
            const std::size_t end = text.find('\n', i);
            blank(i, end == std::string::npos ? text.size() : end);
            i = end == std::string::npos ? text.size() : end;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const std::size_t end = text.find("*/", i + 2);
            const std::size_t stop = end == std::string::npos ? text.size() : end + 2;
            blank(i, stop);
            i = stop;
        } else if (c == '"' || c == '\'') {
            std::size_t end = i + 1;
            while (end < text.size() && text[end] != c) end += text[end] == '\\' ? 2 : 1;
            blank(i, end + 1);
            i = end + 1;
        } else {
            ++i;
        }
    }
    return out;
}

// The line of the first character after `from` that is not white space.
int line_of(const std::string& text, std::size_t from) {
    const std::size_t pos = std::min(text.find_first_not_of(" \t\n", from), text.size());
    return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(pos), '\n'));
}

// Whether `statement` is `namespace cellfx` or `namespace cellfx::a::b` (any white space). By
// hand rather than std::regex: libstdc++'s matcher recurses once per character, and a header's
// blanked-out comments before its first brace overflow the stack under AddressSanitizer.
bool is_cellfx_namespace(const std::string& statement) {
    std::istringstream words(statement);
    std::string keyword, name, word;
    if (!(words >> keyword) || keyword != "namespace") return false;
    while (words >> word) name += word; // "cellfx :: fx" → "cellfx::fx"
    if (name.rfind("cellfx", 0) != 0) return false;
    for (std::size_t i = 6; i < name.size();) { // then "::identifier" parts only
        if (name.compare(i, 2, "::") != 0) return false;
        std::size_t end = i + 2;
        while (end < name.size() && (std::isalnum(static_cast<unsigned char>(name[end])) || name[end] == '_')) ++end;
        if (end == i + 2) return false;
        i = end;
    }
    return true;
}

// Where each file-scope declaration that is not `namespace cellfx[::...] { ... }` begins, as
// "header:line".
std::vector<std::string> top_level_outside_cellfx(const PublicHeader& header) {
    const std::string code = code_only(read_text(header.file));
    std::vector<std::string> found;
    int depth = 0;
    std::size_t statement = 0; // where the current file-scope statement began
    for (std::size_t i = 0; i < code.size(); ++i) {
        const char c = code[i];
        if (c == '{') {
            if (depth == 0 && !is_cellfx_namespace(code.substr(statement, i - statement)))
                found.push_back(header.name + ":" + std::to_string(line_of(code, statement)));
            ++depth;
        } else if (c == '}') {
            if (--depth == 0) statement = i + 1;
        } else if (c == ';' && depth == 0) {
            if (code.find_first_not_of(" \t\n", statement) < i)
                found.push_back(header.name + ":" + std::to_string(line_of(code, statement)));
            statement = i + 1;
        }
    }
    return found;
}

} // namespace

TEST_CASE("the installed headers declare nothing outside namespace cellfx", "[public_headers]") {
    const std::vector<PublicHeader> headers = public_headers();
    REQUIRE(headers.size() > 10);
    for (const PublicHeader& header : headers) {
        const std::vector<std::string> found = top_level_outside_cellfx(header);
        CAPTURE(found);
        CHECK(found.empty());
    }
}

TEST_CASE("the installed headers include only installed headers", "[public_headers]") {
    // fx/src and fx/internal are not installed: a public header that includes one of them
    // compiles here and breaks in a game's build.
    const std::vector<PublicHeader> headers = public_headers();
    std::set<std::string> installed;
    for (const PublicHeader& header : headers) installed.insert(header.name);
    static const std::regex quoted_include(R"re(^\s*#\s*include\s*"([^"]+)")re");
    for (const PublicHeader& header : headers) {
        std::istringstream lines(read_text(header.file));
        std::string line;
        for (int number = 1; std::getline(lines, line); ++number) {
            std::smatch m;
            if (!std::regex_search(line, m, quoted_include)) continue;
            CAPTURE(header.name, number, line);
            CHECK(installed.count(m[1].str()) == 1);
        }
    }
}

TEST_CASE("the header check finds a declaration outside namespace cellfx", "[public_headers]") {
    const fs::path dir = fx_test::output_path("public_headers");
    fs::create_directories(dir);
    const fs::path file = dir / "leaky.hpp";
    std::ofstream(file) << "// namespace fx { struct Commented {}; }\n#pragma once\n#define LEAK(x) \\\n  x;\n"
                           "namespace cellfx::fx {\nstruct Fine { const char* text = \"}\"; };\n} // namespace cellfx::fx\n"
                           "namespace fx {\nstruct Error {};\n}\nusing Id = int;\n";
    const std::vector<std::string> found = top_level_outside_cellfx({file, "leaky.hpp"});
    CHECK(found == std::vector<std::string>{"leaky.hpp:8", "leaky.hpp:11"});
}

namespace {

// Where a header's code (comments and literals aside) declares a friend, as "header:line": a
// friend in an installed header names an internal type to every game that includes it.
std::vector<std::string> friends_in(const PublicHeader& header) {
    const std::string code = code_only(read_text(header.file));
    static const std::regex friend_word(R"(\bfriend\b)");
    std::vector<std::string> found;
    for (auto it = std::sregex_iterator(code.begin(), code.end(), friend_word); it != std::sregex_iterator(); ++it)
        found.push_back(header.name + ":" + std::to_string(line_of(code, std::size_t(it->position()))));
    return found;
}

} // namespace

TEST_CASE("the installed headers declare no friend", "[public_headers]") {
    for (const PublicHeader& header : public_headers()) {
        const std::vector<std::string> found = friends_in(header);
        CAPTURE(found);
        CHECK(found.empty());
    }
}

TEST_CASE("the friend check finds a friend in code and not in a comment", "[public_headers]") {
    const fs::path dir = fx_test::output_path("public_headers");
    fs::create_directories(dir);
    const fs::path file = dir / "friendly.hpp";
    std::ofstream(file) << "// a friend of nobody\n#pragma once\nnamespace cellfx::fx {\nclass A {\n"
                           "    const char* word = \"friend\";\n    friend struct Access;\n};\n} // namespace cellfx::fx\n";
    CHECK(friends_in({file, "friendly.hpp"}) == std::vector<std::string>{"friendly.hpp:6"});
}
