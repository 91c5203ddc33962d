// `cellfx bench ... --json FILE`: the figures of a bench as {"scenes": [row, ...]}, one object
// per scene and configuration, keys in the order each bench adds them. One writer for every
// bench row so that rows of several kinds can share one file.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cellfx_cli {

using BenchJsonRow = nlohmann::ordered_json;

// Writes {"scenes": rows} to `path` (through a temporary file renamed into place, so a reader
// never sees half a file). Throws fx::Error naming the file when it cannot be written.
void write_scenes_json(const std::string& path, const std::vector<BenchJsonRow>& rows);

} // namespace cellfx_cli
