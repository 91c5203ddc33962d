// cellfx — for passes that draw a CellRenderer's mesh with a program of their own (the medium
// compositor, medium/medium_compositor.hpp), sharing the renderer's GL projector: its uploaded
// mesh, tables, shared programs and uniforms.
#pragma once

#include "fx/cell_renderer.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

struct ProjectorAccess {
    static GlProjector& projector(CellRenderer& renderer);
};

} // namespace cellfx::fx
