// cellfx — a pinhole or orthographic camera shared by every render path.
//
// Conventions (OpenGL's): the view looks down −z in eye space; image pixel (x, y) has its
// centre at (x + 0.5, y + 0.5) with y = 0 the BOTTOM row, as glReadPixels returns it.
// `near_distance` is the distance from the eye to the near plane along the view direction;
// everything in front of it is drawn, everything behind is clipped (a camera inside a mesh
// sees what lies ahead of it).
#pragma once

#include <string_view>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace fx {

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
    double near_distance = 0.01;
    double far_distance = 1.0e4;

    bool orthographic() const { return ortho_height > 0.0; }
    glm::dvec3 forward() const; // unit view direction

    glm::dmat4 view_matrix() const;                       // world → eye
    glm::dmat4 projection_matrix(double aspect) const;    // eye → GL clip space
    // The ray through the centre of pixel (x, y) of a width × height image. For perspective
    // cameras it starts at the eye; for orthographic ones on the plane through the eye.
    Ray pixel_ray(double x, double y, int width, int height) const;

    // Parses "eye=x,y,z,target=x,y,z,up=x,y,z,fov=DEG" or with "ortho=HEIGHT" instead of fov;
    // near=D and far=D are accepted too. Any key may be left out. Throws fx::Error naming
    // the bad key or number.
    static Camera parse(std::string_view spec);
    // A view of `lo`..`hi` from the (+x, +y, +z) diagonal that fits the whole box.
    static Camera framing(const glm::dvec3& lo, const glm::dvec3& hi, double fov_y_degrees = 40.0);
};

} // namespace fx
