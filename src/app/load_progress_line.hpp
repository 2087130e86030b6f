// The progress line of a long load on stderr, in the shared format of the commands' progress line
// (app/progress.hpp) with the file's size as its total:
//   "loading armadillo@3.off: 45120/100270 kB   45%  7520 kB/s  0:06 left"
// The count is the load's fraction of the whole (reading, repairs, order and topology: the
// stages of model/load_progress.hpp) in kB of the file, so the rate is the file's size over the
// whole load's time, and the time left follows from it. ProgressLine's rules hold: nothing the
// first half second, nothing when stderr is not a terminal, the line cleared when the load is done.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "app/progress.hpp"
#include "model/load_progress.hpp"

namespace inkline {

// The line's total for a file of `file_bytes`: its size in kB, rounded up (at least 1).
std::size_t load_progress_total_kb(std::uint64_t file_bytes);

// Reports on `line` (made with load_progress_total_kb of the file as its total): each report sets
// done to the fraction of the total; the last one (done) finishes the line.
LoadProgressCallback load_progress_callback(std::shared_ptr<ProgressLine> line);

// On stderr, labelled "loading PATH"; none (an empty callback) when stderr is not a terminal.
LoadProgressCallback load_progress_line(const std::string& path);

}  // namespace inkline
