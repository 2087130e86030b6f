#include "app/load_progress_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>

namespace inkline {

LoadProgressCallback load_progress_line(const std::string& path) {
    if (!::isatty(STDERR_FILENO)) return {};
    struct State {
        std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
        bool shown = false;
        std::uint64_t bytes = 0;  // the most read so far (later stages report none)
        double rate_mb = 0.0;     // MB/s while the file was read
    };
    auto state = std::make_shared<State>();
    return [path, state](const LoadProgress& p) {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - state->start).count();
        if (p.done) {
            if (state->shown) std::fprintf(stderr, "\r\033[K");
            return;
        }
        if (p.bytes_read > state->bytes) {
            state->bytes = p.bytes_read;
            state->rate_mb = double(state->bytes) / std::max(seconds, 1e-3) / 1e6;
        }
        if (seconds < 1.0 || p.fraction <= 0.0) return;
        const double left = seconds * (1.0 - p.fraction) / p.fraction;
        std::fprintf(stderr, "\r\033[Kinkline: loading %s: %d%% (%.1f MB/s, %.0f s left)", path.c_str(),
                     int(100.0 * p.fraction), state->rate_mb, left);
        std::fflush(stderr);
        state->shown = true;
    };
}

}  // namespace inkline
