// cellfx — command line: info, render, convert, bench.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "commands.hpp"

namespace {

void usage() {
    std::puts(
        "usage: cellfx <command> [options]\n"
        "  info FILE [Q_FILE]      mesh summary: cells by type, blocks, bounds, scalars, validation\n"
        "  render FILE [options]   render a mesh to PNG or PFM (see 'cellfx render --help')\n"
        "  convert FILE --out F.vtk  write a mesh as VTK legacy, for other tools (see 'cellfx convert --help')\n"
        "  bench NAME [options]    benchmarks (see 'cellfx bench --help')");
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
        usage();
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    try {
        if (command == "info") return cellfx_cli::run_info(args);
        if (command == "render") return cellfx_cli::run_render(args);
        if (command == "bench") return cellfx_cli::run_bench(args);
        if (command == "convert") return cellfx_cli::run_convert(args);
        std::fprintf(stderr, "cellfx: unknown command '%s' (expected info, render, convert or bench)\n", command.c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cellfx %s: %s\n", command.c_str(), e.what());
        return 1;
    }
}
