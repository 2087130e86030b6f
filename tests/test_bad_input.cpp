// Bad input, through the library (load_mesh) and through the `inkline` command: truncated,
// garbled and huge-count OBJ/OFF/PLY/STL files, non-manifold and non-orientable meshes, repeated
// and out-of-range indices, empty files, bad options and unwritable outputs. Every case must give
// one line naming the file (or flag) and the problem, exit code 1, and no output file (nor a
// temporary) left behind. Files claiming billions of elements must fail without allocating for
// them: the command's peak resident memory is checked.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "model/mesh_io.hpp"

namespace fs = std::filesystem;

namespace {

fs::path scratch() {
    const fs::path d = fs::path(::testing::TempDir()) /
                       ("inkline_bad_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                        "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::size_t count_lines(const std::string& s) {
    std::size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

struct CliResult {
    int code = -1;
    std::string err;
    long maxrss_kib = 0;  // the child's peak resident memory
};

// Runs the command directly (no shell), stderr to a file; the child's rusage gives its peak memory.
CliResult run_cli(const std::vector<std::string>& args, const fs::path& dir) {
    const fs::path errf = dir / "stderr.txt";
    std::vector<std::string> all = {INKLINE_BINARY};
    all.insert(all.end(), args.begin(), args.end());
    const pid_t pid = ::fork();
    if (pid == 0) {
        // A guard, so that a regression cannot take the machine's memory: 2 GiB of address space
        // (ASan reserves terabytes of address space, so there its RSS limit is used instead).
#if defined(__SANITIZE_ADDRESS__)
        const char* given = std::getenv("ASAN_OPTIONS");
        ::setenv("ASAN_OPTIONS", ((given ? std::string(given) + ":" : std::string()) + "hard_rss_limit_mb=2048").c_str(), 1);
#else
        const struct rlimit lim = {rlim_t(2) << 30, rlim_t(2) << 30};
        ::setrlimit(RLIMIT_AS, &lim);
#endif
        std::FILE* e = std::freopen(errf.c_str(), "w", stderr);
        std::FILE* o = std::freopen("/dev/null", "w", stdout);
        if (!e || !o) ::_exit(127);
        std::vector<char*> argv;
        for (auto& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    CliResult r;
    int status = 0;
    struct rusage ru {};
    if (pid > 0 && ::wait4(pid, &status, 0, &ru) == pid) {
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.maxrss_kib = ru.ru_maxrss;
    }
    r.err = slurp(errf);
    fs::remove(errf);
    return r;
}

std::string le32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }
std::string lef(float v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

std::string random_bytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string s(n, '\0');
    for (char& c : s) c = char(rng() & 0xff);
    return s;
}

// A text with some bytes replaced by random ones (after `keep` intact bytes).
std::string garble(std::string s, std::size_t keep, unsigned seed) {
    std::mt19937 rng(seed);
    for (std::size_t i = keep; i < s.size(); i += 1 + rng() % 7) s[i] = char(rng() & 0xff);
    return s;
}

const std::string kTetOff = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const std::string kTetObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
const std::string kPlyAsciiHead =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kTetPlyAscii = kPlyAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const std::string kFacet =
    " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   vertex 1 0 0\n  endloop\n endfacet\n";

std::string ply_binary(std::uint32_t nv, std::uint32_t nf, bool body) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(nv) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nf) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
    if (body) {
        const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (auto& p : v)
            for (float c : p) s += lef(c);
        const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
        for (auto& t : f) {
            s.push_back(char(3));
            for (int k : t) s += le32(std::uint32_t(k));
        }
    }
    return s;
}

// Little-endian binary OFF of a tetrahedron (as OpenMesh writes it); the first face may claim
// `corners` corners.
std::string off_binary(std::uint32_t corners = 3) {
    std::string s = "OFF BINARY\n" + le32(4) + le32(4) + le32(0);
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (auto& p : v)
        for (float c : p) s += lef(c);
    const std::uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (int i = 0; i < 4; ++i) {
        s += le32(i == 0 ? corners : 3);
        for (auto k : f[i]) s += le32(k);
    }
    return s;
}

// Binary PLY whose face lists have int lengths, the first one claiming `n` entries.
std::string ply_binary_list(std::uint32_t n) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 4\nproperty list int int vertex_indices\nend_header\n";
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (auto& p : v)
        for (float c : p) s += lef(c);
    const std::uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (int i = 0; i < 4; ++i) {
        s += le32(i == 0 ? n : 3);
        for (auto k : f[i]) s += le32(k);
    }
    return s;
}

std::string stl_binary(std::uint32_t claimed, std::uint32_t records) {
    std::string s(80, ' ');
    s += le32(claimed);
    for (std::uint32_t i = 0; i < records; ++i) {
        std::string rec(50, '\0');
        const float v[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
        std::memcpy(rec.data(), v, sizeof v);
        s += rec;
    }
    return s;
}

// Moebius strip of n quads (a half twist across the seam).
std::string moebius_off(int n) {
    std::ostringstream o;
    o << "OFF\n" << 2 * n << " " << n << " 0\n";
    for (int i = 0; i < n; ++i) {
        const double u = 2.0 * M_PI * i / n;
        for (double s : {-0.3, 0.3}) {
            const double r = 1.0 + s * std::cos(u / 2);
            o << r * std::cos(u) << " " << r * std::sin(u) << " " << s * std::sin(u / 2) << "\n";
        }
    }
    for (int i = 0; i < n; ++i) {
        const int c = i + 1 < n ? 2 * (i + 1) + 1 : 0, d = i + 1 < n ? 2 * (i + 1) : 1;
        o << "4 " << 2 * i << " " << 2 * i + 1 << " " << c << " " << d << "\n";
    }
    return o.str();
}

struct Case {
    std::string file;     // file name (its extension picks the format)
    std::string content;
    std::string problem;  // expected in the message after the file name
    bool huge = false;    // claims billions of elements: peak memory is checked
};

std::vector<Case> bad_meshes() {
    std::vector<Case> c;
    // Empty and nearly empty.
    for (const char* ext : {"off", "obj", "ply", "stl"}) c.push_back({std::string("empty.") + ext, "", "file is empty"});
    c.push_back({"blank.off", "  \n\n\t\n", "no OFF header"});
    c.push_back({"blank.obj", "\n\n# only a comment\n", "no faces"});
    c.push_back({"blank.stl", "\n\n", "not ASCII STL"});
    // Truncated.
    c.push_back({"trunc_header.off", "OFF\n4", "truncated"});
    c.push_back({"trunc_vertices.off", kTetOff.substr(0, kTetOff.find("0 1 0")), "file ends after 2 of 4 vertices"});
    c.push_back({"trunc_midline.off", kTetOff.substr(0, kTetOff.find("0 0 1") + 2), "coordinates, expected 3"});
    c.push_back({"trunc_faces.off", kTetOff.substr(0, kTetOff.size() - 9), "truncated"});
    c.push_back({"trunc_vertex.obj", kTetObj.substr(0, 20), "coordinates, expected 3"});
    c.push_back({"trunc_header.ply", kPlyAsciiHead.substr(0, kPlyAsciiHead.find("property float z")), "no end_header"});
    c.push_back({"trunc_body.ply", kTetPlyAscii.substr(0, kTetPlyAscii.size() - 14), "truncated"});
    c.push_back({"trunc_binary.ply", ply_binary(4, 4, true).substr(0, ply_binary(4, 4, true).size() - 7), "ply"});
    c.push_back({"trunc_ascii.stl", "solid t\n" + kFacet + " facet normal 0 0 0\n  outer loop\n", "truncated"});
    c.push_back({"trunc_binary.stl", stl_binary(4, 4).substr(0, 84 + 50 * 3 + 20), "not the size of a binary STL"});
    // Garbled: random bytes after a valid start, and pure noise.
    c.push_back({"garbled.off", garble(kTetOff, 10, 1), "garbled.off"});
    c.push_back({"garbled.obj", garble(kTetObj, 0, 2), "garbled.obj"});
    c.push_back({"garbled.ply", garble(kTetPlyAscii, kPlyAsciiHead.size(), 3), "garbled.ply"});
    c.push_back({"garbled_binary.ply", ply_binary(4, 4, false) + random_bytes(90, 4), "garbled_binary.ply"});
    c.push_back({"garbled.stl", garble("solid t\n" + kFacet + "endsolid t\n", 8, 5), "garbled.stl"});
    c.push_back({"noise.off", random_bytes(3000, 6), "noise.off"});
    c.push_back({"noise.obj", "v " + random_bytes(3000, 7), "noise.obj"});
    c.push_back({"noise.stl", random_bytes(3001, 8), "noise.stl"});
    c.push_back({"noise.ply", "ply\n" + random_bytes(3000, 9), "noise.ply"});
    // Huge counts: each claims ~4e9 elements in a file of a few hundred bytes.
    c.push_back({"huge.off", "OFF\n4000000000 4000000000 0\n0 0 0\n", "truncated", true});
    c.push_back({"huge_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", "lists 3 of its", true});
    c.push_back({"huge_overflow.off", "OFF\n99999999999999999999999 1 0\n", "bad vertex count", true});
    c.push_back({"huge_binary.off", "OFF BINARY\n" + le32(4000000000u) + le32(4000000000u) + le32(0) + std::string(60, '\0'),
                 "header claims 4000000000 vertices", true});
    c.push_back({"huge_corners_binary.off", off_binary(4000000000u), "face 0 claims 4000000000 corners", true});
    c.push_back({"huge_list_binary.ply", ply_binary_list(2000000000u), "huge_list_binary.ply", true});
    c.push_back({"negative_list_binary.ply", ply_binary_list(4000000000u), "negative_list_binary.ply", true});
    c.push_back({"huge.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
                             "end_header\n0 0 0\n",
                 "truncated", true});
    c.push_back({"huge_list.ply", kPlyAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n4000000000 0 2 1\n", "truncated", true});
    c.push_back({"huge_binary.ply", ply_binary(4000000000u, 4000000000u, true), "huge_binary.ply", true});
    c.push_back({"huge_binary.stl", stl_binary(4000000000u, 2), "not the size of a binary STL", true});
    // Indices.
    c.push_back({"range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "refers to vertex 3 of 3"});
    c.push_back({"negative.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "refers to vertex -1 of 3"});
    c.push_back({"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "refers to vertex 3 of 3"});
    c.push_back({"negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "refers to vertex -1 of 3"});
    c.push_back({"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "is not a vertex index"});
    c.push_back({"range.ply", kPlyAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n",
                 "refers to vertex 9 of 4"});
    c.push_back({"repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", "repeats vertex index 1"});
    c.push_back({"repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 2\n", "repeats vertex index 1"});
    c.push_back({"repeat.ply", kPlyAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 2\n",
                 "repeats vertex index 2"});
    c.push_back({"short_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "fewer than 3 vertices"});
    // A binary STL facet with two identical corners welds into a face that repeats a vertex.
    {
        std::string s = stl_binary(1, 1);
        const float v[12] = {0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1, 0};
        std::memcpy(s.data() + 84, v, sizeof v);
        c.push_back({"repeat.stl", s, "repeats vertex index"});
    }
    // Topology: the Appel/Markosian method needs an orientable 2-manifold.
    c.push_back({"fin.off", "OFF\n5 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 -1 0.5\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 4 1\n",
                 "non-manifold: 1 extra face(s)"});
    c.push_back({"moebius.off", moebius_off(10), "non-orientable"});
    c.push_back({"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "NaN or infinite"});
    c.push_back({"inf.ply", kPlyAsciiHead + "0 0 0\n1e999 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
                 "NaN or infinite"});
    c.push_back({"nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "no faces"});
    return c;
}

void write(const fs::path& p, const std::string& content) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f << content;
}

// The well-formed versions of the binary files above load (the refusals are not blanket ones).
TEST(BadInput, WellFormedBinaryFilesLoad) {
    const fs::path d = scratch();
    for (const auto& [name, content] : std::vector<std::pair<std::string, std::string>>{
             {"tet_bin.off", off_binary()}, {"tet_list.ply", ply_binary_list(3)}, {"tet_bin.ply", ply_binary(4, 4, true)}}) {
        write(d / name, content);
        const inkline::TriangleMesh m = inkline::load_mesh((d / name).string());
        EXPECT_EQ(m.positions.size(), 4u) << name;
        EXPECT_EQ(m.triangles.size(), 4u) << name;
    }
    fs::remove_all(d);
}

// The library, loading strictly: an inkline::Error whose single-line message starts with the
// file's path.
TEST(BadInput, LoadMeshRefusesWithOneLineNamingFileAndProblem) {
    const fs::path d = scratch();
    for (const Case& c : bad_meshes()) {
        const fs::path p = d / c.file;
        write(p, c.content);
        try {
            inkline::load_mesh(p.string(), {.strict = true});
            ADD_FAILURE() << c.file << ": accepted";
        } catch (const inkline::Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind(p.string() + ": ", 0), 0u) << c.file << ": " << m;
            EXPECT_NE(m.find(c.problem), std::string::npos) << c.file << ": expected '" << c.problem << "' in " << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << c.file << ": " << m;
            EXPECT_LT(m.size(), 400u) << c.file << ": " << m;
        } catch (const std::exception& e) {
            ADD_FAILURE() << c.file << ": not an inkline::Error: " << e.what();
        }
    }
    fs::remove_all(d);
}

// Tolerant loading (the default): the same files are refused for the same problem, except the
// repairable ones: they load with their repairs counted or, when no face is left, are refused
// saying so.
TEST(BadInput, TolerantLoadingRepairsOrRefusesTheSame) {
    const fs::path d = scratch();
    const std::set<std::string> left_empty = {"repeat.off", "repeat.obj", "repeat.stl"};  // their only face
    for (const Case& c : bad_meshes()) {
        const fs::path p = d / c.file;
        write(p, c.content);
        if (c.file == "moebius.off") {  // loaded with an orientation seam, named
            const inkline::TriangleMesh m = inkline::load_mesh(p.string());
            EXPECT_EQ(m.triangles.size(), 20u) << c.file;
            EXPECT_EQ(m.repairs.nonorientable_parts, 1u) << c.file;
            EXPECT_GT(m.repairs.orientation_seam_edges, 0u) << c.file;
            EXPECT_EQ(m.repairs.warnings(c.file).size(), 1u) << c.file;
            continue;
        }
        if (c.file == "repeat.ply" || c.file == "fin.off") {
            const inkline::TriangleMesh m = inkline::load_mesh(p.string());
            const bool fin = c.file == "fin.off";
            EXPECT_EQ(m.triangles.size(), fin ? 5u : 3u) << c.file;
            EXPECT_EQ(m.repairs.faces_dropped, fin ? 0u : 1u) << c.file;
            EXPECT_EQ(m.repairs.nonmanifold_edges_cut, fin ? 1u : 0u) << c.file;
            EXPECT_EQ(m.positions.size(), fin ? 7u : 4u) << c.file;  // the fin's two ends split off
            continue;
        }
        const std::string problem = left_empty.count(c.file) ? "no faces left: all 1 faces are degenerate" : c.problem;
        try {
            inkline::load_mesh(p.string());
            ADD_FAILURE() << c.file << ": accepted";
        } catch (const inkline::Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind(p.string() + ": ", 0), 0u) << c.file << ": " << m;
            EXPECT_NE(m.find(problem), std::string::npos) << c.file << ": expected '" << problem << "' in " << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << c.file << ": " << m;
        }
    }
    fs::remove_all(d);
}

// The command: exit code 1, one line on stderr naming the file and the problem, no output, and
// files claiming billions of elements fail in little memory.
TEST(BadInput, CliExitsOneWithOneLineAndNoOutput) {
    const fs::path d = scratch();
    for (const Case& c : bad_meshes()) {
        const fs::path p = d / c.file;
        write(p, c.content);
        for (const char* ext : {".svg", ".png"}) {
            const fs::path out = d / ("out" + std::string(ext));
            // --strict: some of these files are repaired by the default, tolerant loading.
            const CliResult r = run_cli({"render", p.string(), "--strict", "-o", out.string()}, d);
            EXPECT_EQ(r.code, 1) << c.file << ": " << r.err;
            EXPECT_EQ(count_lines(r.err), 1u) << c.file << ": " << r.err;
            EXPECT_EQ(r.err.rfind("inkline: " + p.string() + ": ", 0), 0u) << c.file << ": " << r.err;
            EXPECT_NE(r.err.find(c.problem), std::string::npos) << c.file << ": " << r.err;
            if (c.huge) {
                EXPECT_LT(r.maxrss_kib, 512 * 1024) << c.file << ": peak memory " << r.maxrss_kib << " KiB";
            }
        }
        fs::remove(p);
        // Nothing left behind: no output, no temporary.
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(d)) left.push_back(e.path().filename().string());
        EXPECT_TRUE(left.empty()) << c.file << ": left " << left.front();
    }
    fs::remove_all(d);
}

// Bad options: one line naming the flag, exit 2 (a usage error), no output.
TEST(BadInput, BadOptionsNameTheFlag) {
    const fs::path d = scratch();
    const fs::path m = d / "tet.off";
    write(m, kTetOff);
    struct Opt {
        std::string flag, expect;
        int code;
    };
    const std::vector<Opt> opts = {
        {"--eye=nan,0,0", "--eye", 2},          {"--eye=1e999,0,0", "--eye", 2},
        {"--target=1,2,3,4", "--target", 2},    {"--up=0,0,0", "camera", 2},
        {"--fov=0", "--fov", 2},                {"--fov=180", "--fov", 2},
        {"--size=100000x10", "--size", 2},      {"--size=10", "--size", 2},
        {"--size=-5x-5", "--size", 2},          {"--ortho=0", "camera", 2},
        {"--ortho=-3", "camera", 2},            {"--near=0", "--near", 2},
        {"--crease=-1", "--crease", 2},         {"--crease=181", "--crease", 2},
        {"--subdivide=7", "--subdivide", 2},    {"--fraction=0", "--fraction", 2},
        {"--fraction=2", "--fraction", 2},      {"--seed=-1", "--seed", 2},
        {"--finder=magic", "--finder", 2},      {"--format=bmp", "--format", 2},
        {"--lines=", "--lines", 0},             {"--nonsense=1", "--nonsense", 2},
        {"--eye=0,0,5 --target=0,0,5", "camera", 2}, {"--up=0,0,1 --eye=0,0,5 --target=0,0,0", "camera", 2},
    };
    for (const Opt& o : opts) {
        const fs::path out = d / "o.svg";
        std::vector<std::string> args = {"render", m.string()};
        std::stringstream ss(o.flag);
        for (std::string a; ss >> a;) args.push_back(a);
        args.push_back("-o");
        args.push_back(out.string());
        const CliResult r = run_cli(args, d);
        if (o.code == 0) {  // no line kind: a valid, empty drawing
            EXPECT_EQ(r.code, 0) << o.flag << ": " << r.err;
            fs::remove(out);
            continue;
        }
        EXPECT_EQ(r.code, o.code) << o.flag << ": " << r.err;
        EXPECT_NE(r.err.find(o.expect), std::string::npos) << o.flag << ": " << r.err;
        // A bad value is its one line; an unknown flag adds where to find the flags.
        EXPECT_EQ(count_lines(r.err), o.flag.rfind("--nonsense", 0) == 0 ? 2u : 1u) << o.flag << ": " << r.err;
        EXPECT_FALSE(fs::exists(out)) << o.flag;
    }
    fs::remove_all(d);
}

// Unwritable outputs (these fail for root too): a directory, a path under a regular file, a name
// too long for the file system, a missing directory. One line naming the output, exit 1, nothing
// written, a previous directory untouched.
TEST(BadInput, UnwritableOutputs) {
    const fs::path d = scratch();
    const fs::path m = d / "tet.off";
    write(m, kTetOff);
    write(d / "plain.txt", "x");
    fs::create_directories(d / "adir.svg");
    const std::vector<fs::path> outs = {d / "adir.svg", d / "plain.txt" / "x.svg", d / (std::string(300, 'n') + ".svg"),
                                        d / "missing" / "x.png", d / "adir.svg" / ".." / "plain.txt" / "y.pdf"};
    for (const fs::path& out : outs) {
        for (const char* fmt : {"svg", "png", "pdf", "json"}) {
            const CliResult r = run_cli({"render", m.string(), "-o", out.string(), std::string("--format=") + fmt}, d);
            EXPECT_EQ(r.code, 1) << out << " " << fmt << ": " << r.err;
            EXPECT_EQ(count_lines(r.err), 1u) << out << ": " << r.err;
            EXPECT_NE(r.err.find(out.filename().string().substr(0, 20)), std::string::npos) << out << ": " << r.err;
        }
    }
    EXPECT_TRUE(fs::is_directory(d / "adir.svg"));
    EXPECT_TRUE(fs::is_empty(d / "adir.svg"));
    EXPECT_EQ(slurp(d / "plain.txt"), "x");
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(d)) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 3u);  // tet.off, plain.txt, adir.svg: no output or temporary left
    fs::remove_all(d);
}

}  // namespace
