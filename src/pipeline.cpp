#include "pipeline.hpp"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "model/early_self_intersections.hpp"
#include "model/self_intersections.hpp"
#include "model/reorder.hpp"
#include "model/subdivide.hpp"
#include "scene/scene.hpp"

namespace inkline {

// Below this many faces the search takes a few milliseconds: a thread's start costs about what
// running it beside the topology saves.
constexpr std::size_t kEarlySearchFaces = 8192;

Model Model::load(const std::string& path, const LoadOptions& options, double crease_degrees, int subdivide,
                  const SubdivideProgress& on_subdivide) {
    const auto t0 = std::chrono::steady_clock::now();
    TriangleMesh mesh;
    // With a thread to spare, the Hilbert orders are made beside the repairs, and used when the
    // repairs changed nothing (most files). (After `mesh`: destroyed first, it waits for its thread.)
    HilbertOrderAhead ahead;
    std::vector<SceneCamera> cameras;
    if (is_scene_file(path)) {
        Scene scene = load_scene(path, options);
        mesh = std::move(scene.mesh);
        cameras = std::move(scene.cameras);
    } else {
        mesh = load_mesh(path, options, options.threads > 1 && subdivide <= 0 ? &ahead : nullptr);
    }
    const LoadReport repairs = mesh.repairs;
    LoadProgressReporter progress(&options.progress, 0);
    // Hilbert order: per-view passes that follow the surface stay in cache.
    std::optional<HilbertOrders> known = ahead.take();
    TriangleMesh ordered = known ? hilbert_ordered(std::move(mesh), *known, options.threads)
                                 : hilbert_ordered(subdivide_loop(std::move(mesh), subdivide, on_subdivide), options.threads);
    known.reset();  // (not held through the topology's construction, the load's peak)
    progress.at(kProgressOrdered);
    // Every view needs the self-intersections: with threads to spare, their search runs beside
    // the topology's construction (it needs only the faces and positions, which the topology
    // keeps as they are), and the first caller of self_intersections() joins it: a render's
    // features (and the window's opening) come first, while the search ends on the other thread.
    // It reads the model's own arrays: they are the model's before it starts, so that whatever
    // ends the model (an exception in the topology's construction included) stops it first.
    Model m{MeshTopology()};
    m.topo_.positions = std::move(ordered.positions);
    m.topo_.faces = std::move(ordered.triangles);
    if (options.threads > 1 && m.topo_.faces.size() >= kEarlySearchFaces)
        m.lazy_->early_search = std::make_unique<EarlySelfIntersections>(
            SearchInput{m.topo_.positions.data(), m.topo_.faces.data(), m.topo_.faces.size(), m.topo_.positions.size()},
            options.threads);
    build_topology_on(m.topo_, std::move(ordered), crease_degrees);
    m.repairs_ = repairs;
    m.cameras_ = std::move(cameras);
    m.load_seconds_ = seconds_since(t0);
    progress.finish();
    return m;
}

Model Model::load(const std::string& path, double crease_degrees, int subdivide) {
    return load(path, LoadOptions{.strict = true}, crease_degrees, subdivide);
}

Model::Model(TriangleMesh mesh, double crease_degrees) : topo_(build_topology(std::move(mesh), crease_degrees)) {}

Model::Model(MeshTopology topology) : topo_(std::move(topology)) {}

Model& Model::operator=(Model&& other) noexcept {
    if (this == &other) return *this;
    stop_early_search();  // (it reads the arrays the assignment frees)
    topo_ = std::move(other.topo_);
    lazy_ = std::move(other.lazy_);  // (its search, if any, reads the arrays just taken)
    load_seconds_ = other.load_seconds_;
    repairs_ = std::move(other.repairs_);
    cameras_ = std::move(other.cameras_);
    return *this;
}

void Model::stop_early_search() {
    if (lazy_) lazy_->early_search.reset();
}

MeshTopology& Model::topology() {
    // A caller may change the arrays the search reads: it ends first (its result is kept, as if a
    // view had asked for it).
    if (lazy_ && lazy_->early_search) self_intersections();
    return topo_;
}

void Model::move_vertices(std::vector<glm::dvec3>& positions, const SelfIntersections* known) {
    if (positions.size() != topo_.positions.size())
        throw Error("model", "move_vertices: " + std::to_string(positions.size()) + " positions for " +
                                 std::to_string(topo_.positions.size()) + " vertices");
    stop_early_search();  // (a search of the old positions: stopped before they change)
    topo_.positions.swap(positions);
    topo_.refresh_geometry();
    if (lazy_->rays) lazy_->rays->refit();
    if (known) {
        std::call_once(lazy_->pierced_once, [] {});
        lazy_->pierced = std::make_unique<SelfIntersections>(*known);
    } else if (lazy_->pierced) {
        *lazy_->pierced = inkline::self_intersections(topo_);
    }
}

void Model::adopt_self_intersections(SelfIntersections known) {
    stop_early_search();
    std::call_once(lazy_->pierced_once, [] {});
    lazy_->pierced = std::make_unique<SelfIntersections>(std::move(known));
}

const RayCaster& Model::rays() const {
    std::call_once(lazy_->rays_once, [this] {
        if (lazy_->rays_from) {
            lazy_->rays_used = &lazy_->rays_from(topo_);
        } else {
            lazy_->rays = std::make_unique<RayCaster>(topo_);
            lazy_->rays_used = lazy_->rays.get();
        }
    });
    return *lazy_->rays_used;
}

void Model::index_rays_with(std::function<const RayCaster&(const MeshTopology&)> index) {
    lazy_->rays_from = std::move(index);
}

const std::vector<std::uint8_t>& Model::self_intersecting_faces() const { return self_intersections().faces; }

const std::vector<std::uint8_t>* Model::pierced_faces() const {
    const SelfIntersections& si = self_intersections();
    return si.flagged > 0 ? &si.faces : nullptr;
}

const SelfIntersections& Model::self_intersections(int threads) const {
    std::call_once(lazy_->pierced_once, [this, threads] {
        if (lazy_->early_search) {
            const auto t0 = std::chrono::steady_clock::now();
            lazy_->pierced = std::make_unique<SelfIntersections>(lazy_->early_search->finish(topo_));
            lazy_->early_search.reset();
            lazy_->early_search_wait.store(seconds_since(t0));
        } else {
            lazy_->pierced = std::make_unique<SelfIntersections>(inkline::self_intersections(topo_, threads));
        }
    });
    return *lazy_->pierced;
}

const IntersectionCurves& Model::intersection_curves() const {
    std::call_once(lazy_->intersections_once, [this] {
        lazy_->intersections =
            std::make_unique<IntersectionCurves>(inkline::intersection_curves(topo_, self_intersections().pairs));
    });
    return *lazy_->intersections;
}

const CurvatureField& Model::curvature() const {
    std::call_once(lazy_->curvature_once,
                   [this] { lazy_->curvature = std::make_unique<CurvatureField>(estimate_curvature(topo_)); });
    return *lazy_->curvature;
}

namespace {
FeatureOptions chained_kinds(const ViewOptions& options) {
    // Propagation needs every occluding curve chained, drawn or not.
    FeatureOptions fo = options.features;
    // (Fast too: near the eye it hands the view to propagation.)
    if (options.visibility != VisibilityMethod::Rays)
        fo.kinds[int(LineKind::Silhouette)] = fo.kinds[int(LineKind::Border)] = true;
    return fo;
}

// Each piece's object: the face beside its first edge (feature pieces), or under its first
// segment (surface lines). A scene's objects are welded each on its own, so no curve runs from
// one object into another.
void assign_objects(const MeshTopology& mesh, View& v) {
    Drawing& d = v.drawing;
    d.object_names.clear();
    if (mesh.object_names.size() < 2 || mesh.face_object.size() != mesh.face_count()) return;
    d.object_names = mesh.object_names;
    const std::uint32_t first_surface = std::uint32_t(v.features.curves.size());
    for (std::size_t i = 0; i < d.pieces.size(); ++i) {
        Piece& p = d.pieces[i];
        std::uint32_t face = kNoFace;
        if (i < v.spans.size() && !v.spans[i].empty()) {
            face = mesh.edge_face[v.spans[i].front().edge][0];
        } else if (p.curve >= first_surface && p.curve - first_surface < v.surface.curves.size()) {
            const auto& c = v.surface.curves[p.curve - first_surface];
            for (std::uint32_t k = c.begin; k < c.end && face == kNoFace; ++k)
                if (k < v.surface.segment_face.size() && v.surface.segment_face[k] != UINT32_MAX)
                    face = v.surface.segment_face[k];
        }
        p.object = face < mesh.face_object.size() ? mesh.face_object[face] : 0;
    }
}
}  // namespace

View render_view(const Model& model, Camera camera, const ViewOptions& options) {
    ViewSession session(model, options);
    return std::move(session.render(camera));
}

namespace {
FinderOptions finder_with_threads(const ViewOptions& options) {
    FinderOptions fo = options.finder;
    fo.threads = std::max({1, fo.threads, options.threads});
    return fo;
}
}  // namespace

ViewSession::ViewSession(const Model& model, const ViewOptions& options)
    : model_(&model), options_(options), finder_(model.topology(), finder_with_threads(options)) {}

const Features& ViewSession::find(Camera camera) { return find(camera, {}); }

const Features& ViewSession::find(Camera camera, const std::function<void()>& searched) {
    if (camera.near_distance() <= 0.0) camera.set_near(default_near(model_->topology()));
    graph_.drop_started_occluders();  // (a render that threw after starting them: they read the features)
    const auto t0 = std::chrono::steady_clock::now();
    finder_.find(camera, chained_kinds(options_), view_.features, searched);
    features_seconds_ = seconds_since(t0);
    return view_.features;
}

View& ViewSession::visibility(Camera camera) {
    if (camera.near_distance() <= 0.0) camera.set_near(default_near(model_->topology()));
    finish(camera);
    return view_;
}

// From this many occluding edges the occluders' images and clipping (about 1.4 ms a frame on one
// thread at 50 k edges) outlast the chaining they overlap, and would be split in two anyway
// (build_pieces splits them from 8000).
constexpr std::size_t kOverlapOccluders = 8000;

View& ViewSession::render(Camera camera) {
    if (camera.near_distance() <= 0.0) camera.set_near(default_near(model_->topology()));
    // On two threads, a large view's occluders are made on the graph's helper while this thread
    // chains the curves, instead of chaining alone and then splitting the occluders in two (the
    // chaining is serial). On more threads the split occluders are faster than one thread's.
    const bool overlap = options_.visibility == VisibilityMethod::Appel && options_.threads == 2;
    Features& f = view_.features;
    find(camera, [&] {
        if (overlap && f.silhouette_edges.size() + f.border_edges.size() >= kOverlapOccluders)
            start_occluders(graph_, model_->topology(), f, camera);
    });
    finish(camera);
    return view_;
}

void ViewSession::finish(const Camera& camera) {
    const Model& model = *model_;
    const ViewOptions& options = options_;
    View& v = view_;
    bool appel = options.visibility == VisibilityMethod::Appel;
    double index_seconds = 0.0;  // building the ray-test index (once per model) is not the view's time
    auto rays = [&]() -> const RayCaster& {
        const auto tb = std::chrono::steady_clock::now();
        const RayCaster& r = model.rays();
        index_seconds += seconds_since(tb);
        return r;
    };
    // Once per model, like the ray-test index: not the view's time.
    const SelfIntersections& si = model.self_intersections(options.threads);
    const bool fast = options.visibility == VisibilityMethod::Fast;
    const std::vector<std::uint8_t>* pierced = appel || fast ? model.pierced_faces() : nullptr;
    const auto t1 = std::chrono::steady_clock::now();
    Drawing& d = v.drawing;
    VisibleCurves curves;
    AppelStats as;
    FastVisibilityStats fs;
    if (fast) {
        FastVisibilityOptions fo = options.fast;
        fo.pierced_faces = pierced;
        fs = fast_.run(model.topology(), v.features, camera, rays, options.features, fo, d.pieces, v.spans);
        appel = fs.exact_needed;  // geometry at the near plane: the exact method takes the view
        d.stats.seconds_pieces = fs.seconds_buffer + fs.seconds_samples;
        d.stats.seconds_propagation = d.stats.seconds_walks = 0.0;
        d.stats.seconds_ray_tests = fs.seconds_ray_tests;
        curves.ray_tests = fs.ray_tests;
    }
    if (appel) {
        // Into the session's graph: its storage (and the previous drawing's) reused.
        PieceGraph& g = graph_;
        build_pieces(g, model.topology(), v.features, camera, &si.cuts, options.threads);
        const auto t2 = std::chrono::steady_clock::now();
        d.stats.seconds_pieces = std::chrono::duration<double>(t2 - t1).count();
        as = assign_qi_appel(model.topology(), camera, v.features.face_front, rays, g,
                             {options.exact_hidden, pierced, options.walk, options.threads});
        d.stats.seconds_walks = as.seconds_walks;
        d.stats.seconds_ray_tests = as.seconds_ray_tests;
        // (the ray-test index, if built in it, is not the view's time)
        d.stats.seconds_propagation =
            std::max(0.0, seconds_since(t2) - index_seconds - as.seconds_walks - as.seconds_ray_tests);
        // Drop what was chained only to propagate QI (their storage stays in the graph).
        auto& pieces = g.curves.pieces;
        auto& spans = g.curves.spans;
        std::size_t k = 0;
        for (std::size_t i = 0; i < pieces.size(); ++i)
            if (options.features.wants(pieces[i].kind)) {
                if (k != i) std::swap(pieces[k], pieces[i]), std::swap(spans[k], spans[i]);
                ++k;
            }
        g.truncate(k);
        // The drawing takes the pieces; the graph keeps the previous drawing's storage for the next view.
        d.pieces.swap(pieces);
        v.spans.swap(spans);
        curves.crossings = g.curves.crossings;
        curves.ray_tests = as.ray_tests;
    } else if (!fast) {
        curves = compute_visibility(model.topology(), v.features, camera, rays(), &si.cuts);
        d.stats.seconds_pieces = curves.seconds_pieces;
        d.stats.seconds_propagation = d.stats.seconds_walks = 0.0;
        d.stats.seconds_ray_tests = curves.seconds_ray_tests;
        d.pieces = std::move(curves.pieces);
        v.spans = std::move(curves.spans);
    }

    // (the curvature, once per model, and the lines' extraction are not visibility time)
    double not_visibility = 0.0;
    if (options.wants_surface_lines()) not_visibility = add_surface_lines(camera, rays, pierced);
    else {
        v.surface.clear();
        d.stats.surface_curves = d.stats.curvature_invalid_vertices = 0;
        d.stats.crossings_surface = d.stats.surface_ray_tests = 0;
        d.stats.seconds_surface_lines = d.stats.seconds_surface_visibility = 0.0;
    }
    if (options.features.intersection) not_visibility += add_intersection_lines(camera, rays);
    else {
        v.intersections = nullptr;
        d.stats.intersection_curves = d.stats.crossings_intersection = d.stats.intersection_ray_tests = 0;
    }

    d.camera = camera;
    DrawingStats& s = d.stats;
    s.triangles = model.topology().face_count();
    s.seam_edges = model.topology().seam_list.size();
    s.silhouette_edges = v.features.silhouette_edges.size();
    s.border_edges = v.features.border_edges.size();
    s.crease_edges = v.features.crease_edges.size();
    s.curves = v.features.curves.size();
    s.cusps = v.features.cusp_vertices.size();
    s.crossings = curves.crossings + s.crossings_surface + s.crossings_intersection;
    s.pieces = d.pieces.size();
    s.ray_tests = curves.ray_tests + s.surface_ray_tests + s.intersection_ray_tests;
    s.visibility = appel ? "appel" : fast ? "fast" : "rays";
    s.clusters = as.clusters;
    s.walks = as.walks;
    s.clusters_bbox = as.clusters_bbox;
    s.clusters_bounded = as.clusters_bounded;
    s.clusters_occluded = as.clusters_occluded;
    s.clusters_inconsistent = as.inconsistent;
    s.seconds_load = model.load_seconds();
    s.finder = finder_name(v.features.stats.finder);
    s.fraction = v.features.stats.fraction;
    s.recall = -1.0;
    s.seconds_features = features_seconds_ + s.seconds_surface_lines;
    s.seconds_visibility = seconds_since(t1) - index_seconds - not_visibility;
    s.seconds_total = s.seconds_features + s.seconds_visibility;
    assign_objects(model.topology(), v);
}

double ViewSession::add_surface_lines(const Camera& camera, const std::function<const RayCaster&()>& rays,
                                      const std::vector<std::uint8_t>* pierced) {
    const Model& model = *model_;
    const MeshTopology& mesh = model.topology();
    View& v = view_;
    DrawingStats& s = v.drawing.stats;
    // Once per model, like the ray-test index: not the view's time.
    const auto tc = std::chrono::steady_clock::now();
    const CurvatureField& field = field_override_ ? *field_override_ : model.curvature();
    const auto t0 = std::chrono::steady_clock::now();
    if (!view_override_) compute_view_curvature(field, mesh, camera, view_curvature_);
    const ViewCurvature& quantities = view_override_ ? *view_override_ : view_curvature_;
    extract_surface_lines(mesh, field, quantities, camera, options_.surface, v.surface);
    const auto t1 = std::chrono::steady_clock::now();
    SurfaceVisibilityOptions so;
    so.propagate = options_.visibility != VisibilityMethod::Rays;
    so.pierced_faces = pierced;
    so.curve_offset = std::uint32_t(v.features.curves.size());
    const SurfaceVisibilityStats st =
        surface_visibility(mesh, v.features, camera, v.surface, rays, so, surface_scratch_, v.drawing.pieces);
    v.spans.resize(v.drawing.pieces.size());  // surface pieces lie across faces: no edge spans
    s.surface_curves = v.surface.curves.size();
    s.curvature_invalid_vertices = field.invalid_vertices;
    s.seconds_surface_lines = std::chrono::duration<double>(t1 - t0).count();
    s.seconds_surface_visibility = seconds_since(t1);
    s.surface_ray_tests = st.ray_tests;
    s.crossings_surface = st.crossings;
    return std::chrono::duration<double>(t1 - tc).count();  // what is not visibility time
}

double ViewSession::add_intersection_lines(const Camera& camera, const std::function<const RayCaster&()>& rays) {
    View& v = view_;
    DrawingStats& s = v.drawing.stats;
    const auto t0 = std::chrono::steady_clock::now();
    const IntersectionCurves& curves = model_->intersection_curves();  // once per model
    const double build_seconds = seconds_since(t0);
    SurfaceVisibilityOptions so;
    so.propagate = options_.visibility != VisibilityMethod::Rays;
    so.curve_offset = std::uint32_t(v.features.curves.size() + v.surface.curves.size());
    const SurfaceVisibilityStats st = intersection_visibility(model_->topology(), v.features, camera, curves, rays, so,
                                                              surface_scratch_, v.drawing.pieces);
    v.spans.resize(v.drawing.pieces.size());  // intersection pieces lie across faces: no edge spans
    v.intersections = &curves;
    s.intersection_curves = curves.curves.size();
    s.crossings_intersection = st.crossings;
    s.intersection_ray_tests = st.ray_tests;
    return build_seconds;
}

double edges_length(const MeshTopology& mesh, const std::vector<std::uint32_t>& edges) {
    double l = 0.0;
    for (std::uint32_t e : edges)
        l += glm::length(mesh.positions[mesh.edge_vertex[e][1]] - mesh.positions[mesh.edge_vertex[e][0]]);
    return l;
}

}  // namespace inkline
