// `inkline render`'s sequences (docs/batch.md): the progress line (app/progress.hpp) on a fake
// terminal, the numbered output names, --frame-range, the pool of jobs, and the command itself:
// frames identical whatever the jobs and the slices, the printed camera reproducing a frame,
// usage errors, and the GNU parallel recipe of the docs run as written.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "app/batch.hpp"
#include "app/flags.hpp"
#include "app/load_progress_line.hpp"
#include "app/progress.hpp"
#include "cli_util.hpp"
#include "core/error.hpp"
#include "test_data.hpp"

namespace {

using namespace inkline;
using inkline_test::Result;
using inkline_test::slurp;
namespace fs = std::filesystem;

fs::path scratch() { return inkline_test::scratch("batch_"); }
Result render(const std::string& args, const fs::path& dir) {
    return inkline_test::run_inkline("", "render " + args, dir);
}

// ---- the progress line ----

struct FakeTerminal {
    std::ostringstream out;
    double now = 0.0;
    std::unique_ptr<ProgressLine> line(std::size_t total, bool terminal = true) {
        return std::make_unique<ProgressLine>("render", total, "frames", out, terminal, [this] { return now; });
    }
    std::string take() {
        const std::string s = out.str();
        out.str("");
        return s;
    }
};

TEST(Progress, TextHasPercentRateAndTimeLeft) {
    EXPECT_EQ(ProgressLine::text("render", 0, 120, "frames", 2.0), "render: 0/120 frames    0%");
    // 30 of 120 in 12 s: 2.5 frames/s, 90 left take 36 s.
    EXPECT_EQ(ProgressLine::text("render", 30, 120, "frames", 12.0), "render: 30/120 frames   25%  2.50 frames/s  0:36 left");
    // 37 of 120 in 3 s: 12.33/s, 83 / 12.33 = 6.73 s, rounded up.
    EXPECT_EQ(ProgressLine::text("bench", 37, 120, "views", 3.0), "bench: 37/120 views   30%  12.3 views/s  0:07 left");
    EXPECT_EQ(ProgressLine::text("subdivide", 208000, 1040000, "triangles", 0.5),
              "subdivide: 208000/1040000 triangles   20%  416000 triangles/s  0:02 left");
    EXPECT_EQ(ProgressLine::text("render", 1, 4001, "frames", 4.0), "render: 1/4001 frames    0%  0.25 frames/s  4:26:40 left");
    EXPECT_EQ(ProgressLine::text("render", 5, 5, "frames", 10.0), "render: 5/5 frames  100%  0.50 frames/s  0:00 left");
    EXPECT_EQ(format_duration(59.2), "1:00");
    EXPECT_EQ(format_duration(3600.0), "1:00:00");
    EXPECT_EQ(format_duration(0.0), "0:00");
}

TEST(Progress, RewrittenInPlaceThrottledAndClearedAtTheEnd) {
    FakeTerminal t;
    auto line = t.line(4);
    t.now = 0.4;  // the first half second stays quiet
    line->advance();
    EXPECT_EQ(t.take(), "");
    t.now = 1.0;
    line->advance();
    const std::string two = "render: 2/4 frames   50%  2.00 frames/s  0:01 left";
    EXPECT_EQ(t.take(), "\r" + two);
    t.now = 1.05;  // 50 ms after the last write: skipped
    line->advance();
    EXPECT_EQ(t.take(), "");
    t.now = 1.08;  // the last one always goes, however soon
    line->advance();
    const std::string four = "render: 4/4 frames  100%  3.70 frames/s  0:00 left";
    EXPECT_EQ(t.take(), "\r" + four);
    line->finish();
    EXPECT_EQ(t.take(), "\r" + std::string(four.size(), ' ') + "\r");
    line->advance();  // after the end: nothing
    line.reset();     // nor from the destructor
    EXPECT_EQ(t.take(), "");
}

TEST(Progress, AShorterLineCoversTheLongerOneAndPrintAboveRedraws) {
    FakeTerminal t;
    auto line = t.line(1000);
    t.now = 128.0;  // (a power of two: the time left, 999 * 128 s, is exact)
    line->set_done(1);
    const std::string first = t.take().substr(1);
    EXPECT_EQ(first, "render: 1/1000 frames    0%  0.01 frames/s  35:31:12 left");
    t.now = 129.0;
    line->set_done(999);
    const std::string second = "render: 999/1000 frames   99%  7.74 frames/s  0:01 left";
    ASSERT_LT(second.size(), first.size());
    EXPECT_EQ(t.take(), "\r" + second + std::string(first.size() - second.size(), ' '));
    std::string printed;
    line->print_above([&] { printed = t.out.str(); });  // the line is gone when the caller prints
    EXPECT_EQ(printed, "\r" + std::string(first.size(), ' ') + "\r");
    t.take();
    t.now = 129.01;  // drawn again at the next update, not throttled by the last write
    line->set_done(999);
    EXPECT_EQ(t.take(), "\r" + second);
}

TEST(Progress, NothingWhenNotATerminal) {
    FakeTerminal t;
    auto line = t.line(3, false);
    for (int i = 0; i < 3; ++i) {
        t.now += 1.0;
        line->advance();
    }
    line->print_above([] {});
    line->finish();
    EXPECT_EQ(t.out.str(), "");
}

// ---- output names, frame ranges, jobs ----

// The load's progress line is the shared one: the file's size in kB as the total, the load's
// fraction of it as the count (so the rate is the file over the whole load), cleared when done.
TEST(Progress, LoadingUsesTheSharedLine) {
    EXPECT_EQ(load_progress_total_kb(0), 1u);
    EXPECT_EQ(load_progress_total_kb(2'600'001), 2601u);
    FakeTerminal t;
    auto line = std::make_shared<ProgressLine>("loading armadillo@3.off", load_progress_total_kb(100'000'000), "kB",
                                               t.out, true, [&t] { return t.now; });
    const LoadProgressCallback report = load_progress_callback(line);
    LoadProgress p;
    p.file_bytes = 100'000'000;
    p.fraction = 0.1;
    t.now = 0.4;  // within the quiet half second
    report(p);
    EXPECT_EQ(t.take(), "");
    p.fraction = 0.25;
    t.now = 5.0;  // 25000 kB in 5 s: 5000 kB/s, 75000 kB left: 15 s
    report(p);
    EXPECT_EQ(t.take(), "\rloading armadillo@3.off: 25000/100000 kB   25%  5000 kB/s  0:15 left");
    p.done = true;
    p.fraction = 1.0;
    t.now = 13.0;
    report(p);
    EXPECT_EQ(t.take(), "\r" + std::string(68, ' ') + "\r");
}

TEST(OutputPatterns, OneIntegerConversion) {
    const std::vector<std::array<std::string, 3>> cases = {
        // pattern, frame 37, frame 12345
        {"out_%04d.svg", "out_0037.svg", "out_12345.svg"},
        {"out_%d.svg", "out_37.svg", "out_12345.svg"},
        {"f%4i.png", "f  37.png", "f12345.png"},
        {"%03d", "037", "12345"},
        {"100%%_%02d.svg", "100%_37.svg", "100%_12345.svg"},
        {"d/%d%%.svg", "d/37%.svg", "d/12345%.svg"},
        {"plain.svg", "plain.svg", "plain.svg"},
        {"odd%%d.svg", "odd%d.svg", "odd%d.svg"},  // %% then a plain 'd': no conversion
    };
    for (const auto& [pattern, f37, f12345] : cases) {
        const OutputPattern p(pattern);
        EXPECT_EQ(p.numbered(), f37 != f12345) << pattern;
        EXPECT_EQ(p.name(37), f37) << pattern;
        EXPECT_EQ(p.name(12345), f12345) << pattern;
    }
    for (const auto& [pattern, error] : std::vector<std::array<std::string, 2>>{
             {"out_%s.svg", "'%' that is no frame number"},
             {"out_%.3d.svg", "'%' that is no frame number"},
             {"out_%x.svg", "'%' that is no frame number"},
             {"out_%", "'%' that is no frame number"},
             {"out_%d_%d.svg", "more than one frame number"},
             {"out_%0123d.svg", "at most 12 digits"}}) {
        try {
            OutputPattern p(pattern);
            ADD_FAILURE() << pattern << " taken";
        } catch (const BadValue& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--output: '" + pattern + "'", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find(error), std::string::npos) << e.what();
        }
    }
}

TEST(FrameRanges, ParsedAndChecked) {
    FrameRange r = parse_frame_range("10:19");
    EXPECT_EQ(r.first, 10);
    EXPECT_EQ(r.last, 19);
    EXPECT_TRUE(r.given());
    r = parse_frame_range("37");
    EXPECT_EQ(r.first, 37);
    EXPECT_EQ(r.last, 37);
    EXPECT_NO_THROW(r.check(38));
    EXPECT_THROW(r.check(37), BadValue);
    EXPECT_FALSE(FrameRange().given());
    EXPECT_NO_THROW(FrameRange().check(1));
    for (const std::string bad : {"", ":", "a:b", "3:", ":3", "-1:2", "1.5:2", "5:4", "1:2:3"})
        EXPECT_THROW(parse_frame_range(bad), Error) << bad;
    try {
        parse_frame_range("5:4");
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "--frame-range: the first frame is after the last ('5:4')");
    }
}

TEST(Jobs, EveryIndexOnceAndTheFirstErrorRethrown) {
    for (int jobs : {1, 2, 7}) {
        std::vector<std::atomic<int>> seen(50);
        run_jobs(jobs, seen.size(), [&](std::size_t i) { ++seen[i]; });
        for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << jobs << " jobs, index " << i;
    }
    // One job: nothing after the failing index is started.
    std::atomic<int> ran{0};
    EXPECT_THROW(run_jobs(1, 1000,
                          [&](std::size_t i) {
                              ++ran;
                              if (i == 5) throw Error("frame 5", "failed");
                          }),
                 Error);
    EXPECT_EQ(ran.load(), 6);
    // Three: the others stop taking work. Each job lasts a millisecond, so that the other two
    // cannot run out the 1000 indices (a third of a second) while the error is being caught (the
    // jobs of a render are frames: milliseconds at least); without the stop all 1000 run.
    ran = 0;
    EXPECT_THROW(run_jobs(3, 1000,
                          [&](std::size_t i) {
                              ++ran;
                              if (i == 5) throw Error("frame 5", "failed");
                              std::this_thread::sleep_for(std::chrono::milliseconds(1));
                          }),
                 Error);
    EXPECT_LT(ran.load(), 1000);
    run_jobs(4, 0, [](std::size_t) { FAIL(); });
}

// ---- the command ----

std::map<std::string, std::string> files_of(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out[e.path().filename().string()] = slurp(e.path());
    return out;
}

// An orbit of armadillo with hidden lines (ray tests and walks: the lazy ray-test index shared by
// the jobs): one job, three jobs, and three slices of two jobs write the same files, byte for byte.
TEST(Batch, FramesIdenticalWhateverTheJobsAndSlices) {
    const fs::path d = scratch();
    const std::string common = inkline::test::mesh_path("armadillo") + " --frames=8 --orbit --arc=300 --hidden --size=400x300 --quiet ";
    ASSERT_EQ(render(common + "--jobs=1 -o " + (d / "one").string() + "/", d).code, 0);
    ASSERT_EQ(render(common + "--jobs=3 -o " + (d / "three" / "armadillo_%04d.svg").string(), d).code, 1)
        << "a pattern's directory is not made";  // (only -o DIR/ makes it)
    fs::create_directories(d / "three");
    ASSERT_EQ(render(common + "--jobs=3 -o " + (d / "three" / "armadillo_%04d.svg").string(), d).code, 0);
    for (const std::string range : {"0:2", "3", "4:7"})
        ASSERT_EQ(render(common + "--jobs=2 --frame-range=" + range + " -o " + (d / "slices").string() + "/", d).code, 0);
    const auto one = files_of(d / "one");
    ASSERT_EQ(one.size(), 8u);
    EXPECT_EQ(one.begin()->first, "armadillo_0000.svg");
    EXPECT_EQ(one.rbegin()->first, "armadillo_0007.svg");
    EXPECT_NE(one.begin()->second, one.rbegin()->second);  // the camera turned
    EXPECT_TRUE(files_of(d / "three") == one);
    EXPECT_TRUE(files_of(d / "slices") == one);
}

// Frame 0 is the drawing of the starting camera; --verbose prints each frame's camera flags, and
// those flags draw that frame again as a single drawing; the summary's flags draw the sequence.
TEST(Batch, PrintedCamerasReproduceTheFrames) {
    const fs::path d = scratch();
    const std::string model = inkline::test::mesh_path("cow");
    const Result seq = render(model + " --frames=6 --orbit --size=300x200 --jobs=2 --verbose -o " + (d / "f_%d.svg").string(), d);
    ASSERT_EQ(seq.code, 0) << seq.err;
    std::vector<std::string> cameras, reports;
    std::stringstream ss(seq.out);
    for (std::string line; std::getline(ss, line);) {
        if (line.rfind("camera: ", 0) == 0) cameras.push_back(line.substr(8));
        if (line.find(": 5804 triangles") != std::string::npos) reports.push_back(line.substr(0, line.find(':')));
    }
    ASSERT_EQ(cameras.size(), 7u) << seq.out;  // six frames, then the sequence's
    ASSERT_EQ(reports.size(), 6u) << seq.out;
    for (int k = 0; k < 6; ++k) EXPECT_EQ(reports[std::size_t(k)], (d / ("f_" + std::to_string(k) + ".svg")).string());  // in order
    EXPECT_NE(seq.out.find("render: 6 frames (0 to 5 of 6) written as " + (d / "f_%d.svg").string() + " in "),
              std::string::npos) << seq.out;
    EXPECT_NE(cameras[6].find(" --size=300x200 --frames=6 --orbit --arc=360"), std::string::npos) << cameras[6];
    const Result still = render(model + " " + cameras[4] + " --quiet -o " + (d / "still4.svg").string(), d);
    ASSERT_EQ(still.code, 0) << still.err;
    EXPECT_EQ(slurp(d / "still4.svg"), slurp(d / "f_4.svg"));
    ASSERT_EQ(render(model + " --size=300x200 --quiet -o " + (d / "still0.svg").string(), d).code, 0);
    EXPECT_EQ(slurp(d / "still0.svg"), slurp(d / "f_0.svg"));
    const std::string again = cameras[6].substr(0, cameras[6].find(" --frames"));
    ASSERT_EQ(render(model + " " + again + " --frames=6 --orbit --frame-range=4 --quiet -o " + (d / "g_%d.svg").string(), d).code, 0);
    EXPECT_EQ(slurp(d / "g_4.svg"), slurp(d / "f_4.svg"));
    EXPECT_FALSE(fs::exists(d / "g_3.svg"));
}

TEST(Batch, SeveralModels) {
    const fs::path d = scratch();
    const std::string models = inkline::test::mesh_path("fandisk") + " " + inkline::test::mesh_path("tetrahedron") + " ";
    const Result dir = render(models + "--size=200x200 -o " + (d / "out").string() + "/", d);
    ASSERT_EQ(dir.code, 0) << dir.err;
    EXPECT_TRUE(fs::exists(d / "out" / "fandisk.svg"));
    EXPECT_TRUE(fs::exists(d / "out" / "tetrahedron.svg"));
    // Each model's report, in the order given, then the run's line.
    const auto fandisk = dir.out.find((d / "out" / "fandisk.svg").string() + ": 12946 triangles");
    const auto tetra = dir.out.find((d / "out" / "tetrahedron.svg").string() + ": 4 triangles");
    ASSERT_NE(fandisk, std::string::npos) << dir.out;
    ASSERT_NE(tetra, std::string::npos) << dir.out;
    EXPECT_LT(fandisk, tetra);
    EXPECT_NE(dir.out.find("render: 2 drawings (0 to 1 of 2) written as " + (d / "out").string() + "/MODEL.svg in "),
              std::string::npos) << dir.out;
    EXPECT_EQ(dir.err, "");  // no progress line: stderr is no terminal here
    const Result numbered = render(models + "--size=200x200 --quiet --frame-range=1 -o " + (d / "m%02d.png").string(), d);
    ASSERT_EQ(numbered.code, 0) << numbered.err;
    EXPECT_EQ(numbered.out, "");
    EXPECT_FALSE(fs::exists(d / "m00.png"));
    EXPECT_EQ(slurp(d / "m01.png").substr(1, 3), "PNG");
    // A model that does not load: exit 1, its name in the one line.
    const Result bad = render(models + (d / "missing.off").string() + " --quiet -o " + (d / "out").string() + "/", d);
    EXPECT_EQ(bad.code, 1);
    EXPECT_EQ(bad.err, "inkline: " + (d / "missing.off").string() + ": cannot open: No such file or directory\n");
}

TEST(Batch, UsageErrorsExit2) {
    const fs::path d = scratch();
    const std::string m = inkline::test::mesh_path("tetrahedron");
    const std::string see = "usage: inkline render MODEL [FLAGS]; see 'inkline render --help'\n";
    const std::vector<std::array<std::string, 2>> cases = {
        {m + " --frames=3 --orbit -o one.svg",
         "inkline: -o one.svg: one file for 3 drawings; put a frame number in it (out_%04d.svg) or name a directory "
         "(DIR/)\n" + see},
        {m + " " + m + " -o one.svg",
         "inkline: -o one.svg: one file for 2 drawings; put a frame number in it (out_%04d.svg) or name a directory "
         "(DIR/)\n" + see},
        {m + " --frames=3", "inkline: --frames=N needs a camera path (--orbit)\n" + see},
        {m + " --orbit", "inkline: --orbit turns the camera over --frames=N frames\n" + see},
        {m + " " + m + " --frames=3 --orbit", "inkline: several models or --frames=N, not both (one orbit a run)\n" + see},
        {m + " --frames=3 --orbit -o f%s.svg",
         "inkline: --output: 'f%s.svg' has a '%' that is no frame number (expected %d, %4d or %04d; %% for a '%')\n"},
        {m + " --frames=3 --orbit --frame-range=2:3 -o f%d.svg", "inkline: --frame-range: 2:3 leaves the run's frames 0:2\n"},
        {m + " --frames=3 --orbit --frame-range=x", "inkline: --frame-range: expected A:B or A, frame numbers from 0, got 'x'\n"},
        {m + " --frames=3 --orbit --jobs=0", "inkline: --jobs: expected an integer from 1 to 1024\n"},
        {m + " " + m + " -o " + (d / "same").string() + "/", "inkline: --output: two drawings of the run would both be written to " + (d / "same" / "tetrahedron.svg").string() + "\n"},
    };
    for (const auto& [args, expect] : cases) {
        const Result r = render(args, d);
        EXPECT_EQ(r.code, 2) << args << ": " << r.err;
        EXPECT_EQ(r.err, expect) << args;
    }
    EXPECT_FALSE(fs::exists(d / "same"));  // refused before any work
}

// docs/batch.md's GNU parallel recipe, run as written (in a scratch directory holding model.off,
// inkline on the PATH): the slices give the files of one run. Skipped when parallel is absent
// (scripts/setup.sh installs it).
TEST(Batch, RecipeWithGnuParallel) {
    if (std::system("command -v parallel >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "GNU parallel is not installed (Debian package 'parallel'): docs/batch.md's recipe not run";
    const std::string doc = slurp(fs::path(INKLINE_SOURCE_DIR) / "docs" / "batch.md");
    const auto marker = doc.find("<!-- tests/test_batch.cpp (Batch.RecipeWithGnuParallel)");
    ASSERT_NE(marker, std::string::npos);
    const auto open = doc.find("```sh\n", marker), close = doc.find("```\n", open + 6);
    ASSERT_NE(open, std::string::npos);
    const std::string recipe = doc.substr(open + 6, close - open - 6);
    ASSERT_NE(recipe.find("parallel"), std::string::npos) << recipe;
    const fs::path d = scratch();
    fs::create_symlink(inkline::test::mesh_path("fandisk"), d / "model.off");
    std::ofstream(d / "recipe.sh") << recipe;
    const std::string bin_dir = fs::path(INKLINE_BINARY).parent_path().string();
    const std::string cmd = "cd " + d.string() + " && PATH=" + bin_dir + ":$PATH sh recipe.sh >recipe.out 2>recipe.err";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(d / "recipe.err");
    ASSERT_EQ(render((d / "model.off").string() + " --frames=120 --orbit --quiet -o " + (d / "whole").string() + "/", d).code, 0);
    const auto whole = files_of(d / "whole");
    ASSERT_EQ(whole.size(), 120u);
    EXPECT_TRUE(files_of(d / "frames") == whole);
}

}  // namespace
