#include "fx/camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "fx/cell_mesh.hpp"
#include "fx/effect.hpp" // rigid_part
#include "fx/error.hpp"

namespace cellfx::fx {

namespace {

// The narrowest view, as a fraction of the eye's distance to the target (Camera::validate).
constexpr double kMinViewHeight = 1e-6;

// v / |v| for any finite non-zero v: scaled by its largest component first, so that neither
// 1e-300 nor 1e300 under- or overflows the squares.
glm::dvec3 unit(const glm::dvec3& v) {
    const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return glm::normalize(v / m);
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

std::string vec(const glm::dvec3& v) { return "(" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + ")"; }

} // namespace

Camera::Basis Camera::basis() const {
    Basis b;
    b.forward = unit(target - eye);
    // Both factors are unit vectors at least 1e-6 rad apart (validate()): the cross product is
    // at least 1e-6 long, and unit() rescales it before its squares are formed.
    b.right = unit(glm::cross(b.forward, unit(up)));
    b.up = glm::cross(b.right, b.forward);
    return b;
}

double Camera::clipping_near(double mesh_size) const {
    return std::max(near_distance, std::isfinite(mesh_size) ? kMinNearFraction * mesh_size : 0.0);
}

glm::dvec3 Camera::forward() const { return unit(target - eye); }
glm::dvec3 Camera::right() const { return basis().right; }

glm::dmat4 Camera::view_matrix() const {
    // glm::lookAt's matrix, from the double basis: rows right, up, −forward.
    const Basis b = basis();
    glm::dmat4 m(1.0);
    for (int i = 0; i < 3; ++i) {
        m[i][0] = b.right[i];
        m[i][1] = b.up[i];
        m[i][2] = -b.forward[i];
    }
    m[3][0] = -glm::dot(b.right, eye);
    m[3][1] = -glm::dot(b.up, eye);
    m[3][2] = glm::dot(b.forward, eye);
    return m;
}

void Camera::validate(std::string_view who) const {
    // Messages are built only on the way out: a frame's check allocates nothing.
    const auto fail = [who](const std::string& what) { throw Error(std::string(who) + ": " + what); };
    if (!finite(eye) || !finite(target) || !finite(up)) fail("eye, target and up must be finite");
    for (const glm::dvec3* p : {&eye, &target}) {
        if (std::max({std::abs(p->x), std::abs(p->y), std::abs(p->z)}) > kMaxCoordinate)
            fail((p == &eye ? "eye " : "target ") + vec(*p) + " is beyond ±" + number(kMaxCoordinate) +
                 ", the coordinates cellfx renders");
    }
    const glm::dvec3 d = target - eye;
    if (d == glm::dvec3(0.0)) fail("eye and target coincide (at " + vec(eye) + ")");
    if (up == glm::dvec3(0.0)) fail("up is zero");
    // sin of the angle between up and the view direction.
    if (!(glm::length(glm::cross(unit(d), unit(up))) >= 1e-6))
        fail("up " + vec(up) + " is parallel to the view direction " + vec(unit(d)) +
             " (choose an up that is not along the line from eye to target)");
    if (!std::isfinite(ortho_height) || ortho_height < 0.0)
        fail("ortho height " + number(ortho_height) + " must be positive (or 0 for a perspective camera)");
    if (!orthographic() && !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0))
        fail("fov " + number(fov_y_degrees) + " must be in (0, 180) degrees");
    if (!(near_distance > 0.0) || !std::isfinite(near_distance) || !std::isfinite(far_distance))
        fail("near " + number(near_distance) + " must be positive and finite (and far finite)");
    if (!(far_distance > near_distance))
        fail("near " + number(near_distance) + " is not in front of far " + number(far_distance) + ": need 0 < near < far");
    // The GPU paths place pixels and cells in float relative to the eye: a view narrower than
    // a millionth of its distance to the target cannot be told apart from its neighbours.
    const double distance = glm::length(d);
    const double height = orthographic() ? ortho_height : 2.0 * distance * std::tan(0.5 * glm::radians(fov_y_degrees));
    if (!(height >= kMinViewHeight * distance))
        fail(std::string(orthographic() ? "ortho height " : "fov ") + number(orthographic() ? ortho_height : fov_y_degrees) +
             " gives a view " + number(height) + " high at the target, " + number(distance) +
             " away: narrower than 1e-6 of that distance, which float cannot resolve (widen the view or move the eye closer)");
}

glm::dmat4 Camera::projection_matrix(double aspect) const {
    if (projection) return *projection;
    if (orthographic()) {
        const double h = 0.5 * ortho_height;
        const double w = h * aspect;
        return glm::ortho(-w, w, -h, h, near_distance, far_distance);
    }
    return glm::perspective(glm::radians(fov_y_degrees), aspect, near_distance, far_distance);
}

Ray Camera::pixel_ray(double x, double y, int width, int height) const {
    if (projection) {
        // The pixel's points on the near and far planes, back through both matrices.
        const glm::dmat4 world_from_clip = glm::inverse(*projection * view_matrix());
        const glm::dvec2 ndc(2.0 * x / width - 1.0, 2.0 * y / height - 1.0);
        const glm::dvec4 a = world_from_clip * glm::dvec4(ndc, -1.0, 1.0);
        const glm::dvec4 b = world_from_clip * glm::dvec4(ndc, 1.0, 1.0);
        const glm::dvec3 near_point = glm::dvec3(a) / a.w, far_point = glm::dvec3(b) / b.w;
        const glm::dvec3 direction = glm::normalize(far_point - near_point);
        if (orthographic()) return Ray{near_point - direction * near_distance, direction};
        return Ray{eye, direction};
    }
    const Basis b = basis();
    const glm::dvec3 &f = b.forward, &r = b.right, &u = b.up;
    const double aspect = static_cast<double>(width) / height;
    // Normalised device coordinates of the point in [-1, 1].
    const double ndc_x = 2.0 * x / width - 1.0;
    const double ndc_y = 2.0 * y / height - 1.0;
    if (orthographic()) {
        const double h = 0.5 * ortho_height;
        return Ray{eye + r * (ndc_x * h * aspect) + u * (ndc_y * h), f};
    }
    const double t = std::tan(0.5 * glm::radians(fov_y_degrees));
    return Ray{eye, glm::normalize(f + r * (ndc_x * t * aspect) + u * (ndc_y * t))};
}

namespace {

double parse_number(std::string_view text, std::string_view key, std::string_view who) {
    const std::string s(text);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
        throw Error(std::string(who) + ": " + std::string(key) + ": '" + s + "' is not a finite number");
    }
    return v;
}

} // namespace

Camera Camera::parse(std::string_view spec, std::string_view who) {
    Camera cam;
    const std::string name(who);
    // Tokens are comma separated; a key=... starts a new value, bare numbers continue a vector.
    std::string key;
    std::vector<double> values;
    auto flush = [&]() {
        if (key.empty()) return;
        auto need = [&](std::size_t n) {
            if (values.size() != n) {
                throw Error(name + ": " + key + " needs " + std::to_string(n) + " number" + (n > 1 ? "s" : "") +
                            ", got " + std::to_string(values.size()));
            }
        };
        if (key == "eye") { need(3); cam.eye = {values[0], values[1], values[2]}; }
        else if (key == "target") { need(3); cam.target = {values[0], values[1], values[2]}; }
        else if (key == "up") { need(3); cam.up = {values[0], values[1], values[2]}; }
        else if (key == "fov") { need(1); cam.fov_y_degrees = values[0]; cam.ortho_height = 0.0; }
        else if (key == "ortho") {
            need(1);
            if (!(values[0] > 0.0)) throw Error(name + ": ortho=" + number(values[0]) + ": the height must be positive");
            cam.ortho_height = values[0];
        }
        else if (key == "near") { need(1); cam.near_distance = values[0]; }
        else if (key == "far") { need(1); cam.far_distance = values[0]; }
        else throw Error(name + ": unknown key '" + key + "' (expected eye, target, up, fov, ortho, near, far)");
        key.clear();
        values.clear();
    };
    std::size_t pos = 0;
    while (pos <= spec.size()) {
        std::size_t comma = spec.find(',', pos);
        if (comma == std::string_view::npos) comma = spec.size();
        std::string_view token = spec.substr(pos, comma - pos);
        const std::size_t eq = token.find('=');
        if (eq != std::string_view::npos) {
            flush();
            key = std::string(token.substr(0, eq));
            token = token.substr(eq + 1);
        } else if (key.empty() && !token.empty()) {
            throw Error(name + ": '" + std::string(token) + "' has no key (write e.g. eye=0,0,5)");
        }
        if (!token.empty() || eq != std::string_view::npos) values.push_back(parse_number(token, key, who));
        pos = comma + 1;
    }
    flush();
    cam.validate(who);
    return cam;
}

Camera Camera::from_matrices(const glm::dmat4& view, const glm::dmat4& projection) {
    const glm::dmat4 world_from_eye = glm::inverse(view);
    const glm::dmat4 rigid = rigid_part(world_from_eye, "camera: the view matrix");
    for (int c = 0; c < 4; ++c) {
        if (glm::length(world_from_eye[c] - rigid[c]) > 1e-6 * std::max(1.0, glm::length(rigid[c]))) {
            throw Error("camera: the view matrix is not a rigid motion (it scales or shears)");
        }
    }
    const glm::dmat4& p = projection; // p[column][row]
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(p[c][r])) throw Error("camera: the projection matrix is not finite");
        }
    }
    const bool perspective = p[2][3] == -1.0 && p[3][3] == 0.0;
    const bool ortho = p[2][3] == 0.0 && p[3][3] == 1.0;
    // Both forms leave x and y unmixed and z independent of x and y (no shear).
    if ((!perspective && !ortho) || p[0][1] != 0.0 || p[0][2] != 0.0 || p[0][3] != 0.0 || p[1][0] != 0.0 ||
        p[1][2] != 0.0 || p[1][3] != 0.0 || (ortho && (p[2][0] != 0.0 || p[2][1] != 0.0)) ||
        (perspective && (p[3][0] != 0.0 || p[3][1] != 0.0)) || !(p[0][0] > 0.0) || !(p[1][1] > 0.0)) {
        throw Error("camera: the projection matrix is neither a perspective frustum nor an orthographic box "
                    "(glFrustum / glOrtho form)");
    }
    Camera cam;
    cam.eye = glm::dvec3(rigid[3]);
    cam.target = cam.eye - glm::dvec3(rigid[2]); // the eye looks down its −z
    cam.up = glm::dvec3(rigid[1]);
    if (perspective) {
        cam.near_distance = p[3][2] / (p[2][2] - 1.0);
        cam.far_distance = p[3][2] / (p[2][2] + 1.0);
        cam.fov_y_degrees = glm::degrees(2.0 * std::atan(1.0 / p[1][1]));
    } else {
        cam.near_distance = (p[3][2] + 1.0) / p[2][2];
        cam.far_distance = (p[3][2] - 1.0) / p[2][2];
        cam.ortho_height = 2.0 / p[1][1];
    }
    if (!(cam.near_distance > 0.0) || !(cam.far_distance > cam.near_distance) || !std::isfinite(cam.far_distance)) {
        throw Error("camera: the projection matrix's depth range is not 0 < near < far");
    }
    cam.projection = projection;
    return cam;
}

Camera Camera::framing(const glm::dvec3& lo, const glm::dvec3& hi, double fov_y_degrees) {
    Camera cam;
    cam.fov_y_degrees = fov_y_degrees;
    cam.target = 0.5 * (lo + hi);
    // Scale-free: a mesh of 1e-20 is framed like one of 1e15 (a single point gets a radius
    // relative to its distance from the origin).
    double radius = 0.5 * glm::length(hi - lo);
    if (!(radius > 0.0)) radius = std::max(1e-6 * std::max({std::abs(cam.target.x), std::abs(cam.target.y), std::abs(cam.target.z)}), 1e-300);
    const double distance = radius / std::sin(0.5 * glm::radians(fov_y_degrees)) * 1.05;
    cam.eye = cam.target + glm::normalize(glm::dvec3(1.0, 0.8, 1.2)) * distance;
    cam.up = glm::dvec3(0.0, 0.0, 1.0);
    cam.near_distance = std::max(distance - 1.5 * radius, distance * 1e-3);
    cam.far_distance = distance + 1.5 * radius;
    return cam;
}

} // namespace cellfx::fx
