// The cellfx subcommands. Each takes the arguments after its name and returns the exit status;
// errors are thrown as exceptions and printed by main() on one line.
#pragma once

#include <string>
#include <vector>

namespace cellfx_cli {

int run_info(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);

} // namespace cellfx_cli
