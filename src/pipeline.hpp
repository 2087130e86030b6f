// The library's front door: a model loaded once, drawn from any number of cameras.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "core/camera.hpp"
#include "core/drawing.hpp"
#include "curvature/curvature.hpp"
#include "features/features.hpp"
#include "model/early_self_intersections.hpp"
#include "model/intersection_curves.hpp"
#include "model/self_intersections.hpp"
#include "model/subdivide.hpp"
#include "model/topology.hpp"
#include "scene/scene.hpp"
#include "visibility/ray_caster.hpp"
#include "visibility/appel.hpp"
#include "visibility/fast_visibility.hpp"
#include "visibility/surface_visibility.hpp"
#include "visibility/visibility.hpp"

namespace inkline {

class Model {
public:
    // Loads a model file (throws inkline::Error naming the file): OBJ, OFF, PLY and STL by
    // load_mesh, every other format Assimp reads as a scene (load_scene: objects, cameras);
    // tolerant unless options.strict (repairs() counts what was repaired).
    // `subdivide` rounds of Loop subdivision are applied after loading.
    // `on_subdivide` hears of the subdivision's progress (model/subdivide.hpp).
    static Model load(const std::string& path, const LoadOptions& options, double crease_degrees = 40.0,
                      int subdivide = 0, const SubdivideProgress& on_subdivide = {});
    // Strict loading (refuses what tolerant loading repairs), for callers that predate the repairs.
    static Model load(const std::string& path, double crease_degrees = 40.0, int subdivide = 0);
    explicit Model(TriangleMesh mesh, double crease_degrees = 40.0);  // moved into the topology
    explicit Model(MeshTopology topology);  // e.g. a copy whose vertices then move (detail/)

    Model(Model&&) noexcept = default;
    // (the search Model::load started, if running, is stopped before this model's arrays go)
    Model& operator=(Model&& other) noexcept;

    const MeshTopology& topology() const { return topo_; }
    // Open to change: first ends the self-intersection search Model::load started, if it runs
    // (it reads the positions and faces), as self_intersections() does. Reading goes through the
    // const overload, which waits for nothing.
    MeshTopology& topology();
    // The ray-test index, built on first use only (views that need no ray test never pay for it);
    // once, also when several threads ask at the same time (so are the self-intersections).
    const RayCaster& rays() const;
    // A ray-test index kept by the caller across models (the progressive mesh's subset index,
    // RayCaster::reindex), asked for on the first ray test instead of building one: `index` brings
    // it to this model's topology and returns it; the caller keeps it alive while the model is
    // drawn. Only before any view asked for rays; move_vertices does not refit such an index.
    void index_rays_with(std::function<const RayCaster&(const MeshTopology&)> index);
    // Per face: intersects another face; computed on first use (the fast visibility needs it).
    const std::vector<std::uint8_t>& self_intersecting_faces() const;
    // Those flags, or null when no face is flagged (AppelOptions::pierced_faces: a view then looks
    // up no face of its pieces).
    const std::vector<std::uint8_t>* pierced_faces() const;
    // Those faces and where edges meet other faces (both visibility methods cut curves there);
    // computed on first use, once, on up to `threads` threads (the first caller's count).
    const SelfIntersections& self_intersections(int threads = 1) const;
    // Per-vertex curvature and its derivative (curvature/curvature.hpp), computed on first use, once:
    // only the curvature line kinds need it, so a render without them never pays for it.
    const CurvatureField& curvature() const;
    // Where surfaces of the model cross (model/intersection_curves.hpp), from the self-intersections'
    // face pairs; computed on first use, once: only intersection lines need them.
    const IntersectionCurves& intersection_curves() const;
    // Those curves if some view has asked for them already, else null (nothing is computed).
    const IntersectionCurves* intersection_curves_if_computed() const { return lazy_->intersections.get(); }
    // The curvature if some view has asked for it already, else null (nothing is computed).
    const CurvatureField* curvature_if_computed() const { return lazy_->curvature.get(); }
    // Moves the vertices (`positions` swapped in, same count; the old ones come back in it) and
    // brings along what depends on them: the topology's geometry (MeshTopology::refresh_geometry),
    // the ray-test index refitted if it was built, and the self-intersections: `known` adopted
    // when given, else computed again if they were. The curvature is not recomputed. Not
    // thread-safe against views of this model in flight.
    void move_vertices(std::vector<glm::dvec3>& positions, const SelfIntersections* known = nullptr);
    // Takes `known` as the self-intersections instead of searching for them (a caller that knows
    // them already, e.g. none); only before any view asked for them.
    void adopt_self_intersections(SelfIntersections known);
    // Model::load's time, and the wait when the first caller of self_intersections() joined the
    // search that load started (the model ready to draw, as a render reports it).
    double load_seconds() const { return load_seconds_ + lazy_->early_search_wait.load(); }
    const LoadReport& repairs() const { return repairs_; }
    // The file's cameras (scenes only; empty for mesh files), in file order.
    const std::vector<SceneCamera>& cameras() const { return cameras_; }

private:
    void stop_early_search();  // drops Model::load's search, if running (its threads stopped)
    // (lazy_ after topo_: destroyed first, so that the search stops before the arrays it reads go)
    MeshTopology topo_;
    // Built on first use, once, also when several threads ask at the same time (the preview
    // window's two sessions); behind a pointer so that the model stays movable.
    struct Lazy {
        std::once_flag rays_once, pierced_once, curvature_once, intersections_once;
        std::unique_ptr<RayCaster> rays;
        std::function<const RayCaster&(const MeshTopology&)> rays_from;  // (index_rays_with)
        const RayCaster* rays_used = nullptr;
        std::unique_ptr<SelfIntersections> pierced;
        // Model::load's search, started beside the topology's construction and joined by the
        // first caller of self_intersections(), so that what comes before (a render's features,
        // the window's opening) runs while it ends on the other thread.
        std::unique_ptr<EarlySelfIntersections> early_search;
        std::atomic<double> early_search_wait{0.0};  // seconds in its finish()
        std::unique_ptr<CurvatureField> curvature;
        std::unique_ptr<IntersectionCurves> intersections;
    };
    std::unique_ptr<Lazy> lazy_ = std::make_unique<Lazy>();
    double load_seconds_ = 0.0;
    LoadReport repairs_;
    std::vector<SceneCamera> cameras_;
};

// Rays: the reference; Appel: exact propagation (the default); Fast: a depth buffer settles what
// it can and the exact method the rest, visible lines only (fast_visibility.hpp).
enum class VisibilityMethod { Rays, Appel, Fast };

struct ViewOptions {
    FeatureOptions features;
    FinderOptions finder;  // exhaustive (default) or randomized seed-and-seek
    VisibilityMethod visibility = VisibilityMethod::Appel;
    // Exact QI of hidden pieces is needed (hidden lines drawn); otherwise the fast method may
    // leave a totally occluded cluster at a lower bound (> 0) without a ray test.
    bool exact_hidden = true;
    // The fast method walks the surface (section 4.4) before it makes a ray test.
    bool walk = true;
    // VisibilityMethod::Fast: its buffer and margins (pierced_faces is set from the model). It
    // draws visible lines only: hidden pieces get QI 1, a lower bound, whatever exact_hidden says.
    FastVisibilityOptions fast;
    // The frame's threads: the exhaustive finder's facing pass and edge scan (a session gives its
    // finder the larger of this and finder.threads) and the visibility's split stages (large views
    // only). The drawing is the same whatever the count.
    int threads = 1;
    // Lines across faces from the mesh's curvature (suggestive contours, smooth contours, ridges,
    // valleys); none by default: the curvature is then never computed.
    SurfaceLineOptions surface{.suggestive = false};
    bool wants_surface_lines() const {
        return surface.suggestive || surface.smooth_contour || surface.ridge || surface.valley;
    }
    // Intersection lines are FeatureOptions::intersection (off by default: the curves are then
    // never built).
};

struct View {
    Features features;
    SurfaceCurves surface;                     // curves across faces (ViewOptions::surface), 3D
    // Intersection lines (FeatureOptions::intersection): the model's curves, null when not drawn.
    const IntersectionCurves* intersections = nullptr;
    Drawing drawing;                           // pieces with QI, in pixels, and statistics
    std::vector<std::vector<EdgeSpan>> spans;  // where each piece of the drawing lies on the mesh
                                               // (empty for pieces of surface curves)
};

// Features -> visibility for one camera. The camera's near plane, when unset (0), is
// default_near(model) for this call.
View render_view(const Model& model, Camera camera, const ViewOptions& options = {});

// Views along a camera path: one finder across them (frame coherence for the randomized finder),
// and the storage of the previous view reused, so a view costs what it touches.
class ViewSession {
public:
    ViewSession(const Model& model, const ViewOptions& options = {});
    // Features only (the silhouette finder, cusps, chaining); timed in seconds_features().
    const Features& find(Camera camera);
    // Features, then visibility; the returned view lives until the next call.
    View& render(Camera camera);
    // Visibility of the features found last by find(camera) (same camera).
    View& visibility(Camera camera);
    double seconds_features() const { return features_seconds_; }
    SilhouetteFinder& finder() { return finder_; }
    // The threads of the next views (ViewOptions::threads: finder and visibility; the same drawing).
    void set_threads(int threads) {
        options_.threads = threads < 1 ? 1 : threads;
        finder_.set_threads(options_.threads);
    }
    int threads() const { return options_.threads; }
    // The surface lines drawn from the next view on (their kinds and thresholds: a window's
    // toggles and sliders); the curvature is computed on first need, once per model.
    void set_surface_lines(const SurfaceLineOptions& surface) { options_.surface = surface; }
    // Intersection lines drawn from the next view on (a window's toggle); their curves are built on
    // first need, once per model.
    void set_intersection_lines(bool on) { options_.features.intersection = on; }
    // The surface lines of the next views from these per-vertex quantities (both or neither)
    // instead of the model's curvature and compute_view_curvature: the multi-scale detail's fields
    // blended between smoothed copies of the shape (detail/). They must outlive the views.
    void use_surface_fields(const CurvatureField* field, const ViewCurvature* view) {
        field_override_ = field;
        view_override_ = view;
    }

private:
    // find() with the finder's `searched` call (SilhouetteFinder::find).
    const Features& find(Camera camera, const std::function<void()>& searched);
    void finish(const Camera& camera);
    const Model* model_;
    ViewOptions options_;
    SilhouetteFinder finder_;
    View view_;
    // Appends the surface lines' pieces to the view's drawing; returns the seconds spent on the
    // curvature and the extraction (the rest was their visibility).
    double add_surface_lines(const Camera& camera, const std::function<const RayCaster&()>& rays,
                             const std::vector<std::uint8_t>* pierced);
    // Appends the intersection lines' pieces to the view's drawing; returns the seconds spent
    // building the model's curves (0 after the first view: they are not the view's time).
    double add_intersection_lines(const Camera& camera, const std::function<const RayCaster&()>& rays);
    PieceGraph graph_;  // the fast visibility's pieces, storage kept from view to view
    FastVisibility fast_;  // VisibilityMethod::Fast's buffer, kept from view to view
    ViewCurvature view_curvature_;           // surface lines: per-vertex quantities of the view
    const CurvatureField* field_override_ = nullptr;  // use_surface_fields
    const ViewCurvature* view_override_ = nullptr;
    SurfaceVisibilityScratch surface_scratch_;
    double features_seconds_ = 0.0;
};

// Total world length of mesh edges (recall of silhouette length compares two of these).
double edges_length(const MeshTopology& mesh, const std::vector<std::uint32_t>& edges);

}  // namespace inkline
