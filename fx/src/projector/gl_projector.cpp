// Based on: Roettger & Ertl 2003, §3 (the projector) and §5 (near-plane caps).
#include "projector/gl_projector.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/trigonometric.hpp>
#include <glm/matrix.hpp>

#include "fx/effect.hpp"
#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_validation.hpp"
#include "transfer/segment_integral.hpp"
#include "gl/gl_check.hpp"
#include "gl/state_guard.hpp"
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

// A face's plane for the planar test and layout (projector_tables.comp's face_plane): unit
// normal along b−a × c−a (a triangle) or along the cross product of the diagonals (a quad),
// through the mean of its corners; zero for a face with no area.
glm::dvec4 face_plane(const glm::dvec3* p, const CellFace& face) {
    const bool quad = face.count == 4;
    const std::uint8_t* v = face.v;
    const glm::dvec3 n = quad ? glm::cross(p[v[2]] - p[v[0]], p[v[3]] - p[v[1]]) : glm::cross(p[v[1]] - p[v[0]], p[v[2]] - p[v[0]]);
    const glm::dvec3 centre = quad ? 0.25 * (p[v[0]] + p[v[1]] + p[v[2]] + p[v[3]]) : (p[v[0]] + p[v[1]] + p[v[2]]) / 3.0;
    const double len = glm::length(n);
    const double scale = std::max(glm::length(p[v[2]] - p[v[0]]), glm::length(p[quad ? v[3] : v[2]] - p[v[1]]));
    if (!(len > 1e-12 * scale * scale && len > 0.0)) return glm::dvec4(0.0);
    const glm::dvec3 u = n / len;
    return glm::dvec4(u, glm::dot(u, centre));
}

// Whether a cell of `type` with points p is planar (gl_interface.hpp, kPlanarTolerance) within
// `tolerance`, as projector_tables.comp's planar_cell decides it; `margin` gets how far inside the
// tolerance it is, relative to it: negative when it is not planar, near 0 on the border.
bool planar_cell(const glm::dvec3* p, CellType type, double tolerance, double& margin) {
    const int n = cell_vertex_count(type);
    glm::dvec3 lo = p[0], hi = p[0];
    for (int k = 1; k < n; ++k) lo = glm::min(lo, p[k]), hi = glm::max(hi, p[k]);
    const double slack = tolerance * glm::length(hi - lo);
    bool planar = true;
    double worst = -HUGE_VAL; // the largest distance the test compares with `slack`
    for (int f = 0; f < cell_face_count(type); ++f) {
        const CellFace& face = cell_faces(type)[f];
        const glm::dvec4 plane = face_plane(p, face);
        if (glm::dvec3(plane) == glm::dvec3(0.0)) planar = false, worst = HUGE_VAL;
        for (int k = 0; k < n; ++k) {
            const double d = glm::dot(glm::dvec3(plane), p[k]) - plane.w;
            const bool on_face = std::find(face.v, face.v + face.count, k) != face.v + face.count;
            const double distance = on_face ? std::abs(d) : d;
            planar = planar && distance <= slack;
            worst = std::max(worst, distance);
        }
    }
    margin = tolerance < 0.0 ? -1.0 : slack > 0.0 ? (slack - worst) / slack : worst <= 0.0 ? 1.0 : -1.0;
    return planar && tolerance >= 0.0; // a negative tolerance: nothing is planar
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

ProjectorTables build_projector_tables(const CellMesh& mesh, const ProjectorGeometry& geometry, int vertices_per_cell,
                                       double planar_tolerance) {
    ProjectorTables t;
    const std::size_t nt = geometry.triangles.size(), nc = mesh.cell_count();
    t.planes.resize(nt);
    t.scalar_functions.resize(nt);
    if (vertices_per_cell != 4) t.barycentrics.assign(2 * nt, glm::vec4(0.0f));
    t.elements.resize(3 * nt);
    t.words.resize(nc);
    t.planar_margins.resize(nc);
    auto point = [&](std::uint32_t i) { return ScalarPoint{glm::dvec3(geometry.positions[i]), double(geometry.scalars[i])}; };
    for (std::size_t c = 0; c < nc; ++c) {
        const CellType type = mesh.cell_types[c];
        const std::uint32_t* cv = mesh.cell_vertices(c);
        const int n = cell_vertex_count(type), faces = cell_face_count(type);
        ScalarPoint v[8];
        glm::dvec3 p[8];
        for (int k = 0; k < n; ++k) v[k] = point(cv[k]), p[k] = v[k].p;
        const glm::vec4 tet = type == CellType::Tetra ? tetrahedron_function(v) : glm::vec4(0.0f);
        // Tetrahedra-only meshes keep the triangle layout (the same for a tetrahedron) and no bit.
        double margin = 0.0;
        const bool planar = vertices_per_cell != 4 && planar_cell(p, type, planar_tolerance, margin);
        t.planar_margins[c] = vertices_per_cell != 4 ? margin : 1.0;
        const std::uint32_t first = geometry.cell_first_triangle[c];
        t.words[c] = cell_word(first, geometry.cell_first_triangle[c + 1] - first, planar);
        std::uint32_t triangle = first;
        int quads = 0;
        for (int f = 0; f < faces; ++f) {
            const CellFace& face = cell_faces(type)[f];
            std::uint8_t local[2][3];
            const int halves = triangulate_face_local(face, cv, local);
            if (planar) {
                // Face f's plane and first half's function in slot f, a quad's diagonal plane
                // and second half's function in slot F + (its index among the quads).
                const std::size_t slot = first + std::size_t(f), second = first + std::size_t(faces + quads);
                const glm::dvec4 plane = face_plane(p, face);
                t.planes[slot] = glm::vec4(plane);
                const ScalarPoint &a = v[local[0][0]], &b = v[local[0][1]], &cc = v[local[0][2]];
                if (halves == 2) {
                    // As projector_tables.comp: the diagonal plane's sign from the farther of b
                    // and d, a half of next to no area given its neighbour's function.
                    const ScalarPoint& d = v[local[1][2]];
                    glm::dvec3 m = glm::cross(glm::dvec3(plane), cc.p - a.p);
                    const double side_b = glm::dot(m, b.p - a.p), side_d = glm::dot(m, d.p - a.p);
                    if (std::abs(side_b) >= std::abs(side_d) ? side_b < 0.0 : side_d > 0.0) m = -m;
                    const double len = glm::length(m);
                    if (len > 0.0) m /= len;
                    t.planes[second] = glm::vec4(glm::vec3(m), float(glm::dot(m, a.p)));
                    const glm::vec4 f1 = triangle_function(a, b, cc), f2 = triangle_function(a, cc, d);
                    const double area1 = glm::length(glm::cross(b.p - a.p, cc.p - a.p));
                    const double area2 = glm::length(glm::cross(cc.p - a.p, d.p - a.p));
                    t.scalar_functions[slot] = area1 < 1e-6 * area2 ? f2 : f1;
                    t.scalar_functions[second] = area2 < 1e-6 * area1 ? f1 : f2;
                    ++quads;
                } else {
                    t.scalar_functions[slot] = type == CellType::Tetra ? tet : triangle_function(a, b, cc);
                }
            }
            for (int h = 0; h < halves; ++h, ++triangle) {
                const ScalarPoint &a = v[local[h][0]], &b = v[local[h][1]], &cc = v[local[h][2]];
                if (!planar) {
                    t.planes[triangle] = triangle_plane(a.p, b.p, cc.p);
                    t.scalar_functions[triangle] = type == CellType::Tetra ? tet : triangle_function(a, b, cc);
                    if (vertices_per_cell != 4 && type != CellType::Tetra)
                        barycentric_rows(a.p, b.p, cc.p, &t.barycentrics[2 * std::size_t(triangle)]);
                }
                for (int k = 0; k < 3; ++k)
                    t.elements[3 * std::size_t(triangle) + k] = std::uint32_t(c) * std::uint32_t(vertices_per_cell) + local[h][k];
            }
        }
    }
    return t;
}

ProjectorTables GlProjector::read_tables() {
    prepare_tables();
    glFinish();
    ProjectorTables t;
    const std::size_t nt = geometry_.triangles.size();
    t.planes.resize(nt);
    t.scalar_functions.resize(nt);
    t.elements.resize(3 * nt);
    glGetNamedBufferSubData(planes_.id(), 0, GLsizeiptr(nt * 16), t.planes.data());
    glGetNamedBufferSubData(scalar_fns_.id(), 0, GLsizeiptr(nt * 16), t.scalar_functions.data());
    glGetNamedBufferSubData(elements_.id(), 0, GLsizeiptr(nt * 12), t.elements.data());
    t.words.resize(mesh_.cell_count());
    glGetNamedBufferSubData(cell_words_.id(), 0, GLsizeiptr(t.words.size() * 4), t.words.data());
    if (!all_tetrahedra() && !compact_rows_) {
        t.barycentrics.resize(2 * nt);
        glGetNamedBufferSubData(barycentrics_.id(), 0, GLsizeiptr(nt * 32), t.barycentrics.data());
    } else if (!all_tetrahedra()) {
        // Laid out by triangle slot as the CPU's build has them: a planar cell's zero.
        t.barycentrics.assign(2 * nt, glm::vec4(0.0f));
        std::vector<std::uint32_t> bases(t.words.size());
        std::vector<glm::vec4> rows(2 * fold_rows_);
        glGetNamedBufferSubData(fold_bases_.id(), 0, GLsizeiptr(bases.size() * 4), bases.data());
        glGetNamedBufferSubData(barycentrics_.id(), 0, GLsizeiptr(rows.size() * 16), rows.data());
        for (std::size_t c = 0; c < t.words.size(); ++c) {
            if (t.words[c] & kWordPlanar) continue;
            const std::uint32_t first = geometry_.cell_first_triangle[c], n = geometry_.cell_first_triangle[c + 1] - first;
            std::copy_n(rows.begin() + 2 * std::ptrdiff_t(bases[c]), 2 * n, t.barycentrics.begin() + 2 * std::ptrdiff_t(first));
        }
    }
    FX_GL_CHECK("read tables");
    return t;
}

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

namespace {

const ScalarField* field_of(const CellMesh& source, const std::string& scalar_name) {
    if (!scalar_name.empty()) {
        const ScalarField* field = source.find_scalar(scalar_name);
        if (!field) throw Error("cell renderer: the mesh has no scalar field '" + scalar_name + "'");
        return field;
    }
    return source.scalars.empty() ? nullptr : &source.scalars[0];
}

ScalarRange range_of(const std::vector<float>& values) {
    ScalarRange r = values.empty() ? ScalarRange{0.0f, 0.0f} : ScalarRange{values[0], values[0]};
    for (float v : values) r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v);
    return r;
}

} // namespace

bool GlProjector::update_mesh(const CellMesh& source, const std::string& scalar_name, const MeshChanges& changes) {
    const ScalarField* field = field_of(source, scalar_name);
    const std::size_t np = source.point_count(), nc = source.cell_count();
    // In place only when the unchanged part is what the renderer has: the same field, no point
    // gone, the changed and new cells of the same kind as the mesh's, positions near the origin
    // the renderer keeps them relative to, and a stamp left to number the update.
    bool in_place = !changes.whole && np >= mesh_.point_count() && stamp_ + 1 < 0xFFFFFFFFu &&
                    source.cell_offsets.size() == nc + 1 && source.connectivity.size() == source.cell_offsets[nc] &&
                    (!field || field->values.size() == np);
    const double extent = std::max(glm::length(bounds_.hi - bounds_.lo), kMinProjectorExtent);
    for (std::size_t i = 0; in_place && i < changes.points.size(); ++i) {
        const std::uint32_t p = changes.points[i];
        if (p >= np) throw Error("cell renderer: update_mesh: changed point " + std::to_string(p) + " beyond the mesh's " +
                                 std::to_string(np) + " points");
        const glm::dvec3 rel = source.points[p] - geometry_.origin;
        in_place = std::max({std::abs(rel.x), std::abs(rel.y), std::abs(rel.z)}) <= 4.0 * extent;
    }
    for (std::size_t i = 0; in_place && i < changes.cells.size(); ++i) {
        const std::uint32_t c = changes.cells[i];
        if (c >= nc) throw Error("cell renderer: update_mesh: changed cell " + std::to_string(c) + " beyond the mesh's " +
                                 std::to_string(nc) + " cells");
        const CellType type = source.cell_types[c];
        in_place = (!all_tetrahedra() || type == CellType::Tetra) && (c >= mesh_.cell_count() || type == mesh_.cell_types[c]);
    }
    // Points and cells past the old counts must all be listed as changed: they are new.
    if (in_place && (np > mesh_.point_count() || nc > mesh_.cell_count())) {
        std::size_t points = 0, cells = 0;
        for (std::uint32_t p : changes.points) points += p >= mesh_.point_count();
        for (std::uint32_t c : changes.cells) cells += c >= mesh_.cell_count();
        in_place = points >= np - mesh_.point_count() && cells >= nc - mesh_.cell_count();
    }
    if (!in_place) {
        set_mesh(source, scalar_name);
        return false;
    }
    // The field's range is kept whatever the function (one set later may be normalized); a
    // normalized function follows it, the whole field's.
    const ScalarRange range = apply_changes(source, field, changes);
    const bool range_changed = range.lo != field_range_.lo || range.hi != field_range_.hi;
    field_range_ = range;
    if (range_changed && source_tf_.normalized()) set_transfer_function(source_tf_);
    return true;
}

ScalarRange GlProjector::apply_changes(const CellMesh& source, const ScalarField* field, const MeshChanges& changes) {
    const std::size_t old_np = mesh_.point_count(), old_nc = mesh_.cell_count();
    const std::size_t np = source.point_count(), nc = source.cell_count();
    ++stamp_;
    // From now on the barycentric rows are laid out by slot (reserve_tables, build_tables).
    updated_in_place_ = true;
    // Points: the CPU's copy (mesh, positions relative to the kept origin, scalars) and the list
    // of changed values for the GPU.
    mesh_.points.resize(np);
    resize_kept(geometry_.positions, np);
    resize_kept(geometry_.scalars, np);
    if (!point_scatter_) {
        point_scatter_ = std::make_unique<gl::ScatterPass>(4);
        cell_scatter_ = std::make_unique<gl::ScatterPass>(8);
    }
    point_scatter_->clear();
    cell_scatter_->clear();
    point_scatter_->reserve(np); // at most every point and cell changes: a steady frame allocates nothing
    cell_scatter_->reserve(nc);
    // The field's range after the changes: it only grows with the new values, unless a changed
    // point held one of its bounds (then the whole field is scanned, below).
    ScalarRange range = field_range_;
    bool range_known = old_np > 0;
    for (std::uint32_t p : changes.points) {
        const glm::dvec3& q = source.points[p];
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            throw Error("projector: point " + std::to_string(p) + " has a non-finite coordinate");
        const float s = field ? field->values[p] : 0.0f;
        if (!std::isfinite(s))
            throw Error("projector: scalar '" + field->name + "' of point " + std::to_string(p) + " is not finite");
        mesh_.points[p] = q;
        const glm::vec3 r(q - geometry_.origin);
        geometry_.positions[p] = r;
        if (p < old_np && (geometry_.scalars[p] == field_range_.lo || geometry_.scalars[p] == field_range_.hi))
            range_known = false;
        geometry_.scalars[p] = s;
        range.lo = std::min(range.lo, s), range.hi = std::max(range.hi, s);
        bounds_.lo = glm::min(bounds_.lo, glm::dvec3(r));
        bounds_.hi = glm::max(bounds_.hi, glm::dvec3(r));
        const glm::vec4 data(r, s);
        std::memcpy(point_scatter_->add(4 * p, 4, p), &data, sizeof(glm::vec4));
    }
    // Cells: removed ones are the last ones; new ones are appended with their triangles and words.
    const std::uint32_t v = std::uint32_t(vertices_per_cell_);
    if (nc < old_nc) {
        mesh_.cell_types.resize(nc);
        mesh_.cell_offsets.resize(nc + 1);
        mesh_.connectivity.resize(mesh_.cell_offsets[nc]);
        geometry_.cell_first_triangle.resize(nc + 1);
        const std::size_t nt = geometry_.cell_first_triangle[nc];
        geometry_.triangles.resize(nt);
        geometry_.triangle_cell.resize(nt);
        cell_triangle_vertices_.resize(3 * nt);
        words_.resize(nc);
    } else if (nc > old_nc) {
        for (std::size_t c = old_nc; c < nc; ++c) {
            const CellType type = source.cell_types[c];
            mesh_.cell_types.push_back(type);
            const std::uint32_t count = std::uint32_t(cell_vertex_count(type));
            mesh_.connectivity.resize(mesh_.connectivity.size() + count);
            mesh_.cell_offsets.push_back(std::uint32_t(mesh_.connectivity.size()));
            std::uint32_t triangles = 0;
            for (int f = 0; f < cell_face_count(type); ++f) triangles += cell_faces(type)[f].count == 4 ? 2 : 1;
            const std::uint32_t first = geometry_.cell_first_triangle.back();
            geometry_.cell_first_triangle.push_back(first + triangles);
            geometry_.triangles.resize(first + triangles);
            geometry_.triangle_cell.resize(first + triangles, std::uint32_t(c));
            cell_triangle_vertices_.resize(3 * std::size_t(first + triangles));
            words_.push_back(cell_word(first, triangles));
        }
        if (geometry_.triangles.size() > kMaxWordTriangle)
            throw Error("cell renderer: the mesh has " + std::to_string(geometry_.triangles.size()) +
                        " face triangles, more than " + std::to_string(kMaxWordTriangle) + " (split it into several renderers)");
        check_texture_buffer_size(std::max(geometry_.triangles.size(), mesh_.connectivity.size()), "face triangles");
        if (nc > std::size_t(0xFFFFFFFFu) / v) throw Error("cell renderer: too many cells (" + std::to_string(nc) + ")");
    }
    for (std::uint32_t c : changes.cells) {
        const std::uint32_t* from = source.cell_vertices(c);
        std::uint32_t* to = mesh_.cell_vertices(c);
        const int n = cell_vertex_count(mesh_.cell_types[c]);
        for (int k = 0; k < n; ++k) {
            if (from[k] >= np)
                throw Error("projector: cell " + std::to_string(c) + " uses point " + std::to_string(from[k]) +
                            " but the mesh has " + std::to_string(np) + " points");
            to[k] = from[k];
        }
        if (!changes.oriented) orient_cell(mesh_, c);
        // Its CPU triangles when a CPU pass asks (flush_triangles): listed once however often it
        // changes meanwhile.
        if (triangles_stale_.size() < nc) {
            triangles_stale_.resize(std::max<std::size_t>(nc, triangles_stale_.size() * 3 / 2), 0);
            untriangulated_.reserve(triangles_stale_.size()); // a cell is listed once at most
        }
        if (!triangles_stale_[c]) {
            triangles_stale_[c] = 1;
            untriangulated_.push_back(c);
        }
        std::memcpy(cell_scatter_->add(mesh_.cell_offsets[c], std::uint32_t(n), c), to, std::size_t(n) * 4);
    }
    planes_stale_ = true;
    unique_faces_ready_ = unique_faces_ready_ && changes.cells.empty() && nc == old_nc;
    if (nc != old_nc) mesh_.blocks = source.blocks;

    // The GPU: grown buffers keep what is built; new cells' offsets and words go up whole, then
    // the changed values are scattered into place and stamped.
    if (points_.reserve(np * sizeof(glm::vec4), old_np * sizeof(glm::vec4))) attach(points_texture_, GL_RGBA32F, points_.id());
    if (nc > old_nc) {
        if (cell_offsets_.reserve((nc + 1) * 4, (old_nc + 1) * 4)) attach(cell_offsets_texture_, GL_R32UI, cell_offsets_.id());
        if (cell_words_.reserve(nc * 4, old_nc * 4)) attach(cell_words_texture_, GL_R32UI, cell_words_.id());
        glNamedBufferSubData(cell_offsets_.id(), GLintptr(4 * (old_nc + 1)), GLsizeiptr(4 * (nc - old_nc)),
                             mesh_.cell_offsets.data() + old_nc + 1);
        glNamedBufferSubData(cell_words_.id(), GLintptr(4 * old_nc), GLsizeiptr(4 * (nc - old_nc)), words_.data() + old_nc);
    }
    if (connectivity_.reserve(mesh_.connectivity.size() * 4, mesh_.connectivity.size() * 4))
        attach(connectivity_texture_, GL_R32UI, connectivity_.id());
    reserve_tables(/*keep=*/true);
    point_scatter_->run(points_.id(), point_stamps_.id(), stamp_);
    cell_scatter_->run(connectivity_.id(), cell_stamps_.id(), stamp_);
    bytes_ = gpu_capacity_bytes();
    FX_GL_CHECK("update mesh");
    return range_known ? range : range_of(geometry_.scalars);
}

void GlProjector::flush_triangles() const {
    for (std::uint32_t c : untriangulated_) {
        triangles_stale_[c] = 0;
        if (c < mesh_.cell_count()) triangulate_cell(c);
    }
    untriangulated_.clear();
}

void GlProjector::triangulate_cell(std::size_t c) const {
    const CellType type = mesh_.cell_types[c];
    const std::uint32_t* cv = mesh_.cell_vertices(c);
    const std::uint32_t v = std::uint32_t(vertices_per_cell_);
    std::uint32_t t = geometry_.cell_first_triangle[c];
    for (int f = 0; f < cell_face_count(type); ++f) {
        std::uint8_t local[2][3];
        const int halves = triangulate_face_local(cell_faces(type)[f], cv, local);
        for (int h = 0; h < halves; ++h, ++t) {
            for (int k = 0; k < 3; ++k) {
                geometry_.triangles[t][k] = cv[local[h][k]];
                cell_triangle_vertices_[3 * std::size_t(t) + k] = std::uint32_t(c) * v + local[h][k];
            }
            geometry_.triangle_cell[t] = std::uint32_t(c);
        }
    }
}

void GlProjector::reserve_tables(bool keep) {
    // Planes and scalar functions keep the room after the triangles for a frame's tetrahedra
    // (upload_pieces) as they have it; with `keep`, what is built stays.
    const std::size_t nt = geometry_.triangles.size(), nc = mesh_.cell_count(), np = mesh_.point_count();
    const std::size_t table = nt * sizeof(glm::vec4);
    const auto kept = [keep](const gl::GrowingBuffer& b) { return keep ? b.capacity() : 0; };
    if (tables_reserved_) {
        if (planes_.reserve(table, kept(planes_))) attach(planes_texture_, GL_RGBA32F, planes_.id());
        if (scalar_fns_.reserve(table, kept(scalar_fns_))) attach(scalar_fns_texture_, GL_RGBA32F, scalar_fns_.id());
        // The rows: by slot (a renderer updated in place), else as many as build_tables lays out.
        if (barycentrics_.reserve(all_tetrahedra() || !updated_in_place_ ? 16 : 2 * table, kept(barycentrics_)))
            attach(barycentrics_texture_, GL_RGBA32F, barycentrics_.id());
        if (fold_bases_.reserve(all_tetrahedra() ? 16 : nc * 4, kept(fold_bases_)))
            attach(fold_bases_texture_, GL_R32UI, fold_bases_.id());
        if (elements_.reserve(3 * nt * 4, kept(elements_)) && vertex_array_)
            glVertexArrayElementBuffer(vertex_array_.id(), elements_.id());
    }
    // New stamps are 0: older than any update.
    const auto stamps = [keep](gl::GrowingBuffer& buffer, std::size_t count) {
        const std::size_t before = buffer.capacity();
        buffer.reserve(count * 4, keep ? before : 0);
        if (buffer.capacity() > before) {
            const GLuint zero = 0;
            glClearNamedBufferSubData(buffer.id(), GL_R32UI, GLintptr(before), GLsizeiptr(buffer.capacity() - before),
                                      GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        }
    };
    stamps(point_stamps_, np);
    stamps(cell_stamps_, nc);
}

void GlProjector::set_planar_tolerance(double tolerance) {
    if (tolerance == planar_tolerance_) return;
    planar_tolerance_ = tolerance;
    build_all_ = true;
    rows_laid_out_ = false;
}

void GlProjector::set_culling(bool culling) {
    if (culling == culling_) return;
    culling_ = culling;
    culled_view_valid_ = false;
    elements_all_ = true;
}

void GlProjector::prepare_draw(const Camera& camera, const Viewport& viewport) {
    build_tables(&camera, double(viewport.width) / double(viewport.height));
}

void GlProjector::prepare_tables() { build_tables(nullptr, 0.0); }

void GlProjector::build_tables(const Camera* view, double aspect) {
    const bool same_view = !view || (culled_view_valid_ && culled_aspect_ == aspect && culled_camera_.eye == view->eye &&
                                     culled_camera_.target == view->target && culled_camera_.up == view->up &&
                                     culled_camera_.fov_y_degrees == view->fov_y_degrees &&
                                     culled_camera_.ortho_height == view->ortho_height &&
                                     culled_camera_.near_distance == view->near_distance &&
                                     culled_camera_.projection == view->projection);
    const bool view_changed = culling_ && !same_view;
    const Camera& camera = view ? *view : culled_camera_;
    if (!build_all_ && built_stamp_ == stamp_ && !elements_all_ && !view_changed) return;
    if (mesh_.cell_count() == 0) {
        build_all_ = elements_all_ = false;
        built_stamp_ = stamp_;
        return;
    }
    gl::StateGuard guard;
    if (!tables_reserved_) { // the first pass that reads the tables: room for them, every cell built
        tables_reserved_ = true;
        reserve_tables(/*keep=*/true);
        bytes_ = gpu_capacity_bytes();
        build_all_ = elements_all_ = true;
    }
    // The rows' layout (projector_tables.comp): compact unless the renderer takes in-place
    // updates; a change of layout rebuilds every cell.
    if (compact_rows_ && updated_in_place_) compact_rows_ = false, build_all_ = true;
    const int layout = all_tetrahedra() || !compact_rows_ ? kTableLayoutFull : rows_laid_out_ ? kTableLayoutKept : kTableLayoutDecide;
    if (!tables_program_ || tables_program_cells_ != vertices_per_cell_) { // linked once per kind of mesh
        tables_program_ = &program({"projector_tables.comp"}, mesh_defines());
        tables_program_cells_ = vertices_per_cell_;
    }
    const GLuint p = tables_program_->id();
    glUseProgram(p);
    glProgramUniform1ui(p, kUniformTableCells, GLuint(mesh_.cell_count()));
    glProgramUniform1ui(p, kUniformTableBuilt, GLuint(built_stamp_));
    glProgramUniform1i(p, kUniformTableAll, build_all_ ? 1 : 0);
    glProgramUniform1i(p, kUniformTableElements, elements_all_ || view_changed ? 1 : 0);
    glProgramUniform1i(p, kUniformTableCull, culling_ ? 1 : 0);
    glProgramUniform1d(p, kUniformTablePlanarTolerance, planar_tolerance_);
    glProgramUniform1i(p, kUniformTableLayout, layout);
    if (view_changed) {
        // The view's left, right, bottom, top and near planes (not the far one: no path cuts cells
        // there) in the relative frame, moved out by a hair of the mesh's size: cells on a plane
        // stay drawn whatever float rounding does.
        const Frustum frustum(camera, aspect);
        const double slack = 1e-4 * std::max(glm::length(bounds_.hi - bounds_.lo), kMinProjectorExtent);
        glm::vec4 planes[5];
        for (int k = 0; k < 5; ++k) {
            const glm::dvec4& f = frustum.planes[k];
            const glm::dvec3 n(f);
            const double length = std::max(glm::length(n), 1e-300);
            // n·(p_world − eye) + w = n·p_rel + n·(origin − eye) + w
            const double w = (f.w + glm::dot(n, geometry_.origin - frustum.origin)) / length + slack;
            planes[k] = glm::vec4(glm::vec3(n / length), float(w));
        }
        glProgramUniform4fv(p, kUniformTableCullPlanes, 5, glm::value_ptr(planes[0]));
        culled_camera_ = camera;
        culled_aspect_ = aspect;
        culled_view_valid_ = true;
    }
    const std::pair<GLuint, GLuint> textures[] = {{kUnitPoints, points_texture_.id()},
                                                  {kUnitConnectivity, connectivity_texture_.id()},
                                                  {kUnitCellOffsets, cell_offsets_texture_.id()}};
    for (const auto& [unit, texture] : textures) {
        glBindTextureUnit(unit, texture);
        glBindSampler(unit, 0);
    }
    const std::pair<GLuint, GLuint> buffers[] = {{kBindingPlanesOut, planes_.id()},
                                                 {kBindingScalarFunctionsOut, scalar_fns_.id()},
                                                 {kBindingBarycentricsOut, barycentrics_.id()},
                                                 {kBindingElementsOut, elements_.id()},
                                                 {kBindingPointStamps, point_stamps_.id()},
                                                 {kBindingCellStamps, cell_stamps_.id()},
                                                 {kBindingCellWordsOut, cell_words_.id()},
                                                 {kBindingFoldBasesOut, fold_bases_.id()}};
    for (const auto& [binding, buffer] : buffers) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer);
    glDispatchCompute(GLuint((mesh_.cell_count() + 63) / 64), 1, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    (layout == kTableLayoutDecide ? GL_BUFFER_UPDATE_BARRIER_BIT : 0u)); // lay_out_rows reads the words
    if (layout == kTableLayoutDecide) lay_out_rows(p);
    build_all_ = elements_all_ = false;
    built_stamp_ = stamp_;
    FX_GL_CHECK("projector tables");
}

void GlProjector::lay_out_rows(GLuint program) {
    // The planar bits the pass decided, back to the CPU (a new mesh or tolerance: once), each
    // cell that is not planar given its row pairs in the order of the cells, then the rows.
    const std::size_t nc = mesh_.cell_count();
    resize_kept(laid_out_words_, nc);
    resize_kept(fold_base_data_, nc);
    glGetNamedBufferSubData(cell_words_.id(), 0, GLsizeiptr(nc * 4), laid_out_words_.data());
    std::size_t rows = 0;
    for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t w = laid_out_words_[c];
        fold_base_data_[c] = (w & kWordPlanar) ? 0u : std::uint32_t(rows);
        rows += (w & kWordPlanar) ? 0u : (w & ((1u << kWordCountBits) - 1u)) + 1u;
    }
    check_texture_buffer_size(2 * rows, "barycentric rows");
    fold_bases_.upload(fold_base_data_.data(), nc * 4, fold_bases_texture_, GL_R32UI);
    if (barycentrics_.reserve(2 * rows * sizeof(glm::vec4))) attach(barycentrics_texture_, GL_RGBA32F, barycentrics_.id());
    fold_rows_ = rows;
    rows_laid_out_ = true;
    bytes_ = gpu_capacity_bytes();
    if (rows == 0) return;
    glProgramUniform1i(program, kUniformTableLayout, kTableLayoutRowsOnly);
    glProgramUniform1i(program, kUniformTableElements, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingBarycentricsOut, barycentrics_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingFoldBasesOut, fold_bases_.id());
    glDispatchCompute(GLuint((nc + 63) / 64), 1, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
}

const ProjectorGeometry& GlProjector::geometry() const {
    flush_triangles();
    if (planes_stale_) {
        compute_triangle_planes(geometry_);
        planes_stale_ = false;
    }
    return geometry_;
}

bool GlProjector::set_scalars(const std::vector<float>& values) {
    if (values.size() != geometry_.scalars.size())
        throw Error("cell renderer: set_scalars got " + std::to_string(values.size()) + " values for " +
                    std::to_string(geometry_.scalars.size()) + " points");
    for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i])) throw Error("cell renderer: set_scalars: value " + std::to_string(i) + " is not finite");
    geometry_.scalars = values;
    upload_point_data();
    build_all_ = true; // the scalar functions follow the values (the GPU rebuilds every cell's)
    field_range_ = range_of(values);
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
    const ScalarField* field = field_of(source, scalar_name);
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
    build_projector_geometry(mesh_, field, geometry_, /*planes=*/false);
    planes_stale_ = true;
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
    untriangulated_.clear();
    triangles_stale_.assign(triangles_stale_.size(), 0);
    for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t first = geometry_.cell_first_triangle[c], n = geometry_.cell_first_triangle[c + 1] - first;
        words_[c] = cell_word(first, n);
        triangulate_cell(c);
    }

    // The tables are the GPU's to build (prepare_draw), every cell of them; the stamps start
    // over.
    connectivity_.upload(mesh_.connectivity.data(), mesh_.connectivity.size() * 4, connectivity_texture_, GL_R32UI);
    cell_offsets_.upload(mesh_.cell_offsets.data(), mesh_.cell_offsets.size() * 4, cell_offsets_texture_, GL_R32UI);
    cell_words_.upload(words_.data(), nc * 4, cell_words_texture_, GL_R32UI);
    if (!vertex_array_) vertex_array_ = gl::VertexArray::create();
    reserve_tables(/*keep=*/false);
    glVertexArrayElementBuffer(vertex_array_.id(), elements_.id());
    const GLuint zero = 0;
    glClearNamedBufferSubData(point_stamps_.id(), GL_R32UI, 0, GLsizeiptr(point_stamps_.capacity()), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    glClearNamedBufferSubData(cell_stamps_.id(), GL_R32UI, 0, GLsizeiptr(cell_stamps_.capacity()), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    stamp_ = built_stamp_ = 0;
    build_all_ = elements_all_ = true;
    compact_rows_ = !updated_in_place_;
    rows_laid_out_ = false;
    bytes_ = gpu_capacity_bytes();
    FX_GL_CHECK("upload mesh");
}

std::size_t GlProjector::gpu_capacity_bytes() const {
    const ProjectorMemory m = memory();
    return m.mesh + m.cell_tables + m.unique_faces;
}

ProjectorMemory GlProjector::memory() const {
    ProjectorMemory m;
    m.mesh = std::size_t(kTableSize + 1) * 3 * 16; // the transfer-function tables
    for (const gl::GrowingBuffer* b : {&points_, &connectivity_, &cell_offsets_, &cell_words_, &point_stamps_, &cell_stamps_})
        m.mesh += b->capacity();
    for (const gl::GrowingBuffer* b : {&planes_, &scalar_fns_, &barycentrics_, &fold_bases_, &elements_, &piece_points_})
        m.cell_tables += b->capacity();
    m.barycentric_rows = barycentrics_.capacity();
    m.unique_faces = unique_faces_buffer_.capacity();
    return m;
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
        {kUnitFoldBases, fold_bases_texture_.id()},
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

glm::dmat4 GlProjector::raster_view_projection(const Camera& camera, const Viewport& viewport, double* ortho_far) const {
    const ProjectorView v = view(camera);
    // No cell is cut at the far plane, as the scan-line reference cuts none: an orthographic
    // view rasterises with far moved past the mesh's deepest corner where that lies beyond it.
    const double far =
        v.orthographic ? std::max(camera.far_distance, v.near_distance + 1.01 * std::max(bounds_depth_range(v).y, 0.0)) : 0.0;
    if (ortho_far) *ortho_far = far;
    return raster_projection(camera, v.near_distance, double(viewport.width) / double(viewport.height), far) * v.view;
}

glm::ivec4 GlProjector::screen_rect(const Camera& camera, const Viewport& viewport) const {
    const glm::ivec4 whole(0, 0, viewport.width, viewport.height);
    if (geometry_.positions.empty()) return glm::ivec4(0);
    const glm::dvec2 depth = bounds_depth_range(view(camera)); // beyond the near plane
    if (depth.y < 0.0) return glm::ivec4(0);                    // wholly before it: nothing drawn
    if (depth.x <= 0.0) return whole;                           // across it: corners behind the eye bound nothing
    const glm::dmat4 vp = raster_view_projection(camera, viewport, nullptr);
    glm::dvec2 lo(HUGE_VAL), hi(-HUGE_VAL);
    for (int k = 0; k < 8; ++k) {
        const glm::dvec4 c = vp * glm::dvec4(bounds_.corner(k), 1.0);
        const glm::dvec2 ndc = glm::dvec2(c) / c.w;
        lo = glm::min(lo, ndc), hi = glm::max(hi, ndc);
    }
    if (!(std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y))) return whole;
    // To pixels, a pixel wider on every side (rounding of the corners' projection), clamped.
    const glm::dvec2 size(viewport.width, viewport.height);
    const glm::dvec2 a = glm::clamp(glm::floor((lo * 0.5 + 0.5) * size) - 1.0, glm::dvec2(0.0), size);
    const glm::dvec2 b = glm::clamp(glm::ceil((hi * 0.5 + 0.5) * size) + 1.0, glm::dvec2(0.0), size);
    if (!(b.x > a.x && b.y > a.y)) return glm::ivec4(0); // off screen
    return glm::ivec4(int(a.x), int(a.y), int(b.x - a.x), int(b.y - a.y));
}

void GlProjector::set_view_uniforms(const gl::Program& program, const Camera& camera, const Viewport& viewport) const {
    const ProjectorView v = view(camera);
    double ortho_far = 0.0;
    const glm::mat4 vp(raster_view_projection(camera, viewport, &ortho_far));
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
    glm::dvec2 centre(0.0); // below
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
    // From the view's axis rather than the pass's corner: the pixel c where the ray runs along
    // `forward` (perspective: its direction has no right or up part; orthographic: its origin
    // is the eye), the direction scaled to a unit forward part. For a symmetric view c is the
    // viewport's centre; for an off-axis tile of a larger frame it is that frame's centre in
    // the tile's pixels, so every tile, and the whole frame, hand the shader the same axis ray
    // and steps, and pixel offsets from c that differ by whole pixels (project.glsl).
    {
        const glm::dvec3 right(v.view[0][0], v.view[1][0], v.view[2][0]), up(v.view[0][1], v.view[1][1], v.view[2][1]);
        const bool ortho = camera.orthographic();
        const glm::dvec3 at = ortho ? origin - v.eye : direction, along_x = ortho ? origin_dx : direction_dx,
                         along_y = ortho ? origin_dy : direction_dy;
        // Solve at + cx·along_x + cy·along_y ⟂ right, up.
        const double a = glm::dot(along_x, right), b = glm::dot(along_y, right), c = glm::dot(along_x, up),
                     d = glm::dot(along_y, up);
        const double det = a * d - b * c;
        const double rx = -glm::dot(at, right), ry = -glm::dot(at, up);
        centre = det != 0.0 ? glm::dvec2((rx * d - b * ry) / det, (a * ry - c * rx) / det) : glm::dvec2(0.0);
        origin += centre.x * origin_dx + centre.y * origin_dy;
        direction += centre.x * direction_dx + centre.y * direction_dy;
        if (!ortho) {
            const double k = glm::dot(direction, f); // > 0: the axis ray looks ahead
            if (k > 0.0) direction /= k, direction_dx /= k, direction_dy /= k;
        }
    }
    glProgramUniform2f(p, kUniformRayCentre, float(centre.x), float(centre.y));
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
    bind_frame();
    FX_GL_CHECK("upload frame data");
}

void GlProjector::bind_frame() const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingFrame, frame_.id()); }

std::size_t GlProjector::unique_face_triangles() {
    if (!unique_faces_ready_) {
        flush_triangles();
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

GlCellList::GlCellList(const GlProjector& projector) : projector_(projector) { vertex_array_ = gl::VertexArray::create(); }

void GlCellList::upload(const std::vector<std::uint32_t>& cells, const std::vector<glm::vec2>& ranges) {
    slots_ = cells.size();
    cells_.upload(cells.data(), cells.size() * 4, cells_texture_, GL_R32UI);
    if (!ranges.empty()) slot_data_.upload(ranges.data(), ranges.size() * sizeof(glm::vec2), slot_data_texture_, GL_RG32F);
    const CellFace* tetra_faces = cell_faces(CellType::Tetra);
    const std::uint32_t v = std::uint32_t(projector_.vertices_per_cell());
    if (projector_.all_tetrahedra()) {
        // The same pattern in every slot: made once for as many slots as a frame has had.
        if (slots_ <= tetra_slots_) return;
        tetra_slots_ = std::max(slots_, tetra_slots_ + tetra_slots_ / 2);
        resize_kept(elements_data_, 12 * tetra_slots_);
        for (std::size_t s = 0; s < tetra_slots_; ++s)
            for (int f = 0; f < 4; ++f)
                for (int k = 0; k < 3; ++k) elements_data_[12 * s + 3 * f + k] = std::uint32_t(s) * v + tetra_faces[f].v[k];
    } else {
        // Each entry's triangles, renumbered to its slot: vertex k of slot s is s·8 + k.
        const std::vector<std::uint32_t>& first_triangle = projector_.cell_first_triangle();
        const std::vector<std::uint32_t>& mesh_elements = projector_.cell_triangle_vertices();
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
    }
    if (elements_.upload(elements_data_.data(), elements_data_.size() * 4))
        glVertexArrayElementBuffer(vertex_array_.id(), elements_.id());
    FX_GL_CHECK("cell list upload");
}

void GlCellList::bind(const gl::Program& program) const {
    glProgramUniform1ui(program.id(), kUniformPieceBase, GLuint(projector_.triangle_count()));
    glBindTextureUnit(kUnitCellList, cells_texture_.id());
    glBindTextureUnit(kUnitSlotData, slot_data_texture_.id());
    glBindSampler(kUnitCellList, 0);
    glBindSampler(kUnitSlotData, 0);
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
