// Exact geometric predicates on double coordinates (CGAL's filtered predicates, or a float filter
// with an exact rational fallback), including the camera's eye as a point (perspective) or as the
// point at infinity behind the image plane (orthographic).
#pragma once
#include <glm/vec3.hpp>

#include "core/camera.hpp"

namespace inkline {

// Sign of the orientation of four points: sign det[b - a, c - a, d - a] (CGAL convention:
// positive when d is on the positive side of the oriented plane abc, i.e. abc counter-clockwise
// seen from d).
int orient3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

// Sign of det[b - a, c - a, w] for a direction w, exactly.
int orient3_dir(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& w);

// orient3(a, b, c, eye) for the camera's eye; for an orthographic camera the eye is the point at
// infinity in direction -forward, so this is orient3_dir(a, b, c, -forward).
int orient_eye(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// Sign of the orientation of the images of a, b, c (the sign CGAL::orientation gives on their
// exact pixel coordinates), decided exactly in 3D: orient3(eye, a, b, c) for a
// perspective camera, orient3_dir(a, b, c, forward) for an orthographic one. The points must lie
// in front of the eye plane (the image of a point behind the eye is mirrored).
int image_orientation(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

}  // namespace inkline
