// cellfx terrain — a continuous LOD and its extracted mesh, refined at most once per view and
// shared by everything drawn from it (the terrain surface and the ground fog ride on one LOD, so
// the fog's prisms stand exactly on the drawn ground).
//
// update(view) does nothing for the view of the previous update (same eye, scale, error bound
// and budget: a camera that only turns needs no new LOD); otherwise it refines
// (ContinuousLod::update) and bumps version() when the mesh changed. Users keep the version they
// built from: at the next version they may apply lod().changes() to what they built (only the
// fans and vertices that changed), at any other they rebuild from the fans. mesh() extracts the
// whole mesh, when asked, once per version.
//
// Ownership: owns the ContinuousLod and the mesh. Not thread-safe.
#pragma once

#include <cstdint>
#include <optional>

#include "terrain/continuous_lod.hpp"
#include "terrain/height_field.hpp"

namespace cellfx::terrain {

class TerrainLod {
public:
    // Throws like ContinuousLod's constructors.
    TerrainLod(HeightField ground, std::optional<HeightField> layer_thickness, const LodSettings& settings = {});

    // Refines for `view` (see the header comment). Returns true if mesh() changed. `stats`, when
    // given, receives the refinement's statistics (all zero when nothing was refined).
    bool update(const LodView& view, LodStats* stats = nullptr);
    // Drops all LOD state: the next update() rebuilds from the root.
    void reset();

    const LodMesh& mesh() const;
    std::uint64_t version() const { return version_; } // 0 before the first update
    const ContinuousLod& lod() const { return lod_; }
    // Wall time of the last refinement and of the last extraction (ms; 0 when update() did nothing).
    double last_update_ms() const { return update_ms_; }
    double last_extract_ms() const { return extract_ms_; }

private:
    ContinuousLod lod_;
    mutable LodMesh mesh_;
    mutable std::uint64_t extracted_version_ = 0;
    std::optional<LodView> last_view_;
    std::uint64_t version_ = 0;
    double update_ms_ = 0.0;
    mutable double extract_ms_ = 0.0;
};

} // namespace cellfx::terrain
