// The stated tolerances. Every figure is a part of the reference's peak (its largest value in
// the compared channels) unless it says otherwise. Each path has a per-pixel bound; where the
// reference changes by more than that bound across a pixel's 3×3 neighbourhood (an outline, a
// step of the transfer function, a cell the near plane cuts) a pixel centre within rounding of
// the change may go to either side, so such a pixel may lie beyond the bound — but only within
// it of the range of values the reference takes around it (image_difference.hpp). Away from any
// edge, "beyond" is the share of pixels a path's own approximation may put past the bound,
// under the same rule. No path may leave a pixel outside that range (a bounded worst pixel for
// every path), except classic pcp, whose trapezoid rule bounds a pixel by its 8-bit range only.
#include "verify/tolerances.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cellfx::verify {

const char* path_name(Path path) {
    switch (path) {
    case Path::Scanline: return "scanline";
    case Path::Pcp: return "pcp";
    case Path::PcpExact: return "pcp-exact";
    case Path::PcpExactFog: return "pcp-exact-fog";
    case Path::Mip: return "mip";
    case Path::Absorption: return "absorption";
    case Path::AbsorptionExact: return "absorption-exact";
    }
    return "?";
}

Path path_of(fx::RenderPath path, bool fog) {
    switch (path) {
    case fx::RenderPath::Pcp: return Path::Pcp;
    case fx::RenderPath::PcpExact: return fog ? Path::PcpExactFog : Path::PcpExact;
    case fx::RenderPath::Mip: return Path::Mip;
    case fx::RenderPath::Absorption: return Path::Absorption;
    case fx::RenderPath::AbsorptionExact: return Path::AbsorptionExact;
    }
    return Path::PcpExact;
}

fx::OpticalModel model_of(Path path, fx::OpticalModel scanline_model) {
    switch (path) {
    case Path::Pcp:
    case Path::PcpExact: return fx::OpticalModel::Emission;
    case Path::Mip: return fx::OpticalModel::Maximum;
    case Path::Scanline: return scanline_model;
    default: return fx::OpticalModel::EmissionAbsorption;
    }
}

Tolerance stated(Path path, const Case& c) {
    const double n = std::max(c.cells_on_ray, 1);
    Tolerance t;
    t.share_beyond = 0.01;
    switch (path) {
    case Path::Scanline:
        // Against closed forms. Segments are integrated in double; what is left is the float
        // image (values near 1 carry ~6e-8) and float screen positions of pixel centres within
        // ~1e-9 px of an edge. 1e-4 per pixel, mean 1e-5: a wrong thickness, a missed crossing or
        // a wrong interpolation shows at > 1e-3 (tests/test_scanline.cpp).
        t.pixel.of_peak = 1e-4, t.mean.of_peak = 1e-5;
        t.why = "scan-line: double segments, float image and screen positions";
        break;
    case Path::PcpExact:
    case Path::PcpExactFog:
    case Path::Mip:
        // Both sides integrate each segment exactly. The GPU sums float32 segments (~1e-6 of a
        // pixel over tens of cells) and reads the emission table at 4096 samples of the scalar
        // range: linear between samples, so a segment's emission is off by at most its change
        // of c·σ over one sample, 1/4095 of the transfer function's range (~0.025%). 0.5% per
        // pixel holds that with a factor of 20 for pixel centres whose chord changes fast
        // (grazing faces); mean 0.05%. Away from edges no pixel beyond.
        t.pixel.of_peak = 0.005, t.mean.of_peak = 0.0005, t.share_beyond = 0.0;
        t.why = "exact integrals: float32 sums and the 4096-sample tables";
        if (path == Path::Mip) {
            // mip takes the largest emission c·σ of the faces a ray crosses (Roettger & Ertl
            // §2): exact where c·σ is monotonic across a cell's scalar span Δs. Where c and σ
            // are both linear between transfer points, c·σ is quadratic there and can peak inside
            // the cell, above both faces by at most |c'·σ'|·Δs²/4: for transfer functions whose
            // c and σ change by at most their full value across the function's range and cells
            // spanning at most a fifth of it, ≤ 1% of the largest c·σ, the peak. Per pixel 1%.
            t.pixel.of_peak = 0.01;
            t.why = "mip: the face rule misses a peak of c·sigma inside a cell (<= |c'sigma'| ds^2/4)";
        }
        if (c.near_plane_cuts) {
            // For a cell cut by the near plane the reference interpolates the scalar on the cut
            // over a fan of its cap, the GPU linearly along the ray between the cell's faces:
            // both exact on the faces, apart inside by up to the scalar's variation over the
            // cell, which these tests keep under 3% of the peak's scalar span. Only rays that
            // start inside a cut cell can differ, and they are not silhouettes: none beyond.
            t.pixel.of_peak = 0.03, t.mean.of_peak = 0.002;
            t.why += "; near plane cuts cells: the cut's scalar interpolated over the cap's fan against along the ray";
        }
        break;
    case Path::Pcp:
        // 8 bits: each of the N cells on a ray adds its light rounded to 1/255 and its α
        // difference is quantised to 1/255 of its Δd: per pixel 0.5·N/255. Colour is κ at the
        // vertices, interpolated over the faces and averaged front/back: the trapezoid rule on
        // κ(s), off by `kappa_share` of the pixel where a kink of the transfer function falls
        // inside a cell. Mean: N independent roundings of ±0.5/255 add to ~0.29·√N/255, plus 2%
        // of peak for the trapezoid rule over the frame.
        // Worst: the trapezoid rule puts a cell's light anywhere between l·κ at its faces, so a
        // single pixel has no bound tighter than the 8-bit target's range: the few pixels beyond
        // the bound (≤ 1% away from edges) are bounded by it alone. (Measured: 37% of peak at
        // worst in the property test, 31% on the search light.)
        t.pixel.absolute = 0.5 * n / 255.0, t.pixel.relative = c.kappa_share;
        t.worst.absolute = 1.0;
        t.mean.absolute = 0.3 * std::sqrt(n) / 255.0, t.mean.of_peak = 0.02;
        t.why = "classic pcp: 8-bit rounding per cell on the ray, the trapezoid rule on kappa";
        break;
    case Path::Absorption:
        // §II's approximations: the thickness and the opacity table's coordinates are linear on
        // screen over each polygon (exact for orthographic views — 0.15% measured without GL —,
        // off by a cell's perspective foreshortening otherwise) and the polygon colour C/α is
        // interpolated between exact vertex values. A polygon spans a few pixels and its depth
        // ratio stays under ~1.1 in these frames: 4% per pixel, mean 0.4%. Where the exact
        // picture changes by more than that within one pixel (outlines, and inside cells where
        // the transfer function bends steeply, e.g. σ rising ×1.5–×5 across a breakpoint in
        // the campfire's core) a polygon's linear colour and α cannot follow it: there a pixel
        // is bounded by the reference's values around it — interpolation between exact vertex
        // values stays within the values the polygon covers — and not by the 4%.
        t.pixel.of_peak = 0.04, t.mean.of_peak = 0.004;
        t.why = "classic absorption: thickness and colour linear on screen over each polygon (§II)";
        if (c.near_plane_cuts) {
            // The cut's scalar over a fan from another corner of the cap than the reference's.
            t.pixel.of_peak += 0.02, t.mean.of_peak += 0.001;
            t.why += "; near plane cuts cells";
        }
        if (c.problem_cells) {
            // Inside a cell cut into tetrahedra the scalar is linear per tetrahedron, where the
            // reference interpolates along the ray between the cell's faces.
            t.pixel.of_peak += 0.01;
            t.why += "; non-planar cells cut into tetrahedra";
        }
        break;
    case Path::AbsorptionExact:
        // The pre-integration table holds τ exactly along the length (mean extinction σ̄ and
        // M = σ̄·colour/α, linear in the length) and is bilinear in the two end scalars at 128
        // samples: a segment is off by the change of M and σ̄ within one sample where the
        // transfer function bends inside it, 1/127 of its range, on that segment's share of
        // the pixel. float32 against double. 0.5% per pixel, mean 0.05% — pcp-exact's; away
        // from edges no pixel beyond.
        t.pixel.of_peak = 0.005, t.mean.of_peak = 0.0005, t.share_beyond = 0.0;
        t.why = "pre-integration table: exact in the length, bilinear in the scalars (128 samples)";
        if (c.near_plane_cuts) {
            t.pixel.of_peak += 0.02, t.mean.of_peak += 0.001;
            t.why += "; near plane cuts cells";
        }
        if (c.problem_cells) {
            t.pixel.of_peak += 0.01;
            t.why += "; non-planar cells cut into tetrahedra";
        }
        break;
    }
    return t;
}

Tolerance same_picture(double absolute, std::string why) {
    Tolerance t;
    t.pixel.absolute = absolute, t.mean.absolute = absolute;
    t.share_beyond = 0.0, t.outlier_radius = 0;
    t.why = std::move(why);
    return t;
}

} // namespace cellfx::verify
