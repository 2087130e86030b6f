// Wall time for the pipeline's own stage timers (DrawingStats' seconds, the window's stage times).
#pragma once

#include <chrono>
#include <ctime>

namespace inkline {

using StageClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(StageClock::time_point t0) {
    return std::chrono::duration<double>(StageClock::now() - t0).count();
}

// CPU seconds of a clock: CLOCK_THREAD_CPUTIME_ID (the calling thread's work, whatever else runs
// on a shared machine) or CLOCK_PROCESS_CPUTIME_ID (all the process's threads).
inline double cpu_seconds(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
inline double thread_cpu_seconds() { return cpu_seconds(CLOCK_THREAD_CPUTIME_ID); }
inline double process_cpu_seconds() { return cpu_seconds(CLOCK_PROCESS_CPUTIME_ID); }
// Wall seconds from an arbitrary start, as a plain function (where a clock is chosen at run time).
inline double wall_seconds() { return std::chrono::duration<double>(StageClock::now().time_since_epoch()).count(); }

}  // namespace inkline
