// cellfx — batching cells whose screen footprints do not overlap (classic PCP).
//
// Based on: Roettger & Ertl 2003, §3. Classic PCP keeps each cell's normalised ray length in
// the ALPHA channel between its passes (pass 1 writes it, pass 2 subtracts from it, pass 3
// multiplies colour by it), so two cells covering the same pixel must not be in the same
// pass. Drawing one cell per pass costs 3 draw calls per cell; instead, cells whose screen
// rectangles are disjoint go into one batch and each pass draws a whole batch at once.
//
// How: each cell's footprint is the set of screen tiles (`tile` × `tile` pixels) that the
// convex hull of its visible part (its vertices beyond the near plane plus its near-plane cap)
// touches, grown by one pixel: per tile row, the one run of tiles the hull meets there. Cells
// are assigned first-fit, in mesh order, to the first batch that has none of their tiles (a
// 64-bit mask of batches per tile and page of 64 batches). Footprints are conservative, so
// cells in one batch never share a pixel.
//
// Limits: the number of batches is at least the largest number of cells covering one tile
// (the depth complexity), and more where the first-fit order packs badly or thin cells cross
// many tiles diagonally. A cell covering the whole screen (camera inside the mesh) forms a
// batch of its own. CPU cost per frame: O(cell vertices + tiles touched).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "fx/cell_mesh.hpp"
#include "projector/polyhedron_projector.hpp"

namespace cellfx::fx {

// Tile runs, one per tile row a cell touches: tiles [first, last] of row `row`.
struct TileSpan {
    std::uint16_t row = 0, first = 0, last = 0;
};

// The footprints of all cells: cell c touches spans [first_span[c], first_span[c + 1]).
struct CellFootprints {
    int tile = 1;                          // tile size in pixels
    int tiles_x = 0, tiles_y = 0;          // tiles across the viewport
    std::vector<std::uint32_t> first_span; // cell_count + 1 entries
    std::vector<TileSpan> spans;
    // Scratch of cell_footprints(), kept with the result so that a steady frame allocates nothing.
    std::vector<std::uint32_t> cap_of;
    std::vector<glm::dvec2> points, hull;

    std::size_t cell_count() const { return first_span.empty() ? 0 : first_span.size() - 1; }
    bool empty(std::size_t cell) const { return first_span[cell] == first_span[cell + 1]; }
};

// The tile footprint of each cell's visible part on a width × height viewport; empty for
// cells wholly in front of the near plane or outside the viewport (none is cut at the far
// plane).
// `view_projection` maps the geometry's relative frame to clip space. `caps` must be the caps
// of `projected` (build_near_caps). tile ≥ 1 pixels; width, height ≤ 65535·tile.
void cell_footprints(const CellMesh& mesh, const ProjectorGeometry& geometry, const glm::dmat4& view_projection,
                     const ProjectedCells& projected, const NearCaps& caps, int width, int height, int tile,
                     CellFootprints& out);

constexpr std::uint32_t kNoBatch = 0xFFFFFFFFu;

// First-fit batches of footprints that share no tile. batch_of[c] = batch of cell c, kNoBatch
// for empty footprints. Returns the number of batches.
std::uint32_t batch_footprints(const CellFootprints& footprints, std::vector<std::uint32_t>& batch_of);
// The same with the caller's scratch for the batches' tile masks (kept between frames).
std::uint32_t batch_footprints(const CellFootprints& footprints, std::vector<std::uint32_t>& batch_of,
                               std::vector<std::uint64_t>& masks);

} // namespace cellfx::fx
