// The GL projector as a layer: one interface table shared by C++ and GLSL, and programs linked
// once per GL context and shared by every renderer in it.
#include <catch2/catch.hpp>

#include <string>

#include "fx/cell_renderer.hpp"
#include "harness/headless_context.hpp"
#include "gl/program_cache.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "projector/gl_interface.hpp"
#include "projector_meshes.hpp"
#include "cellfx_names.hpp"

namespace {

fx::TransferFunction glow() {
    return fx::TransferFunction({{0.0, {0.2, 0.4, 1.0}, 0.5}, {1.0, {1.0, 0.6, 0.2}, 2.0}}, /*normalized=*/true);
}

// One frame of every path (each pass links its programs on first use).
void render_every_path(fx::CellRenderer& renderer, const fx::Camera& camera) {
    for (fx::RenderPath path : fx::kRenderPaths) {
        INFO(fx::render_path_name(path));
        renderer.render_to_image(camera, 16, 16, path);
    }
}

} // namespace

TEST_CASE("the projector interface reaches GLSL as one generated table", "[projector]") {
    const std::string glsl = fx::projector_interface_glsl();
    // Every entry, by name and number, once.
#define FX_CHECK_ENTRY(name, glsl_name, value) \
    CHECK(glsl.find("#define " #glsl_name " " + std::to_string(fx::name) + "\n") != std::string::npos);
    FX_PROJECTOR_INTERFACE(FX_CHECK_ENTRY)
#undef FX_CHECK_ENTRY
    // The tetrahedron's faces come from the C++ table, not a copy.
    const fx::CellFace* f = fx::cell_faces(fx::CellType::Tetra);
    CHECK(glsl.find("ivec3(" + std::to_string(f[3].v[0]) + ", " + std::to_string(f[3].v[1]) + ", " +
                    std::to_string(f[3].v[2]) + "))") != std::string::npos);
    CHECK(fx::projector_shader_library().contains("projector_interface.glsl"));
}

TEST_CASE("GL programs are linked once per context and shared by every renderer in it", "[gl][projector]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = fx_test::one_of_each_cell();
    const fx::Bounds b = fx::mesh_bounds(mesh);
    const fx::Camera camera = fx::Camera::framing(b.lo, b.hi);
    fx::CellRenderer first(mesh, "s", glow());
    render_every_path(first, camera);
    const std::size_t linked = fx::gl::ProgramCache::programs_linked();
    CHECK(fx::gl::ProgramCache::for_current_context()->program_count() >= 5);
    {
        // Many effects of one kind (a scene full of laser beams) add no program.
        std::vector<fx::CellRenderer> more;
        for (int i = 0; i < 50; ++i) more.emplace_back(mesh, "s", glow());
        for (fx::CellRenderer& r : more) render_every_path(r, camera);
        CHECK(fx::gl::ProgramCache::programs_linked() == linked);
    }
    std::size_t after_other = 0;
    {
        // Another context that shares nothing gets programs of its own.
        fx::HeadlessContext other;
        fx::CellRenderer there(mesh, "s", glow());
        render_every_path(there, camera);
        after_other = fx::gl::ProgramCache::programs_linked();
        CHECK(after_other > linked);
        fx::CellRenderer again(mesh, "s", glow());
        render_every_path(again, camera);
        CHECK(fx::gl::ProgramCache::programs_linked() == after_other);
    }
    // Back in the first context, its own cache is found again.
    fx_test::gl_context();
    fx::CellRenderer back(mesh, "s", glow());
    render_every_path(back, camera);
    CHECK(fx::gl::ProgramCache::programs_linked() == after_other);
    fx_test::require_no_gl_error();
}
