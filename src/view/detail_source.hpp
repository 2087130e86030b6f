// The window's detail control (`view --detail=PX`): one stateful session, the progressive mesh's
// (geomorphs, smoothing: detail/progressive_mesh_session.hpp) or the multi-scale method's
// (detail/multiscale.hpp), drawing the window's views in order on one lane. No OpenGL here.
//
// Takes: the model, the method and the target size (the panel's slider may change it while a view
// is computed: it applies from the next view). Gives: each view, the model it was drawn from
// (the base coat's triangles) and a one-line summary for the panel.
//
// The method's pre-process (armadillo@2's hierarchy: about 20 s) is made on a thread of its own,
// so that the window can open, draw the model without detail control and show the progress
// meanwhile; what needs it waits for it.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>

#include "detail/multiscale.hpp"
#include "pipeline.hpp"

namespace inkline {

class ProgressiveMesh;
class PmSession;
class MultiscaleSession;

// How the method's pre-process is made: the multi-scale levels' options (--detail-fairing,
// --detail-smoothing), and with --cache the folder, the model's file and the loader's variant that
// key its files (detail/multiscale_cache.hpp, detail/progressive_mesh_cache.hpp).
struct DetailPreprocess {
    MultiscaleOptions levels;
    std::string cache_dir;  // empty: built every time
    std::string model_path, variant;
};

class DetailSource {
public:
    // Starts the method's pre-process (the hierarchy, or the smoothed levels: built, or read from
    // the cache) on a thread of its own. `progress_changed` (optional; on that thread) hears each
    // step of it and its end: the window wakes its loop to show them.
    DetailSource(const Model& model, const std::string& method, double target_px, double depth_exponent = 0.0,
                 const DetailPreprocess& preprocess = {}, std::function<void()> progress_changed = {});
    // Stops a pre-process still running (within about a hundredth of it) and waits for its thread.
    ~DetailSource();
    DetailSource(const DetailSource&) = delete;
    DetailSource& operator=(const DetailSource&) = delete;

    // Whether the pre-process is done (never waits).
    bool ready() const;
    // Waits for the pre-process; throws what it threw.
    void wait_ready() const;
    // The pre-process's fraction done in [0, 1] and a line saying what it is ("building the
    // progressive mesh hierarchy", "smoothing the multi-scale levels", or reading either).
    double preparation_fraction() const { return fraction_.load(); }
    std::string preparation_text() const;

    // (All below wait for the pre-process.)
    // New sessions for `options` (the panel changed the lines); no view may be in flight.
    void reset(const ViewOptions& options);
    // One view, on the lane's thread. pm: the front settles at the first view after a reset, then
    // geomorphs advance by the wall time since the last view (clamped to [1/60, 1/4] s).
    View& render(const Camera& camera);
    const Model& drawn_model() const;  // what the last view was drawn from
    // pm: geomorphs advance by this step a view instead of the wall time (0: the wall time), so that
    // a test's views do not depend on the machine's speed.
    void set_fixed_step(double seconds) { fixed_step_ = seconds; }
    void set_target(double target_px) { target_px_.store(target_px); }
    double target() const { return target_px_.load(); }
    const std::string& method() const { return method_; }
    // Geomorphs still running after the last view: the window asks for views until they end.
    bool morphing() const { return morphing_.load(); }
    std::string summary() const;
    // One line when the cache could not serve or keep the pre-process (a corrupt or stale file,
    // rebuilt; a folder not writable), else empty.
    const std::string& cache_warning() const {
        wait_ready();
        return cache_warning_;
    }

private:
    void prepare(const DetailPreprocess& pre);
    const Model& model_;
    std::string method_;
    std::atomic<double> target_px_;
    double depth_exponent_;
    std::unique_ptr<ProgressiveMesh> pm_;
    std::unique_ptr<PmSession> pm_session_;
    std::unique_ptr<MultiscaleLevels> levels_;
    std::unique_ptr<MultiscaleSession> ms_session_;
    std::string cache_warning_;
    std::atomic<double> fraction_{0.0};
    std::atomic<bool> stop_{false};  // the destructor's: the pre-process's progress throws
    std::function<void()> progress_changed_;
    std::shared_future<void> prepared_;  // the pre-process's thread (std::async)
    bool settled_ = false;
    double fixed_step_ = 0.0;
    std::chrono::steady_clock::time_point last_view_{};
    std::atomic<bool> morphing_{false};
    mutable std::mutex summary_mutex_;
    std::string summary_;
};

}  // namespace inkline
