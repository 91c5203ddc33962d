// cellfx terrain — where a scene's volumes must be integrated as one medium: the screen region
// in which an absorbing volume overlaps another volume (or a point light's reach), planned on
// the CPU from the volumes' world bounds alone, so a frame whose volumes do not overlap on
// screen costs nothing more (medium/medium_compositor.hpp does the work inside the region).
#pragma once

#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "medium/medium_compositor.hpp"

namespace cellfx::terrain {

// One volume that may take part (an effect drawn with a path of the emission–absorption model).
struct MediumCandidate {
    fx::Bounds bounds;       // world
    bool bulk = false;       // the ground fog: binned, not sorted, and always drawn by its path too
    bool absorbs = false;
    bool scatters = false;   // absorbs with an albedo: lights show in it
    fx::Bounds light_reach{glm::dvec3(1.0), glm::dvec3(-1.0)}; // world box its point light reaches (empty: none)
};

struct MediumPlan {
    fx::PixelRect region;            // empty: nothing overlaps, every volume draws with its own path
    std::vector<fx::PixelRect> rects, reach; // scratch: the candidates' screen rectangles
    std::vector<bool> appended;      // per candidate: it covers part of the region
    std::vector<bool> region_only;   // per candidate: all of it lies in the region and it marks the
                                     // compositor's mask (not the bulk): its own path is skipped
};

// The region: the bounding rectangle of every overlap of two candidates' screen rectangles of
// which at least one absorbs, and of every point light's reach with a scattering candidate.
// None (each drawn by its path, as without overlap) when more than MediumCompositor::kMaxVolumes
// candidates would take part.
// `plan`'s storage is reused (a steady frame allocates nothing).
void plan_medium(const std::vector<MediumCandidate>& candidates, const fx::Camera& camera, int width, int height,
                 MediumPlan& plan);

} // namespace cellfx::terrain
