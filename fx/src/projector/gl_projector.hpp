// cellfx — the GL side of the polyhedron projector: the one layer every GPU render path draws
// through.
//
// Based on: Roettger & Ertl 2003, §3 (the projector) and §5 (near-plane caps).
//
// Owns, per mesh and scalar field: the CPU projector's geometry (polyhedron_projector.hpp), the
// mesh's GPU buffers (points, face triangles and planes, cell ranges), the transfer function's
// tables, one growable per-frame buffer, and the context's shared programs (ProgramCache). Gives
// the passes above it (pcp, pcp-exact, mip, the absorption paths: fx/src/passes/, and the
// dispatcher fx::CellRenderer above them) everything they share: the view and scene-depth
// uniforms of gl_interface.hpp's table, the bindings, the near-plane caps as triangles. It
// includes nothing from the passes or the dispatcher.
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
#include <glm/vec4.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/polyhedron_projector.hpp"
#include "fx/transfer_function.hpp"
#include "gl/gl_object.hpp"
#include "gl/program_cache.hpp"
#include "gl/shader_library.hpp"

namespace fx {

class GlProjector {
public:
    // Uploads the mesh and field (see CellRenderer's constructor) and the function's tables.
    GlProjector(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf);
    GlProjector(const GlProjector&) = delete;
    GlProjector& operator=(const GlProjector&) = delete;

    // As CellRenderer::set_mesh / set_scalars / set_transfer_function.
    void set_mesh(const CellMesh& mesh, const std::string& scalar_name);
    void set_scalars(const std::vector<float>& values);
    void set_transfer_function(const TransferFunction& tf);

    const CellMesh& mesh() const { return mesh_; } // topology (its fields cleared: geometry has the one in use)
    const ProjectorGeometry& geometry() const { return geometry_; }
    const TransferFunction& transfer_function() const { return transfer_; } // in the field's units
    std::size_t gpu_bytes() const { return bytes_; }

    // A program of the projector's shader library (projector_interface.glsl included), linked
    // once per context and shared with every other renderer in it.
    const gl::Program& program(std::initializer_list<std::string_view> stages, const gl::Defines& defines = {}) const;

    // ---- per frame ----------------------------------------------------------------------------
    ProjectorView view(const Camera& camera) const { return make_projector_view(geometry_, camera); }
    // Relative frame → clip space for this viewport.
    glm::mat4 view_projection(const Camera& camera, const Viewport& viewport) const;
    // Binds the mesh buffers and the tables (the bindings of gl_interface.hpp).
    void bind_mesh() const;
    // Sets project.glsl's view and table uniforms on `program`.
    void set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const;
    // Sets project.glsl's scene-depth uniforms on `program` (mode 0 without a scene depth).
    // `scene_depth` is CellRenderOptions::scene_depth.
    void set_scene_depth_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport,
                                  unsigned int scene_depth) const;
    // Binds (or with 0 unbinds) the scene's depth texture on its unit.
    static void bind_scene_depth(unsigned int texture);

    // True if some cell may be cut by the near plane of `view` (a corner of the bounds lies
    // in front of it).
    bool mesh_crosses_near_plane(const ProjectorView& view) const;
    // Appends the cap polygon k of `caps` as fan triangles for project.vert's SOURCE_CAPS:
    // two uvec4 per vertex, (x, y, z, scalar bits) and (d_min bits, Δd bits, 0, 0).
    static void append_cap_vertices(const NearCaps& caps, const ProjectedCells& projected, std::size_t k,
                                    std::vector<glm::uvec4>& out);
    // Uploads `data` into the per-frame buffer (grown as needed, never shrunk) and binds it.
    void upload_frame(const std::vector<glm::uvec4>& data);

private:
    void upload_mesh(const CellMesh& source, const std::string& scalar_name);
    void upload_tables(const TransferFunction& tf);

    std::shared_ptr<gl::ProgramCache> programs_;
    CellMesh mesh_;
    ProjectorGeometry geometry_;
    ScalarRange field_range_;
    glm::dvec3 bounds_lo_{0.0}, bounds_hi_{0.0}; // of the relative positions
    TransferFunction source_tf_; // as given: normalized ones are rescaled when the field changes
    TransferFunction transfer_;  // as in use

    gl::Buffer points_, triangles_, cells_;
    gl::Buffer frame_;
    std::size_t frame_capacity_ = 0; // uvec4 entries
    gl::Texture tables_;
    double s_lo_ = 0.0, s_hi_ = 1.0;
    std::size_t bytes_ = 0;
};

} // namespace fx
