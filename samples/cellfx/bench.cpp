// `cellfx bench NAME`: benchmarks that print figures. Each one verifies the frames it times.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fx/error.hpp"

namespace cellfx_cli {

int run_bench(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help") {
        std::puts("usage: cellfx bench NAME [options]\n"
                  "  scanline   CPU scan-line renderer on a synthetic nine-grid data set (Wilhelms et al. Table 3)\n"
                  "             options: --size WxH (512x512), --repeat N (3), --scale S (1.0),\n"
                  "             --threads LIST (1,2: thread counts, speed-up against the first)");
        return args.empty() ? 2 : 0;
    }
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (args[0] == "scanline") return bench_scanline(rest);
    throw fx::Error("unknown benchmark '" + args[0] + "' (expected scanline)");
}

} // namespace cellfx_cli
