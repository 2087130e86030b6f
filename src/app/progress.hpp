// A progress line for the long runs of the commands (bench, batch renders, subdivision):
//   "render: 37/120 frames  30%  2.41 frames/s  0:34 left"
// rewritten in place with '\r' on stderr, and only when stderr is a terminal: a log file or a
// pipe gets none of it (scripts that read stderr see exactly what they saw before).
//
// Why the rules: nothing the first half second (a short run stays quiet), at most ten writes a
// second (a terminal over ssh is slow, and a fast loop must not spend its time printing), and
// the line cleared at the end, so that what the command prints next starts on a clean line.
// Updates may come from several threads (a batch render's jobs); each call takes a lock.
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <string>

namespace inkline {

class ProgressLine {
public:
    using Clock = std::function<double()>;  // seconds, never going back

    // `label`: "render"; `unit`: "frames" (the count and the rate are in it). Writes to `out`
    // only if `terminal`. `clock` is read at construction (the start) and at each update.
    ProgressLine(std::string label, std::size_t total, std::string unit, std::ostream& out, bool terminal,
                 Clock clock);
    // On stderr, shown when stderr is a terminal and `enabled` (false: --quiet), steady clock.
    static std::unique_ptr<ProgressLine> on_stderr(std::string label, std::size_t total, std::string unit,
                                                   bool enabled = true);
    ~ProgressLine();  // finish()
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    void advance(std::size_t n = 1);
    void set_done(std::size_t done);
    // Clears the line, runs `print` (which writes to another stream, e.g. a frame's report on
    // stdout), and draws the line again at the next update.
    void print_above(const std::function<void()>& print);
    // Clears the line for good (later updates write nothing). Idempotent.
    void finish();
    std::size_t total() const { return total_; }

    // The text of the line for `done` of `total` after `elapsed_s` seconds (no '\r'); exposed for
    // the tests. The rate and the time left appear once something is done.
    static std::string text(const std::string& label, std::size_t done, std::size_t total, const std::string& unit,
                            double elapsed_s);

    static constexpr double kQuietSeconds = 0.5;   // nothing shown before
    static constexpr double kMinInterval = 0.1;    // between two writes (the last one always goes)

private:
    void update_locked(std::size_t done);
    void clear_locked();
    std::mutex mutex_;
    std::string label_, unit_;
    std::size_t total_ = 0, done_ = 0;
    std::ostream* out_;
    bool terminal_, finished_ = false;
    Clock clock_;
    double start_ = 0.0, last_write_ = -1.0;
    std::size_t shown_width_ = 0;  // characters on the terminal now (0: nothing shown)
};

// "0:34", "12:05", "1:02:09": a duration rounded up to whole seconds.
std::string format_duration(double seconds);

}  // namespace inkline
