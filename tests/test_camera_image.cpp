#include <catch2/catch.hpp>

#include <cstdio>

#include <glm/geometric.hpp>

#include "fx/camera.hpp"
#include "fx/error.hpp"
#include "fx/image.hpp"
#include "test_paths.hpp"

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
