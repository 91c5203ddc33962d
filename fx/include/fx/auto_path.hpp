// cellfx — `auto`: the fastest render path that meets a requested accuracy on this machine.
//
// Which path is fastest depends on the machine more than on the mesh: on a software rasteriser
// (Mesa's llvmpipe: CI, CPU-only cluster nodes) the CPU scan-line renderer draws the exact
// picture about 10× faster than any GL path (docs/accuracy.md), on a GPU the GL paths win. So
// `auto` measures instead of guessing, with one rule (docs/render_paths.md, "auto"):
//
//   1. The candidates are the paths that compute the requested optical model: the scan-line
//      renderer, and for emission–absorption absorption-exact and absorption, for emission
//      pcp-exact, for the maximum mip. A candidate whose stated mean error (below) is over the
//      accepted error is dropped unmeasured.
//   2. Each remaining candidate draws one warm-up frame (programs, sort state), then two frames
//      at a quarter and two at half the image's width and height; the quicker of each pair (other
//      work on the machine only adds time) give its cost as fixed + per-pixel milliseconds
//      (PathCost), predicted for the whole image. That is about 0.6 of a frame per candidate,
//      on the actual mesh, view and renderer.
//   3. The candidate with the least predicted time wins (ties: the smaller stated error, then
//      the candidates' order), and PathChoice::reason says what each one cost or why it was out.
//
// The accepted error ("accuracy") is the mean |difference| per pixel from the exact picture,
// as a share of the picture's peak: what `verify::stated` calls a path's mean bound
// (testing/verify/tolerances.cpp derives each; stated_mean_error() repeats them, and a test
// keeps the two equal). Default 1e-3: the exact flavours (5e-4) and the scan-line renderer
// (1e-5) qualify, classic absorption (4e-3) does not.
//
// choose_path() is pure: given the costs it always picks the same path (the tests inject cost
// tables). measure_path_costs() runs the frames; its GL candidates need the CellRenderer's
// context current, and it restores every GL state it changes as render_to_image() does.
#pragma once

#include <string>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "fx/visibility_sort.hpp"

namespace cellfx::fx {

// A path auto may pick: the CPU scan-line renderer or one of CellRenderer's GL paths.
struct AutoCandidate {
    bool scanline = true;
    RenderPath gl = RenderPath::AbsorptionExact; // the GL path when !scanline
    bool operator==(const AutoCandidate& o) const { return scanline == o.scanline && (scanline || gl == o.gl); }
};
inline constexpr AutoCandidate kScanlineCandidate{true, RenderPath::AbsorptionExact};
inline constexpr AutoCandidate gl_candidate(RenderPath path) { return {false, path}; }
// "scanline" or render_path_name(gl).
const char* candidate_name(const AutoCandidate& candidate);

// The accepted error's range and default (mean |difference| per pixel, share of peak).
inline constexpr double kDefaultAccuracy = 1e-3;
inline constexpr double kMinAccuracy = 1e-6; // under the scan-line renderer's own 1e-5 nothing qualifies
inline constexpr double kMaxAccuracy = 1.0;
// Throws fx::Error naming `option` ("--accuracy", "CellfxAccuracy") for a value outside
// [kMinAccuracy, kMaxAccuracy] or not finite.
void check_accuracy(double accuracy, const std::string& option);

// The candidate's stated mean error, share of peak, for its own optical model; with
// `near_plane_cuts` (the near plane cuts the mesh) the larger figures the paths state then.
// Classic absorption with cells at the eye cannot meet its tolerance (docs/accuracy.md: up to
// 3.6% mean), so it is stated at 0.04 there.
double stated_mean_error(const AutoCandidate& candidate, bool near_plane_cuts = false);
// True when the near plane of `camera` passes through the box `bounds` (conservative: the box,
// not the cells).
bool near_plane_cuts(const Camera& camera, const Bounds& bounds);

// The candidates that compute `model`, scan-line first; `with_gl` false leaves the GL paths
// out (no GL context).
std::vector<AutoCandidate> auto_candidates(OpticalModel model, bool with_gl = true);

// What one candidate costs on this machine: fixed_ms + ms_per_pixel · pixels a frame.
struct PathCost {
    AutoCandidate candidate;
    double stated_error = 0.0;  // stated_mean_error() for the frame's case
    double fixed_ms = 0.0;      // per frame, whatever its size (per-cell work, set-up)
    double ms_per_pixel = 0.0;  // per pixel of the frame
    double frame_ms(long long pixels) const { return fixed_ms + ms_per_pixel * double(pixels); }
};

struct PathChoice {
    AutoCandidate candidate;
    double frame_ms = 0.0;      // predicted for the frame's size
    double stated_error = 0.0;
    std::string reason;         // one line: the pick, what it beat and what was out
};

// The cheapest candidate of `costs` whose stated error is ≤ `accuracy`, for a frame of
// width × height. Throws fx::Error naming `option` for a bad accuracy (check_accuracy), and
// saying which paths state what when none meets it or `costs` is empty.
PathChoice choose_path(const std::vector<PathCost>& costs, double accuracy, int width, int height,
                       const std::string& option = "accuracy");

// The frame the candidates are measured on.
struct CalibrationFrame {
    const CellMesh* mesh = nullptr;
    const ScalarField* field = nullptr; // a field of *mesh
    const TransferFunction* tf = nullptr;
    Camera camera;
    int width = 0, height = 0;
    OpticalModel model = OpticalModel::EmissionAbsorption;
    unsigned threads = 0;                // scan-line workers (0: every core)
    SortMethod sort = SortMethod::Xmpvo; // absorption paths
};
// Measures each of `candidates` whose stated error is ≤ `accuracy` (above, step 2); the others
// come back with their stated error and NaN costs, unmeasured. GL candidates draw through `gl`
// (its context current; nullptr: none may be given), the scan-line one through `scanline`
// (built on frame.mesh). Returns the costs in the candidates' order. Throws what the renderers
// throw.
std::vector<PathCost> measure_path_costs(const CalibrationFrame& frame, const std::vector<AutoCandidate>& candidates,
                                         double accuracy, CellRenderer* gl, const ScanlineRenderer* scanline);

} // namespace cellfx::fx
