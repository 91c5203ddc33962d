// cellfx — for passes that draw a CellRenderer's mesh with a program of their own (the medium
// compositor, medium/medium_compositor.hpp), sharing the renderer's GL projector: its uploaded
// mesh, tables, shared programs and uniforms.
#pragma once

#include "fx/cell_renderer.hpp"
#include "projector/gl_projector.hpp"

namespace cellfx::fx {

// The renderer's GL projector (through CellRenderer::impl(), whose type only cellfx's own
// sources see: no friend in the public header).
GlProjector& renderer_projector(CellRenderer& renderer);

} // namespace cellfx::fx
