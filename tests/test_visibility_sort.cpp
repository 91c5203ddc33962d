// Visibility sorts: every cell once, farthest first.
#include <catch2/catch.hpp>

#include <algorithm>

#include "fx/visibility_sort.hpp"
#include "mesh_builders.hpp"

TEST_CASE("centroid sort gives every cell once, farthest centroid first", "[sort]") {
    const fx::CellMesh mesh = fx_test::hex_box(4, 3, 2);
    const fx::VisibilitySort sorter(mesh, fx::SortMethod::Centroid);
    fx::Camera camera;
    camera.eye = {5.0, -4.0, 3.0};
    camera.target = {0.5, 0.5, 0.5};
    std::vector<std::uint32_t> order;
    fx::SortStats stats;
    sorter.sort(camera, order, &stats);
    REQUIRE(order.size() == mesh.cell_count());
    CHECK(stats.cells == mesh.cell_count());
    std::vector<std::uint32_t> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    for (std::uint32_t i = 0; i < sorted.size(); ++i) REQUIRE(sorted[i] == i);

    auto distance = [&](std::uint32_t c) {
        glm::dvec3 sum(0.0);
        for (int i = 0; i < 8; ++i) sum += mesh.points[mesh.cell_vertices(c)[i]];
        return glm::length(sum / 8.0 - camera.eye);
    };
    for (std::size_t i = 1; i < order.size(); ++i) CHECK(distance(order[i - 1]) >= distance(order[i]));

    fx::SortMethod method;
    REQUIRE(fx::parse_sort_method("centroid", method));
    CHECK(method == fx::SortMethod::Centroid);
    CHECK_FALSE(fx::parse_sort_method("bogus", method));
}
