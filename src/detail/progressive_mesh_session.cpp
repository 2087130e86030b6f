#include "detail/progressive_mesh_session.hpp"

#include <algorithm>

#include "core/clock.hpp"

namespace inkline {

PmViewOptions PmViewOptions::for_path(const Model& model, double target_px) {
    PmViewOptions o;
    o.target_px = target_px;
    o.crease_degrees = model.topology().crease_degrees;
    o.geomorphs.enabled = true;
    o.input_self_intersects = model.self_intersections().flagged > 0;
    return o;
}

PmSession::PmSession(const ProgressiveMesh& pm, const ViewOptions& options, const PmViewOptions& pm_options)
    : pm_(pm), options_(options), pm_options_(pm_options), front_(pm, pm_options.geomorphs) {}

void PmSession::settle(const Camera& camera) {
    DetailCriterion criterion;
    criterion.target_area_px = pm_options_.target_px * pm_options_.target_px;
    for (int k = 0; k < 64; ++k) {  // (a handful in practice: the worklist converges within a frame)
        const FrontStats s = front_.update(camera, criterion, 1e6);
        if (s.splits + s.collapses + s.morphs_started + s.morphs_running == 0) break;
    }
}

void PmSession::adopt_self_intersections() {
    moving_search_ = {};
    if (pm_options_.input_self_intersects || options_.features.intersection) return;  // (the model's own search)
    const MeshTopology& t = model_->topology();
    const std::vector<glm::dvec3>& own = pm_.input().positions;
    moved_.resize(t.vertex_count());
    for (std::size_t v = 0; v < moved_.size(); ++v) moved_[v] = t.positions[v] != own[input_vertex_[v]];
    model_->adopt_self_intersections(self_intersections_of_moving(t, moved_, &moving_search_));
}

void PmSession::lend_ray_index() {
    if (!pm_options_.ray_index_across_frames) return;
    if (!rays_) rays_ = std::make_unique<RayCaster>(RayCaster::SubsetOptions{});
    model_->index_rays_with([this](const MeshTopology& t) -> const RayCaster& {
        const double t0 = thread_cpu_seconds();
        ray_index_stats_ = rays_->reindex(t, input_vertex_, input_face_);
        seconds_.ray_index = thread_cpu_seconds() - t0;
        return *rays_;
    });
}

double PmSession::update_frame(const Camera& camera, double frame_seconds, bool drawn) {
    PmFrameSeconds& t = seconds_;
    const double t0 = thread_cpu_seconds();
    auto lap = [last = t0]() mutable {
        const double now = thread_cpu_seconds();
        const double s = now - last;
        last = now;
        return s;
    };
    DetailCriterion criterion;
    criterion.target_area_px = pm_options_.target_px * pm_options_.target_px;
    stats_ = front_.update(camera, criterion, frame_seconds, pm_options_.budget);
    t.adapt = lap();
    TriangleMesh mesh = front_.mesh(&input_vertex_, &input_face_);
    t.mesh = lap();
    // A new Model a frame (its ray index follows the new connectivity), its topology built with the
    // last one's unchanged edges carried over, in the storage of the frame before last.
    MeshTopology topology = std::move(spare_);
    topology_.build(topology, std::move(mesh), input_vertex_, input_face_, pm_options_.crease_degrees,
                    model_ ? &model_->topology() : nullptr);
    session_.reset();
    if (model_) spare_ = std::move(model_->topology());
    model_ = std::make_unique<Model>(std::move(topology));
    t.topology = lap();
    // Only the view needs the frame's self-intersections, ray index and session; the next frames
    // need the front, the topology, the curvature and the smoothing, which every frame carries.
    t.pierced = t.session = t.ray_index = 0.0;
    ray_index_stats_ = {};
    if (drawn) {
        adopt_self_intersections();
        lend_ray_index();
        t.pierced = lap();
        session_ = std::make_unique<ViewSession>(*model_, options_);
        t.session = lap();
    }
    const SurfaceLineOptions& s = options_.surface;
    t.curvature = t.smoothing = 0.0;
    if (s.suggestive || s.smooth_contour || s.ridge || s.valley) {
        // The adapted mesh's curvature, recomputed only near where the front changed (the same
        // field as its Model's own, bit for bit), then the view's quantities, smoothed over time.
        const CurvatureField& field = curvature_.update(model_->topology(), input_vertex_, input_face_);
        t.curvature = lap();
        compute_view_curvature(field, model_->topology(), camera, view_curvature_);
        if (pm_options_.smoothing && (s.suggestive || s.smooth_contour)) {
            const double fps = frame_seconds > 0.0 ? 1.0 / frame_seconds : 0.0;
            smoother_.blend(view_curvature_, input_vertex_,
                            smoothing_weight(pm_options_.smoothing_seconds, fps, pm_options_.smoothing_alpha));
        }
        if (drawn) session_->use_surface_fields(&field, &view_curvature_);
        t.smoothing = lap();
    }
    return t0;
}

void PmSession::advance(const Camera& camera, double frame_seconds) {
    const double t0 = update_frame(camera, frame_seconds, false);
    seconds_.view = seconds_.features = seconds_.visibility = 0.0;
    seconds_.total = thread_cpu_seconds() - t0;
}

View& PmSession::render(const Camera& camera, double frame_seconds) {
    const double t0 = update_frame(camera, frame_seconds, true);
    PmFrameSeconds& t = seconds_;
    const double before_view = thread_cpu_seconds();
    View& v = session_->render(camera);
    t.view = thread_cpu_seconds() - before_view;
    t.features = v.drawing.stats.seconds_features;
    t.visibility = v.drawing.stats.seconds_visibility;
    t.total = thread_cpu_seconds() - t0;
    return v;
}

}  // namespace inkline
