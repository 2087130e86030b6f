// `inkline render --style=...` as users run it: presets found by name, the clean preset drawing
// exactly the default output, bad style files refused with one line naming file and key.
#include <gtest/gtest.h>

#include "cli_util.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

using inkline_test::Result;
using inkline_test::slurp;

fs::path scratch() { return inkline_test::scratch("inkline_style_cli_"); }

Result run(const std::string& args, const fs::path& dir, const std::string& env = "") {
    return inkline_test::run_inkline(env.empty() ? "" : env + " ", args, dir);
}

std::string mesh(const std::string& name) { return std::string(INKLINE_DATA_DIR) + "/meshes/" + name; }

std::size_t lines(const std::string& s) {
    std::size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

}  // namespace

TEST(StyleCli, CleanPresetIsTheDefaultDrawingByteForByte) {
    const fs::path d = scratch();
    for (const std::string flags : {"", " --hidden"}) {
        ASSERT_EQ(run("render " + mesh("fandisk.off") + " -o " + (d / "plain.png").string() + flags + " --quiet --size=300x200", d).code, 0);
        const Result r = run("render " + mesh("fandisk.off") + " -o " + (d / "clean.png").string() + flags + " --quiet --size=300x200 --style=clean", d);
        ASSERT_EQ(r.code, 0) << r.err;
        const std::string a = slurp(d / "plain.png"), b = slurp(d / "clean.png");
        EXPECT_GT(a.size(), 1000u);
        EXPECT_TRUE(a == b) << "flags '" << flags << "': --style=clean differs from the default PNG";
    }
}

TEST(StyleCli, EveryPresetDrawsSvgPdfPng) {
    const fs::path d = scratch();
    for (const char* style : {"clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched"}) {
        for (const char* ext : {"svg", "pdf", "png"}) {
            const fs::path out = d / (std::string(style) + "." + ext);
            const Result r = run("render " + mesh("fandisk.off") + " -o " + out.string() + " --size=200x200 --style=" + style, d);
            ASSERT_EQ(r.code, 0) << style << "." << ext << ": " << r.err;
            const std::string bytes = slurp(out);
            ASSERT_GT(bytes.size(), 200u) << out;
            const std::string magic = std::string(ext) == "png" ? "\x89PNG" : std::string(ext) == "pdf" ? "%PDF" : "<?xml";
            EXPECT_EQ(bytes.substr(0, magic.size()), magic) << out;
            EXPECT_NE(r.out.find("style: "), std::string::npos);
        }
    }
}

TEST(StyleCli, StylesDirectoryFromTheEnvironment) {
    const fs::path d = scratch();
    fs::create_directories(d / "mine");
    std::ofstream(d / "mine" / "red.json") << R"({"lines": {"default": {"colour": "#ff0000"}}})";
    Result r = run("render " + mesh("fandisk.off") + " -o " + (d / "a.png").string() + " --size=64x64 --style=red", d,
                   "INKLINE_STYLES=" + (d / "mine").string());
    EXPECT_EQ(r.code, 0) << r.err;
    r = run("render " + mesh("fandisk.off") + " -o " + (d / "b.png").string() + " --size=64x64 --style=red", d,
            "INKLINE_STYLES=" + (d / "nothing").string());
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("no style 'red'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "b.png"));
}

TEST(StyleCli, BadStyleFileIsOneLineNamingFileAndKey) {
    const fs::path d = scratch();
    const fs::path bad = d / "bad.json";
    std::ofstream(bad) << R"({"lines": {"crease": {"width_rule": "wide"}}})";
    const Result r = run("render " + mesh("fandisk.off") + " -o " + (d / "x.png").string() + " --style=" + bad.string(), d);
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("lines.crease.width_rule"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("constant, taper"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "x.png"));
    // A style has no JSON form.
    const Result j = run("render " + mesh("fandisk.off") + " -o " + (d / "x.json").string() + " --style=clean", d);
    EXPECT_EQ(j.code, 2);
    EXPECT_NE(j.err.find("--style"), std::string::npos) << j.err;
}
