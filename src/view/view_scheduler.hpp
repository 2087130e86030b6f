// The preview window's views, computed on worker threads: one `ViewSession` a lane, each lane a
// long-lived thread that computes its views one at a time (features -> visibility -> line quads,
// or the stylized drawing as pixels). With two lanes, two views are computed at once, the lanes
// taking the views in turn (each session follows its own last view, two views back), while the
// camera moves slowly; one at a time otherwise, on all the threads. Views are taken in the order
// they were started. No OpenGL here, so it is unit-tested.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <vector>

#include "core/camera.hpp"
#include "core/worker_thread.hpp"
#include "pipeline.hpp"
#include "style/style.hpp"
#include "view/detail_source.hpp"
#include "view/frame_stats.hpp"
#include "view/line_mesh.hpp"
#include "view/toon_coat.hpp"

namespace inkline {

// What a view is asked for besides its camera (the panel may change the window's options while
// it is computed: the request holds its own copy).
struct ViewRequest {
    Camera camera;
    LineMeshOptions lines;                // the quads' options (style null)
    std::shared_ptr<const Style> style;   // non-null: the drawing stylized as `render --style`
    bool hidden = false;                  // the style draws hidden lines
    bool recall = false;                  // measure recall of silhouette length against exhaustive
    FeatureOptions kinds;                 // the line kinds of the recall's exhaustive reference
    DetailSource* detail = nullptr;       // --detail: the view drawn by it (one lane), with its coat
};

// A view computed, as taken by the window.
struct FinishedView {
    View* view = nullptr;   // the lane's session's view: rewritten by its next view
    Camera camera;
    DrawingStats stats;     // a copy of view->drawing.stats, taken on the caller's thread
    StageTimes times;       // the view's own stage times
    double recall = -1.0;   // recall of silhouette length (-1: not asked)
    double cpu = 0.0;       // its lane thread's CPU seconds for the view
    double waited = 0.0;    // seconds the caller waited for it in take_oldest()
    int views_at_once = 1;  // when it was started
    std::vector<LineVertex> lines;       // its quads (empty when styled)
    bool styled = false;
    std::vector<std::uint32_t> pixels;   // styled: the drawing, camera.width() x camera.height()
    CoatMesh coat;                       // --detail: the mesh the view was drawn from (its base coat)
    bool has_coat = false;
};

class ViewScheduler {
public:
    // `in_flight`: views computed at once, 1, 2, or 0 (two lanes where there are two threads, two
    // views at once while the camera moves slowly). `wake` is called on a lane's thread as each
    // view is done (the window posts an empty event to its loop).
    ViewScheduler(const Model& model, int in_flight, std::function<void()> wake = {});
    ~ViewScheduler();
    ViewScheduler(const ViewScheduler&) = delete;
    ViewScheduler& operator=(const ViewScheduler&) = delete;

    // New sessions with `options` (its threads split between two lanes): two lanes unless
    // in_flight is 1 or there is one thread. Every view in flight must have been taken.
    void reset(const ViewOptions& options);
    // The randomized finders' fraction of edges sampled (no view in flight).
    void set_fraction(double fraction);
    // The surface lines of the views started from now on (the panel's toggles and sliders), for
    // every session; call while no view is in flight.
    void set_surface_lines(const SurfaceLineOptions& surface);

    // Views to compute at once now, 1 or 2: fixed by in_flight, else by the camera's step between
    // the views started (smoothed over about four views, from the fourth step on), two below
    // 1 degree a view, one above 1.6 (a margin either side so that it does not flip-flop).
    int views_at_once();
    // The same choice as last made, without updating it (for the panel).
    int views_at_once_now() const;
    bool fixed() const { return in_flight_flag_ > 0 || lane_count_ < 2; }  // not by the camera's step
    int lane_count() const { return lane_count_; }
    int threads() const { return threads_; }

    // Starts the pipeline for request.camera on the next lane's thread (there must be fewer views
    // in flight than views_at_once()).
    void start(const ViewRequest& request);
    int in_flight() const { return int(in_flight_.size()); }
    // The camera of the newest view in flight (in_flight() > 0).
    const Camera& newest_camera() const;
    // Whether the oldest view in flight is done (then taking it does not wait).
    bool oldest_done();
    // Waits for the oldest view in flight, if any (its exception, if any, is thrown here), and
    // swaps it into `into` (whose buffers the lane reuses). Returns whether there was one.
    bool take_oldest(FinishedView& into);

private:
    struct Lane;
    static void compute(const Model& model, ViewSession& session, const ViewRequest& request, FinishedView& out);

    const Model& model_;
    const int in_flight_flag_;
    std::function<void()> wake_;
    std::unique_ptr<Lane> lanes_[2];
    int lane_count_ = 1, last_lane_ = -1, threads_ = 1;
    bool two_at_once_ = false;   // the default's current choice (views_at_once())
    double step_ = 0.0;          // the camera's step between views started, radians, smoothed
    int steps_seen_ = 0;         // steps measured since the sessions were made
    std::deque<int> in_flight_;  // lanes with a view started and not taken, oldest first
};

}  // namespace inkline
