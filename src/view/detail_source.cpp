#include "view/detail_source.hpp"

#include <algorithm>
#include <cstdio>

#include "detail/multiscale.hpp"
#include "detail/multiscale_cache.hpp"
#include "detail/progressive_mesh_cache.hpp"
#include "detail/progressive_mesh_session.hpp"

namespace inkline {

namespace {
// Thrown by the pre-process's progress when the source is destroyed: it stops the build.
struct PreprocessStopped {};
}  // namespace

DetailSource::DetailSource(const Model& model, const std::string& method, double target_px, double depth_exponent,
                           const DetailPreprocess& pre, std::function<void()> progress_changed)
    : model_(model), method_(method), target_px_(target_px), depth_exponent_(depth_exponent),
      progress_changed_(std::move(progress_changed)) {
    prepared_ = std::async(std::launch::async, [this, pre] { prepare(pre); }).share();
}

void DetailSource::prepare(const DetailPreprocess& pre) {
    const auto step = [this](double fraction) {
        if (stop_.load()) throw PreprocessStopped{};
        fraction_.store(std::clamp(fraction, 0.0, 1.0));
        if (progress_changed_) progress_changed_();
    };
    const ProgressiveMesh::BuildProgress pm_step = [&](std::size_t done, std::size_t most) {
        step(most > 0 ? double(done) / double(most) : 1.0);
    };
    MultiscaleOptions levels = pre.levels;
    levels.progress = [&](int done, int total) { step(total > 0 ? double(done) / total : 1.0); };
    try {
        const bool cached = !pre.cache_dir.empty();
        if (method_ == "pm" && !cached) {
            pm_ = std::make_unique<ProgressiveMesh>(model_.topology(), pm_step);
        } else if (method_ == "pm") {
            CachedHierarchy c =
                cached_progressive_mesh(model_.topology(), pre.model_path, pre.variant, pre.cache_dir, pm_step);
            pm_ = std::move(c.pm);
            cache_warning_ = c.problem;
        } else if (!cached) {
            levels_ = std::make_unique<MultiscaleLevels>(build_multiscale_levels(model_, levels));
        } else {
            CachedLevels c = cached_multiscale_levels(model_, pre.model_path, pre.variant, levels, pre.cache_dir);
            levels_ = std::make_unique<MultiscaleLevels>(std::move(c.levels));
            cache_warning_ = c.problem;
        }
    } catch (const PreprocessStopped&) {
        return;  // (the source is being destroyed: nothing will ask for it)
    }
    fraction_.store(1.0);
    if (progress_changed_) progress_changed_();
}

DetailSource::~DetailSource() {
    stop_.store(true);
    if (prepared_.valid()) prepared_.wait();
}

bool DetailSource::ready() const {
    return prepared_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void DetailSource::wait_ready() const { prepared_.get(); }

std::string DetailSource::preparation_text() const {
    return method_ == "pm" ? "building the progressive mesh hierarchy" : "smoothing the multi-scale levels";
}

void DetailSource::reset(const ViewOptions& options) {
    wait_ready();
    if (pm_) {
        pm_session_ = std::make_unique<PmSession>(*pm_, options, PmViewOptions::for_path(model_, target_px_.load()));
        settled_ = false;
    } else {
        ms_session_ = std::make_unique<MultiscaleSession>(
            model_, *levels_, options,
            MultiscaleViewOptions{.target_px = target_px_.load(), .depth_exponent = depth_exponent_});
    }
}

View& DetailSource::render(const Camera& camera) {
    wait_ready();
    const auto now = std::chrono::steady_clock::now();
    char line[160];
    if (ms_session_) {
        ms_session_->set_target(target_px_.load());
        View& v = ms_session_->render(camera);
        std::snprintf(line, sizeof line, "multiscale: target %.2g px, blend %.1f ms", target_px_.load(),
                      ms_session_->seconds_blend() * 1e3);
        std::lock_guard<std::mutex> lock(summary_mutex_);
        summary_ = line;
        return v;
    }
    pm_session_->set_target(target_px_.load());
    if (!settled_) pm_session_->settle(camera);
    const double dt = !settled_         ? 1.0 / 25.0
                      : fixed_step_ > 0.0 ? fixed_step_
                                          : std::clamp(std::chrono::duration<double>(now - last_view_).count(), 1.0 / 60.0, 0.25);
    settled_ = true;
    last_view_ = now;
    View& v = pm_session_->render(camera, dt);
    const FrontStats& s = pm_session_->stats();
    morphing_.store(s.morphs_running > 0 || s.splits + s.collapses > 0 || s.deferred > 0);  // (deferred: the budget's)
    // (two lines: one is wider than the panel)
    std::snprintf(line, sizeof line, "pm: target %.2g px, %zu triangles\n%zu splits, %zu collapses, %zu morphs, %.1f ms",
                  target_px_.load(), s.triangles, s.splits, s.collapses, s.morphs_running, s.seconds * 1e3);
    std::lock_guard<std::mutex> lock(summary_mutex_);
    summary_ = line;
    return v;
}

const Model& DetailSource::drawn_model() const {
    wait_ready();
    return pm_session_ ? pm_session_->adapted() : ms_session_->blended();
}

std::string DetailSource::summary() const {
    std::lock_guard<std::mutex> lock(summary_mutex_);
    return summary_;
}

}  // namespace inkline
