// The cellfx subcommands. Each takes the arguments after its name and returns the exit status;
// errors are thrown as exceptions and printed by main() on one line.
#pragma once

#include <string>
#include <vector>

namespace cellfx_cli {

int run_info(const std::vector<std::string>& args);
int run_render(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_convert(const std::vector<std::string>& args);

} // namespace cellfx_cli

namespace cellfx_cli {

// `cellfx bench scanline`: the synthetic nine-grid data set of Wilhelms et al. Table 3.
int bench_scanline(const std::vector<std::string>& args);
// `cellfx bench pcp`: cells per second of the GPU cell-projection paths (Roettger & Ertl §4).
int bench_pcp(const std::vector<std::string>& args);
// `cellfx bench terrain`: continuous LOD, pixels changed, fog valley fps (Roettger et al. 1998, §5).
int bench_terrain(const std::vector<std::string>& args);
// `cellfx bench absorption`: the absorption paths for every sort (Max, Williams & Silva 2000).
int bench_absorption(const std::vector<std::string>& args);

// `cellfx bench effects`: the shipped effect scenes per render path, GPU-timed per stage, verified.
int bench_effects(const std::vector<std::string>& args);
// `cellfx bench accuracy`: every path and flavour, ms per frame against error (CSV, Markdown, plot).
int bench_accuracy(const std::vector<std::string>& args);
// `cellfx bench flicker`: frame-to-frame change along depth edges at each fx scale, along a flight.
int bench_flicker(const std::vector<std::string>& args);

// `cellfx bench render`: every path on an orbit around a user's mesh, checked, for peers to rerun.
int bench_render(const std::vector<std::string>& args);

// `cellfx bench sort`: the visibility sorts on ~1M tetrahedra (Max, Williams & Silva §III).
int bench_sort(const std::vector<std::string>& args);

// `cellfx bench noise`: fx::Noise one call per sample and in batch fills, per instruction set.
int bench_noise(const std::vector<std::string>& args);

} // namespace cellfx_cli
