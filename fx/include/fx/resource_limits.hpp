// cellfx — resource budgets: how much one input may make cellfx read, allocate or build.
//
// cellfx reads files from strangers. Every reader, renderer and scene loader checks what an
// input asks for against these limits BEFORE it allocates, and an input over a limit is an
// fx::Error that names the input, the amount, the limit and how to raise it:
//     big.vtk: line 5: POINTS needs 40,000,000 points, over the mesh-points limit of
//     16,777,216 (raise it with --limit mesh-points=N or fx::ResourceLimits::mesh_points)
// The defaults are sized for a machine with 8 GB (docs/robustness.md has the table: input
// class, limit, what happens). A program that needs more raises the
// limits once, before it reads or renders anything:
//     fx::ResourceLimits limits = fx::resource_limits();
//     limits.mesh_cells = 100'000'000;
//     fx::set_resource_limits(limits);
// The `cellfx` command line does the same with `--limit NAME=N` (any command, repeatable).
//
// The limits are one process-wide setting: set them before use (reading them is thread-safe,
// changing them while another thread reads or renders applies to that thread's next check).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace cellfx::fx {

struct ResourceLimits {
    std::uint64_t file_bytes = std::uint64_t(2) << 30;  // one mesh, q or height-map file
    std::uint64_t json_bytes = std::uint64_t(64) << 20; // one scene or transfer-function file
    std::uint64_t input_wait_seconds = 10;              // a pipe or device silent this long is an error
    std::uint64_t mesh_points = std::uint64_t(1) << 24; // points of one mesh (read, built or rendered)
    std::uint64_t mesh_cells = std::uint64_t(1) << 24;  // cells of one mesh
    std::uint64_t image_pixels = std::uint64_t(1) << 26; // width × height of one rendered image (8192²)
    std::uint64_t frame_bytes = std::uint64_t(2) << 30; // scan-line working memory of one frame
    std::uint64_t sort_pairs = 64;                      // xmpvo: boundary-face pairs tested per boundary triangle
    std::uint64_t effects = 256;                        // effects in one scene
    std::uint64_t effect_cells = std::uint64_t(1) << 21; // cells one effect may build
    std::uint64_t scene_cells = std::uint64_t(1) << 23; // cells all of a scene's effects may build together
    std::uint64_t height_samples = 4097ull * 4097ull;   // samples of one height field (terrain, fog map, aurora)
};

// The limits, by name (the `--limit` names), in the order of ResourceLimits.
enum class Limit {
    FileBytes,
    JsonBytes,
    InputWaitSeconds,
    MeshPoints,
    MeshCells,
    ImagePixels,
    FrameBytes,
    SortPairs,
    Effects,
    EffectCells,
    SceneCells,
    HeightSamples,
};
constexpr int kLimitCount = 12;

const char* limit_name(Limit limit);  // "file-bytes", "mesh-cells", ...
const char* limit_unit(Limit limit);  // "bytes", "cells", ...
const char* limit_field(Limit limit); // "file_bytes", "mesh_cells", ... (the ResourceLimits member)
std::uint64_t limit_value(const ResourceLimits& limits, Limit limit);

// The limits in force (a copy), and setting them for the whole process.
ResourceLimits resource_limits();
void set_resource_limits(const ResourceLimits& limits);

// Applies "NAME=N" (N a non-negative integer, 1e9 allowed) to `limits`. Throws fx::Error
// naming the unknown limit or the bad number.
void apply_limit(ResourceLimits& limits, std::string_view assignment);
// One line per limit: name, value, unit and what it bounds (for --help).
std::string describe_limits(const ResourceLimits& limits);

// True when `amount` is over the limit in force.
bool exceeds(Limit limit, std::uint64_t amount);
// "<what> needs 40,000,000 points, over the mesh-points limit of 16,777,216 (raise it with
// --limit mesh-points=N or fx::ResourceLimits::mesh_points)".
std::string over_limit(Limit limit, std::uint64_t amount, const std::string& what);
// Throws fx::Error(over_limit(...)) when `amount` is over the limit in force. `what` starts
// with the input's name and place ("big.vtk: line 5: POINTS").
void check_limit(Limit limit, std::uint64_t amount, const std::string& what);

// "37,479": counts in messages.
std::string with_commas(std::uint64_t n);

} // namespace cellfx::fx
