// Inputs the parser fuzzers (fuzz/run.sh: off obj ply stl offsets style bpt surfaces) found
// failing, replayed after their fix: fuzz/regressions/<target>-<what>. Mesh formats go through
// load_mesh (accepted meshes must be valid, refusals an inkline::Error of one line naming the
// file); the other parsers through the fuzzers' own checks (fuzz/parser_checks.hpp). The pipeline
// fuzzer's inputs are replayed by Extremes.PipelineFuzzRegressions.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../fuzz/parser_checks.hpp"
#include "core/error.hpp"
#include "model/mesh_io.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = INKLINE_SOURCE_DIR;

std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// The regression inputs of one target, sorted.
std::vector<fs::path> inputs(const std::string& target) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "regressions"))
        if (e.path().filename().string().rfind(target + "-", 0) == 0) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

// The error's message: one line, naming `where`.
void expect_one_line_naming(const inkline::Error& e, const std::string& where, const fs::path& input) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << input << ": " << m;
    EXPECT_NE(m.find(where), std::string::npos) << input << ": " << m;
}

void replay_mesh(const std::string& ext) {
    for (const auto& in : inputs(ext)) {
        const fs::path tmp = fs::temp_directory_path() / ("inkline_fuzz_regression." + ext);
        fs::copy_file(in, tmp, fs::copy_options::overwrite_existing);
        try {
            const inkline::TriangleMesh m = inkline::load_mesh(tmp.string());
            for (const auto& t : m.triangles)
                for (auto i : t) EXPECT_LT(i, m.positions.size()) << in;
        } catch (const inkline::Error& e) {
            expect_one_line_naming(e, tmp.string(), in);
        }
        fs::remove(tmp);
    }
}

}  // namespace

TEST(FuzzRegressions, MeshFormats) {
    for (const char* ext : {"off", "obj", "ply", "stl"}) replay_mesh(ext);
}

TEST(FuzzRegressions, OffsetTables) {
    for (const auto& in : inputs("offsets")) EXPECT_EQ(inkline_fuzz::check_offsets(read(in)), "") << in;
}

TEST(FuzzRegressions, StyleFiles) {
    for (const auto& in : inputs("style"))
        EXPECT_EQ(inkline_fuzz::check_style(read(in), (kRoot / "styles").string()), "") << in;
}

TEST(FuzzRegressions, BezierPatches) {
    for (const auto& in : inputs("bpt")) EXPECT_EQ(inkline_fuzz::check_bpt(read(in)), "") << in;
}

TEST(FuzzRegressions, SurfacesJson) {
    for (const auto& in : inputs("surfaces")) EXPECT_EQ(inkline_fuzz::check_surfaces_json(read(in)), "") << in;
}

// The seeds the fuzzers start from are accepted (so the checks above reach past the parsers).
TEST(FuzzRegressions, SeedsAreAccepted) {
    for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "corpus" / "offsets"))
        EXPECT_NO_THROW(inkline::parse_offset_table(read(e.path()), e.path().string())) << e.path();
    for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "corpus" / "style"))
        EXPECT_NO_THROW(inkline::parse_style(read(e.path()), (kRoot / "styles" / "seed.json").string())) << e.path();
    for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "corpus" / "bpt"))
        EXPECT_NO_THROW(inkline::freeform::parse_bpt(read(e.path()), e.path().string())) << e.path();
    for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "corpus" / "surfaces"))
        EXPECT_NO_THROW(inkline::freeform::parse_surfaces_json(read(e.path()), e.path().string())) << e.path();
}
