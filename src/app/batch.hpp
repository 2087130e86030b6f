// The pieces of `inkline render`'s batch mode (several models, or --frames=N along an orbit):
// the numbered output names, the slice of frames a run renders (--frame-range), and the pool of
// jobs that renders frames in parallel. No rendering here (cli.cpp does it), so each is tested
// alone (tests/test_batch.cpp).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace inkline {

// An output name per frame from a printf-style pattern with at most one integer conversion:
// "out_%04d.svg" -> "out_0037.svg"; "%d", "%5d", "%05d" and "%i" are taken, "%%" is a literal
// '%'. Anything else after a '%' ("%s", "%x", "%.3d", a second conversion) is refused: a
// BadValue "--output: ..." (a usage error, exit 2).
class OutputPattern {
public:
    explicit OutputPattern(const std::string& pattern);
    bool numbered() const { return numbered_; }
    // The name of frame `frame` (the pattern itself, "%%" made '%', when not numbered).
    std::string name(long frame) const;
    const std::string& pattern() const { return pattern_; }

private:
    std::string pattern_, before_, after_;
    bool numbered_ = false, zero_pad_ = false;
    int width_ = 0;
};

// --frame-range=A:B: frames A to B, both included, numbered as in the whole run ("A" alone: one
// frame). Checked against the run's frame count by check().
struct FrameRange {
    long first = 0, last = -1;  // last < first: every frame (no --frame-range)
    bool given() const { return last >= first; }
    // BadValue "--frame-range: ..." when the range leaves frames 0 .. count-1.
    void check(long count) const;
};
// Parses "A:B" or "A"; Error naming --frame-range when the text is no range (A > B included).
FrameRange parse_frame_range(const std::string& text);

// Runs work(i) for i in [0, count) on `jobs` threads (the calling thread is one of them), each
// thread taking the next index when it is done. The first exception thrown stops the others from
// starting more work and is rethrown here, after every thread has finished.
void run_jobs(int jobs, std::size_t count, const std::function<void(std::size_t)>& work);

}  // namespace inkline
