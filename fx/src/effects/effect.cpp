// The effect interface's shared half: update bookkeeping, placement, frustum test.
#include "fx/effect.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"

namespace cellfx::fx {

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// The rigid part of m, or the reason it has none (a message tail; nullptr when it has one).
// Messages are built by the callers only on failure: a frame's transforms allocate nothing.
const char* rigid_part_of(const glm::dmat4& m, glm::dmat4& r) {
    if (!finite(m)) return "not finite";
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
        return "the bottom row must be (0, 0, 0, 1) (no projection)";
    const glm::dvec3 a(m[0]), b(m[1]), c(m[2]);
    const double la = glm::length(a);
    if (!(la > 0.0)) return "singular (its x axis is zero)";
    const glm::dvec3 x = a / la;
    const glm::dvec3 yb = b - glm::dot(b, x) * x;
    const double ly = glm::length(yb);
    if (!(ly > 1e-12 * std::max(glm::length(b), 1e-300))) return "singular (its y axis is zero or along x)";
    const glm::dvec3 y = yb / ly;
    const glm::dvec3 z = glm::cross(x, y);
    const double dz = glm::dot(z, c);
    if (!(std::abs(dz) > 1e-12 * std::max(glm::length(c), 1e-300))) return "singular (its z axis is zero or in the xy plane)";
    if (dz < 0.0) return "mirrors (negative determinant); effects need a rotation";
    r = glm::dmat4(1.0);
    r[0] = glm::dvec4(x, 0.0);
    r[1] = glm::dvec4(y, 0.0);
    r[2] = glm::dvec4(z, 0.0);
    r[3] = glm::dvec4(glm::dvec3(m[3]), 1.0);
    return nullptr;
}

} // namespace

bool renderable_coordinates(const glm::dvec3& v) {
    return std::abs(v.x) <= kMaxCoordinate && std::abs(v.y) <= kMaxCoordinate && std::abs(v.z) <= kMaxCoordinate;
}

bool renderable_length(double length) { return length > 0.0 && length <= kMaxCoordinate; }

void check_effect_cells(std::uint64_t cells, const std::string& what) { check_limit(Limit::EffectCells, cells, what); }

Effect::Effect(std::string scalar_name) : scalar_name_(std::move(scalar_name)) {}

EffectChanges Effect::update(const EffectView& view) {
    const Camera& c = view.camera;
    if (!std::isfinite(view.time)) throw Error(std::string(type_name()) + ": the scene time is not finite");
    if (!finite(c.eye) || !finite(c.target) || !finite(c.up))
        throw Error(std::string(type_name()) + ": the camera is not finite");
    if (view.viewport_width < 1 || view.viewport_height < 1)
        throw Error(std::string(type_name()) + ": the viewport is empty");
    ++counters_.updates;
    EffectChanges changes = simulate(view);
    if (changes.mesh && !lists_mesh_changes_) mesh_changes_.whole = true;
    const glm::dmat4 t = transform_at(view.time);
    if (!placed_ || t != transform_) changes.pose = true;
    transform_ = t;
    placed_ = true;
    return changes;
}

glm::dmat4 Effect::pose_at(double) const { return glm::dmat4(1.0); }

void Effect::set_parent_transform(const glm::dmat4& parent) {
    glm::dmat4 r;
    if (const char* problem = rigid_part_of(parent, r))
        throw Error(std::string(type_name()) + ": parent transform: " + problem);
    parent_ = parent;
}

glm::dmat4 Effect::transform_at(double time) const {
    glm::dmat4 r;
    if (const char* problem = rigid_part_of(parent_ * pose_at(time), r))
        throw Error(std::string(type_name()) + ": transform: " + problem);
    return r;
}

Bounds Effect::world_bounds(double time) const { return transform_bounds(local_bounds(), transform_at(time)); }

glm::dmat4 rigid_part(const glm::dmat4& m, std::string_view what) {
    glm::dmat4 r;
    if (const char* problem = rigid_part_of(m, r)) throw Error(std::string(what) + ": " + problem);
    return r;
}

glm::dmat4 frame_along(const glm::dvec3& position, const glm::dvec3& direction) {
    if (!finite(position)) throw Error("effect placement: the position is not finite");
    const double l = glm::length(direction);
    if (!finite(direction) || !(l > 0.0)) throw Error("effect placement: the direction is zero or not finite");
    const glm::dvec3 z = direction / l;
    // Reference: world +x projected off the axis, unless the axis is close to x (then +y).
    const glm::dvec3 ref = std::abs(z.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 x = glm::normalize(ref - glm::dot(ref, z) * z);
    const glm::dvec3 y = glm::cross(z, x);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(x, 0.0);
    m[1] = glm::dvec4(y, 0.0);
    m[2] = glm::dvec4(z, 0.0);
    m[3] = glm::dvec4(position, 1.0);
    return m;
}

Camera camera_in_frame(const Camera& camera, const glm::dmat4& world_from_local) {
    const glm::dmat3 r(world_from_local);
    const glm::dmat3 rt = glm::transpose(r); // rigid: the inverse rotation
    const glm::dvec3 t(world_from_local[3]);
    Camera local = camera;
    local.eye = rt * (camera.eye - t);
    local.target = rt * (camera.target - t);
    local.up = rt * camera.up;
    return local;
}

Bounds transform_bounds(const Bounds& bounds, const glm::dmat4& m) {
    if (bounds.empty()) return bounds;
    Bounds out{glm::dvec3(HUGE_VAL), glm::dvec3(-HUGE_VAL)};
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 p(m * glm::dvec4(bounds.corner(k), 1.0));
        out.lo = glm::min(out.lo, p);
        out.hi = glm::max(out.hi, p);
    }
    return out;
}

Frustum::Frustum(const Camera& camera, double aspect) : origin(camera.eye) {
    // Row r of the view-projection (of the camera moved to the origin): clip coordinate r of a
    // point relative to the eye. Plane p of the six:
    // w + x ≥ 0, w − x ≥ 0, w + y ≥ 0, w − y ≥ 0, w + z ≥ 0, w − z ≥ 0.
    const Camera relative = camera_in_frame(camera, glm::translate(glm::dmat4(1.0), camera.eye));
    const glm::dmat4 vp = relative.projection_matrix(aspect) * relative.view_matrix();
    const auto row = [&vp](int r) { return glm::dvec4(vp[0][r], vp[1][r], vp[2][r], vp[3][r]); };
    for (int p = 0; p < 6; ++p) planes[p] = row(3) + ((p % 2) ? -1.0 : 1.0) * row(p / 2);
}

bool Frustum::intersects(const Bounds& box) const {
    if (box.empty()) return false;
    for (const glm::dvec4& plane : planes) {
        // The corner furthest along the plane's normal: outside with it, outside with all.
        const glm::dvec3 corner =
            box.corner((plane.x >= 0.0 ? 1 : 0) | (plane.y >= 0.0 ? 2 : 0) | (plane.z >= 0.0 ? 4 : 0)) - origin;
        if (plane.x * corner.x + plane.y * corner.y + plane.z * corner.z + plane.w < 0.0) return false;
    }
    return true;
}

bool bounds_in_view(const Bounds& bounds, const Camera& camera, double aspect) {
    return Frustum(camera, aspect).intersects(bounds);
}

} // namespace cellfx::fx
