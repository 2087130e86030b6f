// Feature lines for one view. Takes MeshTopology + Camera; gives per-face facing, the
// silhouette/border/crease edges, the cusp vertices (three cases of Markosian et al. 97,
// Definition 3), and the edges chained into curves that stop at junctions and cusps.
// Two silhouette finders behind one interface (SilhouetteFinder): the exhaustive scan (the
// reference) and the randomized seed-and-seek search with frame coherence (section 4.1).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "features/facing.hpp"
#include "model/topology.hpp"

namespace inkline {

struct FeatureOptions {
    bool kinds[kLineKindCount] = {true, true, true};  // indexed by LineKind: which curves to chain
    // Intersection lines (where surfaces cross): not chained per view but built once per model
    // (Model::intersection_curves); the switch lives here with the other kinds a view draws.
    bool intersection = false;
    bool wants(LineKind k) const { return kinds[int(k)]; }  // (a mesh feature kind only)
};

enum class CuspCase : std::uint8_t {
    None = 0,
    FrontBackMeet = 1,    // exactly two silhouette edges, one front- and one back-facing
    ManySilhouettes = 2,  // more than two silhouette edges
    BorderEdge = 3,       // a silhouette vertex adjacent to a border edge
};

inline constexpr std::uint8_t kNoKind = 0xff;

// A chain of feature edges; its vertices and edges are views into the CurveList that holds it.
struct FeatureCurve {
    LineKind kind = LineKind::Silhouette;
    std::span<const std::uint32_t> vertices;  // n+1 vertices for n edges (first == last if closed)
    std::span<const std::uint32_t> edges;
    bool closed = false;  // a loop whose start is an ordinary vertex (a loop from a junction back to it is open)
};

// The curves of a view, their vertices and edges stored in two flat arrays (written in order as
// the chains are walked, reused from view to view). Copies point into their own arrays.
class CurveList {
public:
    CurveList() = default;
    CurveList(const CurveList& o) : curves_(o.curves_), vertices_(o.vertices_), edges_(o.edges_) { repoint(); }
    CurveList& operator=(const CurveList& o) {
        if (this != &o) {
            curves_ = o.curves_, vertices_ = o.vertices_, edges_ = o.edges_;
            repoint();
        }
        return *this;
    }
    CurveList(CurveList&&) noexcept = default;  // (moved vectors keep their storage: the views hold)
    CurveList& operator=(CurveList&&) noexcept = default;

    std::size_t size() const { return curves_.size(); }
    bool empty() const { return curves_.empty(); }
    const FeatureCurve& operator[](std::size_t i) const { return curves_[i]; }
    std::vector<FeatureCurve>::const_iterator begin() const { return curves_.begin(); }
    std::vector<FeatureCurve>::const_iterator end() const { return curves_.end(); }
    // The edges of curves [c0, c1), one after another (they are stored so).
    std::span<const std::uint32_t> edges_of(std::size_t c0, std::size_t c1) const {
        if (c0 >= c1) return {};
        const std::uint32_t* first = curves_[c0].edges.data();
        const std::span<const std::uint32_t>& last = curves_[c1 - 1].edges;
        return {first, std::size_t(last.data() + last.size() - first)};
    }

    // Building: clear(), then per curve start() and add() (vertices and edges alternating from
    // the first vertex), then finish() to make the views.
    void clear() {
        curves_.clear();
        vertices_.clear();
        edges_.clear();
    }
    void start(LineKind kind, std::uint32_t vertex) {
        // (the views hold offsets until finish(): the arrays may still grow)
        curves_.push_back({kind, {}, {}, false});
        starts_.push_back({std::uint32_t(vertices_.size()), std::uint32_t(edges_.size())});
        vertices_.push_back(vertex);
    }
    void add(std::uint32_t edge, std::uint32_t vertex) {
        edges_.push_back(edge);
        vertices_.push_back(vertex);
    }
    void set_closed(bool closed) { curves_.back().closed = closed; }
    void finish() {
        starts_.push_back({std::uint32_t(vertices_.size()), std::uint32_t(edges_.size())});
        for (std::size_t i = 0; i < curves_.size(); ++i) {
            curves_[i].vertices = {vertices_.data() + starts_[i].v, starts_[i + 1].v - starts_[i].v};
            curves_[i].edges = {edges_.data() + starts_[i].e, starts_[i + 1].e - starts_[i].e};
        }
        starts_.clear();
    }

private:
    void repoint() {
        std::size_t v = 0, e = 0;
        for (FeatureCurve& c : curves_) {
            const std::size_t nv = c.vertices.size(), ne = c.edges.size();
            c.vertices = {vertices_.data() + v, nv};
            c.edges = {edges_.data() + e, ne};
            v += nv, e += ne;
        }
    }
    struct Start {
        std::uint32_t v, e;
    };
    std::vector<FeatureCurve> curves_;
    std::vector<std::uint32_t> vertices_, edges_;
    std::vector<Start> starts_;
};

enum class FinderKind : std::uint8_t { Exhaustive, Randomized };
const char* finder_name(FinderKind k);

struct FinderOptions {
    FinderKind kind = FinderKind::Exhaustive;
    // Randomized: edges drawn per view as a share of all edges, with probability proportional to
    // the angle between their face normals (pi - dihedral); >= 1 examines every edge once.
    double fraction = 0.05;
    bool coherence = true;        // check every silhouette edge of the previous view
    double seed_fraction = 0.05;  // share of lost previous silhouette edges, and of crease and
                                  // border edges, that start a seek per view
    int step_bound = 24;          // edges a seek may follow
    bool seek_draws = true;       // a drawn edge that is not a silhouette starts a seek too
                                  // (with coherence: only while there is no previous view)
    std::uint64_t seed = 1;       // random seed (runs are deterministic)
    bool first_full = false;      // with coherence: a view without a previous view runs the
                                  // exhaustive scan; later views follow it exactly (complete, so
                                  // they skip the draws and seeks)
    double band_steps = 0.0;      // coherence: the band's margin in steps of the eye's last move;
                                  // 0: chosen from the last band's size (streaming the band and
                                  // rebuilding it balanced: sqrt(faces / (2.5 band faces per step)))
    int threads = 1;              // exhaustive: threads for the facing pass and the edge scan
                                  // (the result and its order do not depend on it)
    bool blocks = true;           // exhaustive scan (from its second view) and band rebuilds: decide
                                  // blocks of faces as a whole where their plane ranges allow (FaceBlocks;
                                  // the same result)
    bool edge_windows = true;     // exhaustive scan (from its second view), where the CPU runs the AVX-512
                                  // or AVX2 kernel: the edge scan over the gather-free layout (BlockEdges;
                                  // the same result)
};

struct FinderStats {
    FinderKind finder = FinderKind::Exhaustive;
    double fraction = 1.0;
    std::size_t edges_examined = 0;  // edges whose facing was compared (scan, draws, trace rings)
    std::size_t seeks = 0, seek_steps = 0, seek_hits = 0;
    std::size_t band_faces = 0, faces_turned = 0;  // coherence: faces checked, faces that changed facing
    bool band_rebuilt = false;                      // coherence: the band was rebuilt this view
    std::size_t faces_decided = 0, exact_facing_tests = 0;
    std::size_t edges_read = 0;   // exhaustive scan: edges whose face pairs were read
    std::size_t planes_read = 0;  // exhaustive facing pass and band rebuilds: faces whose planes were read
    double seconds_search = 0.0;  // finding the silhouette edges (and classifying creases, borders)
    double seconds_chain = 0.0;   // cusps and chaining into curves (the same work for every finder)
};

struct Features {
    FaceFacing face_front;                      // [f]: 1 if the eye is strictly in front of face f
    std::vector<std::uint8_t> edge_kind;        // LineKind or kNoKind, per mesh edge (randomized
                                                // finder: kNoKind also for edges it did not find)
    std::vector<std::uint32_t> silhouette_edges;
    std::vector<std::uint32_t> border_edges;
    std::vector<std::uint32_t> crease_edges;    // creases that are not silhouettes
    std::vector<std::uint32_t> cusp_vertices;
    std::vector<CuspCase> cusp_cases;           // parallel to cusp_vertices
    CurveList curves;                           // only the requested kinds
    FinderStats stats;

    // Scratch per vertex, all zero between views (reset through the chained vertices): the
    // randomized finder's marks.
    struct VertexScratch {
        std::uint8_t traced = 0, sought = 0;
    };
    std::vector<std::vector<std::uint32_t>> thread_candidates;  // exhaustive scan: candidate edges, per thread
    std::vector<VertexScratch> vertex_scratch;
    // Chaining: the view's feature edges (the three lists in a row) and their vertices numbered
    // locally, so that counting, cusps and chaining read compact arrays instead of the mesh's.
    struct ChainVertex {
        std::uint32_t id;            // mesh vertex
        std::uint32_t edge_xor;      // xor of the local numbers of its feature edges
        std::uint8_t degree, silhouettes, front;
        std::uint8_t kinds;          // bit per LineKind of its feature edges
        std::uint8_t cusp;
    };
    std::vector<std::uint32_t> vertex_local;  // per mesh vertex: its local number, UINT32_MAX between views
    std::vector<ChainVertex> chain_vertices;
    // Per feature edge, all a step of the chaining reads (one record, half a cache line): its
    // vertices' local numbers, the feature edge that follows through each (UINT32_MAX where the
    // vertex breaks chains), their mesh numbers, the mesh edge, and whether a chain took it.
    struct ChainLink {
        std::uint32_t end[2];
        std::uint32_t next[2];
        std::uint32_t id[2];
        std::uint32_t edge;
        std::uint32_t used;
    };
    std::vector<ChainLink> chain_links;
    // Set by a SilhouetteFinder's view: a stamp unique to that view while edge_kind marks exactly
    // its silhouette edges (0: unknown). Copied with the rest, so a copy keeps a valid stamp.
    std::uint64_t silhouette_marks = 0;
};

// Exact facing of one face: orientation of the eye against the face's oriented plane (CGAL's
// filtered exact predicate); for an orthographic camera the sign of det[b-a, c-a, -f], exact.
// A face whose plane contains the eye (or the view direction) counts as not front-facing.
bool face_is_front(const MeshTopology& mesh, std::uint32_t face, const Camera& camera);

// One view with the exhaustive finder.
Features extract_features(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options = {});

// A finder that lives across the views of a camera path: it keeps the previous view's silhouette
// edges (frame coherence), its random generator and, built on first use, the sampling table.
// find() reuses the storage of `out` from the previous view, so a randomized view costs what it
// touches, not the mesh size.
class SilhouetteFinder {
public:
    SilhouetteFinder(const MeshTopology& mesh, const FinderOptions& options = {});
    // `searched`, if given, is called once the silhouette, border and crease edge lists of `out`
    // are final, before the cusps and the chaining (which leave those lists as they are): work
    // that needs only the lists can start there (ViewSession: the occluders, on another thread).
    void find(const Camera& camera, const FeatureOptions& options, Features& out,
              const std::function<void()>& searched = {});
    const FinderOptions& options() const { return opt_; }
    void reset();  // forget the previous view
    void set_fraction(double f) { opt_.fraction = f; }  // e.g. a viewer's slider, keeping coherence
    void set_threads(int threads) { opt_.threads = threads < 1 ? 1 : threads; }  // (the same result)

private:
    // block_edges: the scan may skip the edges of blocks of one state (FaceBlocks edge ranges,
    // built on first use) or use BlockEdges; false: every edge is read (the same result).
    void scan_exhaustive(Features& out, bool block_edges = true);
    // carry: the view of out.face_front was left full for the previous camera by this finder
    // (then carried on after following; otherwise begun lazily by the caller).
    void search_randomized(const Camera& camera, Features& out, bool carry = false);
    void trace(std::uint32_t e, Features& out);
    void seek(std::uint32_t vertex, bool front, const Camera& camera, Features& out);
    void build_table();
    void follow(const Camera& camera, Features& out);
    // follow()'s steps, in order (features.cpp says what each does).
    void start_following(const Camera& camera);
    bool update_band(const Camera& camera);
    void tune_band_steps(double steps);
    void find_turned_faces(Features& out, bool rebuilt);
    std::size_t reclassify_turned_edges(Features& out);
    void merge_silhouette(Features& out, std::size_t rechecked);
    void build_band(const double eye[3], double w, double margin);
    void add_silhouette(std::uint32_t e, Features& out);

    const FaceBlocks* blocks();  // built on first use (if opt_.blocks), else null

    const MeshTopology* mesh_;
    // The exhaustive facing pass's and edge scan's threads beyond the caller's (opt_.threads),
    // kept from view to view: a thread made per view costs more than a part of a small view.
    WorkerTeam team_;
    FinderOptions opt_;
    FaceBlocks blocks_;
    BlockEdges block_edges_;  // built on the second exhaustive view (if opt_.edge_windows)
    bool block_edges_tried_ = false;
    std::size_t full_views_ = 0;
    std::size_t planes_read_ = 0;  // this view  // exhaustive scans run so far (blocks are built for the second)
    std::mt19937_64 rng_;
    std::vector<float> alias_prob_;  // Vose's alias table over edges, weights pi - dihedral
    std::vector<std::uint32_t> alias_;
    std::vector<std::uint32_t> stack_, sought_;

    // Frame coherence. The previous view's silhouette edges (their ids). A face changes facing
    // between two views only if its plane passes between the two eyes, so only faces whose plane
    // was within a margin M of the eye when the band was built (their planes copied, 20 bytes
    // each) can change while the eye stays within M of that position; the band is rebuilt by one
    // pass over all faces when the eye leaves. follow() streams the band, and the silhouette is the
    // previous edges minus those of the faces that changed that are no longer silhouettes, plus
    // the new ones among the edges of the faces that changed. Two bits per face (front now,
    // turned) and the band are built on first use, only by a randomized finder with coherence.
    std::vector<std::uint32_t> previous_;
    bool previous_sorted_ = false;  // previous_ is in edge order (the exhaustive scan's, kept by follow())
    std::vector<std::uint32_t> fresh_, dropped_, radix_tmp_;  // follow(): edges of turned faces that became / stopped being silhouettes
    std::vector<std::uint32_t> radix_count_;
    void sort_edges(std::vector<std::uint32_t>& v);
    // The stamp this finder's last view left in its Features (Features::silhouette_marks): a
    // Features holding it marks exactly previous_'s edges as silhouettes, so the next view may
    // keep the marks (any other finder's view, or this one's, stamps it anew or clears it).
    std::uint64_t stamp_ = 0;
    void stamp(Features& out);
    bool marks_kept_ = false;  // this view: find() left previous_'s marks in place
    bool complete_ = false;  // previous_ is the whole silhouette (exhaustive first view, then followed)
    struct Carried {
        const FaceFacing* facing = nullptr;  // a full view this finder left for previous_camera_
        std::uint64_t generation = 0;        // its generation then
    } carried_;
    Camera previous_camera_, camera_;
    FacingFilter previous_filter_, filter_;
    std::vector<std::uint32_t> turned_;
    std::vector<std::uint32_t> block_edges_begin_;  // follow(): per 64 faces, the first edge they number ({0}: none)
    FacingBand band_;
    std::vector<std::uint32_t> check_;  // scratch: band positions to check exactly
    // Bit per face: front now (band faces: set per view; the others: at the band's rebuild,
    // which they keep while the eye stays within the margin); turned since the previous view.
    std::vector<std::uint64_t> front_bits_, turned_bits_;
    double band_eye_[3] = {0, 0, 0}, band_margin_ = -1.0, band_w_ = 0.0;  // margin < 0: no band
    // Views found so far, and the one whose facing front_bits_ hold (the last that ran follow()):
    // a kept band needs the previous view's bits, else it is rebuilt.
    std::uint64_t views_ = 0, bits_view_ = 0;
    double auto_steps_ = 4.0;  // the first band: narrow, so that its rebuild stays cheap (bench/results/finder.md)
};

}  // namespace inkline
