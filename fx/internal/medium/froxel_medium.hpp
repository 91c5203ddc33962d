// cellfx — the one medium on a froxel grid: its cost and memory bounded by the grid, not by how
// many cells a pixel's ray crosses (the exact per-pixel method, medium_compositor.hpp, keeps
// every segment).
//
// Based on: Wronski 2014, "Volumetric fog: unified compute shader-based solution to
// atmospheric scattering" (Assassin's Creed IV; froxels of 160 × 90 × 64) and Hillaire 2015,
// "Physically based and unified volumetric rendering in Frostbite": a grid of screen tiles ×
// exponential depth slices, lit once per froxel, integrated front to back per tile and read per
// pixel at its scene depth. Unlike density sampled at froxel centres, each volume's exact
// per-cell segment integrals along the tile's centre ray are added into the slices they cross,
// so a thin or dense cell is neither missed nor aliased in depth. The optical model is
// fx/medium.hpp's.
//
// Per frame:
//   begin(camera, width, height, far_depth, volumes)   sizes and clears the grid: tiles of
//       kTilePixels (larger where the view would need more than kMaxTiles across or up),
//       kSlices slices from the near plane to `far_depth`;
//   inject(renderer, transform, volume)   an absorbing volume's cells: every tile's centre ray
//       through each cell, the segment cut at the slices, each piece's emission, optical depth
//       and scattering added to its froxel (shaders/froxel_inject.frag, integer compare-and-swap:
//       core GL 4.5);
//   integrate()   per tile column, front to back: the point lights scattered in each froxel,
//       the cumulative light and optical depth at each slice's far end (froxel_integrate.comp);
//   apply(viewport, scene_depth, depth_origin)   every pixel of the bound framebuffer: the
//       medium in front of its scene depth, "over" what is there (froxel_apply.frag) — edges
//       against geometry are as sharp as the depth;
//   draw_emission(renderer, transform, volume, viewport, scene_depth)   an emission-only volume
//       (fire, beam) per pixel of the bound framebuffer, its emission dimmed by the grid in front
//       of it and a beam's light scattered by the grid's medium (froxel_emission.frag), added.
// What is approximate (docs/effects.md): inside a froxel the media are taken as mixed evenly;
// across a tile the grid is interpolated between tile centres, in depth between slice ends;
// point lights are evaluated along the tile's centre ray.
//
// Ownership: owns its programs, buffers and textures (move-only; destroy with the context
// current). Preconditions: a GL 4.5 context current for every call; the calls of a frame in the
// order above (inject, draw_emission and apply any number of times after begin / integrate).
// Every GL state it changes is restored (gl::StateGuard: texture units 0–2, image units 0–1,
// storage binding 4).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/medium.hpp"

namespace cellfx::fx {

class FroxelMedium {
public:
    static constexpr int kTilePixels = 8;   // tile size where the grid fits kMaxTiles
    static constexpr int kMaxTilesAcross = 160, kMaxTilesUp = 90; // Wronski 2014's grid at 1080p
    static constexpr int kSlices = 64;
    static constexpr int kMaxPointLights = 8;

    // The grid for a width × height view: tiles across and up, slices.
    static glm::ivec3 grid_size(int width, int height);
    // The GPU memory of that grid (injection buffer, integrated and scattering grids).
    static std::size_t gpu_bytes_for(int width, int height);

    FroxelMedium(); // GL context current; compiles the programs
    ~FroxelMedium();
    FroxelMedium(FroxelMedium&&) noexcept;
    FroxelMedium& operator=(FroxelMedium&&) noexcept;

    // Starts a frame for a width × height view of `camera` (world frame; an explicit projection
    // is followed). `far_depth` (view depth): the farthest point of the volumes to inject
    // (slices end there; anything beyond counts in the last). `volumes` index what inject()
    // and draw_emission() name: transfer functions in scalar units, absorbing or not, albedo,
    // lights in the world (point lights scatter in the grid; beams are drawn by
    // draw_emission). Throws fx::Error for an empty size, a non-finite or non-positive
    // far_depth, or a volume whose transfer function has no points or is normalized.
    void begin(const Camera& camera, int width, int height, double far_depth, const std::vector<MediumVolume>& volumes,
               bool timing = false);
    // Adds the cells of `renderer`'s mesh (placed in the world by `world_from_local`, rigid) as
    // volume `volume`, which must absorb. Throws fx::Error otherwise.
    void inject(CellRenderer& renderer, const glm::dmat4& world_from_local, std::size_t volume);
    // Lights and integrates the grid (after every inject()).
    void integrate();
    // Composites the medium over the bound draw framebuffer's `viewport` (the begin() view at
    // that viewport's size): premultiplied, blending "over". `scene_depth` as
    // CellRenderOptions::scene_depth, its texel for pixel (i, j) at depth_origin + (i, j); 0: none.
    void apply(const Viewport& viewport, unsigned scene_depth, glm::ivec2 depth_origin);
    // Draws emission-only volume `volume` into the bound draw framebuffer's `viewport` (any
    // size: the begin() view at another resolution), added. `scene_depth` as
    // CellRenderOptions::scene_depth with the framebuffer's layout: texel (x, y) for the
    // framebuffer's pixel (x, y); 0: none.
    void draw_emission(CellRenderer& renderer, const glm::dmat4& world_from_local, std::size_t volume,
                       const Viewport& viewport, unsigned scene_depth);
    // The frame's figures (timing: GL_TIME_ELAPSED, waited for).
    const MediumStats& stats() const;

    std::size_t gpu_bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::fx
