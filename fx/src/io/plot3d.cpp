// cellfx — PLOT3D reader with variant detection, and a writer for every variant.
//
// Format: NASA PLOT3D user's manual (Walatka, Buning, Pierce & Elson 1990, NASA TM-101067),
// chapter 8 "Data file formats"; unformatted Fortran records carry 4-byte length markers.
#include "fx/plot3d.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "io/io_util.hpp"
#include "io/output_file.hpp"

namespace cellfx::fx {
namespace {

using Dims = std::array<std::uint32_t, 3>;

constexpr std::uint64_t kMaxDim = std::uint64_t(1) << 30;

std::string dims_text(const Dims& d) {
    return std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " + std::to_string(d[2]);
}
std::uint64_t node_count(const Dims& d) { return std::uint64_t(d[0]) * d[1] * d[2]; }

// A byte buffer with bounds-checked, endian-aware loads.
struct Bytes {
    const std::vector<char>& data;
    std::string name;
    bool has(std::size_t offset, std::size_t count) const { return offset <= data.size() && count <= data.size() - offset; }
    std::int32_t int32(std::size_t offset, bool big_endian) const { return io::load_scalar<std::int32_t>(data.data() + offset, big_endian); }
    double real(std::size_t offset, bool big_endian, bool double_precision) const {
        return double_precision ? io::load_scalar<double>(data.data() + offset, big_endian)
                                : double(io::load_scalar<float>(data.data() + offset, big_endian));
    }
    [[noreturn]] void fail(std::size_t offset, const std::string& what) const {
        throw Error(name + ": byte " + std::to_string(offset) + ": " + what);
    }
};

// Header of a grid or q file under one interpretation.
struct Header {
    std::vector<Dims> dims;
    std::size_t data_offset = 0;
};

// Reads a record marker pair around `length` bytes at `offset`; false if they do not match.
bool record_fits(const Bytes& b, std::size_t offset, std::uint64_t length, bool big_endian) {
    if (length > std::numeric_limits<std::int32_t>::max()) return false;
    if (!b.has(offset, 8) || length > b.data.size() - offset - 8) return false;
    return b.int32(offset, big_endian) == std::int32_t(length) && b.int32(offset + 4 + length, big_endian) == std::int32_t(length);
}

// Parses the header under (endianness, markers, multi-block). `min_bytes_per_node` bounds the
// node counts by the file size, so that no later step allocates more than the file can hold.
// With `lying_close`, a dims record whose opening marker is right but whose closing one is
// not is read all the same, and the closing marker's offset stored there (else it is 0).
bool parse_header(const Bytes& b, bool big_endian, bool markers, bool multi, std::size_t min_bytes_per_node, Header& h,
                  std::size_t* lying_close = nullptr) {
    if (lying_close) *lying_close = 0;
    std::size_t offset = 0;
    std::uint64_t blocks = 1;
    if (multi) {
        if (markers) {
            if (!record_fits(b, 0, 4, big_endian)) return false;
            offset = 4;
        }
        if (!b.has(offset, 4)) return false;
        const std::int32_t nb = b.int32(offset, big_endian);
        if (nb < 1 || std::uint64_t(nb) * 12 > b.data.size()) return false;
        blocks = std::uint64_t(nb);
        offset += markers ? 8 : 4;
    }
    if (markers) {
        if (!record_fits(b, offset, 12 * blocks, big_endian)) {
            const std::size_t close = offset + 4 + 12 * blocks;
            if (!lying_close || !b.has(offset, 4) || b.int32(offset, big_endian) != std::int32_t(12 * blocks) || !b.has(close, 4))
                return false;
            *lying_close = close;
        }
        offset += 4;
    }
    if (!b.has(offset, 12 * blocks)) return false;
    h.dims.assign(blocks, Dims{0, 0, 0});
    const std::uint64_t max_nodes = b.data.size() / min_bytes_per_node;
    std::uint64_t total_nodes = 0;
    for (std::uint64_t k = 0; k < blocks; ++k) {
        // The node count is bounded as it is multiplied up: three dims of up to 2^30 can wrap
        // around 64 bits (2^28 * 2^25 * 2^25 is 0) and would pass a check of the product.
        std::uint64_t n = 1;
        for (int a = 0; a < 3; ++a) {
            const std::int32_t v = b.int32(offset + 12 * k + 4 * a, big_endian);
            if (v < 1 || std::uint64_t(v) > kMaxDim || std::uint64_t(v) > max_nodes / n) return false;
            h.dims[k][a] = std::uint32_t(v);
            n *= std::uint64_t(v);
        }
        total_nodes += n;
        if (total_nodes > max_nodes) return false;
    }
    offset += 12 * blocks + (markers ? 4 : 0);
    h.data_offset = offset;
    return true;
}

// Where each block's arrays start under a full interpretation, and the size it implies.
struct Layout {
    Plot3dFormat format;
    Header header;
    std::vector<std::size_t> block_offsets; // grid: X array; q: reference values
    std::vector<std::size_t> field_offsets; // q only: density array
    std::uint64_t expected_size = 0;
    bool markers_ok = true;                 // every marker inside the file matched
    std::size_t bad_markers = 0, markers = 0; // of the markers inside the file: disagreeing, all
    std::uint64_t bad_offset = 0;           // the first that disagreed: where, and what it says
    std::string bad_marker;
};

// Checks the record marker at `offset` (inside the file) against the record's length.
void check_marker(const Bytes& b, Layout& l, std::uint64_t offset, std::uint64_t length, const char* which) {
    if (!b.has(offset, 4)) return;
    ++l.markers;
    const std::int32_t found = b.int32(offset, l.format.big_endian);
    if (length <= std::uint64_t(std::numeric_limits<std::int32_t>::max()) && found == std::int32_t(length)) return;
    if (l.markers_ok) {
        l.bad_offset = offset;
        l.bad_marker = "the record marker at byte " + std::to_string(offset) + " (" + which + ") says " +
                       std::to_string(found) + " bytes, but the record holds " + std::to_string(length);
    }
    l.markers_ok = false;
    ++l.bad_markers;
}

std::size_t real_size(bool double_precision) { return double_precision ? 8 : 4; }

Layout grid_layout(const Bytes& b, const Plot3dFormat& f, const Header& h) {
    Layout l{f, h, {}, {}, 0, true, 0, 0, 0, {}};
    std::uint64_t offset = h.data_offset;
    for (const Dims& d : h.dims) {
        const std::uint64_t length = node_count(d) * (3 * real_size(f.double_precision) + (f.iblank ? 4 : 0));
        if (f.record_markers) {
            check_marker(b, l, offset, length, "opening a block's coordinates");
            check_marker(b, l, offset + 4 + length, length, "closing a block's coordinates");
            offset += 4;
        }
        l.block_offsets.push_back(offset);
        offset += length + (f.record_markers ? 4 : 0);
    }
    l.expected_size = offset;
    return l;
}

Layout q_layout(const Bytes& b, const Plot3dFormat& f, const Header& h) {
    Layout l{f, h, {}, {}, 0, true, 0, 0, 0, {}};
    std::uint64_t offset = h.data_offset;
    const std::size_t s = real_size(f.double_precision);
    auto record = [&](std::uint64_t length) {
        if (f.record_markers) {
            check_marker(b, l, offset, length, "opening a record");
            check_marker(b, l, offset + 4 + length, length, "closing a record");
            offset += 4;
        }
        const std::uint64_t start = offset;
        offset += length + (f.record_markers ? 4 : 0);
        return start;
    };
    for (const Dims& d : h.dims) {
        l.block_offsets.push_back(record(4 * s));
        l.field_offsets.push_back(record(5 * node_count(d) * s));
    }
    l.expected_size = offset;
    return l;
}

// Why no reading of the header gives dims the file can hold: the most telling reason among
// the variants (a plausible header whose nodes need more bytes than the file has, or a
// header record marker that disagrees), for the error message.
std::string explain_header(const Bytes& b) {
    std::string truncated_marked, truncated, marker;
    for (bool markers : {true, false}) {
        for (bool big_endian : {true, false}) {
            for (bool multi : {false, true}) {
                const std::string variant = std::string(big_endian ? "big-endian" : "little-endian") + ", " +
                                            (markers ? "with record markers" : "no record markers") + ", " +
                                            (multi ? "multi-block" : "single block");
                std::size_t offset = 0;
                std::uint64_t blocks = 1;
                if (multi) {
                    if (markers && (!b.has(0, 4) || b.int32(0, big_endian) != 4)) continue;
                    offset = markers ? 4 : 0;
                    if (!b.has(offset, 4)) continue;
                    const std::int32_t nb = b.int32(offset, big_endian);
                    if (nb < 1 || nb > (1 << 20)) continue;
                    blocks = std::uint64_t(nb);
                    offset += markers ? 8 : 4;
                }
                if (markers) {
                    if (!b.has(offset, 4) || b.int32(offset, big_endian) != std::int32_t(12 * blocks)) continue;
                    const std::size_t close = offset + 4 + 12 * blocks;
                    if (b.has(close, 4) && b.int32(close, big_endian) != std::int32_t(12 * blocks) && marker.empty()) {
                        marker = "read as " + variant + ", the record marker at byte " + std::to_string(close) + " says " +
                                 std::to_string(b.int32(close, big_endian)) + " where the one at byte " +
                                 std::to_string(offset) + " says " + std::to_string(12 * blocks) + " (a damaged or lying marker)";
                    }
                    offset += 4;
                }
                if (!b.has(offset, 12 * blocks)) continue;
                std::uint64_t nodes = 0;
                bool plausible = true;
                std::string dims;
                for (std::uint64_t k = 0; k < blocks && plausible; ++k) {
                    std::uint64_t n = 1;
                    for (int a = 0; a < 3; ++a) {
                        const std::int32_t v = b.int32(offset + 12 * k + 4 * a, big_endian);
                        plausible = plausible && v >= 1 && std::uint64_t(v) <= kMaxDim;
                        n *= plausible ? std::uint64_t(v) : 1;
                        if (k == 0) dims += (a ? " x " : "") + std::to_string(v);
                    }
                    nodes += n;
                }
                const std::uint64_t needed = nodes * 12 + offset + 12 * blocks;
                if (!plausible || needed <= b.data.size()) continue;
                std::string& slot = markers ? truncated_marked : truncated;
                if (slot.empty()) {
                    slot = "read as " + variant + ", the header gives " + std::to_string(blocks) + " block(s) of " + dims +
                           (blocks > 1 ? ", ..." : "") + " nodes (" + io::with_commas(nodes) + " in all), whose coordinates need at least " +
                           io::with_commas(needed) + " bytes, but the file has " + io::with_commas(b.data.size()) +
                           ": it is truncated, or its header is wrong";
                }
            }
        }
    }
    if (!truncated_marked.empty()) return truncated_marked;
    if (!marker.empty()) return marker;
    return truncated;
}

// Picks the grid interpretation that accounts for every byte of the file.
Layout detect_grid(const Bytes& b, std::vector<std::string>& ambiguity) {
    if (b.data.empty()) b.fail(0, "empty file");
    std::vector<Layout> exact;
    const Layout* closest = nullptr;
    std::vector<Layout> near; // candidates that do not fit, kept for the error message
    std::string bad_marker;   // the first data record marker that ruled a reading out
    // A reading whose header and size account for the whole file but one of whose data markers
    // disagrees (the fewest such): the file is that variant with a damaged or lying marker.
    std::optional<Layout> lying;
    for (bool big_endian : {true, false}) {
        for (bool markers : {true, false}) {
            for (bool multi : {false, true}) {
                Header h;
                std::size_t lying_close = 0;
                if (!parse_header(b, big_endian, markers, multi, 12, h, &lying_close)) continue;
                for (bool double_precision : {false, true}) {
                    for (bool iblank : {false, true}) {
                        const Plot3dFormat f{big_endian, markers, double_precision, iblank, multi};
                        Layout l = grid_layout(b, f, h);
                        if (lying_close) { // the header's closing marker disagrees: a reading only for the message
                            if (!l.markers_ok || l.expected_size != b.data.size() || lying) continue;
                            lying = l;
                            lying->bad_offset = lying_close;
                            lying->bad_marker = "the record marker at byte " + std::to_string(lying_close) +
                                                " (closing the header's dims) says " +
                                                std::to_string(b.int32(lying_close, big_endian)) +
                                                " bytes, but the record holds " + std::to_string(12 * h.dims.size());
                            ++lying->markers, ++lying->bad_markers;
                            continue;
                        }
                        if (!l.markers_ok) {
                            if (bad_marker.empty()) bad_marker = "read as " + describe(f) + ", " + l.bad_marker;
                            if (l.expected_size == b.data.size() && (!lying || l.bad_markers < lying->bad_markers))
                                lying = l;
                            continue;
                        }
                        if (l.expected_size == b.data.size()) {
                            exact.push_back(std::move(l));
                        } else {
                            near.push_back(std::move(l));
                        }
                    }
                }
            }
        }
    }
    if (!exact.empty()) {
        if (exact.size() > 1) {
            ambiguity.push_back("grid file fits " + std::to_string(exact.size()) + " PLOT3D variants; read as " + describe(exact[0].format));
        }
        return exact[0];
    }
    const std::uint64_t size = b.data.size();
    if (lying) {
        std::string dims;
        for (std::size_t k = 0; k < lying->header.dims.size() && k < 4; ++k) dims += (k ? ", " : "") + dims_text(lying->header.dims[k]);
        if (lying->header.dims.size() > 4) dims += ", ...";
        const std::string others = lying->bad_markers == 1
                                       ? "every other record marker agrees"
                                       : std::to_string(lying->bad_markers - 1) + " other record marker" +
                                             (lying->bad_markers > 2 ? "s disagree" : " disagrees") + " too";
        b.fail(lying->bad_offset, "a damaged or lying record marker: " + lying->bad_marker + "; read as " +
                                      describe(lying->format) + ", the header (" + dims + " nodes) accounts for all " +
                                      io::with_commas(size) + " bytes of the file, and " + others);
    }
    for (const Layout& l : near) {
        const std::uint64_t distance = l.expected_size > size ? l.expected_size - size : size - l.expected_size;
        const std::uint64_t best = closest ? (closest->expected_size > size ? closest->expected_size - size : size - closest->expected_size) : 0;
        if (!closest || distance < best) closest = &l;
    }
    if (!closest) {
        const std::string why = !bad_marker.empty() ? bad_marker : explain_header(b);
        b.fail(0, "not a PLOT3D grid file: no reading of the header (either byte order, with or without record markers, "
                  "single or multi-block) gives plausible block dimensions for a file of " + std::to_string(size) + " bytes" +
                  (why.empty() ? std::string() : "; " + why));
    }
    std::string dims;
    for (std::size_t k = 0; k < closest->header.dims.size() && k < 4; ++k) dims += (k ? ", " : "") + dims_text(closest->header.dims[k]);
    if (closest->header.dims.size() > 4) dims += ", ...";
    const std::string as = " as a " + describe(closest->format) + " grid of " + std::to_string(closest->header.dims.size()) +
                           " block(s) (" + dims + ") it needs " + std::to_string(closest->expected_size) + " bytes but has " +
                           std::to_string(size);
    if (closest->expected_size > size) {
        // Name the block whose data is cut.
        std::size_t block = 0;
        while (block + 1 < closest->block_offsets.size() && closest->block_offsets[block + 1] <= size) ++block;
        b.fail(size, "truncated grid file in block " + std::to_string(block) + ":" + as);
    }
    b.fail(closest->expected_size, "grid file has " + std::to_string(size - closest->expected_size) + " unexpected trailing bytes:" + as);
}

Layout detect_q(const Bytes& b, const Plot3dFormat& grid_format, const std::vector<Dims>& grid_dims) {
    if (b.data.empty()) b.fail(0, "empty file");
    Header h;
    // Node counts are bounded by the grid (checked against its file) once the dims match it.
    if (!parse_header(b, grid_format.big_endian, grid_format.record_markers, grid_format.multi_block, 1, h)) {
        b.fail(0, "q file header does not read as " + describe(grid_format) + " (the grid's format)");
    }
    if (h.dims.size() != grid_dims.size()) {
        b.fail(0, "q file has " + std::to_string(h.dims.size()) + " blocks, the grid has " + std::to_string(grid_dims.size()));
    }
    for (std::size_t k = 0; k < h.dims.size(); ++k) {
        if (h.dims[k] != grid_dims[k]) {
            b.fail(0, "block " + std::to_string(k) + ": q dims " + dims_text(h.dims[k]) + " differ from the grid's " + dims_text(grid_dims[k]));
        }
    }
    const Layout* truncated = nullptr;
    std::vector<Layout> candidates;
    for (bool double_precision : {grid_format.double_precision, !grid_format.double_precision}) {
        Plot3dFormat f = grid_format;
        f.double_precision = double_precision;
        f.iblank = false;
        candidates.push_back(q_layout(b, f, h));
    }
    const std::uint64_t size = b.data.size();
    // Exact fits first, then the grid's precision with a small tail (NASA files carry padding),
    // never a reading that leaves a large part of the file unexplained.
    for (const Layout& l : candidates) {
        if (l.markers_ok && l.expected_size == size) return l;
    }
    for (const Layout& l : candidates) {
        if (l.markers_ok && l.expected_size < size && (size - l.expected_size) * 8 < size) return l;
    }
    for (const Layout& l : candidates) {
        if (l.markers_ok && l.expected_size > size && (!truncated || l.expected_size < truncated->expected_size)) truncated = &l;
    }
    if (truncated) {
        std::size_t block = 0;
        while (block + 1 < truncated->block_offsets.size() && truncated->block_offsets[block + 1] <= size) ++block;
        b.fail(size, "truncated q file in block " + std::to_string(block) + ": as " + describe(truncated->format) + " it needs " +
                         std::to_string(truncated->expected_size) + " bytes but has " + std::to_string(size));
    }
    for (const Layout& l : candidates) {
        if (!l.markers_ok) b.fail(0, "q file does not match the grid: as " + describe(l.format) + ", " + l.bad_marker);
    }
    b.fail(0, "q file does not match the grid: no precision explains its " + std::to_string(size) + " bytes");
}

} // namespace

std::string describe(const Plot3dFormat& f) {
    return std::string(f.big_endian ? "big-endian" : "little-endian") + ", " +
           (f.record_markers ? "with record markers" : "no record markers") + ", " +
           (f.multi_block ? "multi-block" : "single block") + ", " + (f.double_precision ? "float64" : "float32") + ", " +
           (f.iblank ? "with IBLANK" : "no IBLANK");
}

Plot3dData parse_plot3d(const std::vector<char>& xyz_bytes, const std::string& xyz_name, const std::vector<char>* q_bytes,
                        const std::string& q_name, std::vector<std::string>* notes) {
    std::vector<std::string> local_notes;
    const Bytes grid{xyz_bytes, xyz_name};
    const Layout layout = detect_grid(grid, local_notes);
    const Plot3dFormat& f = layout.format;
    Plot3dData out;
    out.format = f;
    CellMesh& mesh = out.mesh;

    std::uint64_t total_nodes = 0, total_cells = 0;
    for (const Dims& d : layout.header.dims) {
        total_nodes += node_count(d);
        total_cells += std::uint64_t(d[0] - 1) * (d[1] - 1) * (d[2] - 1);
    }
    if (total_nodes >= std::numeric_limits<std::uint32_t>::max() || total_cells * 8 >= std::numeric_limits<std::uint32_t>::max()) {
        grid.fail(0, "grid too large for cellfx's 32-bit indices");
    }
    if (exceeds(Limit::MeshPoints, total_nodes)) grid.fail(0, over_limit(Limit::MeshPoints, total_nodes, "the grid's nodes"));
    if (exceeds(Limit::MeshCells, total_cells)) grid.fail(0, over_limit(Limit::MeshCells, total_cells, "the grid's cells"));
    mesh.points.resize(total_nodes);
    mesh.cell_types.reserve(total_cells);
    mesh.connectivity.reserve(total_cells * 8);
    mesh.cell_offsets.reserve(total_cells + 1);

    const std::size_t s = real_size(f.double_precision);
    std::size_t base = 0;
    for (std::size_t k = 0; k < layout.header.dims.size(); ++k) {
        const Dims& d = layout.header.dims[k];
        const std::size_t n = node_count(d);
        const std::size_t x0 = layout.block_offsets[k];
        for (std::size_t p = 0; p < n; ++p) {
            glm::dvec3& q = mesh.points[base + p];
            for (int a = 0; a < 3; ++a) q[a] = grid.real(x0 + (a * n + p) * s, f.big_endian, f.double_precision);
            if (!io::all_finite(q.x, q.y, q.z)) {
                grid.fail(x0 + p * s, "block " + std::to_string(k) + ": point " + std::to_string(p) +
                                          " has a non-finite coordinate (NaN or Inf)");
            }
        }
        const std::size_t iblank0 = x0 + 3 * n * s;
        auto blanked = [&](std::size_t p) { return f.iblank && grid.int32(iblank0 + 4 * p, f.big_endian) == 0; };
        mesh.begin_block(std::to_string(k), d);
        const std::uint64_t ni = d[0], nj = d[1];
        auto node = [&](std::uint64_t i, std::uint64_t j, std::uint64_t kk) { return std::uint32_t(i + ni * (j + nj * kk)); };
        for (std::uint64_t kk = 0; kk + 1 < d[2]; ++kk) {
            for (std::uint64_t j = 0; j + 1 < nj; ++j) {
                for (std::uint64_t i = 0; i + 1 < ni; ++i) {
                    std::uint32_t v[8] = {node(i, j, kk),         node(i + 1, j, kk),         node(i + 1, j + 1, kk),
                                          node(i, j + 1, kk),     node(i, j, kk + 1),         node(i + 1, j, kk + 1),
                                          node(i + 1, j + 1, kk + 1), node(i, j + 1, kk + 1)};
                    bool drop = false;
                    for (std::uint32_t& c : v) {
                        drop = drop || blanked(c);
                        c += std::uint32_t(base);
                    }
                    if (drop) {
                        ++out.blanked_cells;
                        continue;
                    }
                    mesh.add_cell(CellType::Hexahedron, v);
                }
            }
        }
        base += n;
    }
    local_notes.insert(local_notes.begin(), "PLOT3D grid: " + describe(f) + ", " + std::to_string(layout.header.dims.size()) + " block(s)");
    if (f.iblank) {
        local_notes.push_back("IBLANK: dropped " + io::with_commas(out.blanked_cells) + " cells touching blanked (IBLANK = 0) nodes");
    }

    if (q_bytes) {
        const Bytes qb{*q_bytes, q_name};
        const Layout ql = detect_q(qb, f, layout.header.dims);
        const Plot3dFormat& qf = ql.format;
        const std::size_t qs = real_size(qf.double_precision);
        static const char* kNames[5] = {"density", "momentum_x", "momentum_y", "momentum_z", "energy"};
        for (const char* name : kNames) mesh.scalars.push_back(ScalarField{name, std::vector<float>(total_nodes)});
        base = 0;
        for (std::size_t k = 0; k < ql.header.dims.size(); ++k) {
            const std::size_t r0 = ql.block_offsets[k];
            Plot3dReference ref;
            ref.mach = qb.real(r0, qf.big_endian, qf.double_precision);
            ref.alpha = qb.real(r0 + qs, qf.big_endian, qf.double_precision);
            ref.reynolds = qb.real(r0 + 2 * qs, qf.big_endian, qf.double_precision);
            ref.time = qb.real(r0 + 3 * qs, qf.big_endian, qf.double_precision);
            out.references.push_back(ref);
            char line[160];
            std::snprintf(line, sizeof line, "q block %zu: Mach %g, alpha %g, Re %g, time %g", k, ref.mach, ref.alpha, ref.reynolds, ref.time);
            local_notes.push_back(line);
            const std::size_t n = node_count(ql.header.dims[k]);
            const std::size_t f0 = ql.field_offsets[k];
            for (int field = 0; field < 5; ++field) {
                std::vector<float>& values = mesh.scalars[field].values;
                for (std::size_t p = 0; p < n; ++p) {
                    values[base + p] = float(qb.real(f0 + (field * n + p) * qs, qf.big_endian, qf.double_precision));
                }
            }
            base += n;
        }
        ScalarField magnitude{"momentum_magnitude", std::vector<float>(total_nodes)};
        for (std::size_t p = 0; p < total_nodes; ++p) {
            const double mx = mesh.scalars[1].values[p], my = mesh.scalars[2].values[p], mz = mesh.scalars[3].values[p];
            magnitude.values[p] = float(std::sqrt(mx * mx + my * my + mz * mz));
        }
        mesh.scalars.push_back(std::move(magnitude));
        if (qf.double_precision != f.double_precision) local_notes.push_back("q file precision differs from the grid's: " + describe(qf));
        if (ql.expected_size < q_bytes->size()) {
            std::size_t nonzero = 0;
            for (std::size_t i = ql.expected_size; i < q_bytes->size(); ++i) nonzero += (*q_bytes)[i] != 0;
            local_notes.push_back("q file: ignored " + std::to_string(q_bytes->size() - ql.expected_size) + " trailing bytes (" +
                                  std::to_string(nonzero) + " non-zero)");
        }
        for (std::size_t field = 0; field < mesh.scalars.size(); ++field) {
            std::size_t bad = 0;
            for (float v : mesh.scalars[field].values) bad += !std::isfinite(v);
            if (bad) local_notes.push_back("field \"" + mesh.scalars[field].name + "\": " + io::with_commas(bad) + " non-finite values");
        }
    }
    // Blocks with a left-handed (i, j, k) give inverted cells: every reader orients them.
    io::orient_and_note(mesh, &local_notes, [&](std::uint32_t c) {
        std::size_t k = 0;
        while (k + 1 < mesh.blocks.size() && mesh.blocks[k + 1].first_cell <= c) ++k;
        return "cell " + std::to_string(c) + " (block " + std::to_string(k) + ")";
    });
    if (notes) notes->insert(notes->end(), local_notes.begin(), local_notes.end());
    return out;
}

Plot3dData read_plot3d(const std::string& xyz_path, const std::string& q_path, std::vector<std::string>* notes) {
    const std::vector<char> xyz = io::read_file_bytes(xyz_path);
    if (q_path.empty()) return parse_plot3d(xyz, xyz_path, nullptr, "", notes);
    const std::vector<char> q = io::read_file_bytes(q_path);
    return parse_plot3d(xyz, xyz_path, &q, q_path, notes);
}

namespace {

// Appends one Fortran record (or the bare bytes without markers).
void append_record(std::string& out, const std::string& payload, const Plot3dFormat& f) {
    if (f.record_markers) io::store_scalar<std::int32_t>(out, std::int32_t(payload.size()), f.big_endian);
    out += payload;
    if (f.record_markers) io::store_scalar<std::int32_t>(out, std::int32_t(payload.size()), f.big_endian);
}
void append_real(std::string& out, double v, const Plot3dFormat& f) {
    if (f.double_precision) {
        io::store_scalar<double>(out, v, f.big_endian);
    } else {
        io::store_scalar<float>(out, float(v), f.big_endian);
    }
}
// Header records: block count (multi-block only), then the dims of every block.
std::string header_bytes(const std::vector<Plot3dBlock>& blocks, const Plot3dFormat& f) {
    std::string out, payload;
    if (f.multi_block) {
        io::store_scalar<std::int32_t>(payload, std::int32_t(blocks.size()), f.big_endian);
        append_record(out, payload, f);
        payload.clear();
    }
    for (const Plot3dBlock& b : blocks) {
        for (std::uint32_t d : b.dims) io::store_scalar<std::int32_t>(payload, std::int32_t(d), f.big_endian);
    }
    append_record(out, payload, f);
    return out;
}

} // namespace

void write_plot3d(const std::vector<Plot3dBlock>& blocks, const Plot3dFormat& format, const std::string& xyz_path,
                  const std::string& q_path) {
    if (blocks.empty()) throw Error(xyz_path + ": no blocks to write");
    if (!format.multi_block && blocks.size() != 1) {
        throw Error(xyz_path + ": a single-block PLOT3D file holds one block, not " + std::to_string(blocks.size()));
    }
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        const Plot3dBlock& b = blocks[k];
        const std::uint64_t n = node_count(b.dims);
        if (b.dims[0] < 1 || b.dims[1] < 1 || b.dims[2] < 1 || b.points.size() != n || (!b.iblank.empty() && b.iblank.size() != n)) {
            throw Error(xyz_path + ": block " + std::to_string(k) + ": dims " + dims_text(b.dims) + " do not match its " +
                        std::to_string(b.points.size()) + " points / " + std::to_string(b.iblank.size()) + " IBLANK values");
        }
        if (!q_path.empty()) {
            for (const std::vector<double>& field : b.q) {
                if (field.size() != n) throw Error(q_path + ": block " + std::to_string(k) + ": q arrays must have one value per point");
            }
        }
    }
    std::string xyz = header_bytes(blocks, format);
    for (const Plot3dBlock& b : blocks) {
        std::string payload;
        for (int a = 0; a < 3; ++a) {
            for (const glm::dvec3& p : b.points) append_real(payload, p[a], format);
        }
        if (format.iblank) {
            for (std::size_t p = 0; p < b.points.size(); ++p) {
                io::store_scalar<std::int32_t>(payload, b.iblank.empty() ? 1 : b.iblank[p], format.big_endian);
            }
        }
        append_record(xyz, payload, format);
    }
    io::write_output_file(xyz_path, xyz);
    if (q_path.empty()) return;
    std::string q = header_bytes(blocks, format);
    for (const Plot3dBlock& b : blocks) {
        std::string payload;
        for (double v : {b.reference.mach, b.reference.alpha, b.reference.reynolds, b.reference.time}) append_real(payload, v, format);
        append_record(q, payload, format);
        payload.clear();
        for (const std::vector<double>& field : b.q) {
            for (double v : field) append_real(payload, v, format);
        }
        append_record(q, payload, format);
    }
    io::write_output_file(q_path, q);
}

} // namespace cellfx::fx
