// cellfx — command line: info, render, convert, bench.
#include <cstdio>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "options.hpp"
#include "fx/resource_limits.hpp"
#include "cellfx_names.hpp"

namespace {

void usage() {
    std::puts(
        "usage: cellfx <command> [options]\n"
        "  info FILE [Q_FILE]      mesh summary: cells by type, blocks, bounds, scalars, validation\n"
        "  render FILE [options]   render a mesh to PNG or PFM (see 'cellfx render --help')\n"
        "  convert FILE --out F.vtk  write a mesh as VTK legacy, for other tools (see 'cellfx convert --help')\n"
        "  bench NAME [options]    benchmarks (see 'cellfx bench --help')\n"
        "  limits                  the resource limits in force and every numeric option's range\n"
        "any command takes --limit NAME=N (repeatable) to change a resource limit, e.g.\n"
        "  cellfx render big.vtk --limit mesh-cells=100000000 --out big.png");
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
        usage();
        return argc < 2 ? 2 : 0;
    }
    const std::string command = argv[1];
    try {
        // --limit NAME=N, anywhere after the command: the budget every input is checked against.
        std::vector<std::string> args;
        fx::ResourceLimits limits = fx::resource_limits();
        for (int i = 2; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--limit" || a.rfind("--limit=", 0) == 0) {
                if (a == "--limit" && i + 1 >= argc) throw std::runtime_error("--limit needs NAME=N");
                fx::apply_limit(limits, a == "--limit" ? argv[++i] : a.substr(8));
            } else {
                args.push_back(a);
            }
        }
        fx::set_resource_limits(limits);
        if (command == "info") return cellfx_cli::run_info(args);
        if (command == "render") return cellfx_cli::run_render(args);
        if (command == "bench") return cellfx_cli::run_bench(args);
        if (command == "convert") return cellfx_cli::run_convert(args);
        if (command == "limits") {
            std::printf("resource limits (change with --limit NAME=N):\n%s", fx::describe_limits(limits).c_str());
            std::printf("\noption ranges (checked before a command reads or allocates anything):\n%s",
                        cellfx_cli::describe_numeric_options().c_str());
            return 0;
        }
        std::fprintf(stderr, "cellfx: unknown command '%s' (expected info, render, convert, bench or limits)\n",
                     command.c_str());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr,
                     "cellfx %s: out of memory: the input needs more memory than this machine gives the process "
                     "(the resource limits, `cellfx limits`, stop larger inputs before they allocate)\n",
                     command.c_str());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "cellfx %s: %s\n", command.c_str(), e.what());
        return 1;
    }
}
