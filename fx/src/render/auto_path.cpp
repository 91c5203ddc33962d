// `auto`: the candidates, their stated errors, measuring their costs and the choice
// (fx/auto_path.hpp; docs/render_paths.md, "auto").
#include "fx/auto_path.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "fx/error.hpp"

namespace cellfx::fx {

const char* candidate_name(const AutoCandidate& candidate) {
    return candidate.scanline ? "scanline" : render_path_name(candidate.gl);
}

void check_accuracy(double accuracy, const std::string& option) {
    if (!(accuracy >= kMinAccuracy && accuracy <= kMaxAccuracy)) {
        char text[160];
        std::snprintf(text, sizeof text, "%s: accuracy %g is out of range: the accepted mean error per pixel, a share of the "
                      "picture's peak, in [%g, %g]", option.c_str(), accuracy, kMinAccuracy, kMaxAccuracy);
        throw Error(text);
    }
}

// The mean bounds of testing/verify/tolerances.cpp (verify::stated(path, case).mean.of_peak),
// where each is derived; tests/test_auto_path.cpp checks that the two agree.
double stated_mean_error(const AutoCandidate& candidate, bool near_plane_cuts) {
    if (candidate.scanline) return 1e-5; // double segments: its own float image and pixel positions
    switch (candidate.gl) {
    case RenderPath::PcpExact:
    case RenderPath::Mip: return near_plane_cuts ? 0.002 : 0.0005;
    case RenderPath::AbsorptionExact: return near_plane_cuts ? 0.0015 : 0.0005;
    case RenderPath::Absorption: return near_plane_cuts ? 0.04 : 0.004; // cut: docs/accuracy.md, measured to 3.6%
    case RenderPath::Pcp: return 0.0212; // 2% for the trapezoid rule + 0.3/255 of 8-bit rounding, a peak of 1
    }
    return 1.0;
}

bool near_plane_cuts(const Camera& camera, const Bounds& bounds) {
    if (bounds.empty()) return false;
    const glm::dvec3 forward = camera.forward();
    bool before = false, beyond = false;
    for (int k = 0; k < 8; ++k) {
        const double depth = glm::dot(bounds.corner(k) - camera.eye, forward);
        (depth < camera.near_distance ? before : beyond) = true;
    }
    return before && beyond;
}

std::vector<AutoCandidate> auto_candidates(OpticalModel model, bool with_gl) {
    std::vector<AutoCandidate> out{kScanlineCandidate};
    if (!with_gl) return out;
    switch (model) {
    case OpticalModel::EmissionAbsorption:
        out.push_back(gl_candidate(RenderPath::AbsorptionExact));
        out.push_back(gl_candidate(RenderPath::Absorption));
        break;
    case OpticalModel::Emission: out.push_back(gl_candidate(RenderPath::PcpExact)); break;
    case OpticalModel::Maximum: out.push_back(gl_candidate(RenderPath::Mip)); break;
    }
    return out;
}

PathChoice choose_path(const std::vector<PathCost>& costs, double accuracy, int width, int height, const std::string& option) {
    check_accuracy(accuracy, option);
    if (width <= 0 || height <= 0) throw Error(option + ": no frame to choose a path for (" + std::to_string(width) + "x" +
                                               std::to_string(height) + ")");
    const long long pixels = (long long)width * height;
    char text[200];
    const PathCost* best = nullptr;
    std::string meeting, out; // the candidates compared, and those left out (over the accuracy, not measured)
    for (const PathCost& c : costs) {
        if (!(c.stated_error <= accuracy)) {
            std::snprintf(text, sizeof text, "%s states %g", candidate_name(c.candidate), c.stated_error);
            out += (out.empty() ? "" : ", ") + std::string(text);
            continue;
        }
        const double ms = c.frame_ms(pixels);
        if (!std::isfinite(ms) || ms < 0.0) { // never measured: it cannot be shown to be faster
            out += (out.empty() ? "" : ", ") + std::string(candidate_name(c.candidate)) + " not measured";
            continue;
        }
        std::snprintf(text, sizeof text, "%s %.3g ms", candidate_name(c.candidate), ms);
        meeting += (meeting.empty() ? "" : ", ") + std::string(text);
        // Strictly cheaper, or as cheap and more accurate; the first of equals stays.
        if (!best || ms < best->frame_ms(pixels) ||
            (ms == best->frame_ms(pixels) && c.stated_error < best->stated_error))
            best = &c;
    }
    std::snprintf(text, sizeof text, "accuracy %g", accuracy);
    if (!best) {
        if (costs.empty()) throw Error(option + ": no render path to choose from");
        throw Error(option + ": no render path meets " + text + " (mean error per pixel, share of peak): " + out +
                    "; accept a larger error or name a path");
    }
    PathChoice choice;
    choice.candidate = best->candidate;
    choice.frame_ms = best->frame_ms(pixels);
    choice.stated_error = best->stated_error;
    std::snprintf(text, sizeof text, "auto picked %s: %.3g ms predicted for %dx%d, stated error %g <= accuracy %g",
                  candidate_name(best->candidate), choice.frame_ms, width, height, best->stated_error, accuracy);
    choice.reason = std::string(text) + " (measured: " + meeting + ")";
    if (!out.empty()) choice.reason += "; left out: " + out;
    return choice;
}

namespace {

double milliseconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The wall time of one frame of `candidate` at w × h (GL: render_to_image waits for the frame).
double time_frame(const CalibrationFrame& frame, const AutoCandidate& candidate, CellRenderer* gl,
                  const ScanlineRenderer* scanline, int w, int h) {
    const auto start = std::chrono::steady_clock::now();
    if (candidate.scanline) {
        ScanlineOptions options;
        options.model = frame.model;
        options.threads = frame.threads;
        static_cast<void>(scanline->render(frame.camera, w, h, *frame.field, *frame.tf, options));
    } else {
        CellRenderOptions options;
        options.sort = frame.sort;
        static_cast<void>(gl->render_to_image(frame.camera, w, h, candidate.gl, options));
    }
    return milliseconds_since(start);
}

} // namespace

std::vector<PathCost> measure_path_costs(const CalibrationFrame& frame, const std::vector<AutoCandidate>& candidates,
                                         double accuracy, CellRenderer* gl, const ScanlineRenderer* scanline) {
    if (!frame.mesh || !frame.field || !frame.tf || frame.width <= 0 || frame.height <= 0)
        throw Error("auto: measure_path_costs needs a mesh, a field, a transfer function and a frame size");
    const bool cuts = near_plane_cuts(frame.camera, mesh_bounds(*frame.mesh));
    // A quarter and half of each side (at least 8 pixels): 1/16 and 1/4 of the frame's pixels.
    const int w1 = std::max(8, frame.width / 4), h1 = std::max(8, frame.height / 4);
    const int w2 = std::max(w1 + 8, frame.width / 2), h2 = std::max(h1 + 8, frame.height / 2);
    const double p1 = double(w1) * h1, p2 = double(w2) * h2;
    std::vector<PathCost> costs;
    for (const AutoCandidate& candidate : candidates) {
        PathCost cost;
        cost.candidate = candidate;
        cost.stated_error = stated_mean_error(candidate, cuts);
        if (!(cost.stated_error <= accuracy)) { // out whatever it costs
            cost.fixed_ms = cost.ms_per_pixel = std::nan("");
            costs.push_back(cost);
            continue;
        }
        if (candidate.scanline ? !scanline : !gl)
            throw Error(std::string("auto: no renderer given for the candidate ") + candidate_name(candidate));
        static_cast<void>(time_frame(frame, candidate, gl, scanline, 8, 8)); // programs, sort state, buffers
        // The quicker of two frames at each size: other work on the machine only ever adds time.
        const double t1 = std::min(time_frame(frame, candidate, gl, scanline, w1, h1),
                                   time_frame(frame, candidate, gl, scanline, w1, h1));
        const double t2 = std::min(time_frame(frame, candidate, gl, scanline, w2, h2),
                                   time_frame(frame, candidate, gl, scanline, w2, h2));
        // A noisy machine can make the larger frame the quicker: no negative per-pixel cost.
        cost.ms_per_pixel = std::max(0.0, (t2 - t1) / (p2 - p1));
        cost.fixed_ms = std::max(0.0, t1 - cost.ms_per_pixel * p1);
        costs.push_back(cost);
    }
    return costs;
}

} // namespace cellfx::fx
