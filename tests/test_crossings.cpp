// Image-space crossings: segment_crossings (proper crossings, touches, collinear overlaps,
// degenerate input, exactness near the last bit) and SegmentGrid (candidates are a superset of the
// segments that meet a query, each reported once, for segments anywhere).
#include <gtest/gtest.h>

#include <bit>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include "core/camera.hpp"
#include "core/predicates.hpp"
#include "visibility/crossings.hpp"
#include "visibility/fast_orient.hpp"

using inkline::Segment2;

namespace {

// Segments with their own mesh vertices (never shared unless a test says so).
Segment2 seg(double ax, double ay, double bx, double by, std::uint32_t id = 0) {
    return Segment2{{ax, ay}, {bx, by}, 1000 + 2 * id, 1001 + 2 * id, id};
}
Segment2 seg(glm::dvec2 a, glm::dvec2 b, std::uint32_t id = 0) { return seg(a.x, a.y, b.x, b.y, id); }

struct Result {
    int n = 0;
    double t[2] = {NAN, NAN};
};
Result cross(const Segment2& q, const Segment2& o) {
    Result r;
    r.n = inkline::segment_crossings(q, o, r.t);
    return r;
}

double up_next(double x) { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
double down_next(double x) { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

// Exact reference in rationals: the parameters along q where o meets it (see crossings.hpp).
using Q = CGAL::Exact_rational;
struct ExactResult {
    int n = 0;
    Q t[2];
};
int sign_of(const Q& x) { return CGAL::sign(x); }
Q orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    return (Q(b.x) - Q(a.x)) * (Q(c.y) - Q(a.y)) - (Q(b.y) - Q(a.y)) * (Q(c.x) - Q(a.x));
}
ExactResult exact_crossings(const Segment2& q, const Segment2& o) {
    ExactResult r;
    if (q.v0 == o.v0 || q.v0 == o.v1 || q.v1 == o.v0 || q.v1 == o.v1) return r;
    if ((q.a.x == q.b.x && q.a.y == q.b.y) || (o.a.x == o.b.x && o.a.y == o.b.y)) return r;
    const int s0 = sign_of(orient(q.a, q.b, o.a)), s1 = sign_of(orient(q.a, q.b, o.b));
    const int s2 = sign_of(orient(o.a, o.b, q.a)), s3 = sign_of(orient(o.a, o.b, q.b));
    const Q dx = Q(q.b.x) - Q(q.a.x), dy = Q(q.b.y) - Q(q.a.y);
    auto param = [&](glm::dvec2 p) -> Q {  // of a point on q's line
        return ((Q(p.x) - Q(q.a.x)) * dx + (Q(p.y) - Q(q.a.y)) * dy) / (dx * dx + dy * dy);
    };
    if (s0 == 0 && s1 == 0) {
        Q u0 = param(o.a), u1 = param(o.b);
        if (u1 < u0) std::swap(u0, u1);
        const Q lo = u0 > Q(0) ? u0 : Q(0), hi = u1 < Q(1) ? u1 : Q(1);
        if (lo > hi) return r;
        r.t[0] = lo;
        r.t[1] = hi;
        r.n = lo == hi ? 1 : 2;
        return r;
    }
    if (s0 * s1 > 0 || s2 * s3 > 0) return r;
    const Q ex = Q(o.b.x) - Q(o.a.x), ey = Q(o.b.y) - Q(o.a.y);
    r.t[0] = Q(((Q(o.a.x) - Q(q.a.x)) * ey - (Q(o.a.y) - Q(q.a.y)) * ex) / (dx * ey - dy * ex));
    r.n = 1;
    return r;
}

void expect_matches_exact(const Segment2& q, const Segment2& o, const std::string& what, int* wrong) {
    const Result got = cross(q, o);
    const ExactResult want = exact_crossings(q, o);
    bool ok = got.n == want.n;
    for (int i = 0; ok && i < got.n; ++i) {
        const double w = CGAL::to_double(want.t[i]);
        ok = got.t[i] >= 0.0 && got.t[i] <= 1.0 && std::abs(got.t[i] - w) <= 1e-9;
    }
    if (!ok && ++*wrong <= 10)
        ADD_FAILURE() << what << ": q (" << q.a.x << "," << q.a.y << ")-(" << q.b.x << "," << q.b.y << ") o ("
                      << o.a.x << "," << o.a.y << ")-(" << o.b.x << "," << o.b.y << "): got " << got.n << " ["
                      << got.t[0] << ", " << got.t[1] << "], exact " << want.n << " ["
                      << (want.n > 0 ? CGAL::to_double(want.t[0]) : NAN) << ", "
                      << (want.n > 1 ? CGAL::to_double(want.t[1]) : NAN) << "]";
}

}  // namespace

// =============================================================================================
// segment_crossings

TEST(SegmentCrossings, ProperCrossing) {
    Result r = cross(seg(0, 0, 4, 0), seg(1, -1, 1, 3, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
    r = cross(seg(0, 0, 2, 2), seg(0, 2, 2, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.5);
    // The parameter is along q, whatever the direction of o.
    r = cross(seg(8, 0, 0, 0), seg(6, 5, 6, -1, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
    r = cross(seg(0, 0, 0, 10), seg(-3, 7.5, 1, 7.5, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.75);
    // Roles swapped: the parameter along the other segment.
    r = cross(seg(1, -1, 1, 3, 1), seg(0, 0, 4, 0));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
}

TEST(SegmentCrossings, NoCrossing) {
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(5, -1, 5, 3, 1)).n, 0);      // beyond the end of q
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(1, 0.5, 3, 2, 1)).n, 0);     // above
    EXPECT_EQ(cross(seg(0, 0, 4, 4), seg(3, 0, 4, 1, 1)).n, 0);       // parallel, below
    EXPECT_EQ(cross(seg(0, 0, 4, 4), seg(0, 4, 1.5, 2.5, 1)).n, 0);   // o stops short of q
    EXPECT_EQ(cross(seg(0, 0, 1, 0), seg(2, -1, 2, 1, 1)).n, 0);      // q's line would meet it
}

TEST(SegmentCrossings, TouchingAtAnEndPoint) {
    // T junction: the end of o on the interior of q.
    Result r = cross(seg(0, 0, 4, 0), seg(1, 0, 1, 3, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
    r = cross(seg(0, 0, 4, 0), seg(3, 5, 3, 0, 1));  // its other end
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.75);
    // The end of q on the interior of o: t is 0 or 1.
    r = cross(seg(1, 0, 1, 3), seg(0, 0, 4, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.0);
    r = cross(seg(1, 3, 1, 0), seg(0, 0, 4, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 1.0);
    // End to end at a point that is not a shared mesh vertex.
    r = cross(seg(0, 0, 2, 1), seg(2, 1, 5, -3, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 1.0);
    r = cross(seg(0, 0, 2, 1), seg(7, 7, 0, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.0);
    // Touching at a skew angle: o ends on q at (3, 1.5), a quarter... (q from (1, .5) to (9, 4.5)).
    r = cross(seg(1, 0.5, 9, 4.5), seg(3, 1.5, 2, 6, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
}

TEST(SegmentCrossings, CollinearOverlap) {
    const Segment2 q = seg(0, 0, 4, 0);
    Result r = cross(q, seg(1, 0, 3, 0, 1));  // inside
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.25);
    EXPECT_EQ(r.t[1], 0.75);
    r = cross(q, seg(3, 0, 1, 0, 1));  // reversed: still in increasing order
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.25);
    EXPECT_EQ(r.t[1], 0.75);
    r = cross(q, seg(-1, 0, 2, 0, 1));  // overlapping the start
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.0);
    EXPECT_EQ(r.t[1], 0.5);
    r = cross(q, seg(6, 0, 3, 0, 1));  // overlapping the end
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.75);
    EXPECT_EQ(r.t[1], 1.0);
    r = cross(q, seg(-5, 0, 9, 0, 1));  // containing q
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.0);
    EXPECT_EQ(r.t[1], 1.0);
    r = cross(q, seg(4, 0, 0, 0, 1));  // the same segment, other mesh vertices
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.0);
    EXPECT_EQ(r.t[1], 1.0);
    // Diagonal.
    r = cross(seg(0, 0, 8, 8), seg(10, 10, 6, 6, 1));
    ASSERT_EQ(r.n, 2);
    EXPECT_EQ(r.t[0], 0.75);
    EXPECT_EQ(r.t[1], 1.0);
    // Collinear and touching end to end: one point.
    r = cross(q, seg(4, 0, 7, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 1.0);
    r = cross(q, seg(-2, 0, 0, 0, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.0);
}

TEST(SegmentCrossings, CollinearDisjointAndParallel) {
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(5, 0, 7, 0, 1)).n, 0);
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(-3, 0, -0.5, 0, 1)).n, 0);
    EXPECT_EQ(cross(seg(0, 0, 1, 1), seg(2, 2, 3, 3, 1)).n, 0);
    EXPECT_EQ(cross(seg(3, 3, 2, 2), seg(1, 1, 0, 0, 1)).n, 0);
    // Parallel, not collinear, overlapping in projection.
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(0, 1, 4, 1, 1)).n, 0);
    EXPECT_EQ(cross(seg(0, 0, 4, 4), seg(1, 0, 5, 4, 1)).n, 0);
    // Parallel one unit in the last place apart.
    EXPECT_EQ(cross(seg(0, 1, 4, 1), seg(1, up_next(1.0), 3, up_next(1.0), 1)).n, 0);
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(1, std::numeric_limits<double>::denorm_min(), 3,
                                         std::numeric_limits<double>::denorm_min(), 1)).n,
              0);
}

TEST(SegmentCrossings, SharedMeshVertexGivesNothing) {
    // Geometrically crossing (or touching), but one mesh vertex in common: adjacent edges.
    Segment2 q = seg(0, 0, 4, 0, 0), o = seg(1, -1, 1, 3, 1);
    for (int k = 0; k < 4; ++k) {
        Segment2 a = q, b = o;
        (k & 1 ? a.v1 : a.v0) = 7;
        (k & 2 ? b.v1 : b.v0) = 7;
        EXPECT_EQ(cross(a, b).n, 0) << k;
        EXPECT_EQ(cross(b, a).n, 0) << k;
    }
    // Consecutive silhouette edges meeting at their common projected vertex.
    Segment2 e1{{0, 0}, {2, 1}, 10, 11, 0}, e2{{2, 1}, {3, 5}, 11, 12, 1};
    EXPECT_EQ(cross(e1, e2).n, 0);
    EXPECT_EQ(cross(e2, e1).n, 0);
    // Collinear overlapping with a shared vertex (a fold seen edge-on).
    Segment2 f1{{0, 0}, {4, 0}, 20, 21, 0}, f2{{4, 0}, {1, 0}, 21, 22, 1};
    EXPECT_EQ(cross(f1, f2).n, 0);
}

TEST(SegmentCrossings, ZeroLengthGivesNothing) {
    EXPECT_EQ(cross(seg(1, 0, 1, 0), seg(0, 0, 4, 0, 1)).n, 0);   // q a point on o
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(1, 0, 1, 0, 1)).n, 0);   // o a point on q
    EXPECT_EQ(cross(seg(2, 2, 2, 2), seg(2, 2, 2, 2, 1)).n, 0);   // both
    EXPECT_EQ(cross(seg(0, 0, 4, 0), seg(1, 5, 1, 5, 1)).n, 0);
}

TEST(SegmentCrossings, DecidedByTheLastBit) {
    // q on the line y = x from -1e15 to 1e15; o starts next to the line at (0.5, 0.5).
    const Segment2 q = seg(-1e15, -1e15, 1e15, 1e15);
    const double above = up_next(0.5), below = down_next(0.5);
    // One unit in the last place above the line, going further above: no contact. (In doubles,
    // the naive cross product of (2e15, 2e15) and (1e15 + 0.5, 1e15 + 0.5 + 2^-53) is zero.)
    EXPECT_EQ(cross(q, seg(0.5, above, 3, 7, 1)).n, 0);
    EXPECT_EQ(cross(q, seg(below, 0.5, 3, 7, 1)).n, 0);
    // Exactly on the line: a touch, at t = (1e15 + 0.5) / 2e15.
    Result r = cross(q, seg(0.5, 0.5, 3, 7, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_NEAR(r.t[0], 0.5, 1e-14);
    // One unit below, going above: a proper crossing.
    r = cross(q, seg(0.5, below, 3, 7, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_NEAR(r.t[0], 0.5, 1e-14);
    // The same with q's roles swapped: o meets q exactly when q meets o.
    EXPECT_EQ(cross(seg(0.5, above, 3, 7, 1), q).n, 0);
    EXPECT_EQ(cross(seg(0.5, 0.5, 3, 7, 1), q).n, 1);
    EXPECT_EQ(cross(seg(0.5, below, 3, 7, 1), q).n, 1);

    // An end point one unit in the last place short of / on / past the other segment's line at
    // large coordinates (ulp(1e15) = 0.125).
    const Segment2 v = seg(1e15, -1e15, 1e15, 1e15);  // the vertical line x = 1e15
    EXPECT_EQ(cross(v, seg(0, 3, down_next(1e15), 3, 1)).n, 0);
    r = cross(v, seg(0, 3, 1e15, 3, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_NEAR(r.t[0], 0.5, 1e-14);
    EXPECT_EQ(cross(v, seg(0, 3, up_next(1e15), 3, 1)).n, 1);
    // Almost collinear: o is q's line turned by one unit in the last place about its start.
    const Segment2 h = seg(0, 0, 1e15, 1);
    EXPECT_EQ(cross(h, seg(2e15, 2, 3e15, 3, 1)).n, 0);  // collinear, disjoint
    EXPECT_EQ(cross(h, seg(5e14, 0.5, 3e15, 3, 1)).n, 2);  // collinear, overlapping
    // Turned about its far end by one unit in the last place at its start, above or below: the
    // lines meet only at (3e15, 3), beyond q.
    EXPECT_EQ(cross(h, seg(5e14, up_next(0.5), 3e15, 3, 1)).n, 0);
    EXPECT_EQ(cross(h, seg(5e14, down_next(0.5), 3e15, 3, 1)).n, 0);
    // Straddling q's line by one unit in the last place on each side: a crossing at t = 1/2.
    r = cross(h, seg(5e14, down_next(0.5), 5e14, up_next(0.5), 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_NEAR(r.t[0], 0.5, 1e-14);
    EXPECT_EQ(cross(h, seg(5e14, up_next(0.5), 5e14, 1, 1)).n, 0);
    // Tiny coordinates (subnormal differences).
    const double d = std::numeric_limits<double>::denorm_min();
    r = cross(seg(0, 0, 4 * d, 0), seg(d, -d, d, d, 1));
    ASSERT_EQ(r.n, 1);
    EXPECT_EQ(r.t[0], 0.25);
    EXPECT_EQ(cross(seg(0, 0, 4 * d, 0), seg(d, d, 3 * d, d, 1)).n, 0);
}

TEST(SegmentCrossings, MatchesExactArithmeticOnDegenerateLattices) {
    // Small integer lattices make collinear, touching and parallel cases common; offset by 1e15
    // (still exact) they also stress cancellation. Every answer must match rationals.
    std::mt19937_64 rng(7);
    int wrong = 0, touching = 0, collinear = 0, crossings = 0;
    for (const double offset : {0.0, 1e15, -4503599627370496.0 /* -2^52 */}) {
        for (const double unit : {1.0, 0.125, 1e-300}) {
            std::uniform_int_distribution<int> L(0, 5);
            auto p = [&] { return glm::dvec2(offset + unit * L(rng), offset + unit * L(rng)); };
            for (int it = 0; it < 8000; ++it) {
                const Segment2 q = seg(p(), p(), 0), o = seg(p(), p(), 1);
                expect_matches_exact(q, o, "offset " + std::to_string(offset), &wrong);
                const ExactResult e = exact_crossings(q, o);
                crossings += e.n > 0;
                collinear += e.n == 2;
                touching += e.n == 1 && (e.t[0] == Q(0) || e.t[0] == Q(1));
            }
        }
    }
    EXPECT_EQ(wrong, 0);
    // The lattices really produce the degenerate cases.
    EXPECT_GT(collinear, 300) << collinear;
    EXPECT_GT(touching, 300) << touching;
    EXPECT_GT(crossings, 8000) << crossings;
}

TEST(SegmentCrossings, MatchesExactArithmeticNearLines) {
    // End points computed to lie on the other segment (so within rounding of it), then nudged.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int wrong = 0;
    for (const double scale : {1.0, 1e3, 1e12}) {
        for (int it = 0; it < 20000; ++it) {
            const glm::dvec2 a(U(rng) * scale, U(rng) * scale), b(U(rng) * scale, U(rng) * scale);
            const double s = U(rng) * 0.5 + 0.5;
            glm::dvec2 m = a + s * (b - a);
            const int k = int(rng() % 2), steps = int(rng() % 5) - 2;
            for (int i = 0; i < std::abs(steps); ++i) m[k] = steps > 0 ? up_next(m[k]) : down_next(m[k]);
            const glm::dvec2 far(U(rng) * scale, U(rng) * scale);
            const Segment2 q = seg(a, b, 0), o = seg(m, far, 1);
            expect_matches_exact(q, o, "near", &wrong);
            expect_matches_exact(o, q, "near, swapped", &wrong);
        }
    }
    EXPECT_EQ(wrong, 0);
}

// =============================================================================================
// SegmentGrid

namespace {

constexpr double kW = 800, kH = 600;

// A mix of segment kinds: short ones in the image, long ones across it, ones leaving it, ones far
// outside (beyond [-W, 2W]), enormous ones, axis-aligned ones on round coordinates, points.
Segment2 random_segment(std::mt19937_64& rng, std::uint32_t id) {
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto in_image = [&] { return glm::dvec2(U(rng) * kW, U(rng) * kH); };
    auto around = [&](double reach) {
        return glm::dvec2((U(rng) * 2 - 1) * reach * kW + kW / 2, (U(rng) * 2 - 1) * reach * kH + kH / 2);
    };
    glm::dvec2 a, b;
    switch (rng() % 10) {
        case 0:
        case 1:
        case 2: {  // short, in the image
            a = in_image();
            b = a + glm::dvec2(U(rng) * 40 - 20, U(rng) * 40 - 20);
            break;
        }
        case 3:  // long, across the image
            a = in_image();
            b = in_image();
            break;
        case 4:  // from the image to far outside
            a = in_image();
            b = around(std::pow(10.0, 1 + 11 * U(rng)));
            break;
        case 5:  // entirely far outside, possibly passing over the image
            a = around(3 + 100 * U(rng));
            b = around(3 + 1e6 * U(rng));
            break;
        case 6:  // enormous
            a = around(1e12);
            b = around(1e15);
            break;
        case 7: {  // axis-aligned on integer (cell-boundary-prone) coordinates
            a = glm::dvec2(std::floor(U(rng) * 3 * kW - kW), std::floor(U(rng) * 3 * kH - kH));
            b = a;
            b[rng() % 2] += std::floor(U(rng) * 400 - 200);
            break;
        }
        case 8:  // a point
            a = b = in_image();
            break;
        default:  // outside the image on one side, short
            a = glm::dvec2(-kW - 50 + U(rng) * 40, U(rng) * kH);
            b = a + glm::dvec2(U(rng) * 30, U(rng) * 30);
            break;
    }
    return seg(a, b, id);
}

bool meet(const Segment2& s, const Segment2& t) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    const K::Point_2 a(s.a.x, s.a.y), b(s.b.x, s.b.y), c(t.a.x, t.a.y), d(t.b.x, t.b.y);
    if (a == b && c == d) return a == c;
    if (a == b) return CGAL::do_intersect(a, K::Segment_2(c, d));
    if (c == d) return CGAL::do_intersect(c, K::Segment_2(a, b));
    return CGAL::do_intersect(K::Segment_2(a, b), K::Segment_2(c, d));
}

// For every query: candidates() reports each index at most once, and every indexed segment that
// meets the query (brute force, exact) is among them.
void expect_superset(const std::vector<Segment2>& segs, const std::vector<Segment2>& queries,
                     const std::string& what) {
    const inkline::SegmentGrid grid(segs, kW, kH);
    EXPECT_GE(grid.cells(), 1u);
    std::vector<int> count(segs.size(), 0);
    int missed = 0, repeated = 0;
    std::size_t candidates = 0, meeting = 0;
    for (std::size_t qi = 0; qi < queries.size(); ++qi) {
        const Segment2& q = queries[qi];
        std::fill(count.begin(), count.end(), 0);
        grid.candidates(q, [&](std::size_t i) {
            ASSERT_LT(i, segs.size());
            ++count[i];
        });
        for (std::size_t i = 0; i < segs.size(); ++i) {
            candidates += count[i] > 0;
            if (count[i] > 1 && ++repeated <= 5)
                ADD_FAILURE() << what << ": query " << qi << " reported segment " << i << " " << count[i] << " times";
            if (meet(q, segs[i])) {
                ++meeting;
                if (count[i] == 0 && ++missed <= 5)
                    ADD_FAILURE() << what << ": query " << qi << " (" << q.a.x << "," << q.a.y << ")-(" << q.b.x
                                  << "," << q.b.y << ") misses segment " << i << " (" << segs[i].a.x << ","
                                  << segs[i].a.y << ")-(" << segs[i].b.x << "," << segs[i].b.y << ")";
            }
        }
    }
    EXPECT_EQ(missed, 0) << what;
    EXPECT_EQ(repeated, 0) << what;
    EXPECT_GE(candidates, meeting);
}

}  // namespace

TEST(SegmentGrid, CandidatesAreASupersetForRandomSegments) {
    std::mt19937_64 rng(2024);
    std::vector<Segment2> segs;
    for (std::uint32_t i = 0; i < 3000; ++i) segs.push_back(random_segment(rng, i));
    std::vector<Segment2> queries;
    for (std::uint32_t i = 0; i < 1500; ++i) queries.push_back(random_segment(rng, 10000 + i));
    for (std::size_t i = 0; i < segs.size(); i += 2) queries.push_back(segs[i]);  // the indexed ones too
    expect_superset(segs, queries, "mixed");

    // The grid must actually prune: a short query in the image does not see everything.
    const inkline::SegmentGrid grid(segs, kW, kH);
    EXPECT_GT(grid.cells(), 100u);
    std::size_t seen = 0;
    grid.candidates(seg(400, 300, 401, 301, 99999), [&](std::size_t) { ++seen; });
    EXPECT_LT(seen, segs.size() / 4);
}

TEST(SegmentGrid, DenseShortSegmentsInTheImage) {
    // Many short segments (a fine grid) and queries that follow cell boundaries exactly.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Segment2> segs;
    for (std::uint32_t i = 0; i < 5000; ++i) {
        const glm::dvec2 a(U(rng) * kW, U(rng) * kH);
        segs.push_back(seg(a, a + glm::dvec2(U(rng) * 6 - 3, U(rng) * 6 - 3), i));
    }
    std::vector<Segment2> queries;
    for (std::uint32_t i = 0; i < 600; ++i) {
        const glm::dvec2 a(U(rng) * kW, U(rng) * kH);
        queries.push_back(seg(a, a + glm::dvec2(U(rng) * 200 - 100, U(rng) * 200 - 100), 20000 + i));
    }
    for (int x = 0; x <= 800; x += 8) queries.push_back(seg(x, -10, x, 610, 30000 + x));  // vertical lines
    for (int y = 0; y <= 600; y += 8) queries.push_back(seg(-10, y, 810, y, 40000 + y));  // horizontal lines
    queries.push_back(seg(0, 0, kW, kH, 50000));  // the diagonal, long
    queries.push_back(seg(-1e9, -0.75e9, 1e9, 0.75e9, 50001));  // the same line, enormous
    queries.push_back(seg(-1e200, -0.75e200, 1e200, 0.75e200, 50002));  // (products overflow)
    expect_superset(segs, queries, "dense");
}

TEST(SegmentGrid, SegmentsOnlyOutsideTheImage) {
    // Nothing inside [-W, 2W] x [-H, 2H]: the grid still answers exactly for anything.
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Segment2> segs, queries;
    for (std::uint32_t i = 0; i < 800; ++i) {
        const double x = 3 * kW + U(rng) * 1e5, y = -2 * kH - U(rng) * 1e5;
        segs.push_back(seg(x, y, x + U(rng) * 1e4 - 5e3, y - U(rng) * 1e4, i));
    }
    for (std::uint32_t i = 0; i < 400; ++i) {
        const double x = 3 * kW + U(rng) * 1e5, y = -2 * kH - U(rng) * 1e5;
        queries.push_back(seg(x, y, x + U(rng) * 3e4 - 1.5e4, y + U(rng) * 3e4 - 1.5e4, 10000 + i));
    }
    queries.push_back(seg(kW / 2, kH / 2, 4e5, -4e5, 20000));  // from the image out to them
    expect_superset(segs, queries, "outside");
}

TEST(SegmentGrid, DegenerateSets) {
    // One segment; all segments on one horizontal line (zero height); points only.
    expect_superset({seg(10, 10, 20, 20, 0)}, {seg(10, 20, 20, 10, 1), seg(0, 0, 5, 5, 2), seg(15, 15, 15, 15, 3)},
                    "single");
    std::vector<Segment2> line;
    for (std::uint32_t i = 0; i < 50; ++i) line.push_back(seg(20.0 * i, 100, 20.0 * i + 30, 100, i));
    expect_superset(line, {seg(0, 100, 1000, 100, 100), seg(55, 0, 55, 200, 101), seg(-1e6, 100, -5e5, 100, 102)},
                    "collinear");
    std::vector<Segment2> points;
    for (std::uint32_t i = 0; i < 50; ++i) points.push_back(seg(7.0 * i, 5.0 * i, 7.0 * i, 5.0 * i, i));
    std::vector<Segment2> queries;
    for (std::uint32_t i = 0; i < 50; ++i) queries.push_back(seg(7.0 * i - 1, 5.0 * i, 7.0 * i + 1, 5.0 * i, 100 + i));
    expect_superset(points, queries, "points");
    // No segments at all: nothing to report.
    const inkline::SegmentGrid empty({}, kW, kH);
    int n = 0;
    empty.candidates(seg(0, 0, kW, kH), [&](std::size_t) { ++n; });
    EXPECT_EQ(n, 0);
}

// ---- exact image-space predicates from 3D points --------------------------------------------

// image_orientation agrees with the orientation of the projected points wherever rounding cannot
// have decided it, and sees exactly degenerate configurations (collinear images) as such.
TEST(ImageOrientation, MatchesTheProjection) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (int ortho = 0; ortho < 2; ++ortho) {
        const inkline::Camera cam = ortho ? inkline::Camera::orthographic({3, 2, 5}, {0, 0, 0}, {0.1, 1, 0}, 4, 600, 500)
                                          : inkline::Camera::perspective({3, 2, 5}, {0, 0, 0}, {0.1, 1, 0}, 40, 600, 500);
        int checked = 0;
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng)), c(U(rng), U(rng), U(rng));
            const glm::dvec2 pa = cam.project(a), pb = cam.project(b), pc = cam.project(c);
            const double det = (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x);
            if (std::abs(det) < 1e-6) continue;
            ++checked;
            EXPECT_EQ(inkline::image_orientation(cam, a, b, c), det > 0 ? 1 : -1) << ortho << " " << i;
            EXPECT_EQ(inkline::image_orientation(cam, a, b, c),
                      int(CGAL::orientation(K::Point_2(pa.x, pa.y), K::Point_2(pb.x, pb.y), K::Point_2(pc.x, pc.y))));
        }
        EXPECT_GT(checked, 1900);
        // On one line of sight (perspective; the eye and p chosen so that the point twice as far
        // is exact) or along an axis-aligned view direction (orthographic): one point in the
        // image, so any third point is collinear with it.
        const inkline::Camera axis = inkline::Camera::orthographic({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 4, 600, 500);
        const glm::dvec3 p(0.25, 0.5, -0.75);
        const glm::dvec3 behind = ortho ? p + glm::dvec3(0, 0, -2) : cam.eye() + 2.0 * (p - cam.eye());
        if (ortho) {
            EXPECT_EQ(inkline::image_orientation(axis, p, behind, {0.3, -0.2, 0.1}), 0);
            continue;
        }
        EXPECT_EQ(inkline::image_orientation(cam, p, behind, {0.3, -0.2, 0.1}), 0) << ortho;
    }
}

// The eye (1, 1, 5) in the plane of two parallel box edges, one in front of the other: their images
// are collinear and overlap, and the end of the front edge lies on the back edge's image (where a
// third edge, the front box's side silhouette, ends on it: a T-junction). The rounded images hide
// both (the 2D predicate sees one touch at the shared start and no crossing with the side edge);
// the exact predicates from 3D find the overlap and the touch, at the image of the front corner.
TEST(SegmentCrossings, ExactFromThreeDimensions) {
    const inkline::Camera cam = inkline::Camera::perspective({1, 1, 5}, {0.5, 0.0, -1}, {0, 1, 0}, 50, 600, 600);
    const glm::dvec3 v4(0, 0, 1), v5(1, 0, 1), v7(1, 1, 1), v12(-1, -1, -3), v13(2, -1, -3);
    const Segment2 back{cam.project(v12), cam.project(v13), 12, 13, 23, inkline::image_slack(cam, v12, cam.project(v12))};
    const Segment2 front{cam.project(v4), cam.project(v5), 4, 5, 5, inkline::image_slack(cam, v4, cam.project(v4))};
    const Segment2 side{cam.project(v5), cam.project(v7), 5, 7, 6, inkline::image_slack(cam, v5, cam.project(v5))};
    const inkline::Segment3 back3{v12, v13, &v12, &v13}, front3{v4, v5, &v4, &v5}, side3{v5, v7, &v5, &v7};
    // Where the front corner v5 appears along the back edge: the line of sight from the eye
    // through v5 meets the back edge at x = 1, 2/3 of the way from v12 to v13 in 3D; in the image
    // (perspective division by the depths of v12 and v13) at the parameter below.
    const double zA = cam.depth(v12), zB = cam.depth(v13), at_v5 = (2.0 / 3.0) * zB / ((1.0 / 3.0) * zA + (2.0 / 3.0) * zB);
    double t[2];
    ASSERT_EQ(inkline::segment_crossings(cam, back, back3, front, front3, t), 2);
    EXPECT_EQ(t[0], 0.0);
    EXPECT_NEAR(t[1], at_v5, 1e-12);
    ASSERT_EQ(inkline::segment_crossings(cam, back, back3, side, side3, t), 1);
    EXPECT_NEAR(t[0], at_v5, 1e-12);
    // The other way round: along the front edge the back edge covers all of it.
    ASSERT_EQ(inkline::segment_crossings(cam, front, front3, back, back3, t), 2);
    EXPECT_EQ(t[0], 0.0);
    EXPECT_EQ(t[1], 1.0);
    // What the rounded image coordinates say (not exact for these segments: recorded, so that a
    // change in rounding shows here rather than in a drawing).
    EXPECT_EQ(inkline::segment_crossings(back, side, t), 0);
}

// Where rounding puts a projected point: within image_slack of the exact image (checked against
// an evaluation in long double, which carries 11 more bits), also far from the origin, very near
// the eye plane and far outside the image.
TEST(ImageSlack, BoundsTheProjectionError) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    using LV = long double;
    for (double offset : {0.0, 1e6}) {
        for (int ortho = 0; ortho < 2; ++ortho) {
            const glm::dvec3 o(offset, -offset, offset);
            const inkline::Camera cam =
                ortho ? inkline::Camera::orthographic(o + glm::dvec3(3, 2, 5), o, {0.1, 1, 0}, 4, 600, 500)
                      : inkline::Camera::perspective(o + glm::dvec3(3, 2, 5), o, {0.1, 1, 0}, 40, 600, 500);
            double worst = 0.0;
            for (int i = 0; i < 3000; ++i) {
                glm::dvec3 P = o + glm::dvec3(U(rng), U(rng), U(rng)) * (i % 3 == 0 ? 30.0 : 1.0);
                if (i % 5 == 0) P = cam.eye() + cam.forward() * std::pow(10.0, -9.0 * std::abs(U(rng))) +
                                    cam.right() * U(rng) + cam.upward() * U(rng);
                if (!(cam.depth(P) > 0.0)) continue;
                const glm::dvec2 p = cam.project(P);
                // The same formula in long double, from the same (rounded) frame.
                const glm::dvec3 E = cam.eye(), r = cam.right(), u = cam.upward(), f = cam.forward();
                const LV dx = LV(P.x) - LV(E.x), dy = LV(P.y) - LV(E.y), dz = LV(P.z) - LV(E.z);
                const LV x = dx * r.x + dy * r.y + dz * r.z, y = dx * u.x + dy * u.y + dz * u.z;
                const LV z = ortho ? LV(1) : dx * f.x + dy * f.y + dz * f.z;
                const LV px = LV(0.5) * cam.width() + LV(cam.focal()) * x / z;
                const LV py = LV(0.5) * cam.height() - LV(cam.focal()) * y / z;
                const double err = double(std::max(std::abs(px - LV(p.x)), std::abs(py - LV(p.y))));
                const double slack = inkline::image_slack(cam, P, p);
                EXPECT_LE(err, slack) << offset << " " << ortho << " " << i;
                worst = std::max(worst, err / slack);
            }
            std::printf("[slack] offset %g ortho %d: worst error / slack %.3g\n", offset, ortho, worst);
        }
    }
}

namespace {
// Pairs of 3D segments seen by `cam`, n draws: on odd draws their ends are lattice points (integers
// in [-3, 3]: many lines of sight through several points, touches, T-junctions, collinear
// images), on even ones random; fn(i, P, q, o) gets the four ends and the two segments' images
// (pairs with a zero-length segment are skipped).
template <class Fn>
void segment_pairs(const inkline::Camera& cam, std::mt19937_64& rng, int n, Fn fn) {
    std::uniform_int_distribution<int> L(-3, 3);
    std::uniform_real_distribution<double> U(-3.0, 3.0);
    for (int i = 0; i < n; ++i) {
        glm::dvec3 P[4];
        for (auto& p : P) p = i % 2 ? glm::dvec3(L(rng), L(rng), L(rng)) : glm::dvec3(U(rng), U(rng), U(rng));
        if (P[0] == P[1] || P[2] == P[3]) continue;
        auto seg2 = [&](const glm::dvec3& a, const glm::dvec3& b, std::uint32_t id) {
            const glm::dvec2 pa = cam.project(a), pb = cam.project(b);
            return Segment2{pa, pb, 2 * id, 2 * id + 1, id,
                            std::max(inkline::image_slack(cam, a, pa), inkline::image_slack(cam, b, pb))};
        };
        fn(i, P, seg2(P[0], P[1], 0), seg2(P[2], P[3], 1));
    }
}

// The cameras those pairs are seen from: an oblique perspective and an oblique orthographic view
// of the lattice's centre, and a perspective one from a lattice eye (lines of sight through
// several lattice points).
inkline::Camera oblique_perspective() {
    return inkline::Camera::perspective({5, 4, 9}, {0, 0, 0}, {0, 1, 0}, 60, 800, 600);
}
inkline::Camera oblique_orthographic() {
    return inkline::Camera::orthographic({7, 5, 9}, {0, 0, 0}, {0, 1, 0}, 10, 500, 500);
}
inkline::Camera lattice_eye_perspective() {
    return inkline::Camera::perspective({2, 2, 12}, {2, 2, 0}, {0, 1, 0}, 50, 640, 640);
}
}  // namespace

// The 3D-exact segment_crossings (with its filter on the rounded image coordinates) against a
// reference made of exact 3D orientations only, on lattice points seen from a lattice eye (many
// lines of sight through several points: touches, T-junctions, collinear images) and at random.
TEST(SegmentCrossings, ThreeDimensionalMatchesExactOrientations) {
    std::mt19937_64 rng(3);
    const inkline::Camera cams[] = {
        oblique_perspective(),
        lattice_eye_perspective(),
        inkline::Camera::orthographic({1, 1, 10}, {1, 1, 0}, {0, 1, 0}, 8, 500, 500),
        oblique_orthographic(),
    };
    int degenerate = 0, crossing = 0;
    for (const auto& cam : cams)
        segment_pairs(cam, rng, 20000, [&](int i, const glm::dvec3* P, const Segment2& q, const Segment2& o) {
            if (q.a == q.b || o.a == o.b) return;
            const inkline::Segment3 q3{P[0], P[1], &P[0], &P[1]}, o3{P[2], P[3], &P[2], &P[3]};
            const int s0 = inkline::image_orientation(cam, P[0], P[1], P[2]), s1 = inkline::image_orientation(cam, P[0], P[1], P[3]);
            const int s2 = inkline::image_orientation(cam, P[2], P[3], P[0]), s3 = inkline::image_orientation(cam, P[2], P[3], P[1]);
            double t[2];
            const int n = inkline::segment_crossings(cam, q, q3, o, o3, t);
            if (s0 == 0 && s1 == 0) {  // collinear images: 0, 1 or 2, within [0, 1]
                ++degenerate;
                EXPECT_LE(n, 2);
                for (int k = 0; k < n; ++k) EXPECT_TRUE(t[k] >= 0.0 && t[k] <= 1.0);
                return;
            }
            const bool meet = !(s0 != 0 && s0 == s1) && !(s2 != 0 && s2 == s3);
            if (s0 * s1 * s2 * s3 == 0) ++degenerate;
            crossing += meet;
            ASSERT_EQ(n, meet ? 1 : 0) << i << " signs " << s0 << s1 << s2 << s3;
        });
    EXPECT_GT(degenerate, 1000);
    EXPECT_GT(crossing, 1000);
}

// The crossing search gives where a crossing lies along the occluder too (build_pieces then
// skips the swapped call): exactly the swapped call's parameter, on lattice points (touches,
// T-junctions, collinear images) and random ones; NaN only for collinear images. Its quick reject
// (apart_by_filter) rejects only pairs that do not meet.
TEST(SegmentCrossings, ParameterAlongTheOtherEqualsTheSwappedCall) {
    std::mt19937_64 rng(4);
    const inkline::Camera cams[] = {
        oblique_perspective(),
        oblique_orthographic(),
    };
    int touches = 0, proper = 0, rejected = 0;
    for (const auto& cam : cams)
        segment_pairs(cam, rng, 20000, [&](int i, const glm::dvec3* P, const Segment2& q, const Segment2& o) {
            using namespace inkline;
            const Segment3 q3{P[0], P[1], &P[0], &P[1]}, o3{P[2], P[3], &P[2], &P[3]};
            double t[2], t_plain[2], to[2], ot;
            const int n = segment_crossings(cam, q, q3, o, o3, t, &ot);
            ASSERT_EQ(n, segment_crossings(cam, q, q3, o, o3, t_plain)) << i;
            for (int k = 0; k < n; ++k) ASSERT_EQ(t[k], t_plain[k]) << i;
            const int n2 = segment_crossings(cam, o, o3, q, q3, to);
            // The quick reject of the search only rejects pairs that do not meet.
            if (apart_by_filter(q, true, o, true)) {
                ++rejected;
                ASSERT_EQ(n, 0) << i;
            }
            ASSERT_EQ(n > 0, n2 > 0) << i;
            const bool collinear = image_orientation(cam, P[2], P[3], P[0]) == 0 && image_orientation(cam, P[2], P[3], P[1]) == 0;
            if (n == 0 || collinear) {
                ASSERT_TRUE(std::isnan(ot)) << i;
                return;
            }
            ASSERT_EQ(ot, to[0]) << i;
            const bool touch = image_orientation(cam, P[0], P[1], P[2]) * image_orientation(cam, P[0], P[1], P[3]) *
                                   image_orientation(cam, P[2], P[3], P[0]) * image_orientation(cam, P[2], P[3], P[1]) ==
                               0;
            (touch ? touches : proper) += 1;
        });
    EXPECT_GT(touches, 100);
    EXPECT_GT(proper, 1000);
    EXPECT_GT(rejected, 1000);
}

// The crossing search's quick reject hands the sides it decided to segment_crossings
// (filter_sides): the same answer as the call that decides them itself, on lattice points
// (touches, T-junctions, collinear images) and random ones, with either segment taken as clipped
// (its line's sides then not from the filter) or not; and a pair it rejects does not meet.
TEST(SegmentCrossings, GivenFilterSidesGiveTheSameResults) {
    std::mt19937_64 rng(6);
    const inkline::Camera cams[] = {
        oblique_perspective(),
        oblique_orthographic(),
    };
    int rejected = 0, met = 0, decided = 0;
    for (const auto& cam : cams)
        segment_pairs(cam, rng, 20000, [&](int i, const glm::dvec3* P, const Segment2& q, const Segment2& o) {
            using namespace inkline;
            for (int clip = 0; clip < 3; ++clip) {  // (none, q, o taken as clipped)
                const bool qu = clip != 1, ou = clip != 2;
                const Segment3 q3{P[0], P[1], &P[0], &P[1], std::int8_t(qu)}, o3{P[2], P[3], &P[2], &P[3], std::int8_t(ou)};
                double t[2], ot, t2[2], ot2;
                const int n = segment_crossings(cam, q, q3, o, o3, t, &ot);
                std::int8_t sides[4];
                const bool apart = filter_sides(q, qu, o, ou, sides);
                ASSERT_EQ(apart, apart_by_filter(q, qu, o, ou)) << i;
                if (apart) {
                    ++rejected;
                    ASSERT_EQ(n, 0) << i;
                    continue;
                }
                // (each side exactly image_side_filter's, where the segment's line is unclipped)
                ASSERT_EQ(sides[0], qu ? image_side_filter(q.a, q.b, q.slack, o.a, o.slack) : 0) << i;
                ASSERT_EQ(sides[1], qu ? image_side_filter(q.a, q.b, q.slack, o.b, o.slack) : 0) << i;
                ASSERT_EQ(sides[2], ou ? image_side_filter(o.a, o.b, o.slack, q.a, q.slack) : 0) << i;
                ASSERT_EQ(sides[3], ou ? image_side_filter(o.a, o.b, o.slack, q.b, q.slack) : 0) << i;
                decided += (sides[0] != 0) + (sides[1] != 0) + (sides[2] != 0) + (sides[3] != 0);
                const int n2 = segment_crossings(cam, q, q3, o, o3, sides, t2, &ot2);
                ASSERT_EQ(n, n2) << i << " clip " << clip;
                for (int k = 0; k < n; ++k) ASSERT_EQ(t[k], t2[k]) << i << " clip " << clip;
                ASSERT_TRUE(ot == ot2 || (std::isnan(ot) && std::isnan(ot2))) << i << " clip " << clip;
                met += n > 0;
            }
        });
    EXPECT_GT(rejected, 1000);
    EXPECT_GT(met, 1000);
    EXPECT_GT(decided, 1000);
}

// build_pieces tests a silhouette segment (a copy of its occluder, either way along it) against
// another's occluder once for both pairs: mirrored_crossings gives the second pair's results from
// the first's sides, bit for bit what testing it gives (count, parameters, parameter along the
// occluder), for every direction of the two copies, on lattice points (touches, T-junctions,
// collinear images) and random ones; pairs the quick reject drops have no mirrored crossing.
TEST(SegmentCrossings, MirroredPairEqualsItsOwnTest) {
    std::mt19937_64 rng(8);
    const inkline::Camera cams[] = {
        oblique_perspective(),
        lattice_eye_perspective(),
        oblique_orthographic(),
    };
    int touches = 0, proper = 0, collinear = 0, apart = 0;
    for (const auto& cam : cams)
        segment_pairs(cam, rng, 20000, [&](int i, const glm::dvec3* P, const Segment2& A, const Segment2& B) {
            using namespace inkline;
            const Segment3 A3{P[0], P[1], &P[0], &P[1], 1}, B3{P[2], P[3], &P[2], &P[3], 1};
            auto copy = [](const Segment2& s, bool forward) {
                return forward ? s : Segment2{s.b, s.a, s.v0, s.v1, s.edge, s.slack};
            };
            auto copy3 = [](const Segment3& s, bool forward) {
                return forward ? s : Segment3{s.B, s.A, s.LB, s.LA, 1};
            };
            for (int dirs = 0; dirs < 4; ++dirs) {
                const bool fa = dirs & 1, fb = dirs & 2;
                const Segment2 qa = copy(A, fa), qb = copy(B, fb);
                const Segment3 qa3 = copy3(A3, fa), qb3 = copy3(B3, fb);
                // The mirror tested on its own (as the search does without mirroring, and without
                // the quick reject: the same answers).
                double t_own[2], ot_own;
                const int n_own = segment_crossings(cam, qb, qb3, A, A3, t_own, &ot_own);
                std::int8_t sides[4];
                if (filter_sides(qa, true, B, true, sides)) {  // (the first pair dropped: the mirror too)
                    ++apart;
                    ASSERT_EQ(n_own, 0) << i << " dirs " << dirs;
                    continue;
                }
                double t[2], ot;
                int exact[4], how;
                segment_crossings(cam, qa, qa3, B, B3, sides, t, &ot, exact, &how);
                double tm[2], otm;
                const int n = mirrored_crossings(cam, qb, qb3, A, A3, fa, fb, how, exact, tm, &otm);
                ASSERT_EQ(n, n_own) << i << " dirs " << dirs << " how " << how;
                for (int k = 0; k < n; ++k) ASSERT_EQ(std::bit_cast<std::uint64_t>(tm[k]), std::bit_cast<std::uint64_t>(t_own[k])) << i;
                ASSERT_TRUE(std::bit_cast<std::uint64_t>(otm) == std::bit_cast<std::uint64_t>(ot_own) ||
                            (std::isnan(otm) && std::isnan(ot_own)))
                    << i << " dirs " << dirs;
                if (how == kCollinear) ++collinear;
                else if (how == kMeet) (exact[0] * exact[1] * exact[2] * exact[3] == 0 ? touches : proper) += 1;
            }
        });
    EXPECT_GT(touches, 400);
    EXPECT_GT(proper, 4000);
    EXPECT_GT(collinear, 40);
    EXPECT_GT(apart, 4000);
    std::printf("mirrored pairs: %d touches, %d proper, %d collinear, %d apart\n", touches, proper, collinear, apart);
}

// ---------------------------------------------------------------------------------------------
// fast_orient.hpp: the float-filtered orientations give the exact signs (CGAL's), also where the
// filter cannot decide (collinear / coplanar points, perturbations in the last bit, coordinates
// near the ends of the double range).

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

int cgal_orient2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
    return int(CGAL::orientation(K::Point_2(a.x, a.y), K::Point_2(b.x, b.y), K::Point_2(c.x, c.y)));
}
int cgal_orient3(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d) {
    return int(CGAL::orientation(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z), K::Point_3(c.x, c.y, c.z),
                                 K::Point_3(d.x, d.y, d.z)));
}

}  // namespace

TEST(FastOrient, Orient2MatchesCgal) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int zeros = 0, n = 0;
    for (double scale : {1.0, 1024.0, 1e-150, 1e150, 1e-300, 1e300}) {
        for (int i = 0; i < 20000; ++i) {
            const glm::dvec2 a(U(rng) * scale, U(rng) * scale), b(U(rng) * scale, U(rng) * scale);
            glm::dvec2 c(U(rng) * scale, U(rng) * scale);
            if (i % 2) {  // on the line a-b, rounded, then nudged by a few ulps
                const double t = U(rng) * 2.0;
                c = a + t * (b - a);
                if (i % 4 == 1) c.x = up_next(c.x);
                if (i % 8 == 3) c.y = down_next(c.y);
            }
            if (i % 16 == 5) c = glm::dvec2(a.x + 4.0 * (b.x - a.x), a.y + 4.0 * (b.y - a.y));  // often exact
            const int want = cgal_orient2(a, b, c);
            zeros += want == 0;
            ++n;
            ASSERT_EQ(inkline::orient2_fast(a, b, c), want) << "scale " << scale << " case " << i;
        }
    }
    // Lattice points: many exactly collinear triples.
    for (int i = 0; i < 20000; ++i) {
        std::uniform_int_distribution<int> L(-4, 4);
        const glm::dvec2 a(L(rng), L(rng)), b(L(rng), L(rng)), c(L(rng), L(rng));
        const int want = cgal_orient2(a * 0.1, b * 0.1, c * 0.1);
        zeros += want == 0;
        ASSERT_EQ(inkline::orient2_fast(a * 0.1, b * 0.1, c * 0.1), want);
    }
    EXPECT_GT(zeros, 1000);  // the exact path was taken, and gave 0
    EXPECT_GT(n, 0);
}

// path_side_fast (the walks' test of where an edge meets the path, before or after u): the exact
// orientation of (lower end, upper end, u) for segments straddling the horizontal line through u,
// also where the comparisons cannot decide (an end at u.x, u on the segment, ulps from it).
TEST(FastOrient, PathSideMatchesOrient2) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    auto want_of = [](glm::dvec2 q0, glm::dvec2 q1, glm::dvec2 u) {
        return q0.y < q1.y ? cgal_orient2(q0, q1, u) : cgal_orient2(q1, q0, u);
    };
    int zeros = 0, compared = 0, n = 0;
    for (double scale : {1.0, 1024.0, 1e-150, 1e150, 1e-300, 1e300}) {
        for (int i = 0; i < 20000; ++i) {
            const glm::dvec2 u(U(rng) * scale, U(rng) * scale);
            // ends strictly below and above u's line (either first)
            glm::dvec2 q0(U(rng) * scale, u.y - std::abs(U(rng)) * scale), q1(U(rng) * scale, u.y + std::abs(U(rng)) * scale);
            if (q0.y >= u.y) q0.y = std::nextafter(u.y, -std::numeric_limits<double>::infinity());
            if (q1.y <= u.y) q1.y = up_next(u.y);
            if (i % 2) std::swap(q0, q1);
            if (i % 3 == 1) q0.x = u.x;  // an end straight above or below u
            if (i % 5 == 2) {  // u on the segment, rounded, then nudged
                glm::dvec2 v = u;
                const double t = (u.y - q0.y) / (q1.y - q0.y);
                v.x = q0.x + t * (q1.x - q0.x);
                if (i % 4 == 1) v.x = up_next(v.x);
                const int want = want_of(q0, q1, v);
                zeros += want == 0;
                ++n;
                ASSERT_EQ(inkline::path_side_fast(q0, q1, v), want) << "scale " << scale << " case " << i;
                continue;
            }
            const int want = want_of(q0, q1, u);
            compared += (q0.x < u.x) == (q1.x < u.x) && q0.x != u.x && q1.x != u.x;
            ++n;
            ASSERT_EQ(inkline::path_side_fast(q0, q1, u), want) << "scale " << scale << " case " << i;
        }
    }
    // Lattice points: segments through u, ends at u.x.
    for (int i = 0; i < 20000; ++i) {
        std::uniform_int_distribution<int> L(-4, 4);
        const glm::dvec2 u(L(rng) * 0.1, L(rng) * 0.1);
        const int d0 = 1 + (L(rng) + 4) % 4, d1 = 1 + (L(rng) + 4) % 4;
        glm::dvec2 q0(L(rng) * 0.1, u.y - d0 * 0.1), q1(L(rng) * 0.1, u.y + d1 * 0.1);
        if (!(q0.y < u.y && u.y < q1.y)) continue;  // (0.1 steps, rounded)
        if (i % 2) std::swap(q0, q1);
        const int want = want_of(q0, q1, u);
        zeros += want == 0;
        ++n;
        ASSERT_EQ(inkline::path_side_fast(q0, q1, u), want) << "lattice case " << i;
    }
    EXPECT_GT(zeros, 100);      // the exact path was taken, and gave 0
    EXPECT_GT(compared, 10000);  // the comparisons decided many
    EXPECT_GT(n, 100000);
}

TEST(FastOrient, Orient3AndEyeMatchCgal) {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int zeros = 0;
    for (double scale : {1.0, 1e-150, 1e150, 1e-300, 1e300}) {
        for (int i = 0; i < 20000; ++i) {
            const glm::dvec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng)), c(U(rng), U(rng), U(rng));
            glm::dvec3 d(U(rng), U(rng), U(rng));
            if (i % 2) {  // in the plane abc, rounded, then nudged
                const double s = U(rng), t = U(rng);
                d = a + s * (b - a) + t * (c - a);
                if (i % 4 == 1) d.z = up_next(d.z);
            }
            if (i % 16 == 7) d = a + 2.0 * (b - a);  // on the line ab: often exactly coplanar
            const int want = cgal_orient3(a * scale, b * scale, c * scale, d * scale);
            zeros += want == 0;
            ASSERT_EQ(inkline::orient3_fast(a * scale, b * scale, c * scale, d * scale), want)
                << "scale " << scale << " case " << i;
        }
    }
    for (int i = 0; i < 20000; ++i) {  // lattice points: coplanar quadruples
        std::uniform_int_distribution<int> L(-3, 3);
        auto p = [&] { return glm::dvec3(L(rng), L(rng), L(rng)) * 0.1; };
        const glm::dvec3 a = p(), b = p(), c = p(), d = p();
        const int want = cgal_orient3(a, b, c, d);
        zeros += want == 0;
        ASSERT_EQ(inkline::orient3_fast(a, b, c, d), want);
    }
    EXPECT_GT(zeros, 1000);
    // The eye as the fourth point (perspective) or at infinity (orthographic).
    const auto persp = inkline::Camera::perspective({0.3, 0.2, 5.0}, {0, 0, 0}, {0, 1, 0}, 40.0, 64, 64);
    const auto ortho = inkline::Camera::orthographic({0.3, 0.2, 5.0}, {0, 0, 0}, {0, 1, 0}, 3.0, 64, 64);
    for (int i = 0; i < 5000; ++i) {
        const glm::dvec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng));
        const glm::dvec3 c = i % 2 ? a + U(rng) * (b - a) + U(rng) * (persp.eye() - a) : glm::dvec3(U(rng), U(rng), U(rng));
        for (const auto* cam : {&persp, &ortho})
            ASSERT_EQ(inkline::orient_eye_fast(*cam, a, b, c), inkline::orient_eye(*cam, a, b, c)) << i;
    }
}

// ---------------------------------------------------------------------------------------------
// outer_box and BoxPairs (the batch crossing search of build_pieces)

TEST(OuterBox, ContainsTheDoubleBoxWidenedBySlack) {
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (int i = 0; i < 200000; ++i) {
        // magnitudes from subnormal to beyond float's range, and exact float values
        const double scale = std::ldexp(1.0, int(rng() % 300) - 160);
        glm::dvec2 a(U(rng) * scale, U(rng) * scale), b(U(rng) * scale, U(rng) * scale);
        if (i % 7 == 0) a = glm::dvec2(double(float(a.x)), double(float(a.y)));
        Segment2 s = seg(a, b, 0);
        s.slack = i % 3 == 0 ? 0.0 : std::abs(U(rng)) * scale * 1e-6;
        const inkline::Box2f box = inkline::outer_box(s);
        const double lo_x = std::min(a.x, b.x) - s.slack, hi_x = std::max(a.x, b.x) + s.slack;
        const double lo_y = std::min(a.y, b.y) - s.slack, hi_y = std::max(a.y, b.y) + s.slack;
        ASSERT_LE(double(box.x0), lo_x) << i;
        ASSERT_GE(double(box.x1), hi_x) << i;
        ASSERT_LE(double(box.y0), lo_y) << i;
        ASSERT_GE(double(box.y1), hi_y) << i;
        ASSERT_EQ(box.v0, s.v0);
        ASSERT_EQ(box.v1, s.v1);
    }
    // beyond float's range: infinite on the outside
    const inkline::Box2f huge = inkline::outer_box(seg(-1e300, 1e300, 1e300, 2e300, 0));
    EXPECT_EQ(huge.x0, -INFINITY);
    EXPECT_EQ(huge.x1, INFINITY);
    EXPECT_EQ(huge.y1, INFINITY);
    // an infinite slack (image_slack for a point at the eye plane): the whole plane
    Segment2 s = seg(1, 2, 3, 4, 0);
    s.slack = INFINITY;
    const inkline::Box2f all = inkline::outer_box(s);
    EXPECT_EQ(all.x0, -INFINITY);
    EXPECT_EQ(all.y1, INFINITY);
}

namespace {
// Every (i, k) with overlapping boxes and no shared vertex, by brute force.
std::vector<std::uint64_t> brute_pairs(const std::vector<inkline::Box2f>& a, const std::vector<inkline::Box2f>& b) {
    std::vector<std::uint64_t> out;
    for (std::uint32_t i = 0; i < a.size(); ++i)
        for (std::uint32_t k = 0; k < b.size(); ++k) {
            const auto &p = a[i], &q = b[k];
            const bool over = p.x0 <= q.x1 && q.x0 <= p.x1 && p.y0 <= q.y1 && q.y0 <= p.y1;
            const bool shared = p.v0 == q.v0 || p.v0 == q.v1 || p.v1 == q.v0 || p.v1 == q.v1;
            if (over && !shared) out.push_back(std::uint64_t(i) << 32 | k);
        }
    return out;
}
void expect_pairs(const std::vector<Segment2>& sa, const std::vector<Segment2>& sb, const std::string& what) {
    std::vector<inkline::Box2f> a, b;
    for (const auto& s : sa) a.push_back(inkline::outer_box(s));
    for (const auto& s : sb) b.push_back(inkline::outer_box(s));
    inkline::BoxPairs pairs;
    std::vector<std::uint64_t> kept_storage;  // (a vector with room left from an earlier call)
    for (int round = 0; round < 3; ++round) {  // storage reused from call to call
        std::vector<std::uint64_t> got;
        if (round == 2) {
            // appended after what the vector holds, its spare capacity reused
            got.swap(kept_storage);
            got.assign(3, ~std::uint64_t(0));
        }
        pairs.find(a, b, kW, kH, got);
        if (round == 2) {
            ASSERT_GE(got.size(), 3u) << what;
            for (int k = 0; k < 3; ++k) EXPECT_EQ(got[k], ~std::uint64_t(0)) << what << ": held pair overwritten";
            got.erase(got.begin(), got.begin() + 3);
        }
        if (round == 0) kept_storage = got, kept_storage.reserve(2 * got.size() + 8);
        std::vector<std::uint64_t> want = brute_pairs(a, b);
        std::sort(got.begin(), got.end());
        const auto dup = std::adjacent_find(got.begin(), got.end());
        EXPECT_TRUE(dup == got.end()) << what << ": pair reported twice";
        EXPECT_EQ(got.size(), want.size()) << what;
        EXPECT_TRUE(got == want) << what << ": not the brute-force pairs";
    }
}
}  // namespace

TEST(BoxPairs, EqualsBruteForceOnMixedSegments) {
    std::mt19937_64 rng(31);
    std::vector<Segment2> a, b;
    for (std::uint32_t i = 0; i < 1500; ++i) a.push_back(random_segment(rng, i));
    for (std::uint32_t i = 0; i < 1500; ++i) b.push_back(random_segment(rng, 5000 + i));
    // shared vertices: some of b reuse a's vertices (never paired), some are a's own segments
    for (std::uint32_t i = 0; i < 300; ++i) {
        Segment2 s = random_segment(rng, 9000 + i);
        s.v0 = a[i].v1;
        b.push_back(s);
        b.push_back(a[i + 300]);
    }
    expect_pairs(a, b, "mixed");
    expect_pairs(b, a, "mixed, swapped");
}

TEST(BoxPairs, DenseClustersAndDegenerateSets) {
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Segment2> a, b;
    // a few hundred tiny segments within a pixel (a dense fold), beside sparse long ones
    for (std::uint32_t i = 0; i < 400; ++i) {
        const glm::dvec2 p(100.0 + U(rng), 200.0 + U(rng));
        (i % 2 ? a : b).push_back(seg(p, p + glm::dvec2(U(rng) - 0.5, U(rng) - 0.5) * 0.3, i));
    }
    for (std::uint32_t i = 0; i < 50; ++i)
        (i % 2 ? a : b).push_back(seg(U(rng) * kW, U(rng) * kH, U(rng) * kW, U(rng) * kH, 1000 + i));
    expect_pairs(a, b, "dense");
    // all boxes the same point; one set empty; all segments far outside the image
    std::vector<Segment2> same, far;
    for (std::uint32_t i = 0; i < 60; ++i) same.push_back(seg(5, 5, 5, 5, i));
    for (std::uint32_t i = 0; i < 60; ++i) far.push_back(seg(1e7 + i, -1e7, 1e7 + i + 0.5, -1e7 + 1, 200 + i));
    expect_pairs(same, same, "one point");
    expect_pairs(same, {}, "empty");
    expect_pairs(far, far, "far outside");
    std::vector<Segment2> inf = {seg(1, 2, 3, 4, 0)};
    inf[0].slack = INFINITY;
    expect_pairs(inf, a, "infinite slack");
}

// Many boxes in each cell, most steps of four with no pair and the pairs at every lane of a step
// (pairs() compacts a step's hits only when it has some): each query meets exactly the boxes it
// should, in cells full of boxes it misses.
TEST(BoxPairs, SparseHitsInFullCells) {
    std::vector<Segment2> a, b;
    // rows of 64 short disjoint segments 1 px apart (a few cells each hold many)
    for (std::uint32_t r = 0; r < 4; ++r)
        for (std::uint32_t i = 0; i < 64; ++i) {
            const double x = 100.0 + i, y = 100.0 + 8.0 * r;
            b.push_back(seg(x, y, x + 0.25, y + 0.25, 2 * (64 * r + i)));
        }
    // a query near every fifth box (lanes 0..3 in turn), each meeting that box alone
    for (std::uint32_t k = 0; k < b.size(); k += 5) {
        const glm::dvec2 p = b[k].a + glm::dvec2(0.1, 0.1);
        a.push_back(seg(p, p + glm::dvec2(0.05, 0.05), 10000 + 2 * k));
    }
    expect_pairs(a, b, "sparse hits");
    expect_pairs(b, a, "sparse hits, swapped");
}

// The binning split among threads (build_pieces' occluders on a large view) makes the same bins
// as one thread: every query then gives the same pairs in the same order, for any part count.
TEST(BoxPairs, SplitBinningEqualsOneThread) {
    std::mt19937_64 rng(57);
    std::vector<Segment2> segs, queries;
    for (std::uint32_t i = 0; i < 9000; ++i) segs.push_back(random_segment(rng, i));
    for (std::uint32_t i = 0; i < 2000; ++i) queries.push_back(random_segment(rng, 20000 + i));
    for (std::uint32_t i = 0; i < 40; ++i)  // big boxes (tested against every box), spread out
        segs[i * 211] = seg(-10.0 + i, 5.0, kW + 10.0 - i, kH - 5.0, 30000 + i);
    std::vector<inkline::Box2f> b, a;
    for (const auto& s : segs) b.push_back(inkline::outer_box(s));
    for (const auto& s : queries) a.push_back(inkline::outer_box(s));
    inkline::BoxPairs one;
    one.prepare(b, kW, kH);
    std::vector<std::uint64_t> want;
    std::vector<std::uint32_t> hits;
    one.pairs(a, want, hits);
    ASSERT_GT(want.size(), 1000u);
    inkline::WorkerTeam team;
    for (int parts : {2, 3, 8}) {
        inkline::BoxPairs split;
        for (int round = 0; round < 2; ++round) {  // (storage kept from the first round)
            split.prepare(b, kW, kH, &team, parts);
            std::vector<std::uint64_t> got;
            split.pairs(a, got, hits);
            EXPECT_TRUE(got == want) << parts << " parts, round " << round;
        }
    }
}
