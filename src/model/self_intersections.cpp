#include "model/self_intersections.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

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

// Do faces f and g meet anywhere but where the mesh joins them (a shared edge or vertex)?
// The case analysis on shared corners is the one of CGAL's Polygon_mesh_processing::
// self_intersections (which needs a halfedge copy of the mesh, see the header); every test is an
// exact predicate of the Epick kernel.
bool faces_intersect(const MeshTopology& mesh, std::uint32_t f, std::uint32_t g) {
    const auto& a = mesh.faces[f];
    const auto& b = mesh.faces[g];
    int shared = 0, ia = -1, ib = -1;  // last shared corner, in a and in b
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a[i] == b[j]) {
                ++shared;
                ia = i;
                ib = j;
            }
    const auto P = [&](std::uint32_t v) { return cgal(mesh.positions[v]); };
    const K::Triangle_3 ta(P(a[0]), P(a[1]), P(a[2])), tb(P(b[0]), P(b[1]), P(b[2]));
    if (shared == 0) return CGAL::do_intersect(ta, tb);
    if (shared == 1) {
        // Beyond the shared corner, two triangles meet iff the side opposite the shared corner of
        // one meets the other.
        const K::Segment_3 sa(P(a[(ia + 1) % 3]), P(a[(ia + 2) % 3])), sb(P(b[(ib + 1) % 3]), P(b[(ib + 2) % 3]));
        return CGAL::do_intersect(sa, tb) || CGAL::do_intersect(sb, ta);
    }
    if (shared == 2) {
        // A shared edge (p, q): the faces overlap iff their far corners are coplanar with it and on
        // the same side of it.
        std::uint32_t ra = 0, rb = 0, p = 0, q = 0;
        for (int i = 0; i < 3; ++i) {
            if (a[i] != b[0] && a[i] != b[1] && a[i] != b[2]) {
                ra = a[i];
                p = a[(i + 1) % 3];
                q = a[(i + 2) % 3];
            }
            if (b[i] != a[0] && b[i] != a[1] && b[i] != a[2]) rb = b[i];
        }
        const K::Point_3 Pp = P(p), Pq = P(q), Ra = P(ra), Rb = P(rb);
        return CGAL::orientation(Pp, Pq, Ra, Rb) == CGAL::COPLANAR &&
               CGAL::coplanar_orientation(Pp, Pq, Ra, Rb) == CGAL::POSITIVE;
    }
    return true;  // the same three vertices twice
}

// Calls fn(f, g) for pairs of faces that intersect (every pair, or, with `once`, only pairs with
// a face not reported yet: enough to flag the faces).
template <class Fn>
void intersecting_pairs(const MeshTopology& mesh, std::vector<std::uint8_t>& out, bool once, Fn&& fn) {
    const std::size_t nf = mesh.face_count();
    out.assign(nf, 0);
    std::vector<Box> boxes;
    boxes.reserve(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.faces[f];
        // A degenerate face (collinear corners) counts as self-intersecting and is tested against
        // nothing, as in CGAL's PMP::self_intersections (CGAL's triangle tests require a proper
        // triangle: found by fuzz/run.sh pipeline).
        if (CGAL::collinear(cgal(mesh.positions[t[0]]), cgal(mesh.positions[t[1]]), cgal(mesh.positions[t[2]]))) {
            out[f] = 1;
            continue;
        }
        float lo[3], hi[3];
        for (int d = 0; d < 3; ++d) {
            const double x0 = mesh.positions[t[0]][d], x1 = mesh.positions[t[1]][d], x2 = mesh.positions[t[2]][d];
            lo[d] = down(std::min({x0, x1, x2}));
            hi[d] = up(std::max({x0, x1, x2}));
        }
        boxes.emplace_back(lo, hi, f);
    }
    // Closed boxes (the default): faces that only touch reach the exact test too. Cutoff: below
    // this many boxes CGAL's streamed segment tree compares boxes by a plain scan, which for sets
    // this small costs less than recursing further; the same pairs either way (bench/results/model.md).
    constexpr std::ptrdiff_t kCutoff = 3000;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
        const auto f = std::uint32_t(x.id()), g = std::uint32_t(y.id());
        if ((once && out[f] && out[g]) || !faces_intersect(mesh, f, g)) return;
        out[f] = out[g] = 1;
        fn(f, g);
    }, kCutoff);
}

// Where edge e meets triangle f (not one of e's faces): the parameter of the point, or of the
// ends of the shared stretch, except at an end vertex that f shares (no event there).
void cut_edge(const MeshTopology& mesh, std::uint32_t e, std::uint32_t f, std::vector<EdgeCut>& cuts) {
    const auto [v0, v1] = mesh.edge_vertex[e];
    const auto& t = mesh.faces[f];
    const glm::dvec3 E0 = mesh.positions[v0], E1 = mesh.positions[v1];
    const K::Segment_3 seg(cgal(E0), cgal(E1));
    const K::Triangle_3 tri(cgal(mesh.positions[t[0]]), cgal(mesh.positions[t[1]]), cgal(mesh.positions[t[2]]));
    if (seg.is_degenerate() || tri.is_degenerate() || !CGAL::do_intersect(seg, tri)) return;
    const auto x = CGAL::intersection(seg, tri);
    if (!x) return;
    const glm::dvec3 d = E1 - E0;
    const double dd = glm::dot(d, d);
    const bool shares0 = std::find(t.begin(), t.end(), v0) != t.end(), shares1 = std::find(t.begin(), t.end(), v1) != t.end();
    auto add = [&](const K::Point_3& p) {
        const double s = std::clamp(glm::dot(glm::dvec3(p.x(), p.y(), p.z()) - E0, d) / dd, 0.0, 1.0);
        // A rounded construction can come out NaN on nearly degenerate pairs (4 cuts of
        // AC14-FZK-Haus.ifc); a NaN cut hung the visibility's curve cutting (no order, no progress).
        if (std::isnan(s)) return;
        if ((s == 0.0 && shares0) || (s == 1.0 && shares1)) return;
        cuts.push_back({e, s});
    };
    if (const K::Point_3* p = boost::get<K::Point_3>(&*x)) add(*p);
    else if (const K::Segment_3* q = boost::get<K::Segment_3>(&*x)) add(q->source()), add(q->target());
}

}  // namespace

std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh) {
    std::vector<std::uint8_t> out;
    intersecting_pairs(mesh, out, true, [](std::uint32_t, std::uint32_t) {});
    return out;
}

SelfIntersections self_intersections(const MeshTopology& mesh) {
    SelfIntersections si;
    intersecting_pairs(mesh, si.faces, false, [&](std::uint32_t fa, std::uint32_t fb) {
        si.pairs.push_back({fa, fb});
        for (int k = 0; k < 2; ++k) {
            const std::uint32_t f = k ? fb : fa, g = k ? fa : fb;
            const auto& fe = mesh.face_edges[f];
            for (int j = 0; j < 3; ++j)
                if (fe.face[j] != g) cut_edge(mesh, fe.edge[j], g, si.cuts);  // (not an edge of both)
        }
    });
    std::sort(si.cuts.begin(), si.cuts.end());
    si.cuts.erase(std::unique(si.cuts.begin(), si.cuts.end(),
                              [](const EdgeCut& a, const EdgeCut& b) { return a.edge == b.edge && a.s == b.s; }),
                  si.cuts.end());
    si.flagged = std::size_t(std::count(si.faces.begin(), si.faces.end(), std::uint8_t(1)));
    return si;
}

}  // namespace inkline
