// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (overlapping grids along a ray) and Max
// 1995, "Optical models for direct volume rendering" (single scattering). The CPU half of one
// medium (fx/medium.hpp): the reference the scan-line renderer integrates spans with.
#include "fx/medium.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"

namespace cellfx::fx {

namespace {

constexpr double kPi = 3.14159265358979323846;

// (1 − e^(−τ))/τ without cancellation for small τ.
double opacity_per_depth(double tau) { return tau < 1e-4 ? 1.0 - tau * (0.5 - tau / 6.0) : -std::expm1(-tau) / tau; }

// Adaptive Simpson quadrature of a vector-valued integrand.
template <class F>
glm::dvec3 simpson(const F& f, double a, double b, const glm::dvec3& fa, const glm::dvec3& fm, const glm::dvec3& fb,
                   const glm::dvec3& whole, double eps, int depth) {
    const double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    const glm::dvec3 flm = f(lm), frm = f(rm);
    const glm::dvec3 left = (m - a) / 6.0 * (fa + 4.0 * flm + fm), right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    const glm::dvec3 delta = left + right - whole;
    if (depth <= 0 || std::max({std::abs(delta.x), std::abs(delta.y), std::abs(delta.z)}) <= 15.0 * eps)
        return left + right + delta / 15.0;
    return simpson(f, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1) + simpson(f, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1);
}

template <class F>
glm::dvec3 integrate(const F& f, double a, double b) {
    const glm::dvec3 fa = f(a), fm = f(0.5 * (a + b)), fb = f(b);
    const glm::dvec3 whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    // Start from 8 panels so that a narrow peak (a point light's core) is not stepped over.
    glm::dvec3 sum(0.0);
    const glm::dvec3 scale = glm::abs(whole) + glm::dvec3(1e-300);
    const double eps = 1e-7 * std::max({scale.x, scale.y, scale.z});
    for (int i = 0; i < 8; ++i) {
        const double x0 = a + (b - a) * i / 8.0, x1 = a + (b - a) * (i + 1) / 8.0, xm = 0.5 * (x0 + x1);
        const glm::dvec3 f0 = f(x0), f1 = f(x1), fmid = f(xm);
        sum += simpson(f, x0, x1, f0, fmid, f1, (x1 - x0) / 6.0 * (f0 + 4.0 * fmid + f1), eps / 8.0, 12);
    }
    return sum;
}

// Distance² from p to the segment a + dir·t, t in [t0, t1].
double distance2_to_segment(const glm::dvec3& p, const RaySpan& span, double t0, double t1) {
    const double t = std::clamp(glm::dot(p - span.origin, span.dir), t0, t1);
    const glm::dvec3 d = span.origin + span.dir * t - p;
    return glm::dot(d, d);
}

} // namespace

const char* medium_method_name(MediumMethod method) { return method == MediumMethod::Froxel ? "froxel" : "exact"; }

bool parse_medium_method(std::string_view name, MediumMethod& method) {
    if (name == "froxel") method = MediumMethod::Froxel;
    else if (name == "exact") method = MediumMethod::Exact;
    else return false;
    return true;
}

double henyey_greenstein(double g, double mu) {
    const double d = std::max(1.0 + g * g - 2.0 * g * mu, 1e-12);
    return (1.0 - g * g) / (4.0 * kPi * d * std::sqrt(d));
}

double relative_phase(double g, double mu) { return 4.0 * kPi * henyey_greenstein(g, mu); }

glm::dvec3 MediumLight::direction_at(const glm::dvec3& x) const {
    if (apex_distance > 0.0) {
        const glm::dvec3 d = x - (origin - glm::normalize(axis) * apex_distance);
        const double l = glm::length(d);
        if (l > 0.0) return d / l;
    }
    return glm::normalize(axis);
}

double MediumLight::point_falloff(double r2) const {
    if (!(r2 < radius * radius)) return 0.0;
    const double r02 = core_radius * core_radius, u = 1.0 - r2 / (radius * radius);
    return r02 / (r02 + r2) * u * u;
}

Medium::Medium(std::vector<MediumVolume> volumes) : volumes_(std::move(volumes)) {
    for (std::size_t v = 0; v < volumes_.size(); ++v) {
        const MediumVolume& m = volumes_[v];
        if (m.tf.points().empty()) throw Error("medium: volume " + std::to_string(v) + " has a transfer function without points");
        if (m.tf.normalized())
            throw Error("medium: volume " + std::to_string(v) + "'s transfer function is normalized (rescale it to its scalars)");
        if (!(m.albedo >= 0.0 && std::isfinite(m.albedo))) throw Error("medium: volume " + std::to_string(v) + ": albedo must be ≥ 0");
        std::vector<TransferPoint> white = m.tf.points();
        for (TransferPoint& p : white) p.color = glm::dvec3(1.0);
        extinction_.emplace_back(std::move(white));
        if (m.light.kind == MediumLight::Kind::Point) point_lights_.push_back(v);
    }
}

SegmentColor Medium::integrate_span(const SpanVolume* inside, std::size_t count, const RaySpan& span) const {
    const double length = span.t_back - span.t_front;
    if (!(length > 0.0) || count == 0) return {};
    // Which lights can scatter here: beams inside the span and point lights within reach, into
    // absorbing volumes with an albedo inside the span.
    bool scatterer = false;
    for (std::size_t i = 0; i < count; ++i) {
        const MediumVolume& m = volumes_[inside[i].volume];
        scatterer = scatterer || (m.absorbs && m.albedo > 0.0);
    }
    bool lit = false;
    if (scatterer) {
        for (std::size_t i = 0; i < count && !lit; ++i) lit = volumes_[inside[i].volume].light.kind == MediumLight::Kind::Beam;
        for (std::size_t v : point_lights_) {
            const MediumLight& l = volumes_[v].light;
            lit = lit || distance2_to_segment(l.origin, span, span.t_front, span.t_back) < l.radius * l.radius;
        }
    }
    if (count == 1 && !lit) { // one medium alone: the exact segment integral
        const MediumVolume& m = volumes_[inside[0].volume];
        if (m.absorbs) return emission_absorption(m.tf, inside[0].s_front, inside[0].s_back, length);
        SegmentColor c;
        c.color = emission_integral(m.tf, inside[0].s_front, inside[0].s_back, length);
        return c;
    }

    auto scalar_at = [&](const SpanVolume& v, double t) {
        return v.s_front + (v.s_back - v.s_front) * ((t - span.t_front) / length);
    };
    // Light scattered towards the eye per unit length at t (rgb).
    auto scattered = [&](double t) {
        const glm::dvec3 x = span.origin + span.dir * t;
        glm::dvec3 sum(0.0);
        for (std::size_t i = 0; i < count; ++i) {
            const MediumVolume& m = volumes_[inside[i].volume];
            if (!(m.absorbs && m.albedo > 0.0)) continue;
            const double sigma = m.albedo * m.tf.sigma(scalar_at(inside[i], t));
            if (!(sigma > 0.0)) continue;
            for (std::size_t k = 0; k < count; ++k) {
                const MediumLight& l = volumes_[inside[k].volume].light;
                if (k == i || l.kind != MediumLight::Kind::Beam) continue;
                const double strength = std::max(scalar_at(inside[k], t), 0.0) * l.strength_per_scalar;
                sum += sigma * strength * relative_phase(l.phase_g, glm::dot(l.direction_at(x), -span.dir)) * l.color;
            }
            for (std::size_t v : point_lights_) {
                const MediumLight& l = volumes_[v].light;
                const glm::dvec3 d = x - l.origin;
                const double r2 = glm::dot(d, d), f = l.point_falloff(r2);
                if (!(f > 0.0)) continue;
                const double mu = r2 > 0.0 ? glm::dot(d, -span.dir) / std::sqrt(r2) : 1.0;
                sum += sigma * f * relative_phase(l.phase_g, mu) * l.color;
            }
        }
        return sum;
    };

    double tau_total = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        const SpanVolume& v = inside[i];
        if (volumes_[v.volume].absorbs) tau_total += emission_integral(extinction_[v.volume], v.s_front, v.s_back, length).x;
    }
    const int pieces = int(std::clamp(std::ceil(tau_total / kReferencePieceDepth), 1.0, 4096.0));
    SegmentColor acc;
    for (int p = 0; p < pieces; ++p) {
        const double a = span.t_front + length * p / pieces, b = span.t_front + length * (p + 1) / pieces;
        glm::dvec3 e(0.0);
        double tau = 0.0;
        for (std::size_t i = 0; i < count; ++i) {
            const SpanVolume& v = inside[i];
            const MediumVolume& m = volumes_[v.volume];
            const double sa = scalar_at(v, a), sb = scalar_at(v, b);
            e += emission_integral(m.tf, sa, sb, b - a);
            if (m.absorbs) tau += emission_integral(extinction_[v.volume], sa, sb, b - a).x;
        }
        if (lit) { // split where a point light is nearest: its phase turns there, its falloff peaks
            std::array<double, 10> cuts{a};
            std::size_t n = 1;
            for (std::size_t v : point_lights_) {
                const double tc = glm::dot(volumes_[v].light.origin - span.origin, span.dir);
                if (!(tc > a && tc < b) || n == cuts.size() - 1) continue;
                std::size_t j = n++; // insertion, in order
                for (; j > 1 && cuts[j - 1] > tc; --j) cuts[j] = cuts[j - 1];
                cuts[j] = tc;
            }
            cuts[n++] = b;
            for (std::size_t k = 0; k + 1 < n; ++k) e += integrate(scattered, cuts[k], cuts[k + 1]);
        }
        SegmentColor piece;
        piece.optical_depth = tau;
        piece.alpha = -std::expm1(-tau);
        piece.color = e * opacity_per_depth(tau);
        acc = composite(acc, piece);
    }
    return acc;
}

} // namespace cellfx::fx
