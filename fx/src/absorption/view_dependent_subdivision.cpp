// Based on: Max, Williams & Silva 2000, §V (view-dependent subdivision of problem cells) and
// §IV (consistent tetrahedra).
#include "absorption/view_dependent_subdivision.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "frame_storage.hpp"
#include "mesh/tetrahedralize.hpp"

namespace cellfx::fx {

ViewDependentSubdivision::ViewDependentSubdivision(const CellMesh& mesh, double planarity)
    : mesh_(mesh), planarity_(planarity) {
    find_candidates();
}

void ViewDependentSubdivision::mesh_changed() {
    find_candidates();
    subdivided_count_ = 0; // the working mesh is the old mesh's: cells() is the mesh until update()
    problem_faces_ = 0;
    changed_ = true;
}

void ViewDependentSubdivision::find_candidates() {
    const CellMesh& mesh = mesh_;
    const std::size_t nc = mesh.cell_count();
    assign_kept(subdivided_, nc, std::uint8_t(0));
    assign_kept(problem_, nc, std::uint8_t(0));
    candidates_.clear();
    for (std::size_t c = 0; c < nc; ++c) {
        const CellType type = mesh.cell_types[c];
        const std::uint32_t* cv = mesh.cell_vertices(c);
        const CellFace* faces = cell_faces(type);
        for (int k = 0; k < cell_face_count(type); ++k) {
            if (faces[k].count != 4) continue;
            std::uint32_t tri[2][3];
            if (triangulate_face(faces[k], cv, tri) != 2) continue;
            // S = (L, b, c) and T = (L, c, d): they share the diagonal L–c (triangulate_face).
            const glm::dvec3 l = mesh.points[tri[0][0]];
            const glm::dvec3 s1 = mesh.points[tri[0][1]], s2 = mesh.points[tri[0][2]];
            const glm::dvec3 t1 = mesh.points[tri[1][1]], t2 = mesh.points[tri[1][2]];
            const glm::dvec3 ns = glm::cross(s1 - l, s2 - l), nt = glm::cross(t1 - l, t2 - l);
            const double ls = glm::length(ns), lt = glm::length(nt);
            if (!(ls > 0.0) || !(lt > 0.0)) continue; // a degenerate triangle bounds nothing
            const double edge = std::max({glm::length(s1 - l), glm::length(s2 - l), glm::length(t1 - l),
                                          glm::length(t2 - l), glm::length(s2 - s1), glm::length(t2 - t1)});
            // b, the vertex of S off the diagonal, against T's outward plane: outside is reflex.
            const double fold = glm::dot(nt / lt, s1 - l);
            if (fold > planarity_ * edge) candidates_.push_back({std::uint32_t(c), l, ns / ls, nt / lt});
        }
    }
}

bool ViewDependentSubdivision::update(const Camera& camera) {
    std::fill(problem_.begin(), problem_.end(), std::uint8_t(0));
    problem_faces_ = 0;
    const bool ortho = camera.orthographic();
    const glm::dvec3 towards_eye = -camera.forward();
    for (const Candidate& k : candidates_) {
        const glm::dvec3 to_eye = ortho ? towards_eye : camera.eye - k.corner;
        const double fs = glm::dot(k.normal_s, to_eye), ft = glm::dot(k.normal_t, to_eye);
        // One triangle faces the eye and the other faces away: with a reflex fold, some ray
        // leaves through one and comes back in through the other.
        if ((fs > 0.0 && ft < 0.0) || (fs < 0.0 && ft > 0.0)) {
            problem_[k.cell] = 1;
            ++problem_faces_;
        }
    }
    if (problem_ == subdivided_ && !changed_) return false;
    changed_ = false;
    std::copy(problem_.begin(), problem_.end(), subdivided_.begin()); // restored cells drop out, new ones come in
    subdivided_count_ = static_cast<std::size_t>(std::count(subdivided_.begin(), subdivided_.end(), std::uint8_t(1)));
    rebuild();
    return true;
}

void ViewDependentSubdivision::rebuild() {
    ++rebuilds_;
    working_.cell_types.clear();
    working_.cell_offsets.assign(1, 0u);
    working_.connectivity.clear();
    parent_.clear();
    piece_.clear();
    if (subdivided_count_ == 0) return;
    // Into the storage of the last rebuild (the block keeps its name: no string made per frame).
    assign_range_kept(working_.points, mesh_.points.begin(), mesh_.points.end());
    if (working_.blocks.empty()) working_.begin_block("view-dependent subdivision");
    working_.blocks[0].first_cell = 0;
    working_.blocks[0].cell_count = 0;
    for (std::size_t c = 0; c < mesh_.cell_count(); ++c) {
        const CellType type = mesh_.cell_types[c];
        if (subdivided_[c]) {
            std::uint32_t tets[kMaxCellTetrahedra][4];
            const int n = subdivide_cell(type, mesh_.cell_vertices(c), tets);
            for (int i = 0; i < n; ++i) {
                working_.add_cell(CellType::Tetra, tets[i]);
                parent_.push_back(static_cast<std::uint32_t>(c));
                piece_.push_back(1);
            }
        } else {
            working_.add_cell(type, mesh_.cell_vertices(c));
            parent_.push_back(static_cast<std::uint32_t>(c));
            piece_.push_back(0);
        }
    }
}

} // namespace cellfx::fx
