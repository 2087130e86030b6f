#include "app/batch.hpp"

#include <atomic>
#include <cctype>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "app/flags.hpp"
#include "core/error.hpp"

namespace inkline {

namespace {
std::string unescape_percent(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        out += s[i];
        if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
    }
    return out;
}
}  // namespace

OutputPattern::OutputPattern(const std::string& pattern) : pattern_(pattern) {
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') continue;
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            ++i;
            continue;
        }
        std::size_t j = i + 1;
        const bool zero = j < pattern.size() && pattern[j] == '0';
        if (zero) ++j;
        int width = 0;
        while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) && width < 100)
            width = 10 * width + (pattern[j++] - '0');
        if (j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i'))
            throw BadValue("--output: '" + pattern +
                           "' has a '%' that is no frame number (expected %d, %4d or %04d; %% for a '%')");
        if (numbered_) throw BadValue("--output: '" + pattern + "' has more than one frame number (one %d)");
        if (width > 12) throw BadValue("--output: '" + pattern + "': a frame number of at most 12 digits");
        numbered_ = true;
        zero_pad_ = zero;
        width_ = width;
        before_ = unescape_percent(pattern.substr(0, i));
        after_ = pattern.substr(j + 1);
        i = j;
    }
    if (numbered_) after_ = unescape_percent(after_);
    else before_ = unescape_percent(pattern);
}

std::string OutputPattern::name(long frame) const {
    if (!numbered_) return before_;
    std::string digits = std::to_string(frame);
    if (int(digits.size()) < width_) digits.insert(0, std::size_t(width_) - digits.size(), zero_pad_ ? '0' : ' ');
    return before_ + digits + after_;
}

FrameRange parse_frame_range(const std::string& text) {
    const auto colon = text.find(':');
    const auto number = [&](const std::string& s) { return long(parse_integer("--frame-range", s, 0, 999999999)); };
    FrameRange r;
    try {
        r.first = number(text.substr(0, colon));
        r.last = colon == std::string::npos ? r.first : number(text.substr(colon + 1));
    } catch (const Error&) {
        throw Error("--frame-range", "expected A:B or A, frame numbers from 0, got '" + text + "'");
    }
    if (r.last < r.first) throw Error("--frame-range", "the first frame is after the last ('" + text + "')");
    return r;
}

void FrameRange::check(long count) const {
    if (given() && last >= count)
        throw BadValue("--frame-range: " + std::to_string(first) + ":" + std::to_string(last) +
                       " leaves the run's frames 0:" + std::to_string(count - 1));
}

void run_jobs(int jobs, std::size_t count, const std::function<void(std::size_t)>& work) {
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr first_error;
    std::mutex error_mutex;
    const auto loop = [&] {
        while (!failed.load()) {
            const std::size_t i = next.fetch_add(1);
            if (i >= count) break;
            try {
                work(i);
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!first_error) first_error = std::current_exception();
                failed = true;
            }
        }
    };
    const std::size_t threads = std::min<std::size_t>(std::size_t(std::max(1, jobs)), count);
    std::vector<std::thread> helpers;
    for (std::size_t t = 1; t < threads; ++t) helpers.emplace_back(loop);
    loop();
    for (std::thread& t : helpers) t.join();
    if (first_error) std::rethrow_exception(first_error);
}

}  // namespace inkline
