// Based on: Max, Williams & Silva 2000, §II (polyhedron projection and "over" back to front),
// §III (visibility sorting), §V (view-dependent subdivision) — the GL half of the two
// Absorption flavours; shaders absorption.{vert,frag}, cells.vert with absorption_exact.frag,
// absorption_resolve.frag.
#include "passes/absorption_pass.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <exception>
#include <iterator>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "fx/error.hpp"
#include "transfer/segment_integral.hpp"
#include "parallel_tasks.hpp"
#include "gl/gl_check.hpp"
#include "projector/gl_interface.hpp"
#include "frame_storage.hpp"
#include "fx/transfer_function.hpp"

namespace cellfx::fx {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// The 2-D table of §II: 1024² keeps its bilinear error below 4e-5 in α with K = 12 (see
// build_opacity_table); K = 12 leaves e^(−12) = 6e-6 of the light behind a polygon whose
// optical depth reaches or exceeds it.
constexpr int kOpacitySizeTexels = 1024;
// Pre-integration table: 128 scalar samples per end and 64 lengths (16 MiB of RGBA32F).
constexpr std::size_t kPreScalars = 128, kPreLengths = 64;
// Classic: cells per run of the order projected as one task (fewer: one task), and at most this
// many runs.
constexpr std::size_t kCellsPerChunk = 4096, kMaxChunks = 64;

} // namespace

AbsorptionPass::AbsorptionPass(GlProjector& projector)
    : projector_(projector), classic_programs_(projector.programs({"absorption.vert", "absorption.frag"})),
      exact_programs_(projector.programs({"cells.vert", "absorption_exact.frag"}, projector.mesh_defines().set("CELL_LIST"))),
      subdivision_(projector.mesh()), exact_list_(projector) {
    measure_cells();
    max_length_ = longest_chord_;

    // Classic: the frame's ClassicVertex array as attributes 0–2 (absorption.vert).
    vao_ = gl::VertexArray::create();
    glVertexArrayAttribFormat(vao_.id(), 0, 4, GL_FLOAT, GL_FALSE, GLuint(offsetof(ClassicVertex, position_uv)));
    glVertexArrayAttribFormat(vao_.id(), 1, 3, GL_FLOAT, GL_FALSE, GLuint(offsetof(ClassicVertex, color)));
    glVertexArrayAttribFormat(vao_.id(), 2, 2, GL_FLOAT, GL_FALSE, GLuint(offsetof(ClassicVertex, depth)));
    for (GLuint a = 0; a < 3; ++a) {
        glVertexArrayAttribBinding(vao_.id(), a, 0);
        glEnableVertexArrayAttrib(vao_.id(), a);
    }
}

AbsorptionPass::~AbsorptionPass() = default;

void AbsorptionPass::measure_cells() {
    const CellMesh& mesh = projector_.mesh();
    // The longest chord of a convex cell is at most its bounding-box diagonal.
    double longest = 0.0;
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const std::uint32_t* cv = mesh.cell_vertices(c);
        glm::dvec3 lo(1e300), hi(-1e300);
        for (int i = 0; i < cell_vertex_count(mesh.cell_types[c]); ++i) {
            const glm::dvec3& p = mesh.points[cv[i]];
            lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
        longest = std::max(longest, glm::length(hi - lo));
    }
    longest_chord_ = longest > 0.0 ? longest * (1.0 + 1e-6) : 1.0;
}

void AbsorptionPass::transfer_function_changed() {
    for (auto& builder : builders_) builder->transfer_function_changed(); // their breakpoints
    preintegration_ready_ = false;
}

std::size_t AbsorptionPass::gpu_bytes() const { return table_bytes_ + frame_.capacity() + index_.capacity() + exact_list_.gpu_bytes(); }

const VisibilitySort& AbsorptionPass::sort_for(SortMethod method, CellRenderStats& stats) {
    const std::size_t m = static_cast<std::size_t>(method);
    if (m >= kSortMethods) throw Error("absorption: unknown visibility sort");
    std::unique_ptr<VisibilitySort>& sort = sorts_[m];
    if (!sort || sort_stale_[m]) {
        const auto t0 = Clock::now();
        if (sort) sort->rebuild(subdivision_.cells()); // into the storage of its last build
        else sort = std::make_unique<VisibilitySort>(subdivision_.cells(), method);
        sort_stale_[m] = false;
        stats.setup_ms += ms_since(t0);
    }
    return *sort;
}

void AbsorptionPass::prepare(const Camera& camera, const Viewport& viewport, bool exact,
                             const CellRenderOptions& options, const ParallelFor& parallel_for,
                             CellRenderStats& stats) {
    auto t0 = Clock::now();
    const std::vector<TransferPoint>& tf = projector_.transfer_function().points();
    const auto same_point = [](const TransferPoint& a, const TransferPoint& b) {
        return a.s == b.s && a.color == b.color && a.sigma == b.sigma;
    };
    if (!std::equal(tf.begin(), tf.end(), tf_points_.begin(), tf_points_.end(), same_point)) {
        transfer_function_changed();
        assign_range_kept(tf_points_, tf.begin(), tf.end());
    }
    if (mesh_changed_) {
        mesh_changed_ = false;
        subdivision_.mesh_changed();
        measure_cells();
        // The table's lengths reach past the longest chord; rebuilt when a chord leaves that
        // range or uses less than half of it (with a 25% margin, so that a mesh changing a little
        // every frame does not rebuild it every frame).
        if (longest_chord_ > max_length_ || longest_chord_ < 0.5 * max_length_) {
            max_length_ = 1.25 * longest_chord_;
            preintegration_ready_ = false;
        }
    }
    // §V: problem cells for this view; the sorts are built on the working mesh, so a new one
    // (or a changed mesh) makes them stale.
    if (subdivision_.update(camera)) std::fill(std::begin(sort_stale_), std::end(sort_stale_), true);
    const CellMesh& cells = subdivision_.cells();
    stats.subdivision_ms = ms_since(t0);
    stats.problem_cells = subdivision_.subdivided_cells();

    const VisibilitySort& sort = sort_for(options.sort, stats);
    t0 = Clock::now();
    SortStats sort_stats;
    sort.sort(camera, order_, &sort_stats);
    stats.sort_ms = ms_since(t0);
    stats.sort_cycles = sort_stats.cycles;

    t0 = Clock::now();
    if (exact) {
        build_exact_frame();
        stats.cells_drawn = order_.size();
        stats.projection_ms = ms_since(t0);
        return;
    }

    // Classic: the projected subdivisions, in order, split into contiguous runs per thread.
    if (classic_settings_.slice_breakpoints != options.slice_breakpoints) {
        classic_settings_.slice_breakpoints = options.slice_breakpoints;
        for (auto& builder : builders_) builder->set_settings(classic_settings_);
    }
    // Contiguous runs of the order, one builder each, concatenated in order by draw(). More runs
    // than threads, so that a host's job system can balance them.
    const std::size_t n = order_.size();
    const std::size_t chunks = std::clamp<std::size_t>(n / kCellsPerChunk, 1, kMaxChunks);
    while (builders_.size() < chunks)
        builders_.push_back(std::make_unique<ClassicAbsorptionBuilder>(projector_.geometry(), projector_.transfer_function(), classic_settings_));
    if (parts_.size() < chunks) parts_.resize(chunks);
    chunks_ = chunks;
    const ProjectorView view = projector_.view(camera);
    if (subpixel_bits_ < 0) {
        GLint bits = 0;
        glGetIntegerv(GL_SUBPIXEL_BITS, &bits);
        subpixel_bits_ = std::max(0, int(bits));
    }
    const ProjectionFrame frame = make_projection_frame(view, camera, viewport.width, viewport.height, subpixel_bits_);
    parallel_for_each(
        parallel_for, chunks,
        [&](std::size_t t) {
            const std::size_t b = n * t / chunks, e = n * (t + 1) / chunks;
            parts_[t].clear();
            builders_[t]->set_view(view, frame);
            builders_[t]->append(cells, order_.data() + b, e - b, parts_[t]);
        },
        errors_);
    std::size_t pieces = 0, culled = 0, polygons = 0;
    for (std::size_t t = 0; t < chunks; ++t) {
        pieces += parts_[t].pieces, culled += parts_[t].culled_cells, polygons += parts_[t].polygons;
    }
    stats.cells_drawn = n - culled;
    stats.polygons = polygons;
    stats.pieces = pieces;
    stats.projection_ms = ms_since(t0);
}

void AbsorptionPass::build_exact_frame() {
    // The frame's cells in visibility order: a whole cell of the mesh by its id, a tetrahedron
    // made for this view (§V) as kPieceBit | its index in pieces_ (GlProjector::upload_pieces).
    const CellMesh& cells = subdivision_.cells();
    resize_kept(list_cells_, order_.size());
    pieces_.clear();
    for (std::size_t i = 0; i < order_.size(); ++i) {
        const std::uint32_t w = order_[i];
        if (subdivision_.is_piece(w)) {
            const std::uint32_t* tet = cells.cell_vertices(w);
            list_cells_[i] = kPieceBit | std::uint32_t(pieces_.size() / 4);
            pieces_.insert(pieces_.end(), tet, tet + 4);
        } else {
            list_cells_[i] = subdivision_.parent(w);
        }
    }
}

void AbsorptionPass::ensure_opacity_table() {
    if (opacity_ready_) return;
    const OpacityTable table = build_opacity_table(kOpacitySizeTexels, classic_settings_.max_product);
    opacity_buffer_ = gl::make_buffer(GLsizeiptr(table.values.size() * sizeof(float)), table.values.data());
    opacity_ = gl::Texture::create(GL_TEXTURE_BUFFER);
    glTextureBuffer(opacity_.id(), GL_R32F, opacity_buffer_.id());
    FX_GL_CHECK("absorption: opacity table");
    table_bytes_ += table.values.size() * sizeof(float);
    opacity_ready_ = true;
}

void AbsorptionPass::ensure_preintegration_table() {
    if (preintegration_ready_) return;
    const TransferFunction& tf = projector_.transfer_function();
    if (tf.points().empty()) throw Error("absorption-exact: the transfer function has no points");
    const PreintegrationTable table = build_preintegration_table(tf, kPreScalars, kPreLengths, max_length_);
    // A buffer texture (absorption_exact.frag): (il·n_s + ib)·n_s + if.
    if (!preintegration_buffer_) {
        preintegration_buffer_ = gl::make_buffer(GLsizeiptr(table.entries.size() * sizeof(glm::vec4)), nullptr, GL_DYNAMIC_STORAGE_BIT);
        preintegration_ = gl::Texture::create(GL_TEXTURE_BUFFER);
        glTextureBuffer(preintegration_.id(), GL_RGBA32F, preintegration_buffer_.id());
        table_bytes_ += table.entries.size() * sizeof(glm::vec4);
    }
    glNamedBufferSubData(preintegration_buffer_.id(), 0, GLsizeiptr(table.entries.size() * sizeof(glm::vec4)), table.entries.data());
    FX_GL_CHECK("absorption: pre-integration table");
    s_lo_ = table.s_lo;
    s_per_unit_ = double(table.n_s - 1) / (table.s_hi - table.s_lo);
    l_per_unit_ = double(table.n_l - 1) / table.max_length;
    preintegration_ready_ = true;
}

void AbsorptionPass::upload(bool exact) {
    if (exact) {
        ensure_preintegration_table();
        projector_.upload_pieces(pieces_);
        exact_list_.upload(list_cells_, {});
        return;
    }
    ensure_opacity_table();
    // The runs' vertices and indices one after the other (each run's indices count from its
    // first vertex: drawn with that base vertex).
    resize_kept(run_vertices_, chunks_ + 1);
    resize_kept(run_indices_, chunks_ + 1);
    run_vertices_[0] = run_indices_[0] = 0;
    for (std::size_t t = 0; t < chunks_; ++t) {
        run_vertices_[t + 1] = run_vertices_[t] + parts_[t].vertices.size();
        run_indices_[t + 1] = run_indices_[t] + parts_[t].indices.size();
    }
    frame_.reserve(run_vertices_[chunks_] * sizeof(ClassicVertex));
    index_.reserve(run_indices_[chunks_] * sizeof(std::uint32_t));
    glVertexArrayVertexBuffer(vao_.id(), 0, frame_.id(), 0, sizeof(ClassicVertex));
    glVertexArrayElementBuffer(vao_.id(), index_.id());
    for (std::size_t t = 0; t < chunks_; ++t) {
        const ClassicGeometry& part = parts_[t];
        if (part.indices.empty()) continue;
        glNamedBufferSubData(frame_.id(), GLintptr(run_vertices_[t] * sizeof(ClassicVertex)),
                             GLsizeiptr(part.vertices.size() * sizeof(ClassicVertex)), part.vertices.data());
        glNamedBufferSubData(index_.id(), GLintptr(run_indices_[t] * sizeof(std::uint32_t)),
                             GLsizeiptr(part.indices.size() * sizeof(std::uint32_t)), part.indices.data());
    }
    FX_GL_CHECK("absorption upload");
}

void AbsorptionPass::draw(const Camera& camera, const Viewport& viewport, bool exact, const CellRenderOptions& options,
                          CellRenderStats& stats) {
    // Scene depth: the renderer binds the texture; the mode and ranges are per program.
    const gl::Program& classic = classic_programs_(options.scene_depth != 0);
    const gl::Program& exact_program = exact_programs_(options.scene_depth != 0);
    for (const gl::Program* p : {&classic, &exact_program})
        projector_.set_scene_depth_uniforms(*p, camera, viewport, options.scene_depth);
    glEnablei(GL_BLEND, 0);
    glBlendEquationSeparate(GL_FUNC_ADD, GL_FUNC_ADD);
    glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA); // "over", back to front
    if (exact) {
        projector_.set_view_uniforms(exact_program, camera, viewport);
        const GLuint p = exact_program.id();
        glProgramUniform3f(p, kUniformPreintegration, float(s_lo_), float(s_per_unit_), float(l_per_unit_));
        glProgramUniform3i(p, kUniformPreintegrationSize, GLint(kPreScalars), GLint(kPreScalars), GLint(kPreLengths));
        glBindTextureUnit(kUnitPreintegration, preintegration_.id());
        glBindSampler(kUnitPreintegration, 0);
        glUseProgram(p);
        exact_list_.bind(exact_program);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT); // back faces only: each pixel a cell covers gets one fragment
        if (exact_list_.size() > 0) {
            exact_list_.draw(0, exact_list_.size());
            stats.draw_calls += 1;
        }
        FX_GL_CHECK("absorption-exact draw");
        return;
    }
    glBindTextureUnit(kUnitOpacity, opacity_.id());
    glBindSampler(kUnitOpacity, 0);
    glProgramUniform1i(classic.id(), kUniformOpacitySize, kOpacitySizeTexels);
    glUseProgram(classic.id());
    glDisable(GL_CULL_FACE);
    glBindVertexArray(vao_.id());
    for (std::size_t t = 0; t < chunks_; ++t) {
        const std::size_t count = run_indices_[t + 1] - run_indices_[t];
        if (count == 0) continue;
        glDrawElementsBaseVertex(GL_TRIANGLES, GLsizei(count), GL_UNSIGNED_INT,
                                 reinterpret_cast<const void*>(run_indices_[t] * sizeof(std::uint32_t)),
                                 GLint(run_vertices_[t]));
        stats.draw_calls += 1;
    }
    FX_GL_CHECK("absorption draw");
}

} // namespace cellfx::fx
