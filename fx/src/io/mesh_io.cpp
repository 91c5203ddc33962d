// cellfx — choosing a mesh reader by sniffing the file's first bytes.
#include "fx/mesh_io.hpp"

#include <algorithm>
#include <cctype>

#include "fx/avs_ucd.hpp"
#include "fx/plot3d.hpp"
#include "fx/vtk_legacy.hpp"
#include "io/io_util.hpp"

namespace cellfx::fx {
namespace {

bool starts_with_vtk_header(const char* data, std::size_t size) {
    static const char kMagic[] = "# vtk datafile";
    const std::size_t n = sizeof(kMagic) - 1;
    if (size < n) return false;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::tolower(static_cast<unsigned char>(data[i])) != kMagic[i]) return false;
    }
    return true;
}

// "#" comment lines, then a line of exactly five integers (the UCD reader rejects negative
// counts with a message of its own).
bool looks_like_ucd(const char* data, std::size_t size) {
    std::size_t pos = 0;
    const std::size_t limit = std::min<std::size_t>(size, 64 * 1024);
    while (pos < limit) {
        while (pos < limit && io::is_space(data[pos])) ++pos;
        if (pos < limit && data[pos] == '#') {
            while (pos < limit && data[pos] != '\n') ++pos;
            continue;
        }
        break;
    }
    int numbers = 0;
    while (pos < limit && data[pos] != '\n') {
        while (pos < limit && (data[pos] == ' ' || data[pos] == '\t' || data[pos] == '\r')) ++pos;
        if (pos >= limit || data[pos] == '\n') break;
        const std::size_t start = pos;
        while (pos < limit && !io::is_space(data[pos])) ++pos;
        std::int64_t v = 0;
        if (!io::parse_int64(std::string_view(data + start, pos - start), v)) return false;
        ++numbers;
    }
    return numbers == 5 && pos < limit; // the header line must end inside what we looked at
}

// Text rather than binary: no NUL byte in the first 4 KiB (every PLOT3D header has some: its
// dims are small 32-bit integers).
bool looks_like_text(const char* data, std::size_t size) {
    const std::size_t n = std::min<std::size_t>(size, 4096);
    return n > 0 && std::find(data, data + n, '\0') == data + n;
}

} // namespace

const char* mesh_file_format_name(MeshFileFormat format) {
    switch (format) {
    case MeshFileFormat::VtkLegacy: return "VTK legacy";
    case MeshFileFormat::AvsUcd: return "AVS UCD";
    case MeshFileFormat::Plot3d: return "PLOT3D";
    }
    return "unknown";
}

MeshFileFormat sniff_mesh_format(const char* data, std::size_t size) {
    if (starts_with_vtk_header(data, size)) return MeshFileFormat::VtkLegacy;
    if (looks_like_ucd(data, size)) return MeshFileFormat::AvsUcd;
    return MeshFileFormat::Plot3d;
}

CellMesh read_mesh(const std::string& path, const std::string& q_path, std::vector<std::string>* notes) try {
    const std::vector<char> bytes = io::read_file_bytes(path);
    const MeshFileFormat format = sniff_mesh_format(bytes.data(), bytes.size());
    if (format == MeshFileFormat::Plot3d && looks_like_text(bytes.data(), bytes.size())) {
        std::size_t first = 0;
        while (first < bytes.size() && io::is_space(bytes[first])) ++first;
        const bool json = first < bytes.size() && (bytes[first] == '{' || bytes[first] == '[');
        throw Error(path + ": not a mesh file cellfx reads: it is text, but neither VTK legacy (a first line \"# vtk "
                           "DataFile ...\") nor AVS UCD (a line of five counts after \"#\" comments); PLOT3D files are "
                           "binary" +
                    std::string(json ? ". It looks like JSON: `cellfx render` takes a scene file named *.json" : ""));
    }
    if (format != MeshFileFormat::Plot3d && !q_path.empty()) {
        throw Error(q_path + ": a q (solution) file only goes with a PLOT3D grid, but " + path + " is " +
                    mesh_file_format_name(format));
    }
    if (notes) notes->push_back(std::string("format: ") + mesh_file_format_name(format));
    switch (format) {
    case MeshFileFormat::VtkLegacy: return parse_vtk_legacy(bytes, path, notes);
    case MeshFileFormat::AvsUcd: return parse_avs_ucd(bytes, path, notes);
    case MeshFileFormat::Plot3d: break;
    }
    if (q_path.empty()) return parse_plot3d(bytes, path, nullptr, "", notes).mesh;
    const std::vector<char> q = io::read_file_bytes(q_path);
    return parse_plot3d(bytes, path, &q, q_path, notes).mesh;
} catch (const std::bad_alloc&) {
    // The budgets (resource_limits.hpp) stop what a file claims before it is allocated; this is
    // what a machine with less memory than they allow runs into.
    throw Error(path + ": out of memory reading the mesh (lower the mesh-points and mesh-cells limits to be told "
                       "before allocating, or free memory)");
}

} // namespace cellfx::fx
