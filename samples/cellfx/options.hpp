// Small helpers shared by the cellfx subcommands for reading "--key value" options.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "cellfx_names.hpp"
#include "fx/medium.hpp"

namespace cellfx_cli {

// Splits arguments into positional ones and "--key value" / "--flag" options. `flags` lists
// the options that take no value. Unknown keys are the caller's to reject.
struct ParsedArgs {
    std::vector<std::string> positional;
    std::vector<std::pair<std::string, std::string>> options; // key without "--", value
    bool has(const std::string& key) const;
    std::string get(const std::string& key, const std::string& fallback = "") const;
};
ParsedArgs parse_args(const std::vector<std::string>& args, const std::vector<std::string>& flags);
// Throws fx::Error naming the option unless every key is in `known`.
void require_known(const ParsedArgs& parsed, const std::vector<std::string>& known);

double parse_double(const std::string& text, const std::string& what);
int parse_int(const std::string& text, const std::string& what);
// "WxH", each in 1..16384 and width × height within the image-pixels limit.
void parse_size(const std::string& text, int& width, int& height);
// --fx-scale: "1", "0.5" (or "1/2"), "0.25" (or "1/4").
double parse_fx_scale(const std::string& text);
// --medium: "froxel" or "exact".
fx::MediumMethod parse_medium_option(const std::string& text);

// ---- numeric options ------------------------------------------------------------------------
// Every numeric option of every subcommand has a documented range, in ONE table (options.cpp):
// the functions below read an option through it — so it is checked before the command reads
// or allocates anything — and `cellfx limits` prints it. A count of cells is bounded by the
// mesh-cells limit in force as well (raised with --limit), an image by image-pixels.

// The table as `cellfx limits` prints it.
std::string describe_numeric_options();

// --NAME of `command` from `parsed` (`fallback` when absent), checked against its range; an
// error names the command, the option, the value and the range.
int int_option(const ParsedArgs& parsed, const char* command, const char* name, int fallback);
double number_option(const ParsedArgs& parsed, const char* command, const char* name, double fallback);
std::vector<int> int_list_option(const ParsedArgs& parsed, const char* command, const char* name,
                                 const std::string& fallback);
// A comma-separated list ("fire,beam"), empty items dropped.
std::vector<std::string> split_list(const std::string& list);
glm::dvec3 parse_vec3(const std::string& text, const std::string& what);
// --NAME FILE, a file to write (empty when absent and not `required`): checked now, before
// the command's work — a folder, a missing or read-only folder and a name without one of
// `extensions` (".png"; any when empty) are errors naming the option and the file.
std::string output_file_option(const ParsedArgs& parsed, const std::string& name,
                               const std::vector<std::string>& extensions, bool required);
// "R,G,B" with every component in [0, 1].
glm::dvec3 parse_colour(const std::string& text, const std::string& what);
// "60", "0.5", "1e-06": a number as a user would write it.
std::string format_number(double v);
// True when `path` ends in `extension` ("scene.JSON" ends in ".json": case is ignored).
bool has_extension(const std::string& path, const std::string& extension);

} // namespace cellfx_cli
