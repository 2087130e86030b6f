// Stylization stage: strokes from pieces (chaining, arc length, resampling).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "style/hatching.hpp"
#include "style/strokes.hpp"
#include "style/noise.hpp"
#include "style/offsets.hpp"
#include "style/style.hpp"
#include "style/stylize.hpp"

using inkline::ArcPolyline;
using inkline::Drawing;
using inkline::LineKind;
using inkline::Piece;

namespace {

Drawing drawing_of(std::vector<Piece> pieces) {
    Drawing d;
    d.camera = inkline::Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 200, 200);
    d.pieces = std::move(pieces);
    return d;
}

}  // namespace

TEST(ArcLength, CumulativeLengthAndPointAt) {
    const ArcPolyline a({{0, 0}, {3, 4}, {3, 4}, {3, 14}});  // duplicate vertex dropped
    ASSERT_EQ(a.size(), 3u);
    EXPECT_DOUBLE_EQ(a.arc()[1], 5.0);
    EXPECT_DOUBLE_EQ(a.length(), 15.0);
    const glm::dvec2 m = a.at(2.5);
    EXPECT_NEAR(m.x, 1.5, 1e-12);
    EXPECT_NEAR(m.y, 2.0, 1e-12);
    const glm::dvec2 q = a.at(10.0);
    EXPECT_NEAR(q.x, 3.0, 1e-12);
    EXPECT_NEAR(q.y, 9.0, 1e-12);
    EXPECT_EQ(a.at(-1.0), glm::dvec2(0, 0));
    EXPECT_EQ(a.at(99.0), glm::dvec2(3, 14));
    const glm::dvec2 t = a.tangent(12.0);
    EXPECT_NEAR(t.x, 0.0, 1e-12);
    EXPECT_NEAR(t.y, 1.0, 1e-12);
    const glm::dvec2 t0 = a.tangent(1.0);
    EXPECT_NEAR(t0.x, 0.6, 1e-12);
    EXPECT_NEAR(t0.y, 0.8, 1e-12);
}

TEST(ArcLength, ResampleIsUniformInArcLength) {
    // A quarter circle of radius 100 as 7 uneven segments, resampled every 2 px.
    std::vector<glm::dvec2> pts;
    for (double a : {0.0, 0.05, 0.3, 0.31, 0.9, 1.2, 1.5, M_PI / 2}) pts.push_back({100 * std::cos(a), 100 * std::sin(a)});
    const ArcPolyline arc(pts);
    const auto r = arc.resample(2.0);
    ASSERT_EQ(r.size(), std::size_t(std::ceil(arc.length() / 2.0)) + 1);
    EXPECT_EQ(r.front(), pts.front());
    EXPECT_EQ(r.back(), pts.back());
    // Every sample lies on the original polyline, at arc length 0, 2, 4, ... measured along it
    // (found here by projecting onto the nearest segment and summing the segment lengths before it).
    for (std::size_t k = 0; k < r.size(); ++k) {
        const glm::dvec2 q = r[k];
        double best = 1e300, s_at = 0.0, before = 0.0;
        for (std::size_t i = 1; i < pts.size(); ++i) {
            const glm::dvec2 a = pts[i - 1], d = pts[i] - a;
            const double t = std::clamp(glm::dot(q - a, d) / glm::dot(d, d), 0.0, 1.0);
            const double dist = glm::distance(q, a + t * d);
            if (dist < best) best = dist, s_at = before + t * glm::length(d);
            before += glm::length(d);
        }
        EXPECT_LT(best, 1e-9);
        EXPECT_NEAR(s_at, k + 1 < r.size() ? 2.0 * double(k) : arc.length(), 1e-9);
    }
    // A straight line with uneven vertices: samples exactly every 2 px, the last one at the end.
    const auto line = ArcPolyline({{0, 5}, {0.5, 5}, {7.25, 5}, {9, 5}}).resample(2.0);
    ASSERT_EQ(line.size(), 6u);
    for (std::size_t i = 0; i + 1 < line.size(); ++i) EXPECT_NEAR(line[i].x, 2.0 * double(i), 1e-12);
    EXPECT_EQ(line.back(), glm::dvec2(9, 5));
}

TEST(Chaining, PiecesOfOneCurveJoinEndToEndWhateverTheirOrientation) {
    // Curve 7 cut into three pieces, the middle one stored backwards, and a sharp corner between
    // the last two: pieces of the same curve join whatever the turn.
    const Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 7, {{10, 10}, {20, 10}}},
        {LineKind::Silhouette, 0, 7, {{40, 10}, {30, 10}, {20, 10}}},
        {LineKind::Silhouette, 0, 7, {{40, 10}, {40, 50}}},
    });
    const auto s = inkline::chain_strokes(d);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s[0].pieces.size(), 3u);
    EXPECT_FALSE(s[0].closed);
    EXPECT_DOUBLE_EQ(s[0].path.length(), 70.0);
    const auto& p = s[0].path.points();
    // Either direction, but in order along the curve.
    const bool forward = p.front() == glm::dvec2(10, 10);
    EXPECT_EQ(forward ? p.back() : p.front(), glm::dvec2(40, 50));
    EXPECT_EQ(p.size(), 5u);  // shared end points appear once
}

TEST(Chaining, AcrossJunctionsOnlyWhereTheTangentContinues) {
    const Drawing d = drawing_of({
        {LineKind::Crease, 0, 1, {{0, 0}, {50, 0}}},
        {LineKind::Crease, 0, 2, {{50, 0}, {100, 5}}},    // turns by ~5.7 degrees: joined
        {LineKind::Crease, 0, 3, {{100, 5}, {100, 60}}},  // turns by ~84 degrees: not joined
    });
    const auto s = inkline::chain_strokes(d);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].pieces.size() + s[1].pieces.size(), 3u);
    const auto& longer = s[0].pieces.size() == 2 ? s[0] : s[1];
    ASSERT_EQ(longer.pieces.size(), 2u);
    EXPECT_NEAR(longer.path.length(), 50.0 + std::hypot(50.0, 5.0), 1e-9);

    inkline::ChainOptions wide;
    wide.max_turn_degrees = 90;
    EXPECT_EQ(inkline::chain_strokes(d, wide).size(), 1u);
    inkline::ChainOptions none;
    none.join = false;
    EXPECT_EQ(inkline::chain_strokes(d, none).size(), 3u);
}

TEST(Chaining, NeverAcrossGapsKindsOrQi) {
    const Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 1, {{0, 0}, {50, 0}}},
        {LineKind::Silhouette, 0, 1, {{50.5, 0}, {100, 0}}},  // same curve, half a pixel gap
        {LineKind::Border, 0, 1, {{100, 0}, {150, 0}}},       // other kind
        {LineKind::Silhouette, 1, 1, {{0, 0}, {-50, 0}}},     // hidden (QI 1)
    });
    EXPECT_EQ(inkline::chain_strokes(d).size(), 3u);  // the hidden piece is not drawn
    inkline::ChainOptions hidden;
    hidden.hidden = true;
    const auto s = inkline::chain_strokes(d, hidden);
    ASSERT_EQ(s.size(), 4u);
    for (const auto& st : s) EXPECT_EQ(st.pieces.size(), 1u);
}

TEST(Chaining, ClosedLoopAndUnusablePieces) {
    const double nan = std::nan("");
    const Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 4, {{0, 0}, {10, 0}, {10, 10}}},
        {LineKind::Silhouette, 0, 4, {{10, 10}, {0, 10}, {0, 0}}},
        {LineKind::Silhouette, 0, 5, {{30, 30}}},                // one point
        {LineKind::Silhouette, 0, 6, {{40, 40}, {nan, 40}}},     // not finite
    });
    const auto s = inkline::chain_strokes(d);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_TRUE(s[0].closed);
    EXPECT_EQ(s[0].path.points().front(), s[0].path.points().back());
    EXPECT_DOUBLE_EQ(s[0].path.length(), 40.0);
}

// ---- Style files -----------------------------------------------------------------------------

namespace {

std::string error_of(const std::string& json_text, const std::string& file = "/tmp/s/mine.json") {
    try {
        inkline::parse_style(json_text, file);
    } catch (const inkline::Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(StyleFile, PresetsLoadAndCleanIsTheBuiltInDefault) {
    for (const char* name : {"clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched"}) {
        const inkline::Style s = inkline::load_style(name);
        EXPECT_EQ(s.name, name);
    }
    const inkline::Style file = inkline::load_style("clean"), builtin = inkline::Style::clean();
    ASSERT_EQ(file.hidden.size(), builtin.hidden.size());
    for (std::size_t i = 0; i < file.hidden.size(); ++i) {
        EXPECT_EQ(file.hidden[i].rgb, builtin.hidden[i].rgb);
        EXPECT_EQ(file.hidden[i].width, builtin.hidden[i].width);
        EXPECT_EQ(file.hidden[i].dash_on, builtin.hidden[i].dash_on);
        EXPECT_EQ(file.hidden[i].dash_off, builtin.hidden[i].dash_off);
    }
    for (const auto& l : file.lines) {
        EXPECT_TRUE(l.plain());
        EXPECT_EQ(l.rgb, 0u);
        EXPECT_EQ(l.width, 1.0);
    }
    EXPECT_FALSE(file.draw_hidden);
    // The presets that are more than lines use what they say.
    EXPECT_TRUE(inkline::load_style("technical").draw_hidden);
    EXPECT_TRUE(inkline::load_style("technical").for_qi(LineKind::Crease, 7).omit);
    EXPECT_TRUE(inkline::load_style("charcoal").lines[0].offsets.has_value());
    EXPECT_FALSE(inkline::load_style("ink-brush").lines[0].brush.empty());
    EXPECT_DOUBLE_EQ(inkline::load_style("ink-brush").lines[0].brush_aspect, 4.0);  // 128 x 32 image
    EXPECT_TRUE(inkline::load_style("hatched").hatching.enabled);
}

TEST(StyleFile, KindsOverrideDefaultKeyByKey) {
    const inkline::Style s = inkline::parse_style(
        R"({"lines": {"default": {"colour": "#102030", "width": 2}, "crease": {"width": 0.5}}, "hidden": [{"dash": [3, 1]}]})",
        "/tmp/s/x.json");
    EXPECT_EQ(s.lines[int(LineKind::Crease)].rgb, 0x102030u);
    EXPECT_EQ(s.lines[int(LineKind::Crease)].width, 0.5);
    EXPECT_EQ(s.lines[int(LineKind::Silhouette)].width, 2.0);
    ASSERT_EQ(s.hidden.size(), 1u);
    EXPECT_EQ(s.for_qi(LineKind::Border, 4).dash_on, 3.0);  // QI beyond the last entry: the last
    EXPECT_EQ(s.for_qi(LineKind::Border, 4).rgb, 0x7f7f7fu);  // from clean's first hidden level
}

TEST(StyleFile, ErrorsNameFileKeyAndExpectedValues) {
    std::string e = error_of(R"({"colour": "#000000"})");
    EXPECT_NE(e.find("/tmp/s/mine.json: unknown key 'colour'"), std::string::npos) << e;
    EXPECT_NE(e.find("expected one of"), std::string::npos) << e;
    EXPECT_NE(e.find("lines"), std::string::npos) << e;

    e = error_of(R"({"lines": {"crease": {"colr": "#000000"}}})");
    EXPECT_NE(e.find("unknown key 'lines.crease.colr'"), std::string::npos) << e;
    EXPECT_NE(e.find("colour"), std::string::npos) << e;

    e = error_of(R"({"lines": {"silhouette": {"width_rule": "wide"}}})");
    EXPECT_NE(e.find("key 'lines.silhouette.width_rule'"), std::string::npos) << e;
    EXPECT_NE(e.find("constant, taper"), std::string::npos) << e;

    e = error_of(R"({"lines": {"default": {"colour": "red"}}})");
    EXPECT_NE(e.find("key 'lines.default.colour': expected a colour \"#rrggbb\", got \"red\""), std::string::npos) << e;

    e = error_of(R"({"lines": {"default": {"opacity": 2}}})");
    EXPECT_NE(e.find("key 'lines.default.opacity': expected a number in [0, 1], got 2"), std::string::npos) << e;

    e = error_of(R"({"hidden": [{"dash": [1]}]})");
    EXPECT_NE(e.find("key 'hidden[0].dash': expected [on, off]"), std::string::npos) << e;

    e = error_of(R"({"hidden": {"qi": 1}})");
    EXPECT_NE(e.find("key 'hidden': expected an array"), std::string::npos) << e;

    e = error_of(R"({"lines": {"default": {"offsets": {"table": "no-such-table"}}}})");
    EXPECT_NE(e.find("key 'lines.default.offsets.table': no such file '/tmp/s/offsets/no-such-table.txt'"),
              std::string::npos) << e;

    e = error_of(R"({"hatching": {"segments": "four"}})");
    EXPECT_NE(e.find("key 'hatching.segments': expected a number in [1, 64]"), std::string::npos) << e;

    e = error_of(R"({"lines": )");
    EXPECT_NE(e.find("/tmp/s/mine.json: not valid JSON"), std::string::npos) << e;

    e = error_of(R"([1, 2])");
    EXPECT_NE(e.find("expected an object"), std::string::npos) << e;

    // Each is one line.
    for (const std::string& m : {error_of(R"({"x": 1})"), error_of("{")}) EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_THROW(inkline::load_style("no-such-style-anywhere"), inkline::Error);
    EXPECT_THROW(inkline::load_style_file("/nonexistent/dir/s.json"), inkline::Error);
}

