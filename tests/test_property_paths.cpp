// Randomised property test of every render path: random valid meshes of convex cells, random
// views and random transfer functions (fixed seeds), each path against the scan-line reference
// of its optical model. Properties: every pixel finite and in [0, 1], and within the path's
// stated tolerance (testing/verify/tolerances.cpp, the one place those are written down).
//
// Meshes (a third each): a box of hexahedra with random layer spacing, rotated and moved
// rigidly; consistent tetrahedra of a grid whose nodes are jittered (boundary nodes along the
// boundary only, so the mesh stays a box); two layers of prisms over a random height field
// (vertical sides, like ground fog: non-convex on top). Views: perspective from outside,
// orthographic, or the eye inside the mesh with the near plane cutting cells — each mesh kind
// with each kind of view.
// Fields: a sum of random sinusoids in [0, 1]; for views from inside a linear one (the
// renderers interpolate the scalar on the near-plane cut differently inside a cell where the
// field is not linear — a modelling difference stated in test_pcp_scanline.cpp — and agree
// exactly where it is). Transfer functions: 2 to 5 random points on [0, 1] (colours in [0, 1],
// optical depth through the mesh 0.2–4), colours scaled so that emission stays below 1 (classic
// pcp's 8-bit target). mip gets the same points made monotonic (so its maximum lies at a
// segment's end, as the path assumes: docs/render_paths.md), the fog flavour the same
// extinction in one colour (its exact case).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "fx/mesh_validation.hpp"
#include "mesh/tetrahedralize.hpp"
#include "hard_case_support.hpp"
#include "cellfx_names.hpp"

using hard_case::Path;

namespace {

struct RandomCase {
    fx::CellMesh mesh;
    fx::TransferFunction tf, monotonic, one_colour;
    fx::Camera camera;
    bool inside = false;
    int cells_on_ray = 1;
    std::string description;
};

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int integer(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
glm::dvec3 unit_vector(std::mt19937& rng) {
    for (;;) {
        const glm::dvec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        const double l = glm::length(v);
        if (l > 0.1 && l <= 1.0) return v / l;
    }
}

// Layer positions in [0, 1]: n random positive steps, normalised.
std::vector<double> random_layers(std::mt19937& rng, int n) {
    std::vector<double> at{0.0};
    for (int i = 0; i < n; ++i) at.push_back(at.back() + uniform(rng, 0.3, 1.0));
    for (double& x : at) x /= at.back();
    return at;
}

fx::CellMesh random_hex_box(std::mt19937& rng, std::ostringstream& d, int& cells_on_ray) {
    const std::array<int, 3> n{integer(rng, 3, 6), integer(rng, 3, 6), integer(rng, 3, 6)};
    const glm::dvec3 size(uniform(rng, 0.6, 1.6), uniform(rng, 0.6, 1.6), uniform(rng, 0.6, 1.6));
    const std::array<std::vector<double>, 3> layers{random_layers(rng, n[0]), random_layers(rng, n[1]),
                                                    random_layers(rng, n[2])};
    const glm::dmat4 pose = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(uniform(rng, -3, 3), uniform(rng, -3, 3),
                                                                                      uniform(rng, -3, 3))),
                                        uniform(rng, 0.0, 6.28), unit_vector(rng));
    fx::CellMesh mesh;
    fx::append_curvilinear_block(mesh, "box", {std::uint32_t(n[0] + 1), std::uint32_t(n[1] + 1), std::uint32_t(n[2] + 1)},
                                 [&](double u, double v, double w) {
                                     const glm::dvec3 q(layers[0][std::size_t(std::lround(u * n[0]))],
                                                        layers[1][std::size_t(std::lround(v * n[1]))],
                                                        layers[2][std::size_t(std::lround(w * n[2]))]);
                                     return glm::dvec3(pose * glm::dvec4(size * (q - 0.5), 1.0));
                                 });
    d << "hexahedra " << n[0] << "x" << n[1] << "x" << n[2] << ", rotated";
    cells_on_ray = int(std::ceil(std::sqrt(3.0) * std::max({n[0], n[1], n[2]}))) + 1;
    return mesh;
}

fx::CellMesh random_jittered_tets(std::mt19937& rng, std::ostringstream& d, int& cells_on_ray) {
    const int n = integer(rng, 3, 5);
    const std::uint32_t nodes = std::uint32_t(n + 1);
    std::vector<glm::dvec3> jitter(std::size_t(nodes) * nodes * nodes);
    for (glm::dvec3& j : jitter) j = glm::dvec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    // Jitter by up to `amount` of a cell; halved until every tetrahedron is positively oriented.
    for (double amount = 0.25;; amount *= 0.5) {
        fx::CellMesh hexes;
        fx::append_curvilinear_block(hexes, "grid", {nodes, nodes, nodes}, [&](double u, double v, double w) {
            const int i = int(std::lround(u * n)), j = int(std::lround(v * n)), k = int(std::lround(w * n));
            glm::dvec3 p(u, v, w), o = jitter[(std::size_t(k) * nodes + std::size_t(j)) * nodes + std::size_t(i)];
            const int idx[3] = {i, j, k};
            for (int a = 0; a < 3; ++a)
                if (idx[a] == 0 || idx[a] == n) o[a] = 0.0; // boundary nodes move along the boundary
            return p + o * (amount / n);
        });
        fx::CellMesh tets = fx::tetrahedralize(hexes);
        bool positive = true;
        for (std::size_t c = 0; c < tets.cell_count() && positive; ++c) positive = fx::cell_signed_volume(tets, c) > 0.0;
        if (positive) {
            d << "tetrahedra of a jittered " << n << "^3 grid (jitter " << amount << " of a cell)";
            cells_on_ray = 3 * int(std::ceil(std::sqrt(3.0) * n)) + 1; // up to ~3 tetrahedra per hexahedron crossed
            return tets;
        }
        REQUIRE(amount > 1e-3);
    }
}

fx::CellMesh random_prisms(std::mt19937& rng, std::ostringstream& d, int& cells_on_ray) {
    const int m = integer(rng, 4, 7);
    const double fx1 = uniform(rng, 2, 6), fy1 = uniform(rng, 2, 6), p1 = uniform(rng, 0, 6.28), p2 = uniform(rng, 0, 6.28);
    auto ground = [&](double x, double y) { return 0.15 * std::sin(fx1 * x + p1) * std::cos(fy1 * y + p2); };
    auto thickness = [&](double x, double y) { return 0.15 + 0.12 * (1.0 + std::sin(fy1 * x - p2 + fx1 * y)); };
    fx::CellMesh mesh;
    const int row = m + 1;
    for (int layer = 0; layer < 3; ++layer)
        for (int j = 0; j <= m; ++j)
            for (int i = 0; i <= m; ++i) {
                const double x = double(i) / m, y = double(j) / m;
                mesh.points.push_back({x, y, ground(x, y) + layer * thickness(x, y)});
            }
    auto id = [&](int layer, int i, int j) { return std::uint32_t((layer * row + j) * row + i); };
    mesh.begin_block("prisms");
    for (int layer = 0; layer < 2; ++layer)
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < m; ++i) {
                const int tri[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}}, {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
                for (const auto& t : tri) {
                    // VTK wedge: bottom (0, 1, 2) facing down, i.e. clockwise seen from above.
                    const std::uint32_t v[6] = {id(layer, t[0][0], t[0][1]),     id(layer, t[2][0], t[2][1]),
                                                id(layer, t[1][0], t[1][1]),     id(layer + 1, t[0][0], t[0][1]),
                                                id(layer + 1, t[2][0], t[2][1]), id(layer + 1, t[1][0], t[1][1])};
                    mesh.add_cell(fx::CellType::Wedge, v);
                }
            }
    fx::orient_cells(mesh);
    d << "2 layers of " << 2 * m * m << " prisms over a height field";
    cells_on_ray = 4 * m + 2; // a grazing ray along the layers crosses ~2 prisms per column, 2 layers
    return mesh;
}

fx::TransferFunction random_tf(std::mt19937& rng, double sigma_max, double colour_scale) {
    const int count = integer(rng, 2, 5);
    std::vector<double> s{0.0, 1.0};
    for (int i = 2; i < count; ++i) s.push_back(uniform(rng, 0.05, 0.95));
    std::sort(s.begin(), s.end());
    std::vector<fx::TransferPoint> points;
    for (double x : s)
        points.push_back({x, glm::dvec3(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)) * colour_scale,
                          uniform(rng, 0.05, 1.0) * sigma_max});
    return fx::TransferFunction(points);
}

// The same points with every channel's colour, and the extinction, sorted rising in s: c·σ
// then rises in s in every channel.
fx::TransferFunction monotonic(const fx::TransferFunction& tf) {
    std::vector<fx::TransferPoint> points = tf.points();
    for (int c = 0; c < 4; ++c) {
        std::vector<double> v;
        for (const fx::TransferPoint& p : points) v.push_back(c < 3 ? p.color[c] : p.sigma);
        std::sort(v.begin(), v.end());
        for (std::size_t i = 0; i < points.size(); ++i) (c < 3 ? points[i].color[c] : points[i].sigma) = v[i];
    }
    return fx::TransferFunction(points);
}

fx::TransferFunction one_colour(const fx::TransferFunction& tf) {
    std::vector<fx::TransferPoint> points = tf.points();
    glm::dvec3 mean(0.0);
    for (const fx::TransferPoint& p : points) mean += p.color / double(points.size());
    for (fx::TransferPoint& p : points) p.color = mean;
    return fx::TransferFunction(points);
}

RandomCase make_case(int index) {
    std::mt19937 rng(9000u + unsigned(index));
    RandomCase c;
    std::ostringstream d;
    d << "case " << index << ": ";
    switch (index % 3) {
    case 0: c.mesh = random_hex_box(rng, d, c.cells_on_ray); break;
    case 1: c.mesh = random_jittered_tets(rng, d, c.cells_on_ray); break;
    default: c.mesh = random_prisms(rng, d, c.cells_on_ray); break;
    }
    const fx::Bounds b = fx::mesh_bounds(c.mesh);
    const glm::dvec3 centre = b.center();
    const double radius = 0.5 * glm::length(b.size());

    // Every mesh kind with every kind of view: perspective (twice), orthographic, inside.
    const int view = (index / 3) % 4;
    c.inside = view == 2;
    fx::Camera& cam = c.camera;
    cam.up = glm::dvec3(0, 0, 1);
    cam.far_distance = 100.0 * radius + 100.0;
    if (c.inside) {
        // A point inside a cell (the centroid of a random one), looking anywhere.
        const std::size_t cell = std::size_t(integer(rng, 0, int(c.mesh.cell_count()) - 1));
        glm::dvec3 p(0.0);
        const int nv = fx::cell_vertex_count(c.mesh.cell_types[cell]);
        for (int v = 0; v < nv; ++v) p += c.mesh.points[c.mesh.cell_vertices(cell)[v]] / double(nv);
        cam.eye = p;
        cam.target = p + unit_vector(rng);
        cam.fov_y_degrees = uniform(rng, 35, 70);
        cam.near_distance = uniform(rng, 0.005, 0.05) * radius;
        d << ", eye inside";
    } else {
        glm::dvec3 dir = unit_vector(rng);
        if (std::abs(glm::dot(dir, cam.up)) > 0.95) dir = glm::normalize(dir + glm::dvec3(0.5, -0.3, 0.0));
        cam.target = centre + glm::dvec3(uniform(rng, -0.2, 0.2), uniform(rng, -0.2, 0.2), uniform(rng, -0.2, 0.2)) * radius;
        cam.eye = cam.target + dir * radius * uniform(rng, 1.8, 3.0);
        cam.near_distance = 0.02 * radius;
        if (view == 1) {
            cam.ortho_height = 2.2 * radius;
            d << ", orthographic";
        } else {
            cam.fov_y_degrees = uniform(rng, 30, 55);
            d << ", perspective";
        }
    }
    if (std::abs(glm::dot(glm::normalize(cam.target - cam.eye), cam.up)) > 0.95) cam.up = glm::dvec3(1, 0, 0);

    // The field, in [0, 1].
    if (c.inside) {
        const glm::dvec3 g = unit_vector(rng);
        fx::set_scalar_field(c.mesh, "s", [&](const glm::dvec3& p) { return 0.5 + 0.5 * glm::dot(g, p - centre) / radius; });
        d << ", linear field";
    } else {
        glm::dvec3 k[3];
        double phase[3], amp[3], total = 0.0;
        for (int i = 0; i < 3; ++i) {
            k[i] = unit_vector(rng) * uniform(rng, 1.0, 4.0) / radius;
            phase[i] = uniform(rng, 0, 6.28), amp[i] = uniform(rng, 0.2, 1.0), total += amp[i];
        }
        fx::set_scalar_field(c.mesh, "s", [&](const glm::dvec3& p) {
            double v = 0.0;
            for (int i = 0; i < 3; ++i) v += amp[i] * std::sin(glm::dot(k[i], p) + phase[i]);
            return 0.5 + 0.5 * v / total;
        });
        d << ", sinusoid field";
    }
    // Extinction: optical depth up to 0.2–4 across the mesh; colours so that the emission
    // through it (≤ c·σ_max·diameter) stays below 0.9.
    const double sigma_max = uniform(rng, 0.1, 2.0) / radius;
    const double colour_scale = std::min(1.0, 0.9 / (sigma_max * 2.0 * radius));
    c.tf = random_tf(rng, sigma_max, colour_scale);
    c.monotonic = monotonic(c.tf);
    c.one_colour = one_colour(c.tf);
    d << "; " << c.mesh.cell_count() << " cells, " << c.tf.points().size() << " transfer points, sigma_max "
      << sigma_max;
    c.description = d.str();
    return c;
}

// Classic absorption's known limit (test_hard_cases.cpp, docs/accuracy.md): thickness linear on
// screen across cells that reach the eye.
bool classic_at_the_eye(const RandomCase& c, Path p) { return c.inside && p == Path::Absorption; }

} // namespace

TEST_CASE("property: random convex meshes, views and transfer functions, every path", "[gl][property]") {
    constexpr int kCases = 12;
    for (int index = 0; index < kCases; ++index) {
        const RandomCase c = make_case(index);
        INFO(c.description);
        {
            const std::vector<fx::MeshProblem> problems = fx::validate_mesh(c.mesh);
            REQUIRE(problems.empty());
        }
        for (Path p : hard_case::kAllPaths) {
            hard_case::Scene s;
            s.mesh = c.mesh;
            s.tf = p == Path::Mip ? c.monotonic : p == Path::PcpExactFog ? c.one_colour : c.tf;
            s.camera = c.camera;
            s.cells_on_ray = c.cells_on_ray;
            const std::string name = "property_" + std::to_string(index);
            INFO(name << " [" << hard_case::name(p) << "]");
            const fx::Image actual = hard_case::render(s, p);
            if (p == Path::Scanline) {
                // The reference itself (its own closed-form tests: test_scanline.cpp,
                // test_hard_cases*.cpp): finite and in [0, 1] for every model.
                for (fx::OpticalModel m : {fx::OpticalModel::Emission, fx::OpticalModel::Maximum,
                                           fx::OpticalModel::EmissionAbsorption}) {
                    const fx::Image image = hard_case::scanline_reference(s, m);
                    fx_test::check_image(name + "_scanline", image, image, hard_case::guaranteed("the reference itself"));
                }
                continue;
            }
            const fx::Image expected = hard_case::scanline_reference(s, hard_case::model_of(p, s.scanline_model));
            if (classic_at_the_eye(c, p)) {
                fx_test::check_frame(name + "_" + hard_case::name(p), actual, expected,
                                     hard_case::guaranteed("eye inside: classic absorption's perspective limit"));
                continue;
            }
            hard_case::check(name, p, actual, expected, hard_case::stated_tolerance(p, s.cells_on_ray));
        }
    }
}

namespace {

// `up` rotated to `angle` radians from the view direction, in the plane of the two.
glm::dvec3 up_at_angle(const fx::Camera& c, double angle) {
    const fx::Camera::Basis b = c.basis();
    return std::cos(angle) * b.forward + std::sin(angle) * b.up;
}

} // namespace

TEST_CASE("property: tiny, huge and near-parallel up vectors and eye-target distances, every path",
          "[gl][property]") {
    // The camera's frame is built in double and normalised before any path sees it in float
    // (Camera::basis): an up of 1e-300 or 1e300 is the up of its direction, an up 2e-6 rad from
    // the view direction (validate() refuses below 1e-6) a well-defined frame, and the target may
    // sit anywhere along the view. Before, pcp and pcp-exact drew garbage or nothing with
    // up = (0, 0, 1e-300) and absorption-exact was 4x too bright. Every variant of every case:
    // each GPU path within its stated tolerance of the scan-line reference of the same camera;
    // where the variant names the same view (a scaled up, a moved target), the reference
    // itself within float rounding of the original view's.
    struct Variant {
        const char* name;
        std::function<void(fx::Camera&, double radius)> apply;
        bool same_view;
    };
    const std::vector<Variant> variants = {
        {"up x 1e-300", [](fx::Camera& c, double) { c.up *= 1e-300; }, true},
        {"up x 1e300", [](fx::Camera& c, double) { c.up *= 1e300; }, true},
        {"up of denormals (5e-324, 0, 5e-324)",
         [](fx::Camera& c, double) {
             const glm::dvec3 u = c.basis().up;
             c.up = glm::dvec3(u.x >= 0 ? 5e-324 : -5e-324, 0.0, u.z >= 0 ? 5e-324 : -5e-324);
         },
         false},
        {"up 2e-6 rad from the view", [](fx::Camera& c, double) { c.up = up_at_angle(c, 2e-6); }, false},
        {"up 1e-3 rad from the view, x 1e-200", [](fx::Camera& c, double) { c.up = 1e-200 * up_at_angle(c, 1e-3); }, false},
        {"target 1e-9 of the mesh from the eye",
         [](fx::Camera& c, double radius) { c.target = c.eye + c.forward() * (1e-9 * radius); }, true},
        {"target 1e5 meshes beyond the eye",
         [](fx::Camera& c, double radius) { c.target = c.eye + c.forward() * (1e5 * radius); }, true},
    };
    // One case of each mesh kind: hexahedra from outside, jittered tetrahedra orthographic,
    // prisms with the eye inside (make_case's index → mesh kind, view kind).
    for (int index : {0, 4, 8}) {
        const RandomCase c = make_case(index);
        const double radius = 0.5 * glm::length(fx::mesh_bounds(c.mesh).size());
        for (const Variant& v : variants) {
            fx::Camera camera = c.camera;
            v.apply(camera, radius);
            INFO(c.description << "; " << v.name);
            REQUIRE_NOTHROW(camera.validate("camera"));
            for (Path p : hard_case::kAllPaths) {
                hard_case::Scene s;
                s.mesh = c.mesh;
                s.tf = p == Path::Mip ? c.monotonic : p == Path::PcpExactFog ? c.one_colour : c.tf;
                s.camera = camera;
                s.cells_on_ray = c.cells_on_ray;
                const std::string name = "property_up_" + std::to_string(index) + "_" + std::to_string(&v - variants.data());
                INFO(name << " [" << hard_case::name(p) << "]");
                const fx::OpticalModel model = hard_case::model_of(p, s.scanline_model);
                const fx::Image expected = hard_case::scanline_reference(s, model);
                if (p == Path::Scanline) {
                    if (!v.same_view) continue;
                    // The reference of the same view, within the reference's own stated tolerance:
                    // the frame differs by rounding (a target 1e-9 away: its direction to ~1e-7 rad).
                    hard_case::Scene original = s;
                    original.camera = c.camera;
                    hard_case::check(name + "_same_view", p, expected, hard_case::scanline_reference(original, model),
                                     hard_case::stated_tolerance(Path::Scanline, s.cells_on_ray));
                    continue;
                }
                const fx::Image actual = hard_case::render(s, p);
                if (classic_at_the_eye(c, p)) {
                    fx_test::check_frame(name + "_" + hard_case::name(p), actual, expected,
                                         hard_case::guaranteed("eye inside: classic absorption's perspective limit"));
                    continue;
                }
                hard_case::check(name, p, actual, expected, hard_case::stated_tolerance(p, s.cells_on_ray));
            }
        }
    }
}
