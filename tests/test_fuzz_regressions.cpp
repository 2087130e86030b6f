// Inputs the parser fuzzers (fuzz/run.sh: off obj ply stl glb gltf offsets style bpt surfaces)
// found failing, replayed after their fix: fuzz/regressions/<target>-<what>. Mesh formats go
// through load_mesh (accepted meshes must be valid, refusals an inkline::Error of one line naming
// the file); glTF through the scene fuzzers' check (fuzz/scene_checks.hpp); the other parsers
// through the fuzzers' own checks (fuzz/parser_checks.hpp). The pipeline fuzzer's inputs are
// replayed by Extremes.PipelineFuzzRegressions.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../fuzz/parser_checks.hpp"
#include "../fuzz/scene_checks.hpp"
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

// glTF files (fuzz_glb, fuzz_gltf): each input as a file of its extension through load_scene,
// tolerant and strict. Assimp misbehaved on each (a 4 GB allocation for a JSON chunk length past
// the file's end; a timeout under the fuzzer on invalid JSON; a heap read past a buffer by one of
// the readers it tries on a .glb without the glTF magic); inkline now refuses them before Assimp
// reads them.
TEST(FuzzRegressions, SceneFiles) {
    std::size_t replayed = 0;
    for (const char* ext : {"glb", "gltf"})
        for (const auto& in : inputs(ext)) {
            const fs::path tmp = fs::temp_directory_path() / ("inkline_fuzz_regression." + std::string(ext));
            fs::copy_file(in, tmp, fs::copy_options::overwrite_existing);
            EXPECT_EQ(inkline_fuzz::check_scene_file(tmp.string()), "") << in;
            try {
                (void)inkline::load_scene(tmp.string());
                ADD_FAILURE() << in << ": accepted";
            } catch (const inkline::Error& e) {
                const std::string m = e.what();
                EXPECT_TRUE(m.find(": truncated: ") != std::string::npos || m.find(": not valid JSON: ") != std::string::npos ||
                            m.find(": not a binary glTF file") != std::string::npos)
                    << in << ": " << m;
            }
            fs::remove(tmp);
            ++replayed;
        }
    EXPECT_EQ(replayed, 3u);
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
    for (const char* dir : {"glb", "gltf"})
        for (const auto& e : fs::directory_iterator(kRoot / "fuzz" / "corpus" / dir)) {
            const inkline::Scene s = inkline::load_scene(e.path().string(), inkline::LoadOptions{.strict = true});
            EXPECT_EQ(inkline_fuzz::scene_problem(s), "") << e.path();
        }
}
