#include "core/predicates.hpp"

#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }
}  // namespace

int orient3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return int(CGAL::orientation(cgal(a), cgal(b), cgal(c), cgal(d)));
}

// A floating-point evaluation decides
// when its value exceeds a forward error bound (36 units in the last place of the permanent,
// several times the worst case of the 2 subtractions, 2 products and 5 additions per term, plus
// an absolute term for products that fall into the subnormal range, where the relative bound
// fails: each of the 12 products then errs by up to 2^-1075, scaled by |w| for the first);
// otherwise the determinant is recomputed in exact rational arithmetic.
int orient3_dir(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& w) {
    const glm::dvec3 e = b - a, g = c - a;
    const double t0 = e.y * g.z * w.x, t1 = e.z * g.y * w.x, t2 = e.z * g.x * w.y, t3 = e.x * g.z * w.y,
                 t4 = e.x * g.y * w.z, t5 = e.y * g.x * w.z;
    const double det = (t0 - t1) + (t2 - t3) + (t4 - t5);
    const double perm = std::abs(t0) + std::abs(t1) + std::abs(t2) + std::abs(t3) + std::abs(t4) + std::abs(t5);
    const double underflow = 0x1p-1066 * (1.0 + std::abs(w.x) + std::abs(w.y) + std::abs(w.z));
    const double bound = 36.0 * 1.1102230246251565e-16 * perm + underflow;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    using Q = CGAL::Exact_rational;
    const Q ex = Q(b.x) - Q(a.x), ey = Q(b.y) - Q(a.y), ez = Q(b.z) - Q(a.z);
    const Q gx = Q(c.x) - Q(a.x), gy = Q(c.y) - Q(a.y), gz = Q(c.z) - Q(a.z);
    const Q d = (ey * gz - ez * gy) * Q(w.x) + (ez * gx - ex * gz) * Q(w.y) + (ex * gy - ey * gx) * Q(w.z);
    return CGAL::sign(d);
}

int orient_eye(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    if (camera.is_ortho()) return orient3_dir(a, b, c, -camera.forward());
    return orient3(a, b, c, camera.eye());
}

int image_orientation(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    // Pixel coordinates are (right, -up) of d = p - eye divided by forward . d (perspective), and
    // (right, -up, forward) is a right-handed frame; see tests/test_crossings.cpp.
    if (camera.is_ortho()) return orient3_dir(a, b, c, camera.forward());
    return int(CGAL::orientation(cgal(camera.eye()), cgal(a), cgal(b), cgal(c)));
}

}  // namespace inkline
