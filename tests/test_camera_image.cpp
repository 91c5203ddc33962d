#include <catch2/catch.hpp>

#include <cstdio>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "fx/image.hpp"
#include "fx/scanline_renderer.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "gl_fixture.hpp"
#include "mesh_builders.hpp"
#include "test_paths.hpp"
#include "cellfx_names.hpp"

TEST_CASE("camera spec parses every key and rejects bad ones", "[camera]") {
    const fx::Camera cam = fx::Camera::parse("eye=1,2,3,target=0,0,0,up=0,0,1,fov=30,near=0.5,far=100");
    CHECK(cam.eye == glm::dvec3(1, 2, 3));
    CHECK(cam.up == glm::dvec3(0, 0, 1));
    CHECK(cam.fov_y_degrees == 30.0);
    CHECK(cam.near_distance == 0.5);
    CHECK_FALSE(cam.orthographic());
    CHECK(fx::Camera::parse("ortho=4").ortho_height == 4.0);
    CHECK_THROWS_WITH(fx::Camera::parse("eye=1,2"), Catch::Contains("eye needs 3 numbers"));
    CHECK_THROWS_WITH(fx::Camera::parse("eye=1,2,x"), Catch::Contains("'x' is not a finite number"));
    CHECK_THROWS_WITH(fx::Camera::parse("zoom=2"), Catch::Contains("unknown key 'zoom'"));
    CHECK_THROWS_WITH(fx::Camera::parse("eye=0,0,0"), Catch::Contains("coincide"));
    CHECK_THROWS_AS(fx::Camera::parse("eye=nan,0,1"), fx::Error);
}

TEST_CASE("a camera that cannot take a picture is refused, naming why, and up of any length works", "[camera]") {
    const fx::Camera base = fx::Camera::parse("eye=3,-2,5,target=0,1,0,up=0,0,1,fov=50");
    CHECK_NOTHROW(base.validate("camera"));
    auto refused = [&](auto change, const std::string& what) {
        fx::Camera c = base;
        change(c);
        CHECK_THROWS_WITH(c.validate("test"), Catch::StartsWith("test: ") && Catch::Contains(what));
    };
    refused([](fx::Camera& c) { c.up = {0, 0, 0}; }, "up is zero");
    refused([](fx::Camera& c) { c.up = c.target - c.eye; }, "parallel to the view direction");
    refused([](fx::Camera& c) { c.up = 1e-300 * (c.target - c.eye); }, "parallel to the view direction");
    refused([](fx::Camera& c) { c.ortho_height = -5.0; }, "ortho height -5 must be positive");
    refused([](fx::Camera& c) { c.near_distance = 2e4; }, "not in front of far");
    refused([](fx::Camera& c) { c.fov_y_degrees = 180.0; }, "fov 180");
    refused([](fx::Camera& c) { c.eye.x = 1e19; }, "beyond");
    CHECK_THROWS_WITH(fx::Camera::parse("ortho=-5"), Catch::Contains("ortho=-5: the height must be positive"));
    // up is scaled before use: 1e-300 and 1e300 give the same rays as 1.
    for (const double scale : {1e-300, 1e300}) {
        fx::Camera c = base;
        c.up *= scale;
        CHECK_NOTHROW(c.validate("camera"));
        const fx::Ray a = c.pixel_ray(10.5, 3.5, 64, 48), b = base.pixel_ray(10.5, 3.5, 64, 48);
        CHECK(glm::length(a.direction - b.direction) < 1e-15);
        CHECK(c.view_matrix() == base.view_matrix());
    }
    // Framing is scale-free: a box of 1e-20 is seen like a box of 1.
    const fx::Camera tiny = fx::Camera::framing(glm::dvec3(0.0), glm::dvec3(1e-20));
    const fx::Camera unit = fx::Camera::framing(glm::dvec3(0.0), glm::dvec3(1.0));
    CHECK_NOTHROW(tiny.validate("camera"));
    CHECK(glm::length(tiny.eye - tiny.target) == Approx(1e-20 * glm::length(unit.eye - unit.target)));
    CHECK(tiny.near_distance == Approx(1e-20 * unit.near_distance));
}

TEST_CASE("pixel rays go through the pixel centres the projection matrix maps them to", "[camera]") {
    fx::Camera cam = fx::Camera::parse("eye=3,-2,5,target=0,1,0,up=0,0,1,fov=50");
    for (bool ortho : {false, true}) {
        if (ortho) cam.ortho_height = 3.0;
        const int w = 64, h = 48;
        const glm::dmat4 vp = cam.projection_matrix(double(w) / h) * cam.view_matrix();
        for (auto [px, py] : {std::pair{0.5, 0.5}, {63.5, 10.5}, {20.5, 47.5}}) {
            const fx::Ray ray = cam.pixel_ray(px, py, w, h);
            CHECK(glm::length(ray.direction) == Approx(1.0));
            const glm::dvec4 clip = vp * glm::dvec4(ray.origin + 2.0 * ray.direction, 1.0);
            CHECK((clip.x / clip.w + 1.0) * 0.5 * w == Approx(px).margin(1e-9));
            CHECK((clip.y / clip.w + 1.0) * 0.5 * h == Approx(py).margin(1e-9));
        }
    }
}

namespace {

// The projection of tile (i, j) of an n × n split of the image `full` projects: the same
// frustum, its NDC square [-1 + 2i/n, -1 + 2(i+1)/n] × ... stretched to [-1, 1]² (what VTK's
// tiled rendering and off-axis window centres give).
glm::dmat4 tile_projection(const glm::dmat4& full, int n, int i, int j) {
    glm::dmat4 t(1.0);
    t[0][0] = t[1][1] = n;
    t[3][0] = -(2.0 * i + 1.0 - n);
    t[3][1] = -(2.0 * j + 1.0 - n);
    return t * full;
}

} // namespace

TEST_CASE("a camera from a host's matrices describes the same view, off-axis ones included", "[camera]") {
    fx::Camera cam = fx::Camera::parse("eye=3,-2,5,target=0,1,0,up=0,0,1,fov=50,near=0.3,far=40");
    for (bool ortho : {false, true}) {
        if (ortho) cam.ortho_height = 3.0;
        const glm::dmat4 full = cam.projection_matrix(1.5);
        for (int tile : {-1, 3}) { // the whole view, then an off-axis quarter
            const glm::dmat4 p = tile < 0 ? full : tile_projection(full, 2, tile % 2, tile / 2);
            const fx::Camera c = fx::Camera::from_matrices(cam.view_matrix(), p);
            INFO((ortho ? "orthographic" : "perspective") << ", tile " << tile);
            CHECK(glm::length(c.eye - cam.eye) < 1e-12);
            CHECK(glm::length(c.forward() - cam.forward()) < 1e-12);
            CHECK(c.near_distance == Approx(0.3));
            CHECK(c.far_distance == Approx(40.0));
            CHECK(c.orthographic() == ortho);
            CHECK(c.projection_matrix(0.25) == p); // its own matrix, whatever the aspect
            const glm::dmat4 v = c.view_matrix();
            for (int col = 0; col < 4; ++col) CHECK(glm::length(v[col] - cam.view_matrix()[col]) < 1e-12);
            // Pixel rays go through the pixel centres the explicit matrix maps them to.
            const glm::dmat4 vp = p * v;
            const int w = 40, h = 30;
            for (auto [px, py] : {std::pair{0.5, 0.5}, {39.5, 10.5}, {20.5, 29.5}}) {
                const fx::Ray ray = c.pixel_ray(px, py, w, h);
                CHECK(glm::length(ray.direction) == Approx(1.0));
                const glm::dvec4 clip = vp * glm::dvec4(ray.origin + 2.0 * ray.direction, 1.0);
                CHECK((clip.x / clip.w + 1.0) * 0.5 * w == Approx(px).margin(1e-9));
                CHECK((clip.y / clip.w + 1.0) * 0.5 * h == Approx(py).margin(1e-9));
            }
        }
        if (!ortho) CHECK(fx::Camera::from_matrices(cam.view_matrix(), full).fov_y_degrees == Approx(50.0));
        if (ortho) CHECK(fx::Camera::from_matrices(cam.view_matrix(), full).ortho_height == Approx(3.0));
    }
}

TEST_CASE("a camera from matrices rejects what it cannot describe, and the scan-line renderer rejects it", "[camera]") {
    const fx::Camera cam = fx::Camera::parse("eye=3,-2,5,target=0,1,0,up=0,0,1,fov=50");
    const glm::dmat4 p = cam.projection_matrix(1.0);
    CHECK_THROWS_WITH(fx::Camera::from_matrices(glm::scale(cam.view_matrix(), glm::dvec3(2.0)), p),
                      Catch::Contains("not a rigid motion"));
    glm::dmat4 sheared = p;
    sheared[1][0] = 0.3;
    CHECK_THROWS_WITH(fx::Camera::from_matrices(cam.view_matrix(), sheared), Catch::Contains("neither a perspective"));
    glm::dmat4 behind = p;
    behind[3][2] = -behind[3][2]; // near and far behind the eye
    CHECK_THROWS_WITH(fx::Camera::from_matrices(cam.view_matrix(), behind), Catch::Contains("0 < near < far"));
    glm::dmat4 nan = p;
    nan[0][0] = std::nan("");
    CHECK_THROWS_WITH(fx::Camera::from_matrices(cam.view_matrix(), nan), Catch::Contains("not finite"));

    fx::CellMesh mesh = fx_test::hex_box(1, 1, 1);
    mesh.scalars.push_back({"s", std::vector<float>(mesh.point_count(), 1.0f)});
    const fx::Camera explicit_cam = fx::Camera::from_matrices(cam.view_matrix(), p);
    CHECK_THROWS_WITH(fx::ScanlineRenderer(mesh).render(explicit_cam, 8, 8, mesh.scalars[0],
                                                         fx::TransferFunction::constant(glm::dvec3(1.0), 1.0)),
                      Catch::Contains("explicit projection"));
}

TEST_CASE("every GPU path draws off-axis tiles that assemble into the frame drawn whole", "[gl][camera]") {
    // How VTK renders a screenshot larger than its window (and ParaView a tile display): each
    // tile with the frustum's off-axis part, into its own viewport. The tiles' pixels are the
    // whole frame's pixels (same rays): each pixel's ray is formed from the view's axis, the
    // whole frame's centre, whole pixels away in a tile (project.glsl), so a tile and the whole
    // frame form the same float ray and the exact paths' pixels away from the edges between
    // tiles come out identical (formed from each tile's own corner, 846 of the 3072 pixels
    // differed, by up to 1.8e-6 of peak). The pixels beside an edge between tiles are another
    // matter: the triangles crossing it are clipped there in a tile and not in the whole frame,
    // so a pixel centre within rounding of a cell's silhouette can gain or lose that cell's
    // fragment — a sliver of a segment, measured up to 1.3e-4 of peak (one pixel, pcp-exact;
    // the same whichever way the rays are formed, in float or in double).
    fx_test::gl_context();
    fx::CellMesh mesh = fx_test::mixed_box_with_tets(4);
    std::vector<float> values;
    for (const glm::dvec3& p : mesh.points) values.push_back(float(p.x + 2.0 * p.y * p.y + 0.5 * p.z));
    mesh.scalars.push_back({"s", values});
    const fx::TransferFunction tf({{0.0, {0.1, 0.3, 1.0}, 0.5}, {1.5, {1.0, 0.9, 0.2}, 3.0}, {3.5, {1.0, 0.1, 0.1}, 1.0}});
    fx::CellRenderer renderer(mesh, "s", tf);
    const fx::Camera cam = fx::Camera::parse("eye=2.2,-1.4,1.9,target=0.5,0.5,0.5,up=0,0,1,fov=40,near=0.1,far=20");
    const int w = 64, h = 48, n = 2;
    // The pixels on either side of an edge between tiles (1), and the others (0); each mask
    // leaves its 1s out of a comparison.
    std::vector<std::uint8_t> at_edge(std::size_t(w) * h, 0), inside(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int tx = x % (w / n), ty = y % (h / n);
            const bool edge = (tx == 0 && x > 0) || (tx == w / n - 1 && x < w - 1) || (ty == 0 && y > 0) || (ty == h / n - 1 && y < h - 1);
            at_edge[std::size_t(y) * w + x] = edge ? 1 : 0;
            inside[std::size_t(y) * w + x] = edge ? 0 : 1;
        }
    verify::Options away_from_edges, beside_edges;
    away_from_edges.skip = &at_edge;
    beside_edges.skip = &inside;
    for (fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::Mip, fx::RenderPath::Absorption,
                                fx::RenderPath::AbsorptionExact}) {
        const fx::Image whole = renderer.render_to_image(cam, w, h, path);
        const fx::gl::RenderTarget target = fx::gl::RenderTarget::create(w, h, fx::gl::ColorFormat::RGBA32F, false);
        {
            fx::gl::StateGuard guard;
            fx::gl::StateGuard::set_render_defaults();
            target.clear(glm::vec4(0.0f));
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.framebuffer());
            for (int j = 0; j < n; ++j) {
                for (int i = 0; i < n; ++i) {
                    const fx::Camera tile = fx::Camera::from_matrices(
                        cam.view_matrix(), tile_projection(cam.projection_matrix(double(w) / h), n, i, j));
                    renderer.render(tile, {i * w / n, j * h / n, w / n, h / n}, path);
                }
            }
        }
        const fx::Image tiled = target.read();
        const std::string name = std::string("tiles_") + fx::render_path_name(path);
        // Away from the edges: the exact paths integrate along the pixel's ray alone, so the same
        // ray gives the same pixel (identical on llvmpipe; 1e-6 of peak, mean 1e-8, leaves a GPU
        // rounding room and still fails the rays formed from each tile's corner); mip and
        // classic absorption interpolate what the rasteriser hands them, which the tile's own
        // projection rounds differently (measured up to 8.4e-6 of peak): 1e-4 of peak.
        const bool exact = path == fx::RenderPath::PcpExact || path == fx::RenderPath::AbsorptionExact;
        verify::Tolerance same = verify::same_picture(
            0.0, exact ? "the same rays, formed from the view's axis: the same pixels"
                       : "the same rays; the rasteriser's interpolation rounded per tile");
        same.pixel.of_peak = exact ? 1e-6 : 1e-4, same.mean.of_peak = exact ? 1e-8 : 1e-6;
        const verify::Difference d = fx_test::check_frame(name, tiled, whole, same, away_from_edges);
        CHECK(d.peak > 0.05);
        verify::Tolerance edge =
            verify::same_picture(0.0, "beside an edge between tiles: a silhouette's fragment gained or lost where the tile clips");
        edge.pixel.of_peak = 3e-4, edge.mean.of_peak = 1e-5;
        fx_test::check_image(name + "_tile_edges", tiled, whole, edge, beside_edges);
    }
    fx_test::require_no_gl_error();
}

TEST_CASE("PFM round-trips float pixels bottom row first", "[image]") {
    fx::Image img(3, 2);
    img.at(0, 0) = {0.25f, -1.5f, 1e-7f, 1.0f};
    img.at(2, 1) = {3.0f, 0.5f, 0.125f, 1.0f};
    const std::string path = fx_test::output_path("roundtrip.pfm");
    fx::write_image(img, path);
    const fx::Image back = fx::read_pfm(path);
    REQUIRE(back.width == 3);
    REQUIRE(back.height == 2);
    CHECK(back.at(0, 0) == img.at(0, 0));
    CHECK(back.at(2, 1) == img.at(2, 1));
    CHECK_THROWS_WITH(fx::read_pfm(fx_test::output_path("missing.pfm")), Catch::Contains("missing.pfm"));
    CHECK_THROWS_WITH(fx::write_image(img, fx_test::output_path("x.jpg")), Catch::Contains("unknown image type"));
}

TEST_CASE("compositing premultiplied colour over a background", "[image]") {
    fx::Image img(1, 1, {0.2f, 0.0f, 0.0f, 0.25f});
    fx::composite_over(img, {0.0f, 1.0f, 0.0f});
    CHECK(img.at(0, 0).r == Approx(0.2f));
    CHECK(img.at(0, 0).g == Approx(0.75f));
    CHECK(img.at(0, 0).a == 1.0f);
}
