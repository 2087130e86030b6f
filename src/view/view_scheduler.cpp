#include "view/view_scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

#include "output/styled.hpp"
#include "style/styled_view.hpp"

namespace inkline {

// A lane: a session and the thread that computes its views, one at a time. The thread lives as
// long as the lane: the stages keep per-thread working storage from view to view (build_pieces'
// scratch arrays are thread_local: tens of megabytes on a large model), which a new thread per
// view would allocate again.
struct ViewScheduler::Lane {
    std::unique_ptr<ViewSession> session;
    Camera camera;       // of the view started last
    int mode = 1;        // views at once when it started
    FinishedView result; // written by the lane's thread, read after its job's get()
    std::future<void> job;
    std::atomic<bool> done{false};  // set by the job as it ends (its future is ready just after)
    WorkerThread thread;            // (last: stopped first, after its job in flight)
};

ViewScheduler::ViewScheduler(const Model& model, int in_flight, std::function<void()> wake)
    : model_(model), in_flight_flag_(in_flight), wake_(std::move(wake)) {}

ViewScheduler::~ViewScheduler() = default;

void ViewScheduler::reset(const ViewOptions& options) {
    // The lanes: two sessions where there are two threads (unless --in-flight=1), one view at a
    // time on all the threads or two at once, the threads split (views_at_once()).
    threads_ = std::max(1, options.threads);
    lane_count_ = in_flight_flag_ == 1 || threads_ < 2 ? 1 : 2;
    for (int i = 0; i < lane_count_; ++i) {
        if (!lanes_[i]) lanes_[i] = std::make_unique<Lane>();
        lanes_[i]->session = std::make_unique<ViewSession>(model_, options);
    }
    for (int i = lane_count_; i < 2; ++i) lanes_[i].reset();
    last_lane_ = -1;
    two_at_once_ = false;  // (until a few views have shown the camera's step)
    step_ = 0.0;
    steps_seen_ = 0;
}

void ViewScheduler::set_fraction(double fraction) {
    for (int i = 0; i < lane_count_; ++i) lanes_[i]->session->finder().set_fraction(fraction);
}

void ViewScheduler::set_surface_lines(const SurfaceLineOptions& surface) {
    for (int i = 0; i < lane_count_; ++i) lanes_[i]->session->set_surface_lines(surface);
}

// Two sessions taking the views in turn each follow a view two views back, so each finder's follow
// costs about twice as much: two at once wins while the camera's step is small, one at a time
// above (bench/results/view_fps.md, "two views at once while the camera moves slowly").
int ViewScheduler::views_at_once() {
    if (lane_count_ < 2) return 1;
    if (in_flight_flag_ == 2) return 2;
    constexpr double kDeg = M_PI / 180.0;
    if (two_at_once_ && step_ > 1.6 * kDeg) two_at_once_ = false;
    else if (!two_at_once_ && steps_seen_ >= 4 && step_ < 1.0 * kDeg) two_at_once_ = true;
    return two_at_once_ ? 2 : 1;
}

int ViewScheduler::views_at_once_now() const {
    return lane_count_ < 2 ? 1 : in_flight_flag_ == 2 || two_at_once_ ? 2 : 1;
}

const Camera& ViewScheduler::newest_camera() const { return lanes_[in_flight_.back()]->camera; }

void ViewScheduler::start(const ViewRequest& request) {
    const int mode = views_at_once();
    const Camera& cam = request.camera;
    // One at a time: the lane of the last view goes on (a step of one view); two: the other lane
    // (the last view's lane is busy, or was the last to start).
    const int lane = last_lane_ < 0 ? 0 : mode == 2 ? 1 - last_lane_ : last_lane_;
    if (last_lane_ >= 0) {  // the camera's step: the eye's and the target's moves over the distance
        const Camera& prev = lanes_[last_lane_]->camera;
        const double dist = std::max(glm::length(prev.eye() - prev.target()), 1e-300);
        const double step = (glm::length(cam.eye() - prev.eye()) + glm::length(cam.target() - prev.target())) / dist;
        const double clamped = std::min(step, 10.0);
        step_ = steps_seen_++ == 0 ? clamped : 0.75 * step_ + 0.25 * clamped;
    }
    last_lane_ = lane;
    Lane& L = *lanes_[lane];
    L.session->set_threads(std::max(1, threads_ / mode));  // (the lane is idle: not in flight)
    in_flight_.push_back(lane);
    L.camera = cam;
    L.mode = mode;
    L.done = false;
    L.job = L.thread.post([this, &L, request] {
        compute(model_, *L.session, request, L.result);
        L.done = true;
        if (wake_) wake_();  // (thread-safe) wakes the window's wait
    });
}

// The pipeline for one view on its lane's thread: features -> visibility -> line quads (or the
// stylized drawing). It reads the model and uses the lane's session; the caller touches neither
// until the view is taken.
void ViewScheduler::compute(const Model& model, ViewSession& session, const ViewRequest& request, FinishedView& j) {
    const Camera& cam = request.camera;
    const double cpu0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    if (!request.detail) session.find(cam);  // find, then visibility: the same as render(), timed apart
    const double cpu1 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    View& view = request.detail ? request.detail->render(cam) : session.visibility(cam);
    j.has_coat = request.detail != nullptr;
    if (request.detail)  // (the original model's box: the depth range stays put while the mesh adapts)
        j.coat.build(request.detail->drawn_model().topology(), model.topology().bounds.center(),
                     model.topology().bounds.half_diagonal());
    j.times = StageTimes{};
    j.times.cpu_features = cpu1 - cpu0;
    j.times.cpu_visibility = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu1;
    j.view = &view;
    j.camera = cam;
    j.times.features = request.detail ? 0.0 : session.seconds_features();
    j.times.search = view.features.stats.seconds_search;
    j.times.chain = view.features.stats.seconds_chain;
    j.times.visibility = view.drawing.stats.seconds_visibility;
    j.recall = -1.0;
    if (request.recall && !request.detail) {  // (with --detail the lines are another mesh's)
        const auto tr = StageClock::now();
        const Features ref = extract_features(model.topology(), cam, request.kinds);
        const double all = edges_length(model.topology(), ref.silhouette_edges);
        j.recall = all > 0.0 ? edges_length(model.topology(), view.features.silhouette_edges) / all : 1.0;
        j.times.recall = seconds_since(tr);
    }
    const auto tl = StageClock::now();
    j.styled = request.style != nullptr;
    if (request.style) {  // what render --style writes, as pixels
        const Model& drawn = request.detail ? request.detail->drawn_model() : model;
        styled_to_pixels(stylize_view(drawn, cam, view, *request.style, request.hidden), j.pixels);
        j.lines.clear();
    } else {
        build_line_mesh(view.drawing, request.lines, j.lines);
    }
    j.times.lines = seconds_since(tl);
    j.cpu = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu0;
}

bool ViewScheduler::oldest_done() {
    if (in_flight_.empty()) return false;
    Lane& L = *lanes_[in_flight_.front()];
    // (done is set as the job's last step, just before its future is ready: then wait for it)
    return L.done.load() ? (L.job.wait(), true) : L.job.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

bool ViewScheduler::take_oldest(FinishedView& into) {
    if (in_flight_.empty()) return false;
    Lane& L = *lanes_[in_flight_.front()];
    in_flight_.pop_front();
    const auto t = StageClock::now();
    L.job.get();
    std::swap(into, L.result);
    into.waited = seconds_since(t);
    into.views_at_once = L.mode;
    into.stats = into.view->drawing.stats;
    into.times.pieces = into.stats.seconds_pieces;
    into.times.propagation = into.stats.seconds_propagation;
    into.times.walks = into.stats.seconds_walks;
    into.times.rays = into.stats.seconds_ray_tests;
    return true;
}

}  // namespace inkline
