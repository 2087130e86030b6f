#include "model/self_intersections.hpp"
#include "model/early_self_intersections.hpp"
#include "model/reorder.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <exception>
#include <condition_variable>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

namespace inkline {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
// A face's box: floats rounded outward (so it holds the face), and the face as the box's id
// (28 bytes).
struct Box : CGAL::Box_intersection_d::Box_d<float, 3, CGAL::Box_intersection_d::ID_NONE> {
    using Base = CGAL::Box_intersection_d::Box_d<float, 3, CGAL::Box_intersection_d::ID_NONE>;
    Box(float lo[3], float hi[3], std::uint32_t f) : Base(lo, hi), face(f) {}
    std::size_t id() const { return face; }
    std::uint32_t face;
};

K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

float down(double x) {
    const float f = float(x);
    return double(f) <= x ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float up(double x) {
    const float f = float(x);
    return double(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// A face as the pair test reads it: its vertices, its corners, and its plane for the float filter
// below, n = (b - a) x (c - a) as Shewchuk's orient3d computes it with a as the origin, and per
// component the permanent of that product (the sum of the absolute values of its two terms).
// Made from the mesh's arrays where it is needed (face_data), never stored for every face: such
// an array, 136 bytes a face, was half of a big model's peak memory while it loaded.
struct FaceData {
    std::array<std::uint32_t, 3> v;
    glm::dvec3 p[3];
    glm::dvec3 n, permanent;
};

// A face's plane alone (the patch test and the normals read no more). The one place its
// arithmetic is written: every filter reads these same doubles.
struct Plane {
    glm::dvec3 n, permanent;
};
[[gnu::always_inline]] inline Plane plane_of(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 u = b - a, v = c - a;
    return {{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x},
            {std::abs(u.y * v.z) + std::abs(u.z * v.y), std::abs(u.z * v.x) + std::abs(u.x * v.z),
             std::abs(u.x * v.y) + std::abs(u.y * v.x)}};
}

Plane face_plane(const SearchInput& in, std::uint32_t f) {
    const auto& t = in.faces[f];
    return plane_of(in.positions[t[0]], in.positions[t[1]], in.positions[t[2]]);
}

FaceData face_data(const SearchInput& in, std::uint32_t f) {
    const auto& t = in.faces[f];
    FaceData d;
    d.v = {t[0], t[1], t[2]};
    for (int k = 0; k < 3; ++k) d.p[k] = in.positions[t[k]];
    const Plane plane = plane_of(d.p[0], d.p[1], d.p[2]);
    d.n = plane.n;
    d.permanent = plane.permanent;
    return d;
}

// The side of face f's plane that x lies on (+1 or -1, a fixed convention), or 0 when the float
// filter cannot tell (then only an exact predicate can). The orientation determinant
// dot(n, x - a) has the shape of Shewchuk's orient3d (each term a difference times a 2x2 minor of
// differences, three terms summed), so his bound o3derrboundA, (7 + 56 eps) eps times the
// permanent, holds; away from underflow and overflow only.
[[gnu::always_inline]] inline int side_if_certain(const FaceData& face, const glm::dvec3& x) {
    const glm::dvec3 w = x - face.p[0];
    const double det = face.n.x * w.x + face.n.y * w.y + face.n.z * w.z;
    const double permanent =
        face.permanent.x * std::abs(w.x) + face.permanent.y * std::abs(w.y) + face.permanent.z * std::abs(w.z);
    if (!(permanent > 1e-250) || !(permanent < 1e250)) return 0;
    const double bound = 7.7715611723761027e-16 * permanent;
    return det > bound ? 1 : det < -bound ? -1 : 0;
}

// Certainly apart beyond their shared corners: the corners of `other` numbered in `far` all
// strictly on one side of the plane of `face`, so that the faces can meet only where they share
// corners.
template <std::size_t N>
[[gnu::always_inline]] inline bool certainly_one_side(const FaceData& face, const FaceData& other, const std::array<int, N>& far) {
    const int first = side_if_certain(face, other.p[far[0]]);
    if (first == 0) return false;
    for (std::size_t k = 1; k < N; ++k)
        if (side_if_certain(face, other.p[far[k]]) != first) return false;
    return true;
}

// Shewchuk's orient3d(a, b, c, d) in floating point: its sign when his bound o3derrboundA,
// (7 + 56 eps) eps times the permanent, settles it, else 0 (then only an exact predicate can);
// away from underflow and overflow only (the filter of side_if_certain, on four input points).
int orient3d_if_certain(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    const glm::dvec3 ad = a - d, bd = b - d, cd = c - d;
    const double bc = bd.x * cd.y, cb = cd.x * bd.y, ca = cd.x * ad.y, ac = ad.x * cd.y, ab = ad.x * bd.y, ba = bd.x * ad.y;
    const double det = ad.z * (bc - cb) + bd.z * (ca - ac) + cd.z * (ab - ba);
    const double permanent = (std::abs(bc) + std::abs(cb)) * std::abs(ad.z) + (std::abs(ca) + std::abs(ac)) * std::abs(bd.z) +
                             (std::abs(ab) + std::abs(ba)) * std::abs(cd.z);
    if (!(permanent > 1e-250) || !(permanent < 1e250)) return 0;
    const double bound = 7.7715611723761027e-16 * permanent;
    return det > bound ? 1 : det < -bound ? -1 : 0;
}

// Does segment pq meet the closed triangle t, exactly: 1 yes, 0 no, -1 when p and q both lie in
// its plane (left to CGAL). Across the plane, the point where the line pq crosses it lies in
// the triangle iff the orientations of pq with the triangle's three edges do not disagree in sign.
// CGAL's do_intersect decides the same way; this one settles its predicates with the float
// filters first (armadillo: 21 k pairs of faces around a shared vertex come here, all settled).
int segment_meets_triangle(const FaceData& t, const glm::dvec3& p, const glm::dvec3& q) {
    int sp = side_if_certain(t, p), sq = side_if_certain(t, q);
    const K::Point_3 a = cgal(t.p[0]), b = cgal(t.p[1]), c = cgal(t.p[2]), P = cgal(p), Q = cgal(q);
    if (sp == 0 || sq == 0) sp = int(CGAL::orientation(a, b, c, P)), sq = int(CGAL::orientation(a, b, c, Q));
    if (sp == 0 && sq == 0) return -1;
    if (sp == sq) return 0;
    int o1 = orient3d_if_certain(p, q, t.p[0], t.p[1]), o2 = orient3d_if_certain(p, q, t.p[1], t.p[2]),
        o3 = orient3d_if_certain(p, q, t.p[2], t.p[0]);
    if (o1 == 0 || o2 == 0 || o3 == 0)  // (all three exactly then: the filter's sign convention is its own)
        o1 = int(CGAL::orientation(P, Q, a, b)), o2 = int(CGAL::orientation(P, Q, b, c)), o3 = int(CGAL::orientation(P, Q, c, a));
    const bool positive = o1 > 0 || o2 > 0 || o3 > 0, negative = o1 < 0 || o2 < 0 || o3 < 0;
    return positive && negative ? 0 : 1;
}

// The exact test of faces_intersect below, for the pairs its float filter leaves open.
[[gnu::noinline]] bool faces_intersect_exactly(const FaceData& fa, const FaceData& fb, int shared, int ia, int ib) {
    const auto& a = fa.v;
    const auto& b = fb.v;
    const auto P = [](const glm::dvec3& p) { return cgal(p); };
    const K::Triangle_3 ta(P(fa.p[0]), P(fa.p[1]), P(fa.p[2])), tb(P(fb.p[0]), P(fb.p[1]), P(fb.p[2]));
    if (shared == 0) return CGAL::do_intersect(ta, tb);
    if (shared == 1) {
        // Beyond the shared corner, two triangles meet iff the side opposite the shared corner of
        // one meets the other.
        const int a_side = segment_meets_triangle(fb, fa.p[(ia + 1) % 3], fa.p[(ia + 2) % 3]);
        if (a_side == 1) return true;
        const int b_side = segment_meets_triangle(fa, fb.p[(ib + 1) % 3], fb.p[(ib + 2) % 3]);
        if (b_side == 1) return true;
        if (a_side == 0 && b_side == 0) return false;
        const K::Segment_3 sa(P(fa.p[(ia + 1) % 3]), P(fa.p[(ia + 2) % 3])), sb(P(fb.p[(ib + 1) % 3]), P(fb.p[(ib + 2) % 3]));
        return CGAL::do_intersect(sa, tb) || CGAL::do_intersect(sb, ta);
    }
    if (shared == 2) {
        // A shared edge (p, q): the faces overlap iff their far corners are coplanar with it and on
        // the same side of it.
        int ra = 0, rb = 0;
        for (int i = 0; i < 3; ++i) {
            if (a[i] != b[0] && a[i] != b[1] && a[i] != b[2]) ra = i;
            if (b[i] != a[0] && b[i] != a[1] && b[i] != a[2]) rb = i;
        }
        const K::Point_3 Pp = P(fa.p[(ra + 1) % 3]), Pq = P(fa.p[(ra + 2) % 3]), Ra = P(fa.p[ra]), Rb = P(fb.p[rb]);
        return CGAL::orientation(Pp, Pq, Ra, Rb) == CGAL::COPLANAR &&
               CGAL::coplanar_orientation(Pp, Pq, Ra, Rb) == CGAL::POSITIVE;
    }
    return true;  // the same three vertices twice
}

// Do faces f and g meet anywhere but where the mesh joins them (a shared edge or vertex)?
// The case analysis on shared corners is the one of CGAL's Polygon_mesh_processing::
// self_intersections (which needs a halfedge copy of the mesh, see the header); every test is an
// exact predicate of the Epick kernel, after a float filter that settles most pairs the box
// search finds (faces around a common vertex or edge, each on one side of the other's plane).
bool faces_intersect(const FaceData& fa, const FaceData& fb) {
    const auto& a = fa.v;
    const auto& b = fb.v;
    int shared = 0, ia = -1, ib = -1;  // last shared corner, in a and in b
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) {
                ++shared;
                ia = i;
                ib = j;
            }
    if (shared == 0) {
        constexpr std::array<int, 3> all{0, 1, 2};
        if (certainly_one_side(fa, fb, all) || certainly_one_side(fb, fa, all)) return false;
    } else if (shared == 1) {
        // The two corners after corner k, in order (a table: the modulo was a measurable share).
        constexpr std::array<std::array<int, 2>, 3> kOthers{{{1, 2}, {2, 0}, {0, 1}}};
        if (certainly_one_side(fa, fb, kOthers[ib]) || certainly_one_side(fb, fa, kOthers[ia])) return false;
    } else if (shared == 2) {
        // Not coplanar: the far corner of one is off the other's plane.
        for (int i = 0; i < 3; ++i)
            if (b[i] != a[0] && b[i] != a[1] && b[i] != a[2] && side_if_certain(fa, fb.p[i]) != 0) return false;
    }
    return faces_intersect_exactly(fa, fb, shared, ia, ib);
}

// Certainly not collinear: a component of the face's normal certainly nonzero. Each component is
// an orient2d of the corners projected to a coordinate plane, in the shape of Shewchuk's, so his
// bound ccwerrboundA, (3 + 16 eps) eps times the permanent, holds (rounded up here); away from
// underflow and overflow only.
bool certainly_proper(const FaceData& face) {
    for (int k = 0; k < 3; ++k) {
        const double permanent = face.permanent[k];
        if (permanent > 1e-250 && permanent < 1e250 && std::abs(face.n[k]) > 3.4e-16 * permanent) return true;
    }
    return false;
}

// Face boxes, one array per bound (a leaf of the search below then loads as one vector), padded
// with kPad boxes that meet nothing. Box i is face i's (so no face numbers are stored): in the
// faces' order, as a loaded model's faces follow a Hilbert curve (model/reorder.hpp), so halving
// the order halves space well enough for the search; any other order gives the same pairs, only
// slower. A degenerate face's box is empty (lo above hi): it meets nothing.
struct BoxColumns {
    static constexpr std::size_t kPad = 8;
    std::vector<float> lo[3], hi[3];
    std::size_t count = 0;
    glm::dvec3 corners_lo{0.0}, corners_hi{0.0};  // the box of every face's corners (degenerate faces' too)
    std::size_t size() const { return count; }
    void add(const float box_lo[3], const float box_hi[3]) {
        for (int d = 0; d < 3; ++d) lo[d].push_back(box_lo[d]), hi[d].push_back(box_hi[d]);
        ++count;
    }
    void add_empty() {
        const float inf = std::numeric_limits<float>::infinity(), box_lo[3] = {inf, inf, inf}, box_hi[3] = {-inf, -inf, -inf};
        add(box_lo, box_hi);
    }
    bool empty_box(std::size_t i) const { return lo[0][i] > hi[0][i]; }
    void pad() {
        for (int d = 0; d < 3; ++d) {
            lo[d].resize(count + kPad, std::numeric_limits<float>::infinity());
            hi[d].resize(count + kPad, -std::numeric_limits<float>::infinity());
        }
    }
    // CGAL's boxes of the faces that have one (not the degenerate faces'), in the same order.
    std::vector<Box> cgal_boxes() const {
        std::vector<Box> boxes;
        boxes.reserve(size());
        for (std::size_t i = 0; i < size(); ++i) {
            if (empty_box(i)) continue;
            float box_lo[3] = {lo[0][i], lo[1][i], lo[2][i]}, box_hi[3] = {hi[0][i], hi[1][i], hi[2][i]};
            boxes.emplace_back(box_lo, box_hi, std::uint32_t(i));
        }
        return boxes;
    }
};

// The boxes of the faces that have an area; degenerate faces (collinear corners) are flagged in
// `out` and get an empty box: they count as self-intersecting and are tested against nothing, as in CGAL's
// PMP::self_intersections (CGAL's triangle tests require a proper triangle: found by fuzz/run.sh
// pipeline).
BoxColumns face_boxes(const SearchInput& in, std::vector<std::uint8_t>& out) {
    const std::size_t nf = in.face_count;
    out.assign(nf, 0);
    BoxColumns boxes;
    for (int d = 0; d < 3; ++d) boxes.lo[d].reserve(nf + BoxColumns::kPad), boxes.hi[d].reserve(nf + BoxColumns::kPad);
    if (nf > 0) boxes.corners_lo = boxes.corners_hi = in.positions[in.faces[0][0]];
    for (std::uint32_t f = 0; f < nf; ++f) {
        const FaceData face = face_data(in, f);
        for (const glm::dvec3& p : face.p) boxes.corners_lo = glm::min(boxes.corners_lo, p), boxes.corners_hi = glm::max(boxes.corners_hi, p);
        if (!certainly_proper(face) && CGAL::collinear(cgal(face.p[0]), cgal(face.p[1]), cgal(face.p[2]))) {
            out[f] = 1;
            boxes.add_empty();
            continue;
        }
        float lo[3], hi[3];
        for (int d = 0; d < 3; ++d) {
            const double x0 = face.p[0][d], x1 = face.p[1][d], x2 = face.p[2][d];
            lo[d] = down(std::min({x0, x1, x2}));
            hi[d] = up(std::max({x0, x1, x2}));
        }
        boxes.add(lo, hi);
    }
    boxes.pad();
    return boxes;
}

// Volino and Thalmann's test, made exact: a patch of faces that no pair of its faces can
// intersect (beyond the corners and edges they share). The patch must be an oriented surface
// (each edge in at most two faces, wound oppositely), every face's normal must make an angle
// below 90 degrees with one direction d (certainly, by a float filter), and its boundary must be
// one cycle whose projection along d is a simple polygon (certainly). Then the projection along d
// keeps every face's orientation, so each point of the plane has as many preimages, counted with
// their local degree, as the boundary's image winds around it: at most one, and the projection is
// one-to-one on the patch. Any doubt (a filter that cannot decide, a pinched vertex, a boundary of
// several cycles) answers no, and the patch's pairs are tested one by one as before: the test is
// a sufficient condition, never an approximation.
class EmbeddedPatches {
public:
    explicit EmbeddedPatches(const SearchInput& in) : in_(in) {}
    // Is the patch of faces [first, first + count) certainly embedded, projected along d? (A
    // degenerate face in it is not certainly in front: no.)
    bool embedded(std::uint32_t first, std::size_t count, const glm::dvec3& d) const {
        for (std::size_t i = 0; i < count; ++i)
            if (!certainly_front(face_plane(in_, first + std::uint32_t(i)), d)) return false;
        thread_local Scratch scratch;
        if (!boundary_cycles(first, count, scratch)) return false;
        if (!simple_projection(d, scratch)) return false;
        return true;
    }

private:
    struct Scratch {
        std::vector<std::uint64_t> table;  // open addressing: directed edges (u << 32 | v)
        std::vector<std::uint32_t> owner;  // per slot: the edge's face and corner (face << 2 | corner)
        std::vector<std::size_t> used;     // the slots filled by this call
        std::vector<std::pair<std::uint64_t, std::uint32_t>> boundary;  // edge, owner
        std::vector<std::uint32_t> cycle;  // the boundary cycles' corners (owners) in order
        std::vector<std::uint32_t> starts;  // where each cycle begins in `cycle`, and its end
        std::vector<std::uint8_t> visited;
        std::vector<glm::dvec3> points;
        std::vector<std::uint32_t> next;  // per point: the next along its cycle
        std::vector<std::array<double, 4>> xy;  // per point: its x and y ranges in the plane
        std::vector<std::array<double, 4>> boxes;  // per cycle
        std::vector<std::array<double, 2>> spans;  // per boundary segment: its x range
        std::vector<std::uint32_t> by_start;
    };
    static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
    static std::uint64_t key(std::uint32_t u, std::uint32_t v) { return (std::uint64_t(u) << 32) | v; }
    static std::size_t slot(std::uint64_t k, std::size_t mask) { return std::size_t((k * 0x9E3779B97F4A7C15ull) >> 40) & mask; }
    // dot(n, d) > 0 certainly: the filter of side_if_certain, with d in the place of x - a (exact
    // here, so fewer roundings than the bound covers).
    static bool certainly_front(const Plane& f, const glm::dvec3& d) {
        const double det = f.n.x * d.x + f.n.y * d.y + f.n.z * d.z;
        const double permanent = f.permanent.x * std::abs(d.x) + f.permanent.y * std::abs(d.y) + f.permanent.z * std::abs(d.z);
        return permanent > 1e-250 && permanent < 1e250 && det > 7.7715611723761027e-16 * permanent;
    }
    // The sign of det[q - p, r - p, d] (the orientation of p, q, r projected along d), or 0 when
    // the same filter cannot tell.
    static int projected_orientation(const glm::dvec3& p, const glm::dvec3& q, const glm::dvec3& r, const glm::dvec3& d) {
        const glm::dvec3 u = q - p, v = r - p;
        const glm::dvec3 n{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
        const glm::dvec3 permanent{std::abs(u.y * v.z) + std::abs(u.z * v.y), std::abs(u.z * v.x) + std::abs(u.x * v.z),
                                   std::abs(u.x * v.y) + std::abs(u.y * v.x)};
        const double det = n.x * d.x + n.y * d.y + n.z * d.z;
        const double bound = permanent.x * std::abs(d.x) + permanent.y * std::abs(d.y) + permanent.z * std::abs(d.z);
        if (!(bound > 1e-250) || !(bound < 1e250)) return 0;
        const double e = 7.7715611723761027e-16 * bound;
        return det > e ? 1 : det < -e ? -1 : 0;
    }
    // The patch's boundary as cycles of corners (scratch.cycle, each cycle from scratch.starts[c]
    // to starts[c + 1]), or false: an edge twice in one direction (two faces wound alike, or
    // three on an edge), or a pinched boundary vertex (two boundary edges leave it).
    bool boundary_cycles(std::uint32_t first, std::size_t count, Scratch& s) const {
        std::size_t size = 16;
        while (size < 6 * count) size *= 2;
        const std::size_t mask = size - 1;
        // (kept empty between calls: cleared slot by slot after use, not refilled each time)
        if (s.table.size() < size) s.table.assign(size, kEmpty), s.owner.resize(size);
        s.used.clear();
        struct Clear {
            Scratch& s;
            ~Clear() { for (const std::size_t i : s.used) s.table[i] = kEmpty; }
        } clear_after{s};
        const auto find = [&](std::uint64_t k) {
            std::size_t i = slot(k, mask);
            while (s.table[i] != kEmpty && s.table[i] != k) i = (i + 1) & mask;
            return i;
        };
        for (std::size_t i = 0; i < count; ++i) {
            const std::uint32_t f = first + std::uint32_t(i);
            const auto& v = in_.faces[f];
            for (int k = 0; k < 3; ++k) {
                const std::uint64_t e = key(v[k], v[(k + 1) % 3]);
                const std::size_t at = find(e);
                if (s.table[at] == e) return false;
                s.table[at] = e;
                s.used.push_back(at);
                s.owner[at] = (f << 2) | std::uint32_t(k);
            }
        }
        s.boundary.clear();
        for (const std::size_t i : s.used) {
            const std::uint64_t e = s.table[i];
            if (s.table[find(key(std::uint32_t(e), std::uint32_t(e >> 32)))] == kEmpty) s.boundary.push_back({e, s.owner[i]});
        }
        if (s.boundary.size() < 3) return false;
        std::sort(s.boundary.begin(), s.boundary.end());  // by the edge's first vertex
        for (std::size_t i = 1; i < s.boundary.size(); ++i)
            if ((s.boundary[i].first >> 32) == (s.boundary[i - 1].first >> 32)) return false;
        // Each boundary vertex has one edge in and one out now, so the edges fall into cycles.
        s.cycle.clear();
        s.starts.assign(1, 0);
        s.visited.assign(s.boundary.size(), 0);
        for (std::size_t first = 0; first < s.boundary.size(); ++first) {
            for (std::size_t at = first; !s.visited[at];) {
                s.visited[at] = 1;
                s.cycle.push_back(s.boundary[at].second);
                const auto head = std::uint32_t(s.boundary[at].first);
                const auto next = std::lower_bound(s.boundary.begin(), s.boundary.end(), std::pair{key(head, 0), std::uint32_t(0)});
                if (next == s.boundary.end() || (next->first >> 32) != head) return false;
                at = std::size_t(next - s.boundary.begin());
            }
            if (s.cycle.size() > s.starts.back()) s.starts.push_back(std::uint32_t(s.cycle.size()));
        }
        return true;
    }
    // The boundary cycles projected along d are simple polygons that neither meet nor nest,
    // certainly: consecutive segments turn (not collinear), segments not consecutive are certainly
    // apart, and the cycles' bounding boxes are apart (so none lies inside another). In the plane
    // two coordinates that are exactly constant along d are used (with b the largest of d's
    // components, x = p_a d_b - p_b d_a and y = p_c d_b - p_b d_c), each range widened by the
    // bound of its rounding; only segments whose x ranges overlap are compared.
    bool simple_projection(const glm::dvec3& d, Scratch& s) const {
        const std::size_t n = s.cycle.size(), cycles = s.starts.size() - 1;
        int b = 0;
        for (int k = 1; k < 3; ++k)
            if (std::abs(d[k]) > std::abs(d[b])) b = k;
        const int a = (b + 1) % 3, c = (b + 2) % 3;
        s.points.resize(n);
        s.next.resize(n);
        s.xy.resize(n);
        for (std::size_t cy = 0; cy < cycles; ++cy) {
            const std::uint32_t begin = s.starts[cy], end = s.starts[cy + 1];
            for (std::uint32_t k = begin; k < end; ++k) s.next[k] = k + 1 < end ? k + 1 : begin;
        }
        for (std::size_t k = 0; k < n; ++k) {
            const glm::dvec3& p = s.points[k] = position(s.cycle[k]);
            // Two products and a difference, each rounded: 3 eps of the terms' sizes covers them.
            const double ex = 4.5e-16 * (std::abs(p[a] * d[b]) + std::abs(p[b] * d[a])) + 1e-300,
                         ey = 4.5e-16 * (std::abs(p[c] * d[b]) + std::abs(p[b] * d[c])) + 1e-300;
            const double x = p[a] * d[b] - p[b] * d[a], y = p[c] * d[b] - p[b] * d[c];
            s.xy[k] = {x - ex, x + ex, y - ey, y + ey};
        }
        for (std::size_t k = 0; k < n; ++k) {
            std::size_t previous = k;
            while (s.next[previous] != k) previous = s.next[previous];
            if (projected_orientation(s.points[previous], s.points[k], s.points[s.next[k]], d) == 0) return false;
        }
        if (cycles > 1 && !cycle_boxes_apart(s)) return false;
        s.spans.resize(n);
        s.by_start.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            const auto &p = s.xy[k], &q = s.xy[s.next[k]];
            s.spans[k] = {std::min(p[0], q[0]), std::max(p[1], q[1])};
            s.by_start[k] = std::uint32_t(k);
        }
        std::sort(s.by_start.begin(), s.by_start.end(), [&](std::uint32_t x, std::uint32_t y) { return s.spans[x][0] < s.spans[y][0]; });
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint32_t p = s.by_start[i];
            for (std::size_t j = i + 1; j < n && s.spans[s.by_start[j]][0] <= s.spans[p][1]; ++j) {
                const std::uint32_t q = s.by_start[j];
                if (s.next[p] == q || s.next[q] == p) continue;  // consecutive: checked above
                if (!certainly_apart(s.points[p], s.points[s.next[p]], s.points[q], s.points[s.next[q]], d)) return false;
            }
        }
        return true;
    }
    // The cycles' boxes in (x, y) pairwise apart.
    static bool cycle_boxes_apart(Scratch& s) {
        const std::size_t cycles = s.starts.size() - 1;
        s.boxes.assign(cycles, {1e308, -1e308, 1e308, -1e308});
        for (std::size_t cy = 0; cy < cycles; ++cy)
            for (std::uint32_t k = s.starts[cy]; k < s.starts[cy + 1]; ++k) {
                auto& box = s.boxes[cy];
                box[0] = std::min(box[0], s.xy[k][0]), box[1] = std::max(box[1], s.xy[k][1]);
                box[2] = std::min(box[2], s.xy[k][2]), box[3] = std::max(box[3], s.xy[k][3]);
            }
        for (std::size_t i = 0; i < cycles; ++i)
            for (std::size_t j = i + 1; j < cycles; ++j) {
                const auto &p = s.boxes[i], &q = s.boxes[j];
                if (!(p[1] < q[0] || q[1] < p[0] || p[3] < q[2] || q[3] < p[2])) return false;
            }
        return true;
    }
    // Segments ab and ce projected along d certainly do not meet: one lies strictly on one side of
    // the other's line.
    static bool certainly_apart(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& e, const glm::dvec3& d) {
        const int c_side = projected_orientation(a, b, c, d);
        if (c_side != 0 && c_side == projected_orientation(a, b, e, d)) return true;
        const int a_side = projected_orientation(c, e, a, d);
        return a_side != 0 && a_side == projected_orientation(c, e, b, d);
    }
    // A corner's position (face << 2 | corner).
    const glm::dvec3& position(std::uint32_t owner) const { return in_.positions[in_.faces[owner >> 2][owner & 3]]; }

    SearchInput in_;
};

// Every pair of boxes that meet (closed), each once, in no particular order: a bounding-volume
// hierarchy over the boxes in the faces' order (consecutive runs of at most kLeaf boxes, halved
// recursively), searched against itself. Its nodes (40 bytes, about one for every two boxes) are
// read in order, where CGAL's segment tree spent most of a model's loading in long scans.
class BoxPairs {
public:
    // With `patches`, a node whose faces make an embedded patch (EmbeddedPatches) reports none of
    // the pairs within it; without, every pair whose boxes meet is reported. `in`: the boxes' faces.
    BoxPairs(const BoxColumns& boxes, const SearchInput& in, const EmbeddedPatches* patches)
        : in_(in), patches_(patches) {
        for (int d = 0; d < 3; ++d) lo_[d] = boxes.lo[d].data(), hi_[d] = boxes.hi[d].data();
        if (boxes.size() == 0) return;
        // (the keys only shape the tree: freed once it is built)
        const std::vector<std::uint64_t> keys = centroid_keys(boxes);
        nodes_.reserve(count_nodes(keys, 0, std::uint32_t(boxes.size()), 0));
        build(keys, 0, std::uint32_t(boxes.size()), 0);
    }
    // A share of the search: the pairs within node a (self), or between nodes a and b.
    struct Task {
        std::uint32_t a, b;
        bool self;
    };
    // The whole search as at least `want` tasks where the tree allows (fewer for small trees),
    // together meeting every pair once: the top of the recursion below, unrolled breadth first.
    std::vector<Task> tasks(std::size_t want) const {
        std::vector<Task> open, whole;  // open[head, end): tasks to split further; whole: leaves
        if (nodes_.empty()) return whole;
        open.push_back({0, 0, true});
        std::size_t head = 0;
        while (head < open.size() && open.size() - head + whole.size() < want) {
            const Task t = open[head++];
            const Node &x = nodes_[t.a], &y = nodes_[t.b];
            if (t.self && x.left) {
                open.push_back({x.left, x.left, true});
                open.push_back({x.right, x.right, true});
                open.push_back({x.left, x.right, false});
            } else if (t.self) {
                whole.push_back(t);
            } else if (!meet(x, y)) {
                continue;  // no pair
            } else if (!x.left && !y.left) {
                whole.push_back(t);
            } else if (!y.left || (x.left && x.end - x.begin >= y.end - y.begin)) {  // as across()
                open.push_back({x.left, t.b, false});
                open.push_back({x.right, t.b, false});
            } else {
                open.push_back({t.a, y.left, false});
                open.push_back({t.a, y.right, false});
            }
        }
        whole.insert(whole.end(), open.begin() + std::ptrdiff_t(head), open.end());
        return whole;
    }
    // Calls fn(f, g) with the faces of each pair of task t.
    template <class Fn>
    void run(const Task& t, Fn&& fn) const {
        if (t.self) self(t.a, fn);
        else across(t.a, t.b, fn);
    }

private:
    // (Eight boxes a leaf rather than four: half the nodes, 40 bytes each, for the same pairs; the
    // leaf's box tests are two vectors of four.)
    static constexpr std::uint32_t kLeaf = 8;
    static_assert(kLeaf <= 8 && kLeaf <= BoxColumns::kPad, "meet_leaf tests a leaf as two vectors of four boxes");
    struct Node {
        float lo[3], hi[3];
        std::uint32_t begin, end;  // boxes [begin, end)
        std::uint32_t left = 0;    // children left and left + 1 ... (0: a leaf)
        std::uint32_t right = 0;
    };
    // Below this many faces the patch test costs about what testing the node's pairs does.
    static constexpr std::uint32_t kMinPatch = 48;
    // A face's unit normal; a node's summed are the mean direction EmbeddedPatches looks from.
    glm::dvec3 unit_normal(std::uint32_t box) const {
        const glm::dvec3 n = face_plane(in_, box).n;
        const double length = glm::length(n);
        return length > 0 ? n / length : glm::dvec3(0.0);
    }
    bool embedded(std::uint32_t node) const {
        const Node& n = nodes_[node];
        if (n.end - n.begin < kMinPatch) return false;
        const auto sum = std::lower_bound(normal_sums_.begin(), normal_sums_.end(), node,
                                          [](const NormalSum& x, std::uint32_t at) { return x.node < at; });
        return patches_->embedded(n.begin, n.end - n.begin, sum->sum);
    }
    // Without a branch per comparison: at the leaves about half the box pairs meet, so branches
    // mispredict (most of the search's time).
    template <class A, class B>
    static bool meet(const A& x, const B& y) {
        return !(x.lo[0] > y.hi[0]) & !(y.lo[0] > x.hi[0]) & !(x.lo[1] > y.hi[1]) & !(y.lo[1] > x.hi[1]) &
               !(x.lo[2] > y.hi[2]) & !(y.lo[2] > x.hi[2]);
    }
    // The boxes' faces' Hilbert keys (model/reorder.hpp; in the box of the faces' corners, which is
    // a loaded model's box but for unused vertices): for a loaded model, sorted. The centroids
    // go to the keys a block at a time (no array of them).
    std::vector<std::uint64_t> centroid_keys(const BoxColumns& boxes) const {
        const std::size_t box_count = boxes.size();
        const HilbertGrid grid(boxes.corners_lo, boxes.corners_hi);
        std::vector<std::uint64_t> keys(box_count);
        constexpr std::size_t kBlock = 256;
        glm::dvec3 centroids[kBlock];
        for (std::size_t first = 0; first < box_count; first += kBlock) {
            const std::size_t m = std::min(kBlock, box_count - first);
            for (std::size_t j = 0; j < m; ++j) {
                const auto& t = in_.faces[first + j];
                centroids[j] = (in_.positions[t[0]] + in_.positions[t[1]] + in_.positions[t[2]]) / 3.0;
            }
            grid.keys(centroids, m, keys.data() + first);
        }
        return keys;
    }
    // Where a node splits: between two cells of the Hilbert curve (the boxes before the first
    // whose key differs from the first box's at the highest bit where the last box's does), so
    // that a node is a cell of the curve's grid, as compact as space allows; halving the run would
    // cut a cell and give nodes of two far-apart parts, whose boxes meet more and whose faces
    // make embedded patches less often. The middle when the keys do not tell (equal keys; a
    // tree already deep enough for 63-bit keys: an order not sorted by them).
    static std::uint32_t split(const std::vector<std::uint64_t>& keys, std::uint32_t begin, std::uint32_t end, int depth) {
        const std::uint32_t middle = begin + (end - begin) / 2;
        const std::uint64_t differ = keys[begin] ^ keys[end - 1];
        if (differ == 0 || depth > 80) return middle;
        const std::uint64_t bit = std::uint64_t(1) << (63 - std::countl_zero(differ));
        const bool first_has = keys[begin] & bit;
        std::uint32_t lo = begin + 1, hi = end - 1;  // the first box on the last box's side, in [lo, hi]
        while (lo < hi) {
            const std::uint32_t m = lo + (hi - lo) / 2;
            if (bool(keys[m] & bit) != first_has) hi = m;
            else lo = m + 1;
        }
        return lo;
    }
    // The nodes build() makes (so that their array is allocated once, at its size).
    static std::size_t count_nodes(const std::vector<std::uint64_t>& keys, std::uint32_t begin, std::uint32_t end, int depth) {
        if (end - begin <= kLeaf) return 1;
        const std::uint32_t mid = split(keys, begin, end, depth);
        return 1 + count_nodes(keys, begin, mid, depth + 1) + count_nodes(keys, mid, end, depth + 1);
    }
    // A node's box: its boxes' hull at a leaf, its children's above (each box read once). Returns
    // the node's unit normals summed (when patches_), kept for the nodes the patch test may see.
    glm::dvec3 build(const std::vector<std::uint64_t>& keys, std::uint32_t begin, std::uint32_t end, int depth) {
        const auto at = std::uint32_t(nodes_.size());
        nodes_.push_back({});
        // (its place taken now, so that normal_sums_ is in the order of the nodes)
        const bool keep_sum = patches_ && end - begin >= kMinPatch;
        const std::size_t sum_at = normal_sums_.size();
        if (keep_sum) normal_sums_.push_back({at, glm::dvec3(0.0)});
        glm::dvec3 sum(0.0);
        Node node{};
        node.begin = begin, node.end = end;
        if (end - begin > kLeaf) {
            const std::uint32_t mid = split(keys, begin, end, depth);
            node.left = std::uint32_t(nodes_.size());
            const glm::dvec3 left_sum = build(keys, begin, mid, depth + 1);
            node.right = std::uint32_t(nodes_.size());
            const glm::dvec3 right_sum = build(keys, mid, end, depth + 1);
            const Node &l = nodes_[node.left], &r = nodes_[node.right];
            for (int d = 0; d < 3; ++d) node.lo[d] = std::min(l.lo[d], r.lo[d]), node.hi[d] = std::max(l.hi[d], r.hi[d]);
            if (patches_) sum = left_sum + right_sum;
        } else {
            if (patches_)
                for (std::uint32_t i = begin; i < end; ++i) sum += unit_normal(i);
            for (int d = 0; d < 3; ++d) {
                float lo = lo_[d][begin], hi = hi_[d][begin];
                for (std::uint32_t i = begin + 1; i < end; ++i) lo = std::min(lo, lo_[d][i]), hi = std::max(hi, hi_[d][i]);
                node.lo[d] = lo, node.hi[d] = hi;
            }
        }
        nodes_[at] = node;
        if (keep_sum) normal_sums_[sum_at].sum = sum;
        return sum;
    }
    template <class Fn>
    void self(std::uint32_t a, Fn& fn) const {
        const Node& n = nodes_[a];
        if (!n.left) {
            for (std::uint32_t i = n.begin; i < n.end; ++i) report(i, n.begin, n.end, i - n.begin + 1, fn);
            return;
        }
        if (patches_ && embedded(a)) return;  // no pair within it can intersect
        self(n.left, fn);
        self(n.right, fn);
        across(n.left, n.right, fn);
    }
    template <class Fn>
    void across(std::uint32_t a, std::uint32_t b, Fn& fn) const {
        const Node &x = nodes_[a], &y = nodes_[b];
        if (!meet(x, y)) return;
        if (!x.left && !y.left) {
            for (std::uint32_t i = x.begin; i < x.end; ++i) report(i, y.begin, y.end, 0, fn);
        } else if (!y.left || (x.left && x.end - x.begin >= y.end - y.begin)) {
            across(x.left, b, fn);
            across(x.right, b, fn);
        } else {
            across(a, y.left, fn);
            across(a, y.right, fn);
        }
    }
    // Bit k set: box i meets box j + k (k < kLeaf), as meet() decides.
    unsigned meet_leaf(std::uint32_t i, std::uint32_t j) const {
#if defined(__SSE__)
        __m128 ok0 = _mm_castsi128_ps(_mm_set1_epi32(-1)), ok1 = ok0;
        for (int d = 0; d < 3; ++d) {
            const __m128 lo = _mm_set1_ps(lo_[d][i]), hi = _mm_set1_ps(hi_[d][i]);
            ok0 = _mm_and_ps(ok0, _mm_cmpngt_ps(lo, _mm_loadu_ps(&hi_[d][j])));
            ok0 = _mm_and_ps(ok0, _mm_cmpngt_ps(_mm_loadu_ps(&lo_[d][j]), hi));
            ok1 = _mm_and_ps(ok1, _mm_cmpngt_ps(lo, _mm_loadu_ps(&hi_[d][j + 4])));
            ok1 = _mm_and_ps(ok1, _mm_cmpngt_ps(_mm_loadu_ps(&lo_[d][j + 4]), hi));
        }
        return unsigned(_mm_movemask_ps(ok0)) | unsigned(_mm_movemask_ps(ok1)) << 4;
#else
        unsigned bits = 0;
        for (std::uint32_t k = 0; k < kLeaf; ++k) {
            bool ok = true;
            for (int d = 0; d < 3; ++d)
                ok &= !(lo_[d][i] > hi_[d][j + k]) & !(lo_[d][j + k] > hi_[d][i]);
            bits |= unsigned(ok) << k;
        }
        return bits;
#endif
    }
    // fn(f, g) for box i against the boxes [begin + skip, end) of one leaf.
    template <class Fn>
    void report(std::uint32_t i, std::uint32_t begin, std::uint32_t end, std::uint32_t skip, Fn& fn) const {
        unsigned bits = meet_leaf(i, begin) & ((1u << (end - begin)) - 1) & ~((1u << skip) - 1);
        for (; bits; bits &= bits - 1) fn(i, begin + std::uint32_t(__builtin_ctz(bits)));
    }
    // The columns' arrays (read through plain pointers: the hot loops need not reload them).
    const float* lo_[3];
    const float* hi_[3];
    SearchInput in_;
    const EmbeddedPatches* patches_;
    std::vector<Node> nodes_;
    // When patches_, for each node of kMinPatch boxes or more (the only ones the patch test sees;
    // a small share of the nodes), by node: its faces' unit normals summed.
    struct NormalSum {
        std::uint32_t node;
        glm::dvec3 sum;
    };
    std::vector<NormalSum> normal_sums_;
};

std::uint64_t pair_key(std::uint32_t f, std::uint32_t g) { return (std::uint64_t(std::min(f, g)) << 32) | std::max(f, g); }

// The search for intersecting pairs, in two halves so that it can run beside other work:
// prepare() reads the faces and builds the hierarchy, and split into tasks, work(k) takes tasks
// until none are left (any number of threads at once, each with its own k), collect() gives the
// pairs found, as pair_key()s, sorted: the same result for any split.
class PairSearch {
public:
    // Below this many boxes (a few milliseconds of search) a thread's start costs more than it saves.
    static constexpr std::size_t kBoxesPerThread = 4096;
    // Reads `in`'s arrays until the last work() returns; once `stop` is set (if given), the
    // construction and work() return at their next step, leaving a search that collects nothing
    // meaningful (for a search whose result is no longer wanted).
    PairSearch(const SearchInput& in, std::size_t workers, PatchTest patch_test, const std::atomic<bool>* stop = nullptr)
        : in_(in), patches_(in), stop_(stop), found_(std::max<std::size_t>(workers, 1)), failed_(found_.size()) {
        columns_ = face_boxes(in_, flags_);
        if (stopped()) return;
        // (EmbeddedPatches packs a face and a corner in 32 bits)
        const bool patches = patch_test == PatchTest::kEmbeddedPatchesSkipped && in_.face_count < (std::size_t(1) << 30);
        tree_.emplace(columns_, in_, patches ? &patches_ : nullptr);
        if (stopped()) return;
        // Many more tasks than threads, so that uneven tasks even out.
        tasks_ = tree_->tasks(found_.size() > 1 ? found_.size() * 64 : 1);
    }
    PairSearch(const PairSearch&) = delete;  // (the hierarchy points into columns_)
    std::size_t workers() const { return found_.size(); }
    void work(std::size_t k) {
        try {
            // Two leaves' pairs come one after another (up to eight boxes against eight): each
            // face's data made once for them, kept in a slot by its number (a leaf's faces are
            // consecutive numbers, so they take different slots).
            struct Slot {
                std::uint32_t face = UINT32_MAX;
                FaceData data;
            };
            constexpr std::uint32_t kSlots = 32;
            std::array<Slot, kSlots> slots;
            const auto data = [&](std::uint32_t f) -> const FaceData& {
                Slot& s = slots[f % kSlots];
                if (s.face != f) s.data = face_data(in_, f), s.face = f;
                return s.data;
            };
            for (std::size_t t = next_++; t < tasks_.size() && !stopped(); t = next_++)
                tree_->run(tasks_[t], [&](std::uint32_t f, std::uint32_t g) {
                    const bool meet = (f - g) % kSlots != 0 ? faces_intersect(data(f), data(g))
                                                          : faces_intersect(face_data(in_, f), face_data(in_, g));
                    if (meet) found_[k].push_back(pair_key(f, g));
                });
        } catch (...) {
            failed_[k] = std::current_exception();
        }
    }
    // After every work(k) has returned.
    std::vector<std::uint64_t> collect() {
        for (const std::exception_ptr& e : failed_)
            if (e) std::rethrow_exception(e);
        std::vector<std::uint64_t> all = std::move(found_[0]);
        for (std::size_t k = 1; k < found_.size(); ++k) all.insert(all.end(), found_[k].begin(), found_[k].end());
        std::sort(all.begin(), all.end());
        return all;
    }
    // Per face: 1 for a degenerate face (collinear corners), set by prepare.
    std::vector<std::uint8_t>& flags() { return flags_; }
    const BoxColumns& columns() const { return columns_; }

private:
    bool stopped() const { return stop_ && stop_->load(std::memory_order_relaxed); }
    SearchInput in_;
    EmbeddedPatches patches_;
    const std::atomic<bool>* stop_;
    std::vector<std::uint8_t> flags_;
    BoxColumns columns_;
    std::optional<BoxPairs> tree_;
    std::vector<BoxPairs::Task> tasks_;
    std::vector<std::vector<std::uint64_t>> found_;
    std::vector<std::exception_ptr> failed_;
    std::atomic<std::size_t> next_{0};
};

std::size_t search_workers(std::size_t faces, int threads) {
    return std::clamp<std::size_t>(faces / PairSearch::kBoxesPerThread, 1, std::size_t(std::max(threads, 1)));
}

// Runs work(k) for k = 1 .. workers - 1 on threads of their own, then work(0) on this one.
void run_workers(PairSearch& search, std::size_t first_helper = 1) {
    std::vector<std::thread> helpers;
    try {
        for (std::size_t k = first_helper; k < search.workers(); ++k) helpers.emplace_back([&search, k] { search.work(k); });
    } catch (const std::system_error&) {
        // No more threads to be had: the ones started and this one take every task.
    }
    search.work(0);
    for (std::thread& helper : helpers) helper.join();
}

// Calls fn(f, g) for the intersecting pairs `found` (pair_key()s, sorted) in the order of CGAL's
// box_self_intersection_d, which the intersection lines' chaining follows. A model that does not
// intersect itself (the usual case) never pays for that search: the hierarchy above finds every
// intersecting pair first (in its own order), and only when there are some does the segment tree
// run, to list them in its order (without testing a pair again).
template <class Fn>
void list_pairs_in_cgal_order(const BoxColumns& columns, const std::vector<std::uint64_t>& found, Fn&& fn) {
    if (found.empty()) return;
    // Closed boxes (the default): faces that only touch reach the exact test too. Cutoff: below
    // this many boxes CGAL's streamed segment tree compares boxes by a plain scan, which for sets
    // this small costs less than recursing further; the same pairs either way (bench/results/model.md).
    constexpr std::ptrdiff_t kCutoff = 3000;
    std::vector<Box> boxes = columns.cgal_boxes();
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
        const auto f = std::uint32_t(x.id()), g = std::uint32_t(y.id());
        if (std::binary_search(found.begin(), found.end(), pair_key(f, g))) fn(f, g);
    }, kCutoff);
}

SearchInput search_input(const MeshTopology& mesh) {
    return {mesh.positions.data(), mesh.faces.data(), mesh.face_count(), mesh.vertex_count()};
}

// Where segment E0E1 meets the triangle `face`, as far as filters can tell without a construction.
// kNothing: both ends strictly on one side of its plane (the float filter). kEnd0 (kEnd1): that end
// at one of its corners (the same vertex, or another one at the same position: a geomorph's vertex
// on its parent) and the other end strictly off its plane (the filter, else one exact orientation,
// which also proves the triangle proper): the segment meets the triangle there and only there, and
// CGAL's intersection is that end itself (s exactly 0 or 1). kOpen: anything else, left to CGAL.
// CGAL's predicates in the settled cases are degenerate (an end at a corner lies on every plane
// through it), so its filtered kernel takes exact arithmetic on each: the dear case of cut_edge.
enum class Meet { kNothing, kEnd0, kEnd1, kOpen };

Meet meet_by_filters(const FaceData& face, const glm::dvec3& E0, const glm::dvec3& E1) {
    const bool at0 = E0 == face.p[0] || E0 == face.p[1] || E0 == face.p[2];
    const bool at1 = E1 == face.p[0] || E1 == face.p[1] || E1 == face.p[2];
    if (at0 != at1) {
        const glm::dvec3& other = at0 ? E1 : E0;
        const bool off = side_if_certain(face, other) != 0 ||
                         CGAL::orientation(cgal(face.p[0]), cgal(face.p[1]), cgal(face.p[2]), cgal(other)) != CGAL::COPLANAR;
        return !off ? Meet::kOpen : at0 ? Meet::kEnd0 : Meet::kEnd1;
    }
    if (at0) return Meet::kOpen;
    const int side = side_if_certain(face, E0);
    return side != 0 && side_if_certain(face, E1) == side ? Meet::kNothing : Meet::kOpen;
}

// Where edge e meets triangle f (not one of e's faces; `face` its FaceData): the parameter of the
// point, or of the ends of the shared stretch, except at an end vertex that f shares (no event
// there). kFilteredFirst settles the cases meet_by_filters can; kCgalOnly leaves all to CGAL.
void cut_edge(const MeshTopology& mesh, std::uint32_t e, std::uint32_t f, const FaceData& face, CutConstruction how,
              std::vector<EdgeCut>& cuts) {
    const auto [v0, v1] = mesh.edge_vertex[e];
    const auto& t = mesh.faces[f];
    const glm::dvec3 E0 = mesh.positions[v0], E1 = mesh.positions[v1];
    const bool shares0 = std::find(t.begin(), t.end(), v0) != t.end(), shares1 = std::find(t.begin(), t.end(), v1) != t.end();
    const glm::dvec3 d = E1 - E0;
    const double dd = glm::dot(d, d);
    auto add = [&](const glm::dvec3& p) {
        const double s = std::clamp(glm::dot(p - E0, d) / dd, 0.0, 1.0);
        // A rounded construction can come out NaN on nearly degenerate pairs (4 cuts of
        // AC14-FZK-Haus.ifc); a NaN cut hung the visibility's curve cutting (no order, no progress).
        if (std::isnan(s)) return;
        if ((s == 0.0 && shares0) || (s == 1.0 && shares1)) return;
        cuts.push_back({e, s});
    };
    if (how == CutConstruction::kFilteredFirst) switch (meet_by_filters(face, E0, E1)) {
        case Meet::kNothing: return;
        case Meet::kEnd0: add(E0); return;
        case Meet::kEnd1: add(E1); return;
        case Meet::kOpen: break;
    }
    const K::Segment_3 seg(cgal(E0), cgal(E1));
    const K::Triangle_3 tri(cgal(mesh.positions[t[0]]), cgal(mesh.positions[t[1]]), cgal(mesh.positions[t[2]]));
    if (seg.is_degenerate() || tri.is_degenerate() || !CGAL::do_intersect(seg, tri)) return;
    const auto x = CGAL::intersection(seg, tri);
    if (!x) return;
    const auto at = [](const K::Point_3& p) { return glm::dvec3(p.x(), p.y(), p.z()); };
    if (const K::Point_3* p = boost::get<K::Point_3>(&*x)) add(at(*p));
    else if (const K::Segment_3* q = boost::get<K::Segment_3>(&*x)) add(at(q->source())), add(at(q->target()));
}

}  // namespace

namespace {
// Where the edges of each face of the intersecting pair meet the other face (then sort_cuts: the
// cuts sorted, repeats dropped, whatever order the pairs came in).
void add_cuts(const MeshTopology& mesh, const std::array<std::uint32_t, 2>& pair, CutConstruction how,
              std::vector<EdgeCut>& cuts) {
    const SearchInput in = search_input(mesh);
    for (int k = 0; k < 2; ++k) {
        const std::uint32_t f = pair[k], g = pair[1 - k];
        const auto& fe = mesh.face_edges[f];
        const FaceData face = face_data(in, g);
        for (int j = 0; j < 3; ++j)
            if (fe.face[j] != g) cut_edge(mesh, fe.edge[j], g, face, how, cuts);  // (not an edge of both)
    }
}

void sort_cuts(std::vector<EdgeCut>& cuts) {
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end(), [](const EdgeCut& a, const EdgeCut& b) { return a.edge == b.edge && a.s == b.s; }),
               cuts.end());
}

// The result on `mesh` (the faces the search read) from the search's flags and pairs.
SelfIntersections assemble(const MeshTopology& mesh, PairSearch& search, const std::vector<std::uint64_t>& found,
                           CutConstruction how = CutConstruction::kFilteredFirst) {
    SelfIntersections si;
    si.faces = std::move(search.flags());
    for (const std::uint64_t k : found) si.faces[k >> 32] = si.faces[std::uint32_t(k)] = 1;
    list_pairs_in_cgal_order(search.columns(), found, [&](std::uint32_t fa, std::uint32_t fb) {
        si.pairs.push_back({fa, fb});
        add_cuts(mesh, {fa, fb}, how, si.cuts);
    });
    sort_cuts(si.cuts);
    si.flagged = std::size_t(std::count(si.faces.begin(), si.faces.end(), std::uint8_t(1)));
    return si;
}
}  // namespace

SelfIntersections self_intersections_among(const MeshTopology& mesh, const std::vector<std::uint32_t>& suspects,
                                           const std::vector<std::array<std::uint32_t, 2>>& candidates) {
    const SearchInput in = search_input(mesh);
    SelfIntersections si;
    si.faces.assign(mesh.face_count(), 0);
    // Per face met: its FaceData's slot in `data` (read once, then by every pair), and whether it
    // is degenerate (flagged and tested against nothing, as face_boxes leaves it out of the search).
    std::vector<std::uint32_t> slot(mesh.face_count(), UINT32_MAX);
    std::vector<FaceData> data;
    std::vector<std::uint8_t> degenerate;
    const auto at = [&](std::uint32_t f) -> std::uint32_t {
        if (slot[f] == UINT32_MAX) {
            slot[f] = std::uint32_t(data.size());
            const FaceData& d = data.emplace_back(face_data(in, f));
            const bool flat = !certainly_proper(d) && CGAL::collinear(cgal(d.p[0]), cgal(d.p[1]), cgal(d.p[2]));
            degenerate.push_back(flat);
            if (flat) si.faces[f] = 1;
        }
        return slot[f];
    };
    for (const std::uint32_t f : suspects) at(f);
    std::vector<std::uint64_t> found;
    for (const auto& [f, g] : candidates) {
        const std::uint32_t a = at(f), b = at(g);
        if (!degenerate[a] && !degenerate[b] && faces_intersect(data[a], data[b])) found.push_back(pair_key(f, g));
    }
    std::sort(found.begin(), found.end());
    si.pairs.reserve(found.size());
    for (const std::uint64_t k : found) {
        const std::array<std::uint32_t, 2> pair{std::uint32_t(k >> 32), std::uint32_t(k)};
        si.faces[pair[0]] = si.faces[pair[1]] = 1;
        si.pairs.push_back(pair);
        add_cuts(mesh, pair, CutConstruction::kFilteredFirst, si.cuts);
    }
    sort_cuts(si.cuts);
    si.flagged = std::size_t(std::count(si.faces.begin(), si.faces.end(), std::uint8_t(1)));
    return si;
}

std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh, int threads) {
    PairSearch search(search_input(mesh), search_workers(mesh.face_count(), threads), PatchTest::kEmbeddedPatchesSkipped);
    run_workers(search);
    const std::vector<std::uint64_t> found = search.collect();
    std::vector<std::uint8_t> out = std::move(search.flags());
    for (const std::uint64_t k : found) out[k >> 32] = out[std::uint32_t(k)] = 1;
    return out;
}

SelfIntersections self_intersections(const MeshTopology& mesh, int threads, PatchTest patch_test, CutConstruction cuts) {
    PairSearch search(search_input(mesh), search_workers(mesh.face_count(), threads), patch_test);
    run_workers(search);
    return assemble(mesh, search, search.collect(), cuts);
}

struct EarlySelfIntersections::Impl {
    SearchInput input;  // (the caller's arrays, read in place)
    std::size_t workers;
    std::atomic<bool> stop{false};  // set by the destructor: the search's threads return at once
    std::unique_ptr<PairSearch> search;
    std::exception_ptr failed;
    std::mutex mutex;
    std::condition_variable prepared_cv;
    bool prepared = false;
    std::thread helper;
};

EarlySelfIntersections::EarlySelfIntersections(const SearchInput& input, int threads) : impl_(std::make_unique<Impl>()) {
    Impl& im = *impl_;
    im.input = input;
    im.workers = std::max<std::size_t>(search_workers(input.face_count, threads), 2);
    // The helper prepares the search, starts any further helpers, and takes tasks as worker 1;
    // finish() takes them as worker 0 once its caller has done its own work.
    im.helper = std::thread([&im] {
        try {
            im.search = std::make_unique<PairSearch>(im.input, im.workers, PatchTest::kEmbeddedPatchesSkipped, &im.stop);
        } catch (...) {
            im.failed = std::current_exception();
        }
        {
            const std::lock_guard<std::mutex> lock(im.mutex);
            im.prepared = true;
        }
        im.prepared_cv.notify_all();
        if (!im.search) return;
        std::vector<std::thread> more;
        try {
            for (std::size_t k = 2; k < im.workers; ++k) more.emplace_back([&im, k] { im.search->work(k); });
        } catch (const std::system_error&) {
            // No more threads to be had: the ones started take every task.
        }
        im.search->work(1);
        for (std::thread& t : more) t.join();
    });
}

EarlySelfIntersections::~EarlySelfIntersections() {
    if (!impl_ || !impl_->helper.joinable()) return;
    impl_->stop.store(true, std::memory_order_relaxed);
    impl_->helper.join();
}

SelfIntersections EarlySelfIntersections::finish(const MeshTopology& mesh) {
    Impl& im = *impl_;
    {
        std::unique_lock<std::mutex> lock(im.mutex);
        im.prepared_cv.wait(lock, [&im] { return im.prepared; });
    }
    if (im.search) im.search->work(0);
    im.helper.join();
    if (im.failed) std::rethrow_exception(im.failed);
    return assemble(mesh, *im.search, im.search->collect());
}

}  // namespace inkline
