// fx::CellRenderer with a scene depth buffer (CellRenderOptions::scene_depth): the volume stops
// at the scene's surfaces. A box of constant fog in front of a depth image made of three
// regions — a surface cutting through the box, one in front of it, none (far plane) — against
// the closed form: optical depth σ·(length of the ray inside the box and in front of the surface).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "fx/cell_renderer.hpp"
#include "gl/render_target.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "scanline_test_support.hpp"
#include "cellfx_names.hpp"

namespace {

constexpr int kSize = 64;
constexpr double kSigma = 0.5; // emission ≤ 0.9·0.5·1.3 < 1: within classic pcp's 8-bit range
const glm::dvec3 kColor{0.9, 0.8, 0.6};

fx::Camera box_camera() {
    fx::Camera cam;
    cam.eye = {0.5, -1.6, 1.9};
    cam.target = {0.5, 0.5, 0.45};
    cam.up = {0, 0, 1};
    cam.fov_y_degrees = 45.0;
    cam.near_distance = 0.1;
    cam.far_distance = 50.0;
    return cam;
}

// View depth of the scene surface per pixel: left third cuts the box, top right is in front of
// it, the rest is empty (window depth 1: the far plane).
double scene_view_depth(const fx::Camera& cam, int x, int y) {
    const double box_mid = glm::dot(glm::dvec3(0.5, 0.5, 0.5) - cam.eye, cam.forward());
    if (x < kSize / 3) return box_mid;
    if (y > kSize / 2) return 0.6 * box_mid - 0.4 * 0.3; // well in front of the box
    return cam.far_distance;
}

// GL window depth for a view depth z (the inverse of project.glsl's conversion).
float window_depth(const fx::Camera& cam, double z) {
    const double n = cam.near_distance, f = cam.far_distance;
    return float(f * (z - n) / (z * (f - n)));
}

fx::Image expected(const fx::Camera& cam, bool fog, bool mip) {
    return scanline_test::expected_image(kSize, kSize, [&](int x, int y) {
        const fx::Ray ray = cam.pixel_ray(x + 0.5, y + 0.5, kSize, kSize);
        auto [t0, t1] = scanline_test::ray_box(ray, glm::dvec3(0.0), glm::dvec3(1.0));
        t0 = std::max(t0, scanline_test::near_t(cam, ray));
        const double t_scene = scene_view_depth(cam, x, y) / glm::dot(ray.direction, cam.forward());
        const double len = std::max(0.0, std::min(t1, t_scene) - t0);
        if (mip) return len > 0.0 ? glm::vec4(glm::vec3(kColor * kSigma), 0.0f) : glm::vec4(0.0f);
        if (!fog) return glm::vec4(glm::vec3(kColor * kSigma * len), 0.0f);
        const double a = 1.0 - std::exp(-kSigma * len);
        return glm::vec4(glm::vec3(kColor * a), float(a));
    });
}

} // namespace

TEST_CASE("Scene depth stops the volume at the scene's surfaces", "[gl][terrain][scene_depth]") {
    fx_test::gl_context();
    fx::CellMesh box = fx_test::hex_box(3, 3, 3);
    box.scalars.push_back({"s", std::vector<float>(box.point_count(), 0.0f)});
    const fx::Camera cam = box_camera();

    // The scene's depth image, uploaded into a depth texture.
    fx::gl::RenderTarget scene = fx::gl::RenderTarget::create(kSize, kSize, fx::gl::ColorFormat::RGBA8, true);
    std::vector<float> depth(kSize * kSize);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) depth[y * kSize + x] = window_depth(cam, scene_view_depth(cam, x, y));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(scene.depth_texture(), 0, 0, 0, kSize, kSize, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    fx_test::require_no_gl_error();

    fx::CellRenderer renderer(box, "s", fx::TransferFunction::constant(kColor, kSigma));
    struct Case {
        const char* name;
        fx::RenderPath path;
        bool fog;
        float tolerance; // per pixel
        double bad;      // fraction of pixels allowed beyond it
    };
    // pcp-exact: exact integrals in float (1e-4 of a value ≤ 1), pixel centres within rounding of
    // the box's silhouette (≤ 3% of pixels, the outline is ~90 pixels long).
    // mip: constant emission wherever any face is in front of the surface: exact, silhouettes only.
    // pcp: 8-bit: ≤ 4 cells on a ray, each rounded to 1/255 in light and α (≈ 4·1.5/255 = 0.024
    // at worst; 0.02 holds for all but the silhouettes).
    const Case cases[] = {
        {"scene_depth_exact_fog", fx::RenderPath::PcpExact, true, 1e-4f, 0.03},
        {"scene_depth_exact", fx::RenderPath::PcpExact, false, 1e-4f, 0.03},
        {"scene_depth_mip", fx::RenderPath::Mip, false, 1e-3f, 0.03},
        {"scene_depth_pcp", fx::RenderPath::Pcp, false, 0.02f, 0.03},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        fx::CellRenderOptions options;
        options.fog = c.fog;
        options.scene_depth = scene.depth_texture();
        GLint bound_before = -1;
        glActiveTexture(GL_TEXTURE3);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound_before);
        glActiveTexture(GL_TEXTURE0);
        const fx::Image actual = renderer.render_to_image(cam, kSize, kSize, c.path, options);
        fx_test::require_no_gl_error();
        GLint bound_after = -1;
        glActiveTexture(GL_TEXTURE3);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound_after);
        glActiveTexture(GL_TEXTURE0);
        CHECK(bound_after == bound_before); // state restored
        const fx::Image want = expected(cam, c.fog, c.path == fx::RenderPath::Mip);
        std::size_t lit = 0, hidden = 0;
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                if (want.at(x, y).r > 0.05f) ++lit;
                if (x >= kSize / 3 && y > kSize / 2 + 2 && actual.at(x, y).r == 0.0f) ++hidden;
            }
        }
        CHECK(lit > kSize * kSize / 8); // the box is in view, partly cut
        CHECK(hidden > 200);            // the surface in front hides it completely there
        verify::Tolerance t;
        t.pixel.absolute = c.tolerance, t.mean.absolute = c.tolerance, t.share_beyond = c.bad;
        t.why = "closed form to the scene depth (bounds above)";
        fx_test::check_frame(c.name, actual, want, t);
    }
}

TEST_CASE("Without scene depth nothing changes", "[gl][terrain][scene_depth]") {
    fx_test::gl_context();
    fx::CellMesh box = fx_test::hex_box(2, 2, 2);
    box.scalars.push_back({"s", std::vector<float>(box.point_count(), 0.0f)});
    fx::CellRenderer renderer(box, "s", fx::TransferFunction::constant(kColor, kSigma));
    const fx::Camera cam = box_camera();
    fx::gl::RenderTarget far = fx::gl::RenderTarget::create(kSize, kSize, fx::gl::ColorFormat::RGBA8, true);
    far.clear(glm::vec4(0.0f), 1.0f);
    for (fx::RenderPath path : fx::kRenderPaths) {
        fx::CellRenderOptions with;
        with.scene_depth = far.depth_texture();
        const fx::Image a = renderer.render_to_image(cam, kSize, kSize, path, {});
        const fx::Image b = renderer.render_to_image(cam, kSize, kSize, path, with);
        // An empty scene (depth 1) is the far plane, beyond the box.
        fx_test::check_image(std::string("no_scene_depth_") + fx::render_path_name(path), b, a,
                             verify::same_picture(1e-6, "the far plane lies beyond the box: the same segments"));
    }
}

TEST_CASE("set_mesh replaces the mesh and keeps the transfer function", "[gl][terrain][scene_depth]") {
    fx_test::gl_context();
    fx::CellMesh a = fx_test::hex_box(2, 2, 2);
    a.scalars.push_back({"s", std::vector<float>(a.point_count(), 0.0f)});
    fx::CellMesh b = fx_test::hex_box(3, 2, 1, glm::dvec3(0.2, 0.1, 0.0), glm::dvec3(0.9, 1.0, 0.7));
    std::vector<float> ramp;
    for (const glm::dvec3& p : b.points) ramp.push_back(float(10.0 * p.x));
    b.scalars.push_back({"s", ramp});
    // Normalized: its range follows the field, so the new mesh must rescale it.
    const fx::TransferFunction tf({{0.0, {1, 0, 0}, 0.5}, {1.0, {0, 1, 1}, 2.0}}, /*normalized=*/true);
    const fx::Camera cam = box_camera();
    fx::CellRenderer reused(a, "s", tf);
    reused.render_to_image(cam, kSize, kSize, fx::RenderPath::PcpExact);
    reused.set_mesh(b, "s");
    CHECK(reused.cell_count() == b.cell_count());
    fx::CellRenderer fresh(b, "s", tf);
    for (fx::RenderPath path : fx::kRenderPaths) {
        fx_test::check_image(std::string("set_mesh_") + fx::render_path_name(path),
                             reused.render_to_image(cam, kSize, kSize, path), fresh.render_to_image(cam, kSize, kSize, path),
                             verify::same_picture(0.0, "the same mesh and transfer function: the same bits"));
    }
    CHECK_THROWS_WITH(reused.set_mesh(b, "missing"), Catch::Contains("missing"));
}
