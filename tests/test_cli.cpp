// The `inkline` command as users run it: exit codes, one-line errors naming the file, no partial
// output files, valid SVG/PDF/PNG/JSON that follows DESIGN.md.
#include <gtest/gtest.h>

#include "cli_util.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using inkline_test::Result;
using inkline_test::slurp;

fs::path scratch() { return inkline_test::scratch("inkline_cli_"); }

Result run(const std::string& args, const fs::path& dir) { return inkline_test::run_inkline("", args, dir); }

std::string mesh(const std::string& name) { return std::string(INKLINE_DATA_DIR) + "/meshes/" + name; }

std::size_t lines(const std::string& s) {
    std::size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

// Drawings (or their temporaries) left in dir.
std::vector<std::string> outputs(const fs::path& dir) {
    std::vector<std::string> v;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".svg") != std::string::npos) v.push_back(e.path().filename().string());
    return v;
}

TEST(Cli, WritesValidJsonFollowingTheDesign) {
    const fs::path d = scratch();
    const Result r = run(mesh("fandisk.off") + " -o " + (d / "f.json").string() + " --hidden", d);
    // (the command word is required)
    EXPECT_EQ(r.code, 2);
    const Result ok = run("render " + mesh("fandisk.off") + " -o " + (d / "f.json").string() + " --hidden", d);
    ASSERT_EQ(ok.code, 0) << ok.err;
    const auto j = nlohmann::json::parse(slurp(d / "f.json"));
    EXPECT_EQ(j["width"], 1024);
    EXPECT_EQ(j["height"], 1024);
    EXPECT_EQ(j["camera"]["fov"], 30.0);
    EXPECT_EQ(j["camera"]["eye"].size(), 3u);
    EXPECT_EQ(j["stats"]["triangles"], 12946);
    EXPECT_GT(j["stats"]["silhouette_edges"].get<int>(), 100);
    EXPECT_EQ(j["stats"]["visibility"], "appel");  // the default method
    EXPECT_GE(j["stats"]["clusters"].get<int>(), 1);
    for (const char* k : {"features", "visibility", "total"}) EXPECT_TRUE(j["stats"]["seconds"].contains(k)) << k;
    int visible = 0, hidden = 0;
    for (const auto& p : j["polylines"]) {
        const std::string kind = p["kind"];
        EXPECT_TRUE(kind == "silhouette" || kind == "crease" || kind == "border") << kind;
        EXPECT_GE(p["points"].size(), 2u);
        (p["qi"].get<int>() == 0 ? visible : hidden)++;
        for (const auto& q : p["points"]) {
            EXPECT_EQ(q.size(), 2u);
            // fandisk is framed by the default camera: well inside the image
            EXPECT_GT(q[0].get<double>(), 0.0);
            EXPECT_LT(q[0].get<double>(), 1024.0);
        }
    }
    EXPECT_GT(visible, 10);
    EXPECT_GT(hidden, 10);
    // The camera flags printed reproduce the same drawing.
    const auto pos = ok.out.find("camera: ");
    ASSERT_NE(pos, std::string::npos) << ok.out;
    const std::string flags = ok.out.substr(pos + 8, ok.out.find('\n', pos) - pos - 8);
    const Result again = run("render " + mesh("fandisk.off") + " -o " + (d / "g.json").string() + " --hidden " + flags, d);
    ASSERT_EQ(again.code, 0) << again.err;
    const auto g = nlohmann::json::parse(slurp(d / "g.json"));
    EXPECT_EQ(g["polylines"], j["polylines"]);
}

TEST(Cli, SvgPdfPngAreValid) {
    const fs::path d = scratch();
    for (const char* ext : {"svg", "pdf", "png"}) {
        const fs::path out = d / (std::string("a.") + ext);
        const Result r = run("render " + mesh("fandisk.off") + " --quiet --hidden -o " + out.string(), d);
        ASSERT_EQ(r.code, 0) << ext << ": " << r.err;
        EXPECT_TRUE(r.out.empty()) << "--quiet printed: " << r.out;
        ASSERT_TRUE(fs::exists(out)) << out;
    }
    const std::string svg = slurp(d / "a.svg");
    EXPECT_NE(svg.find("silhouette-visible"), std::string::npos);
    EXPECT_NE(svg.find("hidden-qi1"), std::string::npos);
    EXPECT_EQ(std::system(("rsvg-convert " + (d / "a.svg").string() + " -o " + (d / "check.png").string()).c_str()), 0);
    EXPECT_EQ(std::system(("pdfinfo " + (d / "a.pdf").string() + " >/dev/null").c_str()), 0);
    const std::string png = slurp(d / "a.png");
    ASSERT_GT(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    // --format overrides an extension-less name
    const Result r = run("render " + mesh("fandisk.off") + " --quiet --format=json -o " + (d / "noext").string(), d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::accept(slurp(d / "noext")));
}

// Each bad input: exit code 1, a single line on stderr naming the file and the problem, no output.
TEST(Cli, BadMeshesGiveOneLineErrorsAndNoOutput) {
    const fs::path d = scratch();
    struct Case {
        std::string name, content, expect;
    };
    const std::vector<Case> cases = {
        {"empty.off", "", "empty.off"},
        {"nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "NaN"},
        {"truncated.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n", "truncated.off"},
        {"noface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
        {"range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "range.off"},
        {"nonmanifold.off",
         "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n", "non-manifold"},
        {"garbage.stl", std::string("solid x\n\x01\x02\x03 garbage \xff\xfe\n"), "garbage.stl"},
        {"unknown.xyz", "1 2 3\n", "unknown.xyz"},
    };
    for (const Case& c : cases) {
        {
            std::ofstream f(d / c.name, std::ios::binary);
            f << c.content;
        }
        const fs::path out = d / (c.name + ".svg");
        // --strict: the non-manifold file is one that tolerant loading repairs (test_scene's CLI tests).
        const Result r = run("render " + (d / c.name).string() + " --strict -o " + out.string(), d);
        EXPECT_EQ(r.code, 1) << c.name << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << c.name << ": " << r.err;
        EXPECT_NE(r.err.find(c.name), std::string::npos) << c.name << ": " << r.err;
        EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": expected '" << c.expect << "' in " << r.err;
        EXPECT_FALSE(fs::exists(out)) << c.name;
    }
    EXPECT_TRUE(outputs(d).empty());
    const Result missing = run("render " + (d / "missing.off").string() + " -o " + (d / "m.svg").string(), d);
    EXPECT_EQ(missing.code, 1);
    EXPECT_NE(missing.err.find("missing.off"), std::string::npos) << missing.err;
}

TEST(Cli, UsageErrorsExitTwo) {
    const fs::path d = scratch();
    // (render draws several models, docs/batch.md: two models and one output file is the usage error.)
    for (const std::string args : {"", "draw x.off", "render", "render a.off b.off -o one.svg", "view a.off b.off",
                                   "render a.off --bogus=1", "render a.off -o"}) {
        const Result r = run(args, d);
        EXPECT_EQ(r.code, 2) << "'" << args << "': " << r.err;
        EXPECT_NE(r.err.find("usage:"), std::string::npos) << r.err;
    }
}

TEST(Cli, BadOptionsAndUnwritableOutput) {
    const fs::path d = scratch();
    const std::string m = mesh("fandisk.off");
    const std::vector<std::array<std::string, 2>> cases = {
        {"--format=gif", "gif"},
        {"--eye=1,2", "--eye"},
        {"--fov=200", "--fov"},
        {"--size=0x10", "--size"},
        {"--crease=abc", "--crease"},
        {"--lines=silhouette,hatch", "hatch"},
        {"--eye=0,0,0 --target=0,0,0", "camera"},
        {"--near=-1", "--near"},
        {"--subdivide=1.5", "--subdivide"},
        {"--visibility=zbuffer", "zbuffer"},
    };
    for (const auto& [flag, expect] : cases) {
        const fs::path out = d / "x.svg";
        const Result r = run("render " + m + " " + flag + " -o " + out.string(), d);
        EXPECT_EQ(r.code, 2) << flag << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1u) << flag << ": " << r.err;
        EXPECT_NE(r.err.find(expect), std::string::npos) << flag << ": " << r.err;
        EXPECT_FALSE(fs::exists(out)) << flag;
    }
    const Result r = run("render " + m + " -o " + (d / "no" / "such" / "dir" / "x.svg").string(), d);
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("x.svg"), std::string::npos) << r.err;
    // A failed write leaves the previous file intact and no temporary beside it.
    {
        std::ofstream f(d / "keep.svg");
        f << "previous";
    }
    fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec);
    const Result ro = run("render " + m + " -o " + (d / "keep.svg").string(), d / "..");
    fs::permissions(d, fs::perms::owner_all);
    if (::geteuid() != 0) {  // root writes through permissions
        EXPECT_EQ(ro.code, 1) << ro.err;
        EXPECT_EQ(slurp(d / "keep.svg"), "previous");
    }
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(d)) files += e.path().filename().string().find("keep.svg") != std::string::npos;
    EXPECT_EQ(files, 1u);
}

}  // namespace

namespace {

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string p; std::getline(ss, p, sep);) out.push_back(p);
    return out;
}

TEST(Cli, RandomizedFinderAndRecallInJson) {
    const fs::path d = scratch();
    const Result r = run("render " + mesh("fandisk.off") + " --finder=randomized --fraction=0.05 --seed=3 --recall -o " +
                             (d / "f.json").string(),
                         d);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(d / "f.json"));
    EXPECT_EQ(j["stats"]["finder"], "randomized");
    EXPECT_EQ(j["stats"]["fraction"], 0.05);
    const double recall = j["stats"]["recall_length"];
    EXPECT_GE(recall, 0.95);
    EXPECT_LE(recall, 1.0);
    EXPECT_NE(r.out.find("finder: randomized"), std::string::npos) << r.out;
    // Bad settings are one-line errors naming the flag.
    const Result bad = run("render " + mesh("fandisk.off") + " --finder=lucky -o " + (d / "g.svg").string(), d);
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--finder: unknown finder 'lucky'"), std::string::npos) << bad.err;
    const Result zero = run("render " + mesh("fandisk.off") + " --fraction=0 -o " + (d / "g.svg").string(), d);
    EXPECT_EQ(zero.code, 2);
    EXPECT_NE(zero.err.find("--fraction"), std::string::npos) << zero.err;
    EXPECT_FALSE(fs::exists(d / "g.svg"));
}

// Coherence from an exhaustive first view follows the silhouette exactly: recall 1 and no wrong
// visible line on every coherence row; a bad value is refused naming the flag.
TEST(Cli, BenchFirstViewExhaustive) {
    const fs::path d = scratch();
    const Result r = run("bench tori:32 --frames=6 --arc=6 --fractions=0.01 --first-view=exhaustive --threads=2 --csv=" +
                             (d / "f.csv").string(), d);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = split(slurp(d / "f.csv"), '\n');
    ASSERT_EQ(rows.size(), 4u);  // header, exhaustive, randomized without and with coherence
    const auto c = split(rows[3], ',');
    ASSERT_EQ(c.size(), 11u);
    EXPECT_EQ(c[4], "1");
    EXPECT_EQ(std::stod(c[9]), 1.0);
    EXPECT_EQ(std::stod(c[10]), 0.0);
    EXPECT_NE(r.out.find("coherence from an exhaustive first view"), std::string::npos) << r.out;
    const Result bad = run("bench tori:32 --first-view=full", d);
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--first-view: unknown value 'full'"), std::string::npos) << bad.err;
}

TEST(Cli, BenchWritesCsvTableAndPlot) {
    const fs::path d = scratch();
    const Result r = run("bench tori:32 --frames=4 --fractions=0.01,0.1 --csv=" + (d / "b.csv").string() +
                             " --plot=" + (d / "b.svg").string() + " --markdown=" + (d / "b.md").string(),
                         d);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = split(slurp(d / "b.csv"), '\n');
    ASSERT_EQ(rows.size(), 1u + 1u + 2u * 2u);  // header, exhaustive, 2 fractions x coherence off/on
    EXPECT_EQ(rows[0],
              "model,triangles,finder,fraction,coherence,frames,ms_per_frame,silhouette_edges_per_frame,"
              "silhouette_edges_per_second,recall_length,wrong_visible_length_px");
    const auto ex = split(rows[1], ',');
    ASSERT_EQ(ex.size(), 11u);
    EXPECT_EQ(ex[0], "tori:32");
    EXPECT_EQ(ex[1], "2048");  // two tori of 32 x 16 quads, two triangles each
    EXPECT_EQ(ex[2], "exhaustive");
    EXPECT_EQ(ex[5], "4");
    EXPECT_EQ(std::stod(ex[9]), 1.0);  // the reference against itself
    EXPECT_EQ(std::stod(ex[10]), 0.0);
    for (std::size_t i = 2; i < rows.size(); ++i) {
        const auto c = split(rows[i], ',');
        ASSERT_EQ(c.size(), 11u) << rows[i];
        EXPECT_EQ(c[2], "randomized");
        EXPECT_EQ(c[4], i < 4 ? "0" : "1") << rows[i];
        EXPECT_GT(std::stod(c[9]), 0.0);
        EXPECT_LE(std::stod(c[9]), 1.0);
        EXPECT_GE(std::stod(c[10]), 0.0);
        EXPECT_GT(std::stod(c[7]), 0.0);
    }
    EXPECT_NE(r.out.find("| finder | fraction | coherence | ms/frame |"), std::string::npos) << r.out;
    EXPECT_EQ(slurp(d / "b.md"), r.out);
    const std::string svg = slurp(d / "b.svg");
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    EXPECT_NE(svg.find("<svg"), std::string::npos);
    // Unknown path: an error naming the flag, nothing written.
    const Result bad = run("bench tori:32 --path=spiral --csv=" + (d / "c.csv").string(), d);
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--path: unknown path 'spiral'"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(d / "c.csv"));
}

}  // namespace

namespace {

// The three commands, each with a model it accepts (view's flags are parsed before its window).
const std::vector<std::string>& commands() {
    static const std::vector<std::string> c = {"render " + mesh("fandisk.off"), "view " + mesh("fandisk.off"),
                                               "bench tori:8"};
    return c;
}

// One definition a flag: render, view and bench take the same values of the flags they share and
// refuse the same ones with the same line. Flags are read left to right, each checked where it
// stands, so "--seed=2^31 --crease=200" failing on --crease shows that --seed=2^31 was taken (the
// window never opens). Before, view and bench refused seeds above 2^31-1 and bench took any crease.
TEST(Cli, SharedFlagsHaveOneDefinition) {
    const fs::path d = scratch();
    const std::string crease = "inkline: --crease: expected an angle in [0, 180] degrees";
    const std::vector<std::array<std::string, 2>> cases = {
        {"--seed=2147483648 --crease=200", crease},   // 2^31: a seed everywhere
        {"--seed=9007199254740992 --crease=200", crease},  // 2^53, the largest
        {"--crease=180 --crease=200", crease},
        {"--crease=-1", crease},
        {"--seed=9007199254740994", "inkline: --seed: expected an integer from 0 to 2^53"},
        {"--seed=-1", "inkline: --seed: expected an integer from 0 to 2^53"},
        {"--seed=1.5", "inkline: --seed: expected an integer from 0 to 2^53"},
        {"--size=800", "inkline: --size: expected WxH, got '800'"},
        {"--size=0x10", "inkline: --size: expected integer sizes between 1 and 32768, got '0x10'"},
        {"--subdivide=7", "inkline: --subdivide: expected a number of levels from 0 to 6"},
        {"--visibility=zbuffer", "inkline: --visibility: unknown method 'zbuffer' (expected appel, rays or fast)"},
    };
    for (const std::string& cmd : commands())
        for (const auto& [flags, expect] : cases) {
            const Result r = run(cmd + " " + flags, d);
            // A bad value exits 1, as tests/test_bad_input.cpp pins for render (usage errors: 2).
            EXPECT_EQ(r.code, 2) << cmd << " " << flags << ": " << r.err;
            EXPECT_EQ(r.err, expect + "\n") << cmd << " " << flags;
        }
    // view and bench share --first-view, render and view --finder, --fraction and --lines.
    for (const std::string& cmd : {commands()[1], commands()[2]}) {
        const Result r = run(cmd + " --first-view=full", d);
        EXPECT_EQ(r.code, 2) << cmd;
        EXPECT_EQ(r.err, "inkline: --first-view: unknown value 'full' (expected exhaustive or random)\n") << cmd;
    }
    for (const std::string& cmd : {commands()[0], commands()[1]}) {
        for (const auto& [flags, expect] : std::vector<std::array<std::string, 2>>{
                 {"--fraction=0", "inkline: --fraction: expected a share in (0, 1]\n"},
                 {"--finder=lucky", "inkline: --finder: unknown finder 'lucky' (expected exhaustive or randomized)\n"},
                 {"--lines=hatch", "inkline: --lines: unknown line kind 'hatch' (expected silhouette, crease, border, suggestive, smooth-contour, ridge, valley, intersection, tone-dark, tone-highlight)\n"}}) {
            const Result r = run(cmd + " " + flags, d);
            EXPECT_EQ(r.code, 2) << cmd << " " << flags;
            EXPECT_EQ(r.err, expect) << cmd << " " << flags;
        }
    }
    // And the seeds taken are used: render and bench run with a seed of 2^31.
    const Result render = run("render " + mesh("fandisk.off") + " --finder=randomized --seed=2147483648 --quiet -o " +
                                  (d / "f.json").string(), d);
    EXPECT_EQ(render.code, 0) << render.err;
    const Result bench = run("bench tori:8 --frames=2 --fractions=0.5 --seed=2147483648 --crease=180", d);
    EXPECT_EQ(bench.code, 0) << bench.err;
}

// A word that is not a flag of the command: exit 2, one line naming it, then the usage with a
// pointer to the command's help (not the whole usage of every command).
TEST(Cli, UnknownFlagNamesItAndPointsAtTheHelp) {
    const fs::path d = scratch();
    for (const std::string& cmd : commands()) {
        const std::string name = cmd.substr(0, cmd.find(' '));
        const std::string see = "usage: inkline " + name + " MODEL [FLAGS]; see 'inkline " + name + " --help'\n";
        const std::vector<std::array<std::string, 2>> cases = {
            {"--bogus=1", "inkline: unknown option '--bogus'"},
            {"--bogus", "inkline: unknown option '--bogus'"},
            {"--hidden=1", name == "bench" ? "inkline: unknown option '--hidden'" : "inkline: --hidden takes no value"},
            {"--crease", "inkline: --crease needs a value (--crease=DEG)"},
            {"extra.off", "inkline: more than one model given"},
        };
        for (const auto& [flags, expect] : cases) {
            // render takes several models (docs/batch.md); a second model is no usage error there.
            if (name == "render" && flags == "extra.off") continue;
            const Result r = run(cmd + " " + flags, d);
            EXPECT_EQ(r.code, 2) << cmd << " " << flags << ": " << r.err;
            EXPECT_EQ(lines(r.err), 2u) << cmd << " " << flags << ": " << r.err;
            EXPECT_EQ(r.err.rfind(expect, 0), 0u) << cmd << " " << flags << ": " << r.err;
            EXPECT_EQ(r.err.substr(r.err.find('\n') + 1), see) << cmd << " " << flags;
        }
    }
    const Result none = run("", d);
    EXPECT_EQ(none.code, 2);
    EXPECT_EQ(none.err, "inkline: no command given\nusage: inkline COMMAND MODEL [FLAGS]; see 'inkline --help'\n");
}

// Every line of a help fits 100 columns, and no help points at a file the user does not have.
void expect_readable(const std::string& help, const std::string& what) {
    EXPECT_EQ(help.find("DESIGN.md"), std::string::npos) << what;
    std::stringstream ss(help);
    for (std::string line; std::getline(ss, line);) EXPECT_LE(line.size(), 100u) << what << ": " << line;
}

TEST(Cli, HelpOverviewAndVersion) {
    const fs::path d = scratch();
    for (const std::string args : {"--help", "-h", "help"}) {
        const Result r = run(args, d);
        EXPECT_EQ(r.code, 0) << args;
        EXPECT_TRUE(r.err.empty()) << args << ": " << r.err;
        EXPECT_EQ(r.out.rfind("inkline draws 3D models as line drawings", 0), 0u) << r.out;
        for (const char* line : {"\n  render   ", "\n  view     ", "\n  bench    ", "inkline COMMAND --help for its flags"})
            EXPECT_NE(r.out.find(line), std::string::npos) << args << ": no '" << line << "' in\n" << r.out;
        EXPECT_LE(lines(r.out), 15u) << r.out;  // an overview, not every command's flags
        expect_readable(r.out, args);
    }
    const Result v = run("--version", d);
    EXPECT_EQ(v.code, 0);
    EXPECT_TRUE(v.err.empty()) << v.err;
    // project(VERSION), then the git revision when built from a checkout (cmake/revision.cmake).
    EXPECT_TRUE(std::regex_match(v.out, std::regex("inkline [0-9]+\\.[0-9]+\\.[0-9]+( \\(git [0-9a-f]{10}(, modified)?\\))?\n")))
        << v.out;
}

// `inkline COMMAND --help`: that command's flags only, grouped, exit 0, wherever --help stands.
TEST(Cli, HelpOfEachCommand) {
    const fs::path d = scratch();
    struct Case {
        std::string command;
        std::vector<std::string> has, hasnt;
    };
    const std::vector<Case> cases = {
        {"render",
         {"\nOutput:\n", "\nCamera (default framed: the whole model in view, fov 30, +Y up):\n", "\nLines:\n",
          "\nSilhouette finder:\n", "\nVisibility:\n", "\nStyle:\n", "\n  -o FILE, --output=FILE ", "\n  --eye=X,Y,Z ",
          "\n  --crease=DEG ", "\n  --seed=S ", "\n  --strokes=KIND ", "\n  --size=WxH ", "(default 1024x1024)",
          "\nSequence (several models, or a camera path; frames numbered from 0):\n", "\n  --frames=N ", "\n  --orbit ",
          "\n  --frame-range=A:B ", "\n  --jobs=N "},
         {"--in-flight", "--fractions", "--path"}},
        {"view",
         {"\nCamera (default framed", "\nWindow:\n", "\n  --in-flight=1|2 ", "\n  --crease=DEG ", "\n  --seed=S ",
          "\n  --frames=N ", "(default 1024x768)"},
         {"--fractions", "--strokes", "--output"}},
        {"bench",
         {"\nCamera path:\n", "\n  --fractions=F,F,... ", "\n  --crease=DEG ", "\n  --seed=S ", "\n  --path=orbit|dolly|walk "},
         {"--eye", "--in-flight", "--strokes", "--style"}},
    };
    for (const Case& c : cases) {
        const Result r = run(c.command + " --help", d);
        EXPECT_EQ(r.code, 0) << c.command << ": " << r.err;
        EXPECT_TRUE(r.err.empty()) << c.command << ": " << r.err;
        EXPECT_EQ(r.out.rfind("usage: inkline " + c.command + " MODEL", 0), 0u) << r.out;
        for (const std::string& s : c.has) EXPECT_NE(r.out.find(s), std::string::npos) << c.command << ": no '" << s << "'";
        for (const std::string& s : c.hasnt) EXPECT_EQ(r.out.find(s), std::string::npos) << c.command << ": '" << s << "'";
        expect_readable(r.out, c.command + " --help");
        // The same after a model and flags, and as `inkline help COMMAND`.
        EXPECT_EQ(run(c.command + " model.off --crease=30 -h", d).out, r.out) << c.command;
        EXPECT_EQ(run("help " + c.command, d).out, r.out) << c.command;
    }
}

}  // namespace
