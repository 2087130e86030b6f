// Image-space crossings: a uniform grid over the projected occluding edges (silhouettes and
// borders) and exact 2D predicates (CGAL) deciding whether two projected segments meet.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <algorithm>
#include <cmath>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "core/worker_thread.hpp"

namespace inkline {

struct Segment2 {
    glm::dvec2 a, b;
    std::uint32_t v0, v1;  // mesh vertices of the edge; segments sharing one never "cross"
    std::uint32_t edge;    // mesh edge
    // Bound on the distance of a and b from the exact images of their 3D points (rounding of the
    // projection, image_slack); 0 for segments given in the image.
    double slack = 0.0;
};

// Where a projected segment lies in 3D, for the exact image-space predicates: the points seen at
// its ends (where the near plane clipped it, the point constructed there) and two exact points of
// its line in the same direction (the mesh edge's vertices).
struct Segment3 {
    glm::dvec3 A, B;
    const glm::dvec3 *LA, *LB;
    // Whether A == *LA and B == *LB (not clipped), if known (1 / 0); -1: compare them when needed.
    std::int8_t unclipped = -1;
};

// Bound on the rounding error of camera.project(P) (pixels), for a point in front of the eye
// plane; see image_slack in crossings.cpp.
double image_slack(const Camera& camera, const glm::dvec3& P, const glm::dvec2& p);

// Parameters t in [0,1] along `q` (q.a + t (q.b - q.a)) where `o` meets it, decided exactly on
// the double coordinates: none if they do not meet; one for a proper crossing or a touch
// (an end point on the other segment); two, the ends of the shared part, if collinear and
// overlapping. Degenerate (zero-length) segments and segments sharing a mesh vertex give none.
int segment_crossings(const Segment2& q, const Segment2& o, double t[2]);

// The same for projected mesh segments, decided exactly in 3D rather than on the rounded image
// coordinates: whether an end point lies left of, right of or on the other segment's image is the
// orientation of the end point against the plane through the eye and the other segment's line
// (image_orientation, core/predicates.hpp), so that a vertex that lies exactly on another edge's
// image (a T-junction, two silhouettes meeting, edges collinear in the image) is seen as such,
// whatever the rounding of the projection. The parameters are constructions from the image
// coordinates, clamped to [0, 1]. All points must lie in front of the eye plane.
int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, double t[2]);
// The same, and *o_t: where they meet along `o`, exactly the first parameter the call with q and o
// swapped gives, when they meet and their images are not collinear; otherwise NaN.
int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, double t[2], double* o_t);
// The same, given the sides the caller's quick reject decided already (sides[0], [1]: o's ends
// against q's line, [2], [3]: q's ends against o's line; each image_side_filter's answer for the
// pair's coordinates and slacks, taken only if that line's segment is unclipped, as
// apart_by_filter does; 0: not known): they are not computed again. The same results.
int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, const std::int8_t sides[4], double t[2], double* o_t);

// The same, also telling how the pair was decided (*how, below) and the sides it decided
// (exact[4], in the order of `sides`: each is image_orientation's sign for that end point and line,
// when image_side_filter is right): exact[0], [1] are set from kApartOnQsLine on, [2], [3] from
// kApartOnOsLine on.
enum : int {
    kDecidedBeforeSides = 0,  // a shared vertex, a degenerate segment, boxes apart: nothing
    kApartOnQsLine = 1,       // o's ends strictly on one side of q's line: nothing
    kApartOnOsLine = 2,       // q's ends strictly on one side of o's line: nothing
    kCollinear = 3,           // exact[0] = exact[1] = 0: the shared part, if any
    kMeet = 4,                // one crossing or touch, t[0] = crossing_param(q, o, exact) clamped
};
int segment_crossings(const Camera& camera, const Segment2& q, const Segment3& q3, const Segment2& o,
                      const Segment3& o3, const std::int8_t sides[4], double t[2], double* o_t, int exact[4],
                      int* how);
// Where the image of o meets q (along q, not clamped), for segments whose images meet and are not
// collinear, given the four sides of the pair (s[0], [1]: o's ends against q's line, [2], [3]: q's
// ends against o's line; exact orientations): what segment_crossings computes from them.
double crossing_param(const Segment2& q, const Segment2& o, const int s[4]);

// What segment_crossings(camera, q2, q2_3d, o1, o1_3d, t, o_t) gives (its return value, t and
// *o_t, bit for bit) for the mirror of a pair tested already, without testing it: that pair was
// (q1, o2), q1 a copy of o1's image and ends (in its direction if q1_forward, else reversed),
// q2 a copy of o2 likewise (q2_forward), all four unclipped (their ends the mesh vertices, LA and
// LB) with the same slack as their copies; `how` and `exact` are what segment_crossings said of
// (q1, o2). The early exits before the sides (a shared vertex, a degenerate segment, boxes apart
// by more than the slacks) are symmetric. Each side is the exact orientation of a mesh vertex
// against the image line of two others (image_orientation, antisymmetric in the line's ends;
// image_side_filter decides one only when it agrees with it), so the mirror's four sides are
// (q1, o2)'s permuted, negated where a copy runs against its occluder. From them the mirror's
// parameters are computed on its own coordinates by the code its own test runs (crossing_param).
// Collinear images are tested on their own (segment_crossings).
int mirrored_crossings(const Camera& camera, const Segment2& q2, const Segment3& q2_3d, const Segment2& o1,
                       const Segment3& o1_3d, bool q1_forward, bool q2_forward, int how, const int exact[4],
                       double t[2], double* o_t);

// The side of line (a, b) the exact image of p lies on (1 left, -1 right), when the rounded image
// coordinates decide it; 0 when they do not. For a and b the images of the ends of an unclipped
// segment (a clipped end is a construction, off the edge's line by its own rounding) and p the
// image of a point, each within its slack (l_slack, p_slack: image_slack) of the exact image:
// moving them changes the determinant u x v (u = b - a, v = p - a) by at most
// 2 d (|u|_1 + |v|_1) + 8 d^2 (d the larger slack); computing it from the rounded coordinates errs
// by at most 5 eps |u|_1 |v|_1 more. The 3D-exact segment_crossings decides by this first.
// LineSideFilter keeps what depends on the line alone (b - a and its norm) for several points.
struct LineSideFilter {
    glm::dvec2 a, u;
    double l_slack, nu;
    LineSideFilter(glm::dvec2 a_, glm::dvec2 b, double l_slack_)
        : a(a_), u(b - a_), l_slack(l_slack_), nu(std::abs(u.x) + std::abs(u.y)) {}
    [[gnu::always_inline]] int side(glm::dvec2 p, double p_slack) const {
        constexpr double kEps = 0x1p-53;
        const double vx = p.x - a.x, vy = p.y - a.y;
        const double det = u.x * vy - u.y * vx;
        const double d = std::max(l_slack, p_slack);
        const double nv = std::abs(vx) + std::abs(vy);
        const double bound = 2.0 * d * (nu + nv) + 8.0 * d * d + 8.0 * kEps * nu * nv;
        return int(det > bound) - int(det < -bound);  // (NaN: 0)
    }
};
inline int image_side_filter(glm::dvec2 a, glm::dvec2 b, double l_slack, glm::dvec2 p, double p_slack) {
    return LineSideFilter(a, b, l_slack).side(p, p_slack);
}

// True only when the 3D-exact segment_crossings(camera, q, q3, o, o3) finds no crossing, decided
// by image_side_filter alone (o's ends on one side of q's line, or q's on one side of o's; a
// segment's line used only if it is unclipped): a quick reject before the full test. The
// reference that filter_sides (below, which build_pieces calls: it also keeps the sides for
// segment_crossings) is tested against.
inline bool apart_by_filter(const Segment2& q, bool q_unclipped, const Segment2& o, bool o_unclipped) {
    if (q_unclipped) {
        const int s0 = image_side_filter(q.a, q.b, q.slack, o.a, o.slack);
        if (s0 != 0 && s0 == image_side_filter(q.a, q.b, q.slack, o.b, o.slack)) return true;
    }
    if (o_unclipped) {
        const int s2 = image_side_filter(o.a, o.b, o.slack, q.a, q.slack);
        if (s2 != 0 && s2 == image_side_filter(o.a, o.b, o.slack, q.b, q.slack)) return true;
    }
    return false;
}

// The sides segment_crossings decides first, by image_side_filter alone (0 where it does not decide
// or the line's segment is clipped), and whether they show the pair apart (apart_by_filter). The
// four sides are all computed and combined without branches (most pairs are rejected, on either
// line: a branch per side would be mispredicted often); when the pair is not apart they are
// exactly what deciding them one by one gives.
// (always inlined: build_pieces runs it on every pair the box search finds)
[[gnu::always_inline]] inline bool filter_sides(const Segment2& q, bool q_unclipped, const Segment2& o, bool o_unclipped,
                                              std::int8_t sides[4]) {
    const LineSideFilter lq(q.a, q.b, q.slack), lo(o.a, o.b, o.slack);
    const int qm = q_unclipped ? 1 : 0, om = o_unclipped ? 1 : 0;
    const int s0 = qm * lq.side(o.a, o.slack), s1 = qm * lq.side(o.b, o.slack);
    const int s2 = om * lo.side(q.a, q.slack), s3 = om * lo.side(q.b, q.slack);
    sides[0] = std::int8_t(s0), sides[1] = std::int8_t(s1), sides[2] = std::int8_t(s2), sides[3] = std::int8_t(s3);
    return ((s0 != 0) & (s0 == s1)) | ((s2 != 0) & (s2 == s3));
}

// The box of a projected segment widened by its slack, in float, rounded outward: two segments
// whose exact images meet have overlapping boxes (closed), whatever the rounding. With the mesh
// vertices of the segment's edge: segments sharing one never "cross" (segment_crossings).
struct Box2f {
    float x0, y0, x1, y1;
    std::uint32_t v0, v1;
};
Box2f outer_box(const Segment2& s);

// All overlapping pairs between two sets of boxes, each pair once: a uniform grid with cells
// about four times the boxes' mean size, the second set binned, each box of the first tested in
// its cells against the pairs whose overlap's lower corner lies in that cell (so a pair is found in one cell only). Boxes covering
// many cells (clipped or very long segments) are tested against every box of the other set.
// Cost: the boxes' cells plus the pairs tested; the storage is reused from call to call.
class BoxPairs {
public:
    // Appends (i << 32 | k) for every i in `a`, k in `b` whose boxes overlap and whose edges share
    // no vertex, in no fixed order. `width`, `height`: the image (cells cover at most the image
    // widened by one size each side; the rim cells hold whatever lies beyond).
    void find(const std::vector<Box2f>& a, const std::vector<Box2f>& b, double width, double height,
              std::vector<std::uint64_t>& out) {
        prepare(b, width, height);
        pairs(a, out, hits_);
    }
    // The same in two steps: bin `b` (kept by reference: it must outlive the queries), then find
    // the pairs of a set `a` (const: several threads may query at once, each with its own `hits`).
    // With a team and parts > 1, the binning is split among `parts` threads (ranges of the boxes,
    // then of the cells); the bins are the same as one thread's: each cell's boxes in box order.
    void prepare(const std::vector<Box2f>& b, double width, double height, WorkerTeam* team = nullptr, int parts = 1);
    void pairs(const std::vector<Box2f>& a, std::vector<std::uint64_t>& out, std::vector<std::uint32_t>& hits) const;

private:
    struct Bins {
        std::vector<std::uint32_t> begin, items, big;
        std::vector<float> x0, y0, x1, y1;  // the items' boxes, parallel to items
        std::vector<std::uint32_t> v0, v1;  // and their vertices
        std::vector<std::int32_t> cx0, cy0;  // and the first cell of their range
    };
    void bin(const std::vector<Box2f>& boxes, Bins& bins);
    void bin_split(const std::vector<Box2f>& boxes, Bins& bins, WorkerTeam& team, int parts);
    // A box's cells: x0, x1, y0, y1 (x0 < 0: a big box, in no cell); false for a big box.
    bool cell_range(const Box2f& b, std::array<std::int16_t, 4>& r) const;
    const std::vector<Box2f>* b_boxes_ = nullptr;
    std::uint32_t most_ = 0;  // the most boxes in a cell
    // Cell of a coordinate: monotone, clamped to the grid (truncation is the floor for c >= 0).
    int cx(float x) const {
        const double c = (double(x) - lo_x_) * inv_x_;
        return !(c >= 0.0) ? 0 : c >= nx_ - 1 ? nx_ - 1 : int(c);
    }
    int cy(float y) const {
        const double c = (double(y) - lo_y_) * inv_y_;
        return !(c >= 0.0) ? 0 : c >= ny_ - 1 ? ny_ - 1 : int(c);
    }
    double lo_x_ = 0.0, lo_y_ = 0.0, inv_x_ = 1.0, inv_y_ = 1.0;
    int nx_ = 1, ny_ = 1;
    Bins b_;
    std::vector<std::uint32_t> hits_;
    std::vector<std::array<std::int16_t, 4>> ranges_;
    // bin_split's per part: the boxes in each cell (then each cell's next slot), the big boxes
    std::vector<std::vector<std::uint32_t>> part_counts_, part_big_;
};

class SegmentGrid {
public:
    // Indexes `segments` in a uniform grid over their bounding box, limited to the image
    // rectangle widened by one image size on each side; cells on the grid's rim also hold
    // whatever lies beyond it, so queries stay exact anywhere.
    SegmentGrid(const std::vector<Segment2>& segments, double width, double height) { build(segments, width, height); }
    SegmentGrid() = default;  // indexes nothing until build()
    // Indexes `segments` instead of what it held (its storage reused).
    void build(const std::vector<Segment2>& segments, double width, double height);

    // Calls fn(index) once for every indexed segment whose cells overlap q's cells (a superset of
    // the segments that can meet q; the caller decides with segment_crossings). Several threads
    // may query one grid at once (the marks of the segments already reported are per thread).
    template <class Fn>
    void candidates(const Segment2& q, Fn&& fn) const {
        thread_local std::vector<std::uint32_t> mark;
        thread_local std::uint32_t stamp = 0;
        if (mark.size() < count_) mark.resize(count_, 0);
        if (++stamp == 0) {  // (stamps of every earlier query, of any grid, are older)
            std::fill(mark.begin(), mark.end(), 0);
            stamp = 1;
        }
        visit_cells(q.a, q.b, q.slack, [&](std::size_t cell) {
            for (std::uint32_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
                const std::uint32_t s = items_[k];
                if (mark[s] == stamp) continue;
                mark[s] = stamp;
                fn(s);
            }
        });
    }
    std::size_t cells() const { return std::size_t(nx_) * ny_; }

private:
    // The cells of segment (a, b) widened by `margin` (the rounding of its images).
    template <class Fn>
    void visit_cells(glm::dvec2 a, glm::dvec2 b, double margin, Fn&& fn) const;
    // floor((x - lo) / cell) clamped to the grid, without the floor: the quotient is below 0 exactly
    // when its floor is, at least n - 1 exactly when its floor is (an integer), and truncated
    // like floored otherwise (c >= 0).
    int cell_x(double x) const {
        const double c = (x - lo_.x) / cell_.x;
        return c < 0.0 ? 0 : c >= nx_ - 1 ? nx_ - 1 : int(c);
    }
    int cell_y(double y) const {
        const double c = (y - lo_.y) / cell_.y;
        return c < 0.0 ? 0 : c >= ny_ - 1 ? ny_ - 1 : int(c);
    }

    glm::dvec2 lo_{0.0}, cell_{1.0};
    int nx_ = 1, ny_ = 1;
    std::vector<std::uint32_t> cell_begin_{0, 0}, items_;
    std::vector<std::uint32_t> fill_, visits_, visit_end_;  // build()'s working arrays
    std::size_t count_ = 0;  // segments indexed
};

template <class Fn>
void SegmentGrid::visit_cells(glm::dvec2 a, glm::dvec2 b, double margin, Fn&& fn) const {
    const int x0 = cell_x(std::min(a.x, b.x) - margin), x1 = cell_x(std::max(a.x, b.x) + margin);
    const int y0 = cell_y(std::min(a.y, b.y) - margin), y1 = cell_y(std::max(a.y, b.y) + margin);
    const bool many = std::size_t(x1 - x0 + 1) * std::size_t(y1 - y0 + 1) > 8;
    const glm::dvec2 d = b - a;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            // For long segments skip interior cells that the segment's line clearly misses
            // (a conservative test: the margin is a quarter of a cell).
            if (many && x > 0 && y > 0 && x + 1 < nx_ && y + 1 < ny_) {
                const glm::dvec2 c = lo_ + (glm::dvec2(x, y) + 0.5) * cell_;
                const double side = d.x * (c.y - a.y) - d.y * (c.x - a.x);
                const double reach = (std::abs(d.x) * cell_.y + std::abs(d.y) * cell_.x) * 0.75 +
                                     margin * (std::abs(d.x) + std::abs(d.y));
                if (std::abs(side) > reach) continue;
            }
            fn(std::size_t(y) * nx_ + x);
        }
}

}  // namespace inkline
