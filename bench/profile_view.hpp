// What the single-stage profiling harnesses (appel_profile, pieces_profile) share: the default
// view of one sample mesh with its features, and a per-frame timer on this thread's CPU clock
// (less sensitive to other processes on a shared machine than wall time; the least frame, less
// still). For perf and valgrind --tool=callgrind.
#pragma once

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <optional>
#include <string>

#include "core/clock.hpp"
#include "bench_models.hpp"

struct ProfileView {
    const inkline::Model* model;
    inkline::Camera camera;
    inkline::Features features;
};

// The framing camera of mesh `name` (1024x1024, the default near plane) and its features, or
// nothing (with a message naming `tool`) when the mesh is not there.
inline std::optional<ProfileView> profile_view(const std::string& name, const char* tool) {
    const inkline::Model* m = bench_model_for(name, tool);
    if (!m) return std::nullopt;
    auto cam = inkline::Camera::framing(m->topology().bounds, 1024, 1024);
    cam.set_near(inkline::default_near(m->topology()));
    return ProfileView{m, cam, inkline::extract_features(m->topology(), cam)};
}

struct FrameTimes {
    double mean_ms = 0.0, least_ms = 0.0;
};

// Runs untimed() then timed() `frames` times; the mean and least CPU time of timed().
template <class Untimed, class Timed>
FrameTimes time_frames(int frames, Untimed&& untimed, Timed&& timed) {
    const auto now = inkline::thread_cpu_seconds;
    double seconds = 0.0, best = 1e30;
    for (int k = 0; k < frames; ++k) {
        untimed();
        const double t0 = now();
        timed();
        const double dt = now() - t0;
        seconds += dt;
        best = std::min(best, dt);
    }
    return {1e3 * seconds / std::max(frames, 1), 1e3 * best};
}
