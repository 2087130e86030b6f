// Loading gives the same model as before it was made fast (issue 46, item 3): every array of the
// loaded mesh and of its topology, the repairs' counts and the self-intersections, hashed, for
// sample meshes written in every format the own parsers read. The hashes were pinned with the
// loader as it was before the speed work (main at 6577e15) and renewed once, when the Hilbert
// order became a sort of Hilbert keys (it renumbers every vertex and face; the counts, the errors
// and the strict loads' hashes stayed, and LoadingOrder below and `vis_check --geometry=median`
// show the drawings unchanged); a changed array names itself in the failure message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "core/error.hpp"
#include "expect_self_intersections.hpp"
#include "model/mesh_io.hpp"
#include "model/reorder.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"
#include "visibility/line_difference.hpp"

namespace inkline {
namespace {

// Positions and polygons as a sample OFF file lists them (read here without inkline's parser, so
// the files below are written from what the file says, not from what the loader made of it).
struct Polygons {
    std::vector<glm::dvec3> positions;
    std::vector<std::vector<std::uint32_t>> faces;
};

Polygons read_sample(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    std::string line;
    while (std::getline(in, line)) text << line.substr(0, line.find('#')) << '\n';
    std::string header;
    std::size_t nv = 0, nf = 0, ne = 0;
    text >> header >> nv >> nf >> ne;
    Polygons p;
    p.positions.resize(nv);
    for (auto& v : p.positions) text >> v.x >> v.y >> v.z;
    p.faces.resize(nf);
    for (auto& f : p.faces) {
        std::size_t n = 0;
        text >> n;
        f.resize(n);
        for (auto& i : f) text >> i;
        std::getline(text, line);  // a colour, if any
    }
    return p;
}

// A small non-manifold soup: a fin (a third face on an edge of a tetrahedron), a face listed
// twice and one with a repeated corner, so that tolerant loading cuts, drops and welds.
Polygons repair_sample() {
    Polygons p;
    p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0, 0, 0}, {0.5, -1, 0.2}};
    p.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {5, 1, 6}, {1, 2, 3}, {1, 1, 4}, {1, 4, 2, 0}};
    return p;
}

void put_u32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
void put_f32(std::string& s, float v) { s.append(reinterpret_cast<const char*>(&v), 4); }
template <class T>
void put_be(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t k = sizeof(T); k-- > 0;) s.push_back(b[k]);
}

std::string g17(double x) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", x);
    return b;
}

// The polygons fanned into triangles, for STL.
std::vector<std::array<std::uint32_t, 3>> fan(const Polygons& p) {
    std::vector<std::array<std::uint32_t, 3>> t;
    for (const auto& f : p.faces)
        for (std::size_t k = 1; k + 1 < f.size(); ++k) t.push_back({f[0], f[k], f[k + 1]});
    return t;
}

std::string write_as(const Polygons& p, const std::string& format) {
    std::string s;
    if (format == "off") {
        s = "OFF\n" + std::to_string(p.positions.size()) + " " + std::to_string(p.faces.size()) + " 0\n";
        for (const auto& v : p.positions) s += g17(v.x) + " " + g17(v.y) + " " + g17(v.z) + "\n";
        for (const auto& f : p.faces) {
            s += std::to_string(f.size());
            for (auto i : f) s.append(" ").append(std::to_string(i));
            s += "\n";
        }
    } else if (format == "obj") {
        s = "# written by test_loading\n";
        for (const auto& v : p.positions) s += "v " + g17(v.x) + " " + g17(v.y) + " " + g17(v.z) + "\n";
        for (const auto& f : p.faces) {
            s += "f";
            for (auto i : f) s.append(" ").append(std::to_string(i + 1));
            s += "\n";
        }
    } else if (format == "ply" || format == "ply-le" || format == "ply-be") {
        const std::string kind = format == "ply" ? "ascii" : format == "ply-le" ? "binary_little_endian" : "binary_big_endian";
        s = "ply\nformat " + kind + " 1.0\nelement vertex " + std::to_string(p.positions.size()) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
            std::to_string(p.faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
        for (const auto& v : p.positions) {
            if (format == "ply") s += g17(v.x) + " " + g17(v.y) + " " + g17(v.z) + "\n";
            for (int k = 0; k < 3 && format != "ply"; ++k) {
                if (format == "ply-le") s.append(reinterpret_cast<const char*>(&v[k]), 8);
                else put_be(s, v[k]);
            }
        }
        for (const auto& f : p.faces) {
            if (format == "ply") {
                s += std::to_string(f.size());
                for (auto i : f) s.append(" ").append(std::to_string(i));
                s += "\n";
                continue;
            }
            s.push_back(char(f.size()));
            for (auto i : f) {
                if (format == "ply-le") put_u32(s, i);
                else put_be(s, std::int32_t(i));
            }
        }
    } else if (format == "off-bin") {
        s = "OFF BINARY\n";
        put_u32(s, std::uint32_t(p.positions.size()));
        put_u32(s, std::uint32_t(p.faces.size()));
        put_u32(s, 0);
        for (const auto& v : p.positions)
            for (int k = 0; k < 3; ++k) put_f32(s, float(v[k]));
        for (const auto& f : p.faces) {
            put_u32(s, std::uint32_t(f.size()));
            for (auto i : f) put_u32(s, i);
        }
    } else if (format == "stl") {
        s = "solid test\n";
        for (const auto& t : fan(p)) {
            s += "facet normal 0 0 0\nouter loop\n";
            for (auto i : t) {
                const auto& v = p.positions[i];
                s += "vertex " + g17(v.x) + " " + g17(v.y) + " " + g17(v.z) + "\n";
            }
            s += "endloop\nendfacet\n";
        }
        s += "endsolid test\n";
    } else {  // binary STL
        s.assign(80, ' ');
        const auto tris = fan(p);
        put_u32(s, std::uint32_t(tris.size()));
        for (const auto& t : tris) {
            for (int k = 0; k < 3; ++k) put_f32(s, 0.0f);
            for (auto i : t)
                for (int k = 0; k < 3; ++k) put_f32(s, float(p.positions[i][k]));
            s.append(2, '\0');
        }
    }
    return s;
}

std::string extension(const std::string& format) { return format.substr(0, format.find('-')) == "stl" ? "stl" : format.substr(0, 3); }

// FNV-1a, 64 bits, over an array's bytes (every array here is of plain values without padding).
template <class T>
std::uint64_t hash_of(const std::vector<T>& v) {
    std::uint64_t h = 1469598103934665603ull;
    const auto* b = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) h = (h ^ b[i]) * 1099511628211ull;
    return h ^ v.size();
}

// Every array of the model as render loads it (tolerant), with its self-intersections.
// `threads`: LoadOptions::threads and the self-intersection search's (the same arrays for any).
std::map<std::string, std::uint64_t> model_hashes(const std::string& path, int threads = 1) {
    const Model model = Model::load(path, LoadOptions{.threads = threads});
    const MeshTopology& t = model.topology();
    std::map<std::string, std::uint64_t> h;
    h["positions"] = hash_of(t.positions);
    h["faces"] = hash_of(t.faces);
    h["face_edges"] = hash_of(t.face_edges);
    h["facing"] = hash_of(t.facing);
    h["edge_vertex"] = hash_of(t.edge_vertex);
    h["edge_face"] = hash_of(t.edge_face);
    h["edge_normal_angle"] = hash_of(t.edge_normal_angle);
    h["edge_flags"] = hash_of(t.edge_flags);
    h["border_list"] = hash_of(t.border_list);
    h["crease_list"] = hash_of(t.crease_list);
    h["vertex_edge_begin"] = hash_of(t.vertex_edge_begin);
    h["vertex_edges"] = hash_of(t.vertex_edges);
    h["scalars"] = hash_of(std::vector<double>{t.bounds.lo.x, t.bounds.lo.y, t.bounds.lo.z, t.bounds.hi.x, t.bounds.hi.y,
                                               t.bounds.hi.z, t.facing_origin.x, t.facing_origin.y, t.facing_origin.z,
                                               t.facing_radius, double(t.closed)});
    const LoadReport& r = model.repairs();
    h["repairs"] = hash_of(std::vector<std::size_t>{r.vertices_welded, r.faces_dropped, r.nonmanifold_edges_cut,
                                                    r.vertices_split, r.components_reoriented});
    const SelfIntersections& si = model.self_intersections(threads);
    h["si_faces"] = hash_of(si.faces);
    std::vector<std::pair<std::uint32_t, double>> cuts;
    for (const auto& c : si.cuts) cuts.emplace_back(c.edge, c.s);
    std::vector<std::uint64_t> cut_words;
    for (const auto& [e, s] : cuts) {
        std::uint64_t b;
        std::memcpy(&b, &s, 8);
        cut_words.push_back(e);
        cut_words.push_back(b);
    }
    h["si_cuts"] = hash_of(cut_words);
    h["si_pairs"] = hash_of(si.pairs);
    return h;
}

// All of them in one: "V<vertices> F<faces> E<edges> <hash>".
std::string summary(const std::string& path, int threads = 1) {
    const Model model = Model::load(path, LoadOptions{.threads = threads});
    std::uint64_t all = 1469598103934665603ull;
    for (const auto& [name, value] : model_hashes(path, threads)) all = (all ^ value) * 1099511628211ull;
    char b[96];
    std::snprintf(b, sizeof b, "V%zu F%zu E%zu %016llx", model.topology().vertex_count(), model.topology().face_count(),
                  model.topology().edge_count(), static_cast<unsigned long long>(all));
    return b;
}

// Strict loading: the triangle mesh's arrays, or the error.
std::string strict_summary(const std::string& path) {
    try {
        LoadOptions strict;
        strict.strict = true;
        const TriangleMesh m = load_mesh(path, strict);
        char b[96];
        std::snprintf(b, sizeof b, "V%zu F%zu %016llx", m.positions.size(), m.triangles.size(),
                      static_cast<unsigned long long>(hash_of(m.positions) ^ (hash_of(m.triangles) * 31) ^ m.faces_reoriented));
        return b;
    } catch (const Error& e) {
        const std::string what = e.what();
        return "error: " + what.substr(what.find(": ") + 2);
    }
}

struct Case {
    const char* mesh;    // sample mesh name, or "repair" for repair_sample()
    const char* format;  // off obj ply ply-le ply-be off-bin stl stl-bin, or file (the sample as it is)
    const char* tolerant;
    const char* strict;
};

// Pinned with main at 6577e15 (before the loading speed work); the tolerant loads' hashes renewed
// with the Hilbert keys' order.
const Case kCases[] = {
#include "test_loading_pins.inc"
};

class LoadingPins : public ::testing::TestWithParam<Case> {};

TEST_P(LoadingPins, SameArraysAsBefore) {
    const Case& c = GetParam();
    const std::string dir = ::testing::TempDir() + "/test_loading";
    std::filesystem::create_directories(dir);
    const std::string mesh = c.mesh, format = c.format;
    std::string path = test::mesh_path(mesh);  // format "file": the sample file as it is
    if (format != "file") {
        const Polygons p = mesh == "repair" ? repair_sample() : read_sample(test::mesh_path(mesh));
        path = dir + "/" + mesh + "." + format + "." + extension(format);
        std::ofstream(path, std::ios::binary) << write_as(p, format);
    }
    std::string tolerant;
    try {
        tolerant = summary(path);
    } catch (const Error& e) {
        const std::string what = e.what();
        tolerant = "error: " + what.substr(what.find(": ") + 2);
    }
    const std::string strict = strict_summary(path);
    if (std::getenv("INKLINE_PRINT_PINS"))
        std::printf("    {\"%s\", \"%s\", \"%s\", \"%s\"},\n", c.mesh, c.format, tolerant.c_str(), strict.c_str());
    EXPECT_EQ(tolerant, c.tolerant) << path;
    EXPECT_EQ(strict, c.strict) << path;
    // On two threads (the Hilbert sorts side by side, the search split): the same arrays.
    if (tolerant.rfind("error", 0) != 0) {
        EXPECT_EQ(summary(path, 2), c.tolerant) << path << " on 2 threads";
    }
    if (tolerant != c.tolerant && tolerant.rfind("error", 0) != 0)
        for (const auto& [name, value] : model_hashes(path)) std::printf("  %s %016llx\n", name.c_str(), static_cast<unsigned long long>(value));
}

// A face listed twice where no other face meets its edges (a two-sided triangle beside a closed
// tetrahedron): every edge of the pair has exactly those two faces, the case the repairs' quick
// check (no face with its three corner mates in one face) must send to the duplicate search. Both
// windings of the copy are dropped as before.
TEST(LoadingRepairs, TwoSidedLoneTriangleIsOneFace) {
    for (const std::array<std::uint32_t, 3> copy : {std::array<std::uint32_t, 3>{4, 5, 6}, {4, 6, 5}, {5, 6, 4}}) {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {3, 0, 0}, {4, 0, 0}, {3, 1, 0}};
        m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {4, 5, 6}, copy};
        repair_mesh(m, "two-sided");
        EXPECT_EQ(m.repairs.faces_dropped, 1u);
        ASSERT_EQ(m.triangles.size(), 5u);
        EXPECT_EQ(inkline::build_topology(m).border_list.size(), 3u);  // the lone triangle's edges
    }
}

// Duplicate faces around a vertex of many faces (more than 32: its bucket is sorted, not
// compared pairwise): a fan of 40 triangles around vertex 0 with one face listed again, once in
// another rotation and once as it is, at the end. The two copies are dropped, the fan kept in order.
TEST(LoadingRepairs, DuplicatesAroundAVertexOfManyFaces) {
    TriangleMesh m;
    m.positions.push_back({0, 0, 0});
    for (int i = 0; i <= 40; ++i) m.positions.push_back({std::cos(0.1 * i), std::sin(0.1 * i), 0.05 * i});
    for (std::uint32_t i = 1; i <= 40; ++i) m.triangles.push_back({0, i, i + 1});
    const auto fan = m.triangles;
    m.triangles.push_back({6, 0, 5});
    m.triangles.push_back({0, 5, 6});
    repair_mesh(m, "fan");
    EXPECT_EQ(m.repairs.faces_dropped, 2u);
    ASSERT_EQ(m.triangles.size(), fan.size());
    for (std::size_t f = 0; f < fan.size(); ++f) {
        auto a = m.triangles[f], b = fan[f];  // (orientation may be flipped as a whole)
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        EXPECT_EQ(a, b) << "face " << f;
    }
}

// The drawing does not depend on how the mesh is numbered: the Hilbert order a load gives, the
// order before it (CGAL's median policy), the file's order and two random numberings (corners
// rotated too) draw the same lines, visible and hidden at every QI, to rounding (1e-6 px), by the
// exact propagation and by rays. What let the Hilbert order change (it renumbers every vertex
// and face) without changing a drawing. (Not every mesh: where QI is a tie, e.g. boeing's borders
// lying on other faces, the tie's outcome depends on the numbering; bench/vis_check --geometry.)
// Binary PLY in the layout nearly every file has (one vertex element of scalars, one face element
// whose only list holds three indices a face) is read straight into triangles; any other layout,
// a polygon, or an index out of range goes the general way. Every layout gives what the ASCII file
// of the same faces gives: the same positions, triangles and repairs, or the same error.
struct PlyLayout {
    const char* name;
    bool doubles = false;                       // coordinates as double (else float)
    bool vertex_extras = false;                 // a uchar before x and three floats after z
    bool face_extras = false;                   // an int before the list and a uchar after it
    const char* count = "uchar";                // the list's count type
    const char* index = "int";                  // its index type
    bool big_endian = false;
};

void put_ply(std::string& s, const std::string& type, double v, bool be) {
    char b[8];
    std::size_t n = 4;
    if (type == "uchar") b[0] = char(std::uint8_t(v)), n = 1;
    else if (type == "ushort") { const auto x = std::uint16_t(v); std::memcpy(b, &x, n = 2); }
    else if (type == "int") { const auto x = std::int32_t(v); std::memcpy(b, &x, 4); }
    else if (type == "uint") { const auto x = std::uint32_t(v); std::memcpy(b, &x, 4); }
    else if (type == "float") { const auto x = float(v); std::memcpy(b, &x, 4); }
    else { std::memcpy(b, &v, n = 8); }
    if (be) std::reverse(b, b + n);
    s.append(b, n);
}

std::string write_ply_binary(const Polygons& p, const PlyLayout& l) {
    const std::string coord = l.doubles ? "double" : "float";
    std::string s = std::string("ply\nformat ") + (l.big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex " + std::to_string(p.positions.size()) + "\n";
    if (l.vertex_extras) s += "property uchar flags\n";
    s += "property " + coord + " x\nproperty " + coord + " y\nproperty " + coord + " z\n";
    if (l.vertex_extras) s += "property float nx\nproperty float ny\nproperty float nz\n";
    s += "element face " + std::to_string(p.faces.size()) + "\n";
    if (l.face_extras) s += "property int material\n";
    s += std::string("property list ") + l.count + " " + l.index + " vertex_indices\n";
    if (l.face_extras) s += "property uchar red\n";
    s += "end_header\n";
    for (const auto& v : p.positions) {
        if (l.vertex_extras) put_ply(s, "uchar", 7, l.big_endian);
        for (int k = 0; k < 3; ++k) put_ply(s, coord, v[k], l.big_endian);
        if (l.vertex_extras)
            for (int k = 0; k < 3; ++k) put_ply(s, "float", 0.5, l.big_endian);
    }
    for (const auto& f : p.faces) {
        if (l.face_extras) put_ply(s, "int", 3, l.big_endian);
        put_ply(s, l.count, double(f.size()), l.big_endian);
        for (const auto i : f) put_ply(s, l.index, i, l.big_endian);
        if (l.face_extras) put_ply(s, "uchar", 200, l.big_endian);
    }
    return s;
}

// "V.. F.. <hashes> <repairs>" of a tolerant load_mesh, or the error without the file's name.
std::string mesh_summary(const std::string& path, bool strict) {
    try {
        LoadOptions options;
        options.strict = strict;
        const TriangleMesh m = load_mesh(path, options);
        const LoadReport& r = m.repairs;
        char b[160];
        std::snprintf(b, sizeof b, "V%zu F%zu %016llx %016llx welded %zu dropped %zu cut %zu reoriented %zu",
                      m.positions.size(), m.triangles.size(), static_cast<unsigned long long>(hash_of(m.positions)),
                      static_cast<unsigned long long>(hash_of(m.triangles)), r.vertices_welded, r.faces_dropped,
                      r.nonmanifold_edges_cut, r.components_reoriented);
        return b;
    } catch (const Error& e) {
        const std::string what = e.what();
        return "error: " + what.substr(what.find(": ") + 2);
    }
}

TEST(LoadingPly, BinaryLayoutsLoadAsTheAsciiFile) {
    // Triangles only, with what tolerant loading repairs: a fin, a face listed twice, a repeated
    // corner, a vertex at the position of another (coordinates exact in float).
    Polygons triangles;
    triangles.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0, 0, 0}, {0.5, -1, 0.25}};
    triangles.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {5, 1, 6}, {1, 2, 3}, {1, 1, 4}};
    Polygons with_quad = triangles;  // (the general way: a polygon)
    with_quad.faces.insert(with_quad.faces.begin() + 3, std::vector<std::uint32_t>{1, 4, 2, 0});
    Polygons out_of_range = triangles;
    out_of_range.faces[4][2] = 9;
    Polygons clean;  // (strict loading takes it: no repeated corner)
    clean.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    clean.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const PlyLayout layouts[] = {
        {"float"},
        {"double extras", true, true, true},
        {"int count, uint index", false, false, false, "int", "uint"},
        {"ushort count and index", false, true, false, "ushort", "ushort"},
        {"uint count, double", true, false, true, "uint", "int"},
        {"big-endian", false, true, true, "uchar", "int", true},
    };
    const auto dir = std::filesystem::temp_directory_path() / ("inkline_ply_layouts_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    for (const auto& [what, mesh] : {std::pair<const char*, const Polygons*>{"triangles", &triangles},
                                    {"with a quad", &with_quad}, {"out of range", &out_of_range}, {"clean", &clean}}) {
        const std::string ascii = (dir / "ascii.ply").string();
        std::ofstream(ascii, std::ios::binary) << write_as(*mesh, "ply");
        for (const bool strict : {false, true}) {
            const std::string expected = mesh_summary(ascii, strict);
            for (const PlyLayout& layout : layouts) {
                const std::string binary = (dir / "binary.ply").string();
                std::ofstream(binary, std::ios::binary) << write_ply_binary(*mesh, layout);
                EXPECT_EQ(mesh_summary(binary, strict), expected) << what << ", " << layout.name << (strict ? ", strict" : "");
            }
        }
    }
    std::filesystem::remove_all(dir);
    // (what the loads compared above do: tolerant ones repair, strict ones refuse the repeated corner)
    std::ofstream(dir.string() + ".ply", std::ios::binary) << write_ply_binary(triangles, layouts[0]);
    EXPECT_NE(mesh_summary(dir.string() + ".ply", false).find("welded 1 dropped 2"), std::string::npos)
        << mesh_summary(dir.string() + ".ply", false);
    EXPECT_EQ(mesh_summary(dir.string() + ".ply", true), "error: face 6 repeats vertex index 1");
    std::filesystem::remove(dir.string() + ".ply");
}

TEST(LoadingOrder, DrawingsDoNotDependOnNumbering) {
    for (const char* name : {"elephant", "knot1", "fandisk"}) {
        const TriangleMesh mesh = load_mesh(test::mesh_path(name));
        const Model hilbert(hilbert_ordered(mesh)), input(mesh), shuffled(shuffled_numbering(mesh, 3u)),
            reshuffled(shuffled_numbering(mesh, 4u)), median(hilbert_ordered_median(mesh));
        std::mt19937 rng(5u);
        for (int k = 0; k < 6; ++k) {
            const Camera cam = test::framed_then_random(k, rng, hilbert.topology().bounds);
            for (const VisibilityMethod method : {VisibilityMethod::Appel, VisibilityMethod::Rays}) {
                ViewOptions o;
                o.visibility = method;
                o.exact_hidden = true;
                const Drawing reference = render_view(hilbert, cam, o).drawing;
                ASSERT_GT(test::visible_length_px(reference), 100.0) << name << " camera " << k;
                const std::pair<const char*, const Model*> orders[] = {
                    {"file", &input}, {"shuffled", &shuffled}, {"reshuffled", &reshuffled}, {"median", &median}};
                for (const auto& [order, other] : orders) {
                    const LineDifference d = drawing_difference(reference, render_view(*other, cam, o).drawing, 1e-6);
                    // (0 but for the rounding of a length less its length near: 1e-13 px)
                    EXPECT_LT(d.missing_px + d.extra_px, 1e-9)
                        << name << " camera " << k << " method " << int(method) << " order " << order;
                    EXPECT_NEAR(d.other_px, d.reference_px, 1e-6 * d.reference_px) << name << " camera " << k;
                }
            }
        }
    }
}

// The keys follow a Hilbert curve: the 8 x 8 x 8 cells at the grid's corner are its first 512
// (the curve fills each octant before the next, at every level), each sharing a face with the
// one before. And the order of a load is the keys' order, ties in the input order.
TEST(LoadingOrder, HilbertKeysVisitNeighbours) {
    std::vector<std::pair<std::uint64_t, glm::ivec3>> cells;
    for (int x = 0; x < 8; ++x)
        for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) cells.push_back({hilbert_key(x, y, z), {x, y, z}});
    std::sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t i = 0; i < cells.size(); ++i) {
        ASSERT_EQ(cells[i].first, i);
        if (i > 0) {
            const glm::ivec3 d = glm::abs(cells[i].second - cells[i - 1].second);
            EXPECT_EQ(d.x + d.y + d.z, 1) << "key " << i;
        }
    }
    EXPECT_EQ(hilbert_key(0, 0, 0), 0u);
    EXPECT_LT(hilbert_key((1u << 21) - 1, (1u << 21) - 1, (1u << 21) - 1), std::uint64_t(1) << 63);
    // Two vertices at one position (keys tie) keep their input order; faces follow their centroids.
    TriangleMesh m;
    m.positions = {{1, 1, 1}, {0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}};
    m.triangles = {{2, 4, 0}, {1, 2, 4}};
    const TriangleMesh ordered = hilbert_ordered(m);
    const std::vector<glm::dvec3> expected = {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 1}, {1, 0, 0}};
    EXPECT_EQ(ordered.positions, expected);
    // vertex 1 of the input became 0, 3 became 1 (ties in input order), 4 -> 2, 0 -> 3, 2 -> 4
    const std::vector<std::array<std::uint32_t, 3>> faces = {{0, 4, 2}, {4, 2, 3}};
    EXPECT_EQ(ordered.triangles, faces);
}

// The comparison above sees a small change: one vertex of the elephant moved by a thousandth of
// the model's size changes the drawing from the framed camera.
TEST(LoadingOrder, DrawingDifferenceSeesAMovedVertex) {
    TriangleMesh mesh = load_mesh(test::mesh_path("elephant"));
    const Model model(hilbert_ordered(mesh));
    const Camera cam = test::framed_camera(model.topology().bounds);
    ViewOptions o;
    o.exact_hidden = true;
    const Drawing reference = render_view(model, cam, o).drawing;
    double moved = 0.0;
    for (std::size_t v = 0; v < mesh.positions.size() && moved == 0.0; v += 97) {
        TriangleMesh changed = mesh;
        changed.positions[v] += 1e-3 * 2.0 * model.topology().bounds.half_diagonal() * glm::dvec3(0.6, 0.8, 0.0);
        changed.corner_mates.clear();
        const LineDifference d = drawing_difference(reference, render_view(Model(changed), cam, o).drawing, 1e-6);
        moved = d.missing_px + d.extra_px;
    }
    EXPECT_GT(moved, 0.0);
}

// With threads, Model::load makes the Hilbert orders beside the repairs (HilbertOrderAhead) and
// uses them only when the repairs left the mesh as it was: on armadillo as it is they are made and
// are hilbert_ordered's own; on copies that the repairs change (a face flipped, a face listed twice,
// a fin on an edge) they are dropped, and two threads load the same arrays as one.
TEST(LoadingOrder, OrdersMadeBesideTheRepairsOnlyForAnUnchangedMesh) {
    const std::string dir = ::testing::TempDir() + "/test_loading_ahead";
    std::filesystem::create_directories(dir);
    const Polygons sample = read_sample(test::mesh_path("armadillo"));
    ASSERT_GE(sample.faces.size(), 16384u);  // (HilbertOrderAhead's least: below it, no thread)
    const auto write = [&](const Polygons& p, const std::string& name) {
        const std::string path = dir + "/" + name + ".off";
        std::ofstream(path, std::ios::binary) << write_as(p, "off");
        return path;
    };
    const auto ahead_orders = [](const std::string& path) {
        HilbertOrderAhead ahead;
        TriangleMesh m = load_mesh(path, {}, &ahead);
        std::optional<HilbertOrders> known = ahead.take();
        return std::make_pair(std::move(m), std::move(known));
    };
    {
        const std::string path = write(sample, "as_is");
        auto [mesh, known] = ahead_orders(path);
        ASSERT_TRUE(known.has_value()) << "no orders made beside the repairs of a mesh they leave as it is";
        const TriangleMesh by_ahead = hilbert_ordered(mesh, *known);
        const TriangleMesh by_keys = hilbert_ordered(load_mesh(path), 1);
        EXPECT_EQ(by_ahead.positions, by_keys.positions);
        EXPECT_EQ(by_ahead.triangles, by_keys.triangles);
        EXPECT_EQ(by_ahead.corner_mates, by_keys.corner_mates);
        EXPECT_EQ(summary(path, 2), summary(path, 1));
    }
    Polygons flipped = sample, twice = sample, fin = sample;
    std::swap(flipped.faces[1000][1], flipped.faces[1000][2]);
    twice.faces.push_back(twice.faces[2000]);
    fin.positions.push_back(fin.positions[fin.faces[3000][0]] + glm::dvec3(0.5, 0.25, 0.125));
    fin.faces.push_back({fin.faces[3000][0], fin.faces[3000][1], std::uint32_t(fin.positions.size() - 1)});
    for (const auto& [p, name] : {std::pair{&flipped, "flipped"}, std::pair{&twice, "twice"}, std::pair{&fin, "fin"}}) {
        const std::string path = write(*p, name);
        const auto [mesh, known] = ahead_orders(path);
        EXPECT_TRUE(mesh.repairs.any() || mesh.faces_reoriented > 0) << name << ": the repairs changed nothing";
        EXPECT_FALSE(known.has_value()) << name << ": orders kept for a mesh the repairs changed";
        EXPECT_EQ(summary(path, 2), summary(path, 1)) << name;
    }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string n = std::string(info.param.mesh) + "_" + info.param.format;
    for (auto& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return n;
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, LoadingPins, ::testing::ValuesIn(kCases), case_name);


// Model::load starts the self-intersection search and returns without waiting for it; the first
// caller of self_intersections() joins it. Vertices moved before that make the search stale: it
// is dropped, and the moved model's self-intersections are its own (a vertex pulled through the
// body pierces many faces; the search of the loaded positions found none).
TEST(LoadingSelfIntersections, SearchStartedByTheLoadIsDroppedWhenVerticesMove) {
    const std::string path = test::mesh_path("armadillo");
    const Model loaded = Model::load(path, LoadOptions{.threads = 2});
    EXPECT_EQ(loaded.self_intersections().flagged, 0u);  // (joined from the load's search)
    Model moved = Model::load(path, LoadOptions{.threads = 2});
    // (read through the const topology(): the other one would end the search first)
    std::vector<glm::dvec3> positions = std::as_const(moved).topology().positions;
    const Bounds3& b = std::as_const(moved).topology().bounds;
    positions[0] = 2.0 * b.center() - positions[0];  // through the body to the other side
    moved.move_vertices(positions);
    const SelfIntersections fresh = self_intersections(moved.topology(), 1);
    ASSERT_GT(fresh.flagged, 0u);
    EXPECT_EQ(moved.self_intersections().flagged, fresh.flagged);
    EXPECT_EQ(moved.self_intersections().faces, fresh.faces);
}

// The load's search reads the model's own positions and faces (no copy), so whatever frees or
// changes them stops it first or ends it: a model assigned over while its search runs, a model
// moved, the writable topology(). Each model's self-intersections are still those of a fresh
// search of its arrays. (mannequin-devil intersects itself; 25 888 faces, over the early search's
// threshold.)
TEST(LoadingSelfIntersections, SearchReadsTheModelsArraysSafely) {
    const std::string devil = test::mesh_path("mannequin-devil"), armadillo = test::mesh_path("armadillo");
    const auto fresh = [](const Model& m) { return self_intersections(m.topology(), 1); };
    const LoadOptions two{.threads = 2};
    Model a = Model::load(armadillo, two);
    a = Model::load(devil, two);  // (armadillo's search stopped before its arrays are freed)
    Model b(std::move(a));        // (the search goes on, reading the same buffers, now b's)
    const SelfIntersections devil_fresh = fresh(b);
    ASSERT_GT(devil_fresh.flagged, 0u);
    test::expect_same_self_intersections(b.self_intersections(), devil_fresh, "assigned, then moved");
    Model c = Model::load(armadillo, two);
    c.topology().positions[0] += glm::dvec3(0.0);  // (the writable topology: the search ended first)
    test::expect_same_self_intersections(c.self_intersections(), fresh(c), "its writable topology asked for");
    for (int k = 0; k < 3; ++k) {
        Model gone = Model::load(devil, two);  // destroyed while its search runs
    }
}

}  // namespace
}  // namespace inkline
