#include "detail/progressive_mesh_session.hpp"

namespace inkline {

PmSession::PmSession(const ProgressiveMesh& pm, const ViewOptions& options, const PmViewOptions& pm_options)
    : options_(options), pm_options_(pm_options), front_(pm, pm_options.geomorphs) {}

void PmSession::settle(const Camera& camera) {
    DetailCriterion criterion;
    criterion.target_area_px = pm_options_.target_px * pm_options_.target_px;
    for (int k = 0; k < 64; ++k) {  // (a handful in practice: the worklist converges within a frame)
        const FrontStats s = front_.update(camera, criterion, 1e6);
        if (s.splits + s.collapses + s.morphs_started + s.morphs_running == 0) break;
    }
}

View& PmSession::render(const Camera& camera, double frame_seconds) {
    DetailCriterion criterion;
    criterion.target_area_px = pm_options_.target_px * pm_options_.target_px;
    stats_ = front_.update(camera, criterion, frame_seconds);
    // (a new Model a frame: its topology, facing classes and ray index follow the new connectivity)
    model_ = std::make_unique<Model>(front_.mesh(&input_vertex_), pm_options_.crease_degrees);
    if (!pm_options_.input_self_intersects)
        model_->adopt_self_intersections({std::vector<std::uint8_t>(model_->topology().face_count(), 0), 0, {}, {}});
    session_ = std::make_unique<ViewSession>(*model_, options_);
    const SurfaceLineOptions& s = options_.surface;
    if (pm_options_.smoothing && (s.suggestive || s.smooth_contour)) {
        compute_view_curvature(model_->curvature(), model_->topology(), camera, curvature_);
        const double fps = frame_seconds > 0.0 ? 1.0 / frame_seconds : 0.0;
        smoother_.blend(curvature_, input_vertex_,
                        smoothing_weight(pm_options_.smoothing_seconds, fps, pm_options_.smoothing_alpha));
        session_->use_surface_fields(&model_->curvature(), &curvature_);
    }
    return session_->render(camera);
}

}  // namespace inkline
