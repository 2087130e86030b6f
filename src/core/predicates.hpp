// Exact geometric predicates on double coordinates (CGAL's filtered predicates, or a float filter
// with an exact rational fallback), including the camera's eye as a point (perspective) or as the
// point at infinity behind the image plane (orthographic).
#pragma once
#include <cmath>

#include <glm/vec3.hpp>

#include "core/camera.hpp"

namespace inkline {

// Sign of the orientation of four points: sign det[b - a, c - a, d - a] (CGAL convention:
// positive when d is on the positive side of the oriented plane abc, i.e. abc counter-clockwise
// seen from d).
int orient3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

// orient3, inlined with a float filter first: a float evaluation decides when it exceeds a
// forward error bound (Shewchuk's first-stage bound with a margin, plus an absolute term for
// products in the subnormal range), else orient3. The same signs as orient3.
inline int orient3_fast(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    const glm::dvec3 e = b - a, f = c - a, g = d - a;
    const double m0 = f.y * g.z, m1 = f.z * g.y, m2 = f.x * g.z, m3 = f.z * g.x, m4 = f.x * g.y, m5 = f.y * g.x;
    const double det = e.x * (m0 - m1) - e.y * (m2 - m3) + e.z * (m4 - m5);
    const double perm = std::abs(e.x) * (std::abs(m0) + std::abs(m1)) + std::abs(e.y) * (std::abs(m2) + std::abs(m3)) +
                        std::abs(e.z) * (std::abs(m4) + std::abs(m5));
    // Shewchuk's o3derrboundA is (7 + 56 eps) eps; 16 eps leaves a margin. A product m that falls
    // into the subnormal range errs by up to 2^-1075, then scaled by e.
    const double bound = 16.0 * 1.1102230246251565e-16 * perm +
                         0x1p-1022 * (1.0 + std::abs(e.x) + std::abs(e.y) + std::abs(e.z));
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient3(a, b, c, d);
}

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
