// Based on: Roettger & Ertl 2003, §3 (the projector) and §5 (near-plane caps).
#include "projector/gl_projector.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/type_ptr.hpp>

#include "fx/error.hpp"
#include "fx/segment_integral.hpp"
#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"

namespace fx {
namespace {

constexpr int kTableSize = 4096;

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

} // namespace

GlProjector::GlProjector(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf)
    : programs_(gl::ProgramCache::for_current_context()) {
    upload_mesh(mesh, scalar_name);
    tables_ = gl::make_texture_2d(GL_RGBA32F, kTableSize, 2);
    set_transfer_function(tf);
}

const gl::Program& GlProjector::program(std::initializer_list<std::string_view> stages,
                                        const gl::Defines& defines) const {
    return programs_->program(projector_shader_library(), stages, defines);
}

void GlProjector::set_mesh(const CellMesh& mesh, const std::string& scalar_name) {
    upload_mesh(mesh, scalar_name);
    set_transfer_function(source_tf_);
}

void GlProjector::set_scalars(const std::vector<float>& values) {
    if (values.size() != geometry_.scalars.size())
        throw Error("cell renderer: set_scalars got " + std::to_string(values.size()) + " values for " +
                    std::to_string(geometry_.scalars.size()) + " points");
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) throw Error("cell renderer: set_scalars: value " + std::to_string(i) + " is not finite");
    geometry_.scalars = values;
    std::vector<glm::vec4> point_data(std::max<std::size_t>(values.size(), 1));
    for (std::size_t i = 0; i < values.size(); ++i) point_data[i] = glm::vec4(geometry_.positions[i], values[i]);
    glNamedBufferSubData(points_.id(), 0, GLsizeiptr(point_data.size() * sizeof(glm::vec4)), point_data.data());
    FX_GL_CHECK("set_scalars upload");
    field_range_ = values.empty() ? ScalarRange{0.0f, 0.0f} : ScalarRange{values[0], values[0]};
    for (float v : values) field_range_.lo = std::min(field_range_.lo, v), field_range_.hi = std::max(field_range_.hi, v);
    if (source_tf_.normalized()) set_transfer_function(source_tf_); // its tables follow the range
}

void GlProjector::set_transfer_function(const TransferFunction& tf) {
    source_tf_ = tf;
    transfer_ = tf.normalized() ? tf.rescaled(field_range_.lo, std::max(field_range_.hi, field_range_.lo + 1e-30f)) : tf;
    upload_tables(transfer_);
}

void GlProjector::upload_mesh(const CellMesh& source, const std::string& scalar_name) {
    const ScalarField* field = nullptr;
    if (!scalar_name.empty()) {
        field = source.find_scalar(scalar_name);
        if (!field) throw Error("cell renderer: the mesh has no scalar field '" + scalar_name + "'");
    } else if (!source.scalars.empty()) {
        field = &source.scalars[0];
    }
    geometry_ = build_projector_geometry(source, field);
    field_range_ = field ? scalar_range(*field) : ScalarRange{0.0f, 0.0f};
    mesh_ = source;
    mesh_.scalars.clear(); // the geometry holds the one field in use

    const std::size_t np = geometry_.positions.size(), nt = geometry_.triangles.size();
    bounds_lo_ = glm::dvec3(1e300), bounds_hi_ = glm::dvec3(-1e300);
    std::vector<glm::vec4> point_data(std::max<std::size_t>(np, 1));
    for (std::size_t i = 0; i < np; ++i) {
        point_data[i] = glm::vec4(geometry_.positions[i], geometry_.scalars[i]);
        bounds_lo_ = glm::min(bounds_lo_, glm::dvec3(geometry_.positions[i]));
        bounds_hi_ = glm::max(bounds_hi_, glm::dvec3(geometry_.positions[i]));
    }
    struct GpuTriangle {
        glm::uvec4 v;
        glm::vec4 plane;
    };
    std::vector<GpuTriangle> triangle_data(std::max<std::size_t>(nt, 1));
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& tri = geometry_.triangles[t];
        triangle_data[t] = {glm::uvec4(tri[0], tri[1], tri[2], geometry_.triangle_cell[t]), geometry_.triangle_planes[t]};
    }
    // Dynamic storage: set_scalars rewrites it in place.
    points_ = gl::make_buffer(GLsizeiptr(point_data.size() * sizeof(glm::vec4)), point_data.data(), GL_DYNAMIC_STORAGE_BIT);
    triangles_ = gl::make_buffer(GLsizeiptr(triangle_data.size() * sizeof(GpuTriangle)), triangle_data.data());
    cells_ = gl::make_buffer(GLsizeiptr(geometry_.cell_first_triangle.size() * sizeof(std::uint32_t)),
                             geometry_.cell_first_triangle.data());
    bytes_ = point_data.size() * sizeof(glm::vec4) + triangle_data.size() * sizeof(GpuTriangle) +
             geometry_.cell_first_triangle.size() * sizeof(std::uint32_t) + std::size_t(kTableSize) * 2 * 16;
    // The CPU copy of planes and triangles is only needed for caps; triangles stay (caps walk
    // them), positions stay (projection). Planes are GPU-only from here on.
    geometry_.triangle_planes = {};
}

void GlProjector::upload_tables(const TransferFunction& tf) {
    // Row 0: E(s) from build_emission_table (rgb) and the same for unit colour, i.e. ∫σ (a).
    const EmissionTable emission = build_emission_table(tf, kTableSize);
    std::vector<TransferPoint> white = tf.points();
    for (TransferPoint& p : white) p.color = glm::dvec3(1.0);
    const EmissionTable extinction = build_emission_table(TransferFunction(white), kTableSize);
    s_lo_ = emission.s_lo;
    s_hi_ = emission.s_hi;
    std::vector<glm::vec4> texels(2 * kTableSize);
    for (int i = 0; i < kTableSize; ++i) {
        texels[i] = glm::vec4(emission.cumulative[i], extinction.cumulative[i].x);
        // Row 1: point values c·σ and σ at the samples (the held end values come from here).
        const double s = i + 1 == kTableSize ? s_hi_ : s_lo_ + (s_hi_ - s_lo_) * double(i) / (kTableSize - 1);
        texels[kTableSize + i] = glm::vec4(glm::vec3(tf.emission(s)), float(tf.sigma(s)));
    }
    glTextureSubImage2D(tables_.id(), 0, 0, 0, kTableSize, 2, GL_RGBA, GL_FLOAT, texels.data());
    FX_GL_CHECK("glTextureSubImage2D(tables)");
}

glm::mat4 GlProjector::view_projection(const Camera& camera, const Viewport& viewport) const {
    const double aspect = double(viewport.width) / double(viewport.height);
    return glm::mat4(camera.projection_matrix(aspect) * view(camera).view);
}

void GlProjector::bind_mesh() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingPoints, points_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingTriangles, triangles_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingCells, cells_.id());
    glBindTextureUnit(kUnitTables, tables_.id());
    glBindSampler(kUnitTables, 0);
    FX_GL_CHECK("bind mesh");
}

void GlProjector::set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const {
    const ProjectorView v = view(camera);
    const glm::mat4 vp = view_projection(camera, viewport);
    const glm::vec3 eye(v.eye), forward(v.forward);
    const double span = s_hi_ - s_lo_;
    const glm::vec4 table(float(s_lo_), float(s_hi_), float(kTableSize), span > 0.0 ? float((kTableSize - 1) / span) : 0.0f);
    const GLuint p = program.id();
    glProgramUniformMatrix4fv(p, kUniformViewProjection, 1, GL_FALSE, glm::value_ptr(vp));
    glProgramUniform3fv(p, kUniformEye, 1, glm::value_ptr(eye));
    glProgramUniform3fv(p, kUniformForward, 1, glm::value_ptr(forward));
    glProgramUniform1f(p, kUniformNear, float(v.near_distance));
    glProgramUniform1i(p, kUniformOrthographic, v.orthographic ? 1 : 0);
    glProgramUniform4fv(p, kUniformTable, 1, glm::value_ptr(table));
    FX_GL_CHECK("view uniforms");
}

void GlProjector::set_scene_depth_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport,
                                           unsigned int scene_depth) const {
    // Mode 0: no scene depth; 1: perspective window depth; 2: orthographic (project.glsl).
    const GLint mode = scene_depth == 0 ? 0 : (camera.orthographic() ? 2 : 1);
    const GLuint p = program.id();
    glProgramUniform1i(p, kUniformSceneDepthMode, mode);
    glProgramUniform2f(p, kUniformSceneDepthRange, float(camera.near_distance), float(camera.far_distance));
    glProgramUniform2i(p, kUniformSceneOrigin, viewport.x, viewport.y);
    FX_GL_CHECK("scene depth uniforms");
}

void GlProjector::bind_scene_depth(unsigned int texture) {
    glBindTextureUnit(kUnitSceneDepth, texture);
    glBindSampler(kUnitSceneDepth, 0);
    FX_GL_CHECK("scene depth");
}

bool GlProjector::mesh_crosses_near_plane(const ProjectorView& v) const {
    if (geometry_.positions.empty()) return false;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 c((k & 1) ? bounds_hi_.x : bounds_lo_.x, (k & 2) ? bounds_hi_.y : bounds_lo_.y,
                           (k & 4) ? bounds_hi_.z : bounds_lo_.z);
        if (v.depth(c) <= 0.0) return true;
    }
    return false;
}

void GlProjector::append_cap_vertices(const NearCaps& caps, const ProjectedCells& projected, std::size_t k,
                                      std::vector<glm::uvec4>& out) {
    const std::uint32_t b = caps.first_vertex[k], e = caps.first_vertex[k + 1];
    const glm::vec2 range = projected.depth_range[caps.cell[k]];
    auto vertex = [&](std::uint32_t v) {
        const glm::vec3& p = caps.positions[v];
        out.emplace_back(bits(p.x), bits(p.y), bits(p.z), bits(caps.scalars[v]));
        out.emplace_back(bits(range.x), bits(range.y), 0u, 0u);
    };
    for (std::uint32_t v = b + 1; v + 1 < e; ++v) { // fan: convex polygon
        vertex(b), vertex(v), vertex(v + 1);
    }
}

void GlProjector::upload_frame(const std::vector<glm::uvec4>& data) {
    const std::size_t n = std::max<std::size_t>(data.size(), 1);
    if (n > frame_capacity_) {
        frame_capacity_ = std::max(n, frame_capacity_ * 3 / 2);
        frame_ = gl::make_buffer(GLsizeiptr(frame_capacity_ * sizeof(glm::uvec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    if (!data.empty()) glNamedBufferSubData(frame_.id(), 0, GLsizeiptr(data.size() * sizeof(glm::uvec4)), data.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingFrame, frame_.id());
    FX_GL_CHECK("upload frame data");
}

} // namespace fx
