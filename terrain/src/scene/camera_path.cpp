// Camera flights of scene files: cubic Hermite curves with Catmull–Rom tangents (finite
// differences over the neighbouring keys, in time), for eye and target alike.
#include <algorithm>
#include <cmath>

#include "terrain/scene.hpp"

namespace cellfx::terrain {

const char* effect_type_name(const EffectParams& params) {
    struct Name {
        const char* operator()(const fx::CampfireParams&) const { return "campfire"; }
        const char* operator()(const fx::SearchLightParams&) const { return "search_light"; }
        const char* operator()(const fx::LaserConeParams&) const { return "laser_cone"; }
        const char* operator()(const fx::VolumeParams&) const { return "volume"; }
    };
    return std::visit(Name{}, params);
}

fx::Camera CameraPath::at(double t, const fx::Camera& base) const {
    fx::Camera cam = base;
    if (keys.empty()) return cam;
    if (keys.size() == 1 || !std::isfinite(t)) {
        cam.eye = keys.front().eye, cam.target = keys.front().target;
        return cam;
    }
    const std::size_t n = keys.size();
    const double t0 = keys.front().time, period = duration();
    if (loop) t = t0 + (std::fmod(t - t0, period) + period * (t < t0 ? 1.0 : 0.0));
    t = std::clamp(t, t0, keys.back().time);
    std::size_t i = std::size_t(std::upper_bound(keys.begin(), keys.end(), t,
                                                 [](double v, const CameraKey& k) { return v < k.time; }) -
                                keys.begin());
    i = std::clamp<std::size_t>(i, 1, n - 1) - 1; // segment [i, i + 1]
    // A key's neighbour in time: the next/previous key, wrapped once around a loop, or the key
    // itself at the ends of an open path (one-sided differences).
    struct Point {
        double time;
        const CameraKey* key;
    };
    auto neighbour = [&](std::size_t k, int step) -> Point {
        if (step < 0 && k == 0) return loop ? Point{keys[n - 2].time - period, &keys[n - 2]} : Point{keys[0].time, &keys[0]};
        if (step > 0 && k == n - 1) return loop ? Point{keys[1].time + period, &keys[1]} : Point{keys[k].time, &keys[k]};
        const std::size_t m = step < 0 ? k - 1 : k + 1;
        return {keys[m].time, &keys[m]};
    };
    auto tangent = [&](std::size_t k, glm::dvec3 CameraKey::*field) {
        const Point a = neighbour(k, -1), b = neighbour(k, +1);
        return (b.key->*field - a.key->*field) / (b.time - a.time);
    };
    const CameraKey &a = keys[i], &b = keys[i + 1];
    const double h = b.time - a.time, u = (t - a.time) / h;
    const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u);
    const double h01 = u * u * (3 - 2 * u), h11 = u * u * (u - 1);
    auto curve = [&](glm::dvec3 CameraKey::*field) {
        return h00 * (a.*field) + h10 * h * tangent(i, field) + h01 * (b.*field) + h11 * h * tangent(i + 1, field);
    };
    cam.eye = curve(&CameraKey::eye);
    cam.target = curve(&CameraKey::target);
    if (cam.eye == cam.target) cam.target = cam.eye + (b.target - b.eye); // a degenerate blend: look as key b does
    return cam;
}

} // namespace cellfx::terrain
