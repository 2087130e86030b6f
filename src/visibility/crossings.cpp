#include "visibility/crossings.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/predicates.hpp"
#include "visibility/fast_orient.hpp"

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Q = CGAL::Exact_rational;
K::Point_2 cgal(const glm::dvec2& p) { return {p.x, p.y}; }
double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// num / den in double, unless the operands left the normal range (a subnormal or zero
// denominator from underflow, an infinite value from overflow): then the quotient of the exact
// values, given as functions, rounded once. Only for coordinates far outside any image.
template <class Num, class Den>
double quotient(double num, double den, Num exact_num, Den exact_den) {
    if (std::abs(den) >= DBL_MIN && std::isfinite(den) && std::isfinite(num)) return num / den;
    const Q d = exact_den();
    if (CGAL::sign(d) == CGAL::ZERO) return 0.0;  // not reached for inputs the predicates accepted
    return CGAL::to_double(Q(exact_num() / d));
}
Q qdot(glm::dvec2 p, glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {  // (p - o) . (b - a)
    return (Q(p.x) - Q(o.x)) * (Q(b.x) - Q(a.x)) + (Q(p.y) - Q(o.y)) * (Q(b.y) - Q(a.y));
}
Q qcross(glm::dvec2 p, glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {  // (p - o) x (b - a)
    return (Q(p.x) - Q(o.x)) * (Q(b.y) - Q(a.y)) - (Q(p.y) - Q(o.y)) * (Q(b.x) - Q(a.x));
}
}  // namespace

int segment_crossings(const Segment2& q, const Segment2& o, double t[2]) {
    if (q.v0 == o.v0 || q.v0 == o.v1 || q.v1 == o.v0 || q.v1 == o.v1) return 0;
    if (q.a == q.b || o.a == o.b) return 0;
    // Disjoint bounding boxes (comparisons of the inputs: exact) cannot meet.
    if (std::max(q.a.x, q.b.x) < std::min(o.a.x, o.b.x) || std::max(o.a.x, o.b.x) < std::min(q.a.x, q.b.x) ||
        std::max(q.a.y, q.b.y) < std::min(o.a.y, o.b.y) || std::max(o.a.y, o.b.y) < std::min(q.a.y, q.b.y))
        return 0;
    const int s0 = orient2_fast(q.a, q.b, o.a), s1 = orient2_fast(q.a, q.b, o.b);
    if (s0 != 0 && s0 == s1) return 0;
    const int s2 = orient2_fast(o.a, o.b, q.a), s3 = orient2_fast(o.a, o.b, q.b);
    if (s2 != 0 && s2 == s3) return 0;
    const K::Point_2 qa = cgal(q.a), qb = cgal(q.b), oa = cgal(o.a), ob = cgal(o.b);
    const glm::dvec2 d = q.b - q.a;
    if (s0 == 0 && s1 == 0) {
        // Collinear: the exact test above only says the lines agree; the overlap must be checked.
        if (!CGAL::do_intersect(K::Segment_2(qa, qb), K::Segment_2(oa, ob))) return 0;
        const double dd = glm::dot(d, d);
        auto qdd = [&] { return qdot(q.b, q.a, q.a, q.b); };
        double u0 = quotient(glm::dot(o.a - q.a, d), dd, [&] { return qdot(o.a, q.a, q.a, q.b); }, qdd);
        double u1 = quotient(glm::dot(o.b - q.a, d), dd, [&] { return qdot(o.b, q.a, q.a, q.b); }, qdd);
        if (u0 > u1) std::swap(u0, u1);
        t[0] = std::clamp(u0, 0.0, 1.0);
        t[1] = std::clamp(u1, 0.0, 1.0);
        return t[0] == t[1] ? 1 : 2;
    }
    // Proper crossing or touch: the exact predicates said they meet; the parameter is a
    // construction, computed in double (exactly, then rounded, if that under- or overflows) and
    // clamped to the segment.
    const glm::dvec2 e = o.b - o.a;
    const double den = cross(d, e);
    auto qdd = [&] { return qdot(q.b, q.a, q.a, q.b); };
    double u;
    if (s0 == 0)
        u = quotient(glm::dot(o.a - q.a, d), glm::dot(d, d), [&] { return qdot(o.a, q.a, q.a, q.b); }, qdd);
    else if (s1 == 0)
        u = quotient(glm::dot(o.b - q.a, d), glm::dot(d, d), [&] { return qdot(o.b, q.a, q.a, q.b); }, qdd);
    else if (s2 == 0) u = 0.0;
    else if (s3 == 0) u = 1.0;
    else u = quotient(cross(o.a - q.a, e), den, [&] { return qcross(o.a, q.a, o.a, o.b); },
                      [&] { return qcross(q.b, q.a, o.a, o.b); });
    t[0] = std::clamp(u, 0.0, 1.0);
    return 1;
}

// The projection (core/camera.cpp) computes d = P - E (error up to eps M per coordinate, with
// M = |P|_1 + |E|_1), its dot products X, Y, Z with the unit frame vectors (a few eps M more each;
// the frame itself is within a few eps of orthonormal), then x = W/2 + F X / Z: the quotient errs
// by (4 eps M / Z) (1 + |X| / Z), so x by 4 eps (M / Z) (F + |x - W/2|), plus a few eps (|x| + W)
// for the last operations; the same for y. Orthographic: x = W/2 + F X errs by 4 eps F M plus the
// last roundings. The bound below takes 64 eps over the sum of both terms (and the depth itself
// less its own error): a filter, never a tolerance (docs/tolerances.md). Infinite when the point
// is so near the eye plane that its depth has no correct bit.
double image_slack(const Camera& camera, const glm::dvec3& P, const glm::dvec2& p) {
    constexpr double kEps = 0x1p-53;
    const glm::dvec3 E = camera.eye();
    const double M = std::abs(P.x) + std::abs(P.y) + std::abs(P.z) + std::abs(E.x) + std::abs(E.y) + std::abs(E.z);
    const double W = camera.width(), H = camera.height();
    double lever;
    if (camera.is_ortho()) {
        lever = camera.focal() * M;
    } else {
        const double z = camera.depth(P) - 8.0 * kEps * M;
        if (!(z > 0.0)) return INFINITY;
        lever = M / z * (camera.focal() + std::abs(p.x - 0.5 * W) + std::abs(p.y - 0.5 * H));
    }
    return 64.0 * kEps * (W + H + std::abs(p.x) + std::abs(p.y) + lever);
}

namespace {
// Order along an image line of two points whose images lie on the line of `l` (exactly): the sign
// of the position of y minus that of x, in the direction *l.LA -> *l.LB.
int image_order(const Camera& camera, const Segment3& l, const glm::dvec3& x, const glm::dvec3& y) {
    if (!camera.is_ortho()) {
        // In the plane through the eye and the line, positions along the image line are angles
        // around the eye: compare the turn from x to y with the turn from LA to LB.
        const K::Point_3 e(camera.eye().x, camera.eye().y, camera.eye().z);
        const auto turn = CGAL::coplanar_orientation(e, K::Point_3(x.x, x.y, x.z), K::Point_3(y.x, y.y, y.z));
        if (turn == CGAL::COLLINEAR) return 0;
        const auto ref = CGAL::coplanar_orientation(e, K::Point_3(l.LA->x, l.LA->y, l.LA->z),
                                                    K::Point_3(l.LB->x, l.LB->y, l.LB->z));
        return turn == ref ? 1 : -1;
    }
    // Orthographic: the component of y - x across the view direction f, along LB - LA:
    // ((y - x) . g) (f . f) - ((y - x) . f) (g . f) with g = LB - LA, in exact rationals.
    const glm::dvec3 f = camera.forward();
    const Q fx(f.x), fy(f.y), fz(f.z);
    const Q dx = Q(y.x) - Q(x.x), dy = Q(y.y) - Q(x.y), dz = Q(y.z) - Q(x.z);
    const Q gx = Q(l.LB->x) - Q(l.LA->x), gy = Q(l.LB->y) - Q(l.LA->y), gz = Q(l.LB->z) - Q(l.LA->z);
    const Q v = (dx * gx + dy * gy + dz * gz) * (fx * fx + fy * fy + fz * fz) -
                (dx * fx + dy * fy + dz * fz) * (gx * fx + gy * fy + gz * fz);
    return CGAL::sign(v);
}

// image_orientation(camera, *l3.LA, *l3.LB, P), from the rounded image coordinates when they decide
// it: each coordinate of l.a, l.b and p is within its slack d of the exact image, so moving them
// changes the determinant u x v (u = b - a, v = p - a) by at most 2 d (|u|_1 + |v|_1) + 8 d^2;
// computing it from the rounded coordinates errs by at most 5 eps |u|_1 |v|_1 more. Only for an
// unclipped l (a clipped end is a construction, off the edge's line by its own rounding).
int orient_filtered(const Camera& camera, const Segment2& l, const Segment3& l3, glm::dvec2 p, double p_slack,
                    const glm::dvec3& P) {
    if (l3.A == *l3.LA && l3.B == *l3.LB) {
        constexpr double kEps = 0x1p-53;
        const glm::dvec2 u = l.b - l.a, v = p - l.a;
        const double det = u.x * v.y - u.y * v.x;
        const double d = std::max(l.slack, p_slack);
        const double nu = std::abs(u.x) + std::abs(u.y), nv = std::abs(v.x) + std::abs(v.y);
        const double bound = 2.0 * d * (nu + nv) + 8.0 * d * d + 8.0 * kEps * nu * nv;
        if (det > bound) return 1;
        if (det < -bound) return -1;
    }
    return image_orientation(camera, *l3.LA, *l3.LB, P);
}

// Parameter along q (image coordinates) of the image of point p of o, known to lie on q's line.
double param_on(const Segment2& q, glm::dvec2 p) {
    const glm::dvec2 d = q.b - q.a;
    return quotient(glm::dot(p - q.a, d), glm::dot(d, d), [&] { return qdot(p, q.a, q.a, q.b); },
                    [&] { return qdot(q.b, q.a, q.a, q.b); });
}
}  // namespace

int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, double t[2]) {
    if (q.v0 == o.v0 || q.v0 == o.v1 || q.v1 == o.v0 || q.v1 == o.v1) return 0;
    if (q.a == q.b || o.a == o.b) return 0;
    // Bounding boxes apart by more than the rounding of the images: the exact images are apart.
    const double m = q.slack + o.slack;
    if (std::max(q.a.x, q.b.x) + m < std::min(o.a.x, o.b.x) || std::max(o.a.x, o.b.x) + m < std::min(q.a.x, q.b.x) ||
        std::max(q.a.y, q.b.y) + m < std::min(o.a.y, o.b.y) || std::max(o.a.y, o.b.y) + m < std::min(q.a.y, q.b.y))
        return 0;
    const int s0 = orient_filtered(camera, q, q3, o.a, o.slack, o3.A), s1 = orient_filtered(camera, q, q3, o.b, o.slack, o3.B);
    if (s0 != 0 && s0 == s1) return 0;
    const int s2 = orient_filtered(camera, o, o3, q.a, q.slack, q3.A), s3 = orient_filtered(camera, o, o3, q.b, q.slack, q3.B);
    if (s2 != 0 && s2 == s3) return 0;
    if (s0 == 0 && s1 == 0) {
        // Collinear images: the shared part, its ends ordered exactly along the line (positions
        // before q's start are 0, after its end 1, otherwise constructions).
        double u[2];
        bool before[2], after[2];
        for (int k = 0; k < 2; ++k) {
            const glm::dvec3& X = k ? o3.B : o3.A;
            const int from_start = image_order(camera, q3, q3.A, X), to_end = image_order(camera, q3, X, q3.B);
            before[k] = from_start < 0;
            after[k] = to_end < 0;
            u[k] = from_start <= 0 ? 0.0 : to_end <= 0 ? 1.0 : std::clamp(param_on(q, k ? o.b : o.a), 0.0, 1.0);
        }
        if ((before[0] && before[1]) || (after[0] && after[1])) return 0;
        t[0] = std::min(u[0], u[1]);
        t[1] = std::max(u[0], u[1]);
        return t[0] == t[1] ? 1 : 2;
    }
    // Proper crossing or touch: the parameter is a construction in the image coordinates.
    double u;
    if (s0 == 0) u = param_on(q, o.a);
    else if (s1 == 0) u = param_on(q, o.b);
    else if (s2 == 0) u = 0.0;
    else if (s3 == 0) u = 1.0;
    else {
        const glm::dvec2 d = q.b - q.a, e = o.b - o.a;
        u = quotient(cross(o.a - q.a, e), cross(d, e), [&] { return qcross(o.a, q.a, o.a, o.b); },
                     [&] { return qcross(q.b, q.a, o.a, o.b); });
    }
    t[0] = std::clamp(u, 0.0, 1.0);
    return 1;
}

SegmentGrid::SegmentGrid(const std::vector<Segment2>& segments, double width, double height) {
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (const auto& s : segments) {
        lo = glm::min(lo, glm::min(s.a, s.b));
        hi = glm::max(hi, glm::max(s.a, s.b));
    }
    lo = glm::max(lo, glm::dvec2(-width, -height));
    hi = glm::min(hi, glm::dvec2(2.0 * width, 2.0 * height));
    if (!(lo.x < hi.x) || !(lo.y < hi.y)) {
        lo = glm::dvec2(0.0);
        hi = glm::dvec2(width, height);
    }
    const glm::dvec2 ext = hi - lo;
    const double n = std::max<double>(1.0, double(segments.size()));
    const double side = std::sqrt(ext.x * ext.y / n);
    nx_ = std::clamp(int(std::ceil(ext.x / side)), 1, 2048);
    ny_ = std::clamp(int(std::ceil(ext.y / side)), 1, 2048);
    lo_ = lo;
    cell_ = glm::dvec2(ext.x / nx_, ext.y / ny_);

    std::vector<std::uint32_t> count(cells() + 1, 0);
    for (const auto& s : segments) visit_cells(s.a, s.b, s.slack, [&](std::size_t c) { ++count[c + 1]; });
    for (std::size_t c = 0; c < cells(); ++c) count[c + 1] += count[c];
    cell_begin_ = count;
    items_.resize(count.back());
    for (std::uint32_t i = 0; i < segments.size(); ++i)
        visit_cells(segments[i].a, segments[i].b, segments[i].slack, [&](std::size_t c) { items_[count[c]++] = i; });
    mark_.assign(segments.size(), 0);
}

}  // namespace inkline
