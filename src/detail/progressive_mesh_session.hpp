// Drawing views along a camera path with the progressive mesh (seed 000, sections 3.1-3.3): the
// incremental front adapted each frame (with geomorphs when asked), the adapted mesh drawn by the
// unchanged pipeline with exact visibility, its suggestive contours from k_r and D_w k_r smoothed
// over time per input vertex. The pm counterpart of MultiscaleSession (multiscale.hpp), for the
// bench and the window.
//
// Takes: a ProgressiveMesh, the pipeline's ViewOptions and a target size; per frame a Camera and
// the frame's duration. Gives: the frame's View and the adapted Model it was drawn from.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "detail/adapted_topology.hpp"
#include "detail/moving_self_intersections.hpp"
#include "detail/progressive_mesh_front.hpp"
#include "curvature/incremental_curvature.hpp"
#include "detail/temporal_smoothing.hpp"
#include "pipeline.hpp"

namespace inkline {

struct PmViewOptions {
    double target_px = 0.0;      // --detail=PX: T = PX^2 square pixels
    double crease_degrees = 40.0;
    GeomorphOptions geomorphs;   // a path's frames: on; one converged drawing: off
    // The front's budget a frame (FrontBudget: splits, collapses and geomorph starts and ends;
    // FrontBudget::fixed(N) for a hard N a frame), so that when many vertices leave the band at
    // once the work is spread over the next frames, most visible first, instead of stalling one
    // frame; what is deferred is made up as the demand falls. settle() takes no budget (it
    // converges).
    FrontBudget budget = default_budget();
    // The rule that follows the lag: on the 1 M-triangle slow dolly it bounds the front's worst
    // frame (800 operations) where an unbudgeted front's peak frames take twice that, costs less
    // over the path, and the mesh follows the view (docs/progressive_mesh.md, "A budget that
    // follows the lag").
    static FrontBudget default_budget() { return FrontBudget::following_lag(); }
    bool smoothing = true;       // section 3.3, over smoothing_seconds to smoothing_alpha of the way
    double smoothing_seconds = 0.8, smoothing_alpha = 0.9;
    // Whether the input intersects itself (Model::self_intersections().flagged > 0). When it does
    // not, a frame's adapted mesh is not searched whole (the search was most of a frame's time):
    // with every vertex at its own position it is taken to be embedded too, the compromise the
    // multi-scale method makes for its blends (a coarsening with no face turned over rarely makes
    // new intersections), and only the faces around the vertices a geomorph has moved off their
    // own position are searched against the rest (detail/moving_self_intersections.hpp: a
    // split's faces cross their neighbours while its vertex slides out). A view that draws
    // intersection lines takes the full search (their chaining follows its order).
    bool input_self_intersects = true;
    // The ray-test index kept across frames (RayCaster's subset index over the input's faces in
    // blocks, only the blocks the frame changed rebuilt or refitted) instead of a new tree a
    // frame; the ray tests' results are the same either way (only the faces Embree proposes
    // differ, each decided exactly).
    bool ray_index_across_frames = true;

    // A camera path's options for `model` (the window, render sequences, the benches): geomorphs on,
    // the model's crease angle, and whether it intersects itself (its search run if not yet).
    static PmViewOptions for_path(const Model& model, double target_px);
};

// Where a frame's time went, in the rendering thread's CPU seconds: the front's adaptation, the
// adapted mesh taken out of the front, its topology and Model, the pipeline's session, the
// curvature, the per-view curvature with the temporal smoothing, and the view (silhouettes,
// surface lines, visibility, and the ray-test index when a ray test asks for it); of the view, the
// drawing's own wall-clock split: features (finder and surface-line extraction) and visibility.
struct PmFrameSeconds {
    double adapt = 0.0, mesh = 0.0, topology = 0.0, pierced = 0.0, session = 0.0, curvature = 0.0, smoothing = 0.0, view = 0.0,
           total = 0.0;
    double ray_index = 0.0;  // of the view: the index kept across frames brought to the frame's mesh
    double features = 0.0, visibility = 0.0;  // wall
};

class PmSession {
public:
    PmSession(const ProgressiveMesh& pm, const ViewOptions& options, const PmViewOptions& pm_options);
    // One frame, `frame_seconds` after the last (geomorphs advance by it; the smoothing's weight
    // takes 1 / frame_seconds as the frame rate). The view lives until the next call.
    View& render(const Camera& camera, double frame_seconds);
    // The same frame without its drawing (no view, no self-intersections): what a sequence's frames
    // before the range it writes need, since the frames after depend on them.
    void advance(const Camera& camera, double frame_seconds);
    // The front converged at `camera` (geomorphs finished at once), e.g. when a window opens.
    void settle(const Camera& camera);
    const Model& adapted() const { return *model_; }
    const FrontStats& stats() const { return stats_; }
    const AdaptiveFront& front() const { return front_; }
    double seconds_adapt() const { return stats_.seconds; }
    const PmFrameSeconds& seconds() const { return seconds_; }
    const IncrementalCurvature& curvature() const { return curvature_; }
    // The last frame's search around moving vertices (zeros when it made none).
    const MovingSearchStats& moving_search() const { return moving_search_; }
    // The last frame's update of the ray-test index kept across frames (zeros when the frame made
    // no ray test or the index is not kept).
    const RayCaster::ReindexStats& ray_index() const { return ray_index_stats_; }
    void set_target(double target_px) { pm_options_.target_px = target_px; }
    // The adapted mesh's vertices' and faces' indices in the input (both increasing).
    const std::vector<std::uint32_t>& input_vertices() const { return input_vertex_; }
    const std::vector<std::uint32_t>& input_faces() const { return input_face_; }

private:
    const ProgressiveMesh& pm_;
    ViewOptions options_;
    PmViewOptions pm_options_;
    AdaptiveFront front_;
    FrontStats stats_;
    PmFrameSeconds seconds_;
    AdaptedTopology topology_;
    MeshTopology spare_;  // the frame before last's topology: its storage is refilled
    std::unique_ptr<Model> model_;
    std::unique_ptr<ViewSession> session_;
    std::vector<std::uint32_t> input_vertex_, input_face_;  // the adapted mesh's, in the input
    std::vector<std::uint8_t> moved_;  // per adapted vertex: shown off its own position
    MovingSearchStats moving_search_;
    std::unique_ptr<RayCaster> rays_;  // (PmViewOptions::ray_index_across_frames)
    RayCaster::ReindexStats ray_index_stats_;
    IncrementalCurvature curvature_;
    ViewCurvature view_curvature_;
    TemporalSmoother smoother_;

    // The frame's self-intersections adopted by its Model when the input has none (see
    // PmViewOptions::input_self_intersects).
    void adopt_self_intersections();
    // A frame up to its drawing (the session made only when `drawn`); returns its start time.
    double update_frame(const Camera& camera, double frame_seconds, bool drawn);
    // The frame's Model takes the index kept across frames, brought to its mesh on its first ray test.
    void lend_ray_index();
};

}  // namespace inkline
