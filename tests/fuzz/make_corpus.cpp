// cellfx — writes the seed corpus of the fuzz targets (tests/fuzz/corpus/<target>/).
//
//   fuzz_make_corpus SOURCE_DIR OUT_DIR
//
// Seeds come from the licensed files in SOURCE_DIR/content (small ones copied as they are,
// large ones cut down to a few cells and written back with cellfx's own writers) and from
// small files composed here to reach every branch the readers have: both VTK encodings and
// layouts, every attribute kind, all 32 PLOT3D variants with and without a q file, every UCD
// cell type. Each seed is a few KiB so that libFuzzer mutates quickly. Output is deterministic.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "fuzz_checks.hpp"
#include "io/io_util.hpp"

namespace fs = std::filesystem;

namespace {

std::string g_out;
std::map<std::string, int> g_counts;

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw fx::Error(path.string() + ": cannot open file");
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_seed(const std::string& target, const std::string& name, const std::string& bytes) {
    const fs::path dir = fs::path(g_out) / target;
    fs::create_directories(dir);
    std::ofstream out(dir / name, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    if (!out) throw fx::Error((dir / name).string() + ": cannot write");
    ++g_counts[target];
}

fs::path temp_path(const std::string& name) {
    const fs::path dir = fs::path(g_out) / ".tmp";
    fs::create_directories(dir);
    return dir / name;
}

// The first `cells` cells of a mesh with the points they use, renumbered, fields kept.
fx::CellMesh first_cells(const fx::CellMesh& mesh, std::size_t cells) {
    fx::CellMesh out;
    std::map<std::uint32_t, std::uint32_t> renumber;
    std::vector<std::uint32_t> kept;
    for (std::size_t c = 0; c < cells && c < mesh.cell_count(); ++c) {
        const std::uint32_t* v = mesh.cell_vertices(c);
        std::uint32_t local[8];
        for (int k = 0; k < fx::cell_vertex_count(mesh.cell_types[c]); ++k) {
            const auto it = renumber.emplace(v[k], std::uint32_t(kept.size()));
            if (it.second) kept.push_back(v[k]);
            local[k] = it.first->second;
        }
        out.add_cell(mesh.cell_types[c], local);
    }
    for (std::uint32_t p : kept) out.points.push_back(mesh.points[p]);
    for (const fx::ScalarField& f : mesh.scalars) {
        fx::ScalarField g{f.name, {}};
        for (std::uint32_t p : kept) g.values.push_back(f.values[p]);
        out.scalars.push_back(std::move(g));
    }
    return out;
}

std::string vtk_bytes(const fx::CellMesh& mesh, bool binary) {
    const fs::path path = temp_path("mesh.vtk");
    fx::write_vtk_legacy(mesh, path.string(), binary);
    return read_file(path);
}

// A VTK legacy file composed section by section, ASCII or BINARY (big-endian values).
class VtkComposer {
public:
    VtkComposer(bool binary, const std::string& dataset, const std::string& version = "3.0") : binary_(binary) {
        text_ = "# vtk DataFile Version " + version + "\ncellfx fuzz seed\n" + (binary ? "BINARY\n" : "ASCII\n") +
                "DATASET " + dataset + "\n";
    }
    void line(const std::string& s) { text_ += s + "\n"; }
    // Values of a VTK data type name: float/double, or an integer type.
    void values(const std::vector<double>& v, const std::string& type) {
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (binary_) {
                if (type == "float") fx::io::store_scalar<float>(text_, float(v[i]), true);
                else if (type == "double") fx::io::store_scalar<double>(text_, v[i], true);
                else if (type == "unsigned_char" || type == "char") text_ += char(int(v[i]));
                else if (type == "short") fx::io::store_scalar<std::int16_t>(text_, std::int16_t(v[i]), true);
                else if (type == "vtktypeint64" || type == "long") fx::io::store_scalar<std::int64_t>(text_, std::int64_t(v[i]), true);
                else fx::io::store_scalar<std::int32_t>(text_, std::int32_t(v[i]), true);
            } else {
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.9g", v[i]);
                text_ += buf;
                text_ += (i + 1) % 9 == 0 || i + 1 == v.size() ? "\n" : " ";
            }
        }
        if (binary_) text_ += "\n";
    }
    const std::string& text() const { return text_; }

private:
    bool binary_;
    std::string text_;
};

std::vector<double> grid_points(int ni, int nj, int nk) {
    std::vector<double> p;
    for (int k = 0; k < nk; ++k)
        for (int j = 0; j < nj; ++j)
            for (int i = 0; i < ni; ++i) {
                p.push_back(i + 0.1 * j);
                p.push_back(j * 0.5);
                p.push_back(k - 0.05 * i);
            }
    return p;
}

std::vector<double> ramp(std::size_t n, double scale) {
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) v.push_back(scale * double(i));
    return v;
}

void vtk_seeds(const fs::path& source) {
    const fs::path meshes = source / "content/meshes";
    // Small real files as they are.
    for (const char* name : {"Tetra.vtk", "Pyramid.vtk", "Wedge.vtk", "Hexahedron.vtk", "Voxel.vtk", "uGridEx.vtk",
                             "VTKCellTypes.vtk", "tetraMesh.vtk"}) {
        write_seed("vtk_legacy", std::string("real_") + name, read_file(meshes / "vtk_cells" / name));
    }
    // Real files too large to seed with: the head of the file as it is (its header and the
    // start of the points), and a few cells written back by write_vtk_legacy in both encodings.
    for (const char* rel : {"lox_post/post.vtk", "cylinder_tets/CylinderLinear.vtk", "hexa_grid/hexa.vtk"}) {
        const fs::path path = meshes / rel;
        const std::string stem = path.stem().string();
        write_seed("vtk_legacy", "head_" + stem + ".vtk", read_file(path).substr(0, 1024));
        const fx::CellMesh part = first_cells(fx::read_vtk_legacy(path.string()), 6);
        write_seed("vtk_legacy", "writer_ascii_" + stem + ".vtk", vtk_bytes(part, false));
        write_seed("vtk_legacy", "writer_binary_" + stem + ".vtk", vtk_bytes(part, true));
    }
    // Every cell type and a field name that needs percent-encoding, through the writer.
    {
        fx::CellMesh mesh;
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) mesh.points.push_back({i + 0.125 * k, j - 1e-7 * i, k * 1.5 + 1e6});
        mesh.points.push_back({0.5, 0.5, 1e6 + 4.0});
        const std::uint32_t hex[8] = {0, 1, 3, 2, 4, 5, 7, 6}, wedge[6] = {4, 6, 5, 8, 10, 9};
        const std::uint32_t tet[4] = {8, 9, 10, 12}, pyr[5] = {8, 9, 11, 10, 12};
        mesh.add_cell(fx::CellType::Hexahedron, hex);
        mesh.add_cell(fx::CellType::Wedge, wedge);
        mesh.add_cell(fx::CellType::Tetra, tet);
        mesh.add_cell(fx::CellType::Pyramid, pyr);
        mesh.scalars = {{"density", {}}, {"my field%", {}}};
        for (std::size_t p = 0; p < mesh.points.size(); ++p) {
            mesh.scalars[0].values.push_back(0.1f * float(p));
            mesh.scalars[1].values.push_back(-float(p) * 1e-3f);
        }
        write_seed("vtk_legacy", "writer_ascii_all_types.vtk", vtk_bytes(mesh, false));
        write_seed("vtk_legacy", "writer_binary_all_types.vtk", vtk_bytes(mesh, true));
    }
    for (bool binary : {false, true}) {
        const std::string enc = binary ? "binary" : "ascii";
        // STRUCTURED_GRID with multi-component scalars, vectors and blanking.
        for (const char* type : {"float", "double"}) {
            VtkComposer v(binary, "STRUCTURED_GRID");
            v.line("DIMENSIONS 3 2 2");
            v.line(std::string("POINTS 12 ") + type);
            v.values(grid_points(3, 2, 2), type);
            v.line("POINT_DATA 12");
            v.line("SCALARS t " + std::string(type) + " 3");
            v.line("LOOKUP_TABLE default");
            v.values(ramp(36, -0.5), type);
            v.line("VECTORS velocity float");
            v.values(ramp(36, 0.25), "float");
            write_seed("vtk_legacy", "structured_" + enc + "_" + type + ".vtk", v.text());
        }
        {
            VtkComposer v(binary, "STRUCTURED_GRID");
            v.line("DIMENSIONS 2 2 1");
            v.line("POINTS 4 float");
            v.values(grid_points(2, 2, 1), "float");
            v.line("BLANKING 4");
            v.values({1, 1, 0, 1}, "unsigned_char");
            write_seed("vtk_legacy", "structured_" + enc + "_flat_blanking.vtk", v.text());
        }
        // Version 5 OFFSETS / CONNECTIVITY layout with 64-bit indices and a 2-D cell.
        {
            VtkComposer v(binary, "UNSTRUCTURED_GRID", "5.1");
            v.line("POINTS 5 float");
            v.values({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}, "float");
            v.line("METADATA");
            v.line("INFORMATION 0");
            v.line("");
            v.line("CELLS 3 7");
            v.line("OFFSETS vtktypeint64");
            v.values({0, 4, 7}, "vtktypeint64");
            v.line("CONNECTIVITY vtktypeint64");
            v.values({0, 1, 2, 3, 1, 2, 3}, "vtktypeint64");
            v.line("CELL_TYPES 2");
            v.values({10, 5}, "int");
            v.line("CELL_DATA 2");
            v.line("SCALARS material int 1");
            v.line("LOOKUP_TABLE default");
            v.values({1, 2}, "int");
            write_seed("vtk_legacy", "v5_offsets_" + enc + ".vtk", v.text());
        }
        // Every point attribute kind the reader reads or skips, FIELD data at both levels.
        {
            VtkComposer v(binary, "UNSTRUCTURED_GRID");
            v.line("FIELD FieldData 2");
            v.line("TIME 1 1 double");
            v.values({0.5}, "double");
            v.line("CYCLE 1 1 int");
            v.values({3}, "int");
            v.line("POINTS 9 double");
            v.values(grid_points(3, 3, 1), "double");
            v.line("CELLS 2 10");
            v.values({4, 0, 1, 3, 4, 4, 1, 2, 4, 5}, "int");
            v.line("CELL_TYPES 2");
            v.values({10, 9}, "int");
            v.line("POINT_DATA 9");
            v.line("SCALARS pressure float");
            v.line("LOOKUP_TABLE my_table");
            v.values(ramp(9, 1.5), "float");
            v.line("SCALARS id unsigned_char 1");
            v.values(ramp(9, 1), "unsigned_char");
            v.line("SCALARS small short 2");
            v.line("LOOKUP_TABLE default");
            v.values(ramp(18, 1), "short");
            v.line("NORMALS n float");
            v.values(ramp(27, 0.1), "float");
            v.line("TEXTURE_COORDINATES uv 2 float");
            v.values(ramp(18, 0.1), "float");
            v.line("TENSORS stress float");
            v.values(ramp(81, 0.01), "float");
            v.line("GLOBAL_IDS gid int");
            v.values(ramp(9, 1), "int");
            v.line("COLOR_SCALARS rgb 3");
            if (binary) {
                v.values(ramp(27, 9), "unsigned_char");
            } else {
                v.values(ramp(27, 0.03), "float");
            }
            v.line("LOOKUP_TABLE my_table 2");
            if (binary) {
                v.values(ramp(8, 30), "unsigned_char");
            } else {
                v.values(ramp(8, 0.1), "float");
            }
            v.line("FIELD attributes 3");
            v.line("temperature 1 9 float");
            v.values(ramp(9, 2.0), "float");
            v.line("velocity 3 9 double");
            v.values(ramp(27, -1.0), "double");
            v.line("short%20list 1 2 int");
            v.values({1, 2}, "int");
            write_seed("vtk_legacy", "attributes_" + enc + ".vtk", v.text());
        }
        // Voxels and 0-D/1-D cells in the classic layout, with CELL_DATA first.
        {
            VtkComposer v(binary, "UNSTRUCTURED_GRID", "2.0");
            v.line("POINTS 12 float");
            v.values(grid_points(2, 2, 3), "float");
            v.line("CELLS 4 23");
            v.values({8, 0, 1, 2, 3, 4, 5, 6, 7, 8, 4, 5, 6, 7, 8, 9, 10, 11, 1, 0, 2, 0, 11}, "int");
            v.line("CELL_TYPES 4");
            v.values({11, 12, 1, 3}, "int");
            v.line("CELL_DATA 4");
            v.line("FIELD cd 1");
            v.line("quality 1 4 float");
            v.values({1, 2, 3, 4}, "float");
            v.line("POINT_DATA 12");
            v.line("VECTORS v double");
            v.values(ramp(36, 0.5), "double");
            write_seed("vtk_legacy", "voxels_" + enc + ".vtk", v.text());
        }
    }
}

// PLOT3D blocks sampled from a real grid (and its q file): every `step`-th node.
std::vector<fx::Plot3dBlock> sampled_blocks(const fx::Plot3dData& data, std::array<std::uint32_t, 3> want) {
    std::vector<fx::Plot3dBlock> out;
    std::size_t base = 0;
    for (std::size_t b = 0; b < data.mesh.blocks.size(); ++b) {
        const auto d = data.mesh.blocks[b].dims;
        fx::Plot3dBlock block;
        block.dims = want;
        for (std::uint32_t k = 0; k < want[2]; ++k)
            for (std::uint32_t j = 0; j < want[1]; ++j)
                for (std::uint32_t i = 0; i < want[0]; ++i) {
                    const std::uint32_t si = i * (d[0] - 1) / (want[0] - 1), sj = j * (d[1] - 1) / (want[1] - 1),
                                        sk = k * (d[2] - 1) / (want[2] - 1);
                    const std::size_t p = base + si + d[0] * (sj + std::size_t(d[1]) * sk);
                    block.points.push_back(data.mesh.points[p]);
                    block.iblank.push_back(i == 1 && j == 1 && k == 0 ? 0 : 1);
                    static const char* kFields[5] = {"density", "momentum_x", "momentum_y", "momentum_z", "energy"};
                    for (int f = 0; f < 5; ++f) block.q[f].push_back(data.mesh.find_scalar(kFields[f])->values[p]);
                }
        if (b < data.references.size()) block.reference = data.references[b];
        out.push_back(std::move(block));
        base += std::size_t(d[0]) * d[1] * d[2];
    }
    return out;
}

std::string variant_name(const fx::Plot3dFormat& f) {
    return std::string(f.big_endian ? "be" : "le") + (f.record_markers ? "_markers" : "") + (f.multi_block ? "_multi" : "_whole") +
           (f.double_precision ? "_f64" : "_f32") + (f.iblank ? "_iblank" : "");
}

void plot3d_seeds(const fs::path& source) {
    const fs::path meshes = source / "content/meshes";
    const fx::Plot3dData fin = fx::read_plot3d((meshes / "blunt_fin/bluntfinxyz.bin").string(), (meshes / "blunt_fin/bluntfinq.bin").string());
    const fx::Plot3dData two = fx::read_plot3d((meshes / "blunt_fin_2block/multi-bin.xyz").string(),
                                               (meshes / "blunt_fin_2block/multi-bin.q").string());
    const std::vector<fx::Plot3dBlock> one_block = sampled_blocks(fin, {4, 3, 3});
    const std::vector<fx::Plot3dBlock> two_blocks = sampled_blocks(two, {3, 3, 2});
    const std::string xyz_path = temp_path("seed.xyz").string(), q_path = temp_path("seed.q").string();
    for (bool big_endian : {true, false})
        for (bool markers : {true, false})
            for (bool double_precision : {false, true})
                for (bool iblank : {false, true})
                    for (bool multi : {false, true}) {
                        const fx::Plot3dFormat f{big_endian, markers, double_precision, iblank, multi};
                        fx::write_plot3d(multi ? two_blocks : one_block, f, xyz_path, q_path);
                        const std::string xyz = read_file(xyz_path), q = read_file(q_path);
                        write_seed("plot3d", variant_name(f) + ".grid", fx_fuzz::pack_plot3d_input(xyz, nullptr));
                        write_seed("plot3d", variant_name(f) + ".grid_q", fx_fuzz::pack_plot3d_input(xyz, &q));
                    }
    // Like NASA's bluntfinq.bin: zero bytes after the q arrays.
    const fx::Plot3dFormat nasa{true, false, false, false, false};
    fx::write_plot3d(one_block, nasa, xyz_path, q_path);
    const std::string xyz = read_file(xyz_path), q = read_file(q_path) + std::string(64, '\0');
    write_seed("plot3d", "be_whole_f32_q_trailing_zeros.grid_q", fx_fuzz::pack_plot3d_input(xyz, &q));
    // A q file in the other precision than its grid.
    fx::Plot3dFormat f64 = nasa;
    f64.double_precision = true;
    fx::write_plot3d(one_block, f64, temp_path("f64.xyz").string(), q_path);
    const std::string q64 = read_file(q_path);
    write_seed("plot3d", "be_whole_f32_grid_f64_q.grid_q", fx_fuzz::pack_plot3d_input(xyz, &q64));
    // The head of the real files as they are.
    write_seed("plot3d", "head_bluntfinxyz.grid", fx_fuzz::pack_plot3d_input(read_file(meshes / "blunt_fin/bluntfinxyz.bin").substr(0, 2048), nullptr));
    write_seed("plot3d", "head_multi-bin.grid", fx_fuzz::pack_plot3d_input(read_file(meshes / "blunt_fin_2block/multi-bin.xyz").substr(0, 2048), nullptr));
}

// UCD vertex k of a cell = VTK vertex from_vtk[k] (the inverse of the reader's conversion).
struct UcdType {
    const char* keyword;
    std::array<int, 8> from_vtk;
};
UcdType ucd_type(fx::CellType t) {
    switch (t) {
    case fx::CellType::Tetra: return {"tet", {0, 1, 3, 2}};
    case fx::CellType::Pyramid: return {"pyr", {4, 0, 1, 2, 3}};
    case fx::CellType::Wedge: return {"prism", {3, 4, 5, 0, 1, 2}};
    case fx::CellType::Hexahedron: return {"hex", {4, 5, 6, 7, 0, 1, 2, 3}};
    }
    return {"tet", {0, 1, 2, 3}};
}

// A mesh as UCD text: node ids 10, 20, ...; cells numbered from 1; every field as node data.
std::string ucd_text(const fx::CellMesh& mesh, bool flip_odd_cells) {
    std::string t = "# AVS UCD written for the cellfx fuzz corpus\n";
    t += std::to_string(mesh.point_count()) + " " + std::to_string(mesh.cell_count()) + " " + std::to_string(mesh.scalars.size()) + " 0 0\n";
    char buf[128];
    for (std::size_t p = 0; p < mesh.point_count(); ++p) {
        std::snprintf(buf, sizeof buf, "%zu %.9g %.9g %.9g\n", 10 * (p + 1), mesh.points[p].x, mesh.points[p].y, mesh.points[p].z);
        t += buf;
    }
    for (std::size_t c = 0; c < mesh.cell_count(); ++c) {
        const UcdType u = ucd_type(mesh.cell_types[c]);
        const int n = fx::cell_vertex_count(mesh.cell_types[c]);
        t += std::to_string(c + 1) + " 1 " + u.keyword;
        std::array<int, 8> order = u.from_vtk;
        if (flip_odd_cells && c % 2 == 1) std::reverse(order.begin(), order.begin() + n); // mixed winding
        for (int k = 0; k < n; ++k) t += " " + std::to_string(10 * (mesh.cell_vertices(c)[order[k]] + 1));
        t += "\n";
    }
    if (!mesh.scalars.empty()) {
        t += std::to_string(mesh.scalars.size());
        for (std::size_t f = 0; f < mesh.scalars.size(); ++f) t += " 1";
        t += "\n";
        for (const fx::ScalarField& f : mesh.scalars) t += f.name + ", none\n";
        for (std::size_t p = 0; p < mesh.point_count(); ++p) {
            t += std::to_string(10 * (p + 1));
            for (const fx::ScalarField& f : mesh.scalars) {
                std::snprintf(buf, sizeof buf, " %.9g", f.values[p]);
                t += buf;
            }
            t += "\n";
        }
    }
    return t;
}

void ucd_seeds(const fs::path& source) {
    const fs::path meshes = source / "content/meshes";
    // Real meshes written as UCD (tetraMesh whole; a few cells of the others).
    write_seed("avs_ucd", "real_tetraMesh.inp", ucd_text(first_cells(fx::read_vtk_legacy((meshes / "vtk_cells/tetraMesh.vtk").string()), 12), false));
    write_seed("avs_ucd", "real_hexa_mixed_winding.inp", ucd_text(first_cells(fx::read_vtk_legacy((meshes / "hexa_grid/hexa.vtk").string()), 6), true));
    write_seed("avs_ucd", "real_post.inp", ucd_text(first_cells(fx::read_vtk_legacy((meshes / "lox_post/post.vtk").string()), 8), true));
    write_seed("avs_ucd", "real_uGridEx.inp", ucd_text(fx::read_vtk_legacy((meshes / "vtk_cells/uGridEx.vtk").string()), false));
    for (const char* name : {"Wedge.vtk", "Pyramid.vtk"}) {
        write_seed("avs_ucd", std::string("real_") + fs::path(name).stem().string() + ".inp",
                   ucd_text(fx::read_vtk_legacy((meshes / "vtk_cells" / name).string()), false));
    }
    // Every UCD cell type (as in the AVS sample ucd1.inp), multi-component node data, cell and
    // model data counts, unordered ids.
    write_seed("avs_ucd", "all_types.inp",
               "# AVS UCD test file\n# all cell types\n9 9 4 1 0\n"
               "101 0 0 1\n102 1 0 1\n103 1 1 1\n104 0 1 1\n108 0 1 0\n107 1 1 0\n106 1 0 0\n105 0 0 0\n109 0.5 0.5 2\n"
               "7 1 hex 101 102 103 104 105 106 107 108\n8 1 pyr 109 101 102 103 104\n9 1 tet 101 104 102 109\n"
               "3 2 prism 101 102 104 105 106 108\n10 1 tri 101 102 103\n11 1 quad 101 102 103 104\n12 2 line 101 105\n"
               "13 2 pt 101\n14 2 tri 105 106 107\n"
               "2 1 3\ntemperature, K\nvelocity, m/s\n"
               "109 9 0 0 9\n101 1 1 0 0\n102 2 0 2 0\n103 3 3 3 3\n104 4 4 0 0\n105 5 0 5 0\n106 6 0 0 6\n107 7 7 0 0\n108 8 0 8 0\n"
               "1 1\nmaterial, none\n");
    write_seed("avs_ucd", "degenerate.inp",
               "# a repeated vertex and a flat tet\n5 2 0 0 2\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0 0 1\n"
               "1 0 tet 1 2 3 4\n2 0 tet 1 1 3 5\n");
}

void transfer_function_seeds(const fs::path& source) {
    for (const auto& entry : fs::directory_iterator(source / "content/transfer_functions")) {
        if (entry.path().extension() == ".json") {
            write_seed("transfer_function", "real_" + entry.path().filename().string(), read_file(entry.path()));
        }
    }
    write_seed("transfer_function", "single_point.json", R"({"points": [[0.25, 1, 0.5, 0, 2]], "normalized": true})");
    write_seed("transfer_function", "steps_raw_range.json",
               R"({"description": "caf\u00e9 \"steps\"", "normalized": false, "points": [[-1e7, 0, 0, 0, 0], [0, 0, 0, 0, 0], )"
               R"([0, 1e-7, 2.5E+1, 0.0, 1e300], [1e7, 1, 1, 1, 0]]})");
    write_seed("transfer_function", "integers.json", R"({"points":[[0,0,0,0,0],[1,1,1,1,1],[1,0,0,0,3],[2,2,2,2,2]]})");
}

// A PNG with the pixels in stored (uncompressed) deflate blocks: any bit depth and colour type,
// no zlib needed. `pixels` holds the raw samples, big-endian for 16 bits, rows top first.
std::uint32_t crc32(const std::string& bytes) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}
void append_be32(std::string& out, std::uint32_t v) {
    for (int k = 3; k >= 0; --k) out += char((v >> (8 * k)) & 0xFF);
}
void append_chunk(std::string& out, const char* type, const std::string& data) {
    append_be32(out, std::uint32_t(data.size()));
    const std::string body = std::string(type, 4) + data;
    out += body;
    append_be32(out, crc32(body));
}
std::string png_bytes(int w, int h, int depth, int colour_type, const std::string& pixels) {
    static const int kChannels[7] = {1, 0, 3, 0, 2, 0, 4};
    const std::size_t row_bytes = std::size_t(w) * kChannels[colour_type] * depth / 8;
    std::string raw;
    for (int y = 0; y < h; ++y) raw += '\0' + pixels.substr(y * row_bytes, row_bytes); // filter type 0
    std::string z = "\x78\x01";
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : raw) a = (a + c) % 65521, b = (b + a) % 65521;
    for (std::size_t at = 0; at < raw.size() || at == 0; at += 65535) {
        const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
        z += char(at + n >= raw.size() ? 1 : 0);
        z += char(n & 0xFF), z += char(n >> 8), z += char(~n & 0xFF), z += char((~n >> 8) & 0xFF);
        z += raw.substr(at, n);
        if (raw.empty()) break;
    }
    append_be32(z, (b << 16) | a);
    std::string ihdr;
    append_be32(ihdr, std::uint32_t(w));
    append_be32(ihdr, std::uint32_t(h));
    ihdr += char(depth), ihdr += char(colour_type), ihdr += '\0', ihdr += '\0', ihdr += '\0';
    std::string out = "\x89PNG\r\n\x1a\n";
    append_chunk(out, "IHDR", ihdr);
    append_chunk(out, "IDAT", z);
    append_chunk(out, "IEND", "");
    return out;
}

std::string ramp_pixels(int w, int h, int channels, int depth) {
    std::string p;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < channels; ++c) {
                const int v = (x * 37 + y * 11 + c * 5) % 256;
                p += char(v);
                if (depth == 16) p += char(255 - v);
            }
    return p;
}

void height_field_seeds(const fs::path& source) {
    write_seed("height_field_png", "real_st_helens_257.png", read_file(source / "content/terrain/st_helens_257.png"));
    write_seed("height_field_png", "grey8_5x5.png", png_bytes(5, 5, 8, 0, ramp_pixels(5, 5, 1, 8)));
    write_seed("height_field_png", "grey16_9x9.png", png_bytes(9, 9, 16, 0, ramp_pixels(9, 9, 1, 16)));
    write_seed("height_field_png", "grey8_6x4_needs_pad.png", png_bytes(6, 4, 8, 0, ramp_pixels(6, 4, 1, 8)));
    write_seed("height_field_png", "grey16_3x17_needs_pad.png", png_bytes(3, 17, 16, 0, ramp_pixels(3, 17, 1, 16)));
    write_seed("height_field_png", "rgb8_5x5.png", png_bytes(5, 5, 8, 2, ramp_pixels(5, 5, 3, 8)));
    write_seed("height_field_png", "grey_alpha8_5x5.png", png_bytes(5, 5, 8, 4, ramp_pixels(5, 5, 2, 8)));
    write_seed("height_field_png", "rgba16_3x3.png", png_bytes(3, 3, 16, 6, ramp_pixels(3, 3, 4, 16)));
}

void scene_seeds(const fs::path& source) {
    for (const auto& entry : fs::directory_iterator(source / "content/scenes")) {
        if (entry.path().extension() == ".json") write_seed("scene", "real_" + entry.path().filename().string(), read_file(entry.path()));
    }
    // Every section and option of the format, on small procedural grids (files resolve in
    // content/scenes/, as for the real scenes).
    const std::string noise = R"({"amplitude": 40, "offset": 5, "frequency": 0.01, "octaves": 3, "lacunarity": 2, "gain": 0.5, "seed": 7})";
    const std::string camera = R"("camera": {"eye": [100, -300, 400], "target": [160, 160, 20], "up": [0, 0, 1], "fov": 50, "near": 5, "far": 6000})";
    write_seed("scene", "procedural_valley_fog.json",
               "{\"description\": \"procedural ground, valley fog with noise density\",\n"
               " \"terrain\": {\"procedural\": {\"size\": 33, \"spacing\": 10, \"origin\": [-5, 5], \"noise\": " + noise + "}},\n"
               " \"lod\": {\"pixel_error\": 3, \"min_resolution\": 4, \"triangle_budget\": 5000, \"geomorph\": false},\n"
               " \"fog\": {\"valley\": {\"level\": 20, \"max_thickness\": 30, \"radius\": 40, \"noise\": " + noise + "},\n"
               "         \"density\": \"noise\", \"density_scale\": 2, \"density_noise\": " + noise + ",\n"
               "         \"transfer_function\": \"../transfer_functions/fog.json\", \"extinction_scale\": 0.01, \"path\": \"pcp-exact\", \"absorb\": false},\n"
               " " + camera + ",\n"
               " \"render\": {\"width\": 64, \"height\": 48, \"background\": [0.1, 0.2, 0.3]},\n"
               " \"surface\": {\"sun\": [1, 2, 3], \"ambient\": 0.4}}\n");
    write_seed("scene", "height_map_thickness_map_aurora.json",
               "{\"terrain\": {\"height_map\": \"../terrain/st_helens_257.png\", \"spacing\": 30, \"vertical_scale\": 0.5, \"vertical_offset\": 10, \"pad\": false},\n"
               " \"fog\": {\"thickness_map\": {\"file\": \"../terrain/st_helens_257.png\", \"vertical_scale\": 0.1, \"pad\": true},\n"
               "         \"density\": \"layer_height\", \"transfer_function\": \"transfer_functions/fog_glow.json\", \"path\": \"mip\"},\n"
               " \"aurora\": {\"ceiling\": 12000, \"size\": 17, \"spacing\": 120, \"origin\": [0, 0],\n"
               "            \"curtains\": {\"count\": 2, \"max_depth\": 3000, \"width\": 250, \"wander\": 1500, \"cutoff\": 0.02, \"seed\": 3},\n"
               "            \"transfer_function\": \"transfer_functions/aurora.json\", \"extinction_scale\": 1, \"path\": \"pcp\", \"pixel_error\": 4},\n"
               " " + camera + "}\n");
}

// The hostile-input classes (docs/robustness.md): well-formed files that ask too much or mean
// nothing, so that mutations start from the places the budgets and policies guard.
fx::CellMesh unit_hex(glm::dvec3 offset = glm::dvec3(0.0)) {
    fx::CellMesh m;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) m.points.push_back(offset + glm::dvec3(i, j, k));
    const std::uint32_t h[8] = {0, 1, 3, 2, 4, 5, 7, 6};
    m.add_cell(fx::CellType::Hexahedron, h);
    m.scalars = {{"s", {0, 1, 2, 3, 4, 5, 6, 7}}};
    return m;
}

void hostile_seeds() {
    fx::CellMesh tets;
    tets.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::uint32_t t[4] = {0, 1, 2, 3};
    for (int i = 0; i < 3; ++i) tets.add_cell(fx::CellType::Tetra, t);
    tets.scalars = {{"s", {0, 1, 2, 3}}};
    write_seed("vtk_legacy", "hostile_duplicate_tets.vtk", vtk_bytes(tets, false));
    fx::CellMesh two = unit_hex(), shifted = unit_hex(glm::dvec3(0.5, 0.2, 0.0));
    std::uint32_t h[8];
    for (int i = 0; i < 8; ++i) h[i] = shifted.cell_vertices(0)[i] + 8;
    two.points.insert(two.points.end(), shifted.points.begin(), shifted.points.end());
    two.scalars[0].values.insert(two.scalars[0].values.end(), shifted.scalars[0].values.begin(), shifted.scalars[0].values.end());
    two.add_cell(fx::CellType::Hexahedron, h);
    write_seed("vtk_legacy", "hostile_overlapping_hexes.vtk", vtk_bytes(two, true));
    fx::CellMesh inverted = unit_hex();
    std::swap_ranges(inverted.cell_vertices(0), inverted.cell_vertices(0) + 4, inverted.cell_vertices(0) + 4);
    write_seed("vtk_legacy", "hostile_inverted_hex.vtk", vtk_bytes(inverted, false));
    fx::CellMesh bowtie = unit_hex();
    std::swap(bowtie.cell_vertices(0)[4], bowtie.cell_vertices(0)[6]);
    write_seed("vtk_legacy", "hostile_bowtie_hex.vtk", vtk_bytes(bowtie, false));
    fx::CellMesh flat = unit_hex();
    for (glm::dvec3& p : flat.points) p.z = 0.0;
    write_seed("vtk_legacy", "hostile_flat_hex.vtk", vtk_bytes(flat, true));
    fx::CellMesh far = unit_hex();
    for (glm::dvec3& p : far.points) p *= 1e300;
    far.scalars[0].values.assign(8, std::nanf(""));
    write_seed("vtk_legacy", "hostile_far_nan_field.vtk", vtk_bytes(far, true));

    // PLOT3D: a left-handed grid, one cut short, one with a lying record marker.
    fx::Plot3dBlock b;
    b.dims = {3, 2, 2};
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) b.points.push_back(glm::dvec3(2 - i, j, k));
    fx::Plot3dFormat f;
    f.record_markers = true;
    const fs::path xyz = temp_path("hostile.xyz");
    fx::write_plot3d({b}, f, xyz.string());
    const std::string grid = read_file(xyz);
    write_seed("plot3d", "hostile_left_handed.grid", fx_fuzz::pack_plot3d_input(grid, nullptr));
    write_seed("plot3d", "hostile_truncated.grid", fx_fuzz::pack_plot3d_input(grid.substr(0, grid.size() / 2), nullptr));
    std::string lying = grid;
    lying[23] = char(lying[23] + 16); // the coordinates' opening marker
    write_seed("plot3d", "hostile_lying_marker.grid", fx_fuzz::pack_plot3d_input(lying, nullptr));

    write_seed("avs_ucd", "hostile_negative_counts.inp", "# counts below zero\n-4 1 0 0 0\n");

    write_seed("transfer_function", "hostile_utf16.json", std::string("\xFF\xFE{\0\"\0p\0\"\0:\0[\0]\0}\0", 18));
    write_seed("transfer_function", "hostile_sigma_1e300.json", R"({"points": [[0, 1, 1, 1, 1], [1, 1, 1, 1, 1e300]]})");
    write_seed("transfer_function", "hostile_colour_1e7.json", R"({"points": [[0, 1e7, 1, 1, 1]]})");

    const std::string tf = "\"transfer_function\": \"../transfer_functions/fire.json\"";
    const std::string effects_only = "\"render\": {\"width\": 64, \"height\": 48},\n";
    write_seed("scene", "hostile_camera_up_parallel.json",
               "{\"effects\": [{\"type\": \"laser_cone\", " + tf + "}], " + effects_only +
                   " \"camera\": {\"eye\": [0, 0, 5], \"target\": [0, 0, 0], \"up\": [0, 0, 1e-300]}}\n");
    write_seed("scene", "hostile_camera_path_above.json",
               "{\"effects\": [{\"type\": \"campfire\", " + tf + "}], " + effects_only +
                   " \"camera\": {\"eye\": [3, -4, 2], \"target\": [0, 0, 0.5], \"ortho\": 5},\n"
                   " \"camera_path\": {\"keys\": [{\"time\": 0, \"eye\": [3, -4, 2], \"target\": [0, 0, 0.5]},"
                   " {\"time\": 2, \"eye\": [0, 0, 9], \"target\": [0, 0, 0.5]}]}}\n");
    write_seed("scene", "hostile_numbers_1e300.json",
               "{\"effects\": [{\"type\": \"campfire\", \"base_radius\": 1e300, " + tf + "},"
               " {\"type\": \"search_light\", \"name\": \"l\", \"range\": 1e300, " + tf + "}], " + effects_only +
                   " \"camera\": {\"eye\": [3, -4, 2], \"target\": [0, 0, 0.5]}}\n");
    write_seed("scene", "hostile_effects_over_budget.json",
               "{\"effects\": [{\"type\": \"campfire\", \"cells_across\": 256, \"cells_up\": 256, " + tf + "}],"
               " \"render\": {\"width\": 16384, \"height\": 16384, \"background\": [5, 5, 5]},"
               " \"camera\": {\"eye\": [3, -4, 2], \"target\": [0, 0, 0.5], \"near\": 50, \"far\": 10}}\n");
    write_seed("scene", "hostile_terrain_1e300.json",
               "{\"terrain\": {\"procedural\": {\"size\": 17, \"spacing\": 1e300, \"noise\": {}}},"
               " \"aurora\": {\"ceiling\": 1e300, \"spacing\": 1, " + tf + "},"
               " \"camera\": {\"eye\": [3, -4, 2], \"target\": [0, 0, 0.5]}}\n");
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SOURCE_DIR OUT_DIR\n", argv[0]);
        return 2;
    }
    try {
        g_out = argv[2];
        const fs::path source = argv[1];
        vtk_seeds(source);
        plot3d_seeds(source);
        ucd_seeds(source);
        transfer_function_seeds(source);
        height_field_seeds(source);
        scene_seeds(source);
        hostile_seeds();
        fs::remove_all(fs::path(g_out) / ".tmp");
        // Every seed must satisfy the fuzz checks, or the corpus would start with a failure.
        int bad = 0;
        for (const auto& [target, count] : g_counts) {
            for (const auto& entry : fs::directory_iterator(fs::path(g_out) / target)) {
                const std::string bytes = read_file(entry.path());
                const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
                const std::size_t n = bytes.size();
                std::string problem = target == "vtk_legacy"         ? fx_fuzz::check_vtk_legacy(data, n)
                                      : target == "plot3d"           ? fx_fuzz::check_plot3d(data, n)
                                      : target == "avs_ucd"          ? fx_fuzz::check_avs_ucd(data, n)
                                      : target == "height_field_png" ? fx_fuzz::check_height_field_png(data, n)
                                      : target == "scene"            ? fx_fuzz::check_scene(data, n, (source / "content/scenes").string())
                                                                     : fx_fuzz::check_transfer_function(data, n);
                if (!problem.empty()) {
                    std::fprintf(stderr, "%s: %s\n", entry.path().c_str(), problem.c_str());
                    ++bad;
                }
            }
            std::printf("%-18s %d seeds\n", target.c_str(), count);
        }
        return bad ? 1 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_make_corpus: %s\n", e.what());
        return 1;
    }
}
