// cellfx — batching cells whose screen footprints do not overlap (classic PCP).
//
// Based on: Roettger & Ertl 2003, §3. Classic PCP keeps each cell's normalised ray length in
// the ALPHA channel between its passes (pass 1 writes it, pass 2 subtracts from it, pass 3
// multiplies colour by it), so two cells covering the same pixel must not be in the same
// pass. Drawing one cell per pass costs 3 draw calls per cell; instead, cells whose screen
// rectangles are disjoint go into one batch and each pass draws a whole batch at once.
//
// How: each cell's footprint is the pixel rectangle around the visible part of the cell (its
// vertices beyond the near plane plus its near-plane cap), grown by one pixel and rounded out
// to tiles of `tile` pixels. Cells are assigned first-fit, in mesh order, to the first batch
// whose occupied tiles they do not touch (a 64-bit mask of batches per tile and page of 64
// batches). Rectangles are conservative, so cells in one batch never share a pixel.
//
// Limits: the number of batches is at least the largest number of cells covering one tile
// (the depth complexity) and, because rectangles overestimate projected cells, usually a small
// factor more; a structured grid seen along a diagonal gives roughly (cells along the view)
// × 2–4 batches. A cell covering the whole screen (camera inside the mesh) forms a batch of
// its own. CPU cost per frame: O(cells × tiles touched).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "fx/cell_mesh.hpp"
#include "fx/polyhedron_projector.hpp"

namespace fx {

// Inclusive pixel ranges; empty (not drawn) when x1 < x0 or y1 < y0.
struct ScreenRect {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    bool empty() const { return x1 < x0 || y1 < y0; }
};

// Pixel rectangle of each cell's visible part on a width × height viewport; empty for cells
// wholly in front of the near plane, beyond the far plane or outside the viewport.
// `view_projection` maps the geometry's relative frame to clip space. `caps` must be the
// caps of `projected` (build_near_caps).
void cell_footprints(const CellMesh& mesh, const ProjectorGeometry& geometry, const ProjectorView& view,
                     const glm::dmat4& view_projection, const ProjectedCells& projected, const NearCaps& caps,
                     int width, int height, std::vector<ScreenRect>& out);

constexpr std::uint32_t kNoBatch = 0xFFFFFFFFu;

// First-fit batches of non-overlapping rectangles. batch_of[i] = batch of rect i, kNoBatch for
// empty ones. Returns the number of batches. tile ≥ 1 pixels.
std::uint32_t batch_footprints(const std::vector<ScreenRect>& rects, int width, int height, int tile,
                               std::vector<std::uint32_t>& batch_of);

} // namespace fx
