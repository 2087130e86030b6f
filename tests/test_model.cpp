// Model stage: load_mesh (formats, refusals with "<file>: <problem>" messages, orientation) and
// build_topology (edges, faces, flags, crease threshold, adjacency) on meshes with known answers.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "model/mesh_io.hpp"
#include "model/primitives.hpp"
#include "model/reorder.hpp"
#include "model/self_intersections.hpp"
#include "model/subdivide.hpp"
#include "model/topology.hpp"
#include "model/topology_steps.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"

namespace fs = std::filesystem;
using inkline::MeshTopology;
using inkline::TriangleMesh;

namespace {

// ---------------------------------------------------------------------------------------------
// Files in a private temporary directory, removed at the end.

const fs::path& temp_dir() {
    static const fs::path dir = [] {
        fs::path d = fs::path(::testing::TempDir()) / ("inkline_test_model_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

class TempDirCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(temp_dir(), ec);
    }
};
[[maybe_unused]] ::testing::Environment* const kCleanup = ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

std::string write_file(const std::string& name, const std::string& content) {
    const fs::path p = temp_dir() / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << content;
    out.close();
    EXPECT_TRUE(out.good()) << p;
    return p.string();
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The message of the inkline::Error that loading `path` must throw ("" and a failure if none).
std::string load_error(const std::string& path, inkline::LoadOptions options = {}) {
    try {
        const TriangleMesh m = inkline::load_mesh(path, options);
        ADD_FAILURE() << path << " was accepted (" << m.positions.size() << " vertices, " << m.triangles.size()
                      << " triangles)";
    } catch (const inkline::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << path << " threw a non-inkline exception: " << e.what();
    }
    return "";
}

// Loading must fail with "<path>: ..." and a message that contains every one of `parts`.
void expect_refused(const std::string& path, const std::vector<std::string>& parts,
                    inkline::LoadOptions options = {}) {
    const std::string msg = load_error(path, options);
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << "message does not start with the file name: " << msg;
    for (const auto& p : parts) EXPECT_TRUE(contains(msg, p)) << "message lacks '" << p << "': " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
}

std::string off_file(const std::vector<glm::dvec3>& v, const std::vector<std::vector<int>>& f) {
    std::ostringstream s;
    s.precision(17);
    s << "OFF\n" << v.size() << ' ' << f.size() << " 0\n";
    for (const auto& p : v) s << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (const auto& face : f) {
        s << face.size();
        for (int i : face) s << ' ' << i;
        s << '\n';
    }
    return s.str();
}

// Unit right tetrahedron, outward orientation (signed volume +1/6).
const std::vector<glm::dvec3> kTetV = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<std::vector<int>> kTetF = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// Unit cube as quads, outward.
const std::vector<glm::dvec3> kCubeV = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                        {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const std::vector<std::vector<int>> kCubeF = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                              {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};

double signed_volume(const TriangleMesh& m) {
    double v = 0.0;
    for (const auto& t : m.triangles)
        v += glm::dot(m.positions[t[0]], glm::cross(m.positions[t[1]], m.positions[t[2]]));
    return v / 6.0;
}

// Every undirected edge of a consistently oriented mesh is traversed once in each direction
// (or once, on a border).
void expect_consistent(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : directed) EXPECT_EQ(n, 1) << "edge " << e.first << "->" << e.second;
}

}  // namespace

// =============================================================================================
// Refusals

TEST(LoadMeshErrors, NonexistentFile) {
    const std::string path = (temp_dir() / "does_not_exist.off").string();
    expect_refused(path, {"cannot open"});
}

TEST(LoadMeshErrors, UnknownExtension) {
    const std::string path = write_file("tet.xyz", off_file(kTetV, kTetF));
    expect_refused(path, {"unsupported", "xyz"});
    const std::string none = write_file("no_extension", off_file(kTetV, kTetF));
    expect_refused(none, {"unsupported"});
}

TEST(LoadMeshErrors, Utf16Text) {
    expect_refused(write_file("utf16.obj", std::string("\xff\xfev\0 \0" "0\0", 8)), {"UTF-16", "UTF-8"});
    expect_refused(write_file("utf16be.off", std::string("\xfe\xff\0O\0F\0F", 8)), {"UTF-16"});
}

TEST(LoadMeshErrors, EmptyFile) {
    for (const char* name : {"empty.off", "empty.obj", "empty.ply", "empty.stl"})
        expect_refused(write_file(name, ""), {"empty"});
}

TEST(LoadMeshErrors, MalformedOff) {
    expect_refused(write_file("bad_header.off", "NOTOFF\n4 4 0\n0 0 0\n"), {"line 1", "OFF header"});
    expect_refused(write_file("bad_count.off", "OFF\nfour 4 0\n"), {"line 2", "vertex count"});
    expect_refused(write_file("bad_number.off",
                              "OFF\n4 4 0\n0 0 0\n1 zero 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"),
                   {"line 4", "'zero' is not a number"});
    expect_refused(write_file("short_vertex.off",
                              "OFF\n4 4 0\n0 0 0\n1 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"),
                   {"line 4", "vertex 1", "coordinates"});
    expect_refused(write_file("short_face.off",
                              "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1\n3 0 3 2\n3 1 2 3\n"),
                   {"line 8", "face 1", "indices"});
    expect_refused(write_file("bad_index.off",
                              "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3.5\n3 0 3 2\n3 1 2 3\n"),
                   {"face 1", "not a vertex index"});
    expect_refused(write_file("two_corners.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n2 0 1\n"),
                   {"face 1", "fewer than 3"});
}

TEST(LoadMeshErrors, TruncatedOff) {
    const std::string full = off_file(kTetV, kTetF);
    // Cut inside the vertices, between vertices and faces, inside the faces, inside the counts.
    expect_refused(write_file("trunc_v.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n"), {"truncated", "2 of 4 vertices"});
    expect_refused(write_file("trunc_f0.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"),
                   {"truncated", "0 of 4 faces"});
    expect_refused(write_file("trunc_f.off", full.substr(0, full.rfind("3 0 3 2"))), {"truncated", "2 of 4 faces"});
    expect_refused(write_file("trunc_hdr.off", "OFF\n4\n"), {"truncated"});
    expect_refused(write_file("only_header.off", "OFF\n"), {"truncated"});
}

TEST(LoadMeshErrors, MalformedObj) {
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    expect_refused(write_file("bad_index.obj", v + "f 1 3 2\nf 1 2 x\n"), {"line 6", "'x' is not a vertex index"});
    expect_refused(write_file("zero_index.obj", v + "f 0 3 2\n"), {"line 5", "not a vertex index"});
    expect_refused(write_file("short_vertex.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"),
                   {"line 2", "vertex 1", "coordinates"});
    expect_refused(write_file("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 0 1 q\nf 1 2 3\n"),
                   {"line 3", "'q' is not a number"});
    expect_refused(write_file("two_corners.obj", v + "f 1 2\n"), {"face 0", "fewer than 3"});
    // Truncated in the middle of a face line: the last face loses its third index.
    expect_refused(write_file("trunc.obj", v + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3"), {"face 3", "fewer than 3"});
}

TEST(LoadMeshErrors, MalformedPlyAndStl) {
    const std::string hdr =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
    expect_refused(write_file("trunc.ply", hdr + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n"),
                   {"truncated", "face 2 of 4"});
    expect_refused(write_file("noheader.ply", "ply\nformat ascii 1.0\nelement vertex 4\n"), {"end_header"});
    expect_refused(write_file("notply.ply", "hello\n"), {"PLY"});
    const std::string facet =
        " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   vertex 1 0 0\n  endloop\n endfacet\n";
    expect_refused(write_file("trunc.stl", "solid t\n" + facet + " facet normal 0 0 0\n  outer loop\n"),
                   {"truncated"});
    expect_refused(write_file("nosolid.stl", "hello\n"), {"STL"});
}

// A vertex element without x, y or z, or a face element without its index list, is refused by
// name, in ASCII and in binary PLY (bodies complete, so that only the roles are wrong); with both,
// the same file is read (the same roles in both readers).
TEST(LoadMeshErrors, PlyElementsLackingTheirProperties) {
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const std::string format : {"ascii", "binary_little_endian"}) {
        const bool ascii = format == "ascii";
        const std::string tag = format.substr(0, 3);
        // The file with the vertices' first `coords` coordinates and the faces' list named `list`.
        auto ply = [&](int coords, const std::string& list) {
            std::string s = "ply\nformat " + format + " 1.0\nelement vertex 4\n";
            for (int c = 0; c < coords; ++c) s += std::string("property float ") + char('x' + c) + "\n";
            s += "element face 4\nproperty list uchar int " + list + "\nend_header\n";
            for (const auto& p : v) {
                for (int c = 0; c < coords; ++c)
                    if (ascii) s += std::to_string(int(p[c])) + (c + 1 < coords ? " " : "\n");
                    else s.append(reinterpret_cast<const char*>(&p[c]), sizeof p[c]);
            }
            for (const auto& t : f) {
                if (ascii) {
                    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
                } else {
                    s.push_back(char(3));
                    s.append(reinterpret_cast<const char*>(t), sizeof t);
                }
            }
            return s;
        };
        expect_refused(write_file("noz_" + tag + ".ply", ply(2, "vertex_indices")), {"vertex element lacks an x, y or z"});
        expect_refused(write_file("noidx_" + tag + ".ply", ply(3, "corners")), {"face element lacks a vertex_indices"});
        const std::string path = write_file("tet_" + tag + ".ply", ply(3, "vertex_indices"));
        const TriangleMesh m = inkline::load_mesh(path);
        EXPECT_EQ(m.positions.size(), 4u) << path;
        EXPECT_EQ(m.triangles.size(), 4u) << path;
    }
}

TEST(LoadMeshErrors, NanAndInfiniteCoordinates) {
    for (const char* bad : {"nan", "NaN", "inf", "-inf", "infinity", "1e999", "-1e400"}) {
        std::string off = off_file(kTetV, kTetF);
        off.replace(off.find("1 0 0"), 5, std::string("1 ") + bad + " 0");
        expect_refused(write_file(std::string("nan_") + bad + ".off", off), {"vertex 1", "NaN or infinite"});
        const std::string obj = std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 ") + bad +
                                "\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
        expect_refused(write_file(std::string("nan_") + bad + ".obj", obj), {"vertex 3", "NaN or infinite"});
    }
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\nnan 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    expect_refused(write_file("nan.ply", ply), {"vertex 2", "NaN or infinite"});
    auto facet = [](const std::string& a, const std::string& b, const std::string& c) {
        return " facet normal 0 0 0\n  outer loop\n   vertex " + a + "\n   vertex " + b + "\n   vertex " + c +
               "\n  endloop\n endfacet\n";
    };
    const std::string stl = "solid t\n" + facet("0 0 0", "0 1 0", "1 0 0") + facet("0 0 0", "1 0 0", "0 0 inf") +
                            facet("0 0 0", "0 0 inf", "0 1 0") + facet("1 0 0", "0 1 0", "0 0 inf") + "endsolid t\n";
    expect_refused(write_file("inf.stl", stl), {"NaN or infinite"});
}

TEST(LoadMeshErrors, NoFaces) {
    expect_refused(write_file("nofaces.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"), {"no faces"});
    expect_refused(write_file("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n# no f lines\n"), {"no faces"});
    expect_refused(write_file("nothing.obj", "# only a comment\n\n"), {"no faces"});
}

TEST(LoadMeshErrors, OutOfRangeIndex) {
    auto f = kTetF;
    f[1] = {0, 1, 7};
    expect_refused(write_file("oor.off", off_file(kTetV, f)), {"face 1", "refers to vertex 7 of 4"});
    f[1] = {0, 1, -1};
    expect_refused(write_file("negative.off", off_file(kTetV, f)), {"face 1", "refers to vertex -1 of 4"});
    f[1] = {0, 1, 4};  // one past the end
    expect_refused(write_file("past_end.off", off_file(kTetV, f)), {"face 1", "refers to vertex 4 of 4"});
    const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    expect_refused(write_file("oor.obj", v + "f 1 3 2\nf 1 2 9\n"), {"face 1", "refers to vertex 8 of 4"});
    // Relative index before the first vertex.
    expect_refused(write_file("oor_rel.obj", v + "f 1 3 2\nf -1 -2 -5\n"), {"face 1", "refers to vertex -1 of 4"});
}

// Strict loading refuses repeated indices (tolerant loading drops those faces: RepairedOnLoad).
const inkline::LoadOptions kStrict{.strict = true};

TEST(LoadMeshErrors, RepeatedIndex) {
    auto f = kTetF;
    f[2] = {0, 3, 3};
    expect_refused(write_file("rep.off", off_file(kTetV, f)), {"face 2", "repeats vertex index 3"}, kStrict);
    expect_refused(write_file("rep.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 2\n"),
                   {"face 1", "repeats vertex index 1"}, kStrict);
    // In a polygon: the repeat is reported for the input face, not a triangle of its fan.
    auto q = kCubeF;
    q[4] = {0, 4, 7, 4};
    expect_refused(write_file("rep_quad.off", off_file(kCubeV, q)), {"face 4", "repeats vertex index 4"}, kStrict);
    // In memory.
    TriangleMesh m;
    m.positions = kTetV;
    m.triangles = {{0, 2, 1}, {1, 1, 3}};
    try {
        inkline::validate_mesh(m, "memory");
        ADD_FAILURE() << "repeated index accepted";
    } catch (const inkline::Error& e) {
        EXPECT_TRUE(contains(e.what(), "memory: face 1 repeats a vertex index")) << e.what();
    }
}

TEST(LoadMeshErrors, NonManifoldEdge) {
    // A tetrahedron plus a fin on edge 0-1: three faces on that edge, one extra.
    auto v = kTetV;
    v.push_back({0.5, -1, 0.5});
    auto f = kTetF;
    f.push_back({0, 4, 1});
    std::string msg = load_error(write_file("fin.off", off_file(v, f)), kStrict);
    EXPECT_TRUE(contains(msg, "fin.off: non-manifold: 1 extra face(s)")) << msg;
    EXPECT_TRUE(contains(msg, "vertices 0-1")) << msg;
    // Two fins on two different edges: two extra faces.
    v.push_back({-1, 0.5, 0.5});
    f.push_back({0, 2, 5});
    msg = load_error(write_file("fins.off", off_file(v, f)), kStrict);
    EXPECT_TRUE(contains(msg, "fins.off: non-manifold: 2 extra face(s)")) << msg;
    // Four faces on one edge (two tetrahedra glued along an edge only): two extra faces.
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}};
    try {
        inkline::validate_mesh(m, "bowtie");
        ADD_FAILURE() << "four faces on one edge accepted";
    } catch (const inkline::Error& e) {
        EXPECT_TRUE(contains(e.what(), "bowtie: non-manifold: 2 extra face(s)")) << e.what();
    }
}

namespace {
// Moebius strip: n quads along a loop with a half twist, as OFF polygons.
std::string moebius_off(int n) {
    std::vector<glm::dvec3> v;
    for (int i = 0; i < n; ++i) {
        const double u = 2.0 * M_PI * i / n;
        for (double s : {-0.3, 0.3}) {
            const double r = 1.0 + s * std::cos(u / 2);
            v.push_back({r * std::cos(u), r * std::sin(u), s * std::sin(u / 2)});
        }
    }
    std::vector<std::vector<int>> f;
    for (int i = 0; i < n; ++i) {
        const int a = 2 * i, b = 2 * i + 1;
        // Across the seam the strip comes back flipped: the inner edge joins the outer one.
        const int c = i + 1 < n ? 2 * (i + 1) + 1 : 0, d = i + 1 < n ? 2 * (i + 1) : 1;
        f.push_back({a, b, c, d});
    }
    return off_file(v, f);
}
}  // namespace

// Strict loading refuses a surface that cannot be oriented; tolerant loading (the default) loads
// it with an orientation seam, named in its one warning line (tests/test_orientation.cpp draws them).
TEST(LoadMeshErrors, MoebiusStripIsNonOrientable) {
    expect_refused(write_file("moebius.off", moebius_off(12)), {"non-orientable"}, kStrict);
    expect_refused(write_file("moebius5.off", moebius_off(5)), {"non-orientable"}, kStrict);
    for (int n : {12, 5}) {
        const TriangleMesh m = inkline::load_mesh(write_file("moebius_t.off", moebius_off(n)));
        EXPECT_EQ(m.triangles.size(), 2u * n) << n;  // each quad in two triangles
        EXPECT_EQ(m.repairs.nonorientable_parts, 1u) << n;
        EXPECT_GT(m.repairs.orientation_seam_edges, 0u) << n;
        const auto w = m.repairs.warnings("moebius_t.off");
        ASSERT_EQ(w.size(), 1u) << n;
        EXPECT_TRUE(contains(w[0], "cannot be oriented")) << w[0];
        const inkline::MeshTopology t = inkline::build_topology(m);
        EXPECT_EQ(t.seam_list.size(), m.repairs.orientation_seam_edges) << n;
        EXPECT_EQ(t.border_list.size(), 2u * n) << n;  // one border loop, twice round
    }
}

TEST(LoadMeshErrors, ClosedStripWithoutTwistIsFine) {
    // The same band without the half twist (an annulus) is orientable and has two border loops.
    std::vector<glm::dvec3> v;
    const int n = 8;
    for (int i = 0; i < n; ++i)
        for (double s : {-0.3, 0.3}) v.push_back({(1 + s) * std::cos(2 * M_PI * i / n), (1 + s) * std::sin(2 * M_PI * i / n), 0});
    std::vector<std::vector<int>> f;
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        // Every other quad written the wrong way round.
        if (i % 2) f.push_back({2 * i, 2 * i + 1, 2 * j + 1, 2 * j});
        else f.push_back({2 * i, 2 * j, 2 * j + 1, 2 * i + 1});
    }
    const TriangleMesh m = inkline::load_mesh(write_file("annulus.off", off_file(v, f)));
    EXPECT_EQ(m.triangles.size(), 16u);
    EXPECT_EQ(m.polygons_triangulated, 8u);
    EXPECT_EQ(m.faces_reoriented, 8u);  // one of the two halves (open surface: no outward rule)
    expect_consistent(m);
    const MeshTopology t = inkline::build_topology(m);
    EXPECT_FALSE(t.closed);
    std::size_t border = 0;
    for (std::size_t e = 0; e < t.edge_count(); ++e) border += t.is_border(std::uint32_t(e));
    EXPECT_EQ(border, 16u);
}

// =============================================================================================
// Successful loads

TEST(LoadMesh, OffTetrahedron) {
    const TriangleMesh m = inkline::load_mesh(write_file("tet.off", off_file(kTetV, kTetF)));
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.polygons_triangulated, 0u);
    EXPECT_EQ(m.faces_reoriented, 0u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(m.positions[i], kTetV[i]);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0);
}

TEST(LoadMesh, OffVariantsAndComments) {
    // Comments anywhere, counts on the header line, COFF colours, face colours, CRLF, blank lines,
    // full double precision.
    const std::string text =
        "# a comment before the header\r\nCOFF 4 4 6 # counts on the header line\r\n\r\n"
        "0 0 0 1 0 0 1\n1 0 0 0 1 0 1 # red\n0 1 0 0 0 1 1\n0.1000000000000000055511151231257827 0 1 1 1 1 1\n"
        "# faces\n3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2 0.5 0.5 0.5 1\n3 1 2 3\n";
    const TriangleMesh m = inkline::load_mesh(write_file("coff.off", text));
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.positions[3], glm::dvec3(0.1, 0, 1));  // not rounded to float
    EXPECT_GT(signed_volume(m), 0.0);
    // 4OFF: homogeneous coordinates.
    const TriangleMesh h = inkline::load_mesh(write_file(
        "homog.off", "4OFF\n4 4 0\n0 0 0 2\n2 0 0 2\n0 4 0 4\n0 0 3 3\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(h.positions[i], kTetV[i]);
}

TEST(LoadMesh, ObjCubeOfQuads) {
    std::ostringstream s;
    s << "# cube\nmtllib none.mtl\no cube\n";
    for (const auto& p : kCubeV) s << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
    s << "vt 0 0\nvn 0 0 1\ng sides\nusemtl x\ns off\n";
    for (std::size_t i = 0; i < kCubeF.size(); ++i) {
        s << 'f';
        for (int k : kCubeF[i]) {
            // All index forms: v, v/vt, v//vn, v/vt/vn, and negative (relative) indices.
            if (i == 1) s << ' ' << k + 1 << "/1";
            else if (i == 2) s << ' ' << k + 1 << "//1";
            else if (i == 3) s << ' ' << k + 1 << "/1/1";
            else if (i == 4) s << ' ' << k - 8;
            else s << ' ' << k + 1;
        }
        s << '\n';
    }
    const TriangleMesh m = inkline::load_mesh(write_file("cube.obj", s.str()));
    EXPECT_EQ(m.positions.size(), 8u);
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_EQ(m.polygons_triangulated, 6u);
    EXPECT_EQ(m.faces_reoriented, 0u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0);
    expect_consistent(m);
}

TEST(LoadMesh, OffQuadsAndPentagon) {
    // A cube with its quads, and a pentagonal prism: polygons are counted and fanned.
    const TriangleMesh cube = inkline::load_mesh(write_file("cube.off", off_file(kCubeV, kCubeF)));
    EXPECT_EQ(cube.triangles.size(), 12u);
    EXPECT_EQ(cube.polygons_triangulated, 6u);
    EXPECT_DOUBLE_EQ(signed_volume(cube), 1.0);
    std::vector<glm::dvec3> v;
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i < 5; ++i) v.push_back({std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5), double(z)});
    std::vector<std::vector<int>> f = {{4, 3, 2, 1, 0}, {5, 6, 7, 8, 9}};
    for (int i = 0; i < 5; ++i) f.push_back({i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i});
    const TriangleMesh prism = inkline::load_mesh(write_file("prism.off", off_file(v, f)));
    EXPECT_EQ(prism.positions.size(), 10u);
    EXPECT_EQ(prism.triangles.size(), 3u + 3u + 10u);
    EXPECT_EQ(prism.polygons_triangulated, 7u);
    EXPECT_GT(signed_volume(prism), 0.0);
}

TEST(LoadMesh, PlyAscii) {
    // Extra vertex and face properties and an extra element are skipped.
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty double x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty list uchar float extra\n"
        "element face 4\nproperty int flags\nproperty list uchar int vertex_indices\nproperty float quality\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        "0 0 0 255 0\n1 0 0 1 2 0.5 0.25\n0 1 0 7 1 3\n0 0 1 8 0\n"
        "9 3 0 2 1 0.5\n9 3 0 1 3 0.5\n9 3 0 3 2 0.5\n9 3 1 2 3 0.5\n0 1\n";
    const TriangleMesh m = inkline::load_mesh(write_file("tet.ply", ply));
    ASSERT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(m.positions[i], kTetV[i]);
    EXPECT_EQ(m.faces_reoriented, 0u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0);
}

TEST(LoadMesh, PlyBinary) {
    // Little-endian binary PLY (read by OpenMesh); a NaN in it is refused like any other.
    auto make = [](float bad) {
        std::string ply =
            "ply\nformat binary_little_endian 1.0\ncomment binary\nelement vertex 4\nproperty float x\n"
            "property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\n"
            "end_header\n";
        for (std::size_t i = 0; i < kTetV.size(); ++i) {
            float p[3] = {float(kTetV[i].x), float(kTetV[i].y), float(kTetV[i].z)};
            if (i == 2) p[0] = bad;
            ply.append(reinterpret_cast<const char*>(p), sizeof p);
        }
        for (const auto& f : kTetF) {
            ply.push_back(char(3));
            for (int k : f) {
                const std::int32_t v = k;
                ply.append(reinterpret_cast<const char*>(&v), 4);
            }
        }
        return ply;
    };
    const TriangleMesh m = inkline::load_mesh(write_file("tet_bin.ply", make(0.0f)));
    EXPECT_EQ(m.positions.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0);
    expect_refused(write_file("nan_bin.ply", make(std::nanf(""))), {"vertex 2", "NaN or infinite"});
}

TEST(LoadMesh, StlAsciiAndBinary) {
    // Each facet repeats its corners; identical corners are welded into 4 vertices.
    auto facet = [](int a, int b, int c) {
        std::ostringstream s;
        s << "  FACET NORMAL 0 0 0\n    outer loop\n";
        for (int i : {a, b, c}) s << "      vertex " << kTetV[i].x << ' ' << kTetV[i].y << ' ' << kTetV[i].z << '\n';
        s << "    endloop\n  endfacet\n";
        return s.str();
    };
    std::string stl = "solid tet\n";
    for (const auto& f : kTetF) stl += facet(f[0], f[1], f[2]);
    stl += "endsolid tet\n";
    const TriangleMesh a = inkline::load_mesh(write_file("tet.stl", stl));
    EXPECT_EQ(a.positions.size(), 4u);
    EXPECT_EQ(a.triangles.size(), 4u);
    EXPECT_DOUBLE_EQ(signed_volume(a), 1.0 / 6.0);

    // Binary: 80-byte header (starting with "solid", which must not fool the reader), count, records.
    std::string bin(80, ' ');
    bin.replace(0, 5, "solid");
    const std::uint32_t n = 4;
    bin.append(reinterpret_cast<const char*>(&n), 4);
    for (const auto& f : kTetF) {
        float rec[12] = {};
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) rec[3 + 3 * c + k] = float(kTetV[f[c]][k]);
        bin.append(reinterpret_cast<const char*>(rec), sizeof rec);
        bin.append(2, '\0');
    }
    ASSERT_EQ(bin.size(), 84u + 50u * 4u);
    const TriangleMesh b = inkline::load_mesh(write_file("tet_bin.stl", bin));
    EXPECT_EQ(b.positions.size(), 4u);
    EXPECT_EQ(b.triangles.size(), 4u);
    EXPECT_DOUBLE_EQ(signed_volume(b), 1.0 / 6.0);
    // A binary file cut short is refused.
    expect_refused(write_file("tet_cut.stl", bin.substr(0, bin.size() - 10)), {"truncated", "84 + 50"});
}

TEST(LoadMesh, InconsistentFacesAreReoriented) {
    // One face of the tetrahedron written the wrong way round: exactly one face is flipped,
    // whichever face the orientation search starts from.
    for (std::size_t bad = 0; bad < kTetF.size(); ++bad) {
        auto f = kTetF;
        std::swap(f[bad][1], f[bad][2]);
        const TriangleMesh m =
            inkline::load_mesh(write_file("tet_bad" + std::to_string(bad) + ".off", off_file(kTetV, f)));
        EXPECT_EQ(m.faces_reoriented, 1u) << "bad face " << bad;
        EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0) << "bad face " << bad;
        expect_consistent(m);
    }
    // One quad of the cube reversed: its two triangles are flipped.
    for (std::size_t bad = 0; bad < kCubeF.size(); ++bad) {
        auto f = kCubeF;
        std::reverse(f[bad].begin(), f[bad].end());
        const TriangleMesh m =
            inkline::load_mesh(write_file("cube_bad" + std::to_string(bad) + ".off", off_file(kCubeV, f)));
        EXPECT_EQ(m.faces_reoriented, 2u) << "bad face " << bad;
        EXPECT_DOUBLE_EQ(signed_volume(m), 1.0) << "bad face " << bad;
        expect_consistent(m);
    }
}

TEST(LoadMesh, InwardClosedMeshIsTurnedOutward) {
    auto f = kTetF;
    for (auto& face : f) std::swap(face[1], face[2]);
    const TriangleMesh m = inkline::load_mesh(write_file("tet_inward.off", off_file(kTetV, f)));
    EXPECT_EQ(m.faces_reoriented, 4u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 1.0 / 6.0);
    // Two closed components, one inward and one outward, far apart: each is turned outward.
    TriangleMesh two;
    two.positions = kTetV;
    for (const auto& p : kTetV) two.positions.push_back(p + glm::dvec3(10, 0, 0));
    for (const auto& t : kTetF) two.triangles.push_back({std::uint32_t(t[0]), std::uint32_t(t[2]), std::uint32_t(t[1])});
    for (const auto& t : kTetF) two.triangles.push_back({std::uint32_t(t[0] + 4), std::uint32_t(t[1] + 4), std::uint32_t(t[2] + 4)});
    inkline::validate_mesh(two, "two tetrahedra");
    EXPECT_EQ(two.faces_reoriented, 4u);
    for (int c = 0; c < 2; ++c) {
        TriangleMesh part;
        part.positions = two.positions;
        part.triangles.assign(two.triangles.begin() + 4 * c, two.triangles.begin() + 4 * c + 4);
        EXPECT_DOUBLE_EQ(signed_volume(part), 1.0 / 6.0) << "component " << c;
    }
}

// Windings already consistent take orient's quick path (its parts found in corner order); one
// bad face sends the mesh through the search. Both must give each part its own outward turn: here
// three tetrahedra whose faces are interleaved in the file, the middle one wound inward, and the
// third open (one face left out: no outward rule).
TEST(LoadMesh, InterleavedPartsAreEachTurnedOutwardOnTheirOwn) {
    for (bool one_bad_face : {false, true}) {
        TriangleMesh m;
        for (int part = 0; part < 3; ++part)
            for (const auto& p : kTetV) m.positions.push_back(p + glm::dvec3(10.0 * part, 0, 0));
        for (int k = 0; k < 4; ++k)
            for (std::uint32_t part = 0; part < 3; ++part) {
                if (part == 2 && k == 3) continue;
                const auto& t = kTetF[std::size_t(k)];
                std::array<std::uint32_t, 3> face = {std::uint32_t(t[0]) + 4 * part, std::uint32_t(t[1]) + 4 * part,
                                                     std::uint32_t(t[2]) + 4 * part};
                if (part == 1) std::swap(face[1], face[2]);            // the inward part
                if (one_bad_face && part == 0 && k == 2) std::swap(face[1], face[2]);
                m.triangles.push_back(face);
            }
        inkline::validate_mesh(m, "three tetrahedra");
        // Inward: its 4 faces; the bad face: itself; the open part: kept as it is.
        EXPECT_EQ(m.faces_reoriented, one_bad_face ? 5u : 4u);
        EXPECT_EQ(m.repairs.components_reoriented, one_bad_face ? 1u : 0u);
        expect_consistent(m);
        for (std::uint32_t part = 0; part < 2; ++part) {
            TriangleMesh closed;
            closed.positions = m.positions;
            for (const auto& t : m.triangles)
                if (t[0] / 4 == part) closed.triangles.push_back(t);
            EXPECT_DOUBLE_EQ(signed_volume(closed), 1.0 / 6.0) << "part " << part << (one_bad_face ? ", one bad face" : "");
        }
    }
}

TEST(LoadMesh, PrimitivesAreValidAndOutward) {
    const TriangleMesh box = inkline::make_box({-1, -2, -3}, {1, 2, 3});
    EXPECT_DOUBLE_EQ(signed_volume(box), 2.0 * 4.0 * 6.0);
    const TriangleMesh sphere = inkline::make_sphere({0, 0, 0}, 1.0, 24, 12);
    EXPECT_GT(signed_volume(sphere), 0.9 * 4.0 / 3.0 * M_PI);
    EXPECT_LT(signed_volume(sphere), 4.0 / 3.0 * M_PI);
    const TriangleMesh torus = inkline::make_torus({0, 0, 0}, {0, 0, 1}, 2.0, 0.5, 32, 16);
    EXPECT_GT(signed_volume(torus), 0.9 * 2 * M_PI * M_PI * 2.0 * 0.25);
    for (const TriangleMesh* m : {&box, &sphere, &torus}) {
        EXPECT_EQ(m->faces_reoriented, 0u);
        expect_consistent(*m);
    }
}

// =============================================================================================
// Topology

namespace {
std::size_t count_flag(const MeshTopology& t, std::uint8_t flag) {
    std::size_t n = 0;
    for (auto f : t.edge_flags) n += (f & flag) ? 1 : 0;
    return n;
}

// Structural invariants every topology must satisfy.
void expect_well_formed(const MeshTopology& t) {
    const std::size_t nv = t.vertex_count(), nf = t.face_count(), ne = t.edge_count();
    ASSERT_EQ(t.face_edges.size(), nf);
    ASSERT_EQ(t.facing.size(), nf);
    ASSERT_EQ(t.edge_face.size(), ne);
    ASSERT_EQ(t.edge_flags.size(), ne);
    ASSERT_EQ(t.edge_normal_angle.size(), ne);
    // Euler: every face has 3 edges; every interior edge 2 faces, border edges 1.
    std::size_t border = 0;
    for (std::uint32_t e = 0; e < ne; ++e) border += t.edge_face[e][1] == inkline::kNoFace;
    EXPECT_EQ(3 * nf, 2 * ne - border);
    EXPECT_EQ(t.closed, border == 0);

    for (std::uint32_t e = 0; e < ne; ++e) {
        const auto [a, b] = t.edge_vertex[e];
        ASSERT_NE(a, b);
        // Face 0 traverses a -> b, face 1 (if any) b -> a.
        auto traverses = [&](std::uint32_t f, std::uint32_t x, std::uint32_t y) {
            for (int k = 0; k < 3; ++k)
                if (t.faces[f][k] == x && t.faces[f][(k + 1) % 3] == y) return true;
            return false;
        };
        EXPECT_TRUE(traverses(t.edge_face[e][0], a, b)) << "edge " << e;
        if (t.edge_face[e][1] != inkline::kNoFace) {
            EXPECT_TRUE(traverses(t.edge_face[e][1], b, a)) << "edge " << e;
            EXPECT_FALSE(t.is_border(e));
        } else {
            EXPECT_TRUE(t.is_border(e));
            EXPECT_FALSE(t.is_crease(e));
            EXPECT_FALSE(t.edge_flags[e] & (inkline::kEdgeConvex | inkline::kEdgeConcave));
        }
        EXPECT_FALSE((t.edge_flags[e] & inkline::kEdgeConvex) && (t.edge_flags[e] & inkline::kEdgeConcave));
    }
    // Face -> edge: edge of corner k joins corners k and k+1.
    for (std::uint32_t f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) {
            const auto e = t.face_edges[f].edge[k];
            ASSERT_LT(e, ne);
            const std::set<std::uint32_t> ends = {t.edge_vertex[e][0], t.edge_vertex[e][1]};
            EXPECT_EQ(ends, (std::set<std::uint32_t>{t.faces[f][k], t.faces[f][(k + 1) % 3]}));
            EXPECT_TRUE(t.edge_face[e][0] == f || t.edge_face[e][1] == f);
            // The face across it: the edge's other face.
            EXPECT_EQ(t.face_edges[f].face[k], t.edge_face[e][0] == f ? t.edge_face[e][1] : t.edge_face[e][0]);
            // Unit normal, plane through the corners.
            EXPECT_NEAR(glm::length(t.face_normal(f)), 1.0, 1e-12);
            EXPECT_NEAR(glm::dot(t.face_normal(f), t.positions[t.faces[f][k]]),
                        glm::dot(t.face_normal(f), t.positions[t.faces[f][0]]),
                        1e-12 * (1.0 + glm::length(t.positions[t.faces[f][k]])));
        }
    // Vertex -> edge CSR: each edge listed exactly once under each of its two vertices.
    ASSERT_EQ(t.vertex_edge_begin.size(), nv + 1);
    EXPECT_EQ(t.vertex_edge_begin[0], 0u);
    EXPECT_EQ(t.vertex_edge_begin[nv], 2 * ne);
    EXPECT_EQ(t.vertex_edges.size(), 2 * ne);
    std::vector<int> seen(ne, 0);
    for (std::uint32_t v = 0; v < nv; ++v) {
        ASSERT_LE(t.vertex_edge_begin[v], t.vertex_edge_begin[v + 1]);
        std::set<std::uint32_t> here;
        for (auto k = t.vertex_edge_begin[v]; k < t.vertex_edge_begin[v + 1]; ++k) {
            const auto e = t.vertex_edges[k];
            ASSERT_LT(e, ne);
            EXPECT_TRUE(t.edge_vertex[e][0] == v || t.edge_vertex[e][1] == v) << "vertex " << v << " edge " << e;
            EXPECT_TRUE(here.insert(e).second) << "edge " << e << " listed twice at vertex " << v;
            ++seen[e];
        }
    }
    for (std::uint32_t e = 0; e < ne; ++e) EXPECT_EQ(seen[e], 2) << "edge " << e;
    // Bounds.
    for (const auto& p : t.positions) {
        EXPECT_LE(t.bounds.lo.x, p.x);
        EXPECT_GE(t.bounds.hi.z, p.z);
    }
}
}  // namespace

TEST(Topology, Box) {
    const MeshTopology t = inkline::build_topology(inkline::make_box({0, 0, 0}, {1, 2, 3}));
    expect_well_formed(t);
    EXPECT_EQ(t.vertex_count(), 8u);
    EXPECT_EQ(t.face_count(), 12u);
    EXPECT_EQ(t.edge_count(), 18u);
    EXPECT_TRUE(t.closed);
    EXPECT_DOUBLE_EQ(t.crease_degrees, 40.0);
    EXPECT_EQ(t.bounds.lo, glm::dvec3(0, 0, 0));
    EXPECT_EQ(t.bounds.hi, glm::dvec3(1, 2, 3));
    std::size_t box_edges = 0, diagonals = 0;
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
        const glm::dvec3 d = t.positions[t.edge_vertex[e][1]] - t.positions[t.edge_vertex[e][0]];
        const int axes = (d.x != 0) + (d.y != 0) + (d.z != 0);
        if (axes == 1) {  // an edge of the box
            ++box_edges;
            EXPECT_TRUE(t.is_crease(e)) << e;
            EXPECT_TRUE(t.is_convex(e)) << e;
            EXPECT_FALSE(t.edge_flags[e] & inkline::kEdgeConcave) << e;
            EXPECT_NEAR(t.edge_normal_angle[e], M_PI / 2, 1e-6) << e;
        } else {  // a diagonal of a side: coplanar faces
            ++diagonals;
            EXPECT_EQ(axes, 2);
            EXPECT_EQ(t.edge_flags[e], 0) << e;
            EXPECT_EQ(t.edge_normal_angle[e], 0.0f) << e;
        }
    }
    EXPECT_EQ(box_edges, 12u);
    EXPECT_EQ(diagonals, 6u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 12u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeConvex), 12u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeConcave), 0u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeBorder), 0u);
    // Outward normals: each face normal points away from the centre.
    for (std::uint32_t f = 0; f < t.face_count(); ++f) {
        glm::dvec3 c(0.0);
        for (auto v : t.faces[f]) c += t.positions[v] / 3.0;
        EXPECT_GT(glm::dot(t.face_normal(f), c - glm::dvec3(0.5, 1, 1.5)), 0.0) << f;
    }
}

TEST(Topology, CreaseThreshold) {
    MeshTopology t = inkline::build_topology(inkline::make_box({0, 0, 0}, {1, 1, 1}));
    t.set_crease_angle(100.0);
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 0u);
    EXPECT_DOUBLE_EQ(t.crease_degrees, 100.0);
    EXPECT_EQ(count_flag(t, inkline::kEdgeConvex), 12u);  // convexity does not depend on it
    t.set_crease_angle(89.0);
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 12u);
    t.set_crease_angle(0.0);  // every non-flat edge
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 12u);
    const MeshTopology u = inkline::build_topology(inkline::make_box({0, 0, 0}, {1, 1, 1}), 95.0);
    EXPECT_EQ(count_flag(u, inkline::kEdgeCrease), 0u);
    // A sphere: neighbouring faces differ by a few degrees; a small threshold creases everything.
    MeshTopology s = inkline::build_topology(inkline::make_sphere({0, 0, 0}, 1, 16, 8));
    EXPECT_EQ(count_flag(s, inkline::kEdgeCrease), 0u);
    // Convex, except the diagonals of the (planar, trapezoidal) quads, flat up to rounding.
    for (std::uint32_t e = 0; e < s.edge_count(); ++e)
        if (!s.is_convex(e)) {
            EXPECT_LT(s.edge_normal_angle[e], 1e-6f) << e;
        }
    EXPECT_GE(count_flag(s, inkline::kEdgeConvex), s.edge_count() - 16 * 6);
    s.set_crease_angle(1.0);
    EXPECT_GT(count_flag(s, inkline::kEdgeCrease), s.edge_count() / 2);
}

TEST(Topology, SheetHasBorder) {
    for (int n : {1, 2, 5}) {
        const MeshTopology t = inkline::build_topology(inkline::make_sheet(1.0, 0.25, n));
        expect_well_formed(t);
        EXPECT_FALSE(t.closed);
        EXPECT_EQ(t.vertex_count(), std::size_t((n + 1) * (n + 1)));
        EXPECT_EQ(t.face_count(), std::size_t(2 * n * n));
        EXPECT_EQ(t.edge_count(), std::size_t(2 * n * (n + 1) + n * n));
        EXPECT_EQ(count_flag(t, inkline::kEdgeBorder), std::size_t(4 * n));
        EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 0u);
        // Flat: no edge is convex or concave (the exact test sees coplanar faces).
        EXPECT_EQ(count_flag(t, inkline::kEdgeConvex | inkline::kEdgeConcave), 0u);
        for (std::uint32_t e = 0; e < t.edge_count(); ++e)
            if (t.is_border(e)) {
                const auto p = t.positions[t.edge_vertex[e][0]], q = t.positions[t.edge_vertex[e][1]];
                const bool on_rim = (std::abs(p.x) == 1.0 && p.x == q.x) || (std::abs(p.z) == 1.0 && p.z == q.z);
                EXPECT_TRUE(on_rim) << "border edge " << e << " is not on the rim";
            }
    }
}

TEST(Topology, ValleyIsConcaveRidgeIsConvex) {
    // Two faces on the edge A-B (along z), normals up (+y): a V-shaped valley, then with the
    // outer corners lowered, a ridge.
    for (const double side : {1.0, -1.0}) {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {0, 0, 1}, {-1, side, 0.5}, {1, side, 0.5}};
        m.triangles = {{0, 2, 1}, {0, 1, 3}};
        inkline::validate_mesh(m, "hinge");
        const MeshTopology t = inkline::build_topology(m);
        expect_well_formed(t);
        std::uint32_t hinge = UINT32_MAX;
        for (std::uint32_t e = 0; e < t.edge_count(); ++e)
            if (!t.is_border(e)) hinge = e;
        ASSERT_NE(hinge, UINT32_MAX);
        EXPECT_NEAR(t.edge_normal_angle[hinge], M_PI / 2, 1e-6);
        EXPECT_TRUE(t.is_crease(hinge));
        EXPECT_EQ(t.face_normal(0).y > 0, true);
        EXPECT_EQ(t.face_normal(1).y > 0, true);
        if (side > 0) {  // normals (1,1,0) and (-1,1,0) point towards each other: valley
            EXPECT_EQ(t.edge_flags[hinge], inkline::kEdgeCrease | inkline::kEdgeConcave);
        } else {
            EXPECT_EQ(t.edge_flags[hinge], inkline::kEdgeCrease | inkline::kEdgeConvex);
        }
    }
}

TEST(Topology, LShapedPrismHasOneConcaveEdge) {
    // L-shaped cross-section extruded along z, written with caps as hexagons (fanned from the
    // reflex corner) and every face oriented inward: the loader turns all 20 triangles outward.
    const double L[6][2] = {{1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}, {2, 1}};  // counter-clockwise from the reflex corner
    std::vector<glm::dvec3> v;
    for (int z = 0; z < 2; ++z)
        for (const auto& p : L) v.push_back({p[0], p[1], double(z)});
    std::vector<std::vector<int>> f;
    f.push_back({0, 1, 2, 3, 4, 5});  // bottom (z = 0) counter-clockwise seen from above: inward
    f.push_back({6, 11, 10, 9, 8, 7});  // top clockwise seen from above: inward
    for (int i = 0; i < 6; ++i) {
        const int j = (i + 1) % 6;
        f.push_back({i, 6 + i, 6 + j, j});  // inward
    }
    const TriangleMesh m = inkline::load_mesh(write_file("lprism.off", off_file(v, f)));
    EXPECT_EQ(m.positions.size(), 12u);
    EXPECT_EQ(m.triangles.size(), 20u);
    EXPECT_EQ(m.polygons_triangulated, 8u);
    EXPECT_EQ(m.faces_reoriented, 20u);
    EXPECT_DOUBLE_EQ(signed_volume(m), 3.0);
    const MeshTopology t = inkline::build_topology(m);
    expect_well_formed(t);
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.edge_count(), 30u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeConcave), 1u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeConvex), 17u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 18u);
    for (std::uint32_t e = 0; e < t.edge_count(); ++e)
        if (t.edge_flags[e] & inkline::kEdgeConcave) {
            // The vertical edge at the reflex corner (1, 1).
            const auto p = t.positions[t.edge_vertex[e][0]], q = t.positions[t.edge_vertex[e][1]];
            EXPECT_EQ(glm::dvec2(p.x, p.y), glm::dvec2(1, 1));
            EXPECT_EQ(glm::dvec2(q.x, q.y), glm::dvec2(1, 1));
            EXPECT_TRUE(t.is_crease(e));
            EXPECT_FALSE(t.is_convex(e));
        }
}

TEST(Topology, TorusHasConvexAndConcaveEdges) {
    // The outer half of a torus is convex, the inner half saddle-shaped: both kinds appear, and
    // every closed-surface invariant holds.
    const MeshTopology t = inkline::build_topology(inkline::make_torus({0, 0, 0}, {0, 1, 0}, 2.0, 0.6, 24, 12));
    expect_well_formed(t);
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.vertex_count(), 24u * 12u);
    EXPECT_EQ(t.edge_count(), 3u * 24u * 12u);  // Euler characteristic 0
    EXPECT_GT(count_flag(t, inkline::kEdgeConcave), 0u);
    EXPECT_GT(count_flag(t, inkline::kEdgeConvex), count_flag(t, inkline::kEdgeConcave));
    // Concave edges only on the inner half (distance to the axis below R).
    for (std::uint32_t e = 0; e < t.edge_count(); ++e)
        if ((t.edge_flags[e] & inkline::kEdgeConcave) && t.edge_normal_angle[e] > 1e-6f) {
            // (Quad diagonals are flat up to rounding and may go either way.)
            const glm::dvec3 m = 0.5 * (t.positions[t.edge_vertex[e][0]] + t.positions[t.edge_vertex[e][1]]);
            EXPECT_LT(std::hypot(m.x, m.z), 2.0) << e;
        }
}

TEST(Topology, FandiskFromDataDir) {
    const std::string path = inkline::test::mesh_path("fandisk");
    if (!fs::exists(path)) GTEST_SKIP() << path << " not found (run scripts/setup.sh)";
    const TriangleMesh m = inkline::load_mesh(path);
    // Header: "OFF / 6475 12946 0", all triangles, a closed genus-0 surface.
    EXPECT_EQ(m.positions.size(), 6475u);
    EXPECT_EQ(m.triangles.size(), 12946u);
    EXPECT_EQ(m.polygons_triangulated, 0u);
    EXPECT_GT(signed_volume(m), 0.0);
    const MeshTopology t = inkline::build_topology(m);
    expect_well_formed(t);
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.edge_count(), 6475u + 12946u - 2u);
    EXPECT_GT(count_flag(t, inkline::kEdgeCrease), 0u);   // the fan disk has sharp features
    EXPECT_GT(count_flag(t, inkline::kEdgeConcave), 0u);  // and concave ones
}

TEST(Topology, MergedMeshesKeepComponentsApart) {
    const TriangleMesh m = inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                 inkline::make_sheet(1.0, 5.0, 3));
    const MeshTopology t = inkline::build_topology(m);
    expect_well_formed(t);
    EXPECT_FALSE(t.closed);
    EXPECT_EQ(t.vertex_count(), 8u + 16u);
    EXPECT_EQ(t.edge_count(), 18u + 33u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeBorder), 12u);
    EXPECT_EQ(count_flag(t, inkline::kEdgeCrease), 12u);
}

// Where edges meet other faces (model/self_intersections.hpp): none on an embedded surface; a
// point where an edge passes through a face; the ends of the stretch where an edge lies on another
// face (touching boxes).
namespace {
glm::dvec3 cut_point(const MeshTopology& t, const inkline::EdgeCut& c) {
    const glm::dvec3 a = t.positions[t.edge_vertex[c.edge][0]], b = t.positions[t.edge_vertex[c.edge][1]];
    return a + c.s * (b - a);
}
}  // namespace

TEST(SelfIntersections, CutsWhereEdgesMeetOtherFaces) {
    const MeshTopology fandisk = inkline::build_topology(inkline::load_mesh(inkline::test::mesh_path("fandisk")));
    const inkline::SelfIntersections none = inkline::self_intersections(fandisk);
    EXPECT_TRUE(none.cuts.empty());
    EXPECT_EQ(std::count(none.faces.begin(), none.faces.end(), 1), 0);

    // A box pierced by a thin box: the thin box's four long edges (along x) pass through the
    // big box's sides x = 0 and x = 1 (at y, z inside them): one cut each at x = 0 and x = 1.
    const MeshTopology pierced = inkline::build_topology(inkline::merge_meshes(
        inkline::make_box({0, 0, 0}, {1, 1, 1}), inkline::make_box({-1, 0.4, 0.3}, {2, 0.6, 0.7})));
    const inkline::SelfIntersections si = inkline::self_intersections(pierced);
    EXPECT_TRUE(std::is_sorted(si.cuts.begin(), si.cuts.end()));
    int at0 = 0, at1 = 0;
    for (const auto& c : si.cuts) {
        const glm::dvec3 p = cut_point(pierced, c);
        EXPECT_TRUE(c.s > 0.0 && c.s < 1.0) << c.s;
        if (std::abs(p.x) < 1e-12) ++at0;
        if (std::abs(p.x - 1.0) < 1e-12) ++at1;
        // Every cut is on the big box's sides or on the thin box's long edges where they meet.
        EXPECT_TRUE(std::abs(p.x) < 1e-12 || std::abs(p.x - 1.0) < 1e-12) << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_GE(at0, 4);
    EXPECT_GE(at1, 4);
    EXPECT_GT(std::count(si.faces.begin(), si.faces.end(), 1), 0);

    // Touching boxes (tests/test_extremes.cpp TouchingBoxesSharingAFace): the second box's edge
    // x = 1, z = 0.7 (y from 0 to 1.5) lies on the first box's side x = 1 for y in [0, 1]: a cut
    // at y = 1, where it leaves that side.
    const MeshTopology touching = inkline::build_topology(inkline::merge_meshes(
        inkline::make_box({0, 0, 0}, {1, 1, 1}), inkline::make_box({1, 0, 0}, {2, 1.5, 0.7})));
    const inkline::SelfIntersections st = inkline::self_intersections(touching);
    bool leaves = false;
    for (const auto& c : st.cuts) {
        const glm::dvec3 a = touching.positions[touching.edge_vertex[c.edge][0]];
        const glm::dvec3 b = touching.positions[touching.edge_vertex[c.edge][1]];
        const glm::dvec3 p = cut_point(touching, c);
        if (a.x == 1 && b.x == 1 && a.z == 0.7 && b.z == 0.7 && std::abs(p.y - 1.0) < 1e-12) leaves = true;
    }
    EXPECT_TRUE(leaves);
}

// Loop subdivision (OpenMesh): each level quadruples the triangles of a closed mesh, keeps it
// closed and outward, and moves vertices toward a smooth limit (a subdivided box shrinks inside).
TEST(Subdivide, LoopQuadruplesAndSmooths) {
    const inkline::TriangleMesh box = inkline::make_box({-1, -1, -1}, {1, 1, 1});
    const inkline::TriangleMesh s1 = inkline::subdivide_loop(box, 1), s2 = inkline::subdivide_loop(box, 2);
    EXPECT_EQ(s1.triangles.size(), 4 * box.triangles.size());
    EXPECT_EQ(s2.triangles.size(), 16 * box.triangles.size());
    const inkline::MeshTopology t = inkline::build_topology(s2);
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.vertex_count() - t.edge_count() + t.face_count(), 2u);  // still a sphere
    for (const auto& p : s2.positions) EXPECT_LT(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 1.0);
    EXPECT_EQ(inkline::subdivide_loop(box, 0).triangles.size(), box.triangles.size());
}

// =============================================================================================
// Tolerant loading: repairs, each counted

// Each side of a cube with its own four corners (as a UV or normal seam splits them): welded into a
// closed cube, the same triangles as the welded file.
TEST(RepairedOnLoad, CubeSplitPerFaceIsWelded) {
    std::vector<glm::dvec3> v;
    std::vector<std::vector<int>> f;
    for (const auto& q : kCubeF) {
        std::vector<int> face;
        for (int i : q) {
            face.push_back(int(v.size()));
            v.push_back(kCubeV[std::size_t(i)]);
        }
        f.push_back(face);
    }
    const std::string path = write_file("split_cube.off", off_file(v, f));
    const TriangleMesh m = inkline::load_mesh(path);
    EXPECT_EQ(m.repairs.vertices_welded, 16u);  // 24 corners at 8 positions
    EXPECT_EQ(m.positions.size(), 8u);
    EXPECT_EQ(m.triangles.size(), 12u);
    const MeshTopology t = inkline::build_topology(m);
    EXPECT_TRUE(t.closed);
    EXPECT_EQ(t.edge_count(), 18u);
    EXPECT_NEAR(signed_volume(m), 1.0, 1e-12);
    // Strict loading is the loading of before: six separate squares.
    const TriangleMesh s = inkline::load_mesh(path, {.strict = true});
    EXPECT_EQ(s.repairs.vertices_welded, 0u);
    EXPECT_EQ(s.positions.size(), 24u);
    EXPECT_EQ(inkline::build_topology(s).border_list.size(), 24u);
}

TEST(RepairedOnLoad, DegenerateFacesAreDropped) {
    auto f = kTetF;
    f.push_back({0, 3, 3});  // a repeated corner
    f.push_back({1, 1, 1});
    const TriangleMesh m = inkline::load_mesh(write_file("rep_tolerant.off", off_file(kTetV, f)));
    EXPECT_EQ(m.triangles.size(), 4u);
    EXPECT_EQ(m.repairs.faces_dropped, 2u);
    // A quad with a corner repeated in a row is the triangle of its other three.
    auto q = kCubeF;
    q.push_back({0, 1, 1, 0});  // nothing left of it
    const TriangleMesh c = inkline::load_mesh(write_file("quad_rep.off", off_file(kCubeV, q)));
    EXPECT_EQ(c.triangles.size(), 12u);
    EXPECT_EQ(c.repairs.faces_dropped, 1u);
    // A zero-area face lying on closed edges (a fin of no width) is dropped; the same face as the
    // only thing joining two sheets is kept (dropping it would open the surface).
    TriangleMesh z;
    z.positions = kTetV;
    z.positions.push_back({0.5, 0, 0});  // on edge 0-1
    z.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 4, 1}};
    inkline::repair_mesh(z, "flat fin");
    EXPECT_EQ(z.triangles.size(), 5u);  // its edges 0-4, 4-1 have no other face: kept
    EXPECT_EQ(z.repairs.faces_dropped, 0u);
    TriangleMesh w;
    w.positions = kTetV;
    w.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 1, 3}};  // a face twice: no area lost
    inkline::repair_mesh(w, "doubled face");
    EXPECT_EQ(w.triangles.size(), 4u);  // the copy: same three points (DuplicateFacesAreDropped)
    EXPECT_EQ(w.repairs.faces_dropped, 1u);
    EXPECT_EQ(w.repairs.nonmanifold_edges_cut, 0u);
}

// Non-manifold edges are cut: each sheet meets the edge as its own border, and a closed part with
// a fin keeps its edge (the fin alone is cut off).
TEST(RepairedOnLoad, NonManifoldEdgesAreCut) {
    auto v = kTetV;
    v.push_back({0.5, -1, 0.5});
    auto f = kTetF;
    f.push_back({0, 4, 1});
    const TriangleMesh m = inkline::load_mesh(write_file("fin_tolerant.off", off_file(v, f)));
    EXPECT_EQ(m.repairs.nonmanifold_edges_cut, 1u);
    EXPECT_EQ(m.repairs.vertices_split, 2u);  // the fin's copies of vertices 0 and 1
    EXPECT_EQ(m.positions.size(), 7u);
    const MeshTopology t = inkline::build_topology(m);
    EXPECT_EQ(t.border_list.size(), 3u);  // the fin's three edges; the tetrahedron stays closed
    EXPECT_EQ(t.edge_count(), 6u + 3u);
    EXPECT_EQ(inkline::corner_mates(m.triangles, m.positions.size()).extra, 0u);
    // Two tetrahedra glued along an edge only (four faces on it): two closed parts.
    TriangleMesh two = inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}), inkline::make_box({1, 1, 0}, {2, 2, 1}));
    inkline::repair_mesh(two, "boxes sharing an edge");
    EXPECT_EQ(two.repairs.vertices_welded, 2u);  // the shared edge's ends
    EXPECT_EQ(two.repairs.nonmanifold_edges_cut, 1u);
    EXPECT_EQ(two.repairs.vertices_split, 2u);
    const MeshTopology tt = inkline::build_topology(two);
    EXPECT_TRUE(tt.closed);
    EXPECT_EQ(tt.edge_count(), 36u);
    // A fan of four sheets on one edge, open (the bowtie of NonManifoldEdge): cut into four.
    TriangleMesh bow;
    bow.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
    bow.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}};
    inkline::repair_mesh(bow, "bowtie");
    EXPECT_EQ(bow.repairs.nonmanifold_edges_cut, 1u);
    EXPECT_EQ(bow.positions.size(), 12u);  // every sheet its own ends: 6 + 3 x 2
    EXPECT_EQ(inkline::build_topology(bow).border_list.size(), 12u);
}

TEST(RepairedOnLoad, DisagreeingOrientationIsCountedPerPart) {
    auto f = kCubeF;
    std::reverse(f[2].begin(), f[2].end());
    TriangleMesh two = inkline::load_mesh(write_file("cube_flip.off", off_file(kCubeV, f)));
    EXPECT_EQ(two.repairs.components_reoriented, 1u);
    EXPECT_EQ(two.faces_reoriented, 2u);
    EXPECT_EQ(inkline::load_mesh(write_file("cube_ok.off", off_file(kCubeV, kCubeF))).repairs.components_reoriented, 0u);
    const std::vector<std::string> lines = two.repairs.warnings("cube_flip.off");
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0], "cube_flip.off: re-oriented 1 connected parts whose faces disagreed in orientation");
}

// Header lines other readers skip ("Created by ..." of old Blender exports) are skipped.
TEST(RepairedOnLoad, PlyUnknownHeaderLinesAreSkipped) {
    const std::string ply =
        "ply\nformat ascii 1.0\nCreated by Blender 2.49\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    for (const bool strict : {false, true}) {
        const TriangleMesh m = inkline::load_mesh(write_file("created_by.ply", ply), {.strict = strict});
        EXPECT_EQ(m.triangles.size(), 4u);
    }
}

TEST(RepairedOnLoad, PointCloudIsAClearError) {
    expect_refused(write_file("cloud.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"),
                   {"no faces", "3 vertices only", "point cloud"});
}

// ---------------------------------------------------------------------------------------------
// Exported models from Debian's assimp-testmodels (skipped where the package is not installed).

namespace {
const std::string kAssimpModels = "/usr/share/assimp/models/";

// Undirected edges (by their ends' positions, rounded to 1e-4) that hold a piece of QI `qi` (or
// of QI >= 1 when qi < 0) of positive length.
std::set<std::pair<std::array<long, 3>, std::array<long, 3>>> edges_drawn(const inkline::Model& m, const inkline::View& v,
                                                                           int qi) {
    const MeshTopology& t = m.topology();
    auto key = [&](std::uint32_t i) {
        const glm::dvec3 p = t.positions[i] * 1e4;
        return std::array<long, 3>{std::lround(p.x), std::lround(p.y), std::lround(p.z)};
    };
    std::set<std::pair<std::array<long, 3>, std::array<long, 3>>> out;
    for (std::size_t i = 0; i < v.drawing.pieces.size(); ++i) {
        const int q = v.drawing.pieces[i].qi;
        if (qi >= 0 ? q != qi : q < 1) continue;
        for (const auto& s : v.spans[i]) {
            if (std::abs(s.s1 - s.s0) < 1e-6) continue;
            auto a = key(t.edge_vertex[s.edge][0]), b = key(t.edge_vertex[s.edge][1]);
            if (b < a) std::swap(a, b);
            out.insert({a, b});
        }
    }
    return out;
}

double drawn_length(const inkline::View& v, bool visible) {
    double l = 0.0;
    for (const auto& p : v.drawing.pieces)
        if ((p.qi == 0) == visible)
            for (std::size_t k = 1; k < p.points.size(); ++k) l += glm::length(p.points[k] - p.points[k - 1]);
    return l;
}
}  // namespace

// PLY/cube_uv.ply: a cube whose corners are split per side (24 vertices, UV seams). Welded, it
// draws what the welded cube draws from a corner: 9 visible edges (6 of the outline, 3 meeting at
// the near corner) and 3 hidden ones; before welding it drew 5 lines and marked outline edges hidden.
TEST(RepairedOnLoad, CubeUvDrawsLikeAWeldedCube) {
    const std::string path = kAssimpModels + "PLY/cube_uv.ply";
    if (!fs::exists(path)) GTEST_SKIP() << "assimp-testmodels is not installed";
    const inkline::Model seamed = inkline::Model::load(path, inkline::LoadOptions{});
    EXPECT_EQ(seamed.repairs().vertices_welded, 16u);
    EXPECT_TRUE(seamed.topology().closed);
    // The same 8 corners (as the file writes them) as one closed cube of quads.
    std::vector<glm::dvec3> v;
    for (const auto& p : kCubeV) v.push_back(2.0 * p - glm::dvec3(1.0));
    v[5] = {0.999999, -1.000001, 1.0};  // (1, -1, 1) in the file
    v[6] = {1.0, 0.999999, 1.0};        // (1, 1, 1)
    const inkline::Model welded = inkline::Model::load(write_file("cube_welded.off", off_file(v, kCubeF)),
                                                       inkline::LoadOptions{.strict = true});
    const inkline::Camera cam = inkline::Camera::perspective({4, 3, 5}, {0, 0, 0}, {0, 1, 0}, 30, 800, 800);
    const inkline::View a = inkline::render_view(seamed, cam), b = inkline::render_view(welded, cam);
    const auto visible = edges_drawn(seamed, a, 0), hidden = edges_drawn(seamed, a, -1);
    EXPECT_EQ(visible.size(), 9u);
    EXPECT_EQ(hidden.size(), 3u);
    EXPECT_EQ(visible, edges_drawn(welded, b, 0));
    EXPECT_EQ(hidden, edges_drawn(welded, b, -1));
    for (const auto& e : visible) EXPECT_EQ(hidden.count(e), 0u) << "a visible edge is marked hidden";
    EXPECT_NEAR(drawn_length(a, true), drawn_length(b, true), 1e-6);
}

// OFF/Wuson.off (3205 vertices at 2117 positions) draws like OBJ/WusonOBJ.obj (the same 3732
// triangles on the 2117 positions): no seam drawn as a border.
TEST(RepairedOnLoad, WusonOffDrawsLikeWusonObj) {
    const std::string off = kAssimpModels + "OFF/Wuson.off", obj = kAssimpModels + "OBJ/WusonOBJ.obj";
    if (!fs::exists(off) || !fs::exists(obj)) GTEST_SKIP() << "assimp-testmodels is not installed";
    const inkline::Model a = inkline::Model::load(off, inkline::LoadOptions{});
    const inkline::Model b = inkline::Model::load(obj, inkline::LoadOptions{});
    EXPECT_EQ(a.repairs().vertices_welded, 3205u - 2117u);
    EXPECT_EQ(a.topology().vertex_count(), b.topology().vertex_count());
    EXPECT_EQ(a.topology().border_list.size(), b.topology().border_list.size());
    const inkline::Camera cam = inkline::Camera::framing(b.topology().bounds, 800, 800);
    const inkline::View va = inkline::render_view(a, cam), vb = inkline::render_view(b, cam);
    EXPECT_EQ(a.topology().border_list.size(), 412u);  // the model's own openings, in both files
    EXPECT_NEAR(drawn_length(va, true), drawn_length(vb, true), 1e-6 * drawn_length(vb, true));
    EXPECT_NEAR(drawn_length(va, false), drawn_length(vb, false), 1e-6 * drawn_length(vb, false));
}

namespace {
double total_area(const TriangleMesh& m) {
    double a = 0.0;
    for (const auto& t : m.triangles)
        a += 0.5 * glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
    return a;
}
}  // namespace

// Polygons that are not strictly convex are cut into ears: a concave L (a fan from its first
// corner would overlap itself) and a keyhole (a 4 x 4 square with a 2 x 2 hole, joined by a bridge
// walked twice, as OBJ/concave_polygon.obj of assimp-testmodels has): triangles that cover the
// polygon once, none of zero area. Strict loading refuses the keyhole's repeated corners.
TEST(RepairedOnLoad, ConcaveAndKeyholePolygonsAreCutIntoEars) {
    const std::vector<glm::dvec3> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
    const TriangleMesh ml = inkline::load_mesh(write_file("ell.off", off_file(l, {{3, 4, 5, 0, 1, 2}})));
    EXPECT_EQ(ml.triangles.size(), 4u);
    EXPECT_NEAR(total_area(ml), 3.0, 1e-12);
    const std::vector<glm::dvec3> k = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0},
                                       {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}};
    const std::vector<std::vector<int>> keyhole = {{0, 1, 2, 3, 0, 4, 5, 6, 7, 4}};
    const std::string path = write_file("keyhole.off", off_file(k, keyhole));
    const TriangleMesh mk = inkline::load_mesh(path);
    EXPECT_EQ(mk.triangles.size(), 8u);
    EXPECT_NEAR(total_area(mk), 12.0, 1e-12);
    EXPECT_EQ(mk.repairs.faces_dropped, 0u);
    EXPECT_EQ(inkline::build_topology(mk).border_list.size(), 8u);  // the outer and the inner square
    expect_refused(path, {"face 0", "repeats vertex index 0"}, kStrict);
    const std::string corpus = "/usr/share/assimp/models/OBJ/concave_polygon.obj";
    if (fs::exists(corpus)) {
        const TriangleMesh c = inkline::load_mesh(corpus);
        EXPECT_EQ(c.repairs.faces_dropped, 0u);
        EXPECT_GT(c.triangles.size(), 60u);
    }
}

// A face on the same three points as another (a double-sided sheet, an object listed twice) is
// dropped: the sheet stays one sheet with a border, where cutting the doubled edges would have
// made two coincident sheets.
TEST(RepairedOnLoad, DuplicateFacesAreDropped) {
    TriangleMesh sheet = inkline::make_sheet(1.0, 0.0, 2);
    const std::size_t n = sheet.triangles.size();
    for (std::size_t f = 0; f < n; ++f) {
        const auto t = sheet.triangles[f];
        sheet.triangles.push_back({t[0], t[2], t[1]});  // the back side
    }
    inkline::repair_mesh(sheet, "double-sided sheet");
    EXPECT_EQ(sheet.triangles.size(), n);
    EXPECT_EQ(sheet.repairs.faces_dropped, n);
    EXPECT_EQ(sheet.repairs.nonmanifold_edges_cut, 0u);
    EXPECT_EQ(inkline::build_topology(sheet).border_list.size(), 8u);
}

// How QI stays exact where the surface was cut: every sheet at a non-manifold edge has its own
// border there, so the fast method's border rule (+-1 per sheet passed behind) holds sheet by
// sheet. Checked against the ray reference (one ray test per piece): the same visible and hidden
// length by QI, on the tetrahedron with a fin and on STL/3DSMaxExport.STL (16 edges cut).
TEST(RepairedOnLoad, QiAtCutEdgesAgreesWithTheRayReference) {
    auto v = kTetV;
    v.push_back({0.5, -1, 0.5});
    auto f = kTetF;
    f.push_back({0, 4, 1});
    std::vector<std::string> paths = {write_file("fin_qi.off", off_file(v, f))};
    if (fs::exists(kAssimpModels + "STL/3DSMaxExport.STL")) paths.push_back(kAssimpModels + "STL/3DSMaxExport.STL");
    for (const std::string& path : paths) {
        const inkline::Model m = inkline::Model::load(path, inkline::LoadOptions{});
        EXPECT_GT(m.repairs().nonmanifold_edges_cut, 0u) << path;
        const glm::dvec3 c = m.topology().bounds.center();
        const double r = m.topology().bounds.half_diagonal();
        for (const glm::dvec3 dir : {glm::dvec3(1, 0.6, 1.4), glm::dvec3(-1.2, 0.3, 0.4), glm::dvec3(0.2, -1, -0.7)}) {
            const inkline::Camera cam =
                inkline::Camera::perspective(c + glm::normalize(dir) * 4.0 * r, c, {0, 1, 0}, 35, 700, 700);
            inkline::ViewOptions rays;
            rays.visibility = inkline::VisibilityMethod::Rays;
            const inkline::View a = inkline::render_view(m, cam), b = inkline::render_view(m, cam, rays);
            std::map<int, double> la, lb;
            for (const auto& p : a.drawing.pieces)
                for (std::size_t k = 1; k < p.points.size(); ++k) la[p.qi] += glm::length(p.points[k] - p.points[k - 1]);
            for (const auto& p : b.drawing.pieces)
                for (std::size_t k = 1; k < p.points.size(); ++k) lb[p.qi] += glm::length(p.points[k] - p.points[k - 1]);
            ASSERT_EQ(la.size(), lb.size()) << path;
            for (const auto& [qi, len] : la) EXPECT_NEAR(len, lb[qi], 1e-6 * (1.0 + len)) << path << " qi " << qi;
            EXPECT_GT(la[0], 0.0) << path;
        }
    }
}

// The topology's angles between face normals come from a faster acos (glibc's vector one where
// there is one) that must give std::acos's floats exactly. The hard cases are cosines whose angle
// lies at a midpoint between two floats, where a result a few ulp off rounds the other way: each
// such midpoint's cosine is tried, with cosines spread over [-1, 1] and the ends.
// build_topology makes each face's normal as the edges reach it and keeps a window of the last
// faces' normals; an edge whose second face lies beyond the window has that normal made again.
// With the faces numbered at random (bunny00, 75 k faces: most second faces far beyond the window)
// every angle, convexity and facing plane is what the plain formulas give edge by edge.
TEST(TopologyAngles, NormalsBeyondTheWindowGiveTheSameAngles) {
    using namespace inkline;
    const MeshTopology t = build_topology(shuffled_numbering(load_mesh(test::mesh_path("bunny00")), 7));
    std::size_t far = 0, differ = 0, convexity_differs = 0;
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
        const auto [f0, f1] = t.edge_face[e];
        if (f1 == kNoFace) continue;
        far += f1 - f0 >= 16384;
        const double sign = t.is_seam(e) ? -1.0 : 1.0;
        const double cosine = std::clamp(sign * glm::dot(t.face_normal(f0), t.face_normal(f1)), -1.0, 1.0);
        differ += t.edge_normal_angle[e] != float(std::acos(cosine));
        convexity_differs += (t.edge_flags[e] & (kEdgeConvex | kEdgeConcave)) != edge_convexity(t, e);
    }
    EXPECT_GT(far, t.edge_count() / 2);
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(convexity_differs, 0u);
    MeshTopology planes = t;  // (the facing planes of a pass of their own)
    compute_bounds_and_facing(planes);
    EXPECT_EQ(std::memcmp(planes.facing.data(), t.facing.data(), t.facing.size() * sizeof t.facing[0]), 0);
}

TEST(TopologyAngles, SameFloatsAsStdAcos) {
    std::vector<double> cosines = {-1.0, 1.0, 0.0, -0.0, std::nextafter(1.0, 0.0), std::nextafter(-1.0, 0.0)};
    for (int i = 0; i <= 200000; ++i) cosines.push_back(-1.0 + 2.0 * i / 200000.0);
    std::size_t midpoints = 0;
    for (float f = 1e-4f; f < 3.14f; f = std::nextafter(f * 1.0001f, 4.0f)) {
        const double mid = (double(f) + double(std::nextafter(f, 4.0f))) / 2.0;
        for (const double c : {std::cos(mid), std::nextafter(std::cos(mid), 2.0), std::nextafter(std::cos(mid), -2.0)})
            cosines.push_back(c), ++midpoints;
    }
    std::vector<float> angle(cosines.size());
    inkline::angles_of_cosines(cosines.data(), cosines.size(), angle.data());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < cosines.size(); ++i) differ += angle[i] != float(std::acos(cosines[i]));
    EXPECT_EQ(differ, 0u) << "of " << cosines.size() << " cosines, " << midpoints << " at float midpoints";
}
