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

#include <cstdint>
#include <string>

#include "gl/shader_library.hpp"

namespace cellfx::fx {

// X(c++ name, GLSL name, value). Uniform locations (kUniform..., an array's elements included)
// are unique across all programs that include this table — the projector's and the medium's —
// so that one program may use any set of them (gl_interface.cpp checks at compile time).
#define FX_PROJECTOR_INTERFACE(X)                                                                  \
    /* shader storage buffers */                                                                   \
    X(kBindingFrame, BINDING_FRAME, 3)          /* per-frame data: near-plane cap triangles */     \
    /* the tables' compute pass (projector_tables.comp) */                                        \
    X(kBindingPlanesOut, BINDING_PLANES_OUT, 4)                                                    \
    X(kBindingScalarFunctionsOut, BINDING_SCALAR_FUNCTIONS_OUT, 5)                                 \
    X(kBindingBarycentricsOut, BINDING_BARYCENTRICS_OUT, 6)                                        \
    X(kBindingElementsOut, BINDING_ELEMENTS_OUT, 7)                                                \
    X(kBindingPointStamps, BINDING_POINT_STAMPS, 8) /* per point: the update that last changed it */ \
    X(kBindingCellStamps, BINDING_CELL_STAMPS, 9)   /* per cell: the same for its connectivity */ \
    X(kBindingCellWordsOut, BINDING_CELL_WORDS_OUT, 10) /* per cell: its word, planar bit set */   \
    X(kBindingFoldBasesOut, BINDING_FOLD_BASES_OUT, 11) /* per cell: its first row pair */        \
    /* texture units (within those gl::StateGuard saves) */                                        \
    X(kUnitTables, UNIT_TABLES, 0)              /* transfer-function tables */                     \
    X(kUnitAccumulation, UNIT_ACCUMULATION, 0)  /* resolve: the pass's target */                   \
    X(kUnitOpacity, UNIT_OPACITY, 1)            /* classic absorption: 1 − exp(−u·v) */            \
    X(kUnitPreintegration, UNIT_PREINTEGRATION, 2) /* exact absorption: (s_f, s_b, l) table */     \
    X(kUnitSceneDepth, UNIT_SCENE_DEPTH, 3)     /* CellRenderOptions::scene_depth */               \
    X(kUnitPoints, UNIT_POINTS, 4)              /* vec4 per point: position, scalar */             \
    X(kUnitConnectivity, UNIT_CONNECTIVITY, 5)  /* the cells' point ids */                         \
    X(kUnitCellOffsets, UNIT_CELL_OFFSETS, 6)   /* per cell: its first point id's index */         \
    X(kUnitCellWords, UNIT_CELL_WORDS, 7)       /* per cell: its word (below) */                   \
    X(kUnitPlanes, UNIT_PLANES, 8)              /* per face triangle: outward plane */             \
    X(kUnitScalarFunctions, UNIT_SCALAR_FUNCTIONS, 9) /* per face triangle: s(q) = g·q + s0 */     \
    X(kUnitBarycentrics, UNIT_BARYCENTRICS, 10) /* per face triangle: 2 rows, q → (b1, b2) */      \
    X(kUnitCellList, UNIT_CELL_LIST, 11)        /* a frame's list: slot → cell */                  \
    X(kUnitSlotData, UNIT_SLOT_DATA, 12)        /* a frame's list: per slot (d_min, Δd) */         \
    X(kUnitPiecePoints, UNIT_PIECE_POINTS, 13)  /* a frame's tetrahedra: 4 point ids each */       \
    X(kUnitUniqueFaces, UNIT_UNIQUE_FACES, 14)  /* mip: each face once, 3 point ids */             \
    X(kUnitFoldBases, UNIT_FOLD_BASES, 15)      /* per cell: its first barycentric row pair */     \
    X(kUnitCount, UNIT_COUNT, 16)               /* (units in use) */                               \
    /* uniform locations */                                                                        \
    X(kUniformViewProjection, UNIFORM_VIEW_PROJECTION, 0)                                          \
    X(kUniformEye, UNIFORM_EYE, 1)                                                                 \
    X(kUniformForward, UNIFORM_FORWARD, 2)                                                         \
    X(kUniformNear, UNIFORM_NEAR, 3)                                                               \
    X(kUniformOrthographic, UNIFORM_ORTHOGRAPHIC, 4)                                               \
    X(kUniformTable, UNIFORM_TABLE, 5)                                                             \
    X(kUniformPass, UNIFORM_PASS, 8)                                                               \
    X(kUniformPreintegration, UNIFORM_PREINTEGRATION, 10)                                          \
    X(kUniformPreintegrationSize, UNIFORM_PREINTEGRATION_SIZE, 11)                                 \
    X(kUniformOpacitySize, UNIFORM_OPACITY_SIZE, 12)                                               \
    X(kUniformPieceBase, UNIFORM_PIECE_BASE, 13) /* first triangle of a frame's tetrahedra */     \
    X(kUniformMaxOpticalDepth, UNIFORM_MAX_OPTICAL_DEPTH, 14) /* pcp-exact: a cell's depth cap */ \
    X(kUniformRasterDepthRange, UNIFORM_RASTER_DEPTH_RANGE, 15) /* orthographic: window z's n, f */ \
    X(kUniformSceneDepthMode, UNIFORM_SCENE_DEPTH_MODE, 20)                                        \
    X(kUniformSceneDepthRange, UNIFORM_SCENE_DEPTH_RANGE, 21)                                      \
    X(kUniformSceneOrigin, UNIFORM_SCENE_ORIGIN, 22)                                               \
    X(kUniformResolveOrigin, UNIFORM_RESOLVE_ORIGIN, 30)                                           \
    X(kUniformRayOrigin, UNIFORM_RAY_ORIGIN, 40)       /* ray of window pixel c + (x, y): */       \
    X(kUniformRayOriginDx, UNIFORM_RAY_ORIGIN_DX, 41)  /* origin o + x·o_dx + y·o_dy, direction */ \
    X(kUniformRayOriginDy, UNIFORM_RAY_ORIGIN_DY, 42)  /* normalize(d + x·d_dx + y·d_dy), */       \
    X(kUniformRayDirection, UNIFORM_RAY_DIRECTION, 43) /* relative frame */                        \
    X(kUniformRayDirectionDx, UNIFORM_RAY_DIRECTION_DX, 44)                                        \
    X(kUniformRayDirectionDy, UNIFORM_RAY_DIRECTION_DY, 45)                                        \
    X(kUniformRayCentre, UNIFORM_RAY_CENTRE, 46)       /* c: the pixel whose ray is the view axis */ \
    /* the tables' compute pass */                                                                 \
    X(kUniformTableCells, UNIFORM_TABLE_CELLS, 50)     /* cells in the mesh */                     \
    X(kUniformTableBuilt, UNIFORM_TABLE_BUILT, 51)     /* stamp the tables were last built at */   \
    X(kUniformTableAll, UNIFORM_TABLE_ALL, 52)         /* 1: every cell's tables */                \
    X(kUniformTableElements, UNIFORM_TABLE_ELEMENTS, 53) /* 1: every cell's element triangles */   \
    X(kUniformTableCull, UNIFORM_TABLE_CULL, 54)       /* 1: cells outside the planes collapse */  \
    X(kUniformTableCullPlanes, UNIFORM_TABLE_CULL_PLANES, 55) /* 5 planes (55–59), relative frame */ \
    X(kUniformTablePlanarTolerance, UNIFORM_TABLE_PLANAR_TOLERANCE, 60) /* double: kPlanarTolerance */ \
    X(kUniformTableLayout, UNIFORM_TABLE_LAYOUT, 61)   /* the rows' layout and the pass's part: */ \
    X(kTableLayoutFull, TABLE_LAYOUT_FULL, 0)          /*   rows per slot, planar bits decided */ \
    X(kTableLayoutDecide, TABLE_LAYOUT_DECIDE, 1)      /*   compact: bits decided, no rows */     \
    X(kTableLayoutKept, TABLE_LAYOUT_KEPT, 2)          /*   compact: bits kept, rows written */   \
    X(kTableLayoutRowsOnly, TABLE_LAYOUT_ROWS_ONLY, 3) /*   compact: bits kept, rows alone */     \
    /* the one medium (fx/internal/medium): its sizes, then its uniforms, clear of the above so */ \
    /* that its append and emission passes, which are projector programs too, may use both. */    \
    /* An array uniform takes as many locations as it has elements (static_asserts below). */    \
    X(kMediumVolumes, MEDIUM_VOLUMES, 32)           /* MediumCompositor::kMaxVolumes */            \
    X(kMediumPointLights, MEDIUM_POINT_LIGHTS, 8)   /* point lights the medium lights */           \
    /* the exact compositor (medium_lists.glsl, medium_append.frag, medium_resolve.frag) */       \
    X(kUniformMediumRegion, UNIFORM_MEDIUM_REGION, 100) /* ivec4: x, y, width, height */          \
    X(kUniformMediumVolume, UNIFORM_MEDIUM_VOLUME, 101)                                            \
    X(kUniformMediumCapacity, UNIFORM_MEDIUM_CAPACITY, 102)                                        \
    X(kUniformMediumBulk, UNIFORM_MEDIUM_BULK, 103)                                                \
    X(kUniformMediumMaskMode, UNIFORM_MEDIUM_MASK_MODE, 104)                                       \
    X(kUniformMediumForward, UNIFORM_MEDIUM_FORWARD, 105)                                          \
    X(kUniformMediumRight, UNIFORM_MEDIUM_RIGHT, 106)                                              \
    X(kUniformMediumUp, UNIFORM_MEDIUM_UP, 107)                                                    \
    X(kUniformMediumOrtho, UNIFORM_MEDIUM_ORTHO, 108)                                              \
    X(kUniformMediumViewport, UNIFORM_MEDIUM_VIEWPORT, 109)                                        \
    X(kUniformMediumTable, UNIFORM_MEDIUM_TABLE, 110)            /* [MEDIUM_VOLUMES] */            \
    X(kUniformMediumMedium, UNIFORM_MEDIUM_MEDIUM, 142)          /* [MEDIUM_VOLUMES] */            \
    X(kUniformMediumBeamOrigin, UNIFORM_MEDIUM_BEAM_ORIGIN, 174) /* [MEDIUM_VOLUMES] */            \
    X(kUniformMediumBeamAxis, UNIFORM_MEDIUM_BEAM_AXIS, 206)     /* [MEDIUM_VOLUMES] */            \
    X(kUniformMediumBeamColor, UNIFORM_MEDIUM_BEAM_COLOR, 238)   /* [MEDIUM_VOLUMES] */            \
    /* the medium's point lights (medium_lights.glsl: the resolve, the froxel grid's passes) */  \
    X(kUniformPointCount, UNIFORM_POINT_COUNT, 270)                                                \
    X(kUniformPointPosition, UNIFORM_POINT_POSITION, 271) /* [MEDIUM_POINT_LIGHTS] */              \
    X(kUniformPointColor, UNIFORM_POINT_COLOR, 279)       /* [MEDIUM_POINT_LIGHTS] */              \
    X(kUniformPointG, UNIFORM_POINT_G, 287)               /* [MEDIUM_POINT_LIGHTS] */              \
    /* the froxel grid (froxel_grid.glsl, froxel_inject.frag, froxel_integrate.comp, */           \
    /* froxel_emission.frag, froxel_apply.frag) */                                                \
    X(kUniformFroxelGrid, UNIFORM_FROXEL_GRID, 300)         /* tiles across, up, slices */         \
    X(kUniformFroxelSlicing, UNIFORM_FROXEL_SLICING, 301)   /* z_near, slice step */               \
    X(kUniformFroxelAlbedo, UNIFORM_FROXEL_ALBEDO, 302)                                            \
    X(kUniformFroxelViewport, UNIFORM_FROXEL_VIEWPORT, 303)                                        \
    X(kUniformFroxelBeam, UNIFORM_FROXEL_BEAM, 304)                                                \
    X(kUniformFroxelBeamOrigin, UNIFORM_FROXEL_BEAM_ORIGIN, 305)                                   \
    X(kUniformFroxelBeamAxis, UNIFORM_FROXEL_BEAM_AXIS, 306)                                       \
    X(kUniformFroxelBeamColor, UNIFORM_FROXEL_BEAM_COLOR, 307)                                     \
    X(kUniformFroxelRayOrigin, UNIFORM_FROXEL_RAY_ORIGIN, 310)     /* a tile's centre ray: */      \
    X(kUniformFroxelRayOriginX, UNIFORM_FROXEL_RAY_ORIGIN_X, 311)  /* origin and its steps, */     \
    X(kUniformFroxelRayOriginY, UNIFORM_FROXEL_RAY_ORIGIN_Y, 312)  /* direction and its steps */   \
    X(kUniformFroxelRayDirection, UNIFORM_FROXEL_RAY_DIRECTION, 313) /* (fx::MediumGridRays) */    \
    X(kUniformFroxelRayDirectionX, UNIFORM_FROXEL_RAY_DIRECTION_X, 314)                            \
    X(kUniformFroxelRayDirectionY, UNIFORM_FROXEL_RAY_DIRECTION_Y, 315)                            \
    X(kUniformFroxelViewForward, UNIFORM_FROXEL_VIEW_FORWARD, 316)                                 \
    X(kUniformFroxelOrtho, UNIFORM_FROXEL_ORTHO, 317)                                              \
    X(kUniformFroxelApplyViewport, UNIFORM_FROXEL_APPLY_VIEWPORT, 320)                             \
    X(kUniformFroxelApplyDepthOrigin, UNIFORM_FROXEL_APPLY_DEPTH_ORIGIN, 321)                      \
    X(kUniformFroxelApplyDepth, UNIFORM_FROXEL_APPLY_DEPTH, 322) /* near, far, depth model */      \
    /* a cell's word: (its first triangle << WORD_FIRST_SHIFT) | (planar << WORD_PLANAR_BIT) |  */ \
    /* (its triangle count − 1); planar: its tables are its faces' planes (projector_tables.comp) */ \
    X(kWordCountBits, WORD_COUNT_BITS, 4)                                                          \
    X(kWordPlanarBit, WORD_PLANAR_BIT, 4)                                                          \
    X(kWordFirstShift, WORD_FIRST_SHIFT, 5)                                                        \
    /* a cell list entry with this bit set names a tetrahedron of the frame (upload_pieces) */     \
    X(kPieceBitIndex, PIECE_BIT_INDEX, 31)

#define FX_INTERFACE_ENUMERATOR(name, glsl, value) name = value,
enum ProjectorInterface : int { FX_PROJECTOR_INTERFACE(FX_INTERFACE_ENUMERATOR) };
#undef FX_INTERFACE_ENUMERATOR

constexpr std::uint32_t kPieceBit = 1u << kPieceBitIndex;

// A cell's word (see WORD_FIRST_SHIFT): where its triangles' data start, how many there are,
// and whether it is planar (decided by the tables' pass: cell_word leaves it 0).
constexpr std::uint32_t kMaxWordTriangle = (1u << (32 - kWordFirstShift)) - 1;
constexpr std::uint32_t kWordPlanar = 1u << kWordPlanarBit;
inline std::uint32_t cell_word(std::uint32_t first_triangle, std::uint32_t triangles, bool planar = false) {
    return (first_triangle << kWordFirstShift) | (planar ? kWordPlanar : 0u) | (triangles - 1);
}

// A cell is planar — its fragments clip their ray by its faces' planes instead of searching
// its triangles (shaders/cell_segment.glsl) — when it is convex with flat faces within this
// fraction of its size (the diagonal L of its box): every face has an area, each of its vertices
// lies within kPlanarTolerance·L of the face's plane (a quad's: normal along the cross product
// of its diagonals, through the mean of its corners) and every other vertex of the cell at most
// that far outside it. Such a cell's planes then stand within kPlanarTolerance·L of its
// triangles (which the scan-line reference draws): a ray's segment gains or loses at most
// kPlanarTolerance·L/|cos θ| where it crosses a face (θ from the face's normal), and two planar
// cells that share a face share its plane, so nothing is lost or counted twice between them.
// 1e-3: most curvilinear hexahedra pass (the combustor 90%, the curved duct 100%; 28% and 37%
// at 1e-4), regular grids and terrain prisms exactly. (GlProjector::set_planar_tolerance
// changes it for tests; a negative one makes no cell planar.)
constexpr double kPlanarTolerance = 1e-3;

static_assert(kWordCountBits == kWordPlanarBit && kWordPlanarBit + 1 == kWordFirstShift, "the word's fields in order");

// The text of "projector_interface.glsl": every entry above as a #define, plus kTetraFaces (the
// faces of a tetrahedron, outward, from cell_faces(CellType::Tetra)), every type's faces
// (kCellFaces, kCellFaceFirst, kCellFaceCount, kFaceQuad: a face's index among its cell's quads,
// −1 for a triangle), and quad_half(triangles, k): whether
// triangle k of a cell with that many triangles is half of a quad face (the halves of a quad are
// triangles 2j and 2j + 1), from the same tables.
std::string projector_interface_glsl();

// The built-in shaders plus the generated "projector_interface.glsl" (made once).
const gl::ShaderLibrary& projector_shader_library();

} // namespace cellfx::fx
