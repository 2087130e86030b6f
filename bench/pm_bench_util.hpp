// Helpers shared by the progressive mesh's bench programs (pm_dolly, pm_frames): memory from
// /proc and the process's and thread's CPU time (the machine is shared, so wall time overstates
// the work). Wall time: core/clock.hpp's seconds_since.
#pragma once

#include <ctime>
#include <fstream>
#include <string>

namespace inkline::bench {

// A /proc/self/status field in MiB (VmRSS now, VmHWM the peak so far); 0 when absent.
inline double status_mib(const std::string& field) {
    std::ifstream in("/proc/self/status");
    std::string key;
    double kib = 0.0;
    while (in >> key)
        if (key == field + ":") {
            in >> kib;
            break;
        }
    return kib / 1024.0;
}

// CPU seconds of the whole process.
inline double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// CPU seconds of the calling thread: one core's work, whatever the other threads do.
inline double thread_seconds() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace inkline::bench
