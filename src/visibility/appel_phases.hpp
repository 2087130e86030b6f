// The phases of assign_qi_appel (appel.hpp) as a type that owns the propagation's state, so that
// each phase reads, and is tested (tests/test_appel_phases.cpp), on its own. Internal to
// visibility/: assign_qi_appel is the interface; this header is for it and the tests.
//
// The nodes of the propagation are the view's pieces [0, np), then one per vertex where curves
// end [np, nn). A union-find forest with offsets records the QI differences between nodes; its
// sets are the clusters; each cluster's base QI is raised by the rules below (phases in the order
// run() calls them) until it is decided (kFixed), proved contradictory (kInconsistent: the
// reference method decides its pieces) or still only bounded below (kBound).
// The state is public: the tests set up and read a phase's input and output directly.
#pragma once
#include <cstdint>
#include <functional>
#include <future>
#include <utility>
#include <vector>

#include "visibility/appel.hpp"

namespace inkline {

// Weighted union-find: value(x) = value(find(x)) + offset(x); unite(a, b, d) records
// value(b) - value(a) = d and reports a contradiction with what is already known. Union by size
// (the root of a set is arbitrary: only differences of values within a set have meaning).
class OffsetForest {
public:
    OffsetForest() = default;
    explicit OffsetForest(std::size_t n) { reset(n); }
    // n nodes, each its own set.
    void reset(std::size_t n) {
        parent_.resize(n), diff_.assign(n, 0), size_.assign(n, 1);
        for (std::size_t i = 0; i < n; ++i) parent_[i] = std::uint32_t(i);
    }
    // The root of x, and offset = value(x) - value(root).
    std::uint32_t find(std::uint32_t x, int& offset) {
        std::uint32_t r = x;
        int d = 0;
        while (parent_[r] != r) d += diff_[r], r = parent_[r];
        offset = d;
        // path compression, keeping offsets relative to the root
        while (parent_[x] != r) {
            const std::uint32_t next = parent_[x];
            const int dx = diff_[x];
            parent_[x] = r;
            diff_[x] = d;
            d -= dx;
            x = next;
        }
        return r;
    }
    bool unite(std::uint32_t a, std::uint32_t b, int d) {
        int oa, ob;
        const std::uint32_t ra = find(a, oa), rb = find(b, ob);
        if (ra == rb) return ob - oa == d;
        // value(b) = value(a) + d  =>  value(rb) = value(ra) + oa + d - ob
        if (size_[ra] >= size_[rb]) {
            parent_[rb] = ra;
            diff_[rb] = oa + d - ob;
            size_[ra] += size_[rb];
        } else {
            parent_[ra] = rb;
            diff_[ra] = ob - d - oa;
            size_[rb] += size_[ra];
        }
        return true;
    }

private:
    std::vector<std::uint32_t> parent_;
    std::vector<int> diff_;
    std::vector<std::uint32_t> size_;
};

// What a walk (section 4.4) proved about its point.
enum class Walk { Visible, Occluded, Failed };

struct AppelPropagation {
    enum ClusterState : std::uint8_t { kBound = 0, kFixed = 1, kInconsistent = 2 };
    // A crossing that changes QI (delta != 0), compactly: what the constraints between clusters
    // need of it (a crossing record is ~100 bytes; these are read several times).
    struct Occluding {
        std::uint32_t edge, link;
        double s;  // where on the occluder's edge
    };
    // A piece's span on the edge of an occluder of `occluding`.
    struct EdgePiece {
        std::uint32_t piece;
        double s0, s1;  // s0 <= s1
    };

    AppelPropagation(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                     const std::function<const RayCaster&()>& ray_index, PieceGraph& graph, const AppelOptions& options);

    // Every phase in order; sets every piece's qi.
    AppelStats run();

    // Geometry around the camera: propagation has no base; every piece by the reference method.
    void ray_test_all();
    // Nodes: pieces, then one per vertex where curves end. The ends sorted by vertex (their index
    // in the low bits) give the vertex nodes in increasing vertex order. Resets the forest.
    void order_vertex_nodes();
    // Pieces on faces that cut through other faces: the QI can change inside them unseen, so they
    // take no part in propagation (each gets its own ray test).
    void mark_pierced();
    // Along curves: the change of QI behind each occluder in front (each crossing's delta, on two
    // threads for a large view), summed per link in order; the crossings that change QI listed.
    void crossing_deltas();
    // Each link unites its two pieces with the link's change of QI.
    void unite_along_curves();
    // At vertices: QI near the vertex on each edge = QI of the vertex + local occlusion. All ends
    // at one vertex share its ring of faces. The local occlusion of every end first (per vertex
    // group; on two threads for a large view), then the unions in order. A face around v seen
    // exactly edge-on (the eye in its plane: a non-generic view) leaves the local occlusion at v
    // undefined; the pieces ending at v take the reference ray test (tests/test_extremes.cpp:
    // EyeOnAnEdgeLine, OrthographicAlongOneSide).
    void unite_at_vertices();
    // Its two steps: the local occlusion of every end (in end_order), then the unions.
    void local_occlusion_at_ends(std::vector<int>& end_occlusion) const;
    void unite_ends(const std::vector<int>& end_occlusion);
    // Clusters: the forest's sets numbered in node order, each node's offset from its root; the
    // base of each is its lower bound (no QI below 0); contradictions and pierced pieces make
    // their cluster inconsistent.
    void form_clusters();
    // Bounding-box rule: the extreme points of all occluding edges are visible. The same pass over
    // the spans collects those on occluder edges of crossings that change QI (on_edge, by_edge),
    // for the constraints between clusters.
    void apply_bounding_box_rule();
    // The same with `beside` (work that reads and writes none of the rule's pass's data: the
    // unions at vertices and form_clusters) run on the calling thread beside the pass, before
    // the rule's fixes.
    void bounding_box_rule_beside(const std::function<void()>& beside);
    // Parity on closed surfaces: front-facing (convex) silhouettes even, back-facing odd. It holds
    // where the surface bounds a solid: a point on a front face is entered from outside, so an
    // even number of layers lie in front of it. Where the surface passes through itself, a part
    // of it lies inside another, and there the count is odd: not only on the pierced faces (whose
    // pieces take no part in propagation) but on every face inside the other part. So a mesh with
    // pierced faces gets no parity (steps of 1 in every raise; the pieces it gave wrong:
    // bench/results/visibility.md). Flags passed all clear keep the rule.
    void apply_parity();
    // The occluder piece of each crossing that changes QI (the piece nearest to the crossing's
    // parameter on the occluder's edge: it lies in it, up to rounding; among equally near ones,
    // the one starting first, then the lowest piece), and the constraints between clusters:
    // (occluder piece, link) pairs not inside one cluster.
    void match_occluders();
    // A large view's occluder grid (what the walks query) built on the first worker while the
    // serial phases from match_occluders to survey_bounded run here; walk() waits for it.
    void start_occluder_grid();
    // Constraints between clusters: behind an occluder of QI n, a curve has QI >= n on both
    // sides. Each side is raised in its own cluster: a side in another cluster than the other
    // side (across a link not united) must not raise this one (raising by the other side's
    // deficit repeated every round: pieces shown hidden that rays show visible, on bones and
    // elephant-with-holes). Raises only go up and are bounded by consistent data; the round limit
    // guards against contradictory input from non-generic views.
    void raise_by_constraints();
    // The constraints whose occluder is in a bounded cluster and whose link is inside one
    // cluster: what bound_above reads.
    void open_upper_bounds();
    // Upper bounds from decided clusters: the occluder's QI at a crossing is at most the QI of
    // the curve behind it on its nearer side (the same constraint read the other way), so a
    // bounded cluster passing in front of a decided one is bounded above too; where that bound
    // leaves only its lower bound (parity: the next value up is 2 away), the cluster is decided
    // without a walk or a ray test. An upper bound below the lower bound contradicts the
    // offsets: the reference method decides that cluster. Decided clusters bound others in turn.
    // Run before the walks, and again after them (from the clusters the walks decided).
    void bound_above();
    // Per bounded cluster: whether it has a piece, its lowest piece value, and its longest piece
    // at QI 0 (where a walk starts).
    void survey_bounded();
    // Walking (section 4.4) for clusters that may be visible: a point of QI 0 proved visible
    // fixes the cluster; proved hidden raises its bound. The walks are independent: made first
    // (on up to `threads` threads from 8 walks on, each thread taking the next walk not yet taken: walks
    // differ in cost by orders of magnitude, so halves of the list would leave one thread
    // waiting; bench/results/visibility.md, eighteenth session), then applied in cluster order.
    void walk();
    // What is still unknown: a ray test at the longest piece of the cluster (the first of
    // equals); totally occluded clusters only when hidden lines are drawn exactly.
    void ray_test_rest();
    // A negative value proves the cluster's offsets wrong (the surface is not embedded there, or
    // the view is degenerate: a crease at QI -2 found by fuzzing): the reference method decides
    // its pieces. Sets every piece's qi.
    void settle();

    // QI of node x (a piece or a vertex) from its cluster's base.
    int value(std::uint32_t x) const { return base[comp[x]] + off[x]; }
    // The bounding-box rule at node x: its value is `qi`.
    void fix(std::uint32_t x, int qi);
    // QI of piece p by a ray test (counted and timed).
    int ray_qi(std::uint32_t p);
    // Node of end vertex v (one of verts).
    std::uint32_t vertex_node(std::uint32_t v) const;

    const MeshTopology& mesh;
    const Camera& camera;
    const FaceFacing& face_front;
    const std::function<const RayCaster&()>& ray_index;
    PieceGraph& graph;
    const AppelOptions& options;
    const RayCaster* rays = nullptr;  // (made on the first ray test)
    AppelStats st;
    std::uint32_t np = 0, nn = 0;  // pieces; nodes
    std::size_t nc = 0;            // clusters
    int threads = 1;  // AppelOptions::threads: the split phases' parts at most
    bool parity = false;  // apply_parity's rule holds (steps of 2 in every raise)

    std::vector<std::uint64_t> end_order;  // graph.ends sorted by vertex: vertex << 32 | end
    std::vector<std::uint64_t> sort_tmp;
    std::vector<std::uint32_t> verts;  // the end vertices, increasing: node np + i is verts[i]
    OffsetForest forest;
    std::vector<std::uint8_t> bad;      // per node: a contradiction recorded there
    std::vector<std::uint8_t> pierced;  // per piece: on a self-intersecting face, or ends edge-on
    std::vector<int> link_delta;        // per link: its change of QI
    std::vector<std::int8_t> parity_of_piece;  // apply_parity: per piece, the parity of base it wants
    std::vector<Occluding> occluding;   // in crossing order
    std::vector<std::uint32_t> comp;    // per node: its cluster
    std::vector<int> off;               // per node: value - cluster base
    std::vector<std::uint8_t> state;    // per cluster (ClusterState)
    std::vector<int> base;              // per cluster
    std::vector<EdgePiece> on_edge;
    std::vector<std::uint64_t> by_edge;  // edge << 32 | index in on_edge
    std::vector<std::pair<std::uint32_t, std::uint32_t>> constraints;  // (occluder piece, link)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> open;         // (bound_above's)
    std::vector<int> upper;              // per cluster (bound_above's, INT_MAX between rounds)
    std::vector<std::uint32_t> touched;  // (bound_above's)
    std::vector<std::uint8_t> has_piece;  // per cluster, bounded: survey_bounded's
    std::vector<int> min_piece;
    std::vector<std::uint32_t> zero;  // (UINT32_MAX: none at QI 0)
    std::future<void> grid_ready;  // start_occluder_grid's build (valid until walk() waits)
};

}  // namespace inkline
