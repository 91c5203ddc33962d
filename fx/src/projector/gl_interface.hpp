// cellfx — the one table of binding points, texture units, uniform locations and shared
// constants between the GL projector's C++ side and its shaders.
//
// Every number is written once, in FX_PROJECTOR_INTERFACE below. C++ sees each entry as an
// enumerator (kBindingPoints, kUniformEye, ...); GLSL sees it as a #define of the same name in
// upper case (BINDING_POINTS, UNIFORM_EYE, ...) from the generated include
// "projector_interface.glsl", which also carries the cell tables the shaders need (the faces of
// a tetrahedron, from cell_faces() in fx/src/cell_mesh.cpp). Shaders write
//     #include "projector_interface.glsl"
//     layout(location = UNIFORM_EYE) uniform vec3 u_eye;
// and never a bare number. projector_shader_library() is the built-in library plus that file.
#pragma once

#include <string>

#include "gl/shader_library.hpp"

namespace fx {

// X(c++ name, GLSL name, value). Uniform locations are unique across all projector programs so
// that one program may use any set of them.
#define FX_PROJECTOR_INTERFACE(X)                                                                  \
    /* shader storage buffers */                                                                   \
    X(kBindingPoints, BINDING_POINTS, 0)       /* vec4: position (relative frame), scalar */       \
    X(kBindingTriangles, BINDING_TRIANGLES, 1) /* uvec4 point ids + cell, vec4 plane */            \
    X(kBindingCells, BINDING_CELLS, 2)         /* first triangle of each cell */                   \
    X(kBindingFrame, BINDING_FRAME, 3)         /* per-frame data of the pass drawing */            \
    /* texture units (within those gl::StateGuard saves) */                                        \
    X(kUnitTables, UNIT_TABLES, 0)                   /* transfer-function tables */                \
    X(kUnitAccumulation, UNIT_ACCUMULATION, 0)       /* resolve: the pass's target */              \
    X(kUnitOpacity, UNIT_OPACITY, 1)                 /* classic absorption: 1 − exp(−u·v) */       \
    X(kUnitPreintegration, UNIT_PREINTEGRATION, 2)   /* exact absorption: (s_f, s_b, l) table */   \
    X(kUnitSceneDepth, UNIT_SCENE_DEPTH, 3)          /* CellRenderOptions::scene_depth */          \
    /* uniform locations */                                                                        \
    X(kUniformViewProjection, UNIFORM_VIEW_PROJECTION, 0)                                          \
    X(kUniformEye, UNIFORM_EYE, 1)                                                                 \
    X(kUniformForward, UNIFORM_FORWARD, 2)                                                         \
    X(kUniformNear, UNIFORM_NEAR, 3)                                                               \
    X(kUniformOrthographic, UNIFORM_ORTHOGRAPHIC, 4)                                               \
    X(kUniformTable, UNIFORM_TABLE, 5)                                                             \
    X(kUniformSource, UNIFORM_SOURCE, 6)                                                           \
    X(kUniformCapBase, UNIFORM_CAP_BASE, 7)                                                        \
    X(kUniformPass, UNIFORM_PASS, 8)                                                               \
    X(kUniformSlotVertices, UNIFORM_SLOT_VERTICES, 9)                                              \
    X(kUniformPreintegration, UNIFORM_PREINTEGRATION, 10)                                          \
    X(kUniformPreintegrationSize, UNIFORM_PREINTEGRATION_SIZE, 11)                                 \
    X(kUniformOpacitySize, UNIFORM_OPACITY_SIZE, 12)                                               \
    X(kUniformSceneDepthMode, UNIFORM_SCENE_DEPTH_MODE, 20)                                        \
    X(kUniformSceneDepthRange, UNIFORM_SCENE_DEPTH_RANGE, 21)                                      \
    X(kUniformSceneOrigin, UNIFORM_SCENE_ORIGIN, 22)                                               \
    X(kUniformResolveOrigin, UNIFORM_RESOLVE_ORIGIN, 30)                                           \
    /* what project.vert draws (UNIFORM_SOURCE) */                                                 \
    X(kSourceMesh, SOURCE_MESH, 0)   /* every triangle of the mesh */                              \
    X(kSourceBatch, SOURCE_BATCH, 1) /* classic PCP: the frame's cell slots */                     \
    X(kSourceCaps, SOURCE_CAPS, 2)   /* near-plane cap triangles */                                \
    /* vertices per cell slot of a classic PCP batch: 3 per triangle of the largest cell */       \
    X(kSlotVertices, SLOT_VERTICES, 36)

#define FX_INTERFACE_ENUMERATOR(name, glsl, value) name = value,
enum ProjectorInterface : int { FX_PROJECTOR_INTERFACE(FX_INTERFACE_ENUMERATOR) };
#undef FX_INTERFACE_ENUMERATOR

// Marks a whole cell in the exact absorption path's item list (GLSL: kWholeCell).
constexpr unsigned kWholeCellItem = 0xFFFFFFFFu;

// The text of "projector_interface.glsl": every entry above as a #define, plus kWholeCell and
// kTetraFaces (the faces of a tetrahedron, outward, from cell_faces(CellType::Tetra)).
std::string projector_interface_glsl();

// The built-in shaders plus the generated "projector_interface.glsl" (made once).
const gl::ShaderLibrary& projector_shader_library();

} // namespace fx
