// The preview window's view scheduler (src/view/view_scheduler.hpp), without a display: views come
// back in the order they were started, the lanes chosen by the camera's step as the window does,
// and every view's drawing and line quads are what render_view and build_line_mesh make at its
// camera, with one view at a time and with two at once. And the frame statistics the panel shows.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <string>
#include <unistd.h>
#include <vector>

#include "pipeline.hpp"
#include "view/camera_rig.hpp"
#include "view/frame_stats.hpp"
#include "view/line_mesh.hpp"
#include "view/view_scheduler.hpp"

using namespace inkline;

namespace {

const Model& fandisk() {
    static const Model model = Model::load(std::string(INKLINE_DATA_DIR) + "/meshes/fandisk.off");
    return model;
}

bool same_camera(const Camera& a, const Camera& b) {
    return a.eye() == b.eye() && a.target() == b.target() && a.up() == b.up() && a.fov_deg() == b.fov_deg() &&
           a.width() == b.width() && a.height() == b.height();
}

ViewOptions two_threads() {
    ViewOptions o;
    o.threads = 2;  // two lanes unless --in-flight=1
    return o;
}

ViewRequest request_at(const Camera& camera) {
    ViewRequest r;
    r.camera = camera;
    r.lines.simplify_px = 0.25;  // as the window asks
    return r;
}

// Cameras along an orbit from the model's framing, `steps_deg[i]` degrees before the (i+1)-th.
std::vector<Camera> orbit(const std::vector<double>& steps_deg) {
    const Camera home = Camera::framing(fandisk().topology().bounds, 320, 240);
    CameraRig rig(home, fandisk().topology().bounds);
    std::vector<Camera> cameras{rig.camera(320, 240)};
    for (double step : steps_deg) {
        rig.orbit(step, 0.0);
        cameras.push_back(rig.camera(320, 240));
    }
    return cameras;
}

std::vector<double> repeat(double step, int n, std::vector<double> before = {}) {
    before.insert(before.end(), std::size_t(n), step);
    return before;
}

// Drives the scheduler as the headless window does (lock-step: the oldest view taken once every
// lane is busy, then the next started; all taken at the end) and calls `taken` for each view as
// it comes back, with the index of the camera it was started at.
template <class Taken>
void run_headless(ViewScheduler& scheduler, const std::vector<Camera>& cameras, Taken taken) {
    std::size_t started = 0, done = 0;
    FinishedView view;
    while (done < cameras.size()) {
        if (started == cameras.size() || scheduler.in_flight() >= scheduler.views_at_once()) {
            ASSERT_TRUE(scheduler.take_oldest(view));
            taken(view, done++);
        }
        if (started < cameras.size() && scheduler.in_flight() < scheduler.views_at_once())
            scheduler.start(request_at(cameras[started++]));
    }
    EXPECT_FALSE(scheduler.take_oldest(view));
}

// The views at once each view was started with, along the cameras.
std::vector<int> modes_along(int in_flight, const std::vector<Camera>& cameras, const ViewOptions& options) {
    ViewScheduler scheduler(fandisk(), in_flight);
    scheduler.reset(options);
    std::vector<int> modes;
    run_headless(scheduler, cameras, [&](const FinishedView& v, std::size_t) { modes.push_back(v.views_at_once); });
    return modes;
}

void expect_same_drawing(const Drawing& a, const Drawing& b) {
    ASSERT_EQ(a.pieces.size(), b.pieces.size());
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
        EXPECT_EQ(a.pieces[i].kind, b.pieces[i].kind) << i;
        EXPECT_EQ(a.pieces[i].qi, b.pieces[i].qi) << i;
        EXPECT_EQ(a.pieces[i].points, b.pieces[i].points) << i;
    }
}

}  // namespace

// The step of an orbit of d degrees a view is 2 sin(d/2) radians (the eye's chord over the
// distance; the target stays), smoothed as s <- 0.75 s + 0.25 step from the second step on. The
// default goes to two views at once from the sixth view (the fourth step is measured when the
// fifth starts) while s < 1 degree, and back to one when s > 1.6 degrees.
TEST(ViewScheduler, TwoLanesBelowOneDegreeAViewOneAboveOnePointSix) {
    const ViewOptions o = two_threads();
    // 0.5 degrees a view: one at a time for five views, then two at once.
    EXPECT_EQ(modes_along(0, orbit(repeat(0.5, 9)), o), (std::vector<int>{1, 1, 1, 1, 1, 2, 2, 2, 2, 2}));
    // 2 degrees a view: always one at a time.
    EXPECT_EQ(modes_along(0, orbit(repeat(2.0, 9)), o), std::vector<int>(10, 1));
    // 1.3 degrees a view, between the two thresholds: one at a time stays one...
    EXPECT_EQ(modes_along(0, orbit(repeat(1.3, 9)), o), std::vector<int>(10, 1));
    // ...and two at once stays two (s rises from 0.5 towards 1.3, never past 1.6).
    EXPECT_EQ(modes_along(0, orbit(repeat(1.3, 8, repeat(0.5, 9))), o),
              (std::vector<int>{1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2}));
    // 4 degrees a view after 0.5: s = 0.5 when the 11th view starts (still two), 1.375 at the
    // 12th (still two), 2.28 at the 13th: one at a time from there on.
    EXPECT_EQ(modes_along(0, orbit(repeat(4.0, 8, repeat(0.5, 9))), o),
              (std::vector<int>{1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 1, 1, 1, 1, 1, 1}));
    // --in-flight fixes it; one thread makes one lane whatever the flag.
    EXPECT_EQ(modes_along(2, orbit(repeat(4.0, 5)), o), std::vector<int>(6, 2));
    EXPECT_EQ(modes_along(1, orbit(repeat(0.5, 9)), o), std::vector<int>(10, 1));
    ViewOptions one_thread;
    one_thread.threads = 1;
    EXPECT_EQ(modes_along(2, orbit(repeat(0.5, 9)), one_thread), std::vector<int>(10, 1));
}

TEST(ViewScheduler, LanesAndThreadsFollowTheFlagAndTheThreads) {
    ViewScheduler two(fandisk(), 0), one(fandisk(), 1), single(fandisk(), 2);
    two.reset(two_threads());
    one.reset(two_threads());
    ViewOptions one_thread;
    one_thread.threads = 1;
    single.reset(one_thread);
    EXPECT_EQ(two.lane_count(), 2);
    EXPECT_FALSE(two.fixed());
    EXPECT_EQ(one.lane_count(), 1);
    EXPECT_TRUE(one.fixed());
    EXPECT_EQ(single.lane_count(), 1);
    EXPECT_TRUE(single.fixed());
    EXPECT_EQ(two.threads(), 2);
    EXPECT_EQ(two.views_at_once_now(), 1);  // (until four steps are seen)
    EXPECT_EQ(two.in_flight(), 0);
    EXPECT_FALSE(two.oldest_done());
}

// Each view comes back in the order started, at its camera, with the drawing render_view makes
// there and the quads build_line_mesh makes of it: one view at a time, two at once (the lanes
// taking the views in turn), and the default switching between them along the orbit.
TEST(ViewScheduler, ViewsComeBackInOrderWithRenderViewsDrawing) {
    const std::vector<Camera> cameras = orbit(repeat(4.0, 4, repeat(0.5, 9)));
    for (int in_flight : {1, 2, 0}) {
        SCOPED_TRACE("in flight " + std::to_string(in_flight));
        ViewScheduler scheduler(fandisk(), in_flight);
        scheduler.reset(two_threads());
        std::size_t next = 0;
        run_headless(scheduler, cameras, [&](const FinishedView& v, std::size_t i) {
            EXPECT_EQ(i, next++);
            EXPECT_TRUE(same_camera(v.camera, cameras[i])) << "view " << i;
            ASSERT_NE(v.view, nullptr);
            EXPECT_FALSE(v.styled);
            EXPECT_EQ(v.recall, -1.0);
            const View reference = render_view(fandisk(), cameras[i], two_threads());
            ASSERT_FALSE(reference.drawing.pieces.empty());
            expect_same_drawing(v.view->drawing, reference.drawing);
            EXPECT_EQ(v.stats.pieces, reference.drawing.stats.pieces);
            EXPECT_EQ(v.stats.silhouette_edges, reference.drawing.stats.silhouette_edges);
            std::vector<LineVertex> quads;
            build_line_mesh(reference.drawing, request_at(cameras[i]).lines, quads);
            ASSERT_EQ(v.lines.size(), quads.size()) << "view " << i;
            EXPECT_EQ(std::memcmp(v.lines.data(), quads.data(), quads.size() * sizeof(LineVertex)), 0) << "view " << i;
        });
        EXPECT_EQ(next, cameras.size());
    }
}

// A view asked with recall measures its finder's silhouette length against the exhaustive
// finder's: the exhaustive finder itself recalls all of it.
TEST(ViewScheduler, RecallOfTheExhaustiveFinderIsOne) {
    ViewScheduler scheduler(fandisk(), 1);
    scheduler.reset(two_threads());
    ViewRequest r = request_at(orbit({})[0]);
    r.recall = true;
    scheduler.start(r);
    FinishedView v;
    ASSERT_TRUE(scheduler.take_oldest(v));
    EXPECT_EQ(v.recall, 1.0);
    EXPECT_EQ(v.views_at_once, 1);
}

// The panel's stage times: the first frame's as they are, then a moving average over the frames
// with a new view (9/10 of the old, 1/10 of the new); a frame without a new view moves only the
// draw time. Frame 0 is not measured (it builds the lazy indexes), nor the headless last frame.
TEST(FrameStats, PanelShowsAMovingAverageOfTheViewsTimes) {
    FrameStats stats;
    StageTimes first, second, idle;
    first.features = 10.0, first.draw = 1.0;
    second.features = 20.0, second.draw = 3.0;
    idle.draw = 2.0;
    DrawingStats drawing;
    drawing.triangles = 12;
    stats.frame_drawn(first, true, 0, false);
    EXPECT_EQ(stats.panel_numbers(drawing, -1.0).times.features, 10.0);
    stats.frame_drawn(second, true, 1, false);  // 0.9 * 10 + 0.1 * 20, 0.9 * 1 + 0.1 * 3
    EXPECT_DOUBLE_EQ(stats.panel_numbers(drawing, -1.0).times.features, 11.0);
    EXPECT_DOUBLE_EQ(stats.panel_numbers(drawing, -1.0).times.draw, 1.2);
    stats.frame_drawn(idle, false, 2, false);  // the draw time only: 0.9 * 1.2 + 0.1 * 2
    EXPECT_DOUBLE_EQ(stats.panel_numbers(drawing, 0.5).times.features, 11.0);
    EXPECT_DOUBLE_EQ(stats.panel_numbers(drawing, 0.5).times.draw, 1.28);
    EXPECT_EQ(stats.panel_numbers(drawing, 0.5).recall, 0.5);
    EXPECT_EQ(stats.panel_numbers(drawing, 0.5).stats.triangles, 12u);
}

// The panel's rates at a still camera: the window sleeps until input, so the time across the sleep
// is not a period (it read as a rate near zero, or 0.0 views/s with a single view); the panel says
// the window is still instead, and the rates after waking are those of the frames and views since.
TEST(FrameStats, RatesDoNotCountTheSleepsOfAStillWindow) {
    using namespace std::chrono_literals;
    FrameStats stats;
    DrawingStats drawing;
    drawing.triangles = 12;
    StageTimes frame;
    auto t = FrameStats::Clock::now();
    for (int i = 0; i < 3; ++i, t += 10ms) {  // a view every frame, 100 a second
        stats.slept(false);
        stats.view_arrived(t);
        stats.frame_drawn(frame, true, i, false, t);
    }
    PanelNumbers moving = stats.panel_numbers(drawing, -1.0, t);
    EXPECT_FALSE(moving.still);
    EXPECT_NEAR(moving.views_per_s, 100.0, 1e-6);
    EXPECT_NEAR(moving.fps, 100.0, 1e-6);
    t += 2s;  // still: the loop sleeps, the panel is drawn after the sleep
    stats.slept(true);
    stats.frame_drawn(frame, false, 3, false, t);
    EXPECT_TRUE(stats.panel_numbers(drawing, -1.0, t).still);
    t += 10ms;  // input: the camera moves, the views come every 10 ms again
    for (int i = 4; i < 6; ++i, t += 10ms) {
        stats.slept(false);
        stats.view_arrived(t);
        stats.frame_drawn(frame, true, i, false, t);
    }
    const PanelNumbers woken = stats.panel_numbers(drawing, -1.0, t);
    EXPECT_FALSE(woken.still);
    EXPECT_NEAR(woken.views_per_s, 100.0, 1e-6);  // the 2 s sleep counted would read 5.2
    EXPECT_NEAR(woken.fps, 100.0, 1e-6);
}

// view --detail: the scheduler draws the detail source's view (its lines are render_view's on the
// mesh it adapted) with that mesh as the base coat; the slider's target applies from the next
// view; at a still camera the pm geomorphs end and the source stops asking for views.
TEST(ViewSchedulerDetail, DrawsTheAdaptedMeshAndFollowsTheSlider) {
    const Model& model = fandisk();
    const Camera cam = Camera::framing(model.topology().bounds, 320, 240);
    DetailSource pm(model, "pm", 2.0);
    pm.set_fixed_step(1.0 / 60.0);  // (the window's shortest step: the most views; the wall time would vary them)
    ViewOptions options;
    pm.reset(options);
    ViewScheduler scheduler(model, 1);
    scheduler.reset(options);
    const auto view_at = [&](FinishedView& out) {
        ViewRequest r = request_at(cam);
        r.detail = &pm;
        scheduler.start(r);
        ASSERT_TRUE(scheduler.take_oldest(out));
    };
    FinishedView first;
    view_at(first);
    const std::size_t fine = pm.drawn_model().topology().faces.size();
    ASSERT_TRUE(first.has_coat);
    EXPECT_EQ(first.coat.triangles.size(), 3 * fine);
    EXPECT_EQ(first.view->drawing.pieces.size(), render_view(pm.drawn_model(), cam).drawing.pieces.size());
    EXPECT_LT(fine, model.topology().faces.size());  // 2 px already coarsens the framed fandisk at 320 x 240
    pm.set_target(8.0);
    FinishedView v;
    int views = 0;
    do {
        view_at(v);
    } while (pm.morphing() && ++views < 1000);
    std::printf("[detail] pm geomorphs ended after %d views\n", views);
    EXPECT_LT(views, 600);  // the geomorphs ended (483 views: the last collapses run one after another)
    EXPECT_LT(pm.drawn_model().topology().faces.size(), fine / 2);
    EXPECT_NE(pm.summary().find("pm: target 8 px"), std::string::npos) << pm.summary();
}

// view --detail: the pre-process runs on its own thread (the window draws the model without detail
// control meanwhile) and reports its progress up to 1; what needs it waits for it.
TEST(ViewSchedulerDetail, PreprocessOnItsOwnThreadWithProgress) {
    for (const std::string method : {"pm", "multiscale"}) {
        std::mutex mutex;
        std::vector<double> heard;  // the fraction at each report (once the source is known)
        std::atomic<DetailSource*> known{nullptr};
        auto source = std::make_unique<DetailSource>(fandisk(), method, 2.0, 0.0, DetailPreprocess{}, [&] {
            std::lock_guard<std::mutex> lock(mutex);
            if (const DetailSource* s = known.load()) heard.push_back(s->preparation_fraction());
        });
        known.store(source.get());
        source->wait_ready();
        EXPECT_TRUE(source->ready());
        EXPECT_EQ(source->preparation_fraction(), 1.0);
        std::lock_guard<std::mutex> lock(mutex);
        ASSERT_GE(heard.size(), 1u) << method;  // at least the end (fandisk's steps may come first)
        EXPECT_EQ(heard.back(), 1.0) << method;
        EXPECT_TRUE(std::is_sorted(heard.begin(), heard.end())) << method;
        EXPECT_NE(source->preparation_text().find(method == "pm" ? "progressive mesh" : "multi-scale"),
                  std::string::npos);
        source->reset({});
        const Camera cam = Camera::framing(fandisk().topology().bounds, 320, 240);
        EXPECT_GT(source->render(cam).drawing.pieces.size(), 0u) << method;
    }
}

// A source destroyed while its hierarchy is built stops the build (the window closed before it
// was needed): the decimater hears no more than a step or two after the destructor began, where a
// whole build reports about a hundred times.
TEST(ViewSchedulerDetail, DestroyedWhileBuildingStopsTheBuild) {
    static const Model armadillo = Model::load(std::string(INKLINE_DATA_DIR) + "/meshes/armadillo.off");
    std::atomic<int> calls{0};
    std::atomic<bool> destroying{false};
    std::promise<void> first;
    auto source = std::make_unique<DetailSource>(armadillo, "pm", 2.0, 0.0, DetailPreprocess{}, [&] {
        if (calls.fetch_add(1) == 0) {
            first.set_value();
            while (!destroying.load()) std::this_thread::yield();
        }
    });
    first.get_future().wait();  // the build is under way
    destroying.store(true);
    source.reset();
    std::printf("[detail] %d progress reports before the build stopped\n", calls.load());
    EXPECT_LE(calls.load(), 3);
}

// view --detail --cache: the window's pre-process comes from the cache as render's does (either
// method), the second source reads the file the first wrote and draws the same view, and a damaged
// file gives the one-line warning the window prints.
TEST(ViewSchedulerDetail, PreprocessFromTheCache) {
    const std::string path = std::string(INKLINE_DATA_DIR) + "/meshes/fandisk.off";
    const Camera cam = Camera::framing(fandisk().topology().bounds, 320, 240);
    const std::filesystem::path folder =
        std::filesystem::path(::testing::TempDir()) / ("view_detail_cache_" + std::to_string(::getpid())) / "c";
    std::filesystem::remove_all(folder);
    for (const std::string method : {"pm", "multiscale"}) {
        DetailPreprocess pre;
        pre.cache_dir = folder.string();
        pre.model_path = path;
        pre.variant = "v";
        DetailSource written(fandisk(), method, 2.0, 0.0, pre);
        EXPECT_EQ(written.cache_warning(), "") << method;
        const std::string extension = method == "pm" ? ".pm" : ".levels";
        std::filesystem::path file;
        for (const auto& e : std::filesystem::directory_iterator(folder))
            if (e.path().extension() == extension) file = e.path();
        ASSERT_FALSE(file.empty()) << method;
        const auto modified = std::filesystem::last_write_time(file);
        DetailSource read(fandisk(), method, 2.0, 0.0, pre);
        EXPECT_EQ(read.cache_warning(), "") << method;
        EXPECT_EQ(std::filesystem::last_write_time(file), modified) << method;  // read, not rewritten
        written.reset({});
        read.reset({});
        EXPECT_EQ(written.render(cam).drawing.pieces.size(), read.render(cam).drawing.pieces.size()) << method;
        EXPECT_EQ(written.drawn_model().topology().faces, read.drawn_model().topology().faces) << method;
        std::filesystem::resize_file(file, 64);
        const DetailSource damaged(fandisk(), method, 2.0, 0.0, pre);
        EXPECT_NE(damaged.cache_warning().find(file.string()), std::string::npos) << damaged.cache_warning();
        EXPECT_NE(damaged.cache_warning().find("checksum"), std::string::npos) << damaged.cache_warning();
    }
}
