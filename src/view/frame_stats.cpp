#include "view/frame_stats.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace inkline {

void StageTimes::add(const StageTimes& o, double k) {
    cpu_features += k * o.cpu_features, cpu_visibility += k * o.cpu_visibility;
    features += k * o.features, search += k * o.search, chain += k * o.chain, visibility += k * o.visibility;
    pieces += k * o.pieces, propagation += k * o.propagation, walks += k * o.walks, rays += k * o.rays;
    recall += k * o.recall, lines += k * o.lines, draw += k * o.draw, frame += k * o.frame, wait += k * o.wait;
}

void FrameStats::view_taken(const StageTimes& view, int views_at_once, double cpu, std::size_t silhouette_edges) {
    if (measuring_) {  // (--fps: the views after the first frame's, however many a frame takes)
        view_total_.add(view);
        ++views_measured_;
        ++views_by_mode_[views_at_once - 1];
        worker_cpu_ += cpu;
    }
    last_silhouettes_ = silhouette_edges;
}

void FrameStats::slept(bool asleep) {
    asleep_ = asleep;
    if (asleep) slept_since_view_ = slept_since_frame_ = true;
}

void FrameStats::view_arrived(Clock::time_point now) {
    if (last_fresh_ != Clock::time_point{} && !slept_since_view_) {
        const double period = std::chrono::duration<double>(now - last_fresh_).count();
        view_period_ = view_period_ > 0.0 ? 0.9 * view_period_ + 0.1 * period : period;
    }
    last_fresh_ = now;
    slept_since_view_ = false;
}

void FrameStats::frame_drawn(const StageTimes& frame, bool fresh, int index, bool last, Clock::time_point now) {
    if (fresh) {
        shown_.add(shown_, -0.1);  // what the panel shows: a moving average
        shown_.add(frame, 0.1);
    } else {  // the window's own frame: no new view
        shown_.draw = 0.9 * shown_.draw + 0.1 * frame.draw;
    }
    // The window's frame rate: between frames drawn (the first waits for the lazy indexes; a
    // frame after a sleep until input waited for the user).
    if (index > 0 && last_drawn_ != Clock::time_point{} && !slept_since_frame_) {
        const double period = std::chrono::duration<double>(now - last_drawn_).count();
        window_period_ = window_period_ > 0.0 ? 0.9 * window_period_ + 0.1 * period : period;
    }
    last_drawn_ = now;
    slept_since_frame_ = false;
    if (last) return;
    if (index == 0) {
        shown_ = frame;
        t_measure_ = Clock::now();  // the first frame builds the lazy indexes: not measured
        cpu_main0_ = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
        cpu_all0_ = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID);
        measuring_ = true;  // the views taken from now on
    } else {
        total_.add(frame);
        ++measured_;
    }
}

void FrameStats::stop_clock() { wall_ = seconds_since(t_measure_); }

const PanelNumbers& FrameStats::panel_numbers(const DrawingStats& stats, double recall, Clock::time_point now) {
    // (and sooner while the snapshot has no view's numbers yet: a short run's panel showed zeros)
    const bool empty = panel_numbers_.stats.triangles == 0 || panel_numbers_.views_per_s == 0.0;
    // (at once when the window falls asleep or wakes: the line then says which)
    if (empty || panel_numbers_.still != asleep_ || now - panel_numbers_at_ >= std::chrono::milliseconds(250)) {
        panel_numbers_ = {shown_, stats, view_period_ > 0 ? 1.0 / view_period_ : 0.0,
                          window_period_ > 0 ? 1.0 / window_period_ : 0.0, recall, asleep_};
        panel_numbers_at_ = now;
    }
    return panel_numbers_;
}

void FrameStats::print_report(const FpsContext& c) {
    if (measured_ <= 0) return;
    if (c.interactive) stop_clock();
    const double k = 1000.0 / measured_;
    const double kv = 1000.0 / std::max(views_measured_, 1);  // per view (as many as frames)
    const StageTimes& v = view_total_;
    const double cpu_main = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu_main0_;
    const double cpu_all = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu_all0_;
    // (With two views at once, a view's stages take about twice a frame: they overlap.)
    std::printf("fps: %.1f over %d frames (after the first) of %d triangles, %.2f ms/frame; views: %d one at "
                "a time on %d thread%s, %d two at once on %d thread%s each; pipeline per view: features %.2f "
                "(search %.2f, chain %.2f), visibility %.2f (pieces %.2f, propagation %.2f, walks %.2f, ray "
                "tests %.2f), line quads %.2f; main thread: GL draw+swap %.2f, waiting for the pipeline %.2f; "
                "%zu silhouette edges, %zu line vertices in the last frame\n",
                measured_ / wall_, measured_, int(c.triangles), wall_ * k, views_by_mode_[0], c.threads,
                c.threads > 1 ? "s" : "", views_by_mode_[1], std::max(1, c.threads / 2), c.threads / 2 > 1 ? "s" : "",
                v.features * kv, v.search * kv, v.chain * kv, v.visibility * kv, v.pieces * kv, v.propagation * kv,
                v.walks * kv, v.rays * kv, v.lines * kv, total_.draw * k, total_.wait * k, last_silhouettes_,
                c.line_vertices);
    // On a loaded machine wall time is inflated; CPU time is the work itself (Mesa's llvmpipe
    // rasterizes on threads of its own, counted in the rest with the visibility's helper threads).
    const double cpu_rest = cpu_all - cpu_main - worker_cpu_;
    std::printf("cpu: pipeline %.2f ms/view on its lane's thread (features %.2f, visibility %.2f), main thread "
                "%.2f ms/frame, all threads of the process %.2f ms/frame, of which other threads %.2f (X server "
                "not included)\n",
                worker_cpu_ * kv, v.cpu_features * kv, v.cpu_visibility * kv, cpu_main * k, cpu_all * k, cpu_rest * k);
}

}  // namespace inkline
