// A generic volume (fx/volume.hpp): box, sphere (icosphere shells) or mesh; constant, noise or
// field density. The noise is fx::Noise (docs/noise.md), 4-D for time like the campfire's.
#include "fx/volume.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "fx/effect_parameters.hpp"
#include "fx/error.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/noise.hpp"

namespace cellfx::fx {

namespace {

constexpr double kDegrees = 0.017453292519943295;

void check(bool ok, const std::string& name, const char* what) {
    if (!ok) throw Error("volume: " + name + " " + what);
}

int cells_of(const VolumeParams& p) {
    if (p.cells > 0) return p.cells;
    const bool plain = p.density_mode == VolumeDensity::Constant && p.edge_fade == 0.0;
    return p.shape == VolumeShape::Box && plain ? 1 : 16;
}

// A box's cells along x, y, z: `cells_of` across the largest extent, in proportion elsewhere.
std::array<int, 3> box_divisions(const VolumeParams& p) {
    const double largest = std::max({p.size.x, p.size.y, p.size.z});
    const int across = cells_of(p);
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::lround(across * p.size[a] / largest)));
    return n;
}

// A sphere's icosphere level (surface triangles about as wide as a cell: the icosahedron's edge
// is ~1.05 radii, each level halves it) and its shells of cells.
int sphere_level(const VolumeParams& p) { return std::clamp(int(std::lround(std::log2(std::max(1.0, 0.5 * cells_of(p))))), 1, 5); }
int sphere_shells(const VolumeParams& p) { return std::max(1, cells_of(p) / 2); }

void validate(const VolumeParams& p) {
    check_parameters(p, "volume"); // each parameter's range (effect_parameters.cpp)
    switch (p.shape) {
    case VolumeShape::Box:
    case VolumeShape::Sphere: break;
    case VolumeShape::Mesh: {
        check(p.mesh != nullptr && p.mesh->cell_count() > 0, "mesh", "has no cells");
        check(p.edge_fade == 0.0, "edge_fade", "applies to a box or a sphere, not a mesh");
        if (p.density_mode == VolumeDensity::Field) {
            check(!p.mesh->scalars.empty(), "field", "is required: the mesh has no point field");
            check(p.field.empty() || p.mesh->find_scalar(p.field) != nullptr, "field",
                  ("'" + p.field + "' is not a field of the mesh").c_str());
        }
        break;
    }
    }
    check(p.density_mode != VolumeDensity::Field || p.shape == VolumeShape::Mesh, "density",
          "\"field\" needs a mesh shape (a box or sphere has no field)");
    check_effect_cells(max_cells(p), "volume: cells");
}

// What changing a into b costs: the table's fields (fx::change_cost), and the ones it does not
// describe. A new shape, mesh or field rebuilds (a mesh's field is copied when it is built, so
// on a mesh a new density mode does too), as does a new automatic cell count (`cells` 0 follows
// the density mode and the edge fade); elsewhere a new density mode re-evaluates.
ParameterCost volume_change_cost(const VolumeParams& a, const VolumeParams& b) {
    if (a.shape != b.shape || a.mesh != b.mesh || a.field != b.field || cells_of(a) != cells_of(b) ||
        (a.shape == VolumeShape::Mesh && a.density_mode != b.density_mode))
        return ParameterCost::Rebuild;
    const ParameterCost cost = change_cost(a, b);
    return a.density_mode != b.density_mode ? std::max(cost, ParameterCost::Scalars) : cost;
}

Fractal fractal_of(const VolumeNoise& n) {
    Fractal f;
    f.basis = NoiseBasis::simplex;
    f.type = FractalType::fbm;
    f.octaves = n.octaves;
    f.frequency = n.frequency;
    return f;
}

glm::dvec4 noise_point(const VolumeNoise& n, const glm::dvec3& p, double time) {
    const glm::dvec3 q = p - n.drift * time;
    return {q.x, q.y, q.z, n.evolve * time / n.frequency};
}

// The soft rim: 1 inside, falling linearly to 0 at the boundary over edge_fade of the half extent.
double edge(const VolumeParams& p, const glm::dvec3& q) {
    if (p.edge_fade == 0.0) return 1.0;
    double inside = 0.0; // distance to the boundary, as a fraction of the half extent
    if (p.shape == VolumeShape::Box) {
        const glm::dvec3 h = 0.5 * p.size;
        inside = std::min({(h.x - std::abs(q.x)) / h.x, (h.y - std::abs(q.y)) / h.y, (h.z - std::abs(q.z)) / h.z});
    } else {
        inside = 1.0 - glm::length(q) / p.radius;
    }
    return std::clamp(inside / p.edge_fade, 0.0, 1.0);
}

// Adds a cell, swapping two vertices of each base if the order came out inverted.
void add_positive(CellMesh& mesh, CellType type, std::array<std::uint32_t, 6> v) {
    mesh.add_cell(type, v.data());
    if (cell_signed_volume(mesh, mesh.cell_count() - 1) >= 0.0) return;
    std::uint32_t* cv = mesh.cell_vertices(mesh.cell_count() - 1);
    std::swap(cv[1], cv[2]);
    if (type == CellType::Wedge) std::swap(cv[4], cv[5]);
}

CellMesh box_mesh(const VolumeParams& p) {
    const std::array<int, 3> n = box_divisions(p);
    CellMesh mesh;
    mesh.begin_block("volume");
    for (int k = 0; k <= n[2]; ++k)
        for (int j = 0; j <= n[1]; ++j)
            for (int i = 0; i <= n[0]; ++i)
                mesh.points.push_back(p.size * (glm::dvec3(double(i) / n[0], double(j) / n[1], double(k) / n[2]) - 0.5));
    auto id = [&](int i, int j, int k) { return std::uint32_t((k * (n[1] + 1) + j) * (n[0] + 1) + i); };
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                // VTK hexahedron order: the bottom quad counter-clockwise seen from +z, then the top.
                const std::uint32_t v[8] = {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                                            id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                mesh.add_cell(CellType::Hexahedron, v);
            }
    return mesh;
}

// The unit icosphere: an icosahedron whose triangles are cut into four `level` times, the new
// points pushed onto the sphere. Triangles counter-clockwise seen from outside.
void icosphere(int level, std::vector<glm::dvec3>& points, std::vector<std::array<std::uint32_t, 3>>& triangles) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    points = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::dvec3& q : points) q = glm::normalize(q);
    triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            const auto it = middle.find(key);
            if (it != middle.end()) return it->second;
            points.push_back(glm::normalize(points[a] + points[b]));
            return middle[key] = std::uint32_t(points.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> finer;
        for (const auto& tri : triangles) {
            const std::uint32_t a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
            finer.push_back({tri[0], a, c});
            finer.push_back({tri[1], b, a});
            finer.push_back({tri[2], c, b});
            finer.push_back({a, b, c});
        }
        triangles = std::move(finer);
    }
}

CellMesh sphere_mesh(const VolumeParams& p) {
    const int level = sphere_level(p);
    const int shells = sphere_shells(p);
    std::vector<glm::dvec3> unit;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    icosphere(level, unit, triangles);
    CellMesh mesh;
    mesh.begin_block("volume");
    mesh.points.push_back(glm::dvec3(0.0)); // the centre
    const std::uint32_t n = std::uint32_t(unit.size());
    for (int k = 1; k <= shells; ++k)
        for (const glm::dvec3& u : unit) mesh.points.push_back(u * (p.radius * k / shells));
    auto at = [&](int shell, std::uint32_t v) { return 1 + std::uint32_t(shell - 1) * n + v; }; // shell ≥ 1
    for (const auto& tri : triangles) {
        add_positive(mesh, CellType::Tetra, {0, at(1, tri[0]), at(1, tri[1]), at(1, tri[2]), 0, 0});
        for (int k = 1; k < shells; ++k)
            add_positive(mesh, CellType::Wedge,
                         {at(k, tri[0]), at(k, tri[1]), at(k, tri[2]), at(k + 1, tri[0]), at(k + 1, tri[1]), at(k + 1, tri[2])});
    }
    return mesh;
}

} // namespace

std::uint64_t max_cells(const VolumeParams& p) {
    switch (p.shape) {
    case VolumeShape::Box: {
        const std::array<int, 3> n = box_divisions(p);
        return std::uint64_t(n[0]) * std::uint64_t(n[1]) * std::uint64_t(n[2]);
    }
    case VolumeShape::Sphere: // 20·4^level surface triangles, a tetrahedron and shells − 1 wedges under each
        return (std::uint64_t(20) << (2 * sphere_level(p))) * std::uint64_t(sphere_shells(p));
    case VolumeShape::Mesh: return p.mesh ? p.mesh->cell_count() : 0;
    }
    return 0;
}

const char* volume_shape_name(VolumeShape shape) {
    switch (shape) {
    case VolumeShape::Box: return "box";
    case VolumeShape::Sphere: return "sphere";
    case VolumeShape::Mesh: return "mesh";
    }
    return "?";
}

const char* volume_density_name(VolumeDensity density) {
    switch (density) {
    case VolumeDensity::Constant: return "constant";
    case VolumeDensity::Noise: return "noise";
    case VolumeDensity::Field: return "field";
    }
    return "?";
}

Volume::Volume(const VolumeParams& params) : ParametricEffect("density"), params_(params) {
    validate(params_);
    if (params_.shape == VolumeShape::Mesh && params_.density_mode == VolumeDensity::Field) {
        const ScalarField* f = params_.field.empty() ? &params_.mesh->scalars[0] : params_.mesh->find_scalar(params_.field);
        field_range_ = fx::scalar_range(*f);
    }
}

void Volume::set_params(const VolumeParams& params) {
    Volume check(params); // validates, and the field's range
    parameters_changed(volume_change_cost(params_, params));
    params_ = params;
    field_range_ = check.field_range_;
}

bool Volume::animated() const {
    return params_.density_mode == VolumeDensity::Noise && (params_.noise.drift != glm::dvec3(0.0) || params_.noise.evolve != 0.0);
}

ScalarRange Volume::scalar_range() const {
    const double d = params_.density;
    if (params_.density_mode == VolumeDensity::Field)
        return {float(std::min(0.0, d * field_range_.lo)), float(std::max(d * field_range_.hi, 0.0))};
    return {0.0f, float(d)};
}

glm::dmat4 Volume::pose_at(double) const {
    const glm::dvec3 r = params_.rotation_degrees * kDegrees;
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), params_.position);
    m = glm::rotate(m, r.z, glm::dvec3(0, 0, 1));
    m = glm::rotate(m, r.y, glm::dvec3(0, 1, 0));
    return glm::rotate(m, r.x, glm::dvec3(1, 0, 0));
}

Bounds Volume::local_bounds() const {
    switch (params_.shape) {
    case VolumeShape::Box: return {-0.5 * params_.size, 0.5 * params_.size};
    case VolumeShape::Sphere: return {glm::dvec3(-params_.radius), glm::dvec3(params_.radius)};
    case VolumeShape::Mesh: return mesh_bounds(*params_.mesh);
    }
    return {};
}

double Volume::density_at(const glm::dvec3& local, double time) const {
    const VolumeParams& p = params_;
    const double e = p.shape == VolumeShape::Mesh ? 1.0 : edge(p, local);
    if (p.density_mode != VolumeDensity::Noise) return p.density * e;
    const glm::dvec4 q = noise_point(p.noise, local, time);
    const double n = Noise(p.noise.seed).fractal4(fractal_of(p.noise), q.x, q.y, q.z, q.w);
    return p.density * std::clamp(p.noise.coverage + p.noise.contrast * n, 0.0, 1.0) * e;
}

void Volume::build_mesh() {
    const VolumeParams& p = params_;
    field_.clear();
    if (p.shape == VolumeShape::Box) {
        mesh_ = box_mesh(p);
    } else if (p.shape == VolumeShape::Sphere) {
        mesh_ = sphere_mesh(p);
    } else {
        CellMesh m = *p.mesh;
        if (p.density_mode == VolumeDensity::Field)
            field_ = (p.field.empty() ? m.scalars[0] : *m.find_scalar(p.field)).values;
        m.scalars.clear();
        orient_cells(m);
        mesh_ = std::move(m);
    }
}

void Volume::evaluate_scalars(double time) {
    const VolumeParams& p = params_;
    std::vector<float>& d = mesh_.scalars[0].values;
    const std::size_t n = mesh_.points.size();
    if (p.density_mode == VolumeDensity::Field) {
        for (std::size_t i = 0; i < n; ++i) d[i] = float(p.density * field_[i]);
    } else if (p.density_mode == VolumeDensity::Constant) {
        for (std::size_t i = 0; i < n; ++i) d[i] = float(p.density * edge(p, mesh_.points[i]));
    } else {
        noise_points_.resize(n);
        noise_values_.resize(n);
        for (std::size_t i = 0; i < n; ++i) noise_points_[i] = noise_point(p.noise, mesh_.points[i], time);
        fill_points4(Noise(p.noise.seed), fractal_of(p.noise), noise_points_.data(), n, noise_values_.data());
        count_noise(n);
        for (std::size_t i = 0; i < n; ++i) {
            const double e = p.shape == VolumeShape::Mesh ? 1.0 : edge(p, mesh_.points[i]);
            d[i] = float(p.density * std::clamp(p.noise.coverage + p.noise.contrast * double(noise_values_[i]), 0.0, 1.0) * e);
        }
    }
}

} // namespace cellfx::fx
