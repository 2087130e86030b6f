// The installed facade (include/inkline/inkline.hpp): it draws what `inkline render` draws, finds
// styles where it is told, and reports bad input as inkline::api::Error naming the problem.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "inkline/inkline.hpp"

namespace {

namespace ink = inkline::api;
using inkline_test::run_inkline;
using inkline_test::slurp;
namespace fs = std::filesystem;

std::string mesh(const std::string& name) { return std::string(INKLINE_DATA_DIR) + "/meshes/" + name; }
fs::path scratch() { return inkline_test::scratch("api_"); }

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const ink::Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(Api, DrawsWhatRenderWrites) {
    const fs::path d = scratch();
    const ink::Model model = ink::Model::load(mesh("fandisk.off"));
    EXPECT_EQ(model.triangles(), 12946u);
    ink::DrawOptions options;
    options.hidden = true;
    const ink::Drawing drawing = ink::draw(model, ink::Camera::framing(model, 640, 480), options);
    EXPECT_EQ(drawing.width(), 640);
    EXPECT_EQ(drawing.height(), 480);
    drawing.write((d / "api.json").string());
    // The command's default camera is the same framing: the same pieces, point for point.
    const auto r = run_inkline("", "render " + mesh("fandisk.off") + " -o " + (d / "cli.json").string() +
                                       " --size=640x480 --hidden --quiet", d);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto api = nlohmann::json::parse(slurp(d / "api.json")), cli = nlohmann::json::parse(slurp(d / "cli.json"));
    ASSERT_GT(cli["polylines"].size(), 100u);
    EXPECT_EQ(api["polylines"], cli["polylines"]);
    EXPECT_EQ(api["camera"], cli["camera"]);

    // polylines(): the same pieces, hidden ones only when asked for.
    const std::vector<ink::Polyline> all = drawing.polylines();
    ASSERT_EQ(all.size(), cli["polylines"].size());
    EXPECT_EQ(all[0].kind, cli["polylines"][0]["kind"].get<std::string>());
    EXPECT_EQ(all[0].qi, cli["polylines"][0]["qi"].get<int>());
    std::size_t hidden = 0;
    for (const ink::Polyline& p : all) hidden += p.qi > 0;
    EXPECT_GT(hidden, 0u);
    const ink::Drawing visible_only = ink::draw(model, ink::Camera::framing(model, 640, 480));
    EXPECT_EQ(visible_only.polylines().size(), all.size() - hidden);
}

TEST(Api, StyleFromTheGivenDirectoryIsWhatRenderDraws) {
    const fs::path d = scratch();
    const ink::Model model = ink::Model::load(mesh("bunny00.off"));
    ink::DrawOptions options;
    options.style = "technical";
    options.styles_dir = std::string(INKLINE_SOURCE_DIR) + "/styles";
    ink::draw(model, ink::Camera::framing(model, 300, 300), options).write((d / "api.png").string());
    const auto r = run_inkline("", "render " + mesh("bunny00.off") + " -o " + (d / "cli.png").string() +
                                       " --size=300x300 --style=technical --quiet", d);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string png = slurp(d / "api.png");
    ASSERT_EQ(png.substr(1, 3), "PNG");
    EXPECT_EQ(png, slurp(d / "cli.png"));
}

TEST(Api, BadInputIsOneErrorNamingIt) {
    const fs::path d = scratch();
    EXPECT_NE(error_of([] { ink::Model::load("/no/such/model.off"); }).find("/no/such/model.off"), std::string::npos);
    EXPECT_NE(error_of([] { ink::Model::load(mesh("fandisk.off"), {.subdivide = 7}); }).find("subdivide"),
              std::string::npos);
    const ink::Model model = ink::Model::load(mesh("fandisk.off"));
    ink::Camera camera = ink::Camera::framing(model, 100, 100);
    ink::DrawOptions options;
    options.lines = {"silhouette", "contour"};
    EXPECT_NE(error_of([&] { ink::draw(model, camera, options); }).find("unknown line kind 'contour'"), std::string::npos);
    options.lines = {"silhouette"};
    options.style = "no-such-style";
    options.styles_dir = std::string(INKLINE_SOURCE_DIR) + "/styles";
    EXPECT_NE(error_of([&] { ink::draw(model, camera, options); }).find("no style 'no-such-style'"), std::string::npos);
    camera.eye = camera.target;
    EXPECT_EQ(error_of([&] { ink::draw(model, camera); }).rfind("camera: ", 0), 0u);
    camera = ink::Camera::framing(model, 100, 100);
    camera.width = 0;
    EXPECT_EQ(error_of([&] { ink::draw(model, camera); }).rfind("camera: ", 0), 0u);
    const ink::Drawing drawing = ink::draw(model, ink::Camera::framing(model, 100, 100));
    EXPECT_NE(error_of([&] { drawing.write((d / "a.txt").string()); }).find("a.txt"), std::string::npos);
    EXPECT_FALSE(fs::exists(d / "a.txt"));
    EXPECT_EQ(ink::version(), INKLINE_VERSION);
}

}  // namespace
