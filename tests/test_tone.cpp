// The tone stage (src/tone/): known answers on synthetic tone images, a lit sphere, bad options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include <glm/geometric.hpp>

#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "tone/tone.hpp"

using namespace inkline;
using namespace inkline::tone;

namespace {

// An image of f(pixel centre).
template <class F>
Image image_of(int w, int h, F f) {
    Image img;
    img.resize(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.pixels[std::size_t(y) * std::size_t(w) + std::size_t(x)] = float(f(x + 0.5, y + 0.5));
    return img;
}

double total_length(const std::vector<Piece>& pieces) {
    double l = 0.0;
    for (const Piece& p : pieces)
        for (std::size_t i = 1; i < p.points.size(); ++i) l += glm::length(p.points[i] - p.points[i - 1]);
    return l;
}

// Blur, detect (dark), trace, as render_tone does for one channel.
std::vector<Piece> dark_lines(const Image& tone, const ToneOptions& o, RidgeField* field_out = nullptr) {
    Image blurred;
    gaussian_blur(tone, o.width, blurred);
    RidgeField field;
    detect_ridges(blurred, blurred, Polarity::Dark, o.dark_lower, o.dark_upper, o, field);
    if (field_out) *field_out = field;
    return trace_lines(field, LineKind::ToneDark, o);
}

}  // namespace

// H = (X^T X)^-1 X^T: the fit of samples of an exact quadratic gives back its coefficients.
TEST(ToneFit, ReproducesAnExactQuadratic) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coef(-3.0, 3.0);
    for (int trial = 0; trial < 20; ++trial) {
        std::array<double, 6> a;
        for (double& v : a) v = coef(rng);
        std::array<double, 9> t;
        for (int i = 0; i < 9; ++i) {
            const double x = i % 3 - 1, y = i / 3 - 1;
            t[std::size_t(i)] = a[0] * x * x + 2 * a[1] * x * y + a[2] * y * y + a[3] * x + a[4] * y + a[5];
        }
        const auto fit = fit_quadratic(t);
        for (std::size_t k = 0; k < 6; ++k) EXPECT_NEAR(fit[k], a[k], 1e-12) << "trial " << trial << " a" << k;
    }
    // H's known entries: a5 (the constant) is the 5/9 centre, 2/9 edge, -1/9 corner weighted mean.
    const auto& H = fit_matrix();
    EXPECT_NEAR(H[5][4], 5.0 / 9.0, 1e-15);
    EXPECT_NEAR(H[5][1], 2.0 / 9.0, 1e-15);
    EXPECT_NEAR(H[5][0], -1.0 / 9.0, 1e-15);
}

// A round bump f = -(x^2 + y^2) + 0.4 x: a spot with centre c = (0.2, 0).
TEST(ToneFit, SpotCentre) {
    const RidgeLine l = ridge_line({-1.0, 0.0, -1.0, 0.4, 0.0, 0.0});
    EXPECT_DOUBLE_EQ(l.curvature, -1.0);
    EXPECT_DOUBLE_EQ(l.other, -1.0);
    EXPECT_DOUBLE_EQ(l.centre.x, 0.2);
    EXPECT_DOUBLE_EQ(l.centre.y, 0.0);
}

// f = 2 (x - 0.3)^2 + 1: a valley along y through x = 0.3 with curvature 2; and the singular case
// (the other curvature exactly 0) gives the same line.
TEST(ToneFit, LineOfAQuadraticValley) {
    const RidgeLine l = ridge_line({2.0, 0.0, 0.0, -1.2, 0.0, 1.18});
    EXPECT_DOUBLE_EQ(l.curvature, 2.0);
    EXPECT_DOUBLE_EQ(l.other, 0.0);
    EXPECT_NEAR(std::abs(l.normal.x), 1.0, 1e-15);
    EXPECT_NEAR(l.offset * l.normal.x, 0.3, 1e-15);
    // A ridge (negative curvature) at 45 degrees: f = -(x + y - 1)^2 / 2 = -(x^2 + 2xy + y^2)/2 + x + y - 1/2.
    const RidgeLine r = ridge_line({-0.5, -0.5, -0.5, 1.0, 1.0, -0.5});
    EXPECT_NEAR(r.curvature, -1.0, 1e-15);
    EXPECT_NEAR(std::abs(r.normal.x), std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(r.normal.x * r.normal.y, 0.5, 1e-15);
    EXPECT_NEAR(r.offset, std::sqrt(0.5) * (r.normal.x > 0 ? 1 : -1), 1e-12);  // (0.5, 0.5) lies on the line
}

// A Gaussian valley of known width and direction: one line, at its centre within 0.25 px, at its angle.
TEST(ToneLines, GaussianValleyAtItsCentreAndAngle) {
    for (double degrees : {0.0, 17.0, 45.0, 100.0}) {
        const double a = degrees * M_PI / 180.0;
        const glm::dvec2 dir(std::cos(a), std::sin(a)), normal(-dir.y, dir.x), centre(60.3, 50.7);
        const Image tone = image_of(120, 100, [&](double x, double y) {
            const double d = glm::dot(glm::dvec2(x, y) - centre, normal);
            return 1.0 - 0.6 * std::exp(-d * d / (2 * 1.5 * 1.5));
        });
        ToneOptions o;  // w = 6, beta = 0.2
        const std::vector<Piece> lines = dark_lines(tone, o);
        ASSERT_EQ(lines.size(), 1u) << degrees;
        const Piece& p = lines[0];
        EXPECT_GT(total_length(lines), 80.0) << degrees;  // crosses most of the image
        double worst = 0.0, worst_angle = 0.0;
        for (std::size_t i = 0; i < p.points.size(); ++i) {
            const glm::dvec2 q = p.points[i];
            if (q.x < 10 || q.y < 10 || q.x > 110 || q.y > 90) continue;  // the border's clamp bends it
            worst = std::max(worst, std::abs(glm::dot(q - centre, normal)));
            if (i > 3) {
                const glm::dvec2 chord = glm::normalize(q - p.points[i - 4]);
                worst_angle = std::max(worst_angle, std::acos(std::min(1.0, std::abs(glm::dot(chord, dir)))));
            }
        }
        EXPECT_LT(worst, 0.25) << degrees;
        EXPECT_LT(worst_angle * 180.0 / M_PI, 3.0) << degrees;
        EXPECT_EQ(p.opacity.size(), p.points.size());
    }
}

// The seed's Figure 4: a step edge is drawn with beta = 0 (the fit sees a valley at the foot of
// the step and never moves) and not with beta = 1 (the search walks away from it).
TEST(ToneLines, StepEdgeWithBetaZeroNotOne) {
    const Image tone = image_of(64, 48, [](double x, double) { return x < 32.0 ? 0.2 : 1.0; });
    ToneOptions o;
    o.beta = 0.0;
    RidgeField f0, f1;
    const auto at0 = dark_lines(tone, o, &f0);
    o.beta = 1.0;
    const auto at1 = dark_lines(tone, o, &f1);
    EXPECT_GT(*std::max_element(f0.opacity.begin(), f0.opacity.end()), 0.3f);
    EXPECT_EQ(at0.size(), 1u);
    EXPECT_GT(total_length(at0), 40.0);
    EXPECT_EQ(*std::max_element(f1.opacity.begin(), f1.opacity.end()), 0.0f);
    EXPECT_TRUE(at1.empty());
}

TEST(ToneLines, FlatAndLinearImagesGiveNothing) {
    ToneOptions o;
    RidgeField f;
    EXPECT_TRUE(dark_lines(image_of(40, 30, [](double, double) { return 0.5; }), o, &f).empty());
    EXPECT_EQ(*std::max_element(f.opacity.begin(), f.opacity.end()), 0.0f);
    // A ramp has no curvature anywhere (the border clamps it flat, which is an edge: kept out).
    const Image ramp = image_of(40, 30, [](double x, double y) { return 0.2 + 0.01 * x + 0.005 * y; });
    Image blurred;
    gaussian_blur(ramp, o.width, blurred);
    detect_ridges(blurred, blurred, Polarity::Dark, o.dark_lower, o.dark_upper, o, f);
    for (int y = 8; y < 22; ++y)
        for (int x = 8; x < 32; ++x) EXPECT_EQ(f.opacity[std::size_t(y * 40 + x)], 0.0f) << x << "," << y;
}

TEST(ToneBlur, PreservesConstantsAndMass) {
    const Image flat = image_of(31, 17, [](double, double) { return 0.25; });
    Image out;
    gaussian_blur(flat, 6.0, out, 2);
    for (float v : out.pixels) EXPECT_NEAR(v, 0.25f, 1e-6f);
    Image dot = image_of(41, 41, [](double x, double y) { return x == 20.5 && y == 20.5 ? 1.0 : 0.0; });
    gaussian_blur(dot, 8.0, out, 1);  // sigma 2: the kernel fits inside, mass kept
    double sum = 0.0;
    for (float v : out.pixels) sum += v;
    EXPECT_NEAR(sum, 1.0, 1e-5);
    EXPECT_GT(out.at(20, 20), out.at(21, 20));
    EXPECT_FLOAT_EQ(out.at(21, 20), out.at(20, 21));  // separable and symmetric
}

// A sphere lit from the eye: no dark line inside its disc (only at the silhouette, where the tone
// meets the white background), one highlight line at the specular spot (the image centre).
TEST(ToneSphere, OneHighlightAtTheSpotNoDarkLinesInside) {
    const MeshTopology mesh = build_topology(make_sphere({0, 0, 0}, 1.0, 128, 64));
    const Camera cam = Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 256, 256);
    ToneOptions o;
    o.lights = {{0, 0, 1}};
    o.threads = 2;
    // A shiny sphere: the spot (where n.h^e > 1/2) about w across, sqrt(2 ln 2 / e) * 97 px.
    o.specular_exponent = 1000.0;
    const ToneMesh normals = prepare_tone_mesh(mesh);
    ToneResult r;
    render_tone(mesh, normals, cam, o, true, true, r);
    // The disc's radius in px: F tan(asin(1/5)).
    const double radius = cam.focal() * std::tan(std::asin(0.2));
    const glm::dvec2 c(128, 128);
    std::size_t highlights = 0;
    for (const Piece& p : r.pieces) {
        for (const glm::dvec2& q : p.points) {
            if (p.kind == LineKind::ToneDark) EXPECT_GT(glm::length(q - c), radius - o.width) << "dark line inside";
            else EXPECT_LT(glm::length(q - c), 0.25 * radius) << "highlight away from the spot";
        }
        if (p.kind == LineKind::ToneHighlight) ++highlights;
    }
    EXPECT_EQ(highlights, 1u);

    // The tone at the centre is lit straight on, the background white, the specular peak at the centre.
    EXPECT_NEAR(r.shaded.tone.at(128, 128), 1.0f, 1e-3f);
    EXPECT_EQ(r.shaded.tone.at(2, 2), 1.0f);
    EXPECT_EQ(r.shaded.covered[0], 0);
    EXPECT_GT(r.shaded.specular.at(128, 128), 0.95f);  // (its centre is 0.7 px from the spot's)
    EXPECT_FLOAT_EQ(r.shaded.specular.at(128, 128), r.shaded.specular.at(127, 127));
    // Toon base: background white, the lit centre in the top band, the rim darker.
    const RasterLayer base = toon_base(r.shaded.tone, r.shaded.covered, 3);
    EXPECT_EQ(base.rgb[0], 0xffffffu);
    EXPECT_EQ(base.rgb[128 * 256 + 128], 0xebebebu);
    EXPECT_LT(base.rgb[128 * 256 + 128 + int(radius) - 2] & 0xff, 0xebu);
}

// Two threads give the same images and lines as one.
TEST(ToneSphere, ThreadsGiveTheSameResult) {
    const MeshTopology mesh = build_topology(make_sphere({0, 0, 0}, 1.0, 64, 32));
    const Camera cam = Camera::perspective({1, 2, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 200, 150);
    const ToneMesh normals = prepare_tone_mesh(mesh);
    ToneOptions o;
    ToneResult one, two;
    render_tone(mesh, normals, cam, o, true, true, one);
    o.threads = 2;
    render_tone(mesh, normals, cam, o, true, true, two);
    EXPECT_EQ(one.shaded.tone.pixels, two.shaded.tone.pixels);
    EXPECT_EQ(one.dark.opacity, two.dark.opacity);
    ASSERT_EQ(one.pieces.size(), two.pieces.size());
    for (std::size_t i = 0; i < one.pieces.size(); ++i) EXPECT_EQ(one.pieces[i].points, two.pieces[i].points);
}

// Tiny and degenerate images work.
TEST(ToneSphere, OnePixelImage) {
    const MeshTopology mesh = build_topology(make_sphere({0, 0, 0}, 1.0, 16, 8));
    const Camera cam = Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 1, 1);
    ToneResult r;
    render_tone(mesh, prepare_tone_mesh(mesh), cam, ToneOptions{}, true, true, r);
    EXPECT_TRUE(r.pieces.empty());
    EXPECT_EQ(r.shaded.covered[0], 1);
}

// Section 3.4, the arithmetic: a width scale s at w is the fit, search and fall-off at spacing
// s w / 2 with the thresholds kept per (w/2)^2; so scale 0.5 everywhere at w = 8 is w = 4 with the
// thresholds a quarter, opacity for opacity, and the field carries the scale.
TEST(ToneWidth, AScaleIsASmallerWidthWithTheThresholdsKept) {
    const glm::dvec2 normal(std::cos(0.3), std::sin(0.3)), centre(40.2, 30.6);
    Image tone = image_of(80, 60, [&](double x, double y) {
        const double d = glm::dot(glm::dvec2(x, y) - centre, normal);
        return 1.0 - 0.6 * std::exp(-d * d / (2 * 1.2 * 1.2));
    });
    Image half_scale;
    half_scale.resize(80, 60, 0.5f);
    ToneOptions wide;
    wide.width = 8.0;
    ToneOptions narrow = wide;
    narrow.width = 4.0;
    RidgeField scaled, plain;
    detect_ridges(tone, tone, Polarity::Dark, 0.02, 0.06, wide, scaled, &half_scale);
    detect_ridges(tone, tone, Polarity::Dark, 0.02 / 4, 0.06 / 4, narrow, plain);
    EXPECT_EQ(scaled.opacity, plain.opacity);
    EXPECT_EQ(scaled.point, plain.point);
    std::size_t drawn = 0;
    for (std::size_t i = 0; i < scaled.opacity.size(); ++i)
        if (scaled.opacity[i] > 0) {
            ++drawn;
            EXPECT_EQ(scaled.width_scale[i], 0.5f);
        }
    EXPECT_GT(drawn, 100u);
    EXPECT_TRUE(plain.width_scale.empty());
    // Traced: the width per point; without a scale, none.
    for (const Piece& p : trace_lines(scaled, LineKind::ToneDark, wide)) EXPECT_EQ(p.width, std::vector<float>(p.points.size(), 0.5f));
    for (const Piece& p : trace_lines(plain, LineKind::ToneDark, narrow)) EXPECT_TRUE(p.width.empty());
}

// Section 3.4 by depth: a square facing the camera at distance 5 (its bounding sphere's radius
// sqrt(2)) has the scale (5 - sqrt(2)) / 5 everywhere. By edge length: a UV sphere's short edges
// at its poles get the thinner lines.
TEST(ToneWidth, ByDepthAndByEdgeLength) {
    const MeshTopology mesh = build_topology(make_sheet(1.0, 0.0, 1));
    const Camera cam = Camera::perspective({0, 5, 0}, {0, 0, 0}, {0, 0, -1}, 40.0, 64, 48);
    EXPECT_NEAR(nearest_model_depth(mesh, cam), 5.0 - std::sqrt(2.0), 1e-12);
    ToneOptions o;
    o.width_by = ToneWidthBy::Depth;
    ShadedImages shaded;
    shade(mesh, prepare_tone_mesh(mesh), cam, o, shaded);
    ASSERT_EQ(shaded.width_scale.width, 64);
    EXPECT_NEAR(shaded.width_scale.at(32, 24), (5.0 - std::sqrt(2.0)) / 5.0, 1e-6);
    EXPECT_EQ(shaded.width_scale.at(0, 0), 1.0f);  // background
    o.width_by = ToneWidthBy::Constant;
    shade(mesh, prepare_tone_mesh(mesh), cam, o, shaded);
    EXPECT_TRUE(shaded.width_scale.pixels.empty());
    // A small sphere (left) and one three times its size (right), as many edges each: the small
    // one's edges are about half the mean, its lines thinner; the big one's at w.
    const TriangleMesh fine = make_sphere({-2, 0, 0}, 1.0, 32, 16);
    const MeshTopology pair = build_topology(merge_meshes(fine, make_sphere({4, 0, 0}, 3.0, 32, 16)));
    const std::size_t fine_vertices = build_topology(fine).vertex_count();
    const ToneMesh normals = prepare_tone_mesh(pair);
    double fine_sum = 0.0, coarse_least = 1.0;
    for (std::size_t v = 0; v < pair.vertex_count(); ++v) {
        const double s = normals.vertex_width_scale[v];
        EXPECT_GE(s, kMinWidthScale);
        EXPECT_LE(s, 1.0);
        if (v < fine_vertices) fine_sum += s;
        else coarse_least = std::min(coarse_least, s);
    }
    EXPECT_EQ(coarse_least, 1.0);  // edges longer than the mean: clamped to w
    EXPECT_LT(fine_sum / double(fine_vertices), 0.7);
    o.width_by = ToneWidthBy::EdgeLength;
    const Camera front = Camera::perspective({1, 0, 20}, {1, 0, 0}, {0, 1, 0}, 40.0, 160, 80);
    shade(pair, normals, front, o, shaded);
    EXPECT_LT(shaded.width_scale.at(63, 40), 0.7f);  // the small sphere's middle (x = 80 - 110 * 3 / 20)
    EXPECT_EQ(shaded.width_scale.at(97, 40), 1.0f);  // the big one's
}

// Each bad option names its flag.
TEST(ToneOptionsCheck, BadValuesNameTheFlag) {
    struct Case {
        void (*change)(ToneOptions&);
        const char* words;
    };
    const Case cases[] = {
        {[](ToneOptions& o) { o.width = 0.0; }, "--tone-width"},
        {[](ToneOptions& o) { o.width = -2.0; }, "--tone-width"},
        {[](ToneOptions& o) { o.width = NAN; }, "--tone-width"},
        {[](ToneOptions& o) { o.beta = -0.1; }, "--tone-beta"},
        {[](ToneOptions& o) { o.beta = 1.5; }, "--tone-beta"},
        {[](ToneOptions& o) { o.dark_lower = 0.5, o.dark_upper = 0.1; }, "--tone-dark: the lower threshold"},
        {[](ToneOptions& o) { o.highlight_lower = 0.5, o.highlight_upper = 0.1; }, "--tone-highlight: the lower"},
        {[](ToneOptions& o) { o.lights = {{0, 0, 0}}; }, "--light: expected a non-zero direction"},
        {[](ToneOptions& o) { o.specular_exponent = 0.5; }, "--specular"},
        {[](ToneOptions& o) { o.toon_bands = 5; }, "--toon-bands"},
    };
    EXPECT_EQ(tone_options_error(ToneOptions{}), "");
    for (const Case& c : cases) {
        ToneOptions o;
        c.change(o);
        const std::string e = tone_options_error(o);
        EXPECT_NE(e.find(c.words), std::string::npos) << e;
        EXPECT_EQ(e.find('\n'), std::string::npos);
    }
}

// ---- The command line ------------------------------------------------------------------

#include <nlohmann/json.hpp>

#include "cli_util.hpp"

namespace {
std::string mesh(const std::string& name) { return std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off"; }
}  // namespace

// Bad tone input: one line naming the flag, exit 2, no output file.
TEST(ToneCli, BadValuesAreOneLineUsageErrors) {
    const auto dir = inkline_test::scratch("tone_");
    const std::string out = (dir / "x.png").string();
    const struct {
        const char* flags;
        const char* words;
    } cases[] = {
        {"--lines=tone-dark --tone-width=0", "--tone-width: expected a width in (0, 256] px"},
        {"--lines=tone-dark --tone-width=-3", "--tone-width"},
        {"--lines=tone-dark --tone-beta=1.5", "--tone-beta: expected a share in [0, 1]"},
        {"--lines=tone-dark --tone-beta=-0.1", "--tone-beta"},
        {"--lines=tone-dark --tone-dark=0.5,0.1", "--tone-dark: the lower threshold is above the upper one"},
        {"--lines=tone-highlight --tone-highlight=0.3", "--tone-highlight: expected CL,CU"},
        {"--lines=tone-dark --light=0,0,0", "--light: expected a non-zero direction"},
        {"--lines=tone-dark --specular=0", "--specular"},
        {"--base=flat", "--base: unknown base 'flat'"},
        {"--base=toon --toon-bands=5", "--toon-bands"},
        {"--lines=tone-dark --tone-line-width=far", "--tone-line-width: unknown mode 'far'"},
        {"--lines=tone-dark --size=16384x16384", "--size: tone lines and the base coat need at most 8192 x 8192"},
    };
    for (const auto& c : cases) {
        const auto r = inkline_test::run_inkline("", "render " + mesh("bunny00") + " -o " + out + " " + c.flags, dir);
        EXPECT_EQ(r.code, 2) << c.flags << ": " << r.err;
        EXPECT_NE(r.err.find(c.words), std::string::npos) << c.flags << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.flags << ": " << r.err;
        EXPECT_FALSE(std::filesystem::exists(out)) << c.flags;
    }
    // The window takes the same flags (its GLSL pass, tests/test_view.cpp) and refuses the same values.
    const auto v = inkline_test::run_inkline("", "view " + mesh("bunny00") + " --lines=tone-dark --tone-beta=2", dir);
    EXPECT_EQ(v.code, 2);
    EXPECT_NE(v.err.find("--tone-beta: expected a share in [0, 1]"), std::string::npos) << v.err;
}

// A 1 x 1 image works (nothing traced); JSON holds tone lines with an opacity per point, mixed
// with silhouettes; SVG has the base coat as an image layer under the line layers.
TEST(ToneCli, OutputsMixTheKinds) {
    const auto dir = inkline_test::scratch("tone_");
    const std::string flags = " --lines=silhouette,tone-dark,tone-highlight --base=toon --quiet";
    auto r = inkline_test::run_inkline("", "render " + mesh("armadillo") + " -o " + (dir / "one.png").string() +
                                               " --size=1x1" + flags, dir);
    EXPECT_EQ(r.code, 0) << r.err;
    r = inkline_test::run_inkline("", "render " + mesh("armadillo") + " -o " + (dir / "a.json").string() +
                                          " --size=400x300" + flags, dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(inkline_test::slurp(dir / "a.json"));
    std::map<std::string, int> kinds;
    for (const auto& p : j["polylines"]) {
        ++kinds[p["kind"].get<std::string>()];
        if (p["kind"] == "tone-dark" || p["kind"] == "tone-highlight") {
            ASSERT_EQ(p["opacity"].size(), p["points"].size());
            for (const auto& o : p["opacity"]) EXPECT_TRUE(o.get<double>() > 0.0 && o.get<double>() <= 1.0);
        } else {
            EXPECT_FALSE(p.contains("opacity"));
        }
    }
    EXPECT_GT(kinds["silhouette"], 0);
    EXPECT_GT(kinds["tone-dark"], 0);
    EXPECT_GT(kinds["tone-highlight"], 0);
    EXPECT_TRUE(j["stats"]["seconds"].contains("tone"));
    r = inkline_test::run_inkline("", "render " + mesh("armadillo") + " -o " + (dir / "a.svg").string() +
                                          " --size=400x300" + flags, dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string svg = inkline_test::slurp(dir / "a.svg");
    const auto base = svg.find("<g id=\"base\""), dark = svg.find("<g id=\"tone-dark-visible\"");
    const auto light = svg.find("<g id=\"tone-highlight-visible\" ");
    ASSERT_NE(base, std::string::npos);
    ASSERT_NE(dark, std::string::npos);
    ASSERT_NE(light, std::string::npos);
    EXPECT_LT(base, dark);
    EXPECT_NE(svg.find("data:image/png;base64,"), std::string::npos);
    EXPECT_NE(svg.find("stroke=\"#ffffff\"", light), std::string::npos);  // highlights drawn light
}
