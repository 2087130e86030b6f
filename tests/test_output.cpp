// Output stage: JSON schema and values, SVG layers, PDF/PNG through Cairo, atomic writes.
#include <gtest/gtest.h>

#include <cairo.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "output/writers.hpp"

namespace fs = std::filesystem;
using inkline::Format;
using inkline::LineKind;
using nlohmann::json;

namespace {

constexpr int kW = 200, kH = 100;

// A visible silhouette along y = 50.5 (through the centres of pixel row 50), visible crease and
// border pieces, a visible piece running from (100, 20.5) far off to the right, hidden pieces at
// QI 1, 2 and 5, and pieces that must never be written (one point, a NaN).
inkline::Drawing sample_drawing() {
    inkline::Drawing d;
    d.camera = inkline::Camera::perspective({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 30.0, kW, kH);
    d.stats.triangles = 1234;
    d.stats.silhouette_edges = 56;
    d.stats.border_edges = 7;
    d.stats.crease_edges = 8;
    d.stats.curves = 9;
    d.stats.cusps = 2;
    d.stats.crossings = 3;
    d.stats.pieces = 8;
    d.stats.ray_tests = 4;
    d.stats.clusters_bbox = 5, d.stats.clusters_bounded = 6, d.stats.clusters_occluded = 7, d.stats.clusters_inconsistent = 1;
    d.stats.seconds_load = 0.5;
    d.stats.seconds_features = 0.25;
    d.stats.seconds_visibility = 0.125;
    d.stats.seconds_pieces = 0.03125;
    d.stats.seconds_propagation = 0.015625;
    d.stats.seconds_walks = 0.0078125;
    d.stats.seconds_ray_tests = 0.00390625;
    d.stats.seconds_output = 0.0625;
    d.stats.seconds_total = 0.9375;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    d.pieces = {
        {LineKind::Silhouette, 0, 0, {{20, 50.5}, {100.1, 50.5}, {180, 50.5}}, {}},
        {LineKind::Crease, 0, 1, {{1.0 / 3.0, 0.1}, {-40, 250}}, {}},  // leaves the image
        {LineKind::Border, 0, 2, {{150, 10}, {190, 20}}, {}},
        {LineKind::Silhouette, 0, 5, {{100, 20.5}, {1e12, 20.5}}, {}},  // as from near the eye plane
        {LineKind::Silhouette, 1, 0, {{20, 80}, {180, 80}}, {}},
        {LineKind::Crease, 2, 1, {{20, 90}, {180, 90}}, {}},
        {LineKind::Border, 5, 2, {{10, 10}, {10, 90}}, {}},
        {LineKind::Silhouette, 0, 3, {{60, 60}}, {}},                      // too short
        {LineKind::Crease, 0, 4, {{70, 70}, {nan, 70}, {80, 80}}, {}},     // NaN
    };
    return d;
}

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

std::set<std::string> keys(const json& j) {
    std::set<std::string> out;
    for (const auto& [k, v] : j.items()) out.insert(k);
    return out;
}

class OutputFiles : public ::testing::Test {
protected:
    void SetUp() override {
        std::string tmpl = (fs::temp_directory_path() / "inkline-output-XXXXXX").string();
        ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
        dir = tmpl;
    }
    void TearDown() override { fs::remove_all(dir); }
    std::set<std::string> entries() const {
        std::set<std::string> out;
        for (const auto& e : fs::directory_iterator(dir)) out.insert(e.path().filename().string());
        return out;
    }
    fs::path dir;
};

}  // namespace

TEST(OutputFormat, FromExtensionOrFlag) {
    EXPECT_EQ(inkline::output_format("a/b.svg", ""), Format::Svg);
    EXPECT_EQ(inkline::output_format("x.PDF", ""), Format::Pdf);
    EXPECT_EQ(inkline::output_format("x.Png", ""), Format::Png);
    EXPECT_EQ(inkline::output_format("dir.v2/x.json", ""), Format::Json);
    EXPECT_EQ(inkline::output_format("x.txt", "png"), Format::Png);
    EXPECT_EQ(inkline::output_format("-", "JSON"), Format::Json);
    EXPECT_THROW(inkline::output_format("x.txt", ""), inkline::Error);
    EXPECT_THROW(inkline::output_format("noext", ""), inkline::Error);
    try {
        inkline::output_format("x.svg", "eps");
        FAIL() << "no exception";
    } catch (const inkline::Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "--format: unknown output format 'eps' (expected svg, pdf, png or json)");
    }
    try {
        inkline::output_format("out.gif", "");
        FAIL() << "no exception";
    } catch (const inkline::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("out.gif: unknown output format 'gif'", 0), 0u)
            << e.what();
    }
}

TEST(OutputJson, SchemaAndValues) {
    const inkline::Drawing d = sample_drawing();
    const json j = json::parse(inkline::drawing_to_json(d, {}));
    EXPECT_EQ(keys(j), (std::set<std::string>{"width", "height", "camera", "stats", "polylines"}));
    EXPECT_EQ(j["width"], kW);
    EXPECT_EQ(j["height"], kH);
    EXPECT_EQ(keys(j["camera"]), (std::set<std::string>{"eye", "target", "up", "fov"}));
    EXPECT_EQ(j["camera"]["eye"], json::array({1.0, 2.0, 3.0}));
    EXPECT_EQ(j["camera"]["target"], json::array({0.0, 0.0, 0.0}));
    EXPECT_EQ(j["camera"]["up"], json::array({0.0, 1.0, 0.0}));
    EXPECT_EQ(j["camera"]["fov"], 30.0);
    const json& s = j["stats"];
    EXPECT_EQ(keys(s), (std::set<std::string>{"triangles", "silhouette_edges", "border_edges",
                                              "crease_edges", "curves", "cusps", "crossings",
                                              "pieces", "ray_tests", "visibility", "clusters", "walks",
                                              "cluster_decisions", "finder", "fraction", "seconds"}));
    EXPECT_EQ(s["finder"], "exhaustive");
    EXPECT_EQ(s["fraction"], 1.0);
    EXPECT_EQ(s["triangles"], 1234);
    EXPECT_EQ(s["silhouette_edges"], 56);
    EXPECT_EQ(s["border_edges"], 7);
    EXPECT_EQ(s["crease_edges"], 8);
    EXPECT_EQ(s["curves"], 9);
    EXPECT_EQ(s["cusps"], 2);
    EXPECT_EQ(s["crossings"], 3);
    EXPECT_EQ(s["pieces"], 8);
    EXPECT_EQ(s["ray_tests"], 4);
    EXPECT_EQ(s["cluster_decisions"],
              (json{{"bounding_box", 5}, {"upper_bound", 6}, {"occluded", 7}, {"inconsistent", 1}}));
    EXPECT_EQ(s["seconds"], (json{{"load", 0.5}, {"features", 0.25}, {"visibility", 0.125},
                                  {"visibility_stages", {{"pieces", 0.03125}, {"propagation", 0.015625},
                                                         {"walks", 0.0078125}, {"ray_tests", 0.00390625}}},
                                  {"output", 0.0625}, {"total", 0.9375}}));

    // Visible, well-formed pieces only, in drawing order, points exact.
    const json& pl = j["polylines"];
    ASSERT_EQ(pl.size(), 4u);
    for (const json& p : pl) {
        EXPECT_EQ(keys(p), (std::set<std::string>{"kind", "qi", "points"}));
        EXPECT_EQ(p["qi"], 0);
    }
    EXPECT_EQ(pl[0]["kind"], "silhouette");
    EXPECT_EQ(pl[1]["kind"], "crease");
    EXPECT_EQ(pl[2]["kind"], "border");
    EXPECT_EQ(pl[3]["kind"], "silhouette");
    for (std::size_t i = 0; i < pl.size(); ++i) {
        const auto& pts = d.pieces[i].points;
        ASSERT_EQ(pl[i]["points"].size(), pts.size());
        for (std::size_t k = 0; k < pts.size(); ++k) {
            EXPECT_EQ(pl[i]["points"][k].get<std::vector<double>>(),
                      (std::vector<double>{pts[k].x, pts[k].y}));  // bit-exact round trip
        }
    }
}

TEST(OutputJson, HiddenOnlyWhenAskedAndOrthoCamera) {
    inkline::Drawing d = sample_drawing();
    inkline::OutputOptions o;
    o.hidden = true;
    const json j = json::parse(inkline::drawing_to_json(d, o));
    std::vector<int> qis;
    for (const json& p : j["polylines"]) qis.push_back(p["qi"]);
    EXPECT_EQ(qis, (std::vector<int>{0, 0, 0, 0, 1, 2, 5}));
    EXPECT_FALSE(j["camera"].contains("ortho"));

    d.camera = inkline::Camera::orthographic({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 2.5, kW, kH);
    const json jo = json::parse(inkline::drawing_to_json(d, {}));
    EXPECT_EQ(keys(jo["camera"]), (std::set<std::string>{"eye", "target", "up", "fov", "ortho"}));
    EXPECT_EQ(jo["camera"]["ortho"], 2.5);
}

TEST(OutputSvg, LayersInOrder) {
    const inkline::Drawing d = sample_drawing();
    const std::string visible = inkline::drawing_to_svg(d, {});
    EXPECT_NE(visible.find("id=\"silhouette-visible\""), std::string::npos);
    EXPECT_NE(visible.find("id=\"crease-visible\""), std::string::npos);
    EXPECT_NE(visible.find("id=\"border-visible\""), std::string::npos);
    EXPECT_EQ(visible.find("hidden"), std::string::npos);
    EXPECT_NE(visible.find("xmlns:inkscape="), std::string::npos);
    EXPECT_NE(visible.find("inkscape:groupmode=\"layer\" inkscape:label=\"silhouette-visible\""),
              std::string::npos);
    EXPECT_NE(visible.find("viewBox=\"0 0 200 100\""), std::string::npos);
    EXPECT_NE(visible.find("points=\"20.000,50.500 100.100,50.500 180.000,50.500\""),
              std::string::npos);
    EXPECT_EQ(visible.find("nan"), std::string::npos);
    // Clipped to the image plus a 200 px margin.
    EXPECT_NE(visible.find("points=\"100.000,20.500 400.000,20.500\""), std::string::npos);

    inkline::OutputOptions o;
    o.hidden = true;
    const std::string all = inkline::drawing_to_svg(d, o);
    const std::size_t qi3 = all.find("id=\"border-hidden-qi3plus\""),
                      qi2 = all.find("id=\"crease-hidden-qi2\""),
                      qi1 = all.find("id=\"silhouette-hidden-qi1\""),
                      vis = all.find("id=\"silhouette-visible\"");
    ASSERT_NE(qi3, std::string::npos);
    ASSERT_NE(qi2, std::string::npos);
    ASSERT_NE(qi1, std::string::npos);
    ASSERT_NE(vis, std::string::npos);
    EXPECT_LT(qi3, qi2);  // deepest underneath, visible on top
    EXPECT_LT(qi2, qi1);
    EXPECT_LT(qi1, vis);
    // Height 100: automatic width is 1 px, QI 1 lines are 0.6 of that.
    EXPECT_NE(all.find("stroke=\"#7f7f7f\" stroke-width=\"0.6\" stroke-dasharray=\"6,4\""),
              std::string::npos);
    EXPECT_EQ(all.find("nan"), std::string::npos);
}

TEST_F(OutputFiles, SvgConvertsWithRsvg) {
    inkline::OutputOptions o;
    o.hidden = true;
    const fs::path svg = dir / "d.svg", png = dir / "d.png";
    inkline::write_drawing(sample_drawing(), svg.string(), Format::Svg, o);
    const std::string cmd = "rsvg-convert -o '" + png.string() + "' '" + svg.string() + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    EXPECT_TRUE(fs::exists(png));
    EXPECT_EQ(entries(), (std::set<std::string>{"d.svg", "d.png"}));
}

TEST_F(OutputFiles, JsonFileMatchesStringAndIsReadable) {
    const fs::path p = dir / "d.json";
    const mode_t old = umask(022);
    inkline::write_drawing(sample_drawing(), p.string(), Format::Json, {});
    umask(old);
    EXPECT_EQ(read_file(p), inkline::drawing_to_json(sample_drawing(), {}));
    struct stat st {};
    ASSERT_EQ(stat(p.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0644u);  // not mkstemp's 0600
}

TEST_F(OutputFiles, PdfPassesPdfinfo) {
    inkline::OutputOptions o;
    o.hidden = true;
    const fs::path pdf = dir / "d.pdf";
    inkline::write_drawing(sample_drawing(), pdf.string(), Format::Pdf, o);
    EXPECT_EQ(read_file(pdf).rfind("%PDF-", 0), 0u);
    const std::string cmd = "pdfinfo '" + pdf.string() + "' > /dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    EXPECT_EQ(entries(), std::set<std::string>{"d.pdf"});
}

TEST_F(OutputFiles, PngPixels) {
    const fs::path png = dir / "d.png";
    inkline::write_drawing(sample_drawing(), png.string(), Format::Png, {});
    EXPECT_EQ(read_file(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

    cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
    ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
    ASSERT_EQ(cairo_image_surface_get_width(s), kW);
    ASSERT_EQ(cairo_image_surface_get_height(s), kH);
    cairo_surface_flush(s);
    const auto green = [&](int x, int y) {  // ARGB32 / RGB24 in native-endian uint32
        const unsigned char* row =
            cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s);
        return (reinterpret_cast<const std::uint32_t*>(row)[x] >> 8) & 0xff;
    };
    EXPECT_LT(green(100, 50), 64u);   // on the visible silhouette
    EXPECT_EQ(green(50, 35), 255u);   // far from every line
    EXPECT_EQ(green(100, 80), 255u);  // hidden silhouette not drawn without options.hidden
    EXPECT_LT(green(150, 20), 64u);   // the far-reaching piece, drawn rightwards ...
    EXPECT_EQ(green(50, 20), 255u);   // ... not wrapped around by Cairo's fixed point
    cairo_surface_destroy(s);
}

TEST_F(OutputFiles, UnwritablePathThrowsAndLeavesNothing) {
    const std::string path = "/nonexistent-dir/x.svg";
    try {
        inkline::write_drawing(sample_drawing(), path, Format::Svg, {});
        FAIL() << "no exception";
    } catch (const inkline::Error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos);
    }
    EXPECT_FALSE(fs::exists("/nonexistent-dir"));
}

// The temporary is created, then the rename onto an existing directory fails: for every format
// the error names the target and no temporary is left behind.
TEST_F(OutputFiles, FailedRenameRemovesTemporary) {
    const fs::path target = dir / "out";
    fs::create_directory(target);
    for (Format f : {Format::Svg, Format::Pdf, Format::Png, Format::Json}) {
        try {
            inkline::write_drawing(sample_drawing(), target.string(), f, {});
            ADD_FAILURE() << "no exception for format " << int(f);
        } catch (const inkline::Error& e) {
            EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
        }
        EXPECT_EQ(entries(), std::set<std::string>{"out"}) << "format " << int(f);
        EXPECT_TRUE(fs::is_directory(target));
    }
}

TEST_F(OutputFiles, ReplacesExistingFile) {
    const fs::path p = dir / "d.svg";
    std::ofstream(p) << "old";
    inkline::write_drawing(sample_drawing(), p.string(), Format::Svg, {});
    EXPECT_EQ(read_file(p), inkline::drawing_to_svg(sample_drawing(), {}));
    EXPECT_EQ(entries(), std::set<std::string>{"d.svg"});
}
