#include "model/intersection_curves.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <glm/vec2.hpp>

namespace inkline {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

// Segment ends as nodes of a graph: one per name (an edge and the face it passes through), united
// where several names meet at one point (an edge through an edge or a vertex).
class Nodes {
public:
    std::uint32_t named(std::uint32_t edge, std::uint32_t face, const glm::dvec3& p) {
        const auto [it, added] = by_name_.try_emplace((std::uint64_t(edge) << 32) | face, std::uint32_t(point_.size()));
        if (added) add(p);
        return it->second;
    }
    std::uint32_t unnamed(const glm::dvec3& p) {
        add(p);
        return std::uint32_t(point_.size() - 1);
    }
    std::uint32_t root(std::uint32_t n) {
        while (parent_[n] != n) n = parent_[n] = parent_[parent_[n]];
        return n;
    }
    void unite(std::uint32_t a, std::uint32_t b) {
        a = root(a), b = root(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // the first point made stays the node's
    }
    const glm::dvec3& point(std::uint32_t n) const { return point_[n]; }
    std::size_t size() const { return point_.size(); }

private:
    void add(const glm::dvec3& p) {
        parent_.push_back(std::uint32_t(point_.size()));
        point_.push_back(p);
    }
    std::unordered_map<std::uint64_t, std::uint32_t> by_name_;
    std::vector<std::uint32_t> parent_;
    std::vector<glm::dvec3> point_;
};

struct End {
    std::uint32_t node;
    glm::dvec3 p;
};
struct Seg {
    std::uint32_t a, b;  // nodes
    std::array<std::uint32_t, 2> faces;
};

class Builder {
public:
    Builder(const MeshTopology& mesh, IntersectionCurves& out)
        : mesh_(mesh), out_(out), eps_(1e-9 * std::max(mesh.bounds.half_diagonal(), 1e-300)) {}

    // The crossing segment of faces f and g (they intersect: the search said so).
    void add_pair(std::uint32_t f, std::uint32_t g) {
        const auto& tg = mesh_.faces[g];
        int coplanar = 0;
        for (std::uint32_t v : mesh_.faces[f])
            coplanar += CGAL::orientation(P(tg[0]), P(tg[1]), P(tg[2]), P(v)) == CGAL::COPLANAR;
        if (coplanar == 3) {
            ++out_.coplanar_pairs;
            return;
        }
        ends_.clear();
        if (!edge_ends(f, g) || !edge_ends(g, f)) return add_degenerate(f, g);
        if (ends_.empty()) {  // (the search and these tests are exact alike: only a touch at a point)
            ++out_.point_pairs;
            return;
        }
        // The ends lie on the line where the planes meet: the segment runs between the extremes
        // along it; names at the same extreme are one point.
        const glm::dvec3 d = glm::cross(mesh_.face_normal(f), mesh_.face_normal(g));
        std::size_t lo = 0, hi = 0;
        for (std::size_t i = 1; i < ends_.size(); ++i) {
            if (glm::dot(ends_[i].p, d) < glm::dot(ends_[lo].p, d)) lo = i;
            if (glm::dot(ends_[i].p, d) > glm::dot(ends_[hi].p, d)) hi = i;
        }
        const bool point_only = glm::length(ends_[hi].p - ends_[lo].p) <= eps_;
        for (const End& e : ends_) {
            if (point_only || glm::length(e.p - ends_[lo].p) <= eps_) nodes_.unite(e.node, ends_[lo].node);
            else if (glm::length(e.p - ends_[hi].p) <= eps_) nodes_.unite(e.node, ends_[hi].node);
        }
        if (point_only) ++out_.point_pairs;
        else segs_.push_back({ends_[lo].node, ends_[hi].node, {f, g}});
    }

    void finish() {
        join_open_ends();
        for (Seg& s : segs_) s.a = nodes_.root(s.a), s.b = nodes_.root(s.b);
        std::erase_if(segs_, [](const Seg& s) { return s.a == s.b; });
        find_meetings();
        chain();
    }

private:
    K::Point_3 P(std::uint32_t v) const { return cgal(mesh_.positions[v]); }

    // Where the edges of face f pass through face g (not coplanar with f): one End per edge that
    // meets g, the point computed from the edge (in its own vertex order) and g's plane alone, so
    // that every pair naming it gets the same bits. False when an edge of f lies in g's plane.
    bool edge_ends(std::uint32_t f, std::uint32_t g) {
        const auto& tg = mesh_.faces[g];
        const K::Point_3 q0 = P(tg[0]), q1 = P(tg[1]), q2 = P(tg[2]);
        const K::Triangle_3 tri(q0, q1, q2);
        const glm::dvec3 Q0 = mesh_.positions[tg[0]];
        const glm::dvec3 n = glm::cross(mesh_.positions[tg[1]] - Q0, mesh_.positions[tg[2]] - Q0);
        for (std::uint32_t e : mesh_.face_edges[f].edge) {
            const auto [va, vb] = mesh_.edge_vertex[e];
            const auto oa = CGAL::orientation(q0, q1, q2, P(va)), ob = CGAL::orientation(q0, q1, q2, P(vb));
            if (oa == CGAL::COPLANAR && ob == CGAL::COPLANAR) return false;
            if (oa == ob || !CGAL::do_intersect(K::Segment_3(P(va), P(vb)), tri)) continue;
            const glm::dvec3 A = mesh_.positions[va], B = mesh_.positions[vb];
            glm::dvec3 X;
            if (oa == CGAL::COPLANAR) X = A;
            else if (ob == CGAL::COPLANAR) X = B;
            else {
                const double da = glm::dot(n, A - Q0), db = glm::dot(n, B - Q0);
                X = A + std::clamp(da / (da - db), 0.0, 1.0) * (B - A);
            }
            ends_.push_back({nodes_.named(e, g, X), X});
        }
        return true;
    }

    // A pair where an edge lies in the other face's plane. The surfaces cross there only where the
    // edge's two faces leave that plane to opposite sides (and, when the other face also has its
    // edge on that line, its two faces leave this face's plane to opposite sides too); where they
    // stay on one side (a box resting on another, a sheet laid on a box) they only touch: no line.
    // A crossing along the line is met by the pairs of faces around it: only the pair where the
    // faces with an edge there are on the positive side adds it, as the part of the edge inside
    // the other face (its ends joined to the others by position).
    void add_degenerate(std::uint32_t f, std::uint32_t g) {
        const EdgeInPlane in_f = crossing_along_edge(f, g), in_g = crossing_along_edge(g, f);
        const EdgeInPlane& in = in_f.lies ? in_f : in_g;
        const bool crosses = (!in_f.lies || in_f.side > 0) && (!in_g.lies || in_g.side > 0);
        double t0 = 0.0, t1 = 1.0;
        const glm::dvec3 A = mesh_.positions[in.a], B = mesh_.positions[in.b];
        if (!crosses || !clip_to_face(A, B, in.plane_face, t0, t1) || (t1 - t0) * glm::length(B - A) <= eps_) {
            ++out_.point_pairs;
            return;
        }
        segs_.push_back({nodes_.unnamed(A + t0 * (B - A)), nodes_.unnamed(A + t1 * (B - A)), {f, g}});
    }

    struct EdgeInPlane {
        bool lies = false;  // an edge of the face lies in the other's plane
        int side = 0;       // +1 or -1: the face on the positive or negative side, the face across
                            // the edge on the other; 0: not so (no crossing there)
        std::uint32_t a = 0, b = 0, plane_face = 0;
    };
    // For an edge of face f that lies in face g's plane: side +1 if f is on the positive side of
    // the plane and the face across the edge on the negative side, -1 the other way round, 0 if
    // they do not cross the plane there.
    EdgeInPlane crossing_along_edge(std::uint32_t f, std::uint32_t g) const {
        const auto& tg = mesh_.faces[g];
        const auto side = [&](std::uint32_t v) { return CGAL::orientation(P(tg[0]), P(tg[1]), P(tg[2]), P(v)); };
        const auto& ff = mesh_.faces[f];
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t a = ff[j], b = ff[(j + 1) % 3], far = ff[(j + 2) % 3];  // edge j is (a, b)
            if (side(a) != CGAL::COPLANAR || side(b) != CGAL::COPLANAR) continue;
            const std::uint32_t h = mesh_.face_edges[f].face[j];
            if (h == kNoFace) return {true, 0, a, b, g};
            std::uint32_t h_far = 0;
            for (std::uint32_t v : mesh_.faces[h])
                if (v != a && v != b) h_far = v;
            const auto sf = side(far), sh = side(h_far);
            if (sf == CGAL::COPLANAR || sh == CGAL::COPLANAR || sf == sh) return {true, 0, a, b, g};
            return {true, sf == CGAL::POSITIVE ? 1 : -1, a, b, g};
        }
        return {};
    }

    // The part [t0, t1] of segment A-B (in face g's plane) inside face g, clipped against g's
    // sides in the plane of its two largest normal axes. Written here rather than taken from
    // CGAL::intersection(Triangle_3, Triangle_3): its coplanar branch crashed on nearly flat
    // pairs of an IFC building (AC14-FZK-Haus).
    bool clip_to_face(const glm::dvec3& A, const glm::dvec3& B, std::uint32_t g, double& t0, double& t1) const {
        const glm::dvec3 n = mesh_.face_normal(g), an = glm::abs(n);
        const int drop = an.x >= an.y && an.x >= an.z ? 0 : an.y >= an.z ? 1 : 2;
        const auto flat = [&](const glm::dvec3& p) { return glm::dvec2(p[(drop + 1) % 3], p[(drop + 2) % 3]); };
        const auto& t = mesh_.faces[g];
        const glm::dvec2 q[3] = {flat(mesh_.positions[t[0]]), flat(mesh_.positions[t[1]]), flat(mesh_.positions[t[2]])};
        const glm::dvec2 a = flat(A), b = flat(B);
        const auto cross = [](const glm::dvec2& u, const glm::dvec2& v) { return u.x * v.y - u.y * v.x; };
        const double orient = cross(q[1] - q[0], q[2] - q[0]) < 0.0 ? -1.0 : 1.0;
        for (int i = 0; i < 3; ++i) {
            const glm::dvec2 &qi = q[i], &qj = q[(i + 1) % 3];
            const double fa = orient * cross(qj - qi, a - qi), fb = orient * cross(qj - qi, b - qi);
            if (fa < 0.0 && fb < 0.0) return false;
            if (fa < 0.0) t0 = std::max(t0, fa / (fa - fb));
            if (fb < 0.0) t1 = std::min(t1, fa / (fa - fb));
        }
        return t1 > t0;
    }

    std::vector<std::uint32_t> degrees() {
        std::vector<std::uint32_t> deg(nodes_.size(), 0);
        for (const Seg& s : segs_) ++deg[nodes_.root(s.a)], ++deg[nodes_.root(s.b)];
        return deg;
    }

    // Curve ends that are one point under names the pairs could not tie (an edge through an
    // edge met from two sides, the degenerate pairs' ends): joined by position.
    void join_open_ends() {
        const std::vector<std::uint32_t> deg = degrees();
        std::vector<std::uint32_t> open;
        for (std::uint32_t n = 0; n < deg.size(); ++n)
            if (deg[n] == 1) open.push_back(n);
        std::sort(open.begin(), open.end(), [&](auto x, auto y) { return nodes_.point(x).x < nodes_.point(y).x; });
        for (std::size_t i = 0; i < open.size(); ++i)
            for (std::size_t j = i + 1; j < open.size() && nodes_.point(open[j]).x - nodes_.point(open[i]).x <= eps_; ++j)
                if (glm::length(nodes_.point(open[j]) - nodes_.point(open[i])) <= eps_) nodes_.unite(open[i], open[j]);
    }

    // Walks the segments into polylines: from every node that is not a plain pass (an end, or a
    // junction of more than two), then the loops left.
    void chain() {
        const std::vector<std::uint32_t> deg = degrees();
        std::vector<std::uint32_t> first(nodes_.size() + 1, 0), incident(2 * segs_.size());
        for (const Seg& s : segs_) ++first[s.a + 1], ++first[s.b + 1];
        for (std::size_t n = 0; n < nodes_.size(); ++n) first[n + 1] += first[n];
        std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
        for (std::uint32_t i = 0; i < segs_.size(); ++i) incident[fill[segs_[i].a]++] = i, incident[fill[segs_[i].b]++] = i;
        used_.assign(segs_.size(), 0);
        auto walk_from = [&](std::uint32_t node) {
            for (std::uint32_t k = first[node]; k < first[node + 1]; ++k)
                if (!used_[incident[k]]) walk(node, incident[k], deg, first, incident);
        };
        for (std::uint32_t n = 0; n < nodes_.size(); ++n)
            if (deg[n] != 0 && deg[n] != 2) walk_from(n);
        for (std::uint32_t i = 0; i < segs_.size(); ++i)
            if (!used_[i]) walk(segs_[i].a, i, deg, first, incident);
    }

    void walk(std::uint32_t start, std::uint32_t seg, const std::vector<std::uint32_t>& deg,
              const std::vector<std::uint32_t>& first, const std::vector<std::uint32_t>& incident) {
        const auto begin = std::uint32_t(out_.points.size());
        std::array<std::uint32_t, 2> slots{kNoFace, kNoFace};
        std::uint32_t node = start;
        bool meets = false, reference = false;
        out_.points.push_back(nodes_.point(node));
        out_.point_cut.push_back(0);
        while (true) {
            used_[seg] = 1;
            reference |= unlocated_[seg] != 0;
            slots = continue_slots(slots, segs_[seg].faces);
            node = segs_[seg].a == node ? segs_[seg].b : segs_[seg].a;
            // Where the segment passes through a third surface, in travel order.
            auto& at = splits_[seg];
            if (!at.empty()) {
                meets = true;
                const bool reversed = segs_[seg].a == node;  // travelling b -> a
                std::sort(at.begin(), at.end());
                if (reversed) std::reverse(at.begin(), at.end());
                for (double u : at) {
                    out_.segment_faces.push_back(slots);
                    const glm::dvec3 A = nodes_.point(segs_[seg].a), B = nodes_.point(segs_[seg].b);
                    out_.points.push_back(A + u * (B - A));
                    out_.point_cut.push_back(1);
                }
            }
            out_.segment_faces.push_back(slots);
            out_.points.push_back(nodes_.point(node));
            out_.point_cut.push_back(0);
            if (deg[node] != 2) break;
            std::uint32_t next = UINT32_MAX;
            for (std::uint32_t k = first[node]; k < first[node + 1]; ++k)
                if (!used_[incident[k]]) next = incident[k];
            if (next == UINT32_MAX) break;  // back at the start of a loop
            seg = next;
        }
        out_.segment_faces.push_back({kNoFace, kNoFace});
        const bool closed = node == start && deg[node] == 2;
        out_.curves.push_back({begin, std::uint32_t(out_.points.size()), closed, meets || reference, reference});
    }

    // The faces of the next segment in the slots of the last: the surface a face shares with the
    // last segment keeps its slot.
    static std::array<std::uint32_t, 2> continue_slots(const std::array<std::uint32_t, 2>& last,
                                                        const std::array<std::uint32_t, 2>& faces) {
        if (faces[1] == last[0] || faces[0] == last[1]) return {faces[1], faces[0]};
        return faces;
    }

    // Where curves pass through a third surface (a triple point): two segments on one face, not
    // joined end to end, that cross there (exact 2D predicates in the face's plane, the point a
    // construction). Each gets a split at the crossing. Segments that overlap along a line (no
    // single crossing) cannot be split: their curves take the reference.
    void find_meetings() {
        splits_.assign(segs_.size(), {});
        unlocated_.assign(segs_.size(), 0);
        std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> on_face;
        for (std::uint32_t i = 0; i < segs_.size(); ++i)
            for (std::uint32_t f : segs_[i].faces) on_face[f].push_back(i);
        for (const auto& [f, list] : on_face)
            for (std::size_t i = 0; i < list.size(); ++i)
                for (std::size_t j = i + 1; j < list.size(); ++j) split_where_they_meet(f, list[i], list[j]);
    }

    void split_where_they_meet(std::uint32_t f, std::uint32_t si, std::uint32_t ti) {
        const Seg& s = segs_[si];
        const Seg& t = segs_[ti];
        if (s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b) return;  // consecutive
        const glm::dvec3 n = glm::abs(mesh_.face_normal(f));
        const int drop = n.x >= n.y && n.x >= n.z ? 0 : n.y >= n.z ? 1 : 2;
        auto flat = [&](std::uint32_t node) {
            const glm::dvec3& p = nodes_.point(node);
            return K::Point_2(p[(drop + 1) % 3], p[(drop + 2) % 3]);
        };
        const K::Segment_2 s2(flat(s.a), flat(s.b)), t2(flat(t.a), flat(t.b));
        if (!CGAL::do_intersect(s2, t2)) return;
        // The parameters along each: solve s.a + u (s.b - s.a) = t.a + v (t.b - t.a) in the plane.
        const K::Vector_2 ds = s2.target() - s2.source(), dt = t2.target() - t2.source(), w = t2.source() - s2.source();
        const double den = ds.x() * dt.y() - ds.y() * dt.x();
        if (den == 0.0 || (CGAL::collinear(s2.source(), s2.target(), t2.source()) &&
                               CGAL::collinear(s2.source(), s2.target(), t2.target()))) {
            unlocated_[si] = unlocated_[ti] = 1;
            return;
        }
        const double u = std::clamp((w.x() * dt.y() - w.y() * dt.x()) / den, 0.0, 1.0);
        const double v = std::clamp((w.x() * ds.y() - w.y() * ds.x()) / den, 0.0, 1.0);
        splits_[si].push_back(u);
        splits_[ti].push_back(v);
    }

    const MeshTopology& mesh_;
    IntersectionCurves& out_;
    const double eps_;
    Nodes nodes_;
    std::vector<End> ends_;
    std::vector<Seg> segs_;
    std::vector<std::uint8_t> used_;
    std::vector<std::vector<double>> splits_;  // per segment: parameters (a = 0, b = 1) of triple points
    std::vector<std::uint8_t> unlocated_;      // per segment: meets another along a line
};

}  // namespace

IntersectionCurves intersection_curves(const MeshTopology& mesh,
                                       const std::vector<std::array<std::uint32_t, 2>>& pairs) {
    IntersectionCurves out;
    Builder b(mesh, out);
    for (const auto& [f, g] : pairs) b.add_pair(f, g);
    b.finish();
    return out;
}

}  // namespace inkline
