// A steady frame allocates nothing: every render path, on a mesh of tetrahedra and on one of
// mixed cells, from outside and from inside the mesh (near-plane caps), with and without a
// scene depth. Global operator new is replaced in this executable (and only here) by one that
// counts while a frame is being counted; each case renders its views twice to warm up (buffers
// grow to their sizes, programs link, the sort builds its state), then renders them again and
// expects no allocation on any thread (cellfx's pool included). Mesa's own memory is C's
// malloc, which is not counted: the point is cellfx's.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "fx/cell_renderer.hpp"
#include "mesh/tetrahedralize.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "cellfx_names.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<std::size_t> allocations{0};
} // namespace

void* operator new(std::size_t size) {
    if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(size ? size : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace {

fx::TransferFunction glow() {
    return fx::TransferFunction({{0.0, {0.2, 0.4, 1.0}, 0.5}, {0.5, {0.3, 0.9, 0.4}, 1.0}, {1.0, {1.0, 0.6, 0.2}, 2.0}},
                                /*normalized=*/true);
}

// Frames of every view; returns the allocations of the last round (rounds 1–2 warm up).
std::size_t allocations_of_steady_frames(fx::CellRenderer& renderer, const std::vector<fx::Camera>& views,
                                         fx::RenderPath path, const fx::CellRenderOptions& options) {
    const fx::gl::RenderTarget target = fx::gl::RenderTarget::create(48, 40, fx::gl::ColorFormat::RGBA8, false);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer());
    std::size_t counted = 0;
    for (int round = 0; round < 3; ++round) {
        for (const fx::Camera& camera : views) {
            allocations = 0;
            counting = round == 2;
            renderer.render(camera, {0, 0, 48, 40}, path, options);
            counting = false;
            counted += round == 2 ? allocations.load() : 0;
        }
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    return counted;
}

} // namespace

TEST_CASE("a steady frame of every path allocates nothing", "[gl][allocation]") {
    fx_test::gl_context();
    const fx::CellMesh mixed = fx_test::mixed_box_with_tets(4);
    const fx::CellMesh tets = fx::tetrahedralize(fx_test::hex_box(4, 4, 4));
    fx::Camera outside = fx::Camera::framing(glm::dvec3(0.0), glm::dvec3(1.0));
    fx::Camera moved = outside;
    moved.eye += glm::dvec3(0.3, -0.2, 0.1);
    fx::Camera inside;
    inside.eye = {0.5, 0.45, 0.55}, inside.target = {1.5, 1.2, 0.9}, inside.up = {0, 0, 1}, inside.near_distance = 0.05;
    // A scene depth: a depth texture cleared to a plane part way into the mesh.
    fx::gl::Texture depth = fx::gl::make_texture_2d(GL_DEPTH_COMPONENT32F, 48, 40);
    const float half = 0.995f;
    glClearTexImage(depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &half);

    for (const fx::CellMesh* mesh : {&tets, &mixed}) {
        const char* mesh_name = mesh == &tets ? "tetrahedra" : "mixed cells";
        fx::CellRenderer renderer(*mesh, "", glow());
        for (fx::RenderPath path : fx::kRenderPaths)
            for (unsigned int scene_depth : {0u, depth.id()}) {
                fx::CellRenderOptions options;
                options.scene_depth = scene_depth;
                options.fog = path == fx::RenderPath::PcpExact;
                INFO(mesh_name << ", " << fx::render_path_name(path) << (scene_depth ? ", scene depth" : ""));
                CHECK(allocations_of_steady_frames(renderer, {outside, moved, inside}, path, options) == 0);
            }
    }
    fx_test::require_no_gl_error();
}
