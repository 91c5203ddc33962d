// cellfx — AVS UCD ASCII reader.
//
// Format: AVS Developer's Guide, appendix "Unstructured Cell Data" (ASCII UCD file format).
// Vertex order conversions follow VTK's vtkAVSucdReader (pyramid apex first) and meshio's
// avsucd module (tet, prism and hex orders), checked against the AVS sample file ucd1.inp
// where hex nodes 1-4 are the top face listed counter-clockwise seen from above.
#include "fx/avs_ucd.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "io/io_util.hpp"

namespace cellfx::fx {
namespace {

using io::Scanner;

struct UcdCellType {
    const char* keyword;
    int vertex_count;
    int dimension;         // 0..3
    CellType type;         // for dimension 3
    std::array<int, 8> to_vtk; // vtk vertex k = ucd vertex to_vtk[k]
};

const UcdCellType kUcdTypes[] = {
    {"pt", 1, 0, CellType::Tetra, {}},
    {"line", 2, 1, CellType::Tetra, {}},
    {"tri", 3, 2, CellType::Tetra, {}},
    {"quad", 4, 2, CellType::Tetra, {}},
    {"tet", 4, 3, CellType::Tetra, {0, 1, 3, 2}},
    {"pyr", 5, 3, CellType::Pyramid, {1, 2, 3, 4, 0}},
    {"prism", 6, 3, CellType::Wedge, {3, 4, 5, 0, 1, 2}},
    {"hex", 8, 3, CellType::Hexahedron, {4, 5, 6, 7, 0, 1, 2, 3}},
};

class UcdReader {
public:
    UcdReader(const std::vector<char>& bytes, const std::string& name, std::vector<std::string>* notes)
        : s_(bytes, name), notes_(notes) {}
    CellMesh read();

private:
    Scanner s_;
    std::vector<std::string>* notes_;
    // (file node id, point index), sorted: a hash map would degrade to O(n^2) for ids chosen
    // to share one bucket (multiples of its bucket count), and a file could hang the reader.
    std::vector<std::pair<std::int64_t, std::uint32_t>> node_ids_;
    std::vector<std::int64_t> cell_ids_;     // file id of each kept cell
    std::vector<std::size_t> cell_starts_;   // byte offset of each kept cell's line

    void note(const std::string& line) {
        if (notes_) notes_->push_back(line);
    }
    std::uint32_t node(std::int64_t id, std::size_t pos, const std::string& where) {
        const auto it = std::lower_bound(node_ids_.begin(), node_ids_.end(), std::make_pair(id, std::uint32_t(0)));
        if (it == node_ids_.end() || it->first != id) s_.fail_at_line(pos, where + ": node id " + std::to_string(id) + " is not defined");
        return it->second;
    }
};

CellMesh UcdReader::read() {
    if (s_.size() == 0) s_.fail_at_line(0, "empty file");
    if (static_cast<unsigned char>(s_.data()[0]) == 7) s_.fail_at_byte(0, "binary AVS UCD files are not supported (ASCII only)");
    // Comments may only precede the data.
    while (true) {
        s_.skip_space();
        if (s_.at_end() || s_.data()[s_.pos()] != '#') break;
        s_.rest_of_line();
    }
    const std::size_t nodes = s_.read_count("number of nodes", s_.max_tokens_left() / 4);
    if (exceeds(Limit::MeshPoints, nodes)) s_.fail_at_line(s_.token_start(), over_limit(Limit::MeshPoints, nodes, "the node count"));
    const std::size_t cells = s_.read_count("number of cells", s_.max_tokens_left() / 4);
    if (exceeds(Limit::MeshCells, cells)) s_.fail_at_line(s_.token_start(), over_limit(Limit::MeshCells, cells, "the cell count"));
    const std::size_t node_data = s_.read_count("node data length", s_.max_tokens_left());
    const std::size_t cell_data = s_.read_count("cell data length", s_.max_tokens_left());
    const std::size_t model_data = s_.read_count("model data length", s_.max_tokens_left());
    if (nodes + cells > s_.max_tokens_left() / 4 + 1) {
        s_.fail_at_line(s_.pos(), "truncated: " + std::to_string(nodes) + " nodes and " + std::to_string(cells) +
                                      " cells announced but the rest of the file is too short");
    }
    if (nodes >= std::numeric_limits<std::uint32_t>::max()) s_.fail_at_line(0, "too many nodes for 32-bit indices");

    CellMesh mesh;
    mesh.points.resize(nodes);
    node_ids_.reserve(nodes);
    std::vector<std::size_t> node_starts(nodes);
    for (std::size_t i = 0; i < nodes; ++i) {
        const std::string what = "node " + std::to_string(i);
        const std::int64_t id = s_.read_int(what + " id");
        const std::size_t pos = s_.token_start();
        glm::dvec3& p = mesh.points[i];
        p.x = s_.read_double(what + " x");
        p.y = s_.read_double(what + " y");
        p.z = s_.read_double(what + " z");
        if (!io::all_finite(p.x, p.y, p.z)) s_.fail_at_line(pos, "node id " + std::to_string(id) + " has a non-finite coordinate (NaN or Inf)");
        node_ids_.emplace_back(id, static_cast<std::uint32_t>(i));
        node_starts[i] = pos;
    }
    std::sort(node_ids_.begin(), node_ids_.end());
    // Report the first line, in file order, whose id was defined before.
    std::size_t first_repeat = nodes;
    std::int64_t repeated_id = 0;
    for (std::size_t k = 1; k < node_ids_.size(); ++k) {
        if (node_ids_[k].first == node_ids_[k - 1].first && node_ids_[k].second < first_repeat) {
            first_repeat = node_ids_[k].second;
            repeated_id = node_ids_[k].first;
        }
    }
    if (first_repeat < nodes) s_.fail_at_line(node_starts[first_repeat], "node id " + std::to_string(repeated_id) + " is defined twice");

    std::size_t skipped_by_dimension[3] = {0, 0, 0};
    mesh.cell_types.reserve(cells);
    mesh.cell_offsets.reserve(cells + 1);
    cell_ids_.reserve(cells);
    cell_starts_.reserve(cells);
    for (std::size_t c = 0; c < cells; ++c) {
        const std::int64_t id = s_.read_int("cell " + std::to_string(c) + " id");
        const std::size_t pos = s_.token_start();
        const std::string where = "cell id " + std::to_string(id);
        s_.read_int(where + " material");
        const std::string_view keyword = s_.require_token(where + " type");
        const UcdCellType* type = nullptr;
        for (const UcdCellType& t : kUcdTypes) {
            if (keyword == t.keyword) type = &t;
        }
        if (!type) {
            s_.fail_at_line(s_.token_start(), where + ": unknown cell type " + io::quote_token(keyword) +
                                                  " (expected pt, line, tri, quad, tet, pyr, prism or hex)");
        }
        std::uint32_t ucd[8];
        for (int k = 0; k < type->vertex_count; ++k) {
            const std::int64_t node_id = s_.read_int(where + " vertex " + std::to_string(k));
            ucd[k] = node(node_id, s_.token_start(), where);
        }
        if (type->dimension < 3) {
            ++skipped_by_dimension[type->dimension];
            continue;
        }
        std::uint32_t vtk[8];
        for (int k = 0; k < type->vertex_count; ++k) vtk[k] = ucd[type->to_vtk[k]];
        mesh.add_cell(type->type, vtk);
        cell_ids_.push_back(id);
        cell_starts_.push_back(pos);
    }
    static const char* kDimensionName[3] = {"0-D", "1-D", "2-D"};
    for (int d = 0; d < 3; ++d) {
        if (skipped_by_dimension[d]) note("skipped " + io::with_commas(skipped_by_dimension[d]) + " " + kDimensionName[d] + " cells");
    }

    if (node_data > 0) {
        const std::size_t components = s_.read_count("number of node data components", node_data);
        if (components == 0) s_.fail_at_line(s_.token_start(), "node data length is " + std::to_string(node_data) + " but 0 components");
        std::vector<std::size_t> sizes(components);
        std::size_t total = 0;
        for (std::size_t k = 0; k < components; ++k) {
            sizes[k] = s_.read_count("size of node data component " + std::to_string(k), node_data);
            total += sizes[k];
        }
        if (total != node_data) {
            s_.fail_at_line(s_.token_start(), "node data component sizes add up to " + std::to_string(total) +
                                                  ", the header says " + std::to_string(node_data));
        }
        if (nodes * node_data > s_.max_tokens_left()) {
            s_.fail_at_line(s_.pos(), "truncated node data: " + std::to_string(nodes * node_data) + " values announced");
        }
        s_.rest_of_line();
        std::vector<std::string> labels(components);
        for (std::size_t k = 0; k < components; ++k) {
            if (s_.at_end()) s_.fail_at_line(s_.pos(), "truncated: missing label line of node data component " + std::to_string(k));
            std::string_view line = s_.rest_of_line();
            line = line.substr(0, line.find(','));
            const std::size_t first = line.find_first_not_of(" \t"), last = line.find_last_not_of(" \t\r");
            labels[k] = first == std::string_view::npos ? "component_" + std::to_string(k) : std::string(line.substr(first, last - first + 1));
        }
        std::vector<std::vector<float>> values(node_data, std::vector<float>(nodes, 0.0f));
        std::vector<char> seen(nodes, 0);
        for (std::size_t i = 0; i < nodes; ++i) {
            const std::int64_t id = s_.read_int("node data id");
            const std::size_t pos = s_.token_start();
            const std::uint32_t n = node(id, pos, "node data");
            if (seen[n]) s_.fail_at_line(pos, "node data for node id " + std::to_string(id) + " given twice");
            seen[n] = 1;
            for (std::size_t v = 0; v < node_data; ++v) values[v][n] = static_cast<float>(s_.read_double("node data of node id " + std::to_string(id)));
        }
        std::size_t column = 0;
        for (std::size_t k = 0; k < components; ++k) {
            for (std::size_t j = 0; j < sizes[k]; ++j) {
                const std::string name = sizes[k] == 1 ? labels[k] : labels[k] + "_" + std::to_string(j);
                mesh.scalars.push_back(ScalarField{name, std::move(values[column++])});
            }
        }
    }
    if (cell_data > 0) note("skipped cell data (" + std::to_string(cell_data) + " values per cell)");
    if (model_data > 0) note("skipped model data (" + std::to_string(model_data) + " values)");

    io::orient_and_note(mesh, notes_, [&](std::uint32_t c) {
        return "id " + std::to_string(cell_ids_[c]) + " (line " + std::to_string(s_.line_of(cell_starts_[c])) + ")";
    });
    return mesh;
}

} // namespace

CellMesh parse_avs_ucd(const std::vector<char>& bytes, const std::string& name, std::vector<std::string>* notes) {
    UcdReader reader(bytes, name, notes);
    return reader.read();
}

CellMesh read_avs_ucd(const std::string& path, std::vector<std::string>* notes) {
    return parse_avs_ucd(io::read_file_bytes(path), path, notes);
}

} // namespace cellfx::fx
