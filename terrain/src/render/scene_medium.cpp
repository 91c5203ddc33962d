// Where a scene needs its one medium (scene_medium.hpp): screen rectangles of world boxes and
// their overlaps.
#include "render/scene_medium.hpp"

#include <algorithm>
#include <cmath>


namespace cellfx::terrain {

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

void plan_medium(const std::vector<MediumCandidate>& candidates, const fx::Camera& camera, int width, int height,
                 MediumPlan& plan) {
    const std::size_t n = candidates.size();
    plan.rects.resize(n);
    plan.reach.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        plan.rects[i] = fx::screen_rect(candidates[i].bounds, camera, width, height);
        plan.reach[i] = fx::screen_rect(candidates[i].light_reach, camera, width, height);
    }
    plan.region = {};
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j)
            if (candidates[i].absorbs || candidates[j].absorbs)
                plan.region = unite(plan.region, intersect(plan.rects[i], plan.rects[j]));
        for (std::size_t j = 0; j < n; ++j)
            if (candidates[j].scatters) plan.region = unite(plan.region, intersect(plan.reach[i], plan.rects[j]));
    }
    plan.appended.assign(n, false);
    plan.region_only.assign(n, false);
    if (plan.region.empty()) return;
    std::size_t appended = 0;
    for (std::size_t i = 0; i < n; ++i) {
        plan.appended[i] = !intersect(plan.rects[i], plan.region).empty();
        plan.region_only[i] = plan.appended[i] && !candidates[i].bulk && contains(plan.region, plan.rects[i]);
        appended += plan.appended[i];
    }
    if (appended > std::size_t(fx::MediumCompositor::kMaxVolumes)) { // too many: none, each by its path
        plan.region = {};
        plan.appended.assign(n, false);
        plan.region_only.assign(n, false);
    }
}

} // namespace cellfx::terrain
