// cellfx — the GPU render paths by name (fx::CellRenderer draws them; cell_renderer.hpp says
// what each does). A value header: scenes, options and tools that only name a path include
// this, not the renderer.
#pragma once

#include <string_view>

namespace cellfx::fx {

enum class RenderPath { Pcp, PcpExact, Mip, Absorption, AbsorptionExact };
// Every path, in the order tools list them (the CLI offers each under render_path_name()).
inline constexpr RenderPath kRenderPaths[] = {RenderPath::Pcp, RenderPath::PcpExact, RenderPath::Mip,
                                              RenderPath::Absorption, RenderPath::AbsorptionExact};
// "pcp", "pcp-exact", "mip", "absorption", "absorption-exact"
const char* render_path_name(RenderPath path);
// Parses a name given by render_path_name(); false for anything else.
bool parse_render_path(std::string_view name, RenderPath& path);

} // namespace cellfx::fx
