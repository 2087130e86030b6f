#include "visibility/visibility.hpp"

#include <algorithm>
#include <chrono>
#include <bit>
#include <cmath>
#include <span>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "visibility/crossings.hpp"

namespace inkline {
namespace {

// A curve edge after near-plane clipping, in 3D and in the image.
struct ClipSeg {
    // (not zeroed: clip_edge or a copy sets every field but edge and run_start, which build_range
    // sets; value-initialization by emplace_back() would clear the whole segment first)
    ClipSeg() {}
    glm::dvec3 A, B;
    glm::dvec2 a, b;
    double slack;   // rounding of a and b (image_slack)
    double zA, zB;  // depths of A and B
    double sA, sB;  // parameters of A and B along the mesh edge
    const glm::dvec3 *LA = nullptr, *LB = nullptr;  // the mesh vertices at the ends, before clipping
    std::uint32_t edge = 0;
    bool run_start = false;  // the curve is interrupted (clipped) before this segment
    bool unclipped = false;  // A == *LA and B == *LB
    bool kept_both = false;  // neither end clipped: A, B the mesh vertices
    // (set by build_range for its curve segments) a copy of the occluder of its edge, with the
    // same slack
    bool occluder_copy = false;
    Segment3 in_3d() const { return {A, B, LA, LB, std::int8_t(unclipped)}; }
};

// Clips the edge from mesh vertex vP to vQ (edge parameters sP, sQ) to depth >= n; returns false
// when nothing is left. The images of unclipped ends come from `images` (each vertex projected
// once per view). Sets everything but `edge` and `run_start`.
bool clip_edge(const Camera& cam, double n, const VertexImages& images, const std::vector<glm::dvec3>& positions,
               std::uint32_t vP, std::uint32_t vQ, double sP, double sQ, ClipSeg& out) {
    glm::dvec3 P = positions[vP], Q = positions[vQ];
    double zP = cam.depth(P), zQ = cam.depth(Q);
    if (!(zP >= n) && !(zQ >= n)) return false;
    bool keepP = true, keepQ = true;
    if (zP < n) {
        keepP = false;
        const double u = (n - zP) / (zQ - zP);
        P = P + u * (Q - P);
        sP = sP + u * (sQ - sP);
        zP = n;
    } else if (zQ < n) {
        keepQ = false;
        const double u = (n - zQ) / (zP - zQ);
        Q = Q + u * (P - Q);
        sQ = sQ + u * (sP - sQ);
        zQ = n;
    }
    out.A = P;
    out.B = Q;
    out.zA = zP;
    out.zB = zQ;
    out.sA = sP;
    out.sB = sQ;
    out.a = keepP ? images(vP) : cam.project(P);
    out.b = keepQ ? images(vQ) : cam.project(Q);
    out.slack = std::max(keepP ? images.slack(vP) : image_slack(cam, P, out.a),
                         keepQ ? images.slack(vQ) : image_slack(cam, Q, out.b));
    out.LA = &positions[vP];
    out.LB = &positions[vQ];
    out.unclipped = out.A == *out.LA && out.B == *out.LB;
    out.kept_both = keepP && keepQ;
    return std::isfinite(out.a.x) && std::isfinite(out.a.y) && std::isfinite(out.b.x) && std::isfinite(out.b.y);
}

// Parameter along the 3D segment of the point seen at image parameter t (perspective-correct).
double to_3d(const Camera& cam, const ClipSeg& s, double t) {
    if (cam.is_ortho()) return t;
    const double den = (1.0 - t) * s.zB + t * s.zA;
    return den > 0.0 ? t * s.zA / den : t;
}

constexpr std::uint32_t kNoOccluder = UINT32_MAX;  // a split where the curve meets another face

struct Split {
    std::uint32_t seg;
    double t;
    std::uint32_t occluder;  // index into the occluders, or kNoOccluder
    double ot = NAN;         // where along the occluder, if the search found it (segment_crossings)
    bool operator<(const Split& o) const { return seg != o.seg ? seg < o.seg : t < o.t; }
};

// The occluder of each silhouette or border edge: a hash table of (edge, occluder) with at least
// twice the occluders' slots (a few hundred kilobytes where a per-edge array would be megabytes
// read at random), probed linearly.
class EdgeOccluders {
public:
    void build(const std::vector<Segment2>& occluders) {
        std::size_t cap = 16;
        while (cap < 2 * occluders.size()) cap *= 2;
        shift_ = 64 - std::countr_zero(cap);
        slots_.assign(cap, {UINT32_MAX, UINT32_MAX});
        for (std::uint32_t k = 0; k < occluders.size(); ++k) {
            std::size_t i = slot(occluders[k].edge);
            while (slots_[i][0] != UINT32_MAX && slots_[i][0] != occluders[k].edge) i = (i + 1) & (cap - 1);
            slots_[i] = {occluders[k].edge, k};  // (an edge listed twice: its last occluder)
        }
    }
    // Prefetches the slot where find(e) starts (no effect on results).
    void prefetch(std::uint32_t e) const { __builtin_prefetch(&slots_[slot(e)]); }
    // The occluder of mesh edge e, or UINT32_MAX.
    std::uint32_t find(std::uint32_t e) const {
        for (std::size_t i = slot(e);; i = (i + 1) & (slots_.size() - 1)) {
            if (slots_[i][0] == e) return slots_[i][1];
            if (slots_[i][0] == UINT32_MAX) return UINT32_MAX;
        }
    }

private:
    std::size_t slot(std::uint32_t e) const { return std::size_t((std::uint64_t(e) * 0x9E3779B97F4A7C15ull) >> shift_); }
    std::vector<std::array<std::uint32_t, 2>> slots_;
    int shift_ = 60;
};

// The view's occluding edges, as build_range reads them: in the image (Segment2), clipped
// (ClipSeg, edge order), their boxes, the occluder of a mesh edge, and whether each is unclipped.
struct OccluderSet {
    const std::vector<Segment2>& segs;
    const std::vector<ClipSeg>& clip;
    const std::vector<Box2f>& boxes;
    const EdgeOccluders& of_edge;
    const std::vector<std::uint8_t>& unclipped;  // clip[k].unclipped, compact
    std::uint32_t find(std::uint32_t e) const { return of_edge.find(e); }
};

// build_pieces' working arrays, kept per thread from view to view.
struct Scratch {
    struct Pending {
        std::uint32_t seg, occluder;
        double t, ot;  // (ot: Split::ot)
    };
    std::vector<ClipSeg> occ_clip, all_segs;
    std::vector<std::uint64_t> in_curves, found;
    struct Kept {  // a pair the quick reject kept, and the sides it decided (filter_sides)
        std::uint64_t pair;
        std::int8_t sides[4];
    };
    std::vector<Kept> kept;
    std::vector<std::uint32_t> seg_begin, at, next;
    std::vector<std::uint32_t> seg_occ;       // the occluder a curve segment was copied from, or UINT32_MAX
    std::vector<std::uint32_t> occ_mirror;    // the mirrorable segment copied from an occluder, or UINT32_MAX
    EdgeOccluders occ_of_edge;
    std::vector<std::uint8_t> occ_unclipped;
    std::vector<Split> all_splits, sorted, splits;
    std::vector<Pending> pending, wrap;
    std::vector<double> lc_ot;  // Split::ot of a curve's link crossings
    std::vector<Box2f> qbox, obox;
    std::vector<std::uint32_t> hits;
    BoxPairs grid;
    struct Parts {  // a second range's output, before it is appended (pieces: storage kept)
        std::vector<Piece> pieces;
        std::vector<std::vector<EdgeSpan>> spans;
        std::vector<PieceGraph::Link> links;
        std::vector<PieceGraph::LinkCrossing> link_crossings;
        std::vector<PieceGraph::End> ends;
        void clear() { links.clear(), link_crossings.clear(), ends.clear(); }
    } parts;
};

// Whether curve segment s has the image, box and exact sides of the occluder k it was copied from
// (seg_occ): unclipped ends (the mesh vertices; a copy's are the occluder's) and the same slack;
// then the pairs (s, k2) and (s2, k) for another such s2 copied from k2 are one question
// (mirrored_crossings).
bool mirrorable(const ClipSeg& s) { return s.occluder_copy && s.unclipped; }

// Prefetches (no effect on results) the cache lines of one record.
template <class T>
void prefetch_record(const T* r) {
    const char* p = reinterpret_cast<const char*>(r);
    for (std::size_t b = 0; b < sizeof(T); b += 64) __builtin_prefetch(p + b);
    __builtin_prefetch(p + sizeof(T) - 1);
}

// True when some geometry lies at or behind the near plane (the camera is among the geometry).
bool geometry_behind_near(const MeshTopology& mesh, const Camera& camera) {
    const Bounds3& b = mesh.bounds;
    double lo = 1e300;
    for (int k = 0; k < 8; ++k)
        lo = std::min(lo, camera.depth({k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z}));
    if (lo > camera.near_distance()) return false;
    for (const auto& p : mesh.positions)
        if (!(camera.depth(p) > camera.near_distance())) return true;
    return false;
}

}  // namespace

double default_near(const MeshTopology& mesh) {
    const double r = mesh.bounds.half_diagonal();
    return 1e-6 * (r > 0.0 ? r : 1.0);
}

namespace {

// What build_range gives for one range of curves. The pieces are pieces[0, n) (and spans[0, n));
// the slots after them hold storage of earlier views, reused in place: a slot's point and span
// vectors keep their capacity.
struct Part {
    std::vector<Piece>& pieces;
    std::vector<std::vector<EdgeSpan>>& spans;
    std::vector<PieceGraph::Link>& links;
    std::vector<PieceGraph::LinkCrossing>& link_crossings;
    std::vector<PieceGraph::End>& ends;
    // Where new slots come from before they are made (the graph's spare storage), if anywhere.
    std::vector<Piece>* spare_pieces = nullptr;
    std::vector<std::vector<EdgeSpan>>* spare_spans = nullptr;
    std::uint32_t n = 0;
    std::size_t crossings = 0;
    // Makes slot n (the next piece) exist; its contents are whatever it held.
    void open_slot() {
        if (pieces.size() > n) return;
        if (spare_pieces && !spare_pieces->empty()) {
            pieces.push_back(std::move(spare_pieces->back()));
            spans.push_back(std::move(spare_spans->back()));
            spare_pieces->pop_back();
            spare_spans->pop_back();
        } else {
            pieces.emplace_back();
            spans.emplace_back();
        }
    }
};

// The pieces of curves [c0, c1) (build_pieces' work after the occluders), appended to P; piece
// and link indices local to P. `images` must hold every curve vertex already when this runs on
// several threads (it is then only read). The steps are its member functions, in run()'s order;
// the working arrays are the scratch's (kept from view to view).
struct RangeBuild {
    const MeshTopology& mesh;
    const Features& features;
    const Camera& camera;
    const std::vector<EdgeCut>* cuts;
    const VertexImages& images;
    const OccluderSet& occ;
    const std::vector<std::uint64_t>& in_curves;
    const BoxPairs& grid;
    std::uint32_t c0, c1;
    bool mirror;
    Scratch& scratch;
    Part& P;
    // The curve segments: all_segs (curve ci's in [seg_begin[ci - c0], seg_begin[ci - c0 + 1])),
    // and the occluder each was copied from (seg_occ, or UINT32_MAX).
    std::vector<ClipSeg>& all_segs = scratch.all_segs;
    std::vector<std::uint32_t>& seg_begin = scratch.seg_begin;
    std::vector<std::uint32_t>& seg_occ = scratch.seg_occ;
    std::vector<Split>& all_splits = scratch.all_splits;  // by segment, then parameter
    // Cutting: the piece being built is always slot P.n (*cur, *cur_spans), filled in place.
    Piece* cur = nullptr;
    std::vector<EdgeSpan>* cur_spans = nullptr;
    std::size_t next_split = 0;  // the first split of the next curve in all_splits
    bool linked = false;         // the next piece emitted continues the last one across `pending`

    void run() {
        clip_curves();
        all_splits.clear();
        find_pairs();
        test_pairs();
        split_at_cuts();
        sort_splits();
        cut_curves();
    }

    // 1. Every curve of the range clipped to the near plane and projected: their segments in one
    // array. A silhouette or border edge in front of the near plane was clipped and projected as
    // an occluder already: the same values (clip_edge keeps both ends, as it did there), in
    // travel order.
    void clip_curves();
    // 2. Crossings of every curve segment with every occluding edge, in one search: pairs whose
    // boxes overlap (BoxPairs, into scratch.found), then the exact test (test_pairs).
    // Silhouette against silhouette: segment j copied from occluder k (its box, slack and
    // unclipped ends), occluder k2 copied as segment j2 (occ_mirror[k2] = j2) of this range make
    // the pairs (j, k2) and (j2, k): the same four points, the same exact sides (up to the
    // segments' directions). Only the pair with k < k2 is kept; the other's results come from
    // the same sides (mirrored_crossings). The others kept as they are, in their order.
    void find_pairs();
    // The quick reject first, over all pairs without branches (most pairs are rejected, which a
    // branch would mispredict often): the pairs it keeps, with the sides it decided, listed. Then
    // the exact test of the pairs kept, in the same order, and of their mirrored pairs.
    void test_pairs();
    // Where an edge meets another face (the surface passes through itself, or touches itself),
    // inside the clipped segment: no occluder, but the QI may change.
    void split_at_cuts();
    // By segment (a counting sort), then parameter and occluder (an insertion sort of each
    // segment's few splits): the same order whatever the order of the pairs.
    void sort_splits();
    // 3. Per curve: pieces cut at the splits.
    void cut_curves();
    void cut_curve(std::uint32_t ci);
    // Slot P.n made the piece being built, empty, of curve ci.
    void start_piece(std::uint32_t ci) {
        cur = &P.pieces[P.n];
        cur_spans = &P.spans[P.n];
        cur->kind = features.curves[ci].kind;
        cur->qi = 0;
        cur->curve = ci;
        cur->points.clear();
        cur_spans->clear();
    }
    // The piece being built, kept if it has a span and two points (linked to the last across
    // `pending`, if `linked`); then the next one started.
    void emit(std::uint32_t ci) {
        if (!cur_spans->empty() && cur->points.size() >= 2) {
            const std::uint32_t p = P.n;
            if (linked) {
                const std::uint32_t l = std::uint32_t(P.links.size());
                P.links.push_back({p - 1, p});
                for (const Scratch::Pending& c : scratch.pending) {
                    P.link_crossings.push_back({l, c.occluder, c.seg, c.t});
                    scratch.lc_ot.push_back(c.ot);
                }
            }
            ++P.n;
            P.open_slot();
        }
        scratch.pending.clear();
        linked = false;
        start_piece(ci);
    }
    // A closed curve that was not cut at its start vertex: the last piece continues the first (a
    // loop from a junction or cusp back to it is not closed: the QI can change there). Else the
    // curve's ends at vertices (junctions, cusps, ends of open lines), where not clipped.
    void close_curve(std::uint32_t ci, std::span<const ClipSeg> segs, std::uint32_t first_piece, std::size_t first_link,
                     bool split_at_start);
    // The curve's crossings in 3D: the curve's segment in travel order, and the occluder's edge
    // parameter.
    void place_crossings(std::span<const ClipSeg> segs, std::size_t first_lc);
};

void RangeBuild::clip_curves() {
    const std::uint32_t ncurves = c1 - c0;
    const std::vector<ClipSeg>& occ_clip = occ.clip;
    all_segs.clear();
    seg_occ.clear();
    seg_begin.assign(ncurves + 1, 0);
    const double near = camera.near_distance();
    std::size_t edges = 0;
    for (std::uint32_t ci = c0; ci < c1; ++ci) edges += features.curves[ci].edges.size();
    all_segs.reserve(edges);
    seg_occ.reserve(edges);
    // (The curves' edges are scattered over a large mesh, and most curves are short: what an edge
    // reads is prefetched some edges ahead in the curves' edges, across curves, in two levels:
    // its occluder's slot and its vertices 16 edges ahead, then the occluder's record and the
    // vertices' positions and images 8 ahead; no effect on results. The occluder found 8 ahead is
    // kept for the edge's turn: `ahead`, the occluders of the next 8 edges, by index mod 8.)
    const std::span<const std::uint32_t> range_edges = features.curves.edges_of(c0, c1);
    std::size_t at_edge = 0;  // the next edge's index in range_edges (the loop's order)
    std::uint32_t ahead[8];
    for (std::size_t d = 0; d < 8 && d < range_edges.size(); ++d) ahead[d] = occ.find(range_edges[d]);
    for (std::uint32_t ci = c0; ci < c1; ++ci) {
        const FeatureCurve& curve = features.curves[ci];
        const std::size_t first = all_segs.size();
        bool interrupted = false;
        for (std::size_t i = 0; i < curve.edges.size(); ++i) {
            const std::uint32_t k = ahead[at_edge & 7];  // the occluder of this edge, or UINT32_MAX
            if (at_edge + 16 < range_edges.size()) {
                occ.of_edge.prefetch(range_edges[at_edge + 16]);
                __builtin_prefetch(&mesh.edge_vertex[range_edges[at_edge + 16]]);
            }
            if (at_edge + 8 < range_edges.size()) {
                const std::uint32_t e8 = range_edges[at_edge + 8], k8 = occ.find(e8);
                ahead[at_edge & 7] = k8;  // (this edge's slot, read above)
                if (k8 != UINT32_MAX) prefetch_record(&occ_clip[k8]);
                for (const std::uint32_t v : mesh.edge_vertex[e8]) {
                    __builtin_prefetch(&mesh.positions[v]);
                    images.prefetch(v);
                }
            }
            ++at_edge;
            const std::uint32_t e = curve.edges[i], va = curve.vertices[i], vb = curve.vertices[i + 1];
            const bool forward = mesh.edge_vertex[e][0] == va;
            const std::size_t at = all_segs.size();
            ClipSeg& s = all_segs.emplace_back();  // (made in place; reserved: no reallocation)
            if (k != UINT32_MAX && occ_clip[k].kept_both && occ_clip[k].zA >= near && occ_clip[k].zB >= near) {
                s = occ_clip[k];
                if (!forward) {
                    std::swap(s.A, s.B), std::swap(s.a, s.b), std::swap(s.zA, s.zB), std::swap(s.sA, s.sB);
                    std::swap(s.LA, s.LB);
                    s.slack = std::max(images.slack(va), images.slack(vb));  // (clip_edge's order)
                }
                // (read here, while the occluder's record is in cache, not again by the search)
                s.occluder_copy = s.slack == occ_clip[k].slack;
                seg_occ.push_back(k);
            } else if (!clip_edge(camera, near, images, mesh.positions, va, vb, forward ? 0.0 : 1.0, forward ? 1.0 : 0.0,
                                  s)) {
                all_segs.pop_back();
                interrupted = true;
                continue;
            } else {
                seg_occ.push_back(UINT32_MAX);
            }
            s.edge = e;
            // A clipped start also interrupts the curve.
            s.run_start = at == first || interrupted || s.A != mesh.positions[va] ||
                          all_segs[at - 1].B != mesh.positions[va];
            interrupted = s.B != mesh.positions[vb];
        }
        seg_begin[ci - c0 + 1] = std::uint32_t(all_segs.size());
    }
}

void RangeBuild::find_pairs() {
    std::vector<Box2f>& qbox = scratch.qbox;
    std::vector<std::uint64_t>& found = scratch.found;
    qbox.resize(all_segs.size());
    for (std::size_t j = 0; j < all_segs.size(); ++j) {
        const ClipSeg& s = all_segs[j];
        // (a copied occluder's box: outer_box is symmetric in the ends, the slack the same)
        if (s.occluder_copy) {
            qbox[j] = occ.boxes[seg_occ[j]];
            continue;
        }
        qbox[j] = outer_box({s.a, s.b, mesh.edge_vertex[s.edge][0], mesh.edge_vertex[s.edge][1], s.edge, s.slack});
    }
    found.clear();
    grid.pairs(qbox, found, scratch.hits);
    std::vector<std::uint32_t>& occ_mirror = scratch.occ_mirror;
    occ_mirror.assign(occ.segs.size(), UINT32_MAX);
    for (std::uint32_t j = 0; j < all_segs.size() && mirror; ++j)
        if (mirrorable(all_segs[j])) occ_mirror[seg_occ[j]] = j;
    std::size_t n = 0;
    for (std::size_t i = 0; i < found.size(); ++i) {
        const std::uint64_t f = found[i];
        const std::uint32_t j = std::uint32_t(f >> 32), k2 = std::uint32_t(f);
        const std::uint32_t k = seg_occ[j];
        found[n] = f;
        // (j mirrorable: occ_mirror of its occluder is j)
        n += !(k != UINT32_MAX && occ_mirror[k] == j && occ_mirror[k2] != UINT32_MAX && k2 < k);
    }
    found.resize(n);
}

void RangeBuild::test_pairs() {
    const std::vector<Segment2>& occluders = occ.segs;
    const std::vector<ClipSeg>& occ_clip = occ.clip;
    const std::vector<Box2f>& qbox = scratch.qbox;
    const std::vector<std::uint64_t>& found = scratch.found;
    const std::vector<std::uint32_t>& occ_mirror = scratch.occ_mirror;
    const std::uint8_t* o_unclipped = occ.unclipped.data();
    std::vector<Scratch::Kept>& kept = scratch.kept;
    kept.resize(found.size());
    std::size_t nkept = 0;
    for (std::size_t i = 0; i < found.size(); ++i) {
        if (i + 8 < found.size()) prefetch_record(&occluders[std::uint32_t(found[i + 8])]);  // (scattered)
        const std::uint64_t f = found[i];
        const std::uint32_t j = std::uint32_t(f >> 32), k = std::uint32_t(f);
        const ClipSeg& s = all_segs[j];
        const Segment2 q{s.a, s.b, qbox[j].v0, qbox[j].v1, s.edge, s.slack};
        Scratch::Kept& c = kept[nkept];
        c.pair = f;
        nkept += !filter_sides(q, s.unclipped, occluders[k], o_unclipped[k], c.sides);
    }
    for (std::size_t i = 0; i < nkept; ++i) {
        if (i + 4 < nkept) {  // (the occluders are scattered)
            const std::uint32_t k4 = std::uint32_t(kept[i + 4].pair);
            prefetch_record(&occ_clip[k4]);
            __builtin_prefetch(&occ_mirror[k4]);
        }
        const std::uint32_t j = std::uint32_t(kept[i].pair >> 32), k = std::uint32_t(kept[i].pair);
        const ClipSeg& s = all_segs[j];
        const Segment2& o = occluders[k];
        // (pairs sharing a vertex, the curve's own neighbours, are not in `found`)
        const Segment2 q{s.a, s.b, qbox[j].v0, qbox[j].v1, s.edge, s.slack};
        double t[2], ot;
        int exact[4], how;
        const int n = segment_crossings(camera, q, s.in_3d(), o, occ_clip[k].in_3d(), kept[i].sides, t, &ot, exact, &how);
        if (n > 0) {
            if (!(in_curves[o.edge >> 6] >> (o.edge & 63) & 1) || s.edge < o.edge) ++P.crossings;
            for (int h = 0; h < n; ++h) all_splits.push_back({j, t[h], k, ot});
        }
        const std::uint32_t j2 = occ_mirror[k];
        if (j2 == UINT32_MAX || seg_occ[j] == UINT32_MAX || occ_mirror[seg_occ[j]] != j) continue;
        // The mirrored pair (j2, seg_occ[j]), left out of the search.
        const std::uint32_t k1 = seg_occ[j];
        const ClipSeg& s2 = all_segs[j2];
        const Segment2& o1 = occluders[k1];
        const Segment2 q2{s2.a, s2.b, o.v0, o.v1, s2.edge, s2.slack};  // (qbox[j2]'s vertices: o's)
        const int n2 = mirrored_crossings(camera, q2, s2.in_3d(), o1, occ_clip[k1].in_3d(), s.LA == occ_clip[k1].LA,
                                          s2.LA == occ_clip[k].LA, how, exact, t, &ot);
        if (n2 == 0) continue;
        if (s2.edge < o1.edge) ++P.crossings;  // (o1's edge is a curve's: segment j's)
        for (int h = 0; h < n2; ++h) all_splits.push_back({j2, t[h], k1, ot});
    }
}

void RangeBuild::split_at_cuts() {
    if (!cuts || cuts->empty()) return;
    for (std::uint32_t j = 0; j < all_segs.size(); ++j) {
        const ClipSeg& s = all_segs[j];
        auto it = std::lower_bound(cuts->begin(), cuts->end(), EdgeCut{s.edge, -1.0});
        for (; it != cuts->end() && it->edge == s.edge; ++it) {
            const double lo = std::min(s.sA, s.sB), hi = std::max(s.sA, s.sB);
            if (it->s < lo || it->s > hi || s.sA == s.sB) continue;
            const double u = (it->s - s.sA) / (s.sB - s.sA);  // along the 3D segment
            double t = u;
            if (!camera.is_ortho()) {
                const double den = (1.0 - u) * s.zA + u * s.zB;
                t = den > 0.0 ? u * s.zB / den : u;
            }
            all_splits.push_back({j, std::clamp(t, 0.0, 1.0), kNoOccluder});
        }
    }
}

void RangeBuild::sort_splits() {
    std::vector<std::uint32_t>&at = scratch.at, &next = scratch.next;
    at.assign(all_segs.size() + 1, 0);
    for (const Split& sp : all_splits) ++at[sp.seg + 1];
    for (std::size_t j = 0; j < all_segs.size(); ++j) at[j + 1] += at[j];
    std::vector<Split>& sorted = scratch.sorted;
    sorted.resize(all_splits.size());
    next.assign(at.begin(), at.end() - 1);
    for (const Split& sp : all_splits) sorted[next[sp.seg]++] = sp;
    auto before = [](const Split& x, const Split& y) { return x.t != y.t ? x.t < y.t : x.occluder < y.occluder; };
    for (std::size_t j = 0; j < all_segs.size(); ++j) {
        if (at[j + 1] - at[j] > 16) {  // (a long segment crossing many edges)
            std::sort(sorted.begin() + at[j], sorted.begin() + at[j + 1], before);
            continue;
        }
        for (std::uint32_t i = at[j] + 1; i < at[j + 1]; ++i)
            for (std::uint32_t k = i; k > at[j] && before(sorted[k], sorted[k - 1]); --k) std::swap(sorted[k], sorted[k - 1]);
    }
    std::swap(all_splits, sorted);
}

void RangeBuild::cut_curves() {
    scratch.pending.clear();  // crossings at the cut being made / at a closed curve's start
    next_split = 0;
    const std::uint32_t ncurves = c1 - c0;
    P.pieces.reserve(P.n + all_splits.size() + ncurves + 1);
    P.spans.reserve(P.n + all_splits.size() + ncurves + 1);
    P.open_slot();
    cur = &P.pieces[P.n];
    cur_spans = &P.spans[P.n];
    for (std::uint32_t ci = c0; ci < c1; ++ci) {
        // (The storage of the slots the next pieces will fill, each its own block: prefetched.)
        for (std::uint32_t d = 2; d <= 3; ++d)
            if (P.n + d < P.pieces.size()) {
                __builtin_prefetch(P.pieces[P.n + d].points.data(), 1);
                __builtin_prefetch(P.spans[P.n + d].data(), 1);
            }
        if (seg_begin[ci - c0] != seg_begin[ci - c0 + 1]) cut_curve(ci);
    }
}

// Walks the curve's segments, cutting pieces at splits and interruptions. Cuts between two pieces
// become links carrying the crossings made there.
void RangeBuild::cut_curve(std::uint32_t ci) {
    const std::uint32_t sb = seg_begin[ci - c0], se = seg_begin[ci - c0 + 1];
    const std::span<const ClipSeg> segs(all_segs.data() + sb, se - sb);
    std::vector<Split>& splits = scratch.splits;
    splits.clear();
    for (; next_split < all_splits.size() && all_splits[next_split].seg < se; ++next_split) {
        Split sp = all_splits[next_split];
        sp.seg -= sb;
        splits.push_back(sp);
    }
    for (auto& sp : splits)  // a split at a segment's end is the next segment's start
        if (sp.t >= 1.0 && sp.seg + 1 < segs.size() && !segs[sp.seg + 1].run_start) sp = {sp.seg + 1, 0.0, sp.occluder};
    std::sort(splits.begin(), splits.end());

    const std::uint32_t first_piece = P.n;
    const std::size_t first_link = P.links.size(), first_lc = P.link_crossings.size();
    std::vector<Scratch::Pending>&pending = scratch.pending, &wrap = scratch.wrap;
    scratch.lc_ot.clear();
    start_piece(ci);
    linked = false;
    wrap.clear();
    std::size_t k = 0;
    bool split_at_start = false;
    for (std::uint32_t j = 0; j < segs.size(); ++j) {
        const ClipSeg& s = segs[j];
        if (s.run_start) {
            emit(ci);
            cur->points.push_back(s.a);
        }
        double t0 = 0.0;
        double e0 = s.sA + to_3d(camera, s, 0.0) * (s.sB - s.sA);  // edge parameter at t0
        auto add_span = [&](double t1) {
            const double e1 = s.sA + to_3d(camera, s, t1) * (s.sB - s.sA);
            cur_spans->push_back({s.edge, e0, e1});
            cur->points.push_back(s.a + t1 * (s.b - s.a));
            e0 = e1;  // (the next span starts here: t0 = t1)
        };
        for (; k < splits.size() && splits[k].seg == j;) {
            const double t = splits[k].t;
            const std::size_t k0 = k;
            while (k < splits.size() && splits[k].seg == j && splits[k].t == t) ++k;  // all crossings here
            if ((t <= 0.0 && j == 0) || (t >= 1.0 && j + 1 == segs.size())) {
                split_at_start = true;
                for (std::size_t i = k0; i < k; ++i)
                    if (splits[i].occluder != kNoOccluder) wrap.push_back({j, splits[i].occluder, t, splits[i].ot});
            }
            if (t >= 1.0) continue;  // the end of the run: nothing follows
            if (t > t0) add_span(t);
            if (cur_spans->empty()) continue;  // nothing to cut yet (split at the run start)
            emit(ci);
            linked = true;
            for (std::size_t i = k0; i < k; ++i)
                if (splits[i].occluder != kNoOccluder) pending.push_back({j, splits[i].occluder, t, splits[i].ot});
            cur->points.push_back(s.a + t * (s.b - s.a));
            t0 = t;
        }
        add_span(1.0);
    }
    emit(ci);
    close_curve(ci, segs, first_piece, first_link, split_at_start);
    place_crossings(segs, first_lc);
}

void RangeBuild::close_curve(std::uint32_t ci, std::span<const ClipSeg> segs, std::uint32_t first_piece,
                             std::size_t first_link, bool split_at_start) {
    const FeatureCurve& curve = features.curves[ci];
    const std::uint32_t np = P.n - first_piece;
    const bool unbroken = segs.size() == curve.edges.size() &&
                          std::none_of(segs.begin() + 1, segs.end(), [](const ClipSeg& s) { return s.run_start; }) &&
                          segs.back().B == segs.front().A;
    const std::uint32_t last_piece = first_piece + np - 1;
    if (curve.closed && unbroken && np >= 2 && !split_at_start) {
        // The last piece followed by the first: into the last's storage, swapped into the
        // first's slot; the last slot becomes the one being built.
        Piece &first = P.pieces[first_piece], &last = P.pieces[last_piece];
        std::vector<EdgeSpan>&first_spans = P.spans[first_piece], &last_spans = P.spans[last_piece];
        last.points.insert(last.points.end(), first.points.begin() + 1, first.points.end());
        last_spans.insert(last_spans.end(), first_spans.begin(), first_spans.end());
        std::swap(first.points, last.points);
        std::swap(first_spans, last_spans);
        --P.n;
        start_piece(ci);
        for (std::size_t l = first_link; l < P.links.size(); ++l)
            if (P.links[l].after == last_piece) P.links[l].after = first_piece;
    } else if (np >= 1 && curve.closed && unbroken) {
        // Cut at its start: the last piece goes on into the first across those crossings.
        const std::uint32_t l = std::uint32_t(P.links.size());
        P.links.push_back({last_piece, first_piece});
        for (const Scratch::Pending& c : scratch.wrap) {
            P.link_crossings.push_back({l, c.occluder, c.seg, c.t});
            scratch.lc_ot.push_back(c.ot);
        }
    } else if (np >= 1) {
        if (segs.front().A == mesh.positions[curve.vertices.front()])
            P.ends.push_back({first_piece, curve.vertices.front(), curve.edges.front()});
        if (segs.back().B == mesh.positions[curve.vertices.back()])
            P.ends.push_back({last_piece, curve.vertices.back(), curve.edges.back()});
    }
}

void RangeBuild::place_crossings(std::span<const ClipSeg> segs, std::size_t first_lc) {
    const std::vector<ClipSeg>& occ_clip = occ.clip;
    for (std::size_t i = first_lc; i < P.link_crossings.size(); ++i) {
        auto& c = P.link_crossings[i];
        if (i + 2 < P.link_crossings.size()) prefetch_record(&occ_clip[P.link_crossings[i + 2].occluder]);
        const ClipSeg& s = segs[c.seg];
        const ClipSeg& o = occ_clip[c.occluder];
        c.c1 = s.A;
        c.c2 = s.B;
        // (found by the search, unless the split moved to the next segment's start or the
        // images are collinear)
        double ot = scratch.lc_ot[i - first_lc];
        if (std::isnan(ot)) {
            double to[2];
            const Segment2 q{s.a, s.b, mesh.edge_vertex[s.edge][0], mesh.edge_vertex[s.edge][1], s.edge, s.slack};
            ot = segment_crossings(camera, occ.segs[c.occluder], o.in_3d(), q, s.in_3d(), to) > 0 ? to[0] : 0.5;
        }
        c.occluder_s = o.sA + to_3d(camera, o, ot) * (o.sB - o.sA);
        c.occluder_edge = occ.segs[c.occluder].edge;
    }
}

void build_range(const MeshTopology& mesh, const Features& features, const Camera& camera,
                 const std::vector<EdgeCut>* cuts, const VertexImages& images, const OccluderSet& occ,
                 const std::vector<std::uint64_t>& in_curves, const BoxPairs& grid, std::uint32_t c0, std::uint32_t c1,
                 bool mirror, Scratch& scratch, Part& P) {
    RangeBuild{mesh, features, camera, cuts, images, occ, in_curves, grid, c0, c1, mirror, scratch, P}.run();
}

}  // namespace

void PieceGraph::truncate(std::size_t k) {
    for (std::size_t i = k; i < curves.pieces.size(); ++i) {
        spare_pieces_.push_back(std::move(curves.pieces[i]));
        spare_spans_.push_back(std::move(curves.spans[i]));
    }
    curves.pieces.resize(std::min(k, curves.pieces.size()));
    curves.spans.resize(curves.pieces.size());
}

PieceGraph build_pieces(const MeshTopology& mesh, const Features& features, const Camera& camera,
                        const std::vector<EdgeCut>* cuts, int threads,
                        std::size_t parallel_edges) {
    PieceGraph g;
    build_pieces(g, mesh, features, camera, cuts, threads, parallel_edges);
    g.curves.pieces.shrink_to_fit();
    return g;
}

namespace {

// Where clip_occluder_range writes: the four arrays' slots from one index on.
struct OccluderSlots {
    Segment2* occluders;
    ClipSeg* clip;
    Box2f* boxes;
    std::uint8_t* unclipped;
};

// Occluding edges [j0, j1) of edge_at (silhouettes, then borders), each clipped in place, into
// the slots from `out` on; returns how many were written (an edge with nothing left in front of
// the near plane writes none). Reads `images`, and fills it where not made yet.
template <class EdgeAt>
std::size_t clip_occluder_range(const MeshTopology& mesh, const Camera& camera, double occluder_near, const VertexImages& images,
                                EdgeAt&& edge_at, std::size_t j0, std::size_t j1, const OccluderSlots& out) {
    std::size_t n = 0;
    for (std::size_t j = j0; j < j1; ++j) {
        const std::uint32_t e = edge_at(j);
        // (The edges are scattered over a large mesh: their vertices 16 edges ahead, then those
        // vertices' positions and images 8 ahead, prefetched; no effect on results.)
        if (j + 16 < j1) __builtin_prefetch(&mesh.edge_vertex[edge_at(j + 16)]);
        if (j + 8 < j1) {
            const auto& ev = mesh.edge_vertex[edge_at(j + 8)];
            __builtin_prefetch(&mesh.positions[ev[0]]);
            __builtin_prefetch(&mesh.positions[ev[1]]);
            images.prefetch(ev[0]);
            images.prefetch(ev[1]);
        }
        const auto [v0, v1] = mesh.edge_vertex[e];
        ClipSeg& s = out.clip[n];
        if (!clip_edge(camera, occluder_near, images, mesh.positions, v0, v1, 0.0, 1.0, s)) continue;
        out.occluders[n] = {s.a, s.b, v0, v1, e, s.slack};
        out.boxes[n] = outer_box(out.occluders[n]);
        out.unclipped[n] = s.unclipped;
        ++n;
    }
    return n;
}

// Occluding edges in the image: silhouettes and borders, into g.occluders, with their clipped
// records, boxes (the crossing search bins them) and whether each is unclipped, in the same pass
// (each clipped in place). QI counts the layers between a point and the eye (DESIGN.md), so the
// near plane clips the curves drawn, not the occluders: those are clipped only where they could
// not be projected, at the default near plane (or the camera's, if nearer). A large view's edges
// are split among up to `threads` threads (ranges of at least 4000 edges), each writing its own
// slots of the four arrays.
void clip_occluders(PieceGraph& g, const MeshTopology& mesh, const Features& features, const Camera& camera,
                    Scratch& scratch, int threads) {
    const double occluder_near = std::min(camera.near_distance(), default_near(mesh));
    const auto& sil = features.silhouette_edges;
    const auto& border = features.border_edges;
    const std::size_t ns = sil.size(), most = ns + border.size();
    auto edge_at = [&](std::size_t j) { return j < ns ? sil[j] : border[j - ns]; };
    // (A slot for every edge; the arrays keep their size from the last view, so only growth is
    // filled before it is written.)
    g.occluders.resize(most);
    scratch.occ_clip.resize(most);
    scratch.obox.resize(most);
    scratch.occ_unclipped.resize(most);
    auto slots_from = [&](std::size_t j) {
        return OccluderSlots{g.occluders.data() + j, scratch.occ_clip.data() + j, scratch.obox.data() + j,
                             scratch.occ_unclipped.data() + j};
    };
    auto set_size = [&](std::size_t n) {
        g.occluders.resize(n), scratch.occ_clip.resize(n), scratch.obox.resize(n), scratch.occ_unclipped.resize(n);
    };
    const int parts = threads > 1 && most >= 8000 ? int(std::min<std::size_t>(std::size_t(threads), most / 4000)) : 1;
    if (parts < 2) {
        set_size(clip_occluder_range(mesh, camera, occluder_near, g.images, edge_at, 0, most, slots_from(0)));
        return;
    }
    // The images of the edges' vertices first, in two passes so that no thread reads every edge:
    // each part marks the vertices of its own edges in a bit set of its own; then each part
    // projects the vertices marked by any part in its own range of 64-vertex words (a thread
    // writes only words of its own). The ranges then only read the images.
    const VertexImages& images = g.images;
    WorkerTeam& team = g.team();
    thread_local std::vector<std::vector<std::uint64_t>> marks_of_this_thread;  // (named here: the workers' own would differ)
    std::vector<std::vector<std::uint64_t>>& marks = marks_of_this_thread;
    if (marks.size() < std::size_t(parts)) marks.resize(std::size_t(parts));
    const std::size_t words = mesh.vertex_count() / 64 + 1;
    auto first_edge = [&](int i) { return most * std::size_t(i) / std::size_t(parts); };
    team.run(parts, [&](int i) {
        std::vector<std::uint64_t>& m = marks[std::size_t(i)];
        m.assign(words, 0);
        for (std::size_t j = first_edge(i), j1 = first_edge(i + 1); j < j1; ++j) {
            if (j + 16 < j1) __builtin_prefetch(&mesh.edge_vertex[edge_at(j + 16)]);
            for (const std::uint32_t v : mesh.edge_vertex[edge_at(j)]) m[v >> 6] |= std::uint64_t(1) << (v & 63);
        }
    });
    team.run(parts, [&](int i) {
        for (std::size_t w = words * std::size_t(i) / std::size_t(parts); w < words * std::size_t(i + 1) / std::size_t(parts); ++w) {
            std::uint64_t bits = 0;
            for (int k = 0; k < parts; ++k) bits |= marks[std::size_t(k)][w];
            for (; bits; bits &= bits - 1) images.slack(std::uint32_t(w * 64 + std::size_t(std::countr_zero(bits))));
        }
    });
    // Each range into its own edges' slots; the slots of edges with nothing left closed up after.
    std::vector<std::size_t> written(std::size_t(parts), 0);
    team.run(parts, [&](int i) {
        written[std::size_t(i)] =
            clip_occluder_range(mesh, camera, occluder_near, images, edge_at, first_edge(i), first_edge(i + 1), slots_from(first_edge(i)));
    });
    std::size_t n = written[0];
    for (int i = 1; i < parts; ++i) {
        const std::size_t from = first_edge(i), count = written[std::size_t(i)];
        if (n != from) {
            std::move(g.occluders.begin() + from, g.occluders.begin() + from + count, g.occluders.begin() + n);
            std::move(scratch.occ_clip.begin() + from, scratch.occ_clip.begin() + from + count, scratch.occ_clip.begin() + n);
            std::move(scratch.obox.begin() + from, scratch.obox.begin() + from + count, scratch.obox.begin() + n);
            std::move(scratch.occ_unclipped.begin() + from, scratch.occ_unclipped.begin() + from + count,
                      scratch.occ_unclipped.begin() + n);
        }
        n += count;
    }
    set_size(n);
}

// The extreme points of the occluders' image (the bounding-box rule of the fast method).
void find_extreme_vertices(PieceGraph& g) {
    g.extreme_vertices.fill(UINT32_MAX);
    if (g.immersive) return;
    double ext[4] = {1e300, -1e300, 1e300, -1e300};
    for (const Segment2& o : g.occluders)
        for (int end = 0; end < 2; ++end) {
            const glm::dvec2 p = end ? o.b : o.a;
            const std::uint32_t v = end ? o.v1 : o.v0;
            const double val[4] = {p.x, p.x, p.y, p.y};
            for (int k = 0; k < 4; ++k)
                if (k % 2 == 0 ? val[k] < ext[k] : val[k] > ext[k]) ext[k] = val[k], g.extreme_vertices[k] = v;
        }
}

// Appends ranges 1.. (their output in `rest`, others[i - 1]) after range 0's (in `first`), in
// range order, their indices shifted; their pieces swapped into the graph's slots (each side
// keeps storage). The slots and the arrays' sizes are made first; then the copies, split among
// the team in equal slices of each array (the outcome does not depend on the slices).
void append_ranges(PieceGraph& g, std::vector<std::unique_ptr<Scratch>>& rest, const std::vector<Part>& others, int parts,
                   Part& first) {
    // Where each range's pieces, links, link crossings and ends start (range 0's first).
    std::vector<std::size_t> piece_at(std::size_t(parts) + 1), link_at(piece_at), lc_at(piece_at), end_at(piece_at);
    piece_at[1] = first.n, link_at[1] = g.links.size(), lc_at[1] = g.link_crossings.size(), end_at[1] = g.ends.size();
    for (int i = 1; i < parts; ++i) {
        const Scratch::Parts& p = rest[std::size_t(i - 1)]->parts;
        const std::size_t k = std::size_t(i);
        piece_at[k + 1] = piece_at[k] + others[k - 1].n;
        link_at[k + 1] = link_at[k] + p.links.size();
        lc_at[k + 1] = lc_at[k] + p.link_crossings.size();
        end_at[k + 1] = end_at[k] + p.ends.size();
        first.crossings += others[k - 1].crossings;
    }
    VisibleCurves& out = g.curves;
    const std::size_t total = piece_at[std::size_t(parts)];
    out.pieces.reserve(total + 1);
    out.spans.reserve(total + 1);
    while (first.n < total) {
        first.open_slot();
        ++first.n;
    }
    g.links.resize(link_at[std::size_t(parts)]);
    g.link_crossings.resize(lc_at[std::size_t(parts)]);
    g.ends.resize(end_at[std::size_t(parts)]);
    // fn(i, k, j) for the items j of this slice of [at[1], at[parts]): item k of range i.
    auto slice = [parts](const std::vector<std::size_t>& at, int t, int slices, auto&& fn) {
        const std::size_t n = at[std::size_t(parts)] - at[1];
        const std::size_t j0 = at[1] + n * std::size_t(t) / std::size_t(slices), j1 = at[1] + n * std::size_t(t + 1) / std::size_t(slices);
        for (int i = 1; i < parts; ++i) {
            const std::size_t lo = std::max(j0, at[std::size_t(i)]), hi = std::min(j1, at[std::size_t(i) + 1]);
            for (std::size_t j = lo; j < hi; ++j) fn(std::size_t(i), j - at[std::size_t(i)], j);
        }
    };
    g.team().run(parts, [&](int t) {
        slice(piece_at, t, parts, [&](std::size_t i, std::size_t k, std::size_t j) {
            Scratch::Parts& p = rest[i - 1]->parts;
            std::swap(out.pieces[j], p.pieces[k]);
            std::swap(out.spans[j], p.spans[k]);
        });
        slice(link_at, t, parts, [&](std::size_t i, std::size_t k, std::size_t j) {
            const PieceGraph::Link& l = rest[i - 1]->parts.links[k];
            g.links[j] = {l.before + std::uint32_t(piece_at[i]), l.after + std::uint32_t(piece_at[i])};
        });
        slice(lc_at, t, parts, [&](std::size_t i, std::size_t k, std::size_t j) {
            g.link_crossings[j] = rest[i - 1]->parts.link_crossings[k];
            g.link_crossings[j].link += std::uint32_t(link_at[i]);
        });
        slice(end_at, t, parts, [&](std::size_t i, std::size_t k, std::size_t j) {
            const PieceGraph::End& e = rest[i - 1]->parts.ends[k];
            g.ends[j] = {e.piece + std::uint32_t(piece_at[i]), e.vertex, e.edge};
        });
    });
}

// build_range of the curves in `parts` ranges of about equal edge counts (two: the calling
// thread's share fitted to the last views' times, SplitShare), range i on the graph's team thread
// i; the other ranges' pieces and links appended after the first's (in `first`) in range order,
// so the pieces do not depend on the split.
void build_ranges(PieceGraph& g, const MeshTopology& mesh, const Features& features, const Camera& camera,
                  const std::vector<EdgeCut>* cuts, const OccluderSet& occ, const std::vector<std::uint64_t>& in_curves,
                  const BoxPairs& grid, std::size_t total_edges, bool mirror_pairs, int parts, Scratch& scratch,
                  Part& first) {
    const std::uint32_t ncurves = std::uint32_t(features.curves.size());
    // The ranges' first curves. Each range holds a curve at least: a range takes one before its
    // target is compared, and leaves one for each range after it. (The helper's side of two is
    // slower per edge: SplitShare, visibility.hpp; more ranges get equal shares.)
    std::vector<std::uint32_t> cut(std::size_t(parts) + 1, ncurves);
    cut[0] = 0;
    std::uint32_t c = 0;
    std::size_t edges = 0;
    for (int i = 1; i < parts; ++i) {
        const double target = parts == 2 ? g.curves_split.share * double(total_edges)
                                         : double(total_edges) * double(i) / double(parts);
        do edges += features.curves[c++].edges.size();
        while (c + std::uint32_t(parts - i) < ncurves && double(edges) < target);
        cut[std::size_t(i)] = c;
    }
    const std::size_t first_edges = parts == 2 ? edges : 0;
    for (const auto& curve : features.curves)  // (every image the ranges read, made before they run)
        for (std::uint32_t v : curve.vertices) g.images.slack(v);
    // (the other ranges' arrays belong to this thread, kept from view to view; the workers are
    // given them by reference: a thread_local named inside one would be the worker's own)
    thread_local std::vector<std::unique_ptr<Scratch>> scratch_of_this_thread;
    std::vector<std::unique_ptr<Scratch>>& scratch_others = scratch_of_this_thread;
    while (scratch_others.size() < std::size_t(parts - 1)) scratch_others.push_back(std::make_unique<Scratch>());
    std::vector<Part> others;
    others.reserve(std::size_t(parts - 1));
    for (int i = 1; i < parts; ++i) {
        Scratch::Parts& p = scratch_others[std::size_t(i - 1)]->parts;
        p.clear();
        others.push_back(Part{p.pieces, p.spans, p.links, p.link_crossings, p.ends});  // (its slots kept by p)
    }
    std::vector<double> seconds(std::size_t(parts), 0.0);
    g.team().run(parts, [&](int i) {
        const auto t0 = StageClock::now();
        const std::uint32_t c0 = cut[std::size_t(i)], c1 = cut[std::size_t(i) + 1];
        if (i == 0)
            build_range(mesh, features, camera, cuts, g.images, occ, in_curves, grid, c0, c1, mirror_pairs, scratch, first);
        else
            build_range(mesh, features, camera, cuts, g.images, occ, in_curves, grid, c0, c1, mirror_pairs,
                        *scratch_others[std::size_t(i - 1)], others[std::size_t(i - 1)]);
        seconds[std::size_t(i)] = seconds_since(t0);
    });
    if (parts == 2) g.curves_split.fit(double(first_edges) / double(total_edges), seconds[0], seconds[1]);
    append_ranges(g, scratch_others, others, parts, first);
}

// build_pieces' working arrays of the calling thread, kept from view to view (no allocation per
// view once they are large enough); start_occluders hands them to the helper thread.
Scratch& this_thread_scratch() {
    thread_local Scratch scratch;
    return scratch;
}

// Every camera parameter the pieces depend on.
bool same_camera(const Camera& a, const Camera& b) {
    return a.eye() == b.eye() && a.target() == b.target() && a.up() == b.up() && a.fov_deg() == b.fov_deg() &&
           a.is_ortho() == b.is_ortho() && a.ortho_height() == b.ortho_height() && a.width() == b.width() &&
           a.height() == b.height() && a.near_distance() == b.near_distance();
}

// build_pieces' first part: the previous view's links and crossings cleared, the occluders in the
// image, clipped, and their extreme points.
void begin_view(PieceGraph& g, const MeshTopology& mesh, const Features& features, const Camera& camera,
                Scratch& scratch, int threads) {
    VisibleCurves& out = g.curves;
    // Everything of the previous view goes; the pieces' slots are refilled in place by build_pieces.
    out.crossings = 0;
    out.ray_tests = 0;
    g.links.clear();
    g.link_crossings.clear();
    g.ends.clear();
    g.immersive = geometry_behind_near(mesh, camera);
    g.images.reset(mesh, camera);
    clip_occluders(g, mesh, features, camera, scratch, threads);
    g.image_size = glm::dvec2(camera.width(), camera.height());
    find_extreme_vertices(g);
}

}  // namespace

void start_occluders(PieceGraph& g, const MeshTopology& mesh, const Features& features, const Camera& camera) {
    if (g.occluders_job_.valid()) g.occluders_job_.get();  // (a job whose build never came)
    g.grid_built_ = false;
    g.occluders_features_ = &features;
    g.occluders_camera_ = camera;
    Scratch& scratch = this_thread_scratch();
    // (one part: the helper cannot hand parts to the team it belongs to)
    g.occluders_job_ = g.helper().post([&g, &mesh, &features, camera, &scratch] {
        begin_view(g, mesh, features, camera, scratch, 1);
    });
}

void build_pieces(PieceGraph& g, const MeshTopology& mesh, const Features& features, const Camera& camera,
                  const std::vector<EdgeCut>* cuts, int threads, std::size_t parallel_edges, bool mirror_pairs) {
    VisibleCurves& out = g.curves;
    Scratch& scratch = this_thread_scratch();
    // The occluders started ahead for this view, else made here.
    bool started = false;
    if (g.occluders_job_.valid()) {
        g.occluders_job_.get();
        started = g.occluders_features_ == &features && same_camera(g.occluders_camera_, camera);
    }
    g.occluders_features_ = nullptr;
    g.grid_built_ = false;
    if (!started) begin_view(g, mesh, features, camera, scratch, threads);

    std::vector<std::uint64_t>& in_curves = scratch.in_curves;  // a bit per edge
    in_curves.assign(mesh.edge_count() / 64 + 1, 0);
    for (const auto& c : features.curves)
        for (std::uint32_t e : c.edges) in_curves[e >> 6] |= std::uint64_t(1) << (e & 63);

    // The occluders binned once for the crossing search of every range.
    BoxPairs& grid = scratch.grid;
    // (split from 8000 boxes, 4000 a part at least, as the occluders' clipping)
    const std::size_t nbox = scratch.obox.size();
    const int bin_parts = threads > 1 && nbox >= 8000 ? int(std::min<std::size_t>(std::size_t(threads), nbox / 4000)) : 1;
    grid.prepare(scratch.obox, camera.width(), camera.height(), &g.team(), bin_parts);
    // The occluder of each silhouette or border edge (curve segments copy its clipping).
    EdgeOccluders& occ_of_edge = scratch.occ_of_edge;
    occ_of_edge.build(g.occluders);
    const OccluderSet occ{g.occluders, scratch.occ_clip, scratch.obox, occ_of_edge, scratch.occ_unclipped};

    // The curves, in one range or (large views, threads > 1) up to `threads` of about equal edge
    // counts, each on its own thread; their pieces and links are appended in range order.
    const std::uint32_t ncurves = std::uint32_t(features.curves.size());
    std::size_t total_edges = 0;
    for (const auto& c : features.curves) total_edges += c.edges.size();
    out.spans.resize(out.pieces.size());  // (slots are pairs)
    Part first{out.pieces, out.spans, g.links, g.link_crossings, g.ends, &g.spare_pieces_, &g.spare_spans_};
    // (small: a thread costs more; a range of at least parallel_edges / 2 edges)
    const std::size_t by_edges = total_edges / std::max<std::size_t>(parallel_edges / 2, 1);
    const int parts = total_edges < parallel_edges ? 1 : int(std::min<std::size_t>({std::size_t(std::max(threads, 1)), ncurves, by_edges}));
    if (parts < 2)
        build_range(mesh, features, camera, cuts, g.images, occ, in_curves, grid, 0, ncurves, mirror_pairs, scratch, first);
    else
        build_ranges(g, mesh, features, camera, cuts, occ, in_curves, grid, total_edges, mirror_pairs, parts, scratch, first);
    out.crossings = first.crossings;
    g.truncate(first.n);  // (the slots after the pieces: kept as spare storage)
}

PieceProbe probe_point(const MeshTopology& mesh, const Camera& camera, const Piece& piece,
                       const std::vector<EdgeSpan>& spans) {
    // The middle of the piece's longest stretch in the image.
    const auto& pts = piece.points;
    std::size_t best = 0;
    double best_len = -1.0;
    for (std::size_t i = 0; i < spans.size(); ++i) {
        const double len = glm::length(pts[i + 1] - pts[i]);
        if (len > best_len) {
            best_len = len;
            best = i;
        }
    }
    // The image midpoint of that stretch, found on the mesh edge (perspective-correct).
    const EdgeSpan& sp = spans[best];
    const auto [v0, v1] = mesh.edge_vertex[sp.edge];
    const glm::dvec3 E0 = mesh.positions[v0], E1 = mesh.positions[v1];
    const glm::dvec3 P0 = E0 + sp.s0 * (E1 - E0), P1 = E0 + sp.s1 * (E1 - E0);
    double u = 0.5;
    if (!camera.is_ortho()) {
        const double z0 = camera.depth(P0), z1 = camera.depth(P1);
        u = 0.5 * z0 / (0.5 * z1 + 0.5 * z0);
    }
    return {P0 + u * (P1 - P0), 0.5 * (pts[best] + pts[best + 1]), sp.edge};
}

int qi_by_ray(const MeshTopology& mesh, const Camera& camera, const RayCaster& rays, const Piece& piece,
              const std::vector<EdgeSpan>& spans) {
    const PieceProbe q = probe_point(mesh, camera, piece, spans);
    const auto [f0, f1] = mesh.edge_face[q.edge];
    return rays.count_layers(camera.ray_origin(q.P), q.P, f0, f1);
}

VisibleCurves compute_visibility(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                 const RayCaster& rays, const std::vector<EdgeCut>* cuts) {
    const auto t0 = StageClock::now();
    PieceGraph g = build_pieces(mesh, features, camera, cuts);
    VisibleCurves& out = g.curves;  // the reference: one ray test per piece
    out.seconds_pieces = seconds_since(t0);
    const auto t1 = StageClock::now();
    for (std::size_t p = 0; p < out.pieces.size(); ++p) {
        out.pieces[p].qi = qi_by_ray(mesh, camera, rays, out.pieces[p], out.spans[p]);
        ++out.ray_tests;
    }
    out.seconds_ray_tests = seconds_since(t1);
    return std::move(g.curves);
}

}  // namespace inkline
