// cellfx terrain — ground fog and aurora as fx::Effects (fx/include/fx/effect.hpp): the same
// interface as the campfire, search light and laser cone, so a scene treats them alike
// (frustum test, skipped when disabled or out of view, per-effect frame statistics).
//
// Based on: Roettger & Ertl 2003, §5 — prisms stacked on the triangles of a continuous-LOD
// height field (fog_layer.hpp), the aurora the same stack hung from a ceiling (aurora.hpp).
//
// Both follow a view-dependent LOD: update() refines their LOD for the camera (TerrainLod:
// nothing for the view of the previous frame, e.g. a camera that only turns) and, when it
// changed, writes only the prisms of the fans and vertices the refinement changed
// (LayerPrismTracker) and lists them in mesh_changes(), so the renderer uploads only those; the
// prisms are not culled on the CPU (the scene renderer draws those in view: CellRenderer::
// set_culling). They live in world coordinates (transform() is the identity).
#pragma once

#include <cstddef>
#include <memory>

#include "fx/effect.hpp"
#include "terrain/aurora.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/terrain_lod.hpp"

namespace cellfx::terrain {

struct LayerEffectSettings {
    double pixel_error = 2.0;         // the LOD's screen-space error bound (LodView::pixel_error)
    std::size_t triangle_budget = 0;  // LodView::triangle_budget (0: none)
};

// What the fog and the aurora share: prisms following a LOD.
class LayerEffect : public fx::Effect {
public:
    const LayerPrismStats& prism_stats() const { return prism_stats_; } // of the current mesh
    const LodStats& lod_stats() const { return lod_stats_; }           // of the last update
    LayerEffectSettings& settings() { return settings_; }

protected:
    LayerEffect(std::string scalar_name, const LayerEffectSettings& settings);
    // The prisms brought up to the LOD's state (nothing when it did not change).
    fx::EffectChanges follow_lod(const TerrainLod& lod, const LayerPrismOptions& options);

    LayerEffectSettings settings_;
    LayerPrismTracker tracker_;
    LayerPrismStats prism_stats_;
    LodStats lod_stats_;
};

// Fog prisms on a terrain LOD built with the fog map as its layer. The LOD is shared: the scene
// draws the terrain surface from the same TerrainLod, which refines once per view for both.
class GroundFog final : public LayerEffect {
public:
    // `lod` must carry a layer (the fog map); `thickness` is that fog map (for the bounds and the
    // scalar range). Throws fx::Error for a LOD without a layer, a fog map on another grid, or
    // LayerDensity::Noise without a generator.
    GroundFog(std::shared_ptr<TerrainLod> lod, const HeightField& thickness, const LayerPrismOptions& prisms,
              const LayerEffectSettings& settings = {});

    static constexpr const char* kTypeName = "ground_fog"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    fx::ScalarRange scalar_range() const override { return range_; }

    const TerrainLod& lod() const { return *lod_; }

private:
    fx::EffectChanges simulate(const fx::EffectView& view) override;
    fx::Bounds local_bounds() const override { return bounds_; }

    std::shared_ptr<TerrainLod> lod_;
    LayerPrismOptions prisms_;
    fx::Bounds bounds_;
    fx::ScalarRange range_;
};

// Aurora curtains: prisms hanging from the ceiling by the penetration depth (make_aurora_layer),
// on their own LOD, density LayerDensity::LowerBorder (1 where the particles stop, falling to 0
// at the deepest curtain's ceiling): scalar "emission" in [0, 1].
class Aurora final : public LayerEffect {
public:
    // Throws like ContinuousLod's constructor.
    explicit Aurora(const AuroraLayer& layer, const LodSettings& lod = {}, const LayerEffectSettings& settings = {});

    static constexpr const char* kTypeName = "aurora"; // type_name(): cellfx::Module::effect<E>() compares it
    const char* type_name() const override { return kTypeName; }
    fx::ScalarRange scalar_range() const override { return {0.0f, 1.0f}; }

    const TerrainLod& lod() const { return lod_; }

private:
    fx::EffectChanges simulate(const fx::EffectView& view) override;
    fx::Bounds local_bounds() const override { return bounds_; }

    TerrainLod lod_;
    LayerPrismOptions prisms_;
    fx::Bounds bounds_;
};

} // namespace cellfx::terrain
