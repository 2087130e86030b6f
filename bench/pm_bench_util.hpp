// Helpers shared by the progressive mesh's bench programs (pm_dolly, pm_frames): memory from
// /proc. CPU time (the machine is shared, so wall time overstates the work) and wall time:
// core/clock.hpp.
#pragma once

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

}  // namespace inkline::bench
