// `cellfx bench NAME`: benchmarks that print figures. Each one verifies the frames it times.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "fx/error.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

int run_bench(const std::vector<std::string>& args) {
    if (args.empty() || args[0] == "--help") {
        std::puts("usage: cellfx bench NAME [options]\n"
                  "  scanline   CPU scan-line renderer on a synthetic nine-grid data set (Wilhelms et al. Table 3)\n"
                  "             options: --size WxH (512x512), --repeat N (3), --scale S (1.0),\n"
                  "             --threads LIST (1,2: thread counts, speed-up against the first)\n"
                  "  pcp        GPU cell projection (pcp, pcp-exact, mip) on the blunt fin and a hex grid\n"
                  "             options: --sizes 512,1024, --repeat N (5), --grid N (100: 1M cells), --mesh XYZ --q Q\n"
                  "  sort       visibility sorts (centroid, mpvo, xmpvo, power) on ~1M tetrahedra\n"
                  "             options: --cells N (1000000), --views N (8), --repeat N (5),\n"
                  "                      --mesh all|grid|jittered|c-shape (all)\n"
                  "  terrain    continuous LOD along a flight (1025², 2049²), pixels changed vs full resolution,\n"
                  "             fog valley fps per path; options: --sizes 1025,2049, --lod-frames N (300),\n"
                  "             --views N (3), --frames N (5), --size WxH (1024x768), --skip-lod, --skip-pixels, --skip-fps\n"
                  "  absorption absorption / absorption-exact paths for every sort: blunt fin, ~1M tetrahedra, SPX\n"
                  "             options: --size WxH (256x256), --frames N (5), --cells N (1000000), --sort A,B,\n"
                  "             --scenes spx,blunt-fin,box, --blunt-fin DIR, --spx FILE\n"
                  "  effects    shipped effect scenes (campfire, searchlight, laser, fog_valley, aurora, fog_valley_night)\n"
                  "             per render path: ms/frame, GPU ms per stage, verified against the scan-line reference, then\n"
                  "             cellfx's CPU per game frame apart from the GL driver's; options: --scenes a,b, --paths a,b,\n"
                  "             --frames N (8; 60 with --only-cpu), --size WxH, --skip-verify, --only-cpu, --gl-calls,\n"
                  "             --fx-scale 1,0.5,0.25 (a row per effects' resolution), --medium froxel|exact, --json FILE\n"
                  "  flicker    frame-to-frame change along depth edges at each fx scale, along the night valley's\n"
                  "             flight; options: --scene FILE, --frames N (60), --time T, --size WxH,\n"
                  "             --fx-scale 1,0.5,0.25, --medium froxel|exact, --disable a,b, --json FILE\n"
                  "  render     every path on an orbit around any mesh (FILE [Q_FILE]): ms/frame, cells/s, CPU and\n"
                  "             GPU ms, bytes per cell, each frame checked against the scan-line renderer; options:\n"
                  "             --paths a,b, --views N (8), --size WxH (512x512), --up x|y|z, --sort a,b, --scalar,\n"
                  "             --tf, --density, --threads, --json FILE, --images DIR (see 'cellfx bench render --help')\n"
                  "  accuracy   every path and flavour against the 4x4 scan-line reference: ms per frame, RMSE, max, PSNR;\n"
                  "             writes CSV, Markdown and a plot; options: --out DIR (out/accuracy), --frames N (5),\n"
                  "             --quick, --scenes blunt-fin,fem,fog-above,fog-inside,campfire,searchlight,night-valley,\n"
                  "             fog-valley-scales, --fem-cells N (1000000),\n"
                  "             --blunt-fin DIR, --images (every flavour's frame as PNG)\n"
                  "  noise      fx::Noise, one call per sample and batch fills, per instruction set: M samples/s;\n"
                  "             options: --rounds N (9), --size N (64: 64^3 samples), --isa all|avx2|baseline");
        return args.empty() ? 2 : 0;
    }
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (args[0] == "scanline") return bench_scanline(rest);
    if (args[0] == "pcp") return bench_pcp(rest);
    if (args[0] == "sort") return bench_sort(rest);
    if (args[0] == "terrain") return bench_terrain(rest);
    if (args[0] == "absorption") return bench_absorption(rest);
    if (args[0] == "effects") return bench_effects(rest);
    if (args[0] == "accuracy") return bench_accuracy(rest);
    if (args[0] == "flicker") return bench_flicker(rest);
    if (args[0] == "render") return bench_render(rest);
    if (args[0] == "noise") return bench_noise(rest);
    throw fx::Error("unknown benchmark '" + args[0] +
                    "' (expected scanline, pcp, sort, terrain, absorption, effects, accuracy, flicker, render or noise)");
}

} // namespace cellfx_cli
