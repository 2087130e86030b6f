// Progress of a long load, reported through LoadOptions::progress (model/mesh_io.hpp): the
// parsers report how far into the file they are, Assimp how far it has read, then the repairs and
// the topology their stage. Calls are throttled (a change of at least 1/256 of the whole, or a
// new stage) so that reporting costs nothing measurable.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>

namespace inkline {

struct LoadProgress {
    double fraction = 0.0;            // of the whole load, 0 to 1, never decreasing
    std::uint64_t file_bytes = 0;     // the file's size
    std::uint64_t bytes_read = 0;     // how far into the file the reader is (file_bytes once read)
    bool done = false;                // the last call of a load (fraction 1)
};
using LoadProgressCallback = std::function<void(const LoadProgress&)>;

// The stages' shares of the whole, in order: about their shares of the time (measured with
// bench/load_probe on armadillo@2 and @3, .glb and OFF: reading and parsing a quarter to a third,
// the repairs a quarter, the Hilbert order and the topology a fifth each).
inline constexpr double kProgressParsed = 0.3;     // the file read and parsed
inline constexpr double kProgressRepaired = 0.55;  // welded, checked and repaired
inline constexpr double kProgressOrdered = 0.75;   // in Hilbert order; the topology follows

class LoadProgressReporter {
public:
    LoadProgressReporter(const LoadProgressCallback* callback, std::uint64_t file_bytes)
        : callback_(callback && *callback ? callback : nullptr) {
        state_.file_bytes = file_bytes;
    }
    bool active() const { return callback_ != nullptr; }
    // `bytes` of the file read, mapped linearly onto [from, to] of the whole.
    void bytes(std::uint64_t bytes, double from, double to) {
        if (!callback_) return;
        const double share = state_.file_bytes ? double(std::min(bytes, state_.file_bytes)) / double(state_.file_bytes) : 1.0;
        state_.bytes_read = std::min(bytes, state_.file_bytes);
        report(from + (to - from) * share, false);
    }
    // `fraction` of the whole reached (bytes read unchanged); reported when it advanced.
    void at(double fraction) {
        if (callback_) report(fraction, true);
    }
    // A stage finished: the file is read whole from here on.
    void stage(double fraction) {
        if (!callback_) return;
        state_.bytes_read = state_.file_bytes;
        report(fraction, true);
    }
    void finish() {
        if (!callback_) return;
        state_.bytes_read = state_.file_bytes;
        state_.fraction = 1.0;
        state_.done = true;
        (*callback_)(state_);
    }

private:
    void report(double fraction, bool always) {
        fraction = std::clamp(fraction, state_.fraction, 1.0);
        if (fraction - last_ < (always ? 1e-9 : 1.0 / 256)) return;
        state_.fraction = last_ = fraction;
        (*callback_)(state_);
    }
    const LoadProgressCallback* callback_;
    LoadProgress state_;
    double last_ = 0.0;
};

}  // namespace inkline
