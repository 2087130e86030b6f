#include "app/load_progress_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace inkline {

std::size_t load_progress_total_kb(std::uint64_t file_bytes) {
    return std::max<std::size_t>(1, std::size_t((file_bytes + 999) / 1000));
}

LoadProgressCallback load_progress_callback(std::shared_ptr<ProgressLine> line) {
    return [line = std::move(line)](const LoadProgress& p) {
        if (p.done) {
            line->finish();
            return;
        }
        line->set_done(std::size_t(std::floor(p.fraction * double(line->total()))));
    };
}

LoadProgressCallback load_progress_line(const std::string& path) {
    if (!::isatty(STDERR_FILENO)) return {};
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(path, error);
    std::shared_ptr<ProgressLine> line =
        ProgressLine::on_stderr("loading " + path, load_progress_total_kb(error ? 0 : bytes), "kB");
    return load_progress_callback(std::move(line));
}

}  // namespace inkline
