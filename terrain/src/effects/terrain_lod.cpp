#include "terrain/terrain_lod.hpp"

#include <chrono>
#include <utility>

namespace cellfx::terrain {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

bool same_view(const LodView& a, const LodView& b) {
    return a.eye == b.eye && a.projection_scale == b.projection_scale && a.pixel_error == b.pixel_error &&
           a.triangle_budget == b.triangle_budget;
}

ContinuousLod make_lod(HeightField ground, std::optional<HeightField> layer, const LodSettings& settings) {
    return layer ? ContinuousLod(std::move(ground), std::move(*layer), settings) : ContinuousLod(std::move(ground), settings);
}

} // namespace

TerrainLod::TerrainLod(HeightField ground, std::optional<HeightField> layer_thickness, const LodSettings& settings)
    : lod_(make_lod(std::move(ground), std::move(layer_thickness), settings)) {}

bool TerrainLod::update(const LodView& view, LodStats* stats) {
    update_ms_ = extract_ms_ = 0.0;
    if (stats) *stats = LodStats{};
    if (last_view_ && same_view(*last_view_, view)) return false;
    const auto t = Clock::now();
    const LodStats s = lod_.update(view);
    update_ms_ = ms_since(t);
    if (stats) *stats = s;
    last_view_ = view;
    const LodChanges& c = lod_.changes();
    if (version_ > 0 && !c.full && c.fans.empty() && c.vertices.empty() && c.fans_before == lod_.fan_count()) return false;
    ++version_;
    return true;
}

const LodMesh& TerrainLod::mesh() const {
    if (extracted_version_ != version_) {
        const auto t = Clock::now();
        lod_.extract(mesh_);
        extracted_version_ = version_;
        extract_ms_ = ms_since(t);
    }
    return mesh_;
}

void TerrainLod::reset() {
    lod_.reset();
    last_view_.reset();
}

} // namespace cellfx::terrain
