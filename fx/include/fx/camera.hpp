// cellfx — a pinhole or orthographic camera shared by every render path.
//
// Conventions (OpenGL's): the view looks down −z in eye space; image pixel (x, y) has its
// centre at (x + 0.5, y + 0.5) with y = 0 the BOTTOM row, as glReadPixels returns it.
// `near_distance` is the distance from the eye to the near plane along the view direction;
// everything in front of it is drawn, everything behind is clipped (a camera inside a mesh
// sees what lies ahead of it).
#pragma once

#include <optional>
#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace cellfx::fx {

// The nearest any render path cuts cells, as a fraction of the mesh's size (the diagonal of
// its bounding box): a near plane closer than that is moved out to it (Camera::clipping_near).
// What that leaves out is at most this fraction of a ray through the mesh, far below what a
// float image resolves; what it prevents is a near plane so close that screen depths overflow
// (the scan-line renderer drew nothing with near = 1e-38 inside a mesh of size 1).
// near_distance itself may be any positive number.
constexpr double kMinNearFraction = 1e-9;

struct Ray {
    glm::dvec3 origin;
    glm::dvec3 direction; // unit length
};

// A rectangle of the framebuffer, in pixels, (x, y) its lower left corner (glViewport's).
struct Viewport {
    int x = 0, y = 0, width = 0, height = 0;
};

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 5.0};
    glm::dvec3 target{0.0, 0.0, 0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double fov_y_degrees = 45.0; // vertical field of view of a perspective camera
    double ortho_height = 0.0;   // > 0: orthographic, this many world units tall
    double near_distance = 0.01; // any positive value; renderers cut at clipping_near()
    // Bounds the host's depth buffer (a scene depth is read with it). No path cuts cells at the
    // far plane: the scan-line renderer ignores it, and the GPU paths rasterise with it at
    // infinity (perspective) or moved past the mesh (orthographic).
    double far_distance = 1.0e4;
    // An explicit eye → clip matrix, for a host whose frustum the fields above cannot describe
    // (off-axis, or one tile of a larger image, as VTK draws tiles). When set,
    // projection_matrix() returns it for any aspect; the fields still describe the same view
    // (eye, direction, near and far exactly; fov or ortho height by the frustum's height).
    // from_matrices() sets it. The GPU paths follow it; the scan-line renderer rejects it.
    std::optional<glm::dmat4> projection;

    // The image's orthonormal frame in world space, built in double: forward the unit view
    // direction, right = forward × up and up' = right × forward, each normalised from vectors
    // scaled by their largest component first, so that an `up` of any length (1e-300, 1e300)
    // or nearly along the view gives the frame of its direction. Every render path takes its
    // frame from here (or from view_matrix(), built from it) and converts to float only after.
    // Meaningful for a camera that passes validate().
    struct Basis {
        glm::dvec3 right, up, forward;
    };
    Basis basis() const;

    bool orthographic() const { return ortho_height > 0.0; }
    // The near plane a renderer of a mesh `mesh_size` across (its bounding box's diagonal)
    // cuts at: near_distance, or kMinNearFraction·mesh_size when that is farther. Every path,
    // CPU and GPU, cuts there, so a near of 1e-300 gives every path the same picture.
    double clipping_near(double mesh_size) const;
    glm::dvec3 forward() const; // unit view direction
    // The unit right vector of the image: basis().right.
    glm::dvec3 right() const;

    // Throws fx::Error, starting with `who` ("camera", "scene.json: camera"), unless the camera
    // can take a picture: every number finite and eye and target within ±kMaxCoordinate;
    // eye ≠ target; up non-zero and at least 1e-6 rad away from the view direction (any length:
    // it is scaled before use, so 1e-300 works as well as 1); perspective fov in (0, 180) or
    // ortho height > 0 (ortho_height < 0 is an error, not a perspective camera);
    // 0 < near < far; the view at the target at least 1e-6 of the eye's distance to it tall (a
    // narrower one float cannot resolve). Every render path calls it (no allocation unless it
    // throws).
    void validate(std::string_view who) const;

    glm::dmat4 view_matrix() const;                       // world → eye
    glm::dmat4 projection_matrix(double aspect) const;    // eye → GL clip space
    // The ray through the centre of pixel (x, y) of a width × height image. For perspective
    // cameras it starts at the eye; for orthographic ones on the plane through the eye.
    Ray pixel_ray(double x, double y, int width, int height) const;

    // Parses "eye=x,y,z,target=x,y,z,up=x,y,z,fov=DEG" or with "ortho=HEIGHT" instead of fov;
    // near=D and far=D are accepted too. Any key may be left out. Throws fx::Error, starting
    // with `who` ("--camera"), naming the bad key or number, or what validate() finds.
    static Camera parse(std::string_view spec, std::string_view who = "camera");
    // The camera of a host's GL matrices: `view` world → eye (a rigid motion), `projection`
    // eye → clip, a perspective frustum or an orthographic box (glFrustum / glOrtho form,
    // off-axis allowed, GL's [−1, 1] depth). Throws fx::Error naming the matrix and what is
    // wrong for anything else (scale or shear in the view, a sheared or reversed projection).
    static Camera from_matrices(const glm::dmat4& view, const glm::dmat4& projection);
    // A view of `lo`..`hi` from the (+x, +y, +z) diagonal that fits the whole box.
    static Camera framing(const glm::dvec3& lo, const glm::dvec3& hi, double fov_y_degrees = 40.0);
};

} // namespace cellfx::fx
