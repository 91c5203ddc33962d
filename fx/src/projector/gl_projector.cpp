// Based on: Roettger & Ertl 2003, §3 (the projector) and §5 (near-plane caps).
#include "projector/gl_projector.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/trigonometric.hpp>
#include <glm/matrix.hpp>

#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/segment_integral.hpp"
#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"
#include "frame_storage.hpp"

namespace cellfx::fx {
namespace {

constexpr int kTableSize = 4096;

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

struct ScalarPoint {
    glm::dvec3 p;
    double s;
};

// The linear function of a tetrahedron's scalar, (g, s0) with s(q) = g·q + s0; for a flat
// tetrahedron (no volume, so no thickness to integrate) the constant mean.
glm::vec4 tetrahedron_function(const ScalarPoint* v) {
    const glm::dvec3 e1 = v[1].p - v[0].p, e2 = v[2].p - v[0].p, e3 = v[3].p - v[0].p;
    const double det = glm::dot(e1, glm::cross(e2, e3));
    const double size = std::max({glm::length(e1), glm::length(e2), glm::length(e3)});
    if (!(std::abs(det) > 1e-12 * size * size * size))
        return glm::vec4(0.0f, 0.0f, 0.0f, float(0.25 * (v[0].s + v[1].s + v[2].s + v[3].s)));
    const glm::dvec3 g = ((v[1].s - v[0].s) * glm::cross(e2, e3) + (v[2].s - v[0].s) * glm::cross(e3, e1) +
                          (v[3].s - v[0].s) * glm::cross(e1, e2)) /
                         det;
    return glm::vec4(glm::vec3(g), float(v[0].s - glm::dot(g, v[0].p)));
}

// The linear function in the plane of triangle (a, b, c) that takes its vertices' scalars: the
// barycentric interpolation the scan-line reference does, as (g, s0) with g in the plane.
glm::vec4 triangle_function(const ScalarPoint& a, const ScalarPoint& b, const ScalarPoint& c) {
    const glm::dvec3 e1 = b.p - a.p, e2 = c.p - a.p;
    const double e11 = glm::dot(e1, e1), e12 = glm::dot(e1, e2), e22 = glm::dot(e2, e2);
    const double det = e11 * e22 - e12 * e12;
    if (!(det > 1e-24 * e11 * e22)) return glm::vec4(0.0f, 0.0f, 0.0f, float((a.s + b.s + c.s) / 3.0));
    const double db = b.s - a.s, dc = c.s - a.s;
    const glm::dvec3 g = ((db * e22 - dc * e12) * e1 + (dc * e11 - db * e12) * e2) / det;
    return glm::vec4(glm::vec3(g), float(a.s - glm::dot(g, a.p)));
}

// The barycentric coordinates of a point q in the plane of triangle (a, b, c) as two linear
// functions, b1 = r1·q + r1w and b2 = r2·q + r2w (b0 = 1 − b1 − b2): the containment test of the
// exact paths' entry search. A triangle with no area gets zeros (b0 = 1: "inside").
void barycentric_rows(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, glm::vec4* out) {
    const glm::dvec3 e1 = b - a, e2 = c - a;
    const double e11 = glm::dot(e1, e1), e12 = glm::dot(e1, e2), e22 = glm::dot(e2, e2);
    const double det = e11 * e22 - e12 * e12;
    if (!(det > 1e-24 * e11 * e22)) {
        out[0] = out[1] = glm::vec4(0.0f);
        return;
    }
    const glm::dvec3 r1 = (e22 * e1 - e12 * e2) / det, r2 = (e11 * e2 - e12 * e1) / det;
    out[0] = glm::vec4(glm::vec3(r1), float(-glm::dot(r1, a)));
    out[1] = glm::vec4(glm::vec3(r2), float(-glm::dot(r2, a)));
}

// Outward unit plane of triangle (a, b, c) as build_projector_geometry makes it: zero when it
// has no area.
glm::vec4 triangle_plane(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    const double scale = std::max({glm::length(b - a), glm::length(c - a), glm::length(c - b)});
    if (!(len > 1e-12 * scale * scale && len > 0.0)) return glm::vec4(0.0f);
    const glm::dvec3 u = n / len;
    return glm::vec4(glm::vec3(u), float(glm::dot(u, (a + b + c) / 3.0)));
}

// Buffer textures read with texelFetch: their texel count must fit the implementation's limit.
void check_texture_buffer_size(std::size_t texels, const char* what) {
    GLint most = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &most);
    if (texels > std::size_t(most))
        throw Error(std::string("cell renderer: the mesh needs ") + std::to_string(texels) + " " + what +
                    ", more than this GL's texture buffers hold (" + std::to_string(most) + ")");
}

} // namespace

GlProjector::GlProjector(const CellMesh& mesh, const std::string& scalar_name, const TransferFunction& tf)
    : programs_(gl::ProgramCache::for_current_context()) {
    tables_buffer_ = gl::make_buffer(GLsizeiptr(3 * (kTableSize + 1) * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
    attach(tables_, GL_RGBA32F, tables_buffer_.id());
    upload_mesh(mesh, scalar_name);
    set_transfer_function(tf);
}

const gl::Program& GlProjector::program(std::initializer_list<std::string_view> stages,
                                        const gl::Defines& defines) const {
    return programs_->program(projector_shader_library(), stages, defines);
}

ProgramVariants GlProjector::programs(std::initializer_list<std::string_view> stages, gl::Defines defines) const {
    ProgramVariants v;
    v.plain = &program(stages, defines);
    v.with_scene_depth = &program(stages, defines.set("SCENE_DEPTH"));
    return v;
}

gl::Defines GlProjector::mesh_defines() const { return gl::Defines{{"VERTICES_PER_CELL", std::to_string(vertices_per_cell_)}}; }

void GlProjector::set_mesh(const CellMesh& mesh, const std::string& scalar_name) {
    upload_mesh(mesh, scalar_name);
    if (source_tf_.normalized()) set_transfer_function(source_tf_); // else the tables stay as they are
}

bool GlProjector::set_scalars(const std::vector<float>& values) {
    if (values.size() != geometry_.scalars.size())
        throw Error("cell renderer: set_scalars got " + std::to_string(values.size()) + " values for " +
                    std::to_string(geometry_.scalars.size()) + " points");
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) throw Error("cell renderer: set_scalars: value " + std::to_string(i) + " is not finite");
    geometry_.scalars = values;
    upload_point_data();
    scalar_functions(function_scratch_); // they follow the values; nothing else changes
    glNamedBufferSubData(scalar_fns_.id(), 0, GLsizeiptr(geometry_.triangles.size() * 16), function_scratch_.data());
    FX_GL_CHECK("set_scalars upload");
    field_range_ = values.empty() ? ScalarRange{0.0f, 0.0f} : ScalarRange{values[0], values[0]};
    for (float v : values) field_range_.lo = std::min(field_range_.lo, v), field_range_.hi = std::max(field_range_.hi, v);
    if (!source_tf_.normalized()) return false;
    set_transfer_function(source_tf_); // its tables follow the range
    return true;
}

void GlProjector::set_transfer_function(const TransferFunction& tf) {
    source_tf_ = tf;
    transfer_ = tf.normalized() ? tf.rescaled(field_range_.lo, std::max(field_range_.hi, field_range_.lo + 1e-30f)) : tf;
    upload_tables(transfer_);
}

gl::Texture& GlProjector::attach(gl::Texture& texture, GLenum format, GLuint buffer) {
    // Made once; a new or grown buffer is attached to the same texture, so bound units stay valid.
    if (!texture) texture = gl::Texture::create(GL_TEXTURE_BUFFER);
    glTextureBuffer(texture.id(), format, buffer);
    FX_GL_CHECK("buffer texture");
    return texture;
}

void GlProjector::upload_point_data() {
    const std::size_t np = geometry_.positions.size();
    resize_kept(point_data_, np); // kept: set_scalars rewrites it every frame
    for (std::size_t i = 0; i < np; ++i) point_data_[i] = glm::vec4(geometry_.positions[i], geometry_.scalars[i]);
    points_.upload(point_data_.data(), np * sizeof(glm::vec4), points_texture_, GL_RGBA32F);
}

void GlProjector::upload_mesh(const CellMesh& source, const std::string& scalar_name) {
    const ScalarField* field = nullptr;
    if (!scalar_name.empty()) {
        field = source.find_scalar(scalar_name);
        if (!field) throw Error("cell renderer: the mesh has no scalar field '" + scalar_name + "'");
    } else if (!source.scalars.empty()) {
        field = &source.scalars[0];
    }
    // Inverted cells (faces wound inward: negative volume) are drawn as their mirror-consistent
    // positive versions, so that front and back, entry and exit mean the same in every cell.
    // Everything here is written into the storage of the mesh before (a terrain's prisms are
    // replaced every frame): the fields are not copied, the geometry holds the one in use.
    mesh_.points = source.points;
    mesh_.cell_types = source.cell_types;
    mesh_.cell_offsets = source.cell_offsets;
    mesh_.connectivity = source.connectivity;
    mesh_.blocks = source.blocks;
    mesh_.scalars.clear();
    orient_cells(mesh_);
    build_projector_geometry(mesh_, field, geometry_);
    field_range_ = field ? scalar_range(*field) : ScalarRange{0.0f, 0.0f};
    unique_faces_ready_ = false;
    unique_faces_.clear();

    const std::size_t np = geometry_.positions.size(), nc = mesh_.cell_count(), nt = geometry_.triangles.size();
    if (nt > kMaxWordTriangle)
        throw Error("cell renderer: the mesh has " + std::to_string(nt) + " face triangles, more than " +
                    std::to_string(kMaxWordTriangle) + " (split it into several renderers)");
    check_texture_buffer_size(std::max(nt, mesh_.connectivity.size()), "face triangles");
    bounds_ = Bounds{glm::dvec3(1e300), glm::dvec3(-1e300)};
    for (std::size_t i = 0; i < np; ++i) {
        bounds_.lo = glm::min(bounds_.lo, glm::dvec3(geometry_.positions[i]));
        bounds_.hi = glm::max(bounds_.hi, glm::dvec3(geometry_.positions[i]));
    }
    upload_point_data();

    // The slot numbering: cell c's vertex k is vertex id c·V + k.
    vertices_per_cell_ = 4;
    for (CellType t : mesh_.cell_types)
        if (t != CellType::Tetra) vertices_per_cell_ = 8;
    const std::uint32_t v = std::uint32_t(vertices_per_cell_);
    if (nc > std::size_t(0xFFFFFFFFu) / v) throw Error("cell renderer: too many cells (" + std::to_string(nc) + ")");
    resize_kept(cell_triangle_vertices_, 3 * nt);
    resize_kept(words_, nc);
    std::vector<glm::vec4>& barycentrics = barycentrics_data_;
    barycentrics.clear();
    for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t first = geometry_.cell_first_triangle[c], n = geometry_.cell_first_triangle[c + 1] - first;
        const CellType type = mesh_.cell_types[c];
        const std::uint32_t* cv = mesh_.cell_vertices(c);
        words_[c] = cell_word(first, n);
        // The cell's triangles in its own vertex numbers, in build_projector_geometry's order.
        std::uint32_t next = first;
        for (int f = 0; f < cell_face_count(type); ++f) {
            std::uint8_t local[2][3];
            const int halves = triangulate_face_local(cell_faces(type)[f], cv, local);
            for (int h = 0; h < halves; ++h, ++next)
                for (int k = 0; k < 3; ++k) cell_triangle_vertices_[3 * next + k] = std::uint32_t(c) * v + local[h][k];
        }
        for (std::uint32_t t = first; t < first + n; ++t) {
            const auto& tri = geometry_.triangles[t];
            const glm::dvec3 a(geometry_.positions[tri[0]]), b(geometry_.positions[tri[1]]), cc(geometry_.positions[tri[2]]);
            // The planes are the geometry's (triangle_planes: triangle_plane's, from the same floats).
            if (type == CellType::Tetra) continue; // convex, one plane per face: never searched
            if (barycentrics.empty()) assign_kept(barycentrics, 2 * nt, glm::vec4(0.0f));
            barycentric_rows(a, b, cc, &barycentrics[2 * t]);
        }
    }
    scalar_functions(function_scratch_);

    // Planes and scalar functions leave room for a frame's tetrahedra (upload_pieces): their
    // buffers keep what they had beyond the mesh's triangles.
    const std::size_t nt_bytes = nt * sizeof(glm::vec4);
    connectivity_.upload(mesh_.connectivity.data(), mesh_.connectivity.size() * 4, connectivity_texture_, GL_R32UI);
    cell_offsets_.upload(mesh_.cell_offsets.data(), mesh_.cell_offsets.size() * 4, cell_offsets_texture_, GL_R32UI);
    cell_words_.upload(words_.data(), nc * 4, cell_words_texture_, GL_R32UI);
    planes_.upload(geometry_.triangle_planes.data(), nt_bytes, planes_texture_, GL_RGBA32F);
    scalar_fns_.upload(function_scratch_.data(), nt_bytes, scalar_fns_texture_, GL_RGBA32F);
    barycentrics_.upload(barycentrics.data(), barycentrics.size() * sizeof(glm::vec4), barycentrics_texture_, GL_RGBA32F);
    if (!vertex_array_) vertex_array_ = gl::VertexArray::create();
    if (elements_.upload(cell_triangle_vertices_.data(), cell_triangle_vertices_.size() * 4))
        glVertexArrayElementBuffer(vertex_array_.id(), elements_.id());
    bytes_ = gpu_capacity_bytes();
    FX_GL_CHECK("upload mesh");
}

std::size_t GlProjector::gpu_capacity_bytes() const {
    std::size_t bytes = std::size_t(kTableSize + 1) * 3 * 16;
    for (const gl::GrowingBuffer* b : {&points_, &connectivity_, &cell_offsets_, &cell_words_, &planes_, &scalar_fns_,
                                       &barycentrics_, &elements_, &piece_points_, &unique_faces_buffer_})
        bytes += b->capacity();
    return bytes;
}

void GlProjector::scalar_functions(std::vector<glm::vec4>& out) const {
    const std::size_t nc = mesh_.cell_count();
    assign_kept(out, geometry_.triangles.size(), glm::vec4(0.0f));
    auto point = [&](std::uint32_t i) { return ScalarPoint{glm::dvec3(geometry_.positions[i]), double(geometry_.scalars[i])}; };
    for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t first = geometry_.cell_first_triangle[c], end = geometry_.cell_first_triangle[c + 1];
        if (mesh_.cell_types[c] == CellType::Tetra) {
            const std::uint32_t* cv = mesh_.cell_vertices(c);
            const ScalarPoint v[4] = {point(cv[0]), point(cv[1]), point(cv[2]), point(cv[3])};
            std::fill(out.begin() + first, out.begin() + end, tetrahedron_function(v));
            continue;
        }
        for (std::uint32_t t = first; t < end; ++t) {
            const auto& tri = geometry_.triangles[t];
            out[t] = triangle_function(point(tri[0]), point(tri[1]), point(tri[2]));
        }
    }
}

void GlProjector::upload_tables(const TransferFunction& tf) {
    // Row 0: the cumulative E(s) = ∫c·σ ds (rgb) and T(s) = ∫σ ds (a) at the samples, from
    // build_emission_table. Row 1: the mean of c·σ and σ over each table cell (exact, in double),
    // entry i + 1 for cell i, with the held end values below (entry 0) and above (entry n) the
    // table. Row 2: c·σ and σ at the samples (mip and the classic vertex colours).
    const EmissionTable emission = build_emission_table(tf, kTableSize);
    std::vector<TransferPoint> white = tf.points();
    for (TransferPoint& p : white) p.color = glm::dvec3(1.0);
    const TransferFunction extinction_tf(white);
    const EmissionTable extinction = build_emission_table(extinction_tf, kTableSize);
    require_float_emission_tables(tf, emission, extinction);
    s_lo_ = emission.s_lo;
    s_hi_ = emission.s_hi;
    const int w = kTableSize + 1;
    std::vector<glm::vec4> texels(std::size_t(3 * w), glm::vec4(0.0f));
    auto sample = [&](int i) { return i + 1 == kTableSize ? s_hi_ : s_lo_ + (s_hi_ - s_lo_) * double(i) / (kTableSize - 1); };
    for (int i = 0; i < kTableSize; ++i) {
        texels[i] = glm::vec4(emission.cumulative[i], extinction.cumulative[i].x);
        texels[2 * w + i] = glm::vec4(glm::vec3(tf.emission(sample(i))), float(tf.sigma(sample(i))));
    }
    texels[w] = texels[2 * w];
    texels[w + kTableSize] = texels[2 * w + kTableSize - 1];
    for (int i = 0; i + 1 < kTableSize; ++i) {
        const double a = sample(i), b = sample(i + 1);
        if (!(b > a)) {
            texels[w + 1 + i] = texels[2 * w + i];
            continue;
        }
        const glm::dvec3 e = emission_integral(tf, a, b, b - a) / (b - a);
        const double t = emission_integral(extinction_tf, a, b, b - a).x / (b - a);
        texels[w + 1 + i] = glm::vec4(glm::vec3(e), float(t));
    }
    glNamedBufferSubData(tables_buffer_.id(), 0, GLsizeiptr(texels.size() * sizeof(glm::vec4)), texels.data());
    FX_GL_CHECK("upload tables");
}

glm::dmat4 GlProjector::raster_projection(const Camera& camera, double near, double aspect, double ortho_far) {
    glm::dmat4 projection = camera.projection_matrix(aspect);
    const double n = near; // the view's clipping near (ProjectorView::near_distance)
    if (!camera.orthographic()) {
        // The frustum's depth row with far at infinity (x, y and w unchanged, near still
        // clips): the passes read depth from 1/w, never from z. With a finite far, n/f below
        // float's 6e-8 rounds the depth row into clipping the back faces of cells well in
        // front of the far plane.
        projection[2][2] = -1.0;
        projection[3][2] = -2.0 * n;
    } else {
        // The box's depth row from near to ortho_far (window z is read back through the same
        // range, UNIFORM_RASTER_DEPTH_RANGE).
        projection[2][2] = -2.0 / (ortho_far - n);
        projection[3][2] = -(ortho_far + n) / (ortho_far - n);
    }
    return projection;
}

glm::dvec2 GlProjector::bounds_depth_range(const ProjectorView& v) const {
    glm::dvec2 range(HUGE_VAL, -HUGE_VAL);
    for (int k = 0; k < 8; ++k) {
        const double d = v.depth(bounds_.corner(k));
        range = glm::dvec2(std::min(range.x, d), std::max(range.y, d));
    }
    return range;
}

void GlProjector::bind_mesh() const {
    const std::pair<GLuint, GLuint> textures[] = {
        {kUnitTables, tables_.id()},
        {kUnitPoints, points_texture_.id()},
        {kUnitConnectivity, connectivity_texture_.id()},
        {kUnitCellOffsets, cell_offsets_texture_.id()},
        {kUnitCellWords, cell_words_texture_.id()},
        {kUnitPlanes, planes_texture_.id()},
        {kUnitScalarFunctions, scalar_fns_texture_.id()},
        {kUnitBarycentrics, barycentrics_texture_.id()},
        {kUnitPiecePoints, piece_points_texture_.id()},
    };
    for (const auto& [unit, texture] : textures) {
        glBindTextureUnit(unit, texture);
        glBindSampler(unit, 0);
    }
    glBindVertexArray(vertex_array_.id());
    FX_GL_CHECK("bind mesh");
}

void GlProjector::draw_slots(std::size_t first_slot, std::size_t slots) const {
    // Tetrahedra: 4 triangles per slot, the same pattern for every slot.
    const std::size_t first = all_tetrahedra() ? 4 * first_slot : geometry_.cell_first_triangle[first_slot];
    const std::size_t end = all_tetrahedra() ? 4 * (first_slot + slots) : geometry_.cell_first_triangle[first_slot + slots];
    if (end > first)
        glDrawElements(GL_TRIANGLES, GLsizei(3 * (end - first)), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(3 * first * sizeof(std::uint32_t)));
}

void GlProjector::set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const {
    const ProjectorView v = view(camera);
    // No cell is cut at the far plane, as the scan-line reference cuts none: an orthographic
    // view rasterises with far moved past the mesh's deepest corner where that lies beyond it.
    const double ortho_far =
        v.orthographic ? std::max(camera.far_distance, v.near_distance + 1.01 * std::max(bounds_depth_range(v).y, 0.0)) : 0.0;
    const glm::mat4 vp(raster_projection(camera, v.near_distance, double(viewport.width) / double(viewport.height), ortho_far) * v.view);
    const glm::vec3 eye(v.eye), forward(v.forward);
    const double span = s_hi_ - s_lo_;
    const glm::vec4 table(float(s_lo_), float(s_hi_), float(kTableSize), span > 0.0 ? float((kTableSize - 1) / span) : 0.0f);
    const GLuint p = program.id();
    glProgramUniformMatrix4fv(p, kUniformViewProjection, 1, GL_FALSE, glm::value_ptr(vp));
    glProgramUniform3fv(p, kUniformEye, 1, glm::value_ptr(eye));
    glProgramUniform3fv(p, kUniformForward, 1, glm::value_ptr(forward));
    glProgramUniform1f(p, kUniformNear, float(v.near_distance));
    glProgramUniform1i(p, kUniformOrthographic, v.orthographic ? 1 : 0);
    if (v.orthographic) glProgramUniform2f(p, kUniformRasterDepthRange, float(v.near_distance), float(ortho_far));
    glProgramUniform4fv(p, kUniformTable, 1, glm::value_ptr(table));

    // The ray of pixel centre (x, y) of the pass's target (the viewport's size, at the origin)
    // is Camera::pixel_ray's for that pixel: linear in x and y, in the relative frame.
    const glm::dvec3 f = v.forward;
    const double w = viewport.width, h = viewport.height;
    glm::dvec3 origin = v.eye, origin_dx(0.0), origin_dy(0.0), direction = f, direction_dx(0.0), direction_dy(0.0);
    if (camera.projection) {
        // An explicit (possibly off-axis) projection: the pixel's point on the near plane, back
        // through both matrices, is linear in x and y (w is constant on that plane).
        const glm::dmat4 from_clip = glm::inverse(*camera.projection * v.view);
        const auto near_point = [&](double x, double y) {
            const glm::dvec4 q = from_clip * glm::dvec4(2.0 * x / w - 1.0, 2.0 * y / h - 1.0, -1.0, 1.0);
            return glm::dvec3(q) / q.w;
        };
        const glm::dvec3 p00 = near_point(0.0, 0.0), p10 = near_point(1.0, 0.0), p01 = near_point(0.0, 1.0);
        if (camera.orthographic()) {
            origin = p00 - f * glm::dot(p00 - v.eye, f), origin_dx = p10 - p00, origin_dy = p01 - p00;
        } else {
            direction = p00 - v.eye, direction_dx = p10 - p00, direction_dy = p01 - p00;
        }
    } else {
        const Camera::Basis basis = camera.basis(); // double, normalised: an up of 1e-300 is an up
        const glm::dvec3 &r = basis.right, &u = basis.up;
        const double aspect = w / h;
        const double half_x = camera.orthographic() ? 0.5 * camera.ortho_height * aspect
                                                    : std::tan(0.5 * glm::radians(camera.fov_y_degrees)) * aspect;
        const double half_y = half_x / aspect;
        // ndc_x = 2·x/w − 1
        const glm::dvec3 step_x = r * (half_x * 2.0 / w), step_y = u * (half_y * 2.0 / h);
        const glm::dvec3 at_origin = -r * half_x - u * half_y;
        if (camera.orthographic()) {
            origin += at_origin, origin_dx = step_x, origin_dy = step_y;
        } else {
            direction += at_origin, direction_dx = step_x, direction_dy = step_y;
        }
    }
    const std::pair<GLint, glm::dvec3> rays[] = {
        {kUniformRayOrigin, origin},       {kUniformRayOriginDx, origin_dx},       {kUniformRayOriginDy, origin_dy},
        {kUniformRayDirection, direction}, {kUniformRayDirectionDx, direction_dx}, {kUniformRayDirectionDy, direction_dy}};
    for (const auto& [location, value] : rays) glProgramUniform3f(p, location, float(value.x), float(value.y), float(value.z));
    FX_GL_CHECK("view uniforms");
}

void GlProjector::set_scene_depth_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport,
                                           unsigned int scene_depth) const {
    const GLuint p = program.id();
    glProgramUniform2f(p, kUniformSceneDepthRange, float(camera.near_distance), float(camera.far_distance));
    if (scene_depth != 0) { // the SCENE_DEPTH variant: 1 perspective window depth, 2 orthographic
        glProgramUniform1i(p, kUniformSceneDepthMode, camera.orthographic() ? 2 : 1);
        glProgramUniform2i(p, kUniformSceneOrigin, viewport.x, viewport.y);
    }
    FX_GL_CHECK("scene depth uniforms");
}

void GlProjector::bind_scene_depth(unsigned int texture) {
    glBindTextureUnit(kUnitSceneDepth, texture);
    glBindSampler(kUnitSceneDepth, 0);
    FX_GL_CHECK("scene depth");
}

void GlProjector::upload_pieces(const std::vector<std::uint32_t>& tetrahedra) {
    const std::size_t pieces = tetrahedra.size() / 4, nt = geometry_.triangles.size();
    if (pieces == 0) return;
    if (nt + 4 * pieces > kMaxWordTriangle || pieces >= kPieceBit)
        throw Error("cell renderer: too many tetrahedra for one frame (" + std::to_string(pieces) + ")");
    check_texture_buffer_size(nt + 4 * pieces, "face triangles and subdivided tetrahedra");
    // Grow the planes and scalar functions keeping the mesh's part, and the pieces' points.
    const std::size_t bytes = (nt + 4 * pieces) * sizeof(glm::vec4), kept = nt * sizeof(glm::vec4);
    if (planes_.reserve(bytes, kept)) attach(planes_texture_, GL_RGBA32F, planes_.id());
    if (scalar_fns_.reserve(bytes, kept)) attach(scalar_fns_texture_, GL_RGBA32F, scalar_fns_.id());
    if (piece_points_.reserve(pieces * 16)) attach(piece_points_texture_, GL_RGBA32UI, piece_points_.id());
    bytes_ = gpu_capacity_bytes();
    resize_kept(piece_data_, 8 * pieces); // 4 planes, then 4 scalar functions, per tetrahedron
    const CellFace* faces = cell_faces(CellType::Tetra);
    for (std::size_t i = 0; i < pieces; ++i) {
        const std::uint32_t* tet = &tetrahedra[4 * i];
        ScalarPoint v[4];
        for (int k = 0; k < 4; ++k) v[k] = {glm::dvec3(geometry_.positions[tet[k]]), double(geometry_.scalars[tet[k]])};
        const glm::vec4 function = tetrahedron_function(v);
        for (int f = 0; f < 4; ++f) {
            piece_data_[4 * i + std::size_t(f)] = triangle_plane(v[faces[f].v[0]].p, v[faces[f].v[1]].p, v[faces[f].v[2]].p);
            piece_data_[4 * pieces + 4 * i + std::size_t(f)] = function;
        }
    }
    const GLintptr offset = GLintptr(nt * 16);
    glNamedBufferSubData(planes_.id(), offset, GLsizeiptr(4 * pieces * 16), piece_data_.data());
    glNamedBufferSubData(scalar_fns_.id(), offset, GLsizeiptr(4 * pieces * 16), piece_data_.data() + 4 * pieces);
    glNamedBufferSubData(piece_points_.id(), 0, GLsizeiptr(pieces * 16), tetrahedra.data());
    glBindTextureUnit(kUnitPiecePoints, piece_points_texture_.id());
    FX_GL_CHECK("upload pieces");
}

bool GlProjector::mesh_crosses_near_plane(const ProjectorView& v) const {
    return !geometry_.positions.empty() && bounds_depth_range(v).x <= 0.0;
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
    frame_.upload(data.data(), data.size() * sizeof(glm::uvec4));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingFrame, frame_.id());
    FX_GL_CHECK("upload frame data");
}

std::size_t GlProjector::unique_face_triangles() {
    if (!unique_faces_ready_) {
        // A face slot is drawn from the cell with the lower slot of the two that share it.
        build_face_topology(mesh_, topology_, topology_scratch_);
        const FaceTopology& topology = topology_;
        unique_faces_.clear();
        for (std::size_t c = 0; c < mesh_.cell_count(); ++c) {
            const CellType type = mesh_.cell_types[c];
            std::uint32_t t = geometry_.cell_first_triangle[c];
            for (int f = 0; f < cell_face_count(type); ++f) {
                const int halves = cell_faces(type)[f].count == 4 ? 2 : 1;
                const std::uint32_t slot = topology.first_face[c] + std::uint32_t(f);
                const std::uint32_t other = topology.neighbour[slot];
                if (other == FaceTopology::kBoundary || other > slot)
                    for (int h = 0; h < halves; ++h) {
                        const auto& tri = geometry_.triangles[t + std::uint32_t(h)];
                        unique_faces_.emplace_back(tri[0], tri[1], tri[2], 0u);
                    }
                t += std::uint32_t(halves);
            }
        }
        unique_faces_buffer_.upload(unique_faces_.data(), unique_faces_.size() * 16, unique_faces_texture_, GL_RGBA32UI);
        bytes_ = gpu_capacity_bytes();
        unique_faces_ready_ = true;
    }
    return unique_faces_.size();
}

void GlProjector::bind_unique_faces() {
    unique_face_triangles();
    glBindTextureUnit(kUnitUniqueFaces, unique_faces_texture_.id());
    glBindSampler(kUnitUniqueFaces, 0);
}

// ---- GlCellList -------------------------------------------------------------------------------

GlCellList::GlCellList(const GlProjector& projector) : projector_(projector) {
    vertex_array_ = gl::VertexArray::create();
    if (projector.all_tetrahedra()) glVertexArrayElementBuffer(vertex_array_.id(), projector.element_buffer());
}

void GlCellList::upload(const std::vector<std::uint32_t>& cells, const std::vector<glm::vec2>& ranges) {
    slots_ = cells.size();
    cells_.upload(cells.data(), cells.size() * 4, cells_texture_, GL_R32UI);
    if (!ranges.empty()) slot_data_.upload(ranges.data(), ranges.size() * sizeof(glm::vec2), slot_data_texture_, GL_RG32F);
    if (projector_.all_tetrahedra()) return; // the mesh's own element buffer: the same pattern per slot
    // Each entry's triangles, renumbered to its slot: vertex k of slot s is s·8 + k.
    const std::vector<std::uint32_t>& first_triangle = projector_.geometry().cell_first_triangle;
    const std::vector<std::uint32_t>& mesh_elements = projector_.cell_triangle_vertices();
    const CellFace* tetra_faces = cell_faces(CellType::Tetra);
    const std::uint32_t v = std::uint32_t(projector_.vertices_per_cell());
    elements_data_.clear();
    resize_kept(first_element_, slots_ + 1);
    for (std::size_t s = 0; s < slots_; ++s) {
        first_element_[s] = elements_data_.size();
        const std::uint32_t base = std::uint32_t(s) * v;
        if (cells[s] & kPieceBit) {
            for (int f = 0; f < 4; ++f)
                for (int k = 0; k < 3; ++k) elements_data_.push_back(base + tetra_faces[f].v[k]);
            continue;
        }
        const std::uint32_t c = cells[s];
        for (std::uint32_t i = 3 * first_triangle[c]; i < 3 * first_triangle[c + 1]; ++i)
            elements_data_.push_back(base + mesh_elements[i] % v);
    }
    first_element_[slots_] = elements_data_.size();
    if (elements_.upload(elements_data_.data(), elements_data_.size() * 4))
        glVertexArrayElementBuffer(vertex_array_.id(), elements_.id());
    FX_GL_CHECK("cell list upload");
}

void GlCellList::bind(const gl::Program& program) const {
    glProgramUniform1ui(program.id(), kUniformPieceBase, GLuint(projector_.geometry().triangles.size()));
    glBindTextureUnit(kUnitCellList, cells_texture_.id());
    glBindTextureUnit(kUnitSlotData, slot_data_texture_.id());
    glBindSampler(kUnitCellList, 0);
    glBindSampler(kUnitSlotData, 0);
    // Tetrahedra draw with the mesh's element buffer, which a new mesh may have grown.
    if (projector_.all_tetrahedra()) glVertexArrayElementBuffer(vertex_array_.id(), projector_.element_buffer());
    glBindVertexArray(vertex_array_.id());
}

void GlCellList::draw(std::size_t first, std::size_t count) const {
    if (count == 0) return;
    std::size_t begin, end;
    if (projector_.all_tetrahedra()) {
        begin = 12 * first, end = 12 * (first + count);
    } else {
        begin = first_element_[first], end = first_element_[first + count];
    }
    if (end > begin)
        glDrawElements(GL_TRIANGLES, GLsizei(end - begin), GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(begin * sizeof(std::uint32_t)));
}

} // namespace cellfx::fx
