// cellfx — view-dependent subdivision of cells with problem faces (the Absorption path).
//
// Based on: Max, Williams & Silva 2000, §V (problem faces and problem cells, subdivision kept
// between frames) and §IV (consistent tetrahedra: fx::subdivide_cell, smallest-vertex rule).
//
// A non-planar quadrilateral face F of cell A is two triangles S and T sharing the diagonal
// from F's smallest vertex L (triangulate_face — what every render path and the scan-line
// reference draw). A viewing ray from the eye V can leave A through S and enter it again
// through T exactly when S and T face the eye from opposite sides and the fold along the
// diagonal is reflex for A (the interior of S lies on V's side of T's plane, and vice versa).
// F is then a problem face for this view and A a problem cell: A is not convex as seen from V,
// a ray crosses it in two segments, and A and its neighbour across F form a visibility cycle.
// Such cells are cut into tetrahedra (planar faces, convex) for this view only; every other
// cell, curved or not, is drawn whole. The fold test is per cell (the same face is convex for
// the neighbour B, which never needs cutting because of F: its F is drawn as S and T anyway).
//
// Per mesh (constructor): every quad face that is folded reflex for its cell, beyond a
// planarity tolerance, with its two triangles' planes — O(cells). Per view (update()): the
// problem test on those candidates only; when the set of problem cells changes, the working
// mesh is rebuilt — each problem cell replaced, in place, by its tetrahedra — and cells that
// stopped being problems are restored. While the set stays the same (a camera that moves a
// little, or a mesh with planar faces, which never has candidates) nothing is rebuilt.
//
// A mesh that changes (terrain prisms, every frame) is taken again by mesh_changed(), which
// finds its candidates anew into the same storage: a steady frame allocates nothing.
//
// Ownership: keeps a reference to `mesh`, which must outlive this object and change only
// before a call to mesh_changed(). Preconditions: the mesh passed validate_mesh() with
// positively oriented cells.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/camera.hpp"
#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

class ViewDependentSubdivision {
public:
    // `planarity` is the relative fold below which a quad counts as planar: the distance of a
    // quad's fourth vertex from the plane of the other three over the quad's longest edge.
    explicit ViewDependentSubdivision(const CellMesh& mesh, double planarity = 1e-6);

    // The mesh changed (points, cells or both): its candidate faces are found again and no cell
    // is subdivided until the next update(), which then returns true.
    void mesh_changed();

    // Finds the problem cells for this camera and updates the working mesh. Returns true when
    // the working mesh changed (callers rebuild what they derived from it, e.g. a sort).
    bool update(const Camera& camera);

    // The mesh to sort and draw: the input mesh while no cell is subdivided, else a copy with
    // every problem cell replaced by its tetrahedra (same points, one block).
    const CellMesh& cells() const { return subdivided_count_ ? working_ : mesh_; }
    // Per working cell: the input cell it is (or is a tetrahedron of).
    std::uint32_t parent(std::uint32_t working_cell) const {
        return subdivided_count_ ? parent_[working_cell] : working_cell;
    }
    // True for the tetrahedra of a subdivided cell.
    bool is_piece(std::uint32_t working_cell) const {
        return subdivided_count_ && piece_[working_cell] != 0;
    }

    std::size_t candidate_faces() const { return candidates_.size(); } // reflex non-planar quads
    std::size_t problem_faces() const { return problem_faces_; }      // for the last view
    std::size_t subdivided_cells() const { return subdivided_count_; }
    std::size_t rebuilds() const { return rebuilds_; }                // working-mesh rebuilds so far
    bool subdivided(std::uint32_t cell) const { return subdivided_[cell] != 0; }

private:
    struct Candidate {
        std::uint32_t cell;
        glm::dvec3 corner;           // L, on both triangles
        glm::dvec3 normal_s, normal_t; // outward normals of the two triangles
    };
    void find_candidates();
    void rebuild();

    const CellMesh& mesh_;
    double planarity_;
    bool changed_ = false; // mesh_changed() since the last update()
    std::vector<Candidate> candidates_;
    std::vector<std::uint8_t> subdivided_, problem_;
    std::size_t subdivided_count_ = 0, problem_faces_ = 0, rebuilds_ = 0;
    CellMesh working_;
    std::vector<std::uint32_t> parent_;
    std::vector<std::uint8_t> piece_;
};

} // namespace cellfx::fx
