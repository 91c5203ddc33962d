// The searchlight sample's moving object: a drone circling the hill that carries the scene's
// "patrol" light (content/scenes/searchlight.json places that light at (0, −150, 26), looking
// at the hill; the drone takes it round the hill once every kDronePeriod seconds, 24 m higher).
#pragma once

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

namespace cellfx_samples {

constexpr double kDronePeriod = 24.0;            // seconds per circle
constexpr double kDroneLift = 24.0;              // metres above the light's place in the scene
inline const glm::dvec3 kPatrolLens{0.0, -150.0, 26.0}; // the light's position in the scene file

// The parent transform of the patrol light at scene time t: a turn about the vertical axis
// through the hill's centre, lifted by kDroneLift.
inline glm::dmat4 drone_parent_transform(double t) {
    const double angle = 2.0 * M_PI * t / kDronePeriod;
    return glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, kDroneLift)), angle, glm::dvec3(0.0, 0.0, 1.0));
}

// The drone's body (unit cube → world): 6 × 3 × 1.5 m just above the lens, long side along the
// direction of flight (+x at the start, where it flies tangentially).
inline glm::dmat4 drone_body_transform(double t) {
    return glm::scale(glm::translate(drone_parent_transform(t), kPatrolLens + glm::dvec3(0.0, 0.0, 1.4)), glm::dvec3(6.0, 3.0, 1.5));
}

} // namespace cellfx_samples
