#include "projector/gl_interface.hpp"

#include <string_view>

#include "fx/cell_mesh.hpp"
#include "fx/error.hpp"
#include "gl/state_guard.hpp"
#include "gl/uniform_table.hpp"

namespace cellfx::fx {

// Every texture unit the projector uses is one gl::StateGuard saves and restores.
static_assert(kUnitCount <= gl::StateGuard::kUnits, "extend gl::StateGuard::kUnits");

namespace {

// The table's uniform locations with the number each takes (an array's elements), checked at
// compile time (gl/uniform_table.hpp).
#define FX_INTERFACE_ENTRY(name, glsl, value) gl::UniformEntry{#name, value},
constexpr gl::UniformEntry kEntries[] = {FX_PROJECTOR_INTERFACE(FX_INTERFACE_ENTRY)};
#undef FX_INTERFACE_ENTRY

constexpr int locations_taken(std::string_view name) {
    if (name == "kUniformTableCullPlanes") return 5;
    if (name == "kUniformMediumTable" || name == "kUniformMediumMedium" || name == "kUniformMediumBeamOrigin" ||
        name == "kUniformMediumBeamAxis" || name == "kUniformMediumBeamColor")
        return kMediumVolumes;
    if (name == "kUniformPointPosition" || name == "kUniformPointColor" || name == "kUniformPointG")
        return kMediumPointLights;
    return 1;
}
static_assert(gl::uniform_locations_apart(kEntries, locations_taken),
              "two uniform locations of FX_PROJECTOR_INTERFACE overlap");
static_assert(gl::uniform_locations_end(kEntries, locations_taken) <= gl::kGuaranteedUniformLocations,
              "uniform locations beyond GL 4.5's guaranteed GL_MAX_UNIFORM_LOCATIONS");

} // namespace

std::string projector_interface_glsl() {
#define FX_INTERFACE_DEFINE(name, glsl, value) gl::GlslDefine{#glsl, value},
    std::string s = gl::interface_glsl("fx/src/projector/gl_interface.cpp from FX_PROJECTOR_INTERFACE",
                                       {FX_PROJECTOR_INTERFACE(FX_INTERFACE_DEFINE)});
#undef FX_INTERFACE_DEFINE
    // Faces of a tetrahedron wound outward, in VTK order; tetrahedra from fx::subdivide_cell
    // keep their cell's positive orientation.
    const CellFace* faces = cell_faces(CellType::Tetra);
    s += "const ivec3 kTetraFaces[4] = ivec3[4](";
    for (int f = 0; f < cell_face_count(CellType::Tetra); ++f) {
        s += f ? ", " : "";
        s += "ivec3(" + std::to_string(faces[f].v[0]) + ", " + std::to_string(faces[f].v[1]) + ", " +
             std::to_string(faces[f].v[2]) + ")";
    }
    s += ");\n";
    // Every cell type's faces for the tables' compute pass, the type told by its vertex count
    // (4 tetrahedron, 5 pyramid, 6 wedge, 8 hexahedron): faces [kCellFaceFirst[t],
    // kCellFaceFirst[t] + kCellFaceCount[t]) of kCellFaces, a triangle's fourth vertex −1.
    {
        std::string first = "const int kCellFaceFirst[4] = int[4](", count = "const int kCellFaceCount[4] = int[4](";
        std::string faces_glsl, quads_glsl;
        int total = 0, t = 0;
        for (CellType type : {CellType::Tetra, CellType::Pyramid, CellType::Wedge, CellType::Hexahedron}) {
            first += (t ? ", " : "") + std::to_string(total);
            count += (t ? ", " : "") + std::to_string(cell_face_count(type));
            int quads = 0;
            for (int f = 0; f < cell_face_count(type); ++f, ++total) {
                const CellFace& face = cell_faces(type)[f];
                faces_glsl += std::string(total ? ", " : "") + "ivec4(" + std::to_string(face.v[0]) + ", " +
                              std::to_string(face.v[1]) + ", " + std::to_string(face.v[2]) + ", " +
                              std::to_string(face.count == 4 ? int(face.v[3]) : -1) + ")";
                quads_glsl += std::string(total ? ", " : "") + std::to_string(face.count == 4 ? quads++ : -1);
            }
            ++t;
        }
        s += first + ");\n" + count + ");\n";
        s += "const ivec4 kCellFaces[" + std::to_string(total) + "] = ivec4[" + std::to_string(total) + "](" + faces_glsl + ");\n";
        s += "const int kFaceQuad[" + std::to_string(total) + "] = int[" + std::to_string(total) + "](" + quads_glsl + ");\n";
        s += "int cell_type_of(uint vertices) { return vertices == 4u ? 0 : vertices == 5u ? 1 : vertices == 6u ? 2 : 3; }\n";
        // A cell's type from its triangle count (4, 6, 8, 12: all differ).
        s += "int cell_type_of_triangles(int triangles) { return triangles == 4 ? 0 : triangles == 6 ? 1 : triangles == 8 ? 2 : 3; }\n";
    }
    // Quad halves by cell type, told apart by their triangle counts (4, 6, 8, 12: all differ).
    s += "bool quad_half(int triangles, int k) {\n";
    for (CellType type : {CellType::Tetra, CellType::Pyramid, CellType::Wedge, CellType::Hexahedron}) {
        std::uint32_t mask = 0;
        int n = 0;
        for (int f = 0; f < cell_face_count(type); ++f) {
            const int halves = cell_faces(type)[f].count == 4 ? 2 : 1;
            if (halves == 2) {
                if (n % 2) throw Error("projector interface: a quad's halves must start at an even triangle");
                mask |= 3u << n;
            }
            n += halves;
        }
        s += "    if (triangles == " + std::to_string(n) + ") return ((" + std::to_string(mask) + "u >> uint(k)) & 1u) != 0u;\n";
    }
    s += "    return false;\n}\n";
    return s;
}

const gl::ShaderLibrary& projector_shader_library() {
    static const gl::ShaderLibrary library = [] {
        gl::ShaderLibrary lib = gl::ShaderLibrary::builtin();
        lib.add("projector_interface.glsl", projector_interface_glsl(),
                "projector_interface.glsl (generated by fx/src/projector/gl_interface.cpp)");
        return lib;
    }();
    return library;
}

} // namespace cellfx::fx
