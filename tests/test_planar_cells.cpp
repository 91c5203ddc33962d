// Planar cells take the plane-based fragment road (shaders/cell_segment.glsl: Cyrus–Beck through
// the faces' planes), folded cells search their triangles: on a grid that mixes both — regular,
// bent (curvilinear, flat within the tolerance) and folded hexahedra beside terrain-fog wedges
// (fx_test::planar_and_folded_grid) — the exact paths draw the same pictures by either road, and
// both match the scan-line reference (which draws every quad as its two triangles).
//
// Tolerances (fractions of `peak`, the brightest reference channel):
//   against the scan-line reference, each path's stated tolerance (verify::stated; with the
//   near plane cutting cells for the views inside), one pixel allowed 10% of peak where the near
//   plane cuts a folded cell (see the test);
//   the planar road against the search: a planar cell's faces stand within kPlanarTolerance (1e-3)
//   of its size from its triangles, so where a ray crosses a face between a planar cell and a
//   folded one or the outside, its segment moves by up to 1e-3 of a cell over |cos θ|; between two
//   planar cells nothing moves (they share the plane). On these views (cells 5–20 pixels, tens
//   of faces on a ray) that is far below 0.1% of the peak per pixel except where a face is seen
//   nearly edge-on: per pixel 0.2% of peak, at most 0.5% of the pixels beyond, mean 0.01%.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "fx/cell_renderer.hpp"
#include "fx/scanline_renderer.hpp"
#include "gl_fixture.hpp"
#include "image_check.hpp"
#include "projector/gl_projector.hpp"
#include "projector_meshes.hpp"
#include "render/projector_access.hpp"
#include "cellfx_names.hpp"

namespace {

fx::Camera perspective(glm::dvec3 eye, glm::dvec3 target, double near_distance = 0.05) {
    fx::Camera cam;
    cam.eye = eye, cam.target = target, cam.up = {0, 0, 1};
    cam.fov_y_degrees = 40.0;
    cam.near_distance = near_distance;
    cam.far_distance = 100.0;
    return cam;
}

fx::TransferFunction glow(double density) {
    return fx::TransferFunction({{0.0, {0.2, 0.5, 1.0}, 0.3 * density},
                                 {0.4, {0.6, 0.4, 0.5}, 1.0 * density},
                                 {1.0, {1.0, 0.9, 0.3}, 2.0 * density}},
                                true);
}

struct View {
    const char* name;
    fx::Camera camera;
    bool inside; // the near plane cuts cells
};

std::vector<View> views() {
    fx::Camera grazing;
    grazing.eye = {1.45, -6.0, 0.36}; // along y, level with the boxes' middle: their x faces edge-on
    grazing.target = {1.45, 1.0, 0.36};
    grazing.up = {0, 0, 1};
    grazing.ortho_height = 3.2;
    grazing.near_distance = 0.1;
    grazing.far_distance = 100.0;
    return {{"outside", perspective({4.2, -2.6, 2.8}, {1.4, 1.0, 0.3}), false},
            {"grazing orthographic", grazing, false},
            {"inside the regular box", perspective({0.55, 0.3, 0.4}, {2.6, 0.1, 0.3}, 0.02), true},
            {"inside the folded block", perspective({0.45, 1.55, 0.4}, {0.6, 2.2, 0.3}, 0.02), true}};
}

} // namespace

TEST_CASE("planar and folded cells: either fragment road, the same picture, the scan-line's", "[gl][pcp][planar]") {
    fx_test::gl_context();
    const fx::CellMesh mesh = fx_test::planar_and_folded_grid();
    const fx::TransferFunction tf = glow(1.5);
    const fx::ScalarField& field = *mesh.find_scalar("s");
    const fx::ScanlineRenderer scanline(mesh);
    const int size = 96;
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
        for (const View& view : views()) {
            const std::string name = std::string("planar_") + fx::render_path_name(path) + "_" + view.name;
            INFO(name);
            fx::ScanlineOptions so;
            so.model = path == fx::RenderPath::PcpExact ? fx::OpticalModel::Emission : fx::OpticalModel::EmissionAbsorption;
            const fx::Image reference = scanline.render(view.camera, size, size, field, tf, so);
            fx::CellRenderer renderer(mesh, "s", tf);
            fx::CellRenderOptions options;
            options.sort = fx::SortMethod::Xmpvo; // three blocks apart: not convex
            const fx::Image planar = renderer.render_to_image(view.camera, size, size, path, options);
            fx::renderer_projector(renderer).set_planar_tolerance(-1.0); // every cell searches
            const fx::Image searched = renderer.render_to_image(view.camera, size, size, path, options);
            fx_test::require_no_gl_error();

            verify::Case c;
            c.near_plane_cuts = view.inside;
            verify::Tolerance against_reference = verify::stated(verify::path_of(path), c);
            if (view.inside) {
                // The near plane cuts a folded cell here: pcp-exact takes the cut's scalar from the
                // cell's faces, the reference along the ray; one pixel of 9216 lies 6.5% of peak
                // outside the reference's range around it, by either road alike.
                against_reference.share_beyond = std::max(against_reference.share_beyond, 0.001);
                against_reference.worst.of_peak = std::max(against_reference.worst.of_peak, 0.1);
                against_reference.why += "; a folded cell cut by the near plane: worst 10% of peak";
            }
            fx_test::check_frame(name + "_planar", planar, reference, against_reference);
            fx_test::check_frame(name + "_searched", searched, reference, against_reference);
            verify::Tolerance same;
            same.pixel.of_peak = 0.002, same.share_beyond = 0.005, same.mean.of_peak = 0.0001;
            same.why = "a planar cell's faces lie within 1e-3 of its size from its triangles (header comment)";
            fx_test::check_frame(name + "_planar_vs_searched", planar, searched, same);
        }
    }
}

TEST_CASE("planar cells turning folded and back in place draw what a renderer made for the mesh draws", "[gl][pcp][planar]") {
    fx_test::gl_context();
    const fx::CellMesh original = fx_test::planar_and_folded_grid();
    // The regular box's inner node (2, 2, 1) moved off its lattice: its 8 hexahedra fold.
    const std::uint32_t moved = 37;
    REQUIRE(original.points[moved] == glm::dvec3(0.5, 0.5, 0.25));
    fx::CellMesh bent = original;
    bent.points[moved] += glm::dvec3(0.04, -0.03, 0.05);
    bent.scalars[0].values[moved] += 0.2f;
    const fx::TransferFunction tf = glow(1.5);
    const View view = views()[0];
    const int size = 96;
    fx::MeshChanges changes;
    changes.clear(); // in place: only `moved` changed
    changes.points = {moved};
    for (const fx::RenderPath path : {fx::RenderPath::PcpExact, fx::RenderPath::AbsorptionExact}) {
        fx::CellRenderOptions options;
        options.sort = fx::SortMethod::Xmpvo;
        fx::CellRenderer updated(original, "s", tf); // its rows compact, then by slot after the update
        updated.render_to_image(view.camera, size, size, path, options);
        int step = 0;
        for (const fx::CellMesh* m : {static_cast<const fx::CellMesh*>(&bent), &original}) {
            const std::string name = std::string("planar_in_place_") + fx::render_path_name(path) + "_" + std::to_string(step++);
            INFO(name);
            REQUIRE(updated.update_mesh(*m, "s", changes));
            const fx::Image in_place = updated.render_to_image(view.camera, size, size, path, options);
            fx::CellRenderer fresh(*m, "s", tf); // compact rows
            const fx::Image made = fresh.render_to_image(view.camera, size, size, path, options);
            fx_test::require_no_gl_error();
            fx::ScanlineOptions so;
            so.model = path == fx::RenderPath::PcpExact ? fx::OpticalModel::Emission : fx::OpticalModel::EmissionAbsorption;
            const fx::Image reference = fx::ScanlineRenderer(*m).render(view.camera, size, size, *m->find_scalar("s"), tf, so);
            const verify::Tolerance stated = verify::stated(verify::path_of(path), verify::Case{});
            fx_test::check_frame(name, in_place, reference, stated);
            fx_test::check_frame(name + "_fresh", made, reference, stated);
            verify::Tolerance same;
            same.pixel.of_peak = 1e-6, same.share_beyond = 0.0, same.mean.of_peak = 1e-7;
            same.why = "the same tables, the rows at other places: the same arithmetic per fragment";
            fx_test::check_frame(name + "_vs_fresh", in_place, made, same);
        }
    }
}
