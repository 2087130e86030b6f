#include "view/detail_source.hpp"

#include <algorithm>
#include <cstdio>

#include "detail/multiscale.hpp"
#include "detail/multiscale_cache.hpp"
#include "detail/progressive_mesh_cache.hpp"
#include "detail/progressive_mesh_session.hpp"

namespace inkline {

DetailSource::DetailSource(const Model& model, const std::string& method, double target_px, double depth_exponent,
                           const DetailPreprocess& pre)
    : model_(model), method_(method), target_px_(target_px), depth_exponent_(depth_exponent) {
    const bool cached = !pre.cache_dir.empty();
    if (method_ == "pm" && !cached) {
        pm_ = std::make_unique<ProgressiveMesh>(model.topology());
    } else if (method_ == "pm") {
        CachedHierarchy c = cached_progressive_mesh(model.topology(), pre.model_path, pre.variant, pre.cache_dir);
        pm_ = std::move(c.pm);
        cache_warning_ = c.problem;
    } else if (!cached) {
        levels_ = std::make_unique<MultiscaleLevels>(build_multiscale_levels(model, pre.levels));
    } else {
        CachedLevels c = cached_multiscale_levels(model, pre.model_path, pre.variant, pre.levels, pre.cache_dir);
        levels_ = std::make_unique<MultiscaleLevels>(std::move(c.levels));
        cache_warning_ = c.problem;
    }
}

DetailSource::~DetailSource() = default;

void DetailSource::reset(const ViewOptions& options) {
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
    return pm_session_ ? pm_session_->adapted() : ms_session_->blended();
}

std::string DetailSource::summary() const {
    std::lock_guard<std::mutex> lock(summary_mutex_);
    return summary_;
}

}  // namespace inkline
