// cellfx — PLOT3D binary grid (xyz) and solution (q) files, every common variant.
//
// Layout (NASA PLOT3D, as read by VTK's vtkMultiBlockPLOT3DReader): an optional block count,
// then ni nj nk per block (int32), then per block the X, Y, Z arrays (i fastest) and, with
// IBLANK, one int32 per node. A q file has the same header, then per block four reference
// values (Mach, alpha, Reynolds number, time) and five arrays: density, x/y/z momentum and
// stagnation energy.
//
// The reader detects the variant from the bytes: big or little endian; with or without
// Fortran record markers (4-byte lengths around each record, checked); single block ("whole")
// or multi-block (leading block count); float32 or float64; with or without IBLANK. A grid
// interpretation must account for every byte of the xyz file; a q file may carry trailing bytes
// (NASA's bluntfinq.bin has 484 zero bytes) but must fit the grid's blocks and dims exactly.
//
// Each block becomes one fx::Block with dims {ni, nj, nk} and (ni-1)(nj-1)(nk-1) hexahedra in
// VTK vertex order, i fastest; its points follow the previous block's points. With IBLANK,
// cells touching a node whose IBLANK is 0 are dropped (counted in the notes), so a block's
// cell_count may be smaller than its dims suggest; other values (1, -1, n) keep the cell.
// Q fields become point scalars "density", "momentum_x", "momentum_y", "momentum_z", "energy"
// and "momentum_magnitude".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/cell_mesh.hpp"

namespace cellfx::fx {

struct Plot3dFormat {
    bool big_endian = true;
    bool record_markers = false; // Fortran unformatted: 4-byte record lengths before and after
    bool double_precision = false;
    bool iblank = false;         // grid only: int32 per node after Z
    bool multi_block = false;    // leading int32 block count
    bool operator==(const Plot3dFormat& o) const {
        return big_endian == o.big_endian && record_markers == o.record_markers && double_precision == o.double_precision &&
               iblank == o.iblank && multi_block == o.multi_block;
    }
};
// "big-endian, no record markers, single block, float32, no IBLANK"
std::string describe(const Plot3dFormat& format);

// The four values at the head of each q block.
struct Plot3dReference {
    double mach = 0.0;
    double alpha = 0.0;
    double reynolds = 0.0;
    double time = 0.0;
};

// One block as stored in the files; what write_plot3d() takes.
struct Plot3dBlock {
    std::array<std::uint32_t, 3> dims{0, 0, 0};
    std::vector<glm::dvec3> points;          // ni*nj*nk, i fastest, then j, then k
    std::vector<std::int32_t> iblank;        // empty (all 1) or one per point
    Plot3dReference reference;
    std::array<std::vector<double>, 5> q;    // density, momentum x/y/z, energy; empty or one per point
};

struct Plot3dData {
    CellMesh mesh;
    Plot3dFormat format;                     // as detected in the xyz file
    std::vector<Plot3dReference> references; // one per block when a q file was read, else empty
    std::size_t blanked_cells = 0;           // cells dropped because of IBLANK == 0
};

// Reads a grid and, when q_path is not empty, its solution. `notes` receives the detected
// format, the reference values and what was dropped. Throws fx::Error naming the file and the
// byte offset or block of the problem.
Plot3dData read_plot3d(const std::string& xyz_path, const std::string& q_path = "",
                       std::vector<std::string>* notes = nullptr);

// Same, from bytes in memory (fuzzers); q_bytes may be null. Names are used in messages.
Plot3dData parse_plot3d(const std::vector<char>& xyz_bytes, const std::string& xyz_name,
                        const std::vector<char>* q_bytes, const std::string& q_name,
                        std::vector<std::string>* notes = nullptr);

// Writes blocks in the given variant (all 32 combinations), the q file too when q_path is not
// empty (every block must then have five q arrays). A single-block format needs exactly one
// block. Throws fx::Error for inconsistent blocks or unwritable files.
void write_plot3d(const std::vector<Plot3dBlock>& blocks, const Plot3dFormat& format, const std::string& xyz_path,
                  const std::string& q_path = "");

} // namespace cellfx::fx
