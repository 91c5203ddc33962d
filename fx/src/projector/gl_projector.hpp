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
// Where the tables are built. The CPU keeps the mesh (oriented) and the geometry's positions and
// triangles; the per-triangle tables the fragment shaders read — planes, scalar functions,
// barycentric rows — and the element buffer are built on the GPU from the points and the
// connectivity (shaders/projector_tables.comp; docs/render_paths.md says why), once for a new
// mesh and, after update_mesh(), only for the cells it changed: their points and connectivity are
// uploaded as records written into place (gl::ScatterPass), each stamped with the update's
// number, and the tables pass rebuilds the cells with a stamp newer than its last build. A CPU pass that needs the planes (classic pcp, the absorption paths, the
// near-plane caps) gets them from geometry(), computed on the CPU when first asked after a change.
// With culling on (set_culling: meshes much larger than the view, such as terrain fog) the same
// pass writes each cell's triangles only when its box meets the view (prepare_draw).
//
// How the mesh is drawn. A cell's vertices are vertex ids slot·V + k (k < V = vertices_per_cell():
// 4 when every cell is a tetrahedron, else 8), so that a cell's vertex is transformed once
// however many of its triangles use it; cells.vert finds the cell of `slot` — the slot itself,
// or entry `slot` of a frame's cell list (GlCellList) — fetches its point, and hands the
// fragment shader the cell's word as one flat integer. The element buffer lists each cell's
// face triangles in that numbering (quads cut by their smallest-vertex diagonal, as
// everywhere); a frame's cell list (GlCellList) has one of its own. Per-cell data is fetched by the fragment
// shaders from buffer textures, not passed down as varyings: on Mesa's llvmpipe the varyings'
// set-up and gl_PrimitiveID run on one thread before rasterisation, the fetches on every core.
//   points            vec4 per point (position in the relative frame, scalar)
//   connectivity      the mesh's cell_vertices, cell offsets
//   cell words        per cell, cell_word(first triangle, triangle count), its planar bit set
//                     by the tables' pass (gl_interface.hpp)
//   planes            per face triangle: outward unit normal n, n·p
//   scalar functions  per face triangle: (g, s0), the scalar on it is g·q + s0 (a
//                     tetrahedron's: its own linear function, on every face)
//   barycentrics      per face triangle of a cell that is not planar, two rows: b1 = r1·q + r1w,
//                     b2 = r2·q + r2w (meshes with cells other than tetrahedra: the exact
//                     paths' entry search), from row pair fold base + k on
//   fold bases        per cell, where its rows start: compact (only cells that are not planar
//                     have rows, in cell order; laid out by the CPU from the planar bits the
//                     GPU decided, read back once per mesh) or, once the renderer has taken an
//                     in-place update, by slot (fold base = first triangle), see the members
//   except for planar cells (the planar bit of their word; gl_interface.hpp: kPlanarTolerance),
//   whose fragments clip their ray by the faces' planes with no search: in the same slots their
//   F faces' planes, then their Q quads' diagonal planes (which side of the diagonal is the
//   quad's first half), the scalar function of each face's first half, then of each quad's
//   second half (F + Q is the cell's triangle count), no barycentric rows
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
#include "gl/scatter_pass.hpp"
#include "gl/shader_library.hpp"
#include "projector/gl_interface.hpp"

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

// The per-triangle tables and the element buffer of a mesh (gl_projector's "where the tables are
// built"): in each cell's triangle slots its planes, scalar functions and (meshes with cells
// other than tetrahedra) two barycentric rows per slot — a planar cell's laid out by face, any
// other's by triangle; a planar cell's rows zero (read_tables lays the GPU's rows out so,
// whatever their layout there) — and per face triangle its three vertex ids cell·V + k; per
// cell its word (gl_interface.hpp: cell_word, with the planar bit).
struct ProjectorTables {
    std::vector<glm::vec4> planes, scalar_functions, barycentrics;
    std::vector<std::uint32_t> elements, words;
    // build_projector_tables only: per cell, how far inside kPlanarTolerance its planar test
    // passed, relative to it (negative: failed; near 0: on the border, where the GPU's rounding
    // may decide otherwise).
    std::vector<double> planar_margins;
};
// The same tables built on the CPU from the oriented mesh and its geometry, with the formulas and
// float inputs the GPU's pass uses: the reference a GPU build is checked against.
ProjectorTables build_projector_tables(const CellMesh& mesh, const ProjectorGeometry& geometry, int vertices_per_cell,
                                       double planar_tolerance = kPlanarTolerance);

// The projector's GPU buffers by who reads them, in bytes (their capacity).
struct ProjectorMemory {
    std::size_t mesh = 0;         // points, connectivity, cell offsets and words, stamps, transfer tables
    std::size_t cell_tables = 0;  // planes, scalar functions, barycentric rows, elements, a frame's pieces:
                                  // the exact paths' (pcp-exact, absorption-exact)
    std::size_t barycentric_rows = 0; // of cell_tables: the rows (compact: only cells that are not planar)
    std::size_t unique_faces = 0; // mip's (made on first use)
};

class GlProjector {
public:
    // Uploads the mesh and field (see CellRenderer's constructor) and the function's tables.
    GlProjector(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf);
    GlProjector(const GlProjector&) = delete;
    GlProjector& operator=(const GlProjector&) = delete;

    // As CellRenderer::set_mesh / update_mesh / set_scalars / set_transfer_function.
    // update_mesh returns false when it replaced the mesh whole instead (see
    // CellRenderer::update_mesh); set_scalars whether the transfer function in use changed too (a
    // normalized one follows the range).
    void set_mesh(const CellMesh& mesh, const std::string& scalar_name);
    bool update_mesh(const CellMesh& mesh, const std::string& scalar_name, const MeshChanges& changes);
    bool set_scalars(const std::vector<float>& values);
    void set_transfer_function(const TransferFunction& tf);
    // Culling (default off): prepare_draw() leaves out of the element buffer the cells whose box
    // lies outside the view's side and near planes.
    void set_culling(bool culling);
    // The planar test's tolerance (default kPlanarTolerance, gl_interface.hpp; negative: no cell
    // is planar, every one searches its triangles), for tests that hold both fragment roads to
    // the same picture. The tables are rebuilt at the next draw.
    void set_planar_tolerance(double tolerance);
    double planar_tolerance() const { return planar_tolerance_; }

    // The mesh as drawn: inverted cells oriented (orient_cells), fields cleared (the geometry
    // has the one in use).
    const CellMesh& mesh() const { return mesh_; }
    // With its triangle planes (computed on the CPU here when a change has left them stale).
    const ProjectorGeometry& geometry() const;
    const TransferFunction& transfer_function() const { return transfer_; } // in the field's units
    std::size_t gpu_bytes() const { return bytes_; }
    ProjectorMemory memory() const;

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
    const std::vector<std::uint32_t>& cell_triangle_vertices() const {
        flush_triangles();
        return cell_triangle_vertices_;
    }
    const std::vector<std::uint32_t>& cell_first_triangle() const { return geometry_.cell_first_triangle; }
    std::size_t triangle_count() const { return geometry_.triangles.size(); }
    // Binds the mesh's buffer textures and tables (the units of gl_interface.hpp), and the
    // vertex array whose element buffer holds the cells' triangles (culled with culling on).
    void bind_mesh() const;
    GLuint vertex_array() const { return vertex_array_.id(); }
    // Draws the triangles of cells [first, first + count) of the mesh's own numbering (after
    // prepare_draw for this view).
    void draw_slots(std::size_t first, std::size_t count) const;

    // ---- per frame ----------------------------------------------------------------------------
    // Brings the GPU tables up to date with the mesh (and, with culling, the element buffer with
    // this view): every pass calls it before drawing the mesh. A no-op when nothing changed.
    void prepare_draw(const Camera& camera, const Viewport& viewport);
    // The same without a view (the element buffer left as the last view culled it).
    void prepare_tables();
    // The GPU's tables read back (tests; with culling off its element buffer is every cell's).
    ProjectorTables read_tables();
    ProjectorView view(const Camera& camera) const { return make_projector_view(geometry_, camera); }
    // Sets project.glsl's view, table and fragment-ray uniforms on `program`, for drawing into a
    // target of the viewport's size at the origin (the pass's own; the viewport's position
    // matters to the resolve and the scene depth only).
    void set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const;
    // The pixels of a target of the viewport's size (at the origin) the mesh can cover in
    // `camera`'s view, as (x, y, width, height): its bounding box's projection, a pixel wider,
    // clamped; the whole target where the box crosses the near plane, (0, 0, 0, 0) when it lies
    // off screen or before the near plane. The frame's clear and resolve are cut to it (CellRenderer::render).
    glm::ivec4 screen_rect(const Camera& camera, const Viewport& viewport) const;
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
    // binds it at BINDING_FRAME; bind_frame() binds it again.
    void upload_frame(const std::vector<glm::uvec4>& data);
    void bind_frame() const;

    // ---- unique faces (mip) -------------------------------------------------------------------
    // Each face shared by two cells once, boundary faces once: point ids per triangle (made on
    // first use, after the mesh's face topology) on UNIT_UNIQUE_FACES.
    std::size_t unique_face_triangles();
    void bind_unique_faces();

private:
    void upload_mesh(const CellMesh& source, const std::string& scalar_name);
    // update_mesh's work once it has checked the changes apply in place.
    // Returns the field's range after the changes.
    ScalarRange apply_changes(const CellMesh& source, const ScalarField* field, const MeshChanges& changes);
    void upload_point_data();
    void upload_tables(const TransferFunction& tf);
    // Room in the stamps for the mesh's cells and points and, once a pass has asked for them
    // (tables_reserved_), in the table buffers (planes, scalar functions, barycentrics, elements)
    // for its triangles; with `keep`, what is built stays.
    void reserve_tables(bool keep);
    // The cell's triangles (geometry_.triangles, cell_triangle_vertices_) from its connectivity;
    // flush_triangles() those of the cells update_mesh changed (left until a CPU pass asks).
    void triangulate_cell(std::size_t cell) const;
    void flush_triangles() const;
    // prepare_draw's work; `view` null: no view to cull for.
    void build_tables(const Camera* view, double aspect);
    // After the tables pass `program` decided the planar bits with compact rows: reads them
    // back, gives each cell that is not planar its row pairs and runs the pass for the rows.
    void lay_out_rows(GLuint program);
    gl::Texture& attach(gl::Texture& texture, GLenum format, GLuint buffer);
    std::size_t gpu_capacity_bytes() const;
    // The nearest and deepest corners of the mesh's bounds beyond the near plane of `view`
    // (ProjectorView::depth).
    glm::dvec2 bounds_depth_range(const ProjectorView& view) const;
    // The projection the passes rasterise with (set_view_uniforms): the camera's, except that
    // no cell is cut at its far plane: a perspective view's far at infinity, an orthographic
    // one's at `ortho_far`; the near plane at `near` (ProjectorView::near_distance).
    static glm::dmat4 raster_projection(const Camera& camera, double near, double aspect, double ortho_far);
    // raster_projection · the view, for the viewport's aspect (and its orthographic far plane).
    glm::dmat4 raster_view_projection(const Camera& camera, const Viewport& viewport, double* ortho_far) const;

    std::shared_ptr<gl::ProgramCache> programs_;
    CellMesh mesh_;
    mutable ProjectorGeometry geometry_;
    mutable bool planes_stale_ = false; // geometry_.triangle_planes (the GPU's are always current)
    ScalarRange field_range_;
    Bounds bounds_; // of the relative positions
    TransferFunction source_tf_; // as given: normalized ones are rescaled when the field changes
    TransferFunction transfer_;  // as in use
    int vertices_per_cell_ = 8;
    double planar_tolerance_ = kPlanarTolerance;
    mutable std::vector<std::uint32_t> cell_triangle_vertices_;
    mutable std::vector<std::uint32_t> untriangulated_; // cells whose CPU triangles are stale
    mutable std::vector<std::uint8_t> triangles_stale_; // per cell: in untriangulated_
    // What the buffers were filled from, kept so that a new mesh of similar size (terrain
    // prisms, every frame) and new scalars allocate nothing.
    std::vector<glm::vec4> point_data_;
    std::vector<std::uint32_t> words_;

    // Grown, never shrunk; planes and scalar functions have room after the mesh's triangles for
    // a frame's tetrahedra (upload_pieces).
    gl::GrowingBuffer points_, connectivity_, cell_offsets_, cell_words_, planes_, scalar_fns_, barycentrics_, fold_bases_,
        elements_;
    gl::Texture points_texture_, connectivity_texture_, cell_offsets_texture_, cell_words_texture_, planes_texture_,
        scalar_fns_texture_, barycentrics_texture_, fold_bases_texture_;
    // The barycentric rows' layout (meshes with cells other than tetrahedra): compact — only
    // the cells that are not planar have rows, fold_bases_ says where — until the renderer's
    // first in-place update, whose changed points may fold any cell the GPU rebuilds (the CPU
    // would have to read the count back every update to size the rows): from then on, for this
    // and every later mesh, by slot, as the planes (fold base = first triangle).
    bool updated_in_place_ = false, compact_rows_ = true;
    bool rows_laid_out_ = false;  // compact: fold_bases_ matches the planar bits (new scalars keep them)
    std::size_t fold_rows_ = 0;   // compact: row pairs laid out
    std::vector<std::uint32_t> laid_out_words_, fold_base_data_; // lay_out_rows' (kept)
    gl::VertexArray vertex_array_;
    gl::Buffer tables_buffer_;
    gl::Texture tables_;
    double s_lo_ = 0.0, s_hi_ = 1.0;
    std::size_t bytes_ = 0;
    // Pieces of a frame.
    gl::GrowingBuffer piece_points_;
    gl::Texture piece_points_texture_;
    std::vector<glm::vec4> piece_data_;
    // Unique faces (mip).
    std::vector<glm::uvec4> unique_faces_; // point ids, w unused
    FaceTopology topology_;                // kept with its scratch: a new mesh every frame allocates nothing
    FaceTopologyScratch topology_scratch_;
    gl::GrowingBuffer unique_faces_buffer_;
    gl::Texture unique_faces_texture_;
    bool unique_faces_ready_ = false;
    // Per-frame storage buffer (caps).
    gl::GrowingBuffer frame_;
    // The tables' compute pass: point and cell stamps (the update that last changed each), the
    // stamp of the latest update and of the last build; the changed points' and cells' values
    // written into place (made on the first update_mesh).
    gl::GrowingBuffer point_stamps_, cell_stamps_;
    std::uint32_t stamp_ = 0, built_stamp_ = 0;
    bool build_all_ = true;   // the next build covers every cell (a new mesh, new scalars)
    // The cell tables are allocated at the first build_tables (prepare_draw): pcp, mip and
    // classic absorption never read them, so a renderer only they draw with keeps none.
    bool tables_reserved_ = false;
    bool elements_all_ = true; // and writes every cell's triangles (a new mesh or view)
    std::unique_ptr<gl::ScatterPass> point_scatter_, cell_scatter_;
    const gl::Program* tables_program_ = nullptr; // for meshes of tables_program_cells_ vertices per cell
    int tables_program_cells_ = 0;
    // Culling: on or off, the planes of the view the element buffer was last written for.
    bool culling_ = false, culled_view_valid_ = false;
    Camera culled_camera_;
    double culled_aspect_ = 0.0;
};

// A frame's list of cells to draw through the projector (absorption-exact's visibility order,
// classic pcp's batches): entry `slot` names a cell (or kPieceBit | a tetrahedron of
// upload_pieces), and the element buffer lists each entry's triangles in the slot numbering (for
// tetrahedra the same pattern in every slot, made once per size). Buffers grow and are kept
// between frames.
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
    std::size_t tetra_slots_ = 0; // slots the element buffer has the tetrahedron pattern for
    gl::Texture cells_texture_, slot_data_texture_;
    gl::VertexArray vertex_array_;
    std::size_t slots_ = 0;
    std::vector<std::uint32_t> elements_data_;
    std::vector<std::size_t> first_element_; // per slot + 1 (cells other than tetrahedra)
};

} // namespace cellfx::fx
