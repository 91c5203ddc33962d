// cellfx_verify — each render path's stated tolerance against an independent reference, in one
// table (tolerances.cpp), each number with where it comes from. Frame tests and benches take
// their bounds from here; a test that needs a different bound says why where it changes one.
//
// Each path is compared with the reference of its own optical model: emission for pcp and
// pcp-exact, maximum for mip, emission–absorption for the fog flavour and both absorption paths
// (model_of). docs/accuracy.md ("Tolerances") prints the table; the measured errors are in the
// docs of each path (render_paths.md, absorption.md, effects.md) and printed by the tests.
#pragma once

#include <string>

#include "fx/cell_renderer.hpp"
#include "fx/scanline_renderer.hpp"
#include "verify/image_difference.hpp"

namespace cellfx::verify {

enum class Path { Scanline, Pcp, PcpExact, PcpExactFog, Mip, Absorption, AbsorptionExact };
inline constexpr Path kPaths[] = {Path::Scanline, Path::Pcp,        Path::PcpExact,       Path::PcpExactFog,
                                  Path::Mip,      Path::Absorption, Path::AbsorptionExact};

// "scanline", "pcp", "pcp-exact", "pcp-exact-fog", "mip", "absorption", "absorption-exact"
const char* path_name(Path path);
// The path fx::CellRenderer draws for `path` (with CellRenderOptions::fog for the fog flavour).
Path path_of(fx::RenderPath path, bool fog = false);
// The optical model `path` computes; the scan-line renderer computes `scanline_model`.
fx::OpticalModel model_of(Path path, fx::OpticalModel scanline_model = fx::OpticalModel::EmissionAbsorption);

// What a frame holds that a path's tolerance depends on.
struct Case {
    int cells_on_ray = 1;          // the most cells a pixel's ray crosses (classic pcp's rounding)
    double kappa_share = 0.15;     // classic pcp: how much of a pixel the trapezoid rule on κ may be
                                   // off — 0.15 where kinks of the transfer function fall inside
                                   // cells; more where one cell spans the whole function (a test
                                   // that sets it says why)
    bool near_plane_cuts = false;  // the near plane cuts cells whose scalar varies inside them
    bool problem_cells = false;    // absorption: non-planar cells cut into tetrahedra
};

// The stated tolerance of `path` for a frame like `c`, its derivation in Tolerance::why.
Tolerance stated(Path path, const Case& c = {});

// Two pictures of one computation made two ways (tiles and the whole frame, a hostile and a calm
// GL state, a window and an offscreen target): every channel within `absolute` of the other, no
// pixel beyond it. `why` says where `absolute` comes from (0: the same bits).
Tolerance same_picture(double absolute, std::string why);

} // namespace cellfx::verify
