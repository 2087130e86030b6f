// The progress line of a long load on stderr: "inkline: loading FILE: 45% (38.2 MB/s, 3 s left)"
// (the rate at which the file was read), rewritten in place from the first report after a second
// of loading, and cleared when the load is done. Nothing when stderr is not a terminal (logs and pipes get no carriage returns).
// One function, so that the commands' shared progress line (app/progress.hpp) can take its place.
#pragma once

#include <string>

#include "model/load_progress.hpp"

namespace inkline {

LoadProgressCallback load_progress_line(const std::string& path);

}  // namespace inkline
