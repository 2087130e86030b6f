// A random perspective camera looking at a model (tests that run the pipeline over many views).
#pragma once

#include <cmath>
#include <random>

#include "core/camera.hpp"
#include "model/topology.hpp"

namespace inkline {

// Direction uniform on the sphere, field of view 25-50 degrees, the target within a fifth of the
// model's half diagonal of its centre, and the distance a random share in [near, near + span) of
// the framing distance (below 1: part of the model is out of the image).
inline Camera random_camera(std::mt19937& rng, const Bounds3& box, double near = 0.7, double span = 0.8) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double z = 2.0 * u(rng) - 1.0, phi = 2.0 * M_PI * u(rng), s = std::sqrt(1.0 - z * z);
    const glm::dvec3 dir(s * std::cos(phi), z, s * std::sin(phi));
    const double fov = 25.0 + 25.0 * u(rng), R = box.half_diagonal();
    const double dist = R / std::sin(fov * M_PI / 360.0) * (near + span * u(rng));
    const glm::dvec3 target = box.center() + 0.2 * R * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    const glm::dvec3 up = std::abs(dir.y) > 0.95 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return Camera::perspective(target + dist * dir, target, up, fov, 1024, 1024);
}

}  // namespace inkline
