// cellfx — what every reader promises for arbitrary bytes, checked the same way by the libFuzzer
// targets (tests/fuzz/fuzz_*.cpp) and by the regression test (tests/test_fuzz_regressions.cpp).
//
// For any input a reader either returns a well-formed result or throws fx::Error whose message
// starts with the name it was given ("fuzz.vtk: line 3: ..."). Anything else is a bug:
//   - another exception type (std::bad_alloc, std::out_of_range, ...) escapes check_*() to the
//     caller: libFuzzer reports it as a crash, the Catch2 test as a failure;
//   - a result that breaks the reader's own contract (indices past the points, a field of the
//     wrong length, non-finite coordinates, a transfer function that evaluates to NaN) or a
//     mesh far bigger than its file could describe comes back as a non-empty problem string.
// Memory errors, undefined behaviour, leaks and hangs are left to the sanitizers and libFuzzer.
//
// PLOT3D needs two files: a fuzzer input is split by split_plot3d_input() (byte 0 bit 0: a q
// file follows; bytes 1-4: little-endian length of the grid part, clamped to what is there).
// Scene files name other files (height maps, transfer functions): they are resolved in the
// folder given to check_scene(), content/scenes/ of the source tree.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fx/avs_ucd.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"
#include "mesh/face_topology.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/plot3d.hpp"
#include "fx/transfer_function.hpp"
#include "fx/vtk_legacy.hpp"
#include "terrain/height_field.hpp"
#include "terrain/scene.hpp"
#include "../cellfx_names.hpp"

namespace fx_fuzz {

// Names the readers get; every fx::Error must start with one of them.
inline const std::string kVtkName = "fuzz.vtk";
inline const std::string kUcdName = "fuzz.inp";
inline const std::string kXyzName = "fuzz.xyz";
inline const std::string kQName = "fuzz.q";
inline const std::string kJsonName = "fuzz.json";
inline const std::string kPngName = "fuzz.png";
inline const std::string kSceneName = "fuzz_scene.json";

// A result may hold this many bytes per input byte (plus a constant): generous for every
// format (an ASCII "0 " is 2 bytes and becomes an 8-byte coordinate or 4-byte index), far
// below what a header that claims 2^31 items would allocate.
constexpr std::size_t kMaxBytesPerInputByte = 64;
constexpr std::size_t kMaxBytesConstant = std::size_t(1) << 20;

struct Plot3dInput {
    std::vector<char> xyz;
    std::optional<std::vector<char>> q;
};

inline Plot3dInput split_plot3d_input(const std::uint8_t* data, std::size_t size) {
    Plot3dInput in;
    if (size < 5) {
        in.xyz.assign(data, data + size);
        return in;
    }
    const bool has_q = data[0] & 1;
    std::size_t length = std::size_t(data[1]) | std::size_t(data[2]) << 8 | std::size_t(data[3]) << 16 | std::size_t(data[4]) << 24;
    const std::uint8_t* rest = data + 5;
    const std::size_t rest_size = size - 5;
    if (length > rest_size) length = rest_size;
    in.xyz.assign(rest, rest + length);
    if (has_q) in.q.emplace(rest + length, rest + rest_size);
    return in;
}

// The inverse, for making seeds.
inline std::string pack_plot3d_input(const std::string& xyz, const std::string* q) {
    std::string out(1, char(q ? 1 : 0));
    for (int k = 0; k < 4; ++k) out += char((xyz.size() >> (8 * k)) & 0xFF);
    out += xyz;
    if (q) out += *q;
    return out;
}

// "" when the message names one of the sources and says something after it.
inline std::string check_message(const fx::Error& e, const std::vector<std::string>& names) {
    const std::string message = e.what();
    for (const std::string& name : names) {
        if (message.rfind(name + ": ", 0) == 0 && message.size() > name.size() + 2) return "";
    }
    return "fx::Error does not start with the source name: \"" + message.substr(0, 200) + "\"";
}

// The CellMesh contract every reader promises, then the first steps a renderer takes on it
// (validation, face topology) so that they see reader output too.
inline std::string check_mesh(const fx::CellMesh& mesh, std::size_t input_size) {
    const std::size_t points = mesh.point_count(), cells = mesh.cell_count();
    if (mesh.cell_offsets.size() != cells + 1 || mesh.cell_offsets[0] != 0) return "cell_offsets do not match the cell count";
    for (std::size_t c = 0; c < cells; ++c) {
        const std::uint32_t begin = mesh.cell_offsets[c], end = mesh.cell_offsets[c + 1];
        if (end < begin || end - begin != std::uint32_t(fx::cell_vertex_count(mesh.cell_types[c])) || end > mesh.connectivity.size()) {
            return "cell " + std::to_string(c) + ": offsets do not match its type";
        }
        for (std::uint32_t k = begin; k < end; ++k) {
            if (mesh.connectivity[k] >= points) return "cell " + std::to_string(c) + ": vertex index past the points";
        }
    }
    if (mesh.cell_offsets.back() != mesh.connectivity.size()) return "connectivity longer than the cells use";
    for (const glm::dvec3& p : mesh.points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "non-finite coordinate returned";
    }
    for (const fx::ScalarField& f : mesh.scalars) {
        if (f.values.size() != points) return "field \"" + f.name + "\" has " + std::to_string(f.values.size()) + " values";
    }
    std::size_t covered = 0;
    for (const fx::Block& b : mesh.blocks) {
        if (b.first_cell != covered) return "blocks do not cover the cells in order";
        covered += b.cell_count;
    }
    if (covered != cells && !(cells == 0 && mesh.blocks.empty())) return "blocks do not cover the cells";
    if (mesh.memory_bytes() > kMaxBytesPerInputByte * input_size + kMaxBytesConstant) {
        return "mesh of " + std::to_string(mesh.memory_bytes()) + " bytes from " + std::to_string(input_size) + " input bytes";
    }
    fx::validate_mesh(mesh);
    fx::build_face_topology(mesh);
    return "";
}

inline std::string check_vtk_legacy(const std::uint8_t* data, std::size_t size) {
    const std::vector<char> bytes(data, data + size);
    fx::sniff_mesh_format(bytes.data(), bytes.size()); // read_mesh's first step, on any bytes
    try {
        std::vector<std::string> notes;
        return check_mesh(fx::parse_vtk_legacy(bytes, kVtkName, &notes), size);
    } catch (const fx::Error& e) {
        return check_message(e, {kVtkName});
    }
}

inline std::string check_avs_ucd(const std::uint8_t* data, std::size_t size) {
    const std::vector<char> bytes(data, data + size);
    fx::sniff_mesh_format(bytes.data(), bytes.size());
    try {
        std::vector<std::string> notes;
        return check_mesh(fx::parse_avs_ucd(bytes, kUcdName, &notes), size);
    } catch (const fx::Error& e) {
        return check_message(e, {kUcdName});
    }
}

inline std::string check_plot3d(const std::uint8_t* data, std::size_t size) {
    const Plot3dInput in = split_plot3d_input(data, size);
    try {
        std::vector<std::string> notes;
        const fx::Plot3dData out = fx::parse_plot3d(in.xyz, kXyzName, in.q ? &*in.q : nullptr, kQName, &notes);
        if (in.q && out.references.size() != out.mesh.blocks.size()) return "one reference block per grid block expected";
        return check_mesh(out.mesh, size);
    } catch (const fx::Error& e) {
        return check_message(e, {kXyzName, kQName});
    }
}

// A parsed transfer function evaluates to finite, non-negative values everywhere, and maps
// onto the scalar ranges real fields have (tiny, unit, huge) without error.
inline std::string check_transfer_function(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const fx::TransferFunction tf = fx::TransferFunction::parse_json(text, kJsonName);
        const auto check_values = [](const fx::TransferFunction& f, const char* what) -> std::string {
            std::vector<double> probes = {-1e300, -1.0, 0.0, 0.5, 1.0, 1e300};
            for (const fx::TransferPoint& p : f.points()) {
                probes.push_back(p.s);
                probes.push_back(std::nextafter(p.s, -INFINITY));
                probes.push_back(std::nextafter(p.s, INFINITY));
            }
            for (std::size_t i = 1; i < f.points().size(); ++i) probes.push_back(0.5 * f.points()[i - 1].s + 0.5 * f.points()[i].s);
            for (double s : probes) {
                const glm::dvec3 c = f.color(s);
                const double sigma = f.sigma(s);
                for (double v : {c.r, c.g, c.b, sigma}) {
                    if (!(std::isfinite(v) && v >= 0.0)) {
                        char at[64];
                        std::snprintf(at, sizeof at, "%.17g", s);
                        return std::string(what) + ": value at s = " + at + " is negative or not finite";
                    }
                }
            }
            return "";
        };
        if (std::string problem = check_values(tf, "parsed"); !problem.empty()) return problem;
        for (const auto& [lo, hi] : {std::pair{0.0, 1.0}, std::pair{1e-7, 2e-7}, std::pair{-1e7, 1e7}, std::pair{5.0, -5.0}}) {
            try {
                if (std::string problem = check_values(tf.rescaled(lo, hi), "rescaled"); !problem.empty()) return problem;
            } catch (const fx::Error& e) {
                char range[64];
                std::snprintf(range, sizeof range, "rescaled(%g, %g)", lo, hi);
                return std::string(range) + " of a valid function failed: " + e.what();
            }
        }
        return "";
    } catch (const fx::Error& e) {
        return check_message(e, {kJsonName});
    }
}

inline std::string check_height_field(const terrain::HeightField& f, const char* what) {
    if (!terrain::is_lod_size(f.size) || f.heights.size() != std::size_t(f.size) * std::size_t(f.size)) {
        return std::string(what) + ": size " + std::to_string(f.size) + " with " + std::to_string(f.heights.size()) + " heights";
    }
    if (!(f.spacing > 0.0) || !std::isfinite(f.spacing)) return std::string(what) + ": spacing not finite and positive";
    for (float h : f.heights) {
        if (!std::isfinite(h)) return std::string(what) + ": non-finite height";
    }
    return "";
}

// Without and, for images of at most 1025 pixels a side, with `pad`: padding a 16385 x 2 image
// to 16385^2 samples (1 GiB) is what pad asks for, not a reader bug. No bound on memory per
// input byte here: deflate compresses up to ~1000:1.
inline std::string check_height_field_png(const std::uint8_t* data, std::size_t size) {
    const std::vector<char> bytes(data, data + size);
    const auto be32 = [&](std::size_t at) {
        return std::uint32_t(data[at]) << 24 | std::uint32_t(data[at + 1]) << 16 | std::uint32_t(data[at + 2]) << 8 | data[at + 3];
    };
    const bool small = size >= 24 && be32(16) <= 1025 && be32(20) <= 1025; // IHDR width, height
    for (bool pad : {false, true}) {
        if (pad && !small) continue;
        terrain::HeightFieldOptions options;
        options.pad = pad;
        options.vertical_scale = pad ? -0.25 : 1.0;
        try {
            if (std::string problem = check_height_field(terrain::parse_height_field_png(bytes, kPngName, options), "height field");
                !problem.empty()) {
                return problem;
            }
        } catch (const fx::Error& e) {
            if (std::string problem = check_message(e, {kPngName}); !problem.empty()) return problem;
        }
    }
    return "";
}

// Scenes may ask for 16385^2 procedural samples (1 GiB, minutes of noise): valid and slow, so
// inputs asking for more than 513 a side are left out here.
inline bool scene_asks_for_large_grid(std::string_view text) {
    nlohmann::json doc = nlohmann::json::parse(text.begin(), text.end(), nullptr, false);
    if (!doc.is_object()) return false;
    const auto too_big = [](const nlohmann::json& section) {
        if (!section.is_object()) return false;
        const auto size = section.find("size");
        return size != section.end() && size->is_number() && !(size->get<double>() <= 513.0);
    };
    const auto terrain_section = doc.find("terrain");
    if (terrain_section != doc.end() && terrain_section->is_object()) {
        const auto procedural = terrain_section->find("procedural");
        if (procedural != terrain_section->end() && too_big(*procedural)) return true;
    }
    const auto aurora = doc.find("aurora");
    return aurora != doc.end() && too_big(*aurora);
}

inline std::string check_scene(const std::uint8_t* data, std::size_t size, const std::string& base_dir) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (scene_asks_for_large_grid(text)) return "";
    try {
        const terrain::Scene scene = terrain::parse_scene(text, kSceneName, base_dir);
        // A scene of effects alone has no terrain (an empty ground); any other has a valid one.
        if (scene.has_terrain() || scene.effects.empty()) {
            if (std::string problem = check_height_field(scene.ground, "ground"); !problem.empty()) return problem;
        }
        if (scene.fog) {
            if (std::string problem = check_height_field(scene.fog->thickness, "fog thickness"); !problem.empty()) return problem;
            if (scene.fog->thickness.size != scene.ground.size) return "fog thickness not on the ground's grid";
        }
        if (scene.aurora) {
            if (std::string problem = check_height_field(scene.aurora->layer.depth, "aurora depth"); !problem.empty()) return problem;
            if (std::string problem = check_height_field(scene.aurora->layer.lower_border, "aurora border"); !problem.empty()) return problem;
        }
        if (scene.width < 1 || scene.height < 1) return "render size not positive";
        return "";
    } catch (const fx::Error& e) {
        return check_message(e, {kSceneName});
    }
}

} // namespace fx_fuzz
