// cellfx samples — writing a file whole or not at all (the panel's saved scene).
#pragma once

#include <string>
#include <string_view>

namespace cellfx_samples {

// Writes `bytes` as the whole of `path`: into a temporary file in the same folder, checked
// through the final flush and close, then renamed over `path`. Throws fx::Error naming `path`
// and the system's reason; a failure leaves an existing `path` as it was and no temporary.
// (The one place the samples write a file of their own: cellfx's own atomic writer takes its
// place once the libraries have one.)
void write_whole_file(const std::string& path, std::string_view bytes);

} // namespace cellfx_samples
