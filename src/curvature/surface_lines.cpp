// Curves across faces: suggestive contours, smooth contours, ridges and valleys (curvature.hpp).
//
// Each kind is found face by face, as in Rusinkiewicz's rtsc (the reference our suggestive contours
// are compared with): a face with a zero of the kind's scalar on two of its edges gets a segment
// between them. A point on an edge is computed from that edge's two vertex values only, in the
// edge's stored vertex order, so both faces of the edge produce the bit-identical point; the
// segments are then chained through those shared points into curves.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "curvature/curvature.hpp"

namespace inkline {

void SurfaceCurves::clear() {
    curves.clear();
    points.clear();
    point_edge.clear();
    segment_face.clear();
    strength.clear();
}

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Curvature times feature size below which a corner is flat for suggestive contours (a radius of
// curvature over 100 feature sizes: 5 bounding radii on CAD parts, where the feature size is
// capped). There kr is numerically zero and the sign of its estimate is noise; a face is skipped
// only when both principal curvatures are that small at all three corners, which organic models'
// suggestive contours almost never are (bench/results/surface_lines.md).
constexpr double kFlatCurvature = 0.01;

// Curvature lines shorter than this on the image are dropped: specks from a test flickering around
// its threshold, which read as dirt, not shape (smooth contours are kept whole: they close).
constexpr double kMinCurvePixels = 3.0;

// The graph of one kind's segments: nodes are points on mesh edges (at most one per edge: a
// linear function has one zero on an edge), points exactly at a vertex (one node for all the edges
// that put their zero there, so the curve passes through the vertex once; where more than two
// segments meet there, curves end at it), or points inside a face (ends cut by a test, the centre
// of a face whose three edges hold a ridge); chaining walks it.
class CurveGraph {
public:
    struct Node {
        glm::dvec3 pos;
        float strength;
        std::uint32_t edge;  // kNone: inside a face
        std::array<std::uint32_t, 3> seg;
        std::uint8_t degree;
        std::array<float, 3> test;  // the suggestive tests' values here (numerator, n.v, angle)
    };

    void begin(std::size_t edge_count, std::size_t vertex_count) {
        if (edge_stamp_.size() != edge_count || vertex_stamp_.size() != vertex_count || ++stamp_ == 0) {
            edge_stamp_.assign(edge_count, 0);
            edge_node_.resize(edge_count);
            vertex_stamp_.assign(vertex_count, 0);
            vertex_node_.resize(vertex_count);
            stamp_ = 1;
        }
        nodes_.clear();
        segs_.clear();
    }
    // The node on edge e, or kNone when none was made this pass.
    std::uint32_t edge_node(std::uint32_t e) const { return edge_stamp_[e] == stamp_ ? edge_node_[e] : kNone; }
    // The node on edge e (kNone: inside a face) at parameter t from edge_vertex[e][0]; t = 0 or
    // 1 is the vertex's node, shared by every edge there.
    std::uint32_t add_node(const glm::dvec3& pos, float strength, std::uint32_t edge,
                           std::array<float, 3> test = {}, std::uint32_t vertex = kNone) {
        if (vertex != kNone && vertex_stamp_[vertex] == stamp_) {
            map_edge(edge, vertex_node_[vertex]);
            return vertex_node_[vertex];
        }
        nodes_.push_back({pos, strength, edge, {kNone, kNone, kNone}, 0, test});
        const auto id = std::uint32_t(nodes_.size() - 1);
        map_edge(edge, id);
        if (vertex != kNone) {
            vertex_stamp_[vertex] = stamp_;
            vertex_node_[vertex] = id;
        }
        return id;
    }
    Node& node(std::uint32_t id) { return nodes_[id]; }
    void add_segment(std::uint32_t a, std::uint32_t b, std::uint32_t face) {
        if (a == b) return;  // both ends at one vertex: nothing to draw, the vertex's node joins on
        const auto s = std::uint32_t(segs_.size());
        segs_.push_back({{a, b}, face});
        attach(a, s);
        attach(b, s);
    }
    // Appends the curves of this pass to `out`, of kind `kind`, but those shorter than `min_px`
    // pixels on `camera`'s image.
    void chain(LineKind kind, const Camera& camera, double min_px, SurfaceCurves& out);

private:
    struct Segment {
        std::array<std::uint32_t, 2> node;
        std::uint32_t face;
    };
    // A node joined to more than three segments (impossible on a manifold, kept safe) ends the
    // curves there: the extra segment is not listed at it, so a walk stops on arriving.
    void attach(std::uint32_t n, std::uint32_t s) {
        Node& nd = nodes_[n];
        if (nd.degree < 3) nd.seg[nd.degree] = s;
        nd.degree = std::uint8_t(std::min(nd.degree + 1, 255));
    }
    void map_edge(std::uint32_t edge, std::uint32_t id) {
        if (edge == kNone) return;
        edge_stamp_[edge] = stamp_;
        edge_node_[edge] = id;
    }
    void walk(std::uint32_t start, std::uint32_t s, LineKind kind, const Camera& camera, double min_px,
              SurfaceCurves& out);
    void emit(std::uint32_t n, std::uint32_t face, std::uint32_t curve_begin, SurfaceCurves& out) const;

    std::vector<std::uint32_t> edge_stamp_, edge_node_, vertex_stamp_, vertex_node_;
    std::uint32_t stamp_ = 0;
    std::vector<Node> nodes_;
    std::vector<Segment> segs_;
    std::vector<std::uint8_t> used_;
};

// Appends node n's point; a point equal to the previous one (a zero exactly at a vertex gives
// zero-length segments) is merged into it, so no curve has a zero-length segment.
void CurveGraph::emit(std::uint32_t n, std::uint32_t face, std::uint32_t curve_begin, SurfaceCurves& out) const {
    const Node& nd = nodes_[n];
    if (out.points.size() > curve_begin && out.points.back() == nd.pos) {
        if (face != kNone) out.segment_face.back() = face;
        return;
    }
    out.points.push_back(nd.pos);
    out.point_edge.push_back(nd.edge);
    out.segment_face.push_back(face);
    out.strength.push_back(nd.strength);
}

void CurveGraph::walk(std::uint32_t start, std::uint32_t s, LineKind kind, const Camera& camera, double min_px,
                      SurfaceCurves& out) {
    const auto begin = std::uint32_t(out.points.size());
    bool closed = false;
    std::uint32_t cur = start;
    for (;;) {
        emit(cur, segs_[s].face, begin, out);
        used_[s] = 1;
        const std::uint32_t next = segs_[s].node[0] == cur ? segs_[s].node[1] : segs_[s].node[0];
        const Node& nd = nodes_[next];
        if (nd.degree != 2) {
            emit(next, kNone, begin, out);
            break;
        }
        const std::uint32_t s2 = nd.seg[0] == s ? nd.seg[1] : nd.seg[0];
        if (used_[s2]) {
            emit(next, kNone, begin, out);
            closed = next == start;
            break;
        }
        cur = next;
        s = s2;
    }
    const auto end = std::uint32_t(out.points.size());
    double px = 0.0;
    for (std::uint32_t i = begin; i + 1 < end && px < min_px; ++i)
        px += glm::length(camera.project(out.points[i + 1]) - camera.project(out.points[i]));
    // Fewer than two distinct points (or a loop through two) draws nothing; nor does a speck.
    if (end - begin < 2 || (closed && end - begin < 4) || px < min_px) {
        out.points.resize(begin);
        out.point_edge.resize(begin);
        out.segment_face.resize(begin);
        out.strength.resize(begin);
        return;
    }
    out.segment_face.back() = kNone;
    out.curves.push_back({kind, begin, end, closed});
}

void CurveGraph::chain(LineKind kind, const Camera& camera, double min_px, SurfaceCurves& out) {
    used_.assign(segs_.size(), 0);
    // Open curves first, from every end or junction; what is left are loops.
    for (std::uint32_t n = 0; n < nodes_.size(); ++n) {
        if (nodes_[n].degree == 2 || nodes_[n].degree == 0) continue;
        const int listed = std::min<int>(nodes_[n].degree, 3);
        for (int k = 0; k < listed; ++k)
            if (!used_[nodes_[n].seg[k]]) walk(n, nodes_[n].seg[k], kind, camera, min_px, out);
    }
    for (std::uint32_t s = 0; s < segs_.size(); ++s)
        if (!used_[s]) walk(segs_[s].node[0], s, kind, camera, min_px, out);
}

thread_local CurveGraph t_graph;

// A crease where the surface has no curvature, as on CAD parts: sharper than 60 degrees (angle
// between the face normals) between two faces whose other edges bend by under 5 degrees. Not every
// edge above the drawing's crease angle: coarse organic meshes have many sharp edges among bent
// neighbours, where the estimate is still the surface's and rings around them would erase real
// lines (bench/results/surface_lines.md). Taken from the mesh's crease list, so a drawing crease
// angle above 60 degrees also narrows this.
constexpr float kSharpCreaseRadians = float(60.0 * M_PI / 180.0);
constexpr float kSmoothSideRadians = float(5.0 * M_PI / 180.0);

// Vertices whose curvature is not the surface's: on a CAD crease the surface has no curvature, and the
// estimate there (from a normal averaged over both sides) is a spike that leaks into the vertices
// that share a face with it (their k), and one ring further (their C, from their neighbours' k). On
// CAD models the suggestive contours found near creases are only that leak (lines one or two rings
// off every crease, specks). Nonzero marks a vertex within two rings of a crease.
void mark_near_creases(const MeshTopology& mesh, std::vector<std::uint8_t>& near, std::vector<std::uint32_t>& frontier) {
    near.assign(mesh.vertex_count(), 0);
    frontier.clear();
    // A crease between smooth sides: its two faces' other edges are nearly flat.
    auto cad_crease = [&](std::uint32_t e) {
        if (mesh.edge_normal_angle[e] <= kSharpCreaseRadians) return false;
        for (std::uint32_t f : mesh.edge_face[e]) {
            if (f == kNoFace) continue;
            for (std::uint32_t o : mesh.face_edges[f].edge)
                if (o != e && mesh.edge_normal_angle[o] > kSmoothSideRadians) return false;
        }
        return true;
    };
    for (std::uint32_t e : mesh.crease_list)
        if (cad_crease(e))
            for (std::uint32_t v : mesh.edge_vertex[e])
                if (!near[v]) near[v] = 3, frontier.push_back(v);
    std::size_t begin = 0;
    for (std::uint8_t ring = 2; ring >= 1; --ring) {
        const std::size_t end = frontier.size();
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t v = frontier[i];
            for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
                const auto& ev = mesh.edge_vertex[mesh.vertex_edges[k]];
                const std::uint32_t other = ev[0] == v ? ev[1] : ev[0];
                if (!near[other]) near[other] = ring, frontier.push_back(other);
            }
        }
        begin = end;
    }
}

thread_local std::vector<std::uint32_t> t_frontier;
thread_local std::vector<std::uint8_t> t_near_crease;

// Sign used for zero sets: 0 counts as positive, so a zero exactly at a vertex puts the point on
// that vertex, the same from every face around it.
inline bool negative(float x) { return x < 0.0f; }

// Zero of the linear function with values fa, fb (opposite signs) at 0 and 1.
inline float zero_of(float fa, float fb) { return fa / (fa - fb); }

// The point at t from a to b; exactly b at t = 1 (a + (b - a) need not round to b), so that a
// point at a vertex is that vertex.
inline glm::dvec3 along(const glm::dvec3& a, const glm::dvec3& b, float t) { return t == 1.0f ? b : a + double(t) * (b - a); }

// The vertex a point at parameter t on edge (a, b) sits on, if any.
inline std::uint32_t at_vertex(std::uint32_t a, std::uint32_t b, float t) { return t == 0.0f ? a : t == 1.0f ? b : kNone; }

// ---- Suggestive contours ------------------------------------------------------------------------

// The suggestive contours' tests, as in rtsc: numerator D_w kr - T n.v and denominator n.v; a
// point passes where they have the same sign, i.e. D_w kr / n.v > T with
// T = threshold / feature_size^2. That one ratio is both tests of DeCarlo et al. 2004: D_w kr
// above a threshold (the contour's side test, Dw kr > 0, and no weak inflections from noise) and
// the angle test, since D_w kr carries sin(theta) and the ratio tan(theta): nearly head-on views
// (theta -> 0), where the zero set of kr is unstable, fail it. The optional third value is the
// cap on n.v (suggestive_max_ndotv; >= 0 passes).
struct SuggestiveTest {
    float threshold, fade, max_ndotv;
    float flat;  // curvature below which the surface counts as flat (kFlatCurvature / feature size)
    std::array<float, 3> at_vertex(const ViewCurvature& view, std::uint32_t v) const {
        return {view.dwkr[v] - threshold * view.ndotv[v], view.ndotv[v], max_ndotv - view.ndotv[v]};
    }
    static bool passes(const std::array<float, 3>& t) { return (t[0] >= 0.0f) == (t[1] >= 0.0f) && t[2] >= 0.0f; }
    // rtsc's fade: r / (fade + r) with r = num / den, 0 where the test fails, up to 1 far above.
    float strength(const std::array<float, 3>& t) const {
        if (!passes(t)) return 0.0f;
        if (t[1] == 0.0f) return 1.0f;
        const float r = t[0] / t[1];
        const float s = r / (fade + r);
        return s >= 0.0f && s <= 1.0f ? s : (s > 1.0f ? 1.0f : 0.0f);
    }
};

inline std::array<float, 3> lerp3(const std::array<float, 3>& a, const std::array<float, 3>& b, float t) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

// The node where kr vanishes on edge e (made once per edge, from its two vertices in stored order).
std::uint32_t suggestive_node(const MeshTopology& mesh, const ViewCurvature& view, const SuggestiveTest& test,
                              std::uint32_t e, CurveGraph& g) {
    std::uint32_t id = g.edge_node(e);
    if (id != kNone) return id;
    const auto [a, b] = mesh.edge_vertex[e];
    const float t = zero_of(view.kr[a], view.kr[b]);
    const auto values = lerp3(test.at_vertex(view, a), test.at_vertex(view, b), t);
    return g.add_node(along(mesh.positions[a], mesh.positions[b], t), test.strength(values), e, values, at_vertex(a, b, t));
}

// Adds the parts of segment p -> q (inside face f) where the test passes: the tests' values are
// linear along the segment, so it is cut at their zeros, as rtsc does.
void add_tested_segment(std::uint32_t p, std::uint32_t q, std::uint32_t f, const SuggestiveTest& test, CurveGraph& g) {
    const auto tp = g.node(p).test, tq = g.node(q).test;
    float cut[5] = {0.0f};
    int cuts = 1;
    for (int k = 0; k < 3; ++k)
        if ((tp[k] >= 0.0f) != (tq[k] >= 0.0f)) cut[cuts++] = zero_of(tp[k], tq[k]);
    if (cuts == 1 && SuggestiveTest::passes(tp)) {
        g.add_segment(p, q, f);
        return;
    }
    // At most three cuts: sorted by insertion (std::sort over this small array trips -Warray-bounds).
    for (int a = 2; a < cuts; ++a)
        for (int b = a; b > 1 && cut[b] < cut[b - 1]; --b) std::swap(cut[b], cut[b - 1]);
    cut[cuts++] = 1.0f;
    std::uint32_t run_start = kNone;
    const glm::dvec3 pp = g.node(p).pos, pq = g.node(q).pos;
    auto node_at = [&](int k) -> std::uint32_t {
        if (k == 0) return p;
        if (k == cuts - 1) return q;
        const auto values = lerp3(tp, tq, cut[k]);
        return g.add_node(along(pp, pq, cut[k]), test.strength(values), kNone, values);
    };
    for (int k = 0; k + 1 < cuts; ++k) {
        const bool ok = cut[k + 1] > cut[k] && SuggestiveTest::passes(lerp3(tp, tq, 0.5f * (cut[k] + cut[k + 1])));
        if (ok && run_start == kNone) run_start = node_at(k);
        if (!ok && run_start != kNone) {
            g.add_segment(run_start, node_at(k), f);
            run_start = kNone;
        }
    }
    if (run_start != kNone) g.add_segment(run_start, q, f);
}

// The two edges (corner indices) of face f whose ends differ in sign of `value`; false if none.
template <class Value>
bool crossing_edges(const std::array<std::uint32_t, 3>& vs, Value value, int& i, int& j) {
    const bool s0 = negative(value(vs[0])), s1 = negative(value(vs[1])), s2 = negative(value(vs[2]));
    if (s0 == s1 && s1 == s2) return false;
    // Edge k joins corners k and k+1; the odd corner's two edges cross.
    if (s0 == s1) i = 1, j = 2;       // corner 2 odd: edges (1,2), (2,0)
    else if (s1 == s2) i = 0, j = 2;  // corner 0 odd: edges (0,1), (2,0)
    else i = 0, j = 1;                // corner 1 odd: edges (0,1), (1,2)
    return true;
}

// Per-vertex facts the suggestive contours' face test needs, one byte a vertex, so that the face
// loop reads three bytes and takes one branch per face (the kr signs of a scanned model are noise
// over much of it: branch per fact would mispredict).
enum VertexBit : std::uint8_t {
    kKrNegative = 1,   // kr < 0 (0 counts as positive)
    kUsable = 2,       // estimated, off CAD creases, all finite
    kCurved = 4,       // not flat (a principal curvature at least kFlatCurvature / feature size)
    kFront = 8,        // n.v > 0
    kPasses = 16,      // the test passes here
    kTestSigns = 32 | 64 | 128,  // signs of the test's three values (numerator, n.v, cap)
};

void mark_vertices(const CurvatureField& field, const ViewCurvature& view, const SuggestiveTest& test,
                   const std::vector<std::uint8_t>& near_crease, std::vector<std::uint8_t>& bits) {
    const std::size_t n = field.size();
    bits.resize(n);
    for (std::size_t v = 0; v < n; ++v) {
        const float kr = view.kr[v], nv = view.ndotv[v], dw = view.dwkr[v];
        const float num = dw - test.threshold * nv, cap = test.max_ndotv - nv;
        // Bitwise, not short-circuit: no branches. (A NaN fails every comparison; x - x is 0 only
        // for finite x.)
        const unsigned finite = unsigned(kr - kr == 0.0f) & unsigned(nv - nv == 0.0f) & unsigned(dw - dw == 0.0f);
        const unsigned num_pos = num >= 0.0f, nv_pos = nv >= 0.0f, cap_pos = cap >= 0.0f;
        const unsigned passes = unsigned(num_pos == nv_pos) & cap_pos;
        const unsigned usable = unsigned(field.valid[v] != 0) & unsigned(near_crease[v] == 0) & finite;
        const float k = std::max(std::fabs(field.k1[v]), std::fabs(field.k2[v]));
        bits[v] = std::uint8_t(unsigned(kr < 0.0f) * kKrNegative | usable * kUsable | unsigned(k >= test.flat) * kCurved |
                               unsigned(nv > 0.0f) * kFront | passes * kPasses | num_pos * 32 | nv_pos * 64 | cap_pos * 128);
    }
}

thread_local std::vector<std::uint8_t> t_vertex_bits;

void extract_suggestive(const MeshTopology& mesh, const CurvatureField& field, const ViewCurvature& view,
                        const SuggestiveTest& test, CurveGraph& g) {
    std::vector<std::uint8_t>& bits = t_vertex_bits;
    mark_vertices(field, view, test, t_near_crease, bits);
    const auto kr = [&](std::uint32_t v) { return view.kr[v]; };
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const auto& vs = mesh.faces[f];
        const unsigned b0 = bits[vs[0]], b1 = bits[vs[1]], b2 = bits[vs[2]];
        const unsigned all = b0 & b1 & b2, any = b0 | b1 | b2;
        // A face draws if kr changes sign in it; all corners are usable; not all flat (there the
        // sign of kr is estimator noise: CAD facets); not all back-facing (no suggestive contour
        // on back faces; rtsc culls them the same way); and the test passes somewhere in it: at a
        // corner, or where one of its values changes sign (rtsc's quick reject).
        const bool draws = ((any & ~all) & kKrNegative) && (all & kUsable) && (any & kCurved) && (any & kFront) &&
                           ((any & kPasses) || ((any ^ all) & kTestSigns));
        if (!draws) continue;
        int i = 0, j = 0;
        crossing_edges(vs, kr, i, j);
        const auto& fe = mesh.face_edges[f].edge;
        const std::uint32_t p = suggestive_node(mesh, view, test, fe[std::size_t(i)], g);
        const std::uint32_t q = suggestive_node(mesh, view, test, fe[std::size_t(j)], g);
        add_tested_segment(p, q, f, test, g);
    }
}

// ---- Smooth contours ----------------------------------------------------------------------------

void extract_smooth_contours(const MeshTopology& mesh, const CurvatureField& field, const ViewCurvature& view,
                             CurveGraph& g) {
    const auto ndotv = [&](std::uint32_t v) { return view.ndotv[v]; };
    auto node = [&](std::uint32_t e) {
        std::uint32_t id = g.edge_node(e);
        if (id != kNone) return id;
        const auto [a, b] = mesh.edge_vertex[e];
        const float t = zero_of(view.ndotv[a], view.ndotv[b]);
        return g.add_node(along(mesh.positions[a], mesh.positions[b], t), 1.0f, e, {}, at_vertex(a, b, t));
    };
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const auto& vs = mesh.faces[f];
        int i, j;
        // Not face_usable: n.v needs only normals, and the contour runs over creases too.
        if (!crossing_edges(vs, ndotv, i, j)) continue;
        if (!field.valid[vs[0]] || !field.valid[vs[1]] || !field.valid[vs[2]] || !std::isfinite(view.ndotv[vs[0]]) ||
            !std::isfinite(view.ndotv[vs[1]]) || !std::isfinite(view.ndotv[vs[2]]))
            continue;
        const auto& fe = mesh.face_edges[f].edge;
        g.add_segment(node(fe[std::size_t(i)]), node(fe[std::size_t(j)]), f);
    }
}

// ---- Ridges and valleys -------------------------------------------------------------------------

// Ridges: maxima of the principal curvature of largest magnitude where it is positive, along its
// own direction; valleys: minima where it is negative (rtsc, after Ohtake et al. 2004). With
// k1 >= k2 that curvature is k1 along dir1 (ridges) or k2 along dir2 (valleys).
struct RidgeKind {
    bool ridge;
    float threshold;  // ridge_threshold / feature_size
    const CurvatureField* field;
    bool eligible(std::uint32_t v) const {
        const float a = field->k1[v], b = field->k2[v];
        return ridge ? (a > 0.0f && a >= -b) : (b < 0.0f && -b > a);
    }
    float kmax(std::uint32_t v) const { return ridge ? field->k1[v] : field->k2[v]; }
    // Derivative of that curvature along its direction: C(d1,d1,d1) or C(d2,d2,d2).
    float emax(std::uint32_t v) const { return ridge ? field->dcurv[v][0] : field->dcurv[v][3]; }
    // The direction in which the curvature grows (ridges) or falls (valleys). emax * dir does not
    // change when dir is flipped (C is odd in each argument), which removes the sign ambiguity of
    // the principal direction between the corners of a face.
    glm::vec3 uphill(std::uint32_t v) const {
        const glm::vec3 d = ridge ? field->dir1[v] : glm::cross(field->normal[v], field->dir1[v]);
        return (ridge ? 1.0f : -1.0f) * emax(v) * d;
    }
    // rtsc's fade: (|k| - T) / |k| over the threshold, 0 below it.
    float strength(float k) const {
        const float over = std::fabs(k) - threshold;
        return over > 0.0f ? over / (over + threshold) : 0.0f;
    }
};

// Whether the extremum lies on edge (a, b): the uphill directions oppose, and the curvature peaks
// between a and b (not a minimum). Symmetric in a and b, so both faces of the edge agree.
bool ridge_crosses(const MeshTopology& mesh, const RidgeKind& kind, std::uint32_t a, std::uint32_t b) {
    const glm::vec3 ta = kind.uphill(a), tb = kind.uphill(b);
    if (glm::dot(ta, tb) > 0.0f) return false;
    const glm::vec3 ab = glm::vec3(mesh.positions[b] - mesh.positions[a]);
    return glm::dot(ta, ab) >= 0.0f || glm::dot(tb, ab) <= 0.0f;
}

std::uint32_t ridge_node(const MeshTopology& mesh, const RidgeKind& kind, std::uint32_t e, CurveGraph& g) {
    std::uint32_t id = g.edge_node(e);
    if (id != kNone) return id;
    const auto [a, b] = mesh.edge_vertex[e];
    const float ea = std::fabs(kind.emax(a)), eb = std::fabs(kind.emax(b));
    const float t = ea + eb > 0.0f ? ea / (ea + eb) : 0.5f;
    const float k = kind.kmax(a) + t * (kind.kmax(b) - kind.kmax(a));
    return g.add_node(along(mesh.positions[a], mesh.positions[b], t), kind.strength(k), e, {}, at_vertex(a, b, t));
}

void extract_ridges(const MeshTopology& mesh, const CurvatureField& field, const RidgeKind& kind, CurveGraph& g) {
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const auto& vs = mesh.faces[f];
        if (!field.valid[vs[0]] || !field.valid[vs[1]] || !field.valid[vs[2]]) continue;
        if (t_near_crease[vs[0]] || t_near_crease[vs[1]] || t_near_crease[vs[2]]) continue;
        if (!kind.eligible(vs[0]) || !kind.eligible(vs[1]) || !kind.eligible(vs[2])) continue;
        bool z[3];
        int count = 0;
        for (int k = 0; k < 3; ++k) count += z[k] = ridge_crosses(mesh, kind, vs[std::size_t(k)], vs[std::size_t((k + 1) % 3)]);
        if (count < 2) continue;
        const auto& fe = mesh.face_edges[f].edge;
        std::uint32_t n[3] = {kNone, kNone, kNone};
        for (int k = 0; k < 3; ++k)
            if (z[k]) n[k] = ridge_node(mesh, kind, fe[std::size_t(k)], g);
        if (count == 2) {
            const int i = z[0] ? 0 : 1, j = z[2] ? 2 : 1;
            // Below the threshold at both ends: nothing to draw (rtsc's rule).
            if (g.node(n[i]).strength > 0.0f || g.node(n[j]).strength > 0.0f) g.add_segment(n[i], n[j], f);
            continue;
        }
        // Three crossings: each joins the face's centre.
        const glm::dvec3 c = (mesh.positions[vs[0]] + mesh.positions[vs[1]] + mesh.positions[vs[2]]) / 3.0;
        const float kc = (kind.kmax(vs[0]) + kind.kmax(vs[1]) + kind.kmax(vs[2])) / 3.0f;
        const std::uint32_t centre = g.add_node(c, kind.strength(kc), kNone);
        for (int k = 0; k < 3; ++k)
            if (g.node(n[k]).strength > 0.0f || g.node(centre).strength > 0.0f) g.add_segment(n[k], centre, f);
    }
}

// The length that makes the thresholds dimensionless: rtsc's feature size, so that our defaults
// mean what the reference's do. It is 1 % of the inverse of the 10th percentile of |k1|, |k2| over
// 500 vertices picked by a fixed linear congruential sequence (deterministic), capped at 5 % of
// the radius of a bounding sphere (the one through the box's corners: no pass over the vertices). A curvature scale, unlike the median edge
// length (CurvatureField::feature_size): with that, a threshold over feature_size^2 grows with
// the square of the tessellation's density, and refining a mesh would erase its lines.
double threshold_length(const MeshTopology& mesh, const CurvatureField& field, std::vector<float>& samples) {
    const std::size_t n = field.size();
    const double cap = 0.05 * mesh.bounds.half_diagonal();
    samples.clear();
    std::uint32_t state = 0;
    for (std::size_t i = 0; i < std::min<std::size_t>(n, 500); ++i) {
        state = 1664525u * state + 1013904223u;
        const std::size_t v = state % n;
        samples.push_back(std::fabs(field.k1[v]));
        samples.push_back(std::fabs(field.k2[v]));
    }
    double fs = cap;
    if (!samples.empty()) {
        const auto which = samples.begin() + std::ptrdiff_t(0.1 * double(samples.size()));
        std::nth_element(samples.begin(), which, samples.end());
        if (std::isfinite(*which) && *which > 0.0f) fs = std::min(fs, 0.01 / double(*which));
    }
    if (std::isfinite(fs) && fs > 0.0) return fs;
    // No extent (a single point): any positive length keeps the thresholds finite.
    return std::isfinite(field.feature_size) && field.feature_size > 0.0 ? field.feature_size : 1.0;
}

thread_local std::vector<float> t_samples;

}  // namespace

void extract_surface_lines(const MeshTopology& mesh, const CurvatureField& field, const ViewCurvature& view,
                           const Camera& camera, const SurfaceLineOptions& options, SurfaceCurves& out) {
    out.clear();
    if (field.size() != mesh.vertex_count() || view.kr.size() != mesh.vertex_count()) return;
    CurveGraph& g = t_graph;
    mark_near_creases(mesh, t_near_crease, t_frontier);
    const double fs = threshold_length(mesh, field, t_samples);
    if (options.suggestive) {
        // rtsc's fade constant, 0.03 / feature_size^2, on the same scale as the threshold.
        const SuggestiveTest test{float(options.suggestive_threshold / (fs * fs)), float(0.03 / (fs * fs)),
                                  float(options.suggestive_max_ndotv), float(kFlatCurvature / fs)};
        g.begin(mesh.edge_count(), mesh.vertex_count());
        extract_suggestive(mesh, field, view, test, g);
        g.chain(LineKind::Suggestive, camera, kMinCurvePixels, out);
    }
    if (options.smooth_contour) {
        g.begin(mesh.edge_count(), mesh.vertex_count());
        extract_smooth_contours(mesh, field, view, g);
        g.chain(LineKind::SmoothContour, camera, 0.0, out);
    }
    for (const bool ridge : {true, false}) {
        if (!(ridge ? options.ridge : options.valley)) continue;
        const RidgeKind kind{ridge, float(options.ridge_threshold / fs), &field};
        g.begin(mesh.edge_count(), mesh.vertex_count());
        extract_ridges(mesh, field, kind, g);
        g.chain(ridge ? LineKind::Ridge : LineKind::Valley, camera, kMinCurvePixels, out);
    }
}

}  // namespace inkline
