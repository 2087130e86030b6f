// The preview window's frame statistics: each view's stage times, the moving averages the panel
// shows (views a second, the window's frames a second), and the `--fps` report over a headless
// run. No OpenGL here: the loop tells it what happened, it keeps the numbers.
#pragma once

#include <cstddef>
#include <ctime>

#include "core/clock.hpp"
#include "core/drawing.hpp"

namespace inkline {

// Seconds spent in each stage of a view or a frame.
struct StageTimes {
    double features = 0, search = 0, chain = 0, visibility = 0, recall = 0, lines = 0, draw = 0, frame = 0, wait = 0;
    double pieces = 0, propagation = 0, walks = 0, rays = 0;  // visibility's stages (DrawingStats)
    double cpu_features = 0, cpu_visibility = 0;  // CPU time of the pipeline thread
    void add(const StageTimes& o, double k = 1.0);
};

// What the panel's statistics show: a snapshot taken a few times a second (numbers that change
// every frame cannot be read, and would make the panel be rasterized every frame).
struct PanelNumbers {
    StageTimes times;
    DrawingStats stats;
    double views_per_s = 0.0, fps = 0.0, recall = -1.0;
    bool still = false;  // the window sleeps until input: no view asked, no frame rate to show
};

// The facts the `--fps` report adds to the measured times.
struct FpsContext {
    std::size_t triangles = 0;
    int threads = 1;                  // the pipeline's threads (split between two views at once)
    std::size_t line_vertices = 0;    // in the last frame
    bool interactive = false;         // the measured time ends now (no headless last frame)
};

class FrameStats {
public:
    using Clock = StageClock;

    // A view was taken from the pipeline: `view` its own stage times, `views_at_once` when it was
    // started (1 or 2), `cpu` its lane thread's CPU seconds, `silhouette_edges` its count.
    void view_taken(const StageTimes& view, int views_at_once, double cpu, std::size_t silhouette_edges);
    // The newest view arrived this frame (the time between views, smoothed; the time since the
    // last view is not a period when the window slept in between).
    void view_arrived(Clock::time_point now = Clock::now());
    // The loop slept until input (a still camera, nothing in flight): the next frame's and the
    // next view's time since the last are not rates, and the panel says the window is still.
    void slept(bool asleep);
    // A frame was drawn: `frame` its times (draw, frame, wait, and those of the views it took),
    // `fresh` whether it shows a new view, `index` the loop's frame number, `last` the headless
    // run's last frame (not measured: it only draws). Frame 0 starts the measurement (it builds
    // the lazy indexes: not measured).
    void frame_drawn(const StageTimes& frame, bool fresh, int index, bool last, Clock::time_point now = Clock::now());
    // Ends the measured wall time (headless, at the last frame; interactive, print_report does).
    void stop_clock();
    // The panel's numbers, refreshed every 250 ms (sooner while they have no view's numbers yet).
    const PanelNumbers& panel_numbers(const DrawingStats& stats, double recall, Clock::time_point now = Clock::now());
    // Prints the `fps:` and `cpu:` lines (nothing when no frame was measured).
    void print_report(const FpsContext& context);

private:
    StageTimes shown_;                // moving average of the views' times: what the panel shows
    StageTimes total_;                // the measured frames' times
    int measured_ = 0;                // frames measured (after the first)
    double cpu_main0_ = 0.0, cpu_all0_ = 0.0, wall_ = 0.0;
    Clock::time_point t_measure_ = Clock::now();
    // --fps: the views taken after the first frame, their times and their lanes' CPU time.
    bool measuring_ = false;
    StageTimes view_total_;
    int views_measured_ = 0, views_by_mode_[2] = {0, 0};  // (by views at once when each started)
    double worker_cpu_ = 0.0;
    std::size_t last_silhouettes_ = 0;
    Clock::time_point last_fresh_{};  // when the last view arrived
    double view_period_ = 0.0;        // moving average of the time between views
    double window_period_ = 0.0;      // moving average of the window's frame time
    Clock::time_point last_drawn_{};
    bool asleep_ = false;               // the loop is sleeping until input
    bool slept_since_view_ = false;     // ... or slept since the last view arrived
    bool slept_since_frame_ = false;    // ... or since the last frame was drawn
    PanelNumbers panel_numbers_;
    Clock::time_point panel_numbers_at_{};
};

}  // namespace inkline
