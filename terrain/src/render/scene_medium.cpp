// Where a scene needs its one medium (scene_medium.hpp): screen rectangles of world boxes and
// their overlaps.
#include "render/scene_medium.hpp"

#include <algorithm>
#include <cmath>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

namespace terrain {

namespace {

fx::PixelRect intersect(const fx::PixelRect& a, const fx::PixelRect& b) {
    const int x0 = std::max(a.x, b.x), y0 = std::max(a.y, b.y);
    const int x1 = std::min(a.x + a.width, b.x + b.width), y1 = std::min(a.y + a.height, b.y + b.height);
    if (x1 <= x0 || y1 <= y0) return {};
    return {x0, y0, x1 - x0, y1 - y0};
}

fx::PixelRect unite(const fx::PixelRect& a, const fx::PixelRect& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    const int x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
    const int x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
    return {x0, y0, x1 - x0, y1 - y0};
}

bool contains(const fx::PixelRect& outer, const fx::PixelRect& inner) {
    return inner.empty() || (inner.x >= outer.x && inner.y >= outer.y && inner.x + inner.width <= outer.x + outer.width &&
                             inner.y + inner.height <= outer.y + outer.height);
}

} // namespace

fx::PixelRect screen_rect(const fx::Bounds& bounds, const fx::Camera& camera, int width, int height) {
    if (bounds.empty() || width <= 0 || height <= 0) return {};
    const glm::dmat4 vp = camera.projection_matrix(double(width) / double(height)) * camera.view_matrix();
    double lo_x = HUGE_VAL, lo_y = HUGE_VAL, hi_x = -HUGE_VAL, hi_y = -HUGE_VAL;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec4 c = vp * glm::dvec4((k & 1) ? bounds.hi.x : bounds.lo.x, (k & 2) ? bounds.hi.y : bounds.lo.y,
                                             (k & 4) ? bounds.hi.z : bounds.lo.z, 1.0);
        // A corner at or behind the near plane: the box's projection is unbounded, take the view.
        if (!(c.w >= camera.near_distance) && !camera.orthographic()) return {0, 0, width, height};
        lo_x = std::min(lo_x, c.x / c.w), hi_x = std::max(hi_x, c.x / c.w);
        lo_y = std::min(lo_y, c.y / c.w), hi_y = std::max(hi_y, c.y / c.w);
    }
    const double x0 = std::floor((lo_x + 1.0) * 0.5 * width) - 1.0, x1 = std::ceil((hi_x + 1.0) * 0.5 * width) + 1.0;
    const double y0 = std::floor((lo_y + 1.0) * 0.5 * height) - 1.0, y1 = std::ceil((hi_y + 1.0) * 0.5 * height) + 1.0;
    const int ix0 = int(std::clamp(x0, 0.0, double(width))), ix1 = int(std::clamp(x1, 0.0, double(width)));
    const int iy0 = int(std::clamp(y0, 0.0, double(height))), iy1 = int(std::clamp(y1, 0.0, double(height)));
    if (ix1 <= ix0 || iy1 <= iy0) return {};
    return {ix0, iy0, ix1 - ix0, iy1 - iy0};
}

MediumPlan plan_medium(const std::vector<MediumCandidate>& candidates, const fx::Camera& camera, int width, int height) {
    const std::size_t n = candidates.size();
    std::vector<fx::PixelRect> rects(n), reach(n);
    for (std::size_t i = 0; i < n; ++i) {
        rects[i] = screen_rect(candidates[i].bounds, camera, width, height);
        reach[i] = screen_rect(candidates[i].light_reach, camera, width, height);
    }
    MediumPlan plan;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j)
            if (candidates[i].absorbs || candidates[j].absorbs) plan.region = unite(plan.region, intersect(rects[i], rects[j]));
        for (std::size_t j = 0; j < n; ++j)
            if (candidates[j].scatters) plan.region = unite(plan.region, intersect(reach[i], rects[j]));
    }
    plan.appended.assign(n, false);
    plan.region_only.assign(n, false);
    if (plan.region.empty()) return plan;
    for (std::size_t i = 0; i < n; ++i) {
        plan.appended[i] = !intersect(rects[i], plan.region).empty();
        plan.region_only[i] = plan.appended[i] && contains(plan.region, rects[i]);
    }
    return plan;
}

} // namespace terrain
