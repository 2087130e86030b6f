// The preview window (src/view/): the camera rig and the line quads without a display, and the
// window itself driven under Xvfb: its screenshot must be the line drawing `inkline render` makes
// at the camera the window prints.
#include <gtest/gtest.h>

#include "cli_util.hpp"

#include <cairo.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/camera.hpp"
#include "test_data.hpp"
#include "view/camera_rig.hpp"
#include "view/line_mesh.hpp"
#include "view/tone_pass.hpp"

namespace fs = std::filesystem;
using namespace inkline;

namespace {

// ---- The camera rig -----------------------------------------------------------------------------

Bounds3 unit_box() { return {{-1, -1, -1}, {1, 1, 1}}; }

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tol = 1e-9) {
    EXPECT_LT(glm::length(a - b), tol) << "(" << a.x << "," << a.y << "," << a.z << ") vs (" << b.x << "," << b.y
                                       << "," << b.z << ")";
}

TEST(CameraRig, OrbitKeepsTheDistanceAndAFullTurnComesBack) {
    const Camera home = Camera::framing(unit_box(), 640, 480);
    CameraRig rig(home, unit_box());
    const double d = glm::length(home.eye() - home.target());
    rig.orbit(30.0, 0.0);
    EXPECT_NEAR(glm::length(rig.eye() - rig.target()), d, 1e-9 * d);
    EXPECT_GT(glm::length(rig.eye() - home.eye()), 0.1 * d);  // it moved
    for (int i = 0; i < 11; ++i) rig.orbit(30.0, 0.0);
    expect_near(rig.eye(), home.eye(), 1e-9 * d);
    rig.orbit(0.0, 25.0);
    EXPECT_NEAR(glm::length(rig.eye() - rig.target()), d, 1e-9 * d);
    EXPECT_NEAR(glm::dot(rig.up(), glm::normalize(rig.target() - rig.eye())), 0.0, 1e-12);
    rig.reset();
    expect_near(rig.eye(), home.eye());
    expect_near(rig.up(), home.upward());
}

TEST(CameraRig, StandardViewsPanZoomAndOrtho) {
    const Camera home = Camera::framing(unit_box(), 640, 480);
    CameraRig rig(home, unit_box());
    const double d = glm::length(home.eye() - home.target());
    rig.front();
    expect_near(glm::normalize(rig.eye() - rig.target()), {0, 0, 1});
    rig.side();
    expect_near(glm::normalize(rig.eye() - rig.target()), {1, 0, 0});
    rig.top();  // straight down: the up vector must not be parallel to the view
    expect_near(glm::normalize(rig.eye() - rig.target()), {0, 1, 0});
    const Camera top = rig.camera(640, 480);
    EXPECT_LT(top.project({0, 0, -1}).y, top.project({0, 0, 1}).y);  // -Z is up on screen
    // Pan: the target's image follows the cursor.
    rig.reset();
    const glm::dvec3 t0 = rig.target();
    rig.pan(40.0, -20.0, 480);
    const Camera panned = rig.camera(640, 480);
    const glm::dvec2 p = panned.project(t0);
    EXPECT_NEAR(p.x, 320.0 + 40.0, 1e-6);
    EXPECT_NEAR(p.y, 240.0 - 20.0, 1e-6);
    rig.zoom(2.0);
    EXPECT_NEAR(glm::length(rig.eye() - rig.target()), 0.81 * d, 1e-9 * d);
    // Ortho keeps the target plane's size: a point beside the target projects to the same pixel.
    rig.reset();
    const Camera persp = rig.camera(640, 480);
    const glm::dvec3 beside = persp.target() + 0.3 * persp.right() + 0.2 * persp.upward();
    rig.toggle_ortho();
    const Camera ortho = rig.camera(640, 480);
    ASSERT_TRUE(ortho.is_ortho());
    EXPECT_NEAR(ortho.project(beside).x, persp.project(beside).x, 1e-6);
    EXPECT_NEAR(ortho.project(beside).y, persp.project(beside).y, 1e-6);
    rig.toggle_ortho();
    EXPECT_FALSE(rig.camera(640, 480).is_ortho());
    expect_near(rig.eye(), home.eye(), 1e-9 * d);
}

// ---- Line quads -------------------------------------------------------------------------------

TEST(LineMesh, QuadsPerSegmentHiddenOnlyWhenAsked) {
    Drawing d;
    d.camera = Camera::framing(unit_box(), 1024, 1024);
    Piece visible;
    visible.points = {{10, 10}, {110, 10}, {110, 60}};
    Piece hidden = visible;
    hidden.qi = 2;
    Piece bad = visible;
    bad.points[1].x = std::nan("");
    d.pieces = {visible, hidden, bad};
    std::vector<LineVertex> v;
    LineMeshOptions o;
    build_line_mesh(d, o, v);
    ASSERT_EQ(v.size(), 12u);  // two segments of the visible piece
    for (const LineVertex& q : v) {
        EXPECT_EQ(q.style, 0.0f);
        EXPECT_FLOAT_EQ(q.half, 0.75f);               // 1.5 px at 1024 px high
        EXPECT_FLOAT_EQ(std::abs(q.across), 1.75f);   // half width + 1 px of antialiasing
    }
    // The second segment starts where the first ends, along the piece.
    EXPECT_FLOAT_EQ(v[6].along, 100.0f - 1.75f);
    // Segment-local coordinates for round caps: from -reach to length + reach.
    EXPECT_FLOAT_EQ(v[0].u, -1.75f);
    EXPECT_FLOAT_EQ(v[5].u, 101.75f);
    EXPECT_FLOAT_EQ(v[0].length, 100.0f);
    EXPECT_FLOAT_EQ(v[6].length, 50.0f);
    o.hidden = true;
    build_line_mesh(d, o, v);
    ASSERT_EQ(v.size(), 24u);
    EXPECT_EQ(v.front().style, 2.0f);  // hidden first, visible drawn over them
    EXPECT_EQ(v.back().style, 0.0f);
}

TEST(LineMesh, SimplificationDropsOnlyPointsOnTheLine) {
    Drawing d;
    d.camera = Camera::framing(unit_box(), 1024, 1024);
    Piece straight, zigzag;
    for (int i = 0; i <= 100; ++i) {
        straight.points.push_back({10.0 + i, 20.0 + 0.5 * i + (i % 2 ? 0.1 : -0.1)});  // within 0.25 px of a line
        zigzag.points.push_back({10.0 + 2 * i, 200.0 + (i % 2 ? 1.0 : -1.0)});
    }
    std::vector<LineVertex> v;
    LineMeshOptions o;
    o.simplify_px = 0.25;
    d.pieces = {straight};
    build_line_mesh(d, o, v);
    EXPECT_LE(v.size(), 6u * 2);  // at most 64 points dropped in a row: two segments
    EXPECT_GE(v.size(), 6u);
    d.pieces = {zigzag};
    build_line_mesh(d, o, v);
    EXPECT_EQ(v.size(), 6u * 100);  // every corner is 2 px off its neighbours' line: all kept
    o.simplify_px = 0.0;
    d.pieces = {straight};
    build_line_mesh(d, o, v);
    EXPECT_EQ(v.size(), 6u * 100);
}

// ---- The window under Xvfb --------------------------------------------------------------------

using inkline_test::Result;
using inkline_test::slurp;

fs::path scratch() { return inkline_test::scratch("inkline_view_"); }

Result run(const std::string& prefix, const std::string& args, const fs::path& dir) {
    return inkline_test::run_inkline(prefix, args, dir);
}

bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }
const char* kXvfb = "xvfb-run -a -s '-screen 0 1280x800x24' ";


// Dark pixels (luminance below half) of a PNG, row-major, with its size.
struct Mask {
    int w = 0, h = 0;
    std::vector<std::uint8_t> dark;
    std::size_t count() const {
        std::size_t n = 0;
        for (auto v : dark) n += v;
        return n;
    }
};

// Pixels with luminance in [lo, hi) (lines drawn black: below 128; hidden lines grey).
Mask dark_pixels(const fs::path& png, double lo = -1.0, double hi = 128.0) {
    Mask m;
    cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return m;
    }
    cairo_surface_flush(s);
    m.w = cairo_image_surface_get_width(s);
    m.h = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    m.dark.resize(std::size_t(m.w) * m.h);
    for (int y = 0; y < m.h; ++y)
        for (int x = 0; x < m.w; ++x) {
            const std::uint32_t p = reinterpret_cast<const std::uint32_t*>(data + std::size_t(y) * stride)[x];
            const double lum = 0.299 * ((p >> 16) & 0xff) + 0.587 * ((p >> 8) & 0xff) + 0.114 * (p & 0xff);
            m.dark[std::size_t(y) * m.w + x] = lum >= lo && lum < hi;
        }
    cairo_surface_destroy(s);
    return m;
}

// Share of a's dark pixels with a dark pixel of b within `r` pixels (Chebyshev distance).
double covered(const Mask& a, const Mask& b, int r) {
    std::size_t hit = 0, all = 0;
    for (int y = 0; y < a.h; ++y)
        for (int x = 0; x < a.w; ++x) {
            if (!a.dark[std::size_t(y) * a.w + x]) continue;
            ++all;
            bool found = false;
            for (int yy = std::max(0, y - r); yy <= std::min(b.h - 1, y + r) && !found; ++yy)
                for (int xx = std::max(0, x - r); xx <= std::min(b.w - 1, x + r) && !found; ++xx)
                    found = b.dark[std::size_t(yy) * b.w + xx];
            hit += found;
        }
    return all ? double(hit) / double(all) : 0.0;
}

// a without the pixels that have a pixel of b within r pixels.
Mask away_from(const Mask& a, const Mask& b, int r) {
    Mask m = a;
    for (int y = 0; y < a.h; ++y)
        for (int x = 0; x < a.w; ++x) {
            if (!a.dark[std::size_t(y) * a.w + x]) continue;
            for (int yy = std::max(0, y - r); yy <= std::min(b.h - 1, y + r); ++yy)
                for (int xx = std::max(0, x - r); xx <= std::min(b.w - 1, x + r); ++xx)
                    if (b.dark[std::size_t(yy) * b.w + xx]) m.dark[std::size_t(y) * a.w + x] = 0;
        }
    return m;
}

std::string camera_line(const std::string& out) {
    const auto at = out.rfind("camera: ");
    if (at == std::string::npos) return {};
    const auto end = out.find('\n', at);
    return out.substr(at + 8, end == std::string::npos ? std::string::npos : end - at - 8);
}

// The render command the window printed for its export to `exported` ("...; the same with:
// inkline render ... -o EXPORTED"), without its " -o EXPORTED"; empty if it did not print one.
std::string printed_render_command(const std::string& out, const fs::path& exported) {
    const std::string said = "; the same with: inkline ";
    const auto at = out.find(said);
    if (at == std::string::npos) return "";
    const std::string command = out.substr(at + said.size(), out.find('\n', at) - at - said.size());
    const std::string target = " -o " + exported.string();
    if (command.size() < target.size() || command.substr(command.size() - target.size()) != target) return "";
    return command.substr(0, command.size() - target.size());
}

// flags: given to both view and render; view_flags: to view only.
void expect_screenshot_is_render(const std::string& model, const std::string& flags, const std::string& view_flags = "") {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png", drawn = d / "render.png", other = d / "other.png";
    const Result v = run(kXvfb, "view " + test::mesh_path(model) + " --frames=6 --orbit --arc=60 --size=640x480 --screenshot=" +
                                    shot.string() + " " + flags + " " + view_flags, d);
    ASSERT_EQ(v.code, 0) << v.err;
    const std::string cam = camera_line(v.out);
    ASSERT_NE(cam.find("--size=640x480"), std::string::npos) << v.out;
    const Result r = run("", "render " + test::mesh_path(model) + " " + flags + " " + cam + " -o " + drawn.string() + " --quiet", d);
    ASSERT_EQ(r.code, 0) << r.err;
    const Mask a = dark_pixels(shot), b = dark_pixels(drawn);
    ASSERT_EQ(a.w, 640);
    ASSERT_EQ(a.h, 480);
    ASSERT_EQ(b.w, 640);
    ASSERT_EQ(b.h, 480);
    ASSERT_GT(b.count(), 1000u) << "render drew almost nothing";
    const double recall = covered(b, a, 2), precision = covered(a, b, 2);
    std::printf("%s: render %zu dark px, screenshot %zu; render's near the screenshot's %.4f, screenshot's near "
                "render's %.4f\n", model.c_str(), b.count(), a.count(), recall, precision);
    EXPECT_GE(recall, 0.9) << "render's line pixels without a screenshot line pixel within 2 px";
    EXPECT_GE(precision, 0.9) << "screenshot line pixels far from render's lines";
    EXPECT_GT(double(a.count()), 0.5 * double(b.count()));
    EXPECT_LT(double(a.count()), 2.0 * double(b.count()));
    // The check tells views apart: the first frame's camera (60 degrees before) does not match.
    const Result o = run("", "render " + test::mesh_path(model) + " " + flags + " --size=640x480 -o " + other.string() + " --quiet", d);
    ASSERT_EQ(o.code, 0) << o.err;
    const Mask c = dark_pixels(other);
    const double other_recall = covered(c, a, 2), other_precision = covered(a, c, 2);
    std::printf("against the first frame's camera: %.4f, %.4f\n", other_recall, other_precision);
    EXPECT_LT(std::min(other_recall, other_precision), 0.6);
}

TEST(ViewWindow, ScreenshotIsTheRenderDrawingFandisk) { expect_screenshot_is_render("fandisk.off", ""); }

// Two views at once (two sessions taking the views in turn, each following its own last view) and
// one at a time: either way the last frame is render's drawing at its camera.
TEST(ViewWindow, ScreenshotIsTheRenderDrawingWithOneOrTwoViewsInFlight) {
    expect_screenshot_is_render("fandisk.off", "", "--in-flight=1");
    expect_screenshot_is_render("fandisk.off", "", "--in-flight=2");
}

TEST(ViewWindow, ScreenshotIsTheRenderDrawingBunnyRandomizedFinder) {
    // Randomized finder with coherence along the orbit from a random first view; render runs the
    // exhaustive finder at the last camera, so this also checks the window's finder misses little.
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png", drawn = d / "render.png";
    const Result v = run(kXvfb, "view " + test::mesh_path("bunny00.off") + " --frames=6 --orbit --arc=60 --size=640x480 "
                                    "--finder=randomized --first-view=random --screenshot=" + shot.string(), d);
    ASSERT_EQ(v.code, 0) << v.err;
    const Result r = run("", "render " + test::mesh_path("bunny00.off") + " " + camera_line(v.out) + " -o " + drawn.string() + " --quiet", d);
    ASSERT_EQ(r.code, 0) << r.err;
    const Mask a = dark_pixels(shot), b = dark_pixels(drawn);
    ASSERT_GT(b.count(), 1000u);
    const double recall = covered(b, a, 2), precision = covered(a, b, 2);
    std::printf("bunny, randomized finder: render %zu dark px, screenshot %zu; %.4f, %.4f\n", b.count(), a.count(),
                recall, precision);
    EXPECT_GE(recall, 0.9);
    EXPECT_GE(precision, 0.9);
}

TEST(ViewWindow, RandomizedFinderFollowsAnExhaustiveFirstViewExactly) {
    // The window's default for the randomized finder: an exhaustive first view, then followed
    // exactly along the orbit, so the export at the last frame draws what the printed render
    // command (the exhaustive finder) writes: the same silhouette and the same line length at each
    // kind and QI, with as many ray tests (a finder that missed edges would leave clusters
    // inconsistent, each decided by a ray test per piece).
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    // One view at a time, two at once, and the default at 10 degrees a view (one at a time) and at
    // half a degree (one at a time for four views, then two at once: the second session's first
    // view comes after the first session's fourth).
    for (const std::string flags : {"--in-flight=1 --frames=6 --arc=60", "--in-flight=2 --frames=6 --arc=60",
                                    "--frames=6 --arc=60", "--frames=12 --arc=6 --threads=2 --fps"}) {
        SCOPED_TRACE(flags);
        const fs::path mine = d / "view.json", theirs = d / "render.json";
        const Result v = run(kXvfb, "view " + test::mesh_path("bunny00.off") + " --orbit --size=640x480 --finder=randomized "
                                        "--fraction=0.002 --hidden " + flags + " --export=" + mine.string(), d);
        ASSERT_EQ(v.code, 0) << v.err;
        if (flags.find("--fps") != std::string::npos) {  // (the views after the first frame's)
            EXPECT_NE(v.out.find("views: 4 one at a time on 2 threads, 7 two at once"), std::string::npos) << v.out;
        }
        std::string command = printed_render_command(v.out, mine);
        ASSERT_FALSE(command.empty()) << v.out;
        EXPECT_EQ(command.find("--finder=randomized"), std::string::npos) << command;
        command += " -o " + theirs.string() + " --quiet";
        const Result r = run("", command, d);
        ASSERT_EQ(r.code, 0) << command << "\n" << r.err;
        const auto a = nlohmann::json::parse(slurp(mine)), b = nlohmann::json::parse(slurp(theirs));
        EXPECT_EQ(a["stats"]["finder"], "randomized");
        EXPECT_EQ(a["stats"]["silhouette_edges"], b["stats"]["silhouette_edges"]);
        EXPECT_EQ(a["stats"]["ray_tests"], b["stats"]["ray_tests"]);  // (hidden lines: the occluded clusters')
        // (The finders list their edges in different orders, so chains start and run differently:
        // compared as line length per kind and QI.)
        auto lengths = [](const nlohmann::json& j) {
            std::map<std::pair<std::string, int>, double> out;
            for (const auto& p : j["polylines"]) {
                double len = 0.0;
                for (std::size_t k = 1; k < p["points"].size(); ++k)
                    len += std::hypot(double(p["points"][k][0]) - double(p["points"][k - 1][0]),
                                      double(p["points"][k][1]) - double(p["points"][k - 1][1]));
                out[{p["kind"].get<std::string>(), p["qi"].get<int>()}] += len;
            }
            return out;
        };
        const auto la = lengths(a), lb = lengths(b);
        ASSERT_EQ(la.size(), lb.size());
        ASSERT_GE(la.size(), 2u);  // visible and hidden lines
        for (const auto& [key, len] : lb) {
            ASSERT_TRUE(la.count(key)) << key.first << " qi " << key.second;
            EXPECT_NEAR(la.at(key), len, 1e-9 * len) << key.first << " qi " << key.second;
        }
    }
}

TEST(ViewWindow, StyledScreenshotIsWhatRenderWritesWithTheStyle) {
    // With --style the window shows the stylized drawing (brush strokes, offsets, hatching) as
    // render --style writes it at the same camera: the same pixels, not an approximation.
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    // (and with two views at once: two views stylized at the same time, on the two lanes' threads)
    for (const std::string in_flight : {"", " --in-flight=2"})
    for (const std::string style : {"ink-brush", "technical", "hatched"}) {
        SCOPED_TRACE(in_flight);
        const fs::path shot = d / (style + "-shot.png"), drawn = d / (style + "-render.png");
        const Result v = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=3 --orbit --arc=20 --size=480x360 "
                                        "--style=" + style + in_flight + " --screenshot=" + shot.string(), d);
        ASSERT_EQ(v.code, 0) << v.err;
        const Result r = run("", "render " + test::mesh_path("fandisk.off") + " --style=" + style + " " + camera_line(v.out) +
                                     " -o " + drawn.string() + " --quiet", d);
        ASSERT_EQ(r.code, 0) << r.err;
        for (const double hi : {128.0, 235.0}) {  // black lines; then grey ones too (hidden, hatching)
            const Mask a = dark_pixels(shot, -1.0, hi), b = dark_pixels(drawn, -1.0, hi);
            ASSERT_GT(b.count(), 500u) << style;
            const double recall = covered(b, a, 0), precision = covered(a, b, 0);
            std::printf("%s (< %.0f): render %zu px, screenshot %zu; same pixel %.4f, %.4f\n", style.c_str(), hi,
                        b.count(), a.count(), recall, precision);
            EXPECT_GE(recall, 0.999) << style;
            EXPECT_GE(precision, 0.999) << style;
        }
    }
    // A bad style is refused before a window opens, naming the style.
    const Result bad = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=1 --style=no-such-style", d);
    EXPECT_NE(bad.code, 0);
    EXPECT_NE(bad.err.find("no-such-style"), std::string::npos) << bad.err;
}

TEST(ViewWindow, HiddenLinesAreDrawnGreyWhereRenderDrawsThem) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png", drawn = d / "render.png", plain = d / "plain.png";
    const Result v = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=3 --orbit --arc=20 --size=640x480 --hidden "
                                    "--screenshot=" + shot.string(), d);
    ASSERT_EQ(v.code, 0) << v.err;
    const std::string cam = camera_line(v.out);
    ASSERT_EQ(run("", "render " + test::mesh_path("fandisk.off") + " --hidden " + cam + " -o " + drawn.string() + " --quiet", d).code, 0);
    ASSERT_EQ(run("", "render " + test::mesh_path("fandisk.off") + " " + cam + " -o " + plain.string() + " --quiet", d).code, 0);
    // Grey away from black: the hidden lines (dashed, thinner, lighter), not the antialiased rims
    // of the visible ones.
    const Mask a_dark = dark_pixels(shot), b_dark = dark_pixels(drawn), c_dark = dark_pixels(plain);
    const Mask a = away_from(dark_pixels(shot, 128.0, 235.0), a_dark, 2);
    const Mask b = away_from(dark_pixels(drawn, 128.0, 235.0), b_dark, 2);
    const Mask c = away_from(dark_pixels(plain, 128.0, 235.0), c_dark, 2);
    const double recall = covered(b, a, 3), precision = covered(a, b, 3);
    std::printf("hidden: render %zu grey px away from lines (%zu without --hidden), screenshot %zu; %.4f, %.4f\n",
                b.count(), c.count(), a.count(), recall, precision);
    ASSERT_GT(b.count(), 300u) << "render --hidden drew few hidden lines";
    ASSERT_LT(c.count(), b.count() / 10);
    EXPECT_GE(recall, 0.8);
    EXPECT_GE(precision, 0.8);
    EXPECT_GT(double(a.count()), 0.5 * double(b.count()));
    EXPECT_LT(double(a.count()), 2.0 * double(b.count()));
    EXPECT_GE(covered(b_dark, a_dark, 2), 0.9);  // the visible lines as without --hidden
    EXPECT_GE(covered(a_dark, b_dark, 2), 0.9);
}

TEST(ViewWindow, ShadingFillsTheModelUnderTheSameLines) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png", drawn = d / "render.png";
    const Result v = run(kXvfb, "view " + test::mesh_path("bunny00.off") + " --frames=2 --size=640x480 --shading --screenshot=" +
                                    shot.string(), d);
    ASSERT_EQ(v.code, 0) << v.err;
    ASSERT_EQ(run("", "render " + test::mesh_path("bunny00.off") + " " + camera_line(v.out) + " -o " + drawn.string() + " --quiet", d).code, 0);
    const Mask a_dark = dark_pixels(shot), b_dark = dark_pixels(drawn);
    const Mask grey = away_from(dark_pixels(shot, 150.0, 245.0), a_dark, 2);  // the shading's bands
    // The lines' bounding box, grown by 3 px: the shading lies inside it and fills much of it.
    int x0 = b_dark.w, y0 = b_dark.h, x1 = -1, y1 = -1;
    for (int y = 0; y < b_dark.h; ++y)
        for (int x = 0; x < b_dark.w; ++x)
            if (b_dark.dark[std::size_t(y) * b_dark.w + x]) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    ASSERT_GE(x1, x0);
    std::size_t inside = 0;
    for (int y = 0; y < grey.h; ++y)
        for (int x = 0; x < grey.w; ++x)
            inside += grey.dark[std::size_t(y) * grey.w + x] && x >= x0 - 3 && x <= x1 + 3 && y >= y0 - 3 && y <= y1 + 3;
    const double box = double(x1 - x0 + 1) * double(y1 - y0 + 1);
    std::printf("shading: %zu grey px, %zu inside the lines' box of %.0f px; lines %.4f, %.4f\n", grey.count(), inside,
                box, covered(b_dark, a_dark, 2), covered(a_dark, b_dark, 2));
    EXPECT_GT(double(grey.count()), 0.3 * box);
    EXPECT_GE(double(inside), 0.99 * double(grey.count()));
    EXPECT_GE(covered(b_dark, a_dark, 2), 0.9);  // the lines drawn over the shading are render's
    EXPECT_GE(covered(a_dark, b_dark, 2), 0.9);
}

// ---- The tone pass (tone_pass.hpp) ---------------------------------------------------------------

TEST(ToneLight, AnglesRoundTripAndTurnWithTheCamera) {
    const Camera cam = Camera::perspective({3, 4, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 640, 480);
    // The CPU pass's default headlight is view + up - 0.7 right: 35 degrees left, 39.3 up.
    const LightAngles home = light_angles(cam, tone::default_light(cam));
    EXPECT_NEAR(home.azimuth_deg, -std::atan(0.7) * 180.0 / M_PI, 1e-9);
    EXPECT_NEAR(home.elevation_deg, std::asin(1.0 / std::sqrt(2.49)) * 180.0 / M_PI, 1e-9);
    expect_near(light_direction(cam, home), tone::default_light(cam), 1e-12);
    expect_near(light_direction(cam, {0.0, 0.0}), -cam.forward(), 1e-12);  // from the eye
    expect_near(light_direction(cam, {90.0, 0.0}), cam.right(), 1e-12);
    expect_near(light_direction(cam, {0.0, 90.0}), cam.upward(), 1e-12);
    // The same angles from another camera: the light turned with it.
    const Camera other = Camera::perspective({-5, 4, 3}, {0, 0, 0}, {0, 1, 0}, 30.0, 640, 480);
    expect_near(light_direction(other, home), tone::default_light(other), 1e-12);
}

// The window's GLSL tone pass against render's CPU pass at the window's last camera: the
// screenshot's dark pixels (lum < `dark_below`) and render's, each within 1 px of the other's.
struct ToneAgreement {
    std::size_t shot_px = 0, render_px = 0;
    double render_near_shot = 0.0, shot_near_render = 0.0;
};
// view_only: where the window's pass runs (GLSL by default here: the window tests run on a
// software renderer, where --tone-pass=auto would pick the CPU).
ToneAgreement tone_agreement(const std::string& model, const std::string& flags, double dark_below,
                             const std::string& render_only = "", const std::string& view_only = "--tone-pass=glsl") {
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png", drawn = d / "render.png";
    const Result v = run(kXvfb, "view " + test::mesh_path(model) + " --frames=3 --orbit --arc=20 --size=640x480 --no-panel " +
                                    flags + " " + view_only + " --screenshot=" + shot.string(), d);
    EXPECT_EQ(v.code, 0) << v.err;
    const Result r = run("", "render " + test::mesh_path(model) + " " + flags + " " + camera_line(v.out) + " " + render_only +
                                 " -o " + drawn.string() + " --quiet", d);
    EXPECT_EQ(r.code, 0) << r.err;
    const Mask a = dark_pixels(shot, -1.0, dark_below), b = dark_pixels(drawn, -1.0, dark_below);
    EXPECT_EQ(a.w, 640);
    EXPECT_EQ(b.w, 640);
    ToneAgreement t{a.count(), b.count(), covered(b, a, 1), covered(a, b, 1)};
    std::printf("%s %s %s: screenshot %zu dark px, render %zu; render's within 1 px of the screenshot's %.4f, the "
                "screenshot's within 1 px of render's %.4f\n", model.c_str(), flags.c_str(), render_only.c_str(),
                t.shot_px, t.render_px, t.render_near_shot, t.shot_near_render);
    return t;
}

TEST(ViewWindow, TonePassDrawsTheLinesRenderTraces) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    for (const char* model : {"bunny00.off", "armadillo.off"}) {
        // Dark lines alone (black over white), then over the toon base (its darkest band is grey
        // 110: "dark" is below 80 there, a line of opacity over about a quarter).
        const ToneAgreement lines = tone_agreement(model, "--lines=tone-dark", 128.0);
        EXPECT_GT(lines.render_px, 500u);
        EXPECT_GE(lines.render_near_shot, 0.9);
        EXPECT_GE(lines.shot_near_render, 0.85);
        const ToneAgreement all = tone_agreement(model, "--lines=tone-dark,tone-highlight --base=toon", 80.0);
        EXPECT_GE(all.render_near_shot, 0.9);
        EXPECT_GE(all.shot_near_render, 0.85);
    }
    // Section 3.4's widths, the same in both.
    for (const char* width_by : {"depth", "edge-length"}) {
        const ToneAgreement w = tone_agreement("armadillo.off", std::string("--lines=tone-dark --tone-line-width=") + width_by, 128.0);
        EXPECT_GE(w.render_near_shot, 0.9) << width_by;
        EXPECT_GE(w.shot_near_render, 0.8) << width_by;  // (render's thinner strokes: fewer dark pixels)
    }
    // The check tells lights apart: render's lines under a light turned away do not match.
    const ToneAgreement other = tone_agreement("bunny00.off", "--lines=tone-dark", 128.0, "--light=1,0,0");
    EXPECT_LT(std::min(other.render_near_shot, other.shot_near_render), 0.6);
}

// Without a GPU the window runs render's CPU pass and uploads its image: the same per-pixel
// opacities as render traces, so at least as close to render's drawing as the GLSL pass.
TEST(ViewWindow, TonePassOnTheCpuDrawsWhatRenderDraws) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    for (const char* model : {"bunny00.off", "armadillo.off"}) {
        const ToneAgreement lines = tone_agreement(model, "--lines=tone-dark", 128.0, "", "--tone-pass=cpu");
        EXPECT_GT(lines.render_px, 500u);
        EXPECT_GE(lines.render_near_shot, 0.9);
        EXPECT_GE(lines.shot_near_render, 0.85);
        const ToneAgreement all = tone_agreement(model, "--lines=tone-dark,tone-highlight --base=toon", 80.0, "", "--tone-pass=cpu");
        EXPECT_GE(all.render_near_shot, 0.9);
        EXPECT_GE(all.shot_near_render, 0.85);
    }
    const ToneAgreement other = tone_agreement("bunny00.off", "--lines=tone-dark", 128.0, "--light=1,0,0", "--tone-pass=cpu");
    EXPECT_LT(std::min(other.render_near_shot, other.shot_near_render), 0.6);
}

TEST(ViewWindow, ToneFlagsAreCheckedAndTheExportHasTracedToneLines) {
    const fs::path d = scratch();
    for (const auto& [flags, words] : std::vector<std::pair<std::string, std::string>>{
             {"--tone-width=0", "--tone-width"},
             {"--tone-beta=1.5", "--tone-beta"},
             {"--tone-dark=0.2,0.1", "--tone-dark"},
             {"--light=0,0,0", "--light"},
             {"--light=1,0,0 --light=0,1,0", "one light"},
             {"--tone-pass=gpu", "--tone-pass"}}) {
        const Result r = run("", "view " + test::mesh_path("fandisk.off") + " --lines=tone-dark --frames=1 " + flags, d);
        EXPECT_EQ(r.code, 2) << flags;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(words), std::string::npos) << flags << ": " << r.err;
    }
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    // The export runs render's CPU pass: traced tone lines with opacity per point, and the printed
    // render command (with the panel's light) writes the same JSON.
    const fs::path exported = d / "export.json", again = d / "again.json";
    const Result v = run(kXvfb, "view " + test::mesh_path("bunny00.off") + " --frames=2 --size=320x240 --no-panel "
                                    "--lines=tone-dark --tone-width=5 --export=" + exported.string(), d);
    ASSERT_EQ(v.code, 0) << v.err;
    const std::string command = printed_render_command(v.out, exported);
    ASSERT_NE(command.find("--tone-width=5"), std::string::npos) << v.out;
    ASSERT_NE(command.find("--light="), std::string::npos) << v.out;
    ASSERT_EQ(run("", command + " -o " + again.string() + " --quiet", d).code, 0) << command;
    std::ifstream a(exported), b(again);
    const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
    std::size_t tone_lines = 0;
    for (const auto& p : ja["polylines"]) tone_lines += p["kind"] == "tone-dark" && p.contains("opacity");
    EXPECT_GT(tone_lines, 5u);
    EXPECT_EQ(ja["polylines"], jb["polylines"]);
}

TEST(ViewWindow, ExportIsWhatThePrintedRenderCommandWrites) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const fs::path exported = d / "view.json", rendered = d / "render.json";
    const Result v = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=4 --orbit --arc=30 --size=500x400 "
                                    "--hidden --crease=30 --export=" + exported.string(), d);
    ASSERT_EQ(v.code, 0) << v.err;
    std::string command = printed_render_command(v.out, exported);
    ASSERT_FALSE(command.empty()) << v.out;
    command += " -o " + rendered.string() + " --quiet";
    EXPECT_NE(command.find("--hidden"), std::string::npos) << command;
    EXPECT_NE(command.find("--crease=30"), std::string::npos) << command;
    const Result r = run("", command, d);
    ASSERT_EQ(r.code, 0) << command << "\n" << r.err;
    const auto a = nlohmann::json::parse(slurp(exported)), b = nlohmann::json::parse(slurp(rendered));
    EXPECT_EQ(a["width"], 500);
    EXPECT_EQ(a["height"], 400);
    EXPECT_EQ(a["camera"], b["camera"]);
    ASSERT_EQ(a["polylines"].size(), b["polylines"].size());
    ASSERT_GT(a["polylines"].size(), 50u);
    std::size_t hidden = 0;
    for (std::size_t i = 0; i < a["polylines"].size(); ++i) {
        const auto &p = a["polylines"][i], &q = b["polylines"][i];
        ASSERT_EQ(p["kind"], q["kind"]) << i;
        ASSERT_EQ(p["qi"], q["qi"]) << i;
        ASSERT_EQ(p["points"].size(), q["points"].size()) << i;
        for (std::size_t k = 0; k < p["points"].size(); ++k)
            for (int c = 0; c < 2; ++c)
                ASSERT_NEAR(p["points"][k][c].get<double>(), q["points"][k][c].get<double>(), 1e-9) << i;
        hidden += p["qi"].get<int>() > 0;
    }
    EXPECT_GT(hidden, 0u);  // hidden pieces exported with --hidden
}

TEST(ViewWindow, PrintedCameraIsReproducedByRender) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    for (const std::string flags : {"--eye=3,1,2 --target=0,0.1,0 --fov=40", "--ortho=1.2 --eye=0,2,3"}) {
        const Result v = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=3 --orbit --arc=30 --size=320x200 " + flags, d);
        ASSERT_EQ(v.code, 0) << v.err;
        const std::string cam = camera_line(v.out);
        EXPECT_EQ(cam.find("--ortho") != std::string::npos, flags.find("--ortho") != std::string::npos) << cam;
        const Result r = run("", "render " + test::mesh_path("fandisk.off") + " " + cam + " -o " + (d / "r.json").string(), d);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(camera_line(r.out), cam);  // the same flags, digit for digit
    }
}

// The panel is kept as a layer (src/view/ui_layer.cpp) rasterized only when it changes and blended
// over each frame: the result must be what ImGui draws directly, over a pattern that shows its
// translucency, and the layer must tell a changed panel from an unchanged one.
TEST(ViewWindow, PanelLayerLooksLikeImGuiDrawnDirectly) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    const std::string cmd = std::string(kXvfb) + INKLINE_UI_LAYER_CHECK + " >" + (d / "out").string() + " 2>&1";
    const int status = std::system(cmd.c_str());
    const std::string out = inkline_test::slurp(d / "out");
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
    int max_diff = -1, first = -1, same_again = -1, changed_again = -1;
    std::size_t differing = 0, panel = 0, rasterized = 0;
    ASSERT_EQ(std::sscanf(out.c_str(), "max_diff=%d differing=%zu panel_pixels=%zu first=%d same_again=%d changed_again=%d rasterized=%zu",
                          &max_diff, &differing, &panel, &first, &same_again, &changed_again, &rasterized), 7)
        << out;
    std::printf("%s", out.c_str());
    EXPECT_GT(panel, 10000u) << "the panel drew almost nothing";
    EXPECT_LE(max_diff, 2) << "the layer blended over the pattern differs from ImGui's own drawing";
    EXPECT_LT(differing, panel / 20) << "more than rounding differs";
    EXPECT_EQ(first, 1);
    EXPECT_EQ(same_again, 1) << "the same draw data was rasterized again";
    EXPECT_EQ(changed_again, 1) << "a changed panel was not rasterized";
    EXPECT_EQ(rasterized, 2u);
}

// Every line of the panel is whole (none cut off at its right edge: the window measures its widest
// line against where it clips), and the panel is no taller than the window (a scroll bar shows the
// rest), with the most rows (the recall line, hidden lines, a style) and in a small window.
TEST(ViewWindow, PanelLinesAreWholeAndThePanelFitsTheWindow) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup.sh installs it)";
    const fs::path d = scratch();
    // (the tone pass's section open with its sliders: the second set of flags; the pm detail's status)
    for (const auto& [size, height, flags] : {std::tuple{"1024x768", 768.0, ""}, std::tuple{"640x480", 480.0, ""},
                                              std::tuple{"1024x768", 768.0, " --lines=silhouette,tone-dark --base=toon"},
                                              std::tuple{"640x480", 480.0, " --lines=silhouette,tone-dark --base=toon"},
                                              std::tuple{"1024x768", 768.0, " --lines=silhouette,suggestive --detail=3 --detail-method=pm"}}) {
        const Result v = run(kXvfb, "view " + test::mesh_path("fandisk.off") + " --frames=4 --orbit --arc=20 --recall --hidden --size=" +
                                        size + flags + " --screenshot-ui --screenshot=" + (d / "ui.png").string(), d);
        ASSERT_EQ(v.code, 0) << v.err;
        const auto at = v.out.find("panel: ");
        ASSERT_NE(at, std::string::npos) << v.out;
        double w = 0, h = 0, past = -1;
        ASSERT_EQ(std::sscanf(v.out.c_str() + at, "panel: %lf x %lf px, its widest line %lf px past its clipped edge", &w,
                              &h, &past), 3)
            << v.out;
        std::printf("%s%s: panel %.0f x %.0f px, widest line %.0f px past its edge\n", size, flags, w, h, past);
        EXPECT_EQ(past, 0.0) << "a line of the panel is cut off";
        EXPECT_GT(w, 100.0);
        EXPECT_GT(h, 100.0);
        EXPECT_LE(h, height) << "the panel is taller than the window";
    }
}

TEST(ViewWindow, NoDisplayIsAOneLineErrorNotACrash) {
    const fs::path d = scratch();
    const fs::path shot = d / "shot.png";
    const Result r = run("env -u DISPLAY -u WAYLAND_DISPLAY ",
                         "view " + test::mesh_path("fandisk.off") + " --frames=2 --screenshot=" + shot.string(), d);
    EXPECT_EQ(r.code, 1) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("inkline: view: cannot open a window"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(shot));
}

TEST(ViewWindow, UsageErrors) {
    const fs::path d = scratch();
    EXPECT_EQ(run("", "view " + test::mesh_path("fandisk.off") + " --orbit", d).code, 2);  // --orbit needs --frames
    EXPECT_EQ(run("", "view", d).code, 2);
    const Result lanes = run("", "view " + test::mesh_path("fandisk.off") + " --in-flight=3 --frames=1", d);
    EXPECT_NE(lanes.code, 0);
    EXPECT_NE(lanes.err.find("--in-flight"), std::string::npos) << lanes.err;
    const Result first = run("", "view " + test::mesh_path("fandisk.off") + " --first-view=sideways --frames=1", d);
    EXPECT_NE(first.code, 0);
    EXPECT_NE(first.err.find("--first-view"), std::string::npos) << first.err;
    const Result bad = run("", "view " + (d / "missing.off").string() + " --frames=1", d);
    EXPECT_EQ(bad.code, 1);
    EXPECT_NE(bad.err.find("missing.off"), std::string::npos) << bad.err;
}

}  // namespace
