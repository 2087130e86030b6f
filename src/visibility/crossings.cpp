#include "visibility/crossings.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

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
    for (const auto& s : segments) visit_cells(s.a, s.b, [&](std::size_t c) { ++count[c + 1]; });
    for (std::size_t c = 0; c < cells(); ++c) count[c + 1] += count[c];
    cell_begin_ = count;
    items_.resize(count.back());
    for (std::uint32_t i = 0; i < segments.size(); ++i)
        visit_cells(segments[i].a, segments[i].b, [&](std::size_t c) { items_[count[c]++] = i; });
    mark_.assign(segments.size(), 0);
}

}  // namespace inkline
