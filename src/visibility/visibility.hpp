// Visibility, reference method: curves are projected, split at every image-space crossing with
// a silhouette or border edge (and where the near plane cuts them), and every piece gets its QI
// from one ray test at a point inside it. Takes MeshTopology + Features + Camera + RayCaster;
// gives pieces in pixels with QI, and where each piece lies on the mesh edges.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "core/worker_thread.hpp"
#include "features/features.hpp"
#include "model/self_intersections.hpp"
#include "model/topology.hpp"
#include "visibility/crossings.hpp"
#include "visibility/ray_caster.hpp"

namespace inkline {

// A stretch of one mesh edge: parameters along the edge from edge_vertex[edge][0] (0) to [1] (1).
struct EdgeSpan {
    std::uint32_t edge;
    double s0, s1;
};

struct VisibleCurves {
    std::vector<Piece> pieces;
    std::vector<std::vector<EdgeSpan>> spans;  // parallel to pieces
    std::size_t crossings = 0;                 // intersecting (curve edge, occluding edge) pairs
    std::size_t ray_tests = 0;
    // compute_visibility (the reference): the pieces' time (crossings, cuts) and the ray tests'.
    double seconds_pieces = 0.0, seconds_ray_tests = 0.0;
};

// Image positions of mesh vertices for one view, each projected at most once (on first use):
// the same value Camera::project gives.
class VertexImages {
public:
    VertexImages() = default;
    VertexImages(const MeshTopology& mesh, const Camera& camera) { reset(mesh, camera); }
    // Starts a new view: nothing projected yet (the arrays kept when the vertex count is the same).
    void reset(const MeshTopology& mesh, const Camera& camera) {
        positions_ = &mesh.positions;
        camera_ = camera;
        if (count_ != mesh.vertex_count() || !p_) {
            count_ = mesh.vertex_count();
            p_.reset(new glm::dvec2[count_]);
            slack_.reset(new double[count_]);
        }
        done_.assign(count_ / 64 + 1, 0);
        slack_done_.assign(done_.size(), 0);
    }
    glm::dvec2 operator()(std::uint32_t v) const {
        std::uint64_t& w = done_[v >> 6];
        const std::uint64_t bit = std::uint64_t(1) << (v & 63);
        if (!(w & bit)) {
            w |= bit;
            p_[v] = camera_.project((*positions_)[v]);
        }
        return p_[v];
    }
    // Prefetches what operator()(v) and slack(v) read and write (no effect on results).
    void prefetch(std::uint32_t v) const {
        __builtin_prefetch(&done_[v >> 6]);
        __builtin_prefetch(&slack_done_[v >> 6]);
        __builtin_prefetch(&p_[v], 1);
        __builtin_prefetch(&slack_[v], 1);
    }
    // image_slack (crossings.hpp) of the vertex's image, computed at most once.
    double slack(std::uint32_t v) const {
        std::uint64_t& w = slack_done_[v >> 6];
        const std::uint64_t bit = std::uint64_t(1) << (v & 63);
        if (!(w & bit)) {
            w |= bit;
            slack_[v] = image_slack(camera_, (*positions_)[v], (*this)(v));
        }
        return slack_[v];
    }

private:
    const std::vector<glm::dvec3>* positions_ = nullptr;
    Camera camera_;
    std::size_t count_ = 0;
    std::unique_ptr<glm::dvec2[]> p_;
    std::unique_ptr<double[]> slack_;
    mutable std::vector<std::uint64_t> done_, slack_done_;
};

// The calling thread's share of the work units of a stage split between two threads (the rest
// goes to the helper thread), fitted from view to view: the side on the helper thread can cost
// more per unit (it reads what the other core has just written; bench/results/visibility.md,
// eighteenth session), so halves leave the calling thread waiting.
struct SplitShare {
    double share = 0.5;  // within [0.3, 0.7]
    void set(double s) { share = std::clamp(s, 0.3, 0.7); }
    // After a split that gave the calling thread the fraction f of the units, and took t_here on
    // it and t_there on the helper: moves halfway toward the share that would have made both
    // sides end together (views differ, and the host can inflate a time).
    void fit(double f, double t_here, double t_there) {
        if (!(t_here > 0.0 && t_there > 0.0 && f > 0.0 && f < 1.0)) return;
        const double c1 = t_here / f, c2 = t_there / (1.0 - f);
        set(0.5 * share + 0.5 * c2 / (c1 + c2));
    }
};

// The pieces of a view before they get their QI, and what the fast method needs to propagate QI
// between them: links where a curve is cut at crossings, the vertices where curves end, whether
// geometry surrounds the camera, and the extreme points of the occluders' image.
struct PieceGraph {
    VisibleCurves curves;  // pieces (qi unset), spans, crossing count
    struct Link {
        std::uint32_t before, after;  // consecutive pieces of one curve, in travel order
    };
    std::vector<Link> links;
    struct LinkCrossing {
        std::uint32_t link;
        std::uint32_t occluder;  // index among the view's occluding segments
        std::uint32_t seg;       // segment of the curve (internal)
        double t;                // image parameter along it
        glm::dvec3 c1{0.0}, c2{0.0};     // the curve's segment in 3D, in travel order
        std::uint32_t occluder_edge = 0;  // mesh edge of the occluder
        double occluder_s = 0.0;          // where on it (edge parameter)
        int delta = 0;                    // change of QI across it (set by the fast method)
    };
    std::vector<LinkCrossing> link_crossings;
    struct End {
        std::uint32_t piece, vertex, edge;  // a piece ending at a curve's end vertex, on this edge
    };
    std::vector<End> ends;
    std::vector<Segment2> occluders;   // silhouette and border edges in the image (clipped)
    // Their grid index, built on first use (walks need it; most views make none).
    const SegmentGrid& occluder_grid() const {
        if (!grid_built_) {
            grid_.build(occluders, image_size.x, image_size.y);
            grid_built_ = true;
        }
        return grid_;
    }
    glm::dvec2 image_size{0.0};  // the camera's image, pixels
    bool immersive = false;  // geometry at or behind the near plane
    std::array<std::uint32_t, 4> extreme_vertices{};  // min x, max x, min y, max y (UINT32_MAX: none)
    VertexImages images;  // the mesh vertices in the image (walks project the faces they cross)
    // A copy for each further thread of the walks (images are made on first use: not shared);
    // kept from view to view with their storage, as `images` is.
    std::vector<VertexImages> walk_images;

    // Keeps pieces [0, k) (and their spans); the storage of the others is kept for the next build.
    void truncate(std::size_t k);

    // The calling thread's share of the curve edges when build_pieces splits the curves between
    // two threads, fitted by each build to the two sides' times (the pieces do not depend on it).
    // (Only this split is fitted: fitting the others gained nothing, bench/results/visibility.md.)
    SplitShare curves_split;

    // The thread that runs the second half of a stage split in two (build_pieces' curves, the
    // fast method's curve ends and walks), started on first use and kept with the graph from view
    // to view.
    WorkerThread& helper() { return team_.first_worker(); }
    // The threads of stages split in more parts (build_pieces' curve ranges, the crossings' QI
    // changes, the curve ends' local occlusion); helper() is its first worker.
    WorkerTeam& team() { return team_; }

    // Waits for start_occluders' job if one is in flight and drops it: its view went no further
    // (an exception between start_occluders and build_pieces, already the caller's), and the
    // features it reads are about to change.
    void drop_started_occluders() {
        if (!occluders_job_.valid()) return;
        occluders_job_.wait();
        occluders_job_ = {};
        occluders_features_ = nullptr;
    }

private:
    friend void build_pieces(PieceGraph& graph, const MeshTopology& mesh, const Features& features,
                             const Camera& camera, const std::vector<EdgeCut>* cuts, int threads,
                             std::size_t parallel_edges, bool mirror_pairs);
    friend void start_occluders(PieceGraph& graph, const MeshTopology& mesh, const Features& features,
                                const Camera& camera);
    // start_occluders' job on helper(), and what it was started for (build_pieces takes its
    // result only for the same features and camera).
    std::future<void> occluders_job_;
    const Features* occluders_features_ = nullptr;
    Camera occluders_camera_;
    mutable SegmentGrid grid_;
    mutable bool grid_built_ = false;
    // Storage of pieces no longer in the graph (their point and span vectors keep their capacity).
    std::vector<Piece> spare_pieces_;
    std::vector<std::vector<EdgeSpan>> spare_spans_;
    WorkerTeam team_;
};

// Clips, projects and splits the curves at every crossing (no QI yet), and at `cuts` (where
// curve edges meet other faces: model/self_intersections.hpp), if given. With threads > 1 a large
// view's curves (at least `parallel_edges` curve edges) are split among up to `threads` threads,
// at least parallel_edges / 2 edges each (the same pieces, in the same order).
PieceGraph build_pieces(const MeshTopology& mesh, const Features& features, const Camera& camera,
                        const std::vector<EdgeCut>* cuts = nullptr, int threads = 1,
                        std::size_t parallel_edges = 4000);
// The same into `graph`, which is overwritten: its storage (every vector, the pieces' point and
// span vectors, the vertex images, the occluder grid) is reused, so a view along a camera path
// allocates (nearly) nothing once the graph has seen a view as large. The result equals a fresh
// build_pieces, whatever the graph held before.
//
// mirror_pairs: a silhouette (or border) segment copied from its occluder and crossing another such
// is tested once for both pairs, (its segment, the other's occluder) and (the other's segment, its
// occluder): the second pair's sides are the first's exact orientations, permuted (see
// mirrored_crossings, crossings.hpp). Off: each pair tested on its own (the same results; for tests).
void build_pieces(PieceGraph& graph, const MeshTopology& mesh, const Features& features, const Camera& camera,
                  const std::vector<EdgeCut>* cuts = nullptr, int threads = 1, std::size_t parallel_edges = 4000,
                  bool mirror_pairs = true);

// Starts build_pieces' first part, the occluders (their vertex images, clipping and extreme points:
// it reads only the silhouette and border edge lists of `features`), on the graph's helper thread
// and returns at once: a caller that has found the silhouettes can chain the curves meanwhile
// (ViewSession on two threads). The next build_pieces of `graph` waits for it and, for the same
// `features` object and camera, goes on from there (the same pieces); otherwise it starts over.
// Until then `graph` and the edge lists must not change.
void start_occluders(PieceGraph& graph, const MeshTopology& mesh, const Features& features, const Camera& camera);

// Where a piece is probed: the image midpoint of its longest stretch, on the mesh edge.
struct PieceProbe {
    glm::dvec3 P;
    glm::dvec2 p;
    std::uint32_t edge;
};
PieceProbe probe_point(const MeshTopology& mesh, const Camera& camera, const Piece& piece,
                       const std::vector<EdgeSpan>& spans);

// QI of one piece by a ray test at the image midpoint of its longest stretch.
int qi_by_ray(const MeshTopology& mesh, const Camera& camera, const RayCaster& rays, const Piece& piece,
              const std::vector<EdgeSpan>& spans);

// Default near plane of a camera for this model: 1e-6 of the model's half diagonal in front of
// the eye plane (geometry closer than that is clipped, as in any graphics pipeline).
double default_near(const MeshTopology& mesh);

// The reference method: one ray test per piece.
VisibleCurves compute_visibility(const MeshTopology& mesh, const Features& features, const Camera& camera,
                                 const RayCaster& rays, const std::vector<EdgeCut>* cuts = nullptr);

}  // namespace inkline
