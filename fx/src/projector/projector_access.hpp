// cellfx — for passes that draw a CellRenderer's mesh with a program of their own (the medium
// compositor, fx/medium_compositor.hpp), sharing the renderer's uploaded buffers and tables.
#pragma once

#include <epoxy/gl.h>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"

namespace fx {

struct ProjectorAccess {
    // Binds the renderer's mesh at storage bindings 0–2 (project.glsl), its tables on texture
    // unit 0 and `scene_depth` on unit 3, and sets project.glsl's view, table and scene-depth
    // uniforms and project.vert's source (the whole mesh) on `program` for `camera` (in the
    // mesh's frame) and `viewport`. Returns the vertex count of one draw of every triangle.
    // The caller holds a gl::StateGuard (units 0–3 and bindings 0–3 are among what it saves).
    static GLsizei bind(CellRenderer& renderer, GLuint program, const Camera& camera, const Viewport& viewport,
                        unsigned scene_depth);
};

} // namespace fx
