#include "visibility/crossings.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
// it (image_side_filter, crossings.hpp); only for an unclipped l.
int orient_filtered(const Camera& camera, const Segment2& l, const Segment3& l3, glm::dvec2 p, double p_slack,
                    const glm::dvec3& P) {
    if (l3.unclipped >= 0 ? l3.unclipped == 1 : l3.A == *l3.LA && l3.B == *l3.LB) {
        const int side = image_side_filter(l.a, l.b, l.slack, p, p_slack);
        if (side != 0) return side;
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
    return segment_crossings(camera, q, q3, o, o3, t, nullptr);
}

int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, double t[2], double* o_t) {
    constexpr std::int8_t unknown[4] = {0, 0, 0, 0};
    return segment_crossings(camera, q, q3, o, o3, unknown, t, o_t);
}

int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, const std::int8_t sides[4], double t[2], double* o_t) {
    int exact[4], how;
    return segment_crossings(camera, q, q3, o, o3, sides, t, o_t, exact, &how);
}

double crossing_param(const Segment2& q, const Segment2& o, const int s[4]) {
    if (s[0] == 0) return param_on(q, o.a);
    if (s[1] == 0) return param_on(q, o.b);
    if (s[2] == 0) return 0.0;
    if (s[3] == 0) return 1.0;
    const glm::dvec2 d = q.b - q.a, e = o.b - o.a;
    return quotient(cross(o.a - q.a, e), cross(d, e), [&] { return qcross(o.a, q.a, o.a, o.b); },
                    [&] { return qcross(q.b, q.a, o.a, o.b); });
}

int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, const std::int8_t sides[4], double t[2], double* o_t, int exact[4],
                      int* how) {
    if (o_t) *o_t = NAN;
    *how = kDecidedBeforeSides;
    if (q.v0 == o.v0 || q.v0 == o.v1 || q.v1 == o.v0 || q.v1 == o.v1) return 0;
    if (q.a == q.b || o.a == o.b) return 0;
    // Bounding boxes apart by more than the rounding of the images: the exact images are apart.
    const double m = q.slack + o.slack;
    if (std::max(q.a.x, q.b.x) + m < std::min(o.a.x, o.b.x) || std::max(o.a.x, o.b.x) + m < std::min(q.a.x, q.b.x) ||
        std::max(q.a.y, q.b.y) + m < std::min(o.a.y, o.b.y) || std::max(o.a.y, o.b.y) + m < std::min(q.a.y, q.b.y))
        return 0;
    // (a side the caller's filter decided is what orient_filtered's filter would give)
    const int s0 = sides[0] ? sides[0] : orient_filtered(camera, q, q3, o.a, o.slack, o3.A);
    const int s1 = sides[1] ? sides[1] : orient_filtered(camera, q, q3, o.b, o.slack, o3.B);
    exact[0] = s0, exact[1] = s1;
    *how = kApartOnQsLine;
    if (s0 != 0 && s0 == s1) return 0;
    const int s2 = sides[2] ? sides[2] : orient_filtered(camera, o, o3, q.a, q.slack, q3.A);
    const int s3 = sides[3] ? sides[3] : orient_filtered(camera, o, o3, q.b, q.slack, q3.B);
    exact[2] = s2, exact[3] = s3;
    *how = kApartOnOsLine;
    if (s2 != 0 && s2 == s3) return 0;
    if (s0 == 0 && s1 == 0) {
        *how = kCollinear;
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
    *how = kMeet;
    if (o_t && !(s2 == 0 && s3 == 0)) {
        // Along o: what the call with q and o swapped computes (its orientations are these, q's
        // ends against o's line first; it would take the collinear branch when s2 = s3 = 0).
        const int swapped[4] = {s2, s3, s0, s1};
        *o_t = std::clamp(crossing_param(o, q, swapped), 0.0, 1.0);
    }
    // Proper crossing or touch: the parameter is a construction in the image coordinates.
    t[0] = std::clamp(crossing_param(q, o, exact), 0.0, 1.0);
    return 1;
}

int mirrored_crossings(const Camera& camera, const Segment2& q2, const Segment3& q2_3d, const Segment2& o1,
                const Segment3& o1_3d, bool q1_forward, bool q2_forward, int how, const int exact[4], double t[2],
                double* o_t) {
    *o_t = NAN;
    if (how == kDecidedBeforeSides || how == kApartOnQsLine || how == kApartOnOsLine) return 0;
    // exact[0], [1]: o2's ends against q1's line; [2], [3]: q1's ends against o2's line.
    const int f1 = q1_forward ? 1 : -1, f2 = q2_forward ? 1 : -1;
    int m[4];  // the mirror's: o1's ends against q2's line, q2's ends against o1's line
    m[0] = f2 * (q1_forward ? exact[2] : exact[3]);
    m[1] = f2 * (q1_forward ? exact[3] : exact[2]);
    m[2] = f1 * (q2_forward ? exact[0] : exact[1]);
    m[3] = f1 * (q2_forward ? exact[1] : exact[0]);
    if (how == kCollinear || (m[0] == 0 && m[1] == 0)) {
        constexpr std::int8_t unknown[4] = {0, 0, 0, 0};
        return segment_crossings(camera, q2, q2_3d, o1, o1_3d, unknown, t, o_t);
    }
    // (how == kMeet: neither pair's ends lie strictly on one side of the other's line)
    if (!(m[2] == 0 && m[3] == 0)) {
        const int swapped[4] = {m[2], m[3], m[0], m[1]};
        *o_t = std::clamp(crossing_param(o1, q2, swapped), 0.0, 1.0);
    }
    t[0] = std::clamp(crossing_param(q2, o1, m), 0.0, 1.0);
    return 1;
}

void SegmentGrid::build(const std::vector<Segment2>& segments, double width, double height) {
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

    // Each segment's cells visited once (listed in segment order, with a cell's count), then
    // placed by a counting sort: in each cell the segments in increasing order.
    std::vector<std::uint32_t>& count = fill_;
    count.assign(cells() + 1, 0);
    visits_.clear();
    visit_end_.resize(segments.size());
    for (std::uint32_t i = 0; i < segments.size(); ++i) {
        const Segment2& s = segments[i];
        visit_cells(s.a, s.b, s.slack, [&](std::size_t c) {
            ++count[c + 1];
            visits_.push_back(std::uint32_t(c));
        });
        visit_end_[i] = std::uint32_t(visits_.size());
    }
    for (std::size_t c = 0; c < cells(); ++c) count[c + 1] += count[c];
    cell_begin_.assign(count.begin(), count.end());
    items_.resize(count.back());
    for (std::uint32_t i = 0, v = 0; i < segments.size(); ++i)
        for (; v < visit_end_[i]; ++v) items_[count[visits_[v]]++] = i;
    count_ = segments.size();
}

}  // namespace inkline

namespace inkline {

Box2f outer_box(const Segment2& s) {
    // Rounded to float toward the outside: the double widened by 2^-22 of its magnitude (and a
    // little more than float's least subnormal), more than the 2^-24 relative rounding of the
    // conversion. Beyond float's range: infinite on the outside, the largest float on the inside.
    auto down = [](double v) { return std::min(float(v - (std::abs(v) * 0x1p-22 + 0x1p-140)), FLT_MAX); };
    auto up = [](double v) { return std::max(float(v + (std::abs(v) * 0x1p-22 + 0x1p-140)), -FLT_MAX); };
    const double m = s.slack >= 0.0 ? s.slack : INFINITY;  // (a NaN slack bounds nothing)
    return {down(std::min(s.a.x, s.b.x) - m), down(std::min(s.a.y, s.b.y) - m), up(std::max(s.a.x, s.b.x) + m),
            up(std::max(s.a.y, s.b.y) + m), s.v0, s.v1};
}

namespace {
constexpr int kBigCells = 64;  // a box covering more cells is tested against every box instead
bool overlap(const Box2f& p, const Box2f& q) {
    return p.x0 <= q.x1 && q.x0 <= p.x1 && p.y0 <= q.y1 && q.y0 <= p.y1 && p.v0 != q.v0 && p.v0 != q.v1 &&
           p.v1 != q.v0 && p.v1 != q.v1;
}
}  // namespace

void BoxPairs::bin(const std::vector<Box2f>& boxes, Bins& bins) {
    const std::size_t cells = std::size_t(nx_) * ny_;
    bins.begin.assign(cells + 1, 0);
    bins.big.clear();
    // Each box's cells, found once (x0, x1, y0, y1; x0 < 0 for a big box).
    std::vector<std::array<std::int16_t, 4>>& r = ranges_;
    r.resize(boxes.size());
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
        if (!cell_range(boxes[i], r[i])) {
            bins.big.push_back(i);
            continue;
        }
        for (int y = r[i][2]; y <= r[i][3]; ++y)
            for (int x = r[i][0]; x <= r[i][1]; ++x) ++bins.begin[std::size_t(y) * nx_ + x + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) bins.begin[c + 1] += bins.begin[c];
    const std::size_t n = bins.begin[cells];
    bins.items.resize(n + 3);
    // (padded by 3: pairs() reads the last cell's boxes four at a time, past its end)
    bins.x0.resize(n + 3), bins.y0.resize(n + 3), bins.x1.resize(n + 3), bins.y1.resize(n + 3);
    bins.v0.resize(n + 3), bins.v1.resize(n + 3), bins.cx0.resize(n + 3), bins.cy0.resize(n + 3);
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
        if (r[i][0] < 0) continue;
        const Box2f& b = boxes[i];
        for (int y = r[i][2]; y <= r[i][3]; ++y)
            for (int x = r[i][0]; x <= r[i][1]; ++x) {
                const std::uint32_t at = bins.begin[std::size_t(y) * nx_ + x]++;
                bins.items[at] = i;
                bins.x0[at] = b.x0, bins.y0[at] = b.y0, bins.x1[at] = b.x1, bins.y1[at] = b.y1;
                bins.v0[at] = b.v0, bins.v1[at] = b.v1;
                bins.cx0[at] = r[i][0], bins.cy0[at] = r[i][2];
            }
    }
    // (the fill pass moved each start to the next cell's: shift back)
    for (std::size_t c = cells; c > 0; --c) bins.begin[c] = bins.begin[c - 1];
    bins.begin[0] = 0;
}

bool BoxPairs::cell_range(const Box2f& b, std::array<std::int16_t, 4>& r) const {
    const int x0 = cx(b.x0), x1 = cx(b.x1), y0 = cy(b.y0), y1 = cy(b.y1);
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > kBigCells) {
        r[0] = -1;
        return false;
    }
    r = {std::int16_t(x0), std::int16_t(x1), std::int16_t(y0), std::int16_t(y1)};
    return true;
}

void BoxPairs::bin_split(const std::vector<Box2f>& boxes, Bins& bins, WorkerTeam& team, int parts) {
    // A counting sort in parallel: each part counts its boxes per cell; each range of cells then
    // turns the counts into every part's first slot in the cell (part 0's boxes first, so a
    // cell's boxes stay in box order); each part then writes its boxes at its slots.
    const std::size_t cells = std::size_t(nx_) * ny_, nb = boxes.size();
    auto first_box = [&](int p) { return std::uint32_t(nb * std::size_t(p) / std::size_t(parts)); };
    auto first_cell = [&](int p) { return cells * std::size_t(p) / std::size_t(parts); };
    if (part_counts_.size() < std::size_t(parts)) part_counts_.resize(std::size_t(parts)), part_big_.resize(std::size_t(parts));
    std::vector<std::array<std::int16_t, 4>>& r = ranges_;
    r.resize(nb);
    team.run(parts, [&](int p) {
        std::vector<std::uint32_t>& count = part_counts_[std::size_t(p)];
        count.assign(cells, 0);
        part_big_[std::size_t(p)].clear();
        for (std::uint32_t i = first_box(p); i < first_box(p + 1); ++i) {
            if (!cell_range(boxes[i], r[i])) {
                part_big_[std::size_t(p)].push_back(i);
                continue;
            }
            for (int y = r[i][2]; y <= r[i][3]; ++y)
                for (int x = r[i][0]; x <= r[i][1]; ++x) ++count[std::size_t(y) * nx_ + x];
        }
    });
    std::vector<std::uint32_t> range_start(std::size_t(parts) + 1, 0);
    team.run(parts, [&](int p) {
        std::uint32_t total = 0;
        for (std::size_t c = first_cell(p); c < first_cell(p + 1); ++c)
            for (int q = 0; q < parts; ++q) total += part_counts_[std::size_t(q)][c];
        range_start[std::size_t(p) + 1] = total;
    });
    for (int p = 0; p < parts; ++p) range_start[std::size_t(p) + 1] += range_start[std::size_t(p)];
    bins.begin.resize(cells + 1);
    team.run(parts, [&](int p) {
        std::uint32_t at = range_start[std::size_t(p)];
        for (std::size_t c = first_cell(p); c < first_cell(p + 1); ++c) {
            bins.begin[c] = at;
            for (int q = 0; q < parts; ++q) {
                const std::uint32_t k = part_counts_[std::size_t(q)][c];
                part_counts_[std::size_t(q)][c] = at;
                at += k;
            }
        }
    });
    const std::size_t n = range_start[std::size_t(parts)];
    bins.begin[cells] = std::uint32_t(n);
    // (padded by 3, as bin)
    bins.items.resize(n + 3);
    bins.x0.resize(n + 3), bins.y0.resize(n + 3), bins.x1.resize(n + 3), bins.y1.resize(n + 3);
    bins.v0.resize(n + 3), bins.v1.resize(n + 3), bins.cx0.resize(n + 3), bins.cy0.resize(n + 3);
    team.run(parts, [&](int p) {
        std::vector<std::uint32_t>& next = part_counts_[std::size_t(p)];
        for (std::uint32_t i = first_box(p); i < first_box(p + 1); ++i) {
            if (r[i][0] < 0) continue;
            const Box2f& b = boxes[i];
            for (int y = r[i][2]; y <= r[i][3]; ++y)
                for (int x = r[i][0]; x <= r[i][1]; ++x) {
                    const std::uint32_t at = next[std::size_t(y) * nx_ + x]++;
                    bins.items[at] = i;
                    bins.x0[at] = b.x0, bins.y0[at] = b.y0, bins.x1[at] = b.x1, bins.y1[at] = b.y1;
                    bins.v0[at] = b.v0, bins.v1[at] = b.v1;
                    bins.cx0[at] = r[i][0], bins.cy0[at] = r[i][2];
                }
        }
    });
    bins.big.clear();
    for (int p = 0; p < parts; ++p) bins.big.insert(bins.big.end(), part_big_[std::size_t(p)].begin(), part_big_[std::size_t(p)].end());
}

void BoxPairs::prepare(const std::vector<Box2f>& b, double width, double height, WorkerTeam* team, int parts) {
    b_boxes_ = &b;
    // The grid: over the finite extent of the boxes within the widened image, cells about four
    // times the mean box side, at most ~4 cells per box and 1024 a side.
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, sum = 0.0;
    std::size_t counted = 0;
    for (const Box2f& x : b) {
        const double w = double(x.x1) - x.x0, h = double(x.y1) - x.y0;
        if (!(w <= width && h <= height)) continue;  // huge or not finite: not in the sizing
        lo[0] = std::min(lo[0], double(x.x0)), hi[0] = std::max(hi[0], double(x.x1));
        lo[1] = std::min(lo[1], double(x.y0)), hi[1] = std::max(hi[1], double(x.y1));
        sum += std::max(w, h);
        ++counted;
    }
    lo[0] = std::max(lo[0], -width), hi[0] = std::min(hi[0], 2.0 * width);
    lo[1] = std::max(lo[1], -height), hi[1] = std::min(hi[1], 2.0 * height);
    if (!(lo[0] < hi[0]) || !(lo[1] < hi[1])) lo[0] = 0.0, hi[0] = width, lo[1] = 0.0, hi[1] = height;
    const double ex = hi[0] - lo[0], ey = hi[1] - lo[1];
    double side = counted ? 2.0 * sum / double(counted) : 0.0;
    side = std::max({side, std::sqrt(ex * ey / (4.0 * double(b.size() + 1))), ex / 1024.0, ey / 1024.0});
    nx_ = std::clamp(int(std::ceil(ex / side)), 1, 1024);
    ny_ = std::clamp(int(std::ceil(ey / side)), 1, 1024);
    lo_x_ = lo[0], lo_y_ = lo[1];
    inv_x_ = double(nx_) / ex, inv_y_ = double(ny_) / ey;
    if (team && parts > 1) bin_split(b, b_, *team, parts);
    else bin(b, b_);
    most_ = 0;
    for (std::size_t c = 0; c + 1 < b_.begin.size(); ++c) most_ = std::max(most_, b_.begin[c + 1] - b_.begin[c]);
}

void BoxPairs::pairs(const std::vector<Box2f>& a, std::vector<std::uint64_t>& out,
                     std::vector<std::uint32_t>& hits) const {
    if (a.empty() || !b_boxes_ || b_boxes_->empty()) return;
    const std::vector<Box2f>& b = *b_boxes_;
    // Pairs in the grid: found in the cell of their overlap's lower corner, that is the first cell
    // of both boxes' ranges (the cell of a coordinate is monotone): x = max(first x of either) —
    // one of the two starts at x — and the same in y. Only `b` is binned; each box of `a` visits
    // its cells. The tests of one box against a cell's boxes are branch-free; the hits are
    // compacted (in place, without branches, with SSE2; in `hits` first otherwise).
    // (`out` sized to its capacity once, at least; the pairs written at n_out, room made when
    // short, the size set at the end)
    std::size_t n_out = out.size();
    out.resize(std::max(out.capacity(), n_out + 1024));
    auto room = [&](std::size_t need) {
        if (need > out.size()) out.resize(std::max(need, 2 * out.size()));
    };
#if defined(__SSE2__)
    (void)hits;
#else
    hits.resize(most_);
    std::uint32_t* hit = hits.data();
#endif
    const float *bx0 = b_.x0.data(), *by0 = b_.y0.data(), *bx1 = b_.x1.data(), *by1 = b_.y1.data();
    const std::uint32_t *bv0 = b_.v0.data(), *bv1 = b_.v1.data();
    const std::int32_t *bcx = b_.cx0.data(), *bcy = b_.cy0.data();
    const std::uint32_t* items = b_.items.data();
    // Each box of `a` against the binned boxes of `b` in its cells, and against the big ones.
    for (std::uint32_t i = 0; i < a.size(); ++i) {
        const Box2f& A = a[i];
        const int ax0c = cx(A.x0), ax1c = cx(A.x1), ay0c = cy(A.y0), ay1c = cy(A.y1);
        const std::uint64_t i_hi = std::uint64_t(i) << 32;
        if ((ax1c - ax0c + 1) * (ay1c - ay0c + 1) > kBigCells) {  // a big box: against every box
            for (std::uint32_t k = 0; k < b.size(); ++k)
                if (overlap(A, b[k])) room(n_out + 1), out[n_out++] = i_hi | k;
            continue;
        }
        for (std::uint32_t k : b_.big)
            if (overlap(A, b[k])) room(n_out + 1), out[n_out++] = i_hi | k;
        for (int y = ay0c; y <= ay1c; ++y)
            for (int x = ax0c; x <= ax1c; ++x) {
                const std::size_t c = std::size_t(y) * nx_ + x;
                const std::uint32_t b0 = b_.begin[c], b1 = b_.begin[c + 1];
                if (b0 == b1) continue;
                const bool first_x = ax0c == x, first_y = ay0c == y;
                std::uint32_t n = 0, q = b0;
#if defined(__SSE2__)
                // (the pairs written in place: room for every box of the cell and one more)
                room(n_out + (b1 - b0) + 1);
                std::uint64_t* dst = out.data() + n_out;
                // Four boxes a step (SSE2 is part of x86-64), the last step's lanes past the cell
                // masked (the arrays are padded); the hits compacted without branches.
                const __m128 vx0 = _mm_set1_ps(A.x0), vy0 = _mm_set1_ps(A.y0), vx1 = _mm_set1_ps(A.x1),
                             vy1 = _mm_set1_ps(A.y1);
                const __m128i w0 = _mm_set1_epi32(int(A.v0)), w1 = _mm_set1_epi32(int(A.v1));
                const __m128i cxv = _mm_set1_epi32(x), cyv = _mm_set1_epi32(y);
                const __m128i all = _mm_set1_epi32(-1);
                const __m128i end = _mm_set1_epi32(int(b1));
                __m128i lane = _mm_add_epi32(_mm_set1_epi32(int(b0)), _mm_setr_epi32(0, 1, 2, 3));
                for (; q < b1; q += 4, lane = _mm_add_epi32(lane, _mm_set1_epi32(4))) {
                    const __m128 in = _mm_and_ps(
                        _mm_and_ps(_mm_cmple_ps(vx0, _mm_loadu_ps(bx1 + q)), _mm_cmple_ps(_mm_loadu_ps(bx0 + q), vx1)),
                        _mm_and_ps(_mm_cmple_ps(vy0, _mm_loadu_ps(by1 + q)), _mm_cmple_ps(_mm_loadu_ps(by0 + q), vy1)));
                    const __m128i u0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bv0 + q));
                    const __m128i u1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bv1 + q));
                    const __m128i shared = _mm_or_si128(_mm_or_si128(_mm_cmpeq_epi32(w0, u0), _mm_cmpeq_epi32(w0, u1)),
                                                        _mm_or_si128(_mm_cmpeq_epi32(w1, u0), _mm_cmpeq_epi32(w1, u1)));
                    const __m128i okx =
                        first_x ? all : _mm_cmpeq_epi32(cxv, _mm_loadu_si128(reinterpret_cast<const __m128i*>(bcx + q)));
                    const __m128i oky =
                        first_y ? all : _mm_cmpeq_epi32(cyv, _mm_loadu_si128(reinterpret_cast<const __m128i*>(bcy + q)));
                    const __m128i ok = _mm_andnot_si128(shared, _mm_and_si128(_mm_and_si128(okx, oky), _mm_cmplt_epi32(lane, end)));
                    const unsigned mask = unsigned(_mm_movemask_ps(_mm_and_ps(_mm_castsi128_ps(ok), in)));
                    if (mask == 0) continue;  // (most steps: no pair)
                    dst[n] = i_hi | items[q], n += mask & 1;
                    dst[n] = i_hi | items[q + 1], n += (mask >> 1) & 1;
                    dst[n] = i_hi | items[q + 2], n += (mask >> 2) & 1;
                    dst[n] = i_hi | items[q + 3], n += mask >> 3;
                }
                n_out += n;
#else
                for (; q < b1; ++q) {
                    hit[n] = q;
                    n += (A.x0 <= bx1[q]) & (bx0[q] <= A.x1) & (A.y0 <= by1[q]) & (by0[q] <= A.y1) & (A.v0 != bv0[q]) &
                         (A.v0 != bv1[q]) & (A.v1 != bv0[q]) & (A.v1 != bv1[q]) & (first_x | (bcx[q] == x)) &
                         (first_y | (bcy[q] == y));
                }
                room(n_out + n);
                for (std::uint32_t h = 0; h < n; ++h) out[n_out++] = i_hi | b_.items[hit[h]];
#endif
            }
    }
    out.resize(n_out);
}

}  // namespace inkline
