// Wall time for the pipeline's own stage timers (DrawingStats' seconds, the window's stage times).
#pragma once

#include <chrono>

namespace inkline {

using StageClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(StageClock::time_point t0) {
    return std::chrono::duration<double>(StageClock::now() - t0).count();
}

}  // namespace inkline
