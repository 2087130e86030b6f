// Stylization stage: strokes from pieces (chaining, arc length, resampling).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <cairo.h>
#include <filesystem>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "output/styled.hpp"
#include "style/attributes.hpp"
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

TEST(Chaining, NeverAcrossObjectsSpecksJoinAnyNeighbourOrAreDropped) {
    Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 1, {{0, 0}, {50, 0}}},
        {LineKind::Silhouette, 0, 2, {{50, 0}, {100, 0}}},    // straight on, but another object
        {LineKind::Silhouette, 0, 3, {{100, 0}, {100, 0.6}}},  // a speck at a right angle: joined
        {LineKind::Silhouette, 0, 4, {{0, 20}, {0.3, 20}, {0.6, 20}}},  // a lone speck of 0.6 px
        {LineKind::Silhouette, 0, 5, {{0, 40}, {0.5, 40}}},    // two specks, 0.9 px together:
        {LineKind::Silhouette, 0, 6, {{0.5, 40}, {0.5, 40.4}}},  // still a speck, dropped
    });
    d.pieces[1].object = d.pieces[2].object = 1;
    inkline::ChainStats st;
    const auto s = inkline::chain_strokes(d, {}, nullptr, &st);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s[0].pieces, (std::vector<std::uint32_t>{0}));
    EXPECT_EQ(s[0].object, 0u);
    EXPECT_EQ(s[1].pieces.size(), 2u);
    EXPECT_EQ(s[1].object, 1u);
    EXPECT_DOUBLE_EQ(s[1].path.length(), 50.6);
    EXPECT_EQ(st.specks_dropped, 3u);  // pieces 3, 4 and 5

    inkline::ChainOptions keep;
    keep.keep_specks = true;
    const auto k = inkline::chain_strokes(d, keep, nullptr, &st);
    EXPECT_EQ(k.size(), 4u);
    EXPECT_EQ(st.specks_dropped, 0u);
    // Without joining each piece is a stroke; the specks are still dropped.
    inkline::ChainOptions apart;
    apart.join = false;
    EXPECT_EQ(inkline::chain_strokes(d, apart, nullptr, &st).size(), 2u);
    EXPECT_EQ(st.specks_dropped, 4u);
    // A style keeps them with chain.keep_specks (the command's --keep-specks sets it too).
    EXPECT_TRUE(inkline::parse_style(R"({"chain": {"keep_specks": true}})", "/tmp/s/k.json").keep_specks);
    EXPECT_FALSE(inkline::Style::clean().keep_specks);
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
    for (const char* name : {"clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched", "illustration"}) {
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
    for (int k = 0; k < inkline::kPieceKindCount; ++k) {
        const auto& l = file.lines[std::size_t(k)];
        EXPECT_TRUE(l.plain()) << inkline::to_string(LineKind(k));
        EXPECT_EQ(l.rgb, inkline::kind_rgb(LineKind(k))) << inkline::to_string(LineKind(k));  // black, highlights white
        EXPECT_EQ(l.rgb, LineKind(k) == LineKind::ToneHighlight ? 0xffffffu : 0u) << inkline::to_string(LineKind(k));
        EXPECT_EQ(l.width, builtin.lines[std::size_t(k)].width) << inkline::to_string(LineKind(k));
        // Lines from curvature are drawn lighter than the outline (as the plain writers draw them).
        EXPECT_EQ(l.width, inkline::kind_width(LineKind(k)) == 0.7 ? 0.7 : 1.0) << inkline::to_string(LineKind(k));
    }
    // The illustration preset turns suggestive contours on.
    const std::vector<LineKind> ill = inkline::load_style("illustration").kinds;
    EXPECT_NE(std::find(ill.begin(), ill.end(), LineKind::Suggestive), ill.end());
    EXPECT_TRUE(inkline::load_style("clean").kinds.empty());
    EXPECT_FALSE(file.draw_hidden);
    // The presets that are more than lines use what they say.
    EXPECT_TRUE(inkline::load_style("technical").draw_hidden);
    EXPECT_TRUE(inkline::load_style("technical").for_qi(LineKind::Crease, 7).omit);
    EXPECT_TRUE(inkline::load_style("charcoal").lines[0].offsets.has_value());
    EXPECT_FALSE(inkline::load_style("ink-brush").lines[0].brush.empty());
    EXPECT_DOUBLE_EQ(inkline::load_style("ink-brush").lines[0].brush_aspect, 4.0);  // 128 x 32 image
    EXPECT_TRUE(inkline::load_style("hatched").hatching.enabled);
}

TEST(StyleObjects, LinesChosenByObjectNameOverTheStylesLines) {
    // The cube's visible lines red (its creases also wider), the ball's as the style's; hidden
    // lines by QI whatever their object; an object the drawing does not have changes nothing.
    const inkline::Style style = inkline::parse_style(
        R"({"lines": {"default": {"width": 2}},
            "objects": {"Cube": {"default": {"colour": "#ff0000"}, "crease": {"width": 3}}, "Lamp": {}}})",
        "/tmp/s/objects.json");
    const std::string cube = "Cube", lamp = "Lamp";
    EXPECT_EQ(style.for_line(LineKind::Silhouette, 0, &cube).rgb, 0xff0000u);
    EXPECT_EQ(style.for_line(LineKind::Silhouette, 0, &cube).width, 2.0);
    EXPECT_EQ(style.for_line(LineKind::Crease, 0, &cube).width, 3.0);
    EXPECT_EQ(style.for_line(LineKind::Crease, 0, &cube).rgb, 0xff0000u);
    EXPECT_EQ(style.for_line(LineKind::Crease, 0, &lamp).rgb, 0u);
    EXPECT_EQ(style.for_line(LineKind::Crease, 0, nullptr).width, 2.0);
    EXPECT_EQ(style.for_line(LineKind::Crease, 1, &cube).rgb, 0x7f7f7fu);

    Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 1, {{0, 0}, {50, 0}}},
        {LineKind::Silhouette, 0, 2, {{0, 20}, {50, 20}}},
    });
    d.object_names = {"Ball", "Cube"};
    d.pieces[1].object = 1;
    const auto sd = inkline::stylize(d, style, false);
    ASSERT_EQ(sd.layers.size(), 1u);
    ASSERT_EQ(sd.layers[0].marks.size(), 2u);
    EXPECT_EQ(sd.layers[0].marks[0].rgb, 0u);
    EXPECT_EQ(sd.layers[0].marks[0].paths.at(0).front().y, 0.0);
    EXPECT_EQ(sd.layers[0].marks[1].rgb, 0xff0000u);
    EXPECT_EQ(sd.layers[0].marks[1].paths.at(0).front().y, 20.0);

    EXPECT_NE(error_of(R"({"objects": {"Cube": {"silhuette": {}}}})").find("unknown key 'objects.Cube.silhuette'"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"objects": [1]})").find("objects"), std::string::npos);
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

    e = error_of(R"({"lines": {"default": {"offsets": {"table": "x", "period": 1e-9}}}})");
    EXPECT_NE(e.find("key 'lines.default.offsets"), std::string::npos) << e;

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

// A number too large for a double is nlohmann's out_of_range, not a parse_error: it was let
// through and aborted the program (found by fuzz/run.sh style; fuzz/regressions/style-*).
TEST(StyleFile, NumberTooLargeIsAOneLineError) {
    for (const char* text : {R"({"base_width": 1e999})", R"({"description": 2222e2222222222222222})"}) {
        const std::string e = error_of(text);
        EXPECT_NE(e.find("/tmp/s/mine.json: not valid JSON: number overflow"), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    }
}

// A brush or table name longer than the file system allows made std::filesystem throw its own
// exception (found by fuzz/run.sh style; fuzz/regressions/style-name-too-long).
TEST(StyleFile, NameTooLongIsNoSuchFile) {
    const std::string name(5000, 'x');
    for (const std::string key : {"brush", "offsets"}) {
        const std::string text = key == "brush" ? R"({"lines": {"default": {"brush": ")" + name + "\"}}}"
                                                : R"({"lines": {"default": {"offsets": {"table": ")" + name + "\"}}}}";
        const std::string e = error_of(text);
        EXPECT_NE(e.find("/tmp/s/mine.json: key 'lines.default." + std::string(key == "brush" ? "brush" : "offsets.table") +
                         "': no such file"), std::string::npos) << e.substr(0, 200);
    }
    EXPECT_THROW(inkline::load_style(name), inkline::Error);
}

// ---- Offset tables ---------------------------------------------------------------------------

namespace {

std::string table_error(const std::string& text) {
    try {
        inkline::parse_offset_table(text, "t.txt");
    } catch (const inkline::Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(OffsetTable, ParsesVerticesPeriodAndBreaks) {
    const auto t = inkline::parse_offset_table(
        "# a dash and a tick\nperiod 10   # px\n0 0 0\n0.5 0 0\nbreak\n0.7 0 -1  \n0.7 0 1\n\n", "dir/tick.txt");
    EXPECT_EQ(t.name, "tick");
    EXPECT_EQ(t.period, 10.0);
    ASSERT_EQ(t.vertices.size(), 4u);
    EXPECT_FALSE(t.vertices[0].break_before);
    EXPECT_FALSE(t.vertices[1].break_before);
    EXPECT_TRUE(t.vertices[2].break_before);
    EXPECT_FALSE(t.vertices[3].break_before);
    EXPECT_EQ(t.vertices[2].t, 0.7);
    EXPECT_EQ(t.vertices[2].vy, -1.0);
    // A break after the last vertex leaves the repetitions unconnected.
    const auto d = inkline::parse_offset_table("period 4\n0 0 0\n1 0 0\nbreak\n", "d.txt");
    EXPECT_TRUE(d.vertices.front().break_before);
    // Every shipped table parses.
    for (const auto& e : std::filesystem::directory_iterator(inkline::styles_dir() + "/offsets"))
        EXPECT_NO_THROW(inkline::load_offset_table(e.path().string())) << e.path();
}

// Valid-looking tables that made strokes of non-finite or millions of points (fuzz/run.sh offsets;
// fuzz/regressions/offsets-*): offsets beyond +-1000 px (1e307 px times a scale of 100 is
// infinite), more than 1000 vertices, more than 100 vertices per px of period, in the table or
// through a style's period override.
TEST(OffsetTable, BoundsKeepStrokesFiniteAndSmall) {
    EXPECT_EQ(table_error("period 1\n0 1e307 0\n1 0 0\n"), "t.txt:2: offsets must be within +-1000 px, got '0 1e307 0'");
    EXPECT_EQ(table_error("period 1\n0 0 0\n1 0 -1000.5\n"), "t.txt:3: offsets must be within +-1000 px, got '1 0 -1000.5'");
    EXPECT_EQ(table_error("period 1\n0 -1000 1000\n1 0 0\n"), "");  // the limit itself is fine
    std::string many = "period 100\n";
    for (int i = 0; i < 1001; ++i) many += "0.5 " + std::to_string(i % 7) + " 0\n";
    EXPECT_EQ(table_error(many), "t.txt:1002: more than 1000 vertices");
    std::string dense = "period 1\n";
    for (int i = 0; i < 101; ++i) dense += "0.5 " + std::to_string(i % 7) + " 0\n";
    EXPECT_EQ(table_error(dense), "t.txt: 101 vertices in a period of 1.000000 px (at most 100 per px of period)");
    // The shipped jittery table (25 vertices) with a 0.2 px override: 125 per px.
    const std::string e = error_of(R"({"lines": {"default": {"offsets": {"table": "jittery", "period": 0.2}}}})",
                                   inkline::styles_dir() + "/dense.json");
    EXPECT_NE(e.find("key 'lines.default.offsets.period': table 'jittery' has 25 vertices, more than 100 per px of a 0.2 px period"),
              std::string::npos) << e;
    EXPECT_EQ(error_of(R"({"lines": {"default": {"offsets": {"table": "jittery", "period": 0.25}}}})",
                       inkline::styles_dir() + "/dense.json"), "");
}

TEST(OffsetTable, MalformedFilesNameFileAndLine) {
    EXPECT_EQ(table_error("0 0 0\n1 0 0\n"), "t.txt: no 'period' line (expected 'period P', P >= 0.1 px)");
    EXPECT_EQ(table_error("period 5\n0 0 0\n"), "t.txt: an offset table needs at least two vertices 't vx vy'");
    EXPECT_EQ(table_error("period 5\n0 0 0\n0.5 1 1\n0.4 0 0\n"), "t.txt:4: t must not decrease (0.4 after 0.500000)");
    EXPECT_EQ(table_error("period 5\n0 0 0\n1.5 0 0\n"), "t.txt:3: t must be in [0, 1], got 1.5");
    EXPECT_EQ(table_error("period -2\n"), "t.txt:1: 'period' expects one number of px, at least 0.1");
    EXPECT_EQ(table_error("period 1e-9\n"), "t.txt:1: 'period' expects one number of px, at least 0.1");
    EXPECT_EQ(table_error("period 2\nperiod 3\n"), "t.txt:2: 'period' given twice");
    EXPECT_EQ(table_error("period 2\n0 0\n"), "t.txt:2: expected 't vx vy' (three numbers), 'period P' or 'break', got '0 0'");
    EXPECT_EQ(table_error("period 2\n0 x 0\n"), "t.txt:2: expected 't vx vy' (three numbers), 'period P' or 'break', got '0 x 0'");
    EXPECT_EQ(table_error("period 2\n0 0 0\nbreak now\n1 0 0\n"), "t.txt:3: 'break' takes no value");
    EXPECT_THROW(inkline::load_offset_table("/nonexistent/x.txt"), inkline::Error);
}

TEST(OffsetTable, OffsetsInTheTangentNormalBasisWithBreaks) {
    // Spine along +x: tangent (1, 0), normal (0, 1) (left of travel in the y-down image).
    const ArcPolyline spine({{0, 50}, {35, 50}});
    const auto dashes = inkline::parse_offset_table("period 10\n0 0 0\n0.6 0 0\nbreak\n", "d.txt");
    const auto runs = inkline::apply_offsets(spine, dashes, 1.0, 0.0, 1.0);
    ASSERT_EQ(runs.size(), 4u);  // [0, 6], [10, 16], [20, 26], [30, 35]: the last cut at the end
    for (std::size_t i = 0; i < runs.size(); ++i) {
        EXPECT_DOUBLE_EQ(runs[i].points.front().x, 10.0 * double(i));
        EXPECT_DOUBLE_EQ(runs[i].points.back().x, i < 3 ? 10.0 * double(i) + 6 : 35.0);
        for (const auto& p : runs[i].points) EXPECT_DOUBLE_EQ(p.y, 50.0);
        EXPECT_EQ(runs[i].points.size(), i < 3 ? 7u : 6u);  // extra vertices every px
    }
    // q = p + vx p' + vy n, scaled; the period can be overridden.
    const auto tick = inkline::parse_offset_table("period 10\n0 0 0\n0.5 2 3\n1 0 0\n", "t.txt");
    const auto r = inkline::apply_offsets(spine, tick, 2.0, 20.0, 100.0);
    ASSERT_EQ(r.size(), 1u);
    ASSERT_GE(r[0].points.size(), 3u);
    EXPECT_NEAR(r[0].points[1].x, 10.0 + 2 * 2.0, 1e-12);  // spine point at s = 10, 4 px along the tangent
    EXPECT_NEAR(r[0].points[1].y, 50.0 + 2 * 3.0, 1e-12);  // 6 px along the normal
    EXPECT_DOUBLE_EQ(r[0].arc[1], 10.0);
    // A circle drawn at one t (offsets loop around one spine point), apart from its dash.
    const auto circle = inkline::parse_offset_table(
        "period 20\n0 0 0\n0.25 0 0\nbreak\n0.5 0 -2\n0.5 2 0\n0.5 0 2\n0.5 -2 0\n0.5 0 -2\nbreak\n", "c.txt");
    const auto c = inkline::apply_offsets(ArcPolyline({{0, 0}, {20, 0}}), circle, 1.0, 0.0, 1.0);
    ASSERT_EQ(c.size(), 2u);
    ASSERT_EQ(c[1].points.size(), 5u);
    for (const auto& p : c[1].points) EXPECT_NEAR(glm::distance(p, glm::dvec2(10, 0)), 2.0, 1e-12);
    EXPECT_EQ(c[1].points.front(), c[1].points.back());
}

// ---- Perlin noise ------------------------------------------------------------------------------

TEST(Noise, PerlinIsZeroAtLatticePointsBoundedAndSmooth) {
    const inkline::PerlinNoise n(0);
    double lo = 1e9, hi = -1e9;
    for (int i = -20; i <= 20; ++i)
        for (int j = -20; j <= 20; ++j) {
            EXPECT_EQ(n(double(i), double(j)), 0.0);
            const double v = n(i * 0.37 + 0.11, j * 0.29 + 0.05);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
            EXPECT_LE(std::abs(v), 1.0);
            EXPECT_LT(std::abs(n(i * 0.37 + 0.11 + 1e-6, j * 0.29 + 0.05) - v), 1e-5);  // continuous
        }
    EXPECT_LT(lo, -0.2);  // not constant
    EXPECT_GT(hi, 0.2);
    EXPECT_NE(inkline::PerlinNoise(1)(0.5, 0.25), inkline::PerlinNoise(2)(0.5, 0.25));  // the seed matters
}

TEST(Noise, SameScreenPointSameOffsetInEveryStrokeAndFrame) {
    // A noise-only style: two different strokes through the same screen points, and a second
    // frame of the first stroke: where a point lands on the same pixel, it gets the same offset.
    inkline::Style style = inkline::Style::clean();
    for (auto& l : style.lines) {
        l.noise = {3.0, 2.0, 25.0};
        l.spacing = 1.0;
    }
    const Drawing a = drawing_of({{LineKind::Silhouette, 0, 1, {{10, 50}, {110, 50}}}});
    const Drawing b = drawing_of({{LineKind::Silhouette, 0, 9, {{30, 50}, {80, 50}}},
                                  {LineKind::Crease, 0, 3, {{5, 5}, {7, 190}}}});
    const auto sa = inkline::stylize(a, style, false), sa2 = inkline::stylize(a, style, false);
    const auto sb = inkline::stylize(b, style, false);
    const auto& pa = sa.layers.at(0).marks.at(0).paths.at(0);
    const auto& pb = sb.layers.at(0).marks.at(0).paths.at(0);  // silhouettes come first
    ASSERT_EQ(pa.size(), 101u);
    ASSERT_EQ(pb.size(), 51u);
    for (std::size_t i = 0; i < pb.size(); ++i) EXPECT_EQ(pb[i], pa[i + 20]) << i;  // x = 30 + i
    EXPECT_EQ(sa2.layers[0].marks[0].paths[0], pa);
    // And the noise moves points: not the straight line.
    double moved = 0;
    for (std::size_t i = 0; i < pa.size(); ++i) moved = std::max(moved, std::abs(pa[i].y - 50.0));
    EXPECT_GT(moved, 0.3);
    EXPECT_LE(moved, 3.0);
}

// ---- Width outlines ------------------------------------------------------------------------------

namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

bool segments_cross(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a), d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

// Closed (first point repeated) and no two non-adjacent edges touching or crossing.
void expect_simple_closed(const std::vector<glm::dvec2>& o) {
    ASSERT_GE(o.size(), 4u);
    EXPECT_EQ(o.front(), o.back());
    const std::size_t n = o.size() - 1;  // edges
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;  // adjacent through the closing vertex
            EXPECT_FALSE(segments_cross(o[i], o[i + 1], o[j], o[j + 1])) << "edges " << i << " and " << j;
            EXPECT_NE(o[i], o[j]) << "vertices " << i << " and " << j << " coincide";
        }
}

}  // namespace

TEST(WidthOutline, StraightTaperedStrokeIsClosedAndSimple) {
    std::vector<glm::dvec2> pts;
    std::vector<double> w;
    for (int i = 0; i <= 40; ++i) {
        pts.push_back({10.0 + 2.0 * i, 30.0});
        w.push_back(0.5 + 4.0 * std::sin(M_PI * i / 40.0));
    }
    const auto o = inkline::width_outline(pts, w);
    ASSERT_EQ(o.size(), 2 * pts.size() + 1);
    expect_simple_closed(o);
    // Area (shoelace) is the integral of the width (trapezoids).
    double area = 0, expected = 0;
    for (std::size_t i = 0; i + 1 < o.size(); ++i) area += cross2(o[i], o[i + 1]);
    for (std::size_t i = 0; i + 1 < w.size(); ++i) expected += 0.5 * (w[i] + w[i + 1]) * 2.0;
    EXPECT_NEAR(std::abs(area) / 2, expected, 1e-9);
    // Through the stylizer: a tapered straight stroke becomes one filled outline, closed and simple.
    inkline::Style style = inkline::Style::clean();
    style.lines[0].width_rule = inkline::WidthRule::Taper;
    style.lines[0].width = 4;
    style.lines[0].taper_length = 15;
    const auto sd = inkline::stylize(drawing_of({{LineKind::Silhouette, 0, 1, {{20, 20}, {60, 50}, {100, 80}}}}), style, false);
    ASSERT_EQ(sd.layers.size(), 1u);
    ASSERT_EQ(sd.layers[0].marks.size(), 1u);
    EXPECT_EQ(sd.layers[0].marks[0].type, inkline::Mark::Type::Fill);
    ASSERT_EQ(sd.layers[0].marks[0].paths.size(), 1u);
    expect_simple_closed(sd.layers[0].marks[0].paths[0]);
}

// ---- Hatching ---------------------------------------------------------------------------------

namespace {

// Does the segment from o to p pass through the ball (c, r) before p?
bool ray_hits_ball(const glm::dvec3& o, const glm::dvec3& p, const glm::dvec3& c, double r) {
    const glm::dvec3 d = p - o;
    const double a = glm::dot(d, d), b = 2 * glm::dot(d, o - c), cc = glm::dot(o - c, o - c) - r * r;
    const double disc = b * b - 4 * a * cc;
    if (disc < 0) return false;
    const double t = (-b - std::sqrt(disc)) / (2 * a);
    return t > 0 && t < 1 - 1e-9;
}

}  // namespace

TEST(Hatching, OnlyOnVisibleSurfaceCheckedAgainstRayTests) {
    // A small ball in front of a big one: the big one's surface behind the small one is hidden.
    const glm::dvec3 c0(0, 0, 0), c1(0.4, 0.1, -3.0);
    const double r0 = 0.8, r1 = 1.6;
    const inkline::TriangleMesh mesh = inkline::merge_meshes(inkline::make_sphere(c0, r0, 48, 24),
                                                             inkline::make_sphere(c1, r1, 64, 32));
    const inkline::Model model(mesh);
    const auto& topo = model.topology();
    inkline::Camera cam = inkline::Camera::perspective({0, 0, 6}, {0, 0, -1}, {0, 1, 0}, 40.0, 400, 400);
    cam.set_near(1e-3);
    inkline::HatchStyle hs;
    hs.enabled = true;
    hs.threshold = 0.9;
    hs.spacing = 0.02;
    hs.min_pixels = 0.0;
    inkline::HatchStats st;
    const auto hatches = inkline::hatch_strokes(topo, cam, model.rays(), hs, true, &st);
    const auto unchecked = inkline::hatch_strokes(topo, cam, model.rays(), hs, false);
    std::size_t on_front = 0, on_back = 0, hidden_unchecked = 0;
    for (const auto& h : hatches) {
        const bool back = glm::distance(h.centre, c1) < glm::distance(h.centre, c0);  // faces may be reordered
        (back ? on_back : on_front)++;
        // Front-facing, tone below the threshold, and no surface between it and the eye: by the
        // ray-test service and by the exact ball (the mesh is inside the ball, so a ray to a point
        // of the big ball that clears the small ball's inscribed mesh may graze the ball itself:
        // test against a ball inside the mesh: 0.98 r < r cos(pi/24) cos(pi/48)).
        EXPECT_LT(glm::dot(topo.face_normal(h.face), h.centre - cam.eye()), 0.0);
        EXPECT_LT(h.tone, hs.threshold);
        EXPECT_EQ(model.rays().count_layers(cam.eye(), h.centre, h.face, inkline::kNoFace), 0);
        if (back) {
            EXPECT_FALSE(ray_hits_ball(cam.eye(), h.centre, c0, 0.98 * r0)) << "hatch behind the small ball";
        }
        EXPECT_GE(h.points.size(), 2u);
    }
    for (const auto& h : unchecked)
        hidden_unchecked += glm::distance(h.centre, c1) < glm::distance(h.centre, c0) && ray_hits_ball(cam.eye(), h.centre, c0, 0.98 * r0);
    EXPECT_GT(on_front, 50u);
    EXPECT_GT(on_back, 50u);
    // The ray tests removed exactly the particles an exact test finds hidden (within the
    // faceting of the spheres): without them, strokes land behind the small ball.
    EXPECT_GT(hidden_unchecked, 20u);
    EXPECT_LT(hatches.size(), unchecked.size());
    EXPECT_EQ(st.ray_tests, st.lit);  // one ray test per particle that would be drawn
    EXPECT_EQ(unchecked.size(), st.lit);
    // Strokes run along normal x view ray: across the view direction, tangent to the outline.
    for (const auto& h : hatches) {
        const glm::dvec3 n = topo.face_normal(h.face), v = glm::normalize(h.centre - cam.eye());
        const glm::dvec3 dir = glm::normalize(glm::cross(n, v));
        const glm::dvec2 a = cam.project(h.centre), b = cam.project(h.centre + 1e-4 * dir);
        if (glm::distance(a, b) < 1e-6) continue;
        const glm::dvec2 want = glm::normalize(b - a);
        const glm::dvec2 got = glm::normalize(h.points.back() - h.points.front());
        EXPECT_GT(std::abs(glm::dot(want, got)), 0.8);
    }
}

// ---- Brush strokes -------------------------------------------------------------------------------

TEST(Brush, QuadsFollowTheSpineWithCrossbarsAtVerticesAndSeams) {
    inkline::Style style = inkline::load_style("ink-brush");
    inkline::LineStyle& ls = style.lines[int(LineKind::Silhouette)];
    ls.width_rule = inkline::WidthRule::Constant;
    ls.noise = {};
    ls.width = 5.0;     // 5 px at base width 1
    ls.spacing = 7.0;   // spine vertices every 7 px
    style.base_width = 1.0;
    // Straight, 100 px: the 128 x 32 brush (aspect 4) repeats every 20 px.
    const auto sd = inkline::stylize(drawing_of({{LineKind::Silhouette, 0, 1, {{50, 100}, {150, 100}}}}), style, false);
    ASSERT_EQ(sd.layers.size(), 1u);
    const inkline::Mark& m = sd.layers[0].marks.at(0);
    ASSERT_EQ(m.type, inkline::Mark::Type::Brush);
    EXPECT_NE(m.brush.find("ink.png"), std::string::npos);
    // Crossbars at x = 50 + 7k (vertices), 50 + 20k (seams) and 150: the union, sorted.
    std::vector<double> bars;
    for (int k = 0; 7 * k < 100; ++k) bars.push_back(50 + 7.0 * k);
    for (int k = 1; 20 * k < 100; ++k) bars.push_back(50 + 20.0 * k);
    bars.push_back(150);
    std::sort(bars.begin(), bars.end());
    bars.erase(std::unique(bars.begin(), bars.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }), bars.end());
    ASSERT_EQ(m.quads.size(), bars.size() - 1);
    for (std::size_t i = 0; i < m.quads.size(); ++i) {
        const inkline::BrushQuad& q = m.quads[i];
        EXPECT_NEAR(q.corner[0].x, bars[i], 1e-9);
        EXPECT_NEAR(q.corner[3].x, bars[i + 1], 1e-9);
        EXPECT_NEAR(std::abs(q.corner[0].y - q.corner[1].y), 5.0, 1e-9);  // the crossbar spans the width
        EXPECT_NEAR(q.corner[2].x, q.corner[3].x, 1e-9);
        // The image runs along: u advances by the length over 20 px, wrapping at the seams.
        EXPECT_NEAR(q.u0, std::fmod(bars[i] - 50, 20.0) / 20.0, 1e-9);
        EXPECT_NEAR(q.u1 - q.u0, (bars[i + 1] - bars[i]) / 20.0, 1e-9);
        EXPECT_LE(q.u1, 1.0 + 1e-12);
        if (i > 0) {
            EXPECT_EQ(q.corner[0], m.quads[i - 1].corner[3]);  // neighbours share a crossbar
        }
    }
}

TEST(Brush, InkOnlyInsideTheStrokeInEveryFormat) {
    inkline::Style style = inkline::load_style("ink-brush");
    for (auto& l : style.lines) l.noise = {}, l.width_rule = inkline::WidthRule::Constant, l.width = 8.0;
    style.base_width = 1.0;
    const auto sd = inkline::stylize(drawing_of({{LineKind::Silhouette, 0, 1, {{40, 100}, {160, 100}}}}), style, false);
    const std::string png = inkline::styled_to_bytes(sd, inkline::Format::Png);
    cairo_surface_t* s = [&] {
        struct Reader { const std::string* b; std::size_t at; } r{&png, 0};
        return cairo_image_surface_create_from_png_stream(
            [](void* c, unsigned char* data, unsigned int n) {
                auto* rr = static_cast<Reader*>(c);
                if (rr->at + n > rr->b->size()) return CAIRO_STATUS_READ_ERROR;
                std::memcpy(data, rr->b->data() + rr->at, n);
                rr->at += n;
                return CAIRO_STATUS_SUCCESS;
            },
            &r);
    }();
    ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* px = cairo_image_surface_get_data(s);
    std::size_t inside_dark = 0, outside_dark = 0, inside = 0;
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 200; ++x) {
            const auto* p = px + y * stride + 4 * x;
            const bool dark = p[1] < 128;
            const bool in = x >= 41 && x <= 159 && std::abs(y + 0.5 - 100) < 3.5;
            const bool near = x >= 38 && x <= 162 && std::abs(y + 0.5 - 100) < 5.5;
            inside += in;
            inside_dark += in && dark;
            outside_dark += !near && dark;
        }
    cairo_surface_destroy(s);
    EXPECT_GT(double(inside_dark), 0.7 * double(inside));
    EXPECT_EQ(outside_dark, 0u);
    // The same drawing as PDF and SVG (Cairo's surfaces; the brush is embedded as an image).
    const std::string pdf = inkline::styled_to_bytes(sd, inkline::Format::Pdf);
    const std::string svg = inkline::styled_to_bytes(sd, inkline::Format::Svg);
    EXPECT_EQ(pdf.substr(0, 4), "%PDF");
    EXPECT_NE(svg.find("<svg"), std::string::npos);
    EXPECT_NE(svg.find("image"), std::string::npos);
    EXPECT_THROW(inkline::styled_to_bytes(sd, inkline::Format::Json), inkline::Error);
}

TEST(Hatching, ChosenDirectionalLightShadesTheFarSide) {
    const inkline::Model model(inkline::make_sphere({0, 0, 0}, 1.0, 64, 32));
    inkline::Camera cam = inkline::Camera::perspective({0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 30.0, 300, 300);
    cam.set_near(1e-3);
    inkline::Style s = inkline::parse_style(R"({"hatching": {"enabled": true, "light": [1, 0, 0], "threshold": 0.3,
                                                "min_pixels": 0}})", "/tmp/l.json");
    ASSERT_FALSE(s.hatching.light_at_camera);
    const auto hatches = inkline::hatch_strokes(model.topology(), cam, model.rays(), s.hatching);
    ASSERT_GT(hatches.size(), 20u);
    for (const auto& h : hatches) EXPECT_LT(h.centre.x, 0.35);  // n.x < 0.3 up to faceting
    // With the light at the camera the same threshold shades the rim all around instead.
    s.hatching.light_at_camera = true;
    bool right = false, left = false;
    for (const auto& h : inkline::hatch_strokes(model.topology(), cam, model.rays(), s.hatching))
        right |= h.centre.x > 0.8, left |= h.centre.x < -0.8;
    EXPECT_TRUE(right && left);
    const std::string e = error_of(R"({"hatching": {"light": "sun"}})");
    EXPECT_NE(e.find("key 'hatching.light': expected \"camera\" or a direction [x, y, z]"), std::string::npos) << e;
}

TEST(StyledSvg, OneLayerPerLineClassAndBrushImageEmbeddedOnce) {
    // Visible silhouette and crease, hidden silhouette at QI 1 and crease at QI 2, technical style.
    const Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 1, {{10, 10}, {100, 10}}},
        {LineKind::Crease, 0, 2, {{10, 50}, {100, 60}}},
        {LineKind::Silhouette, 1, 3, {{10, 90}, {100, 90}}},
        {LineKind::Crease, 2, 4, {{10, 120}, {100, 120}}},
        {LineKind::Border, 5, 5, {{10, 150}, {100, 150}}},  // QI >= 3: omitted by technical
    });
    const std::string svg = inkline::styled_to_bytes(inkline::stylize(d, inkline::load_style("technical"), false),
                                                     inkline::Format::Svg);
    std::vector<std::string> ids;
    for (std::size_t at = 0; (at = svg.find("inkscape:groupmode=\"layer\"", at)) != std::string::npos; ++at) {
        const std::size_t open = svg.rfind("id=\"", at) + 4;
        ids.push_back(svg.substr(open, svg.find('"', open) - open));
    }
    // Hidden layers first (deepest first), visible last, as the default writer.
    EXPECT_EQ(ids, (std::vector<std::string>{"crease-hidden-qi2", "silhouette-hidden-qi1", "silhouette-visible", "crease-visible"}));
    EXPECT_NE(svg.find("stroke-dasharray=\"7,4\""), std::string::npos);
    EXPECT_EQ(svg.find("border"), std::string::npos);

    // A brush stroke: the image once, one clipped copy per quad.
    const inkline::StyledDrawing sd = inkline::stylize(
        drawing_of({{LineKind::Silhouette, 0, 1, {{20, 100}, {180, 100}}}, {LineKind::Crease, 0, 2, {{20, 50}, {180, 40}}}}),
        inkline::load_style("ink-brush"), false);
    std::size_t quads = 0;
    for (const auto& l : sd.layers)
        for (const auto& m : l.marks) quads += m.quads.size();
    const std::string b = inkline::styled_to_bytes(sd, inkline::Format::Svg);
    const auto count = [&](const std::string& s) {
        std::size_t n = 0;
        for (std::size_t at = 0; (at = b.find(s, at)) != std::string::npos; ++at) ++n;
        return n;
    };
    EXPECT_GT(quads, 10u);
    EXPECT_EQ(count("<image id=\"brush"), 1u);
    EXPECT_EQ(count("<svg x="), quads);
}

// ---- Width by depth and by lighting -----------------------------------------------------------

TEST(PointAttributes, ChainedWithTheirPointsAndScaleWidths) {
    // Two pieces of one curve, the second stored backwards; depth 1..2 along the stroke.
    const Drawing d = drawing_of({
        {LineKind::Silhouette, 0, 1, {{10, 50}, {60, 50}}},
        {LineKind::Silhouette, 0, 1, {{110, 50}, {85, 50}, {60, 50}}},
    });
    inkline::PointAttributes a;
    a.depth = {{1.0, 1.5}, {2.0, 1.75, 1.5}};
    a.tone = {{0.0, 0.5}, {1.0, 0.75, 0.5}};
    const auto s = inkline::chain_strokes(d, {}, &a);
    ASSERT_EQ(s.size(), 1u);
    const bool forward = s[0].path.points().front().x == 10;
    std::vector<double> depth = s[0].depth;
    if (!forward) std::reverse(depth.begin(), depth.end());
    EXPECT_EQ(depth, (std::vector<double>{1.0, 1.5, 1.75, 2.0}));
    EXPECT_EQ(s[0].tone.size(), 4u);

    // Width x2 at the nearest point, x0.5 at the farthest: the outline is 2w wide at depth 1
    // and w/2 at depth 2, linear in depth between.
    inkline::Style style = inkline::Style::clean();
    style.base_width = 1.0;
    style.lines[0].width = 4.0;
    style.lines[0].depth_near = 2.0;
    style.lines[0].depth_far = 0.5;
    style.lines[0].spacing = 5.0;
    const auto sd = inkline::stylize(d, style, false, {}, nullptr, &a);
    ASSERT_EQ(sd.layers.size(), 1u);
    const auto& o = sd.layers[0].marks.at(0).paths.at(0);
    ASSERT_EQ(sd.layers[0].marks[0].type, inkline::Mark::Type::Fill);
    expect_simple_closed(o);
    const std::size_t n = (o.size() - 1) / 2;  // points per side
    const auto width_at_x = [&](double x) {
        for (std::size_t i = 0; i < n; ++i)
            if (std::abs(o[i].x - x) < 1e-9) return std::abs(o[i].y - o[o.size() - 2 - i].y);
        return -1.0;
    };
    EXPECT_NEAR(width_at_x(10), 8.0, 1e-9);
    EXPECT_NEAR(width_at_x(110), 2.0, 1e-9);
    EXPECT_NEAR(width_at_x(60), 4.0 * (2.0 + 0.5 * (0.5 - 2.0)), 1e-9);  // depth 1.5: halfway
    // Without attributes the factors are 1: a stroke of constant width.
    const auto none = inkline::stylize(d, style, false);
    EXPECT_EQ(none.layers[0].marks.at(0).type, inkline::Mark::Type::Stroke);
    EXPECT_EQ(none.layers[0].marks[0].width, 4.0);
}

TEST(PointAttributes, FromAViewDepthAndToneAtEveryPoint) {
    const inkline::Model model(inkline::make_box({-1, -1, -1}, {1, 1, 1}));
    const auto cam = inkline::Camera::perspective({3, 2.5, 4}, {0, 0, 0}, {0, 1, 0}, 40.0, 300, 300);
    const inkline::View v = inkline::render_view(model, cam);
    const auto a = inkline::point_attributes(model.topology(), cam, v.drawing, v.spans, true, {});
    ASSERT_EQ(a.depth.size(), v.drawing.pieces.size());
    std::size_t checked = 0;
    for (std::size_t p = 0; p < v.drawing.pieces.size(); ++p) {
        ASSERT_EQ(a.depth[p].size(), v.drawing.pieces[p].points.size());
        for (std::size_t i = 0; i < a.depth[p].size(); ++i) {
            EXPECT_GT(a.depth[p][i], 0.0);
            EXPECT_GE(a.tone[p][i], 0.0);
            EXPECT_LE(a.tone[p][i], 1.0);
            ++checked;
        }
    }
    EXPECT_GT(checked, 8u);
    // A directional light straight along +y: the edges of the top face (y = 1) share the top's
    // normal with a side face, so their tone is cos 45 degrees.
    const auto up = inkline::point_attributes(model.topology(), cam, v.drawing, v.spans, false, {0, 1, 0});
    std::size_t top = 0;
    for (std::size_t p = 0; p < v.drawing.pieces.size(); ++p)
        for (std::size_t i = 0; i < up.tone[p].size(); ++i) {
            // Project back: a top edge point projects near the top face's outline; check by tone value.
            if (std::abs(up.tone[p][i] - std::sqrt(0.5)) < 1e-9) ++top;
        }
    EXPECT_GT(top, 0u);
    EXPECT_NE(inkline::parse_style(R"({"lines": {"default": {"width_by_light": [0.5, 2]}}})", "/tmp/x.json").lines[0].light_dark, 1.0);
    const std::string e = error_of(R"({"lines": {"default": {"width_by_depth": 2}}})");
    EXPECT_NE(e.find("key 'lines.default.width_by_depth': expected [near, far] width factors"), std::string::npos) << e;
}

TEST(Brush, ZeroWidthEndsDrawNothingAndTerminate) {
    inkline::Style style = inkline::load_style("ink-brush");
    for (auto& l : style.lines) l.taper_min = 0.0, l.noise = {};
    const auto sd = inkline::stylize(drawing_of({{LineKind::Silhouette, 0, 1, {{20, 100}, {180, 100}}}}), style, false);
    ASSERT_EQ(sd.layers.size(), 1u);
    for (const auto& q : sd.layers[0].marks.at(0).quads) EXPECT_GT(q.u1, q.u0);
    style.lines[0].width = 0.0;
    const auto none = inkline::stylize(drawing_of({{LineKind::Silhouette, 0, 1, {{20, 100}, {180, 100}}}}), style, false);
    std::size_t quads = 0;
    for (const auto& l : none.layers)
        for (const auto& m : l.marks) quads += m.quads.size();
    EXPECT_EQ(quads, 0u);
}
