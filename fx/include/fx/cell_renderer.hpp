// cellfx — GPU cell projection: the PCP, PCP-exact and MIP render paths and the sorted
// absorption paths on OpenGL 4.5.
//
// Based on: Roettger & Ertl 2003, §2 (MIP), §3 (PCP) and §5 (near-plane caps); Max, Williams &
// Silva 2000, §II–§V (absorption).
//
//   pcp        classic, as in the paper: per batch of cells with disjoint screen footprints,
//              back faces → alpha (d − d_min)/Δd, front faces and near-plane caps subtracted,
//              then colour κ(S)·Δd/2 blended with glBlendFunc(GL_DST_ALPHA, GL_ONE), into an
//              8-bit RGBA target. Emission only; κ·Δd/2 per cell and the sum per pixel must stay
//              ≤ 1 (8-bit, clamped). Per frame the CPU projects the mesh, builds caps and batches.
//   pcp-exact  one draw per mesh into a float target: each back-face fragment intersects its ray
//              with the cell's planes, integrates the linear scalar through the transfer
//              function's cumulative table exactly; near plane clamps the entry. With
//              `fog = true` it also accumulates optical depth and composites
//              bg·e^(−τ) + c·(1 − e^(−τ)) once — exact absorption for a one-colour medium,
//              no sort. Nothing per frame on the CPU.
//   mip        one draw: all faces with GL_MAX, emission c·σ at the face's scalar, plus caps.
//   absorption        emission and absorption (Max, Williams & Silva 2000, §II–§V), cells
//              sorted back to front (CellRenderOptions::sort) and composited with "over":
//              per cell the projected subdivision built on the CPU, opacity through a 2-D
//              texture of 1 − exp(−u·v), colour computed at the vertices and divided by α;
//              cells at transfer-function breakpoints sliced (§V). CPU work per frame.
//   absorption-exact  the same order, one draw: per fragment entry/exit through the cell's
//              planes and a pre-integration table over (s_front, s_back, length), float target.
//              Both cut the cells with problem faces (§V) into tetrahedra for the view.
//              docs/absorption.md: tolerances, limits, timings.
//
// STEP BY STEP (a game loop):
//     fx::CellRenderer fog(mesh, "density", tf);        // once, context current: uploads
//     while (running) {
//         ... draw the scene into your framebuffer ...
//         fog.render(camera, {0, 0, w, h}, fx::RenderPath::PcpExact, {/*fog=*/true});
//     }
// render() draws into the framebuffer bound to GL_DRAW_FRAMEBUFFER at the call, inside the
// given viewport, over its contents (premultiplied "over"; the emission paths add light). It
// saves and restores every GL state it changes (gl::StateGuard). Without
// CellRenderOptions::scene_depth nothing is depth-tested against the scene; with it the volume
// stops at the scene's surfaces (fog ends at the ground, hills hide what is behind them).
//
// Inverted cells (faces wound inward) are drawn as their positive versions on every path (the
// renderer orients its copy of the mesh: fx::orient_cells).
//
// Ownership: owns its GL buffers, textures and internal render targets, and shares the GL
// programs of its context with every other renderer there (move-only; destroy it while its
// context is current). Preconditions: a GL 4.5 core context current on
// the calling thread for every call; the mesh valid (validate_mesh) with convex cells.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/image.hpp"
#include "fx/parallel_for.hpp"
#include "fx/render_path.hpp"
#include "fx/sort_method.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {

struct CellRenderOptions {
    // pcp-exact only: accumulate optical depth too and composite e^(−τ) over the background.
    bool fog = false;
    // Measure the frame's GPU time with a GL_TIME_ELAPSED query (waits for the result). Not
    // while the host has a GL_TIME_ELAPSED query of its own active (GL allows one at a time).
    bool timing = false;
    // Classic pcp: tile size in pixels for the footprint batching (see footprint_batches.hpp).
    int batch_tile = 4;
    // The scene's depth buffer, so the volume stops at opaque surfaces: a GL_TEXTURE_2D name
    // (0: none) holding window-space depth in [0, 1] written with this camera's
    // projection_matrix() (GL's default depth range and clip control; the texture's compare mode
    // NONE, as GL creates it). Texel (viewport.x + i, viewport.y + j) belongs to pixel (i, j) of
    // the viewport. pcp-exact ends each ray's segment at the scene depth (exact: the scalar is
    // interpolated to the cut); pcp clamps every face's depth d to it, so the α difference is the
    // length in front of the scene (colour stays the per-cell trapezoid estimate); mip drops the
    // fragments behind it (a cell cut by a surface shows its entry face's maximum).
    // absorption-exact ends each segment at the scene depth like pcp-exact; absorption scales
    // each pixel's thickness by the part of its segment in front (the colour is kept). It is read
    // on texture unit 3 only while drawing into the renderer's own targets and unbound before the
    // resolve, so it may be attached to the framebuffer render() draws into (a game's usual set-up).
    unsigned int scene_depth = 0;
    // Absorption paths: the visibility sort (its per-mesh state is built on first use of each
    // method, and again when the view-dependent subdivision changes the cells). The default,
    // xmpvo, is exact on convex and non-convex meshes of convex cells; centroid is faster and
    // approximate (docs/visibility_sort.md).
    SortMethod sort = SortMethod::Xmpvo;
    // Classic absorption: cut cells at the transfer function's breakpoints (§V) so that colour
    // and extinction are linear inside every piece; off shows §II's projection alone.
    bool slice_breakpoints = true;
    // Where the frame's time goes (CellRenderStats' stage figures; cellfx bench render): each GL
    // stage runs alone, the GL finished before and after it, timed by a GL_TIME_ELAPSED query,
    // and the frame's draws are issued once more first with rasterisation off to time their
    // vertex stage alone. For benchmarks: it slows the frame (and replaces `timing`'s query).
    bool profile = false;
};

struct CellRenderStats {
    double gpu_ms = -1.0;         // GL_TIME_ELAPSED of all GL work of the frame (with profile: the
                                  // stages' `gl` sum, `vertex`'s rerun aside); −1 if not timed
    double cpu_ms = 0.0;          // CPU work of the frame (projection, caps, batches, uploads)
    std::size_t cells = 0;        // cells in the mesh
    std::size_t cells_drawn = 0;  // classic: cells in some batch (culled ones left out)
    std::size_t caps = 0;         // near-plane cap polygons drawn
    std::size_t batches = 0;      // classic: footprint batches
    std::size_t draw_calls = 0;
    // Absorption paths (CPU work, done before the GPU work and included in cpu_ms):
    double setup_ms = 0.0;         // one-time work done in this frame (a sort's per-mesh state)
    double subdivision_ms = 0.0;   // problem faces and the working mesh (§V)
    double sort_ms = 0.0;          // visibility sort for this view
    double projection_ms = 0.0;    // classic: projected subdivisions and vertex colours; exact: items;
                                   // pcp (classic PCP) too: footprints, batches and caps
    std::size_t problem_cells = 0; // cells cut into tetrahedra for this view (§V)
    std::size_t sort_cycles = 0;   // visibility cycles the sort found and broke
    std::size_t pieces = 0;        // classic: convex pieces projected (cells, tetrahedra, slabs)
    std::size_t polygons = 0;      // classic: polygons of their projected subdivisions
    // With CellRenderOptions::profile (else 0), each GL stage of the frame run alone (the CPU's
    // projection and sort are projection_ms, sort_ms and subdivision_ms above, timed on the CPU
    // before the GL work starts), in ms by the CPU's clock from the GL finished before it to the
    // GL finished after it (`wall`: what it costs end to end on any GL) and by its
    // GL_TIME_ELAPSED query (`gl`: the GL's own clock; Mesa's llvmpipe counts only part of its
    // work there, so `wall` is the figure on it):
    struct StageTime {
        double wall = 0.0, gl = 0.0;
    };
    StageTime tables;   // the projector's tables and culled cells brought up to date (0 if current)
    StageTime clear;    // the path's own target cleared
    StageTime upload;   // the frame's buffers sent (cell lists, caps, classic polygons, pieces)
    StageTime vertex;   // the draws, issued once more first with rasterisation off: vertex fetch, shading, assembly
    StageTime fragment; // the draws less `vertex`: rasterisation, fragment shading, blending
    StageTime resolve;  // the target composited over the host's framebuffer
};

class CellRenderer {
public:
    // Uploads the mesh (positions relative to its centre as floats, face triangles and planes)
    // and the transfer-function tables. `scalar_name` picks the field ("" = the first one; a
    // mesh without fields renders with scalar 0). Throws fx::Error for an unknown field, bad
    // geometry (non-finite values), or a GL failure (shader errors with file:line).
    CellRenderer(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf);
    ~CellRenderer();
    CellRenderer(CellRenderer&&) noexcept;
    CellRenderer& operator=(CellRenderer&&) noexcept;
    CellRenderer(const CellRenderer&) = delete;
    CellRenderer& operator=(const CellRenderer&) = delete;

    // Rebuilds the tables (normalized functions are rescaled to the field's range).
    void set_transfer_function(const TransferFunction& tf);
    // Replaces the mesh (and field), keeping the programs and the transfer function: for meshes
    // rebuilt every frame (terrain LOD prisms). The function's normalized range follows the new
    // field. Throws like the constructor.
    void set_mesh(const CellMesh& mesh, const std::string& scalar_name);
    // The same for a mesh that changed in part (`changes`: the points and cells that differ from
    // the mesh this renderer last took, MeshChanges in cell_mesh.hpp): only they are copied and
    // uploaded, and the GPU rebuilds the tables of the cells they touch. Falls back to
    // set_mesh (returning false) when the changes cannot apply in place — `whole`, a point
    // removed, a cell of another type, a point far outside the mesh's first bounds. Throws
    // fx::Error like set_mesh for bad changed values or ids.
    bool update_mesh(const CellMesh& mesh, const std::string& scalar_name, const MeshChanges& changes);
    // Culling (default off): each frame draws only the cells whose box meets the view, chosen on
    // the GPU. For meshes far larger than what the camera sees (terrain fog, aurora).
    void set_culling(bool culling);
    // Replaces the values of the field in use (one per mesh point), keeping the geometry: for
    // scalars animated on a fixed mesh (a campfire's noise), far cheaper than set_mesh. A
    // normalized function's range follows the new values. Throws fx::Error for a wrong count or
    // a non-finite value (nothing is changed then).
    void set_scalars(const std::vector<float>& values);

    // The job system for the CPU work a frame can split (the classic absorption path's
    // projection, the exact one's per-frame index lists). Default: cellfx's own persistent pool
    // (default_parallel_for()); a ParallelFor with no `run` makes that work serial.
    void set_parallel_for(const ParallelFor& parallel_for);

    CellRenderStats render(const Camera& camera, const Viewport& viewport, RenderPath path,
                           const CellRenderOptions& options = {});
    // Renders into a new RGBA32F target cleared to 0 and reads it back: premultiplied, bottom
    // row first; emission paths give (light, 0), fog gives (c·(1 − e^(−τ)), 1 − e^(−τ)), the
    // absorption paths premultiplied colour and alpha.
    Image render_to_image(const Camera& camera, int width, int height, RenderPath path,
                          const CellRenderOptions& options = {}, CellRenderStats* stats = nullptr);

    std::size_t cell_count() const;
    std::size_t gpu_bytes() const; // mesh buffers + tables + the passes' own (gpu_memory() less targets)
    // The GPU memory the renderer holds, in bytes, by who reads it.
    struct Memory {
        std::size_t mesh = 0;         // points, connectivity, cell offsets and words, transfer tables: every path but absorption
        std::size_t cell_tables = 0;  // per face triangle planes, scalar functions, barycentric rows, elements: the exact paths
        std::size_t unique_faces = 0; // mip's faces, made on first use
        std::size_t pcp_list = 0;     // classic pcp's frame cell list and slot data
        std::size_t absorption = 0;   // the absorption paths': frame lists and geometry, opacity and pre-integration tables
        std::size_t targets = 0;      // the paths' own targets: per pixel, not per cell
    };
    Memory gpu_memory() const;

    // The implementation, opaque here: cellfx's own passes that draw with this renderer's GL
    // projector (the medium) reach it through a private header (fx/src/render/projector_access.hpp).
    struct Impl;
    Impl& impl();

private:
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::fx
