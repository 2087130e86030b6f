#include "app/progress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <unistd.h>

namespace inkline {

std::string format_duration(double seconds) {
    const long s = seconds > 0.0 ? long(std::ceil(seconds)) : 0;
    char buf[32];
    if (s >= 3600) std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
    return buf;
}

namespace {
// Three significant figures or so, without an exponent: "0.25", "2.41", "12.3", "1234".
std::string format_rate(double rate) {
    char buf[32];
    std::snprintf(buf, sizeof buf, rate >= 100.0 ? "%.0f" : rate >= 10.0 ? "%.1f" : "%.2f", rate);
    return buf;
}
}  // namespace

std::string ProgressLine::text(const std::string& label, std::size_t done, std::size_t total, const std::string& unit,
                               double elapsed_s) {
    const std::size_t shown = std::min(done, total);
    const int percent = total > 0 ? int(100.0 * double(shown) / double(total)) : 100;
    char pct[16];
    std::snprintf(pct, sizeof pct, "%3d%%", percent);
    std::string line = label + ": " + std::to_string(shown) + "/" + std::to_string(total) + " " + unit + "  " + pct;
    if (shown > 0 && elapsed_s > 0.0) {
        const double rate = double(shown) / elapsed_s;
        line += "  " + format_rate(rate) + " " + unit + "/s  " + format_duration(double(total - shown) / rate) + " left";
    }
    return line;
}

ProgressLine::ProgressLine(std::string label, std::size_t total, std::string unit, std::ostream& out, bool terminal,
                           Clock clock)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), out_(&out), terminal_(terminal),
      clock_(std::move(clock)) {
    start_ = clock_();
}

std::unique_ptr<ProgressLine> ProgressLine::on_stderr(std::string label, std::size_t total, std::string unit,
                                                      bool enabled) {
    const auto t0 = std::chrono::steady_clock::now();
    return std::make_unique<ProgressLine>(
        std::move(label), total, std::move(unit), std::cerr, enabled && ::isatty(STDERR_FILENO) == 1,
        [t0] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); });
}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::advance(std::size_t n) {
    std::lock_guard<std::mutex> lock(mutex_);
    update_locked(done_ + n);
}

void ProgressLine::set_done(std::size_t done) {
    std::lock_guard<std::mutex> lock(mutex_);
    update_locked(done);
}

void ProgressLine::update_locked(std::size_t done) {
    done_ = done;
    if (!terminal_ || finished_) return;
    const double now = clock_(), elapsed = now - start_;
    if (elapsed < kQuietSeconds) return;
    if (last_write_ >= 0.0 && now - last_write_ < kMinInterval && done_ < total_) return;
    const std::string line = text(label_, done_, total_, unit_, elapsed);
    // Spaces over what a longer line left behind.
    *out_ << '\r' << line << std::string(shown_width_ > line.size() ? shown_width_ - line.size() : 0, ' ')
          << std::flush;
    shown_width_ = std::max(shown_width_, line.size());
    last_write_ = now;
}

void ProgressLine::clear_locked() {
    if (shown_width_ == 0) return;
    *out_ << '\r' << std::string(shown_width_, ' ') << '\r' << std::flush;
    shown_width_ = 0;
}

void ProgressLine::print_above(const std::function<void()>& print) {
    std::lock_guard<std::mutex> lock(mutex_);
    clear_locked();
    last_write_ = -1.0;  // draw again at the next update
    print();
    std::fflush(stdout);
}

void ProgressLine::finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    clear_locked();
    finished_ = true;
}

}  // namespace inkline
