// Orientation predicates for the visibility stage's inner loops, exact and inlined: a float
// evaluation decides when it exceeds a forward error bound (Shewchuk's first-stage bounds, taken
// with a margin, plus an absolute term for products in the subnormal range); otherwise CGAL's
// exact predicate decides. Same signs as CGAL::orientation and inkline::orient3 / orient_eye.
// The absolute terms are normal numbers (at least DBL_MIN, more than the subnormal error needs):
// arithmetic on a subnormal constant costs a microcode assist on every call
// (bench/results/visibility.md).
#pragma once

#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/predicates.hpp"

namespace inkline {

// Sign of (b - a) x (c - a): positive when c is left of the directed line a -> b.
inline int orient2_exact(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    return int(CGAL::orientation(K::Point_2(a.x, a.y), K::Point_2(b.x, b.y), K::Point_2(c.x, c.y)));
}
inline int orient2_fast(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    const double l = (b.x - a.x) * (c.y - a.y), r = (b.y - a.y) * (c.x - a.x);
    const double det = l - r;
    // Shewchuk's ccwerrboundA is (3 + 16 eps) eps; 8 eps leaves a margin.
    const double bound = 8.0 * 1.1102230246251565e-16 * (std::abs(l) + std::abs(r)) + 0x1p-1022;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient2_exact(a, b, c);
}

// For a segment (q0, q1) with its ends strictly on either side of the horizontal line through u
// (q0.y < u.y < q1.y or q1.y < u.y < q0.y; otherwise the result may differ from that orientation):
// orient2(lower end, upper end, u), which is the sign of
// x - u.x where the segment meets that line (the orientation is (upper.y - lower.y) (x - u.x),
// exactly). Where both ends lie before u.x, or both after it, so does the meeting point: decided
// by comparisons; otherwise by orient2_fast, negated when q0 is the upper end (swapping the first
// two points negates an orientation, exactly).
inline int path_side_fast(glm::dvec2 q0, glm::dvec2 q1, glm::dvec2 u) {
    if (q0.x < u.x && q1.x < u.x) return -1;
    if (q0.x > u.x && q1.x > u.x) return 1;
    const int s = orient2_fast(q0, q1, u);
    return q0.y > q1.y ? -s : s;
}

// orient3_fast: core/predicates.hpp (the loading's topology uses it too).

// orient_eye (core/predicates.hpp).
inline int orient_eye_fast(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    if (camera.is_ortho()) return orient_eye(camera, a, b, c);
    return orient3_fast(a, b, c, camera.eye());
}

}  // namespace inkline
