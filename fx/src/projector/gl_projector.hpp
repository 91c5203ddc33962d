// cellfx — the GL side of the polyhedron projector: the one layer every GPU render path draws
// through.
//
// Based on: Roettger & Ertl 2003, §3 (the projector) and §5 (near-plane caps).
//
// Owns, per mesh and scalar field: the CPU projector's geometry (polyhedron_projector.hpp), the
// mesh on the GPU, the transfer function's tables and the context's shared programs
// (ProgramCache). Gives the passes above it (fx/src/passes/: pcp, pcp-exact, mip, the absorption
// paths; the dispatcher fx::CellRenderer above them) what they share: the mesh's bindings, the
// view, ray and scene-depth uniforms of gl_interface.hpp's table, cell lists and near-plane caps.
// It includes nothing from the passes or the dispatcher.
//
// How the mesh is drawn. A cell's vertices are vertex ids slot·V + k (k < V = vertices_per_cell():
// 4 when every cell is a tetrahedron, else 8), so that a cell's vertex is transformed once
// however many of its triangles use it; cells.vert finds the cell of `slot` — the slot itself,
// or entry `slot` of a frame's cell list (GlCellList) — fetches its point, and hands the
// fragment shader the cell's word as one flat integer. The element buffer lists each cell's
// face triangles in that numbering (quads cut by their smallest-vertex diagonal, as
// everywhere); for tetrahedra the pattern is the same for every cell, so a frame's list of
// tetrahedra needs no element buffer of its own. Per-cell data is fetched by the fragment
// shaders from buffer textures, not passed down as varyings: on Mesa's llvmpipe the varyings'
// set-up and gl_PrimitiveID run on one thread before rasterisation, the fetches on every core.
//   points            vec4 per point (position in the relative frame, scalar)
//   connectivity      the mesh's cell_vertices, cell offsets
//   cell words        per cell, cell_word(first triangle, triangle count) (gl_interface.hpp)
//   planes            per face triangle: outward unit normal n, n·p
//   scalar functions  per face triangle: (g, s0), the scalar on it is g·q + s0 (a
//                     tetrahedron's: its own linear function, on every face)
//   barycentrics      per face triangle, two rows: b1 = r1·q + r1w, b2 = r2·q + r2w (meshes
//                     with cells other than tetrahedra: the exact paths' entry search)
//   after the mesh's triangles, room for the planes and scalar functions of the tetrahedra a
//   frame makes (upload_pieces: the absorption paths' view-dependent subdivision).
//
// Cells whose faces wind inward (negative volume, e.g. from a VTK file written with the other
// convention) are oriented when the mesh is uploaded (orient_cells), so every path draws them as
// their positive versions.
//
// Ownership: move-only through std::unique_ptr; its GL objects belong to the context current
// when it was made, which must be current for every call and for destruction.
// Preconditions: the mesh passed validate_mesh() (indices in range, finite values).
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "mesh/face_topology.hpp"
#include "projector/polyhedron_projector.hpp"
#include "fx/transfer_function.hpp"
#include "gl/gl_object.hpp"
#include "gl/program_cache.hpp"
#include "gl/shader_library.hpp"

namespace cellfx::fx {

// A projector program in two variants: without and with the scene's depth (SCENE_DEPTH defined,
// project.glsl). Testing against the scene costs every fragment a fetch and two divisions, and
// Mesa's llvmpipe runs a branch's code whether or not a fragment takes it, so the test is
// compiled in only for frames that have a scene depth.
struct ProgramVariants {
    const gl::Program* plain = nullptr;
    const gl::Program* with_scene_depth = nullptr;
    const gl::Program& operator()(bool scene_depth) const { return scene_depth ? *with_scene_depth : *plain; }
};

class GlProjector {
public:
    // Uploads the mesh and field (see CellRenderer's constructor) and the function's tables.
    GlProjector(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf);
    GlProjector(const GlProjector&) = delete;
    GlProjector& operator=(const GlProjector&) = delete;

    // As CellRenderer::set_mesh / set_scalars / set_transfer_function. set_scalars returns
    // whether the transfer function in use changed too (a normalized one follows the range).
    void set_mesh(const CellMesh& mesh, const std::string& scalar_name);
    bool set_scalars(const std::vector<float>& values);
    void set_transfer_function(const TransferFunction& tf);

    // The mesh as drawn: inverted cells oriented (orient_cells), fields cleared (the geometry
    // has the one in use).
    const CellMesh& mesh() const { return mesh_; }
    const ProjectorGeometry& geometry() const { return geometry_; }
    const TransferFunction& transfer_function() const { return transfer_; } // in the field's units
    std::size_t gpu_bytes() const { return bytes_; }

    // A program of the projector's shader library (projector_interface.glsl included), linked
    // once per context and shared with every other renderer in it. The mesh's programs get
    // VERTICES_PER_CELL (see mesh_defines()).
    const gl::Program& program(std::initializer_list<std::string_view> stages, const gl::Defines& defines = {}) const;
    // Both variants of a program (ProgramVariants).
    ProgramVariants programs(std::initializer_list<std::string_view> stages, gl::Defines defines = {}) const;
    // VERTICES_PER_CELL for this mesh.
    gl::Defines mesh_defines() const;

    // ---- drawing the mesh ---------------------------------------------------------------------
    int vertices_per_cell() const { return vertices_per_cell_; }
    bool all_tetrahedra() const { return vertices_per_cell_ == 4; }
    // Cell c's triangles in the element buffer: 3 vertex ids per triangle from 3·first, first =
    // geometry().cell_first_triangle[c]; id = c·V + k for the cell's vertex k.
    const std::vector<std::uint32_t>& cell_triangle_vertices() const { return cell_triangle_vertices_; }
    // Binds the mesh's buffer textures and tables (the units of gl_interface.hpp), and the
    // vertex array whose element buffer is cell_triangle_vertices().
    void bind_mesh() const;
    GLuint vertex_array() const { return vertex_array_.id(); }
    GLuint element_buffer() const { return elements_.id(); }
    // Draws the triangles of slots [first_slot, first_slot + slots) of the mesh's own numbering
    // (every cell once: slot = cell), or — for a list of tetrahedra, whose pattern is the same
    // for every slot — of a frame's cell list.
    void draw_slots(std::size_t first_slot, std::size_t slots) const;

    // ---- per frame ----------------------------------------------------------------------------
    ProjectorView view(const Camera& camera) const { return make_projector_view(geometry_, camera); }
    // Sets project.glsl's view, table and fragment-ray uniforms on `program`, for drawing into a
    // target of the viewport's size at the origin (the pass's own; the viewport's position
    // matters to the resolve and the scene depth only).
    void set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const;
    // Sets project.glsl's scene-depth uniforms on `program`, the variant for `scene_depth`
    // (CellRenderOptions::scene_depth; 0: none).
    void set_scene_depth_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport,
                                  unsigned int scene_depth) const;
    // Binds (or with 0 unbinds) the scene's depth texture on its unit.
    static void bind_scene_depth(unsigned int texture);

    // Tetrahedra made for this frame (4 point ids each, positively oriented): their planes and
    // scalar functions go after the mesh's triangles; a cell list names tetrahedron i as
    // kPieceBit | i (cells.vert reads its points from here, its word is
    // cell_word(triangle_count() + 4·i, 4)). Grows the buffers when needed.
    void upload_pieces(const std::vector<std::uint32_t>& tetrahedra);

    // True if some cell may be cut by the near plane of `view` (a corner of the bounds lies
    // in front of it).
    bool mesh_crosses_near_plane(const ProjectorView& view) const;
    // Appends the cap polygon k of `caps` as fan triangles for caps.vert: two uvec4 per vertex,
    // (x, y, z, scalar bits) and (d_min bits, Δd bits, 0, 0).
    static void append_cap_vertices(const NearCaps& caps, const ProjectedCells& projected, std::size_t k,
                                    std::vector<glm::uvec4>& out);
    // Uploads `data` into the per-frame storage buffer (grown as needed, never shrunk) and
    // binds it at BINDING_FRAME.
    void upload_frame(const std::vector<glm::uvec4>& data);

    // ---- unique faces (mip) -------------------------------------------------------------------
    // Each face shared by two cells once, boundary faces once: point ids per triangle (made on
    // first use, after the mesh's face topology) on UNIT_UNIQUE_FACES.
    std::size_t unique_face_triangles();
    void bind_unique_faces();

private:
    void upload_mesh(const CellMesh& source, const std::string& scalar_name);
    void upload_point_data();
    void upload_tables(const TransferFunction& tf);
    void scalar_functions(std::vector<glm::vec4>& out) const; // per triangle, from the geometry's scalars
    gl::Texture& attach(gl::Texture& texture, GLenum format, GLuint buffer);
    std::size_t gpu_capacity_bytes() const;
    // The nearest and deepest corners of the mesh's bounds beyond the near plane of `view`
    // (ProjectorView::depth).
    glm::dvec2 bounds_depth_range(const ProjectorView& view) const;
    // The projection the passes rasterise with (set_view_uniforms): the camera's, except that
    // no cell is cut at its far plane: a perspective view's far at infinity, an orthographic
    // one's at `ortho_far`; the near plane at `near` (ProjectorView::near_distance).
    static glm::dmat4 raster_projection(const Camera& camera, double near, double aspect, double ortho_far);

    std::shared_ptr<gl::ProgramCache> programs_;
    CellMesh mesh_;
    ProjectorGeometry geometry_;
    ScalarRange field_range_;
    Bounds bounds_; // of the relative positions
    TransferFunction source_tf_; // as given: normalized ones are rescaled when the field changes
    TransferFunction transfer_;  // as in use
    int vertices_per_cell_ = 8;
    std::vector<std::uint32_t> cell_triangle_vertices_;
    // What the buffers were filled from, kept so that a new mesh of similar size (terrain
    // prisms, every frame) and new scalars allocate nothing.
    std::vector<glm::vec4> point_data_, barycentrics_data_;
    std::vector<std::uint32_t> words_;

    // Grown, never shrunk; planes and scalar functions have room after the mesh's triangles for
    // a frame's tetrahedra (upload_pieces).
    gl::GrowingBuffer points_, connectivity_, cell_offsets_, cell_words_, planes_, scalar_fns_, barycentrics_, elements_;
    gl::Texture points_texture_, connectivity_texture_, cell_offsets_texture_, cell_words_texture_, planes_texture_,
        scalar_fns_texture_, barycentrics_texture_;
    gl::VertexArray vertex_array_;
    gl::Buffer tables_buffer_;
    gl::Texture tables_;
    double s_lo_ = 0.0, s_hi_ = 1.0;
    std::size_t bytes_ = 0;
    // Pieces of a frame.
    gl::GrowingBuffer piece_points_;
    gl::Texture piece_points_texture_;
    std::vector<glm::vec4> piece_data_, function_scratch_;
    // Unique faces (mip).
    std::vector<glm::uvec4> unique_faces_; // point ids, w unused
    FaceTopology topology_;                // kept with its scratch: a new mesh every frame allocates nothing
    FaceTopologyScratch topology_scratch_;
    gl::GrowingBuffer unique_faces_buffer_;
    gl::Texture unique_faces_texture_;
    bool unique_faces_ready_ = false;
    // Per-frame storage buffer (caps).
    gl::GrowingBuffer frame_;
};

// A frame's list of cells to draw through the projector (absorption-exact's visibility order,
// classic pcp's batches): entry `slot` names a cell (or kPieceBit | a tetrahedron of
// upload_pieces), and for cells other than tetrahedra the element buffer lists each entry's
// triangles in the slot numbering. Buffers grow and are kept between frames.
class GlCellList {
public:
    explicit GlCellList(const GlProjector& projector);
    // The frame's entries; `ranges` (may be empty) is a (d_min, Δd) per slot for classic pcp.
    // Builds the element buffer when the mesh needs one (each cell's own triangles; a
    // tetrahedron's for kPieceBit entries).
    void upload(const std::vector<std::uint32_t>& cells, const std::vector<glm::vec2>& ranges);
    // Binds the list (UNIT_CELL_LIST, UNIT_SLOT_DATA) and the vertex array to draw it, and sets
    // UNIFORM_PIECE_BASE on `program` (cells.vert with CELL_LIST).
    void bind(const gl::Program& program) const;
    // Draws entries [first, first + count) (by their triangles; 3 vertices each).
    void draw(std::size_t first, std::size_t count) const;
    std::size_t size() const { return slots_; }
    std::size_t gpu_bytes() const { return cells_.capacity() + slot_data_.capacity() + elements_.capacity(); }

private:

    const GlProjector& projector_;
    gl::GrowingBuffer cells_, slot_data_, elements_;
    gl::Texture cells_texture_, slot_data_texture_;
    gl::VertexArray vertex_array_;
    std::size_t slots_ = 0;
    std::vector<std::uint32_t> elements_data_;
    std::vector<std::size_t> first_element_; // per slot + 1 (cells other than tetrahedra)
};

} // namespace cellfx::fx
