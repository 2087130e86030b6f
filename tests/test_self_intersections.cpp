// self_intersecting_faces (src/model/self_intersections.cpp: float boxes and our own pair test)
// against CGAL's Polygon_mesh_processing::self_intersections on a Surface_mesh copy, the
// reference: the same faces, exactly (and the same cuts as CGAL's intersection makes on every edge
// and face, against the cuts the filters settle first), on constructed cases with touching and overlapping faces
// (shared edge folded flat, shared vertex, coincident faces, crossing boxes), on crumpled
// spheres that intersect themselves in many ways, and on real meshes.
#include <gtest/gtest.h>

#include <malloc.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "model/mesh_io.hpp"
#include "model/primitives.hpp"
#include "model/reorder.hpp"
#include "model/early_self_intersections.hpp"
#include "model/self_intersections.hpp"
#include "model/topology.hpp"
#include "expect_self_intersections.hpp"
#include "test_data.hpp"

namespace {

using inkline::TriangleMesh;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;

std::vector<std::uint8_t> reference(const inkline::MeshTopology& mesh) {
    SM sm;
    std::vector<SM::Vertex_index> vs;
    for (const auto& p : mesh.positions) vs.push_back(sm.add_vertex({p.x, p.y, p.z}));
    for (const auto& t : mesh.faces) {
        const auto f = sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
        EXPECT_NE(f, SM::null_face()) << "reference needs a manifold mesh";
    }
    std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
    std::vector<std::uint8_t> out(mesh.face_count(), 0);
    for (const auto& [a, b] : pairs) out[std::size_t(a)] = out[std::size_t(b)] = 1;
    return out;
}

// Same faces as the reference; returns how many were flagged (so cases can say they are not empty).
std::size_t expect_same(const TriangleMesh& m, const std::string& what) {
    const inkline::MeshTopology t = inkline::build_topology(m);
    const auto ours = inkline::self_intersecting_faces(t);
    const auto ref = reference(t);
    EXPECT_EQ(ours.size(), ref.size());
    std::size_t flagged = 0, differ = 0;
    for (std::size_t f = 0; f < ref.size(); ++f) {
        flagged += ref[f];
        if (ours[f] != ref[f] && ++differ <= 5) ADD_FAILURE() << what << ": face " << f << " ours " << int(ours[f]) << " CGAL " << int(ref[f]);
    }
    EXPECT_EQ(differ, 0u) << what;
    const inkline::SelfIntersections got = inkline::self_intersections(t);
    EXPECT_EQ(got.flagged, flagged) << what;  // (Model::pierced_faces reads it)
    // The cuts the filters settle first are CGAL's own (every edge and face given to it).
    const inkline::SelfIntersections cgal_cuts =
        inkline::self_intersections(t, 1, inkline::PatchTest::kEmbeddedPatchesSkipped, inkline::CutConstruction::kCgalOnly);
    inkline::test::expect_same_self_intersections(got, cgal_cuts, what + ", cuts by CGAL alone");
    return flagged;
}

TEST(SelfIntersections, ClosedSurfacesDoNotIntersectThemselves) {
    EXPECT_EQ(expect_same(inkline::make_sphere({0, 0, 0}, 1, 32, 16), "sphere"), 0u);
    EXPECT_EQ(expect_same(inkline::make_box({0, 0, 0}, {1, 2, 3}), "box"), 0u);
    EXPECT_EQ(expect_same(inkline::make_sheet(1.0, 0.3, 12), "sheet"), 0u);
}

TEST(SelfIntersections, CrossingAndTouchingParts) {
    EXPECT_GT(expect_same(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                inkline::make_box({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5})),
                          "crossing boxes"),
              0u);
    // Sharing part of a face: coincident coplanar faces of opposite orientation.
    EXPECT_GT(expect_same(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                inkline::make_box({1, 0, 0}, {2, 1.5, 0.7})),
                          "boxes sharing a face"),
              0u);
    // Touching at one edge only, and at one corner only.
    EXPECT_GT(expect_same(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                inkline::make_box({1, 1, 0}, {2, 2, 1})),
                          "boxes sharing an edge line"),
              0u);
    EXPECT_GT(expect_same(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                inkline::make_box({1, 1, 1}, {2, 2, 2})),
                          "boxes sharing a corner point"),
              0u);
    // Apart by a hair: boxes overlap in float but not in double.
    EXPECT_EQ(expect_same(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                                inkline::make_box({1 + 1e-12, 0, 0}, {2, 1, 1})),
                          "boxes 1e-12 apart"),
              0u);
    EXPECT_EQ(expect_same(inkline::merge_meshes(inkline::make_torus({0, 0, 0}, {0, 0, 1}, 1.0, 0.25, 48, 16),
                                                inkline::make_torus({1, 0, 0}, {0, 1, 0}, 1.0, 0.25, 48, 16)),
                          "linked tori"),
              0u);
}

// Faces joined by the mesh: a shared edge folded flat (far corners coplanar, same side) and a
// shared vertex with overlapping coplanar wedges; and the same joints not overlapping.
TEST(SelfIntersections, FacesThatShareCorners) {
    TriangleMesh fold;  // open strip: 0-1 shared; 2 and 3 on the same side of it, coplanar
    fold.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.3, 0.6, 0}};
    fold.triangles = {{0, 1, 2}, {1, 0, 3}};
    EXPECT_EQ(expect_same(fold, "folded flat"), 2u);
    fold.positions[3] = {0.3, 0.6, 1e-9};  // just out of the plane
    EXPECT_EQ(expect_same(fold, "folded, not flat"), 0u);
    fold.positions[3] = {0.5, -1, 0};  // flat, unfolded
    EXPECT_EQ(expect_same(fold, "flat"), 0u);

    TriangleMesh fan;  // two triangles sharing vertex 0 only
    fan.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0.2, 0}, {0.2, 1, 0}};
    fan.triangles = {{0, 1, 2}, {0, 3, 4}};
    EXPECT_EQ(expect_same(fan, "coplanar wedge inside"), 2u);
    fan.positions[3] = {-1, 0.2, 0};
    fan.positions[4] = {-0.2, 1, 0};
    EXPECT_EQ(expect_same(fan, "coplanar wedges apart"), 0u);
    fan.positions[3] = {1, 1, 1};
    fan.positions[4] = {1, 1, -1};  // pierces the first triangle
    EXPECT_EQ(expect_same(fan, "piercing at a shared vertex"), 2u);
    fan.positions[4] = {1, 1, 0.5};  // both above
    EXPECT_EQ(expect_same(fan, "above a shared vertex"), 0u);
}

// Degenerate faces (collinear or coincident corners, zero area): CGAL counts each as intersecting
// and tests it against nothing (its triangle tests require proper triangles). Found by the
// pipeline fuzzer (fuzz/regressions/pipeline-degenerate-face-*), which aborted in CGAL here.
TEST(SelfIntersections, DegenerateFaces) {
    TriangleMesh s = inkline::make_sphere({0, 0, 0}, 1, 8, 4);
    const auto& t0 = s.triangles[0];
    s.positions[t0[2]] = s.positions[t0[1]];  // two corners at one point
    EXPECT_GE(expect_same(s, "sphere with a collapsed face"), 1u);
    TriangleMesh line;  // corners exactly on a line (representable midpoint), and a proper face
    line.positions = {{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    line.triangles = {{0, 1, 2}, {1, 0, 3}};
    EXPECT_EQ(expect_same(line, "collinear corners"), 1u);
    s = inkline::make_sphere({0, 0, 0}, 1, 6, 3);
    for (auto& p : s.positions) p = {std::round(p.x), std::round(p.y), std::round(p.z)};  // many collapse
    EXPECT_GE(expect_same(s, "sphere rounded to the unit grid"), 1u);
}

// Spheres whose vertices are moved at random by about an edge length: many folds, of every kind above.
TEST(SelfIntersections, CrumpledSpheres) {
    std::mt19937 rng(7);
    std::size_t total = 0;
    for (int round = 0; round < 6; ++round) {
        TriangleMesh s = inkline::make_sphere({0, 0, 0}, 1, 20 + 4 * round, 10 + 2 * round);
        std::uniform_real_distribution<double> r(-0.25, 0.25);  // edges are 0.16 to 0.3 long
        for (auto& p : s.positions) p += glm::dvec3(r(rng), r(rng), r(rng));
        total += expect_same(s, "crumpled sphere " + std::to_string(round));
    }
    std::printf("[self-intersections] crumpled spheres: %zu faces\n", total);
    EXPECT_GT(total, 50u) << "the crumpled spheres should intersect themselves";
}

// The box search split over threads (src/model/self_intersections.cpp splits it from 8192 faces
// on): the same faces as the reference, and the same faces, cuts and pairs, in the same order, as
// one thread.
TEST(SelfIntersections, ThreadsGiveTheSameResult) {
    std::mt19937 rng(11);
    TriangleMesh s = inkline::make_sphere({0, 0, 0}, 1, 160, 80);  // 25 600 faces, edges about 0.04 long
    std::uniform_real_distribution<double> r(-0.02, 0.02);
    for (auto& p : s.positions) p += glm::dvec3(r(rng), r(rng), r(rng));
    const inkline::MeshTopology t = inkline::build_topology(s);
    const inkline::SelfIntersections one = inkline::self_intersections(t, 1);
    EXPECT_GT(one.flagged, 100u) << "the crumpled sphere should intersect itself";
    EXPECT_EQ(one.faces, reference(t));
    for (const int threads : {2, 3, 8}) {
        inkline::test::expect_same_self_intersections(inkline::self_intersections(t, threads), one,
                                                     std::to_string(threads) + " threads");
        EXPECT_EQ(inkline::self_intersecting_faces(t, threads), one.faces) << threads;
        // Started before the topology was built, from the mesh's arrays (as Model::load does).
        inkline::EarlySelfIntersections early({s.positions.data(), s.triangles.data(), s.triangles.size(), s.positions.size()},
                                             threads);
        inkline::test::expect_same_self_intersections(early.finish(t), one, std::to_string(threads) + " threads, started early");
    }
}

TEST(SelfIntersections, RealMeshes) {
    for (const char* name : {"ChineseDragon-10kv.off", "bunny00.off", "fandisk.off", "knot1.off"}) {
        const TriangleMesh m = inkline::load_mesh(inkline::test::mesh_path(name));
        const std::size_t n = expect_same(m, name);
        std::printf("[self-intersections] %s: %zu faces\n", name, n);
    }
}

}  // namespace

namespace {

// The search with embedded patches skipped (the default) gives what testing every pair whose boxes
// meet gives: the same faces, pairs (in the same order) and cuts.
void expect_same_as_every_pair(const inkline::MeshTopology& t, const std::string& what, int threads) {
    const inkline::SelfIntersections every = inkline::self_intersections(t, threads, inkline::PatchTest::kEveryBoxPair);
    const inkline::SelfIntersections got = inkline::self_intersections(t, threads);
    inkline::test::expect_same_self_intersections(got, every, what);
}

}  // namespace

// Real meshes, smooth and bumpy, three of them intersecting themselves (bones, cow and
// mannequin-devil, whose intersection lines test_intersections pins), on one and two threads.
TEST(SelfIntersections, PatchTestKeepsEveryPairOnRealMeshes) {
    std::size_t intersecting_meshes = 0;
    for (const char* name : {"armadillo.off", "bones.off", "cow.off", "mannequin-devil.off", "elephant.off",
                             "ChineseDragon-10kv.off", "fandisk.off", "knot1.off"}) {
        // (in the Hilbert order a loaded model has: the patches the test skips are runs of it)
        const TriangleMesh m = inkline::hilbert_ordered(inkline::load_mesh(inkline::test::mesh_path(name)));
        const inkline::MeshTopology t = inkline::build_topology(m);
        for (const int threads : {1, 2}) expect_same_as_every_pair(t, std::string(name) + " on " + std::to_string(threads), threads);
        intersecting_meshes += inkline::self_intersections(t).flagged > 0;
    }
    EXPECT_EQ(intersecting_meshes, 4u);
}

// Crumpled spheres (folds of every size: patches that pass the test next to ones that do not) and
// a flat grid folded over itself (one patch whose normals all agree but whose boundary's
// projection overlaps itself: the test must refuse it, and the search finds the crossing).
TEST(SelfIntersections, PatchTestKeepsEveryPairOnFolds) {
    std::mt19937 rng(5);
    for (const double amount : {0.0, 0.002, 0.01, 0.03}) {
        TriangleMesh s = inkline::make_sphere({0, 0, 0}, 1, 120, 60);
        std::uniform_real_distribution<double> r(-amount, amount);
        for (auto& p : s.positions) p += glm::dvec3(r(rng), r(rng), r(rng));
        expect_same_as_every_pair(inkline::build_topology(inkline::hilbert_ordered(s)), "sphere moved by " + std::to_string(amount), 1);
    }
    // A strip of 2 x 200 squares along a helix of radius 1 that climbs 0.02 a turn and makes two
    // turns: seen along the axis every face faces +z (tilted 0.02 at most), and the second turn lies
    // 0.02 above the first, so their faces do not meet; then the climb is made 0 for the second
    // turn's last half, so that it comes down through the first turn.
    const auto helix = [](double drop) {
        TriangleMesh h;
        const int n = 200;
        for (int i = 0; i <= n; ++i) {
            const double a = 4 * M_PI * i / n;
            double z = 0.02 * a / (2 * M_PI);
            if (drop > 0 && i > 3 * n / 4) z -= drop * (i - 3 * n / 4) / double(n / 4);
            for (int k = 0; k < 3; ++k) {
                const double radius = 1 + 0.1 * k;
                h.positions.push_back({radius * std::cos(a), radius * std::sin(a), z});
            }
        }
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < 2; ++k) {
                const std::uint32_t a = std::uint32_t(3 * i + k), b = a + 1, c = a + 3, d = a + 4;
                h.triangles.push_back({a, b, d});
                h.triangles.push_back({a, d, c});
            }
        return h;
    };
    const inkline::MeshTopology stacked = inkline::build_topology(helix(0));
    EXPECT_EQ(inkline::self_intersections(stacked).flagged, 0u);
    expect_same_as_every_pair(stacked, "two turns of a helix", 1);
    const inkline::MeshTopology pierced = inkline::build_topology(helix(0.05));
    EXPECT_GT(inkline::self_intersections(pierced).flagged, 0u);
    EXPECT_EQ(inkline::self_intersections(pierced).faces, reference(pierced));
    expect_same_as_every_pair(pierced, "a helix that passes through itself", 1);
}

// Two pieces in one node of the search (80 faces, so the node is tried whole): a flat 6 x 6 grid
// and a small 2 x 2 grid tilted 30 degrees that passes through its middle. Every normal is within
// 30 degrees of +z and neither boundary crosses the other in the projection (the grids' points
// are moved a little so that the test does not refuse the node for three boundary points on a
// line), but the small one's
// lies inside the big one's: the patch test must refuse the node (the cycles nest), and the
// search finds the crossing faces, as testing every pair does.
TEST(SelfIntersections, PatchTestRefusesNestedPieces) {
    TriangleMesh m;
    const auto grid = [&m](int n, double size, const glm::dvec3& origin, const glm::dvec3& along, const glm::dvec3& across) {
        const auto first = std::uint32_t(m.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                // (moved a little within the grid's plane, so that no three boundary points line up)
                const double di = 0.05 * std::sin(7.0 * i + 3.0 * j), dj = 0.05 * std::cos(5.0 * i + 11.0 * j);
                m.positions.push_back(origin + size * ((i + di) * along + (j + dj) * across) / double(n));
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const std::uint32_t a = first + std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
                m.triangles.push_back({a, b, d});
                m.triangles.push_back({a, d, c});
            }
    };
    grid(6, 6.0, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const double c30 = std::cos(M_PI / 6), s30 = std::sin(M_PI / 6);
    grid(2, 1.0, {2.5, 2.5, -0.25}, {c30, 0, s30}, {0, 1, 0});  // from z = -0.25 to +0.25 over x 2.5..3.37
    const inkline::MeshTopology t = inkline::build_topology(m);
    const inkline::SelfIntersections got = inkline::self_intersections(t);
    EXPECT_EQ(got.faces, reference(t));
    EXPECT_GT(got.flagged, 0u);
    expect_same_as_every_pair(t, "a tilted square through a flat grid", 1);
}

// Heap bytes in use, and their peak, as this test program's operator new sees them (the
// aligned and array forms end in these two); for the search's memory a face below.
namespace heap {
std::atomic<std::size_t> live{0}, peak{0};
void count(std::size_t bytes) {
    const std::size_t now = live.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    std::size_t old = peak.load(std::memory_order_relaxed);
    while (now > old && !peak.compare_exchange_weak(old, now, std::memory_order_relaxed)) {
    }
}
}  // namespace heap

void* operator new(std::size_t size) {
    void* p = std::malloc(size == 0 ? 1 : size);
    if (!p) throw std::bad_alloc();
    heap::count(malloc_usable_size(p));
    return p;
}
void operator delete(void* p) noexcept {
    if (p) heap::live.fetch_sub(malloc_usable_size(p), std::memory_order_relaxed);
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }

// What the search keeps a face at its peak, started early (as Model::load does) and on the
// topology, for a surface that does not intersect itself (the usual case; one that does pays
// besides for CGAL's listing of the pairs): no record of the face (its plane is made from the
// mesh's arrays where a test needs it) and no copy of the mesh's arrays. Per box 28 bytes (six
// float bounds and the face's number), per face its flag (1), while the tree is built each box's
// Hilbert key (8), and the nodes: 40 bytes each, at most two a box (a leaf holds one box or
// more). So at most 28 + 1 + 8 + 80 = 117 bytes a face, and about 70 for a smooth surface (about
// 0.7 nodes a box); a per-face record (136 bytes before, plus 36 of copies) cannot fit. (On two
// threads, as Model::load runs it: on one, the root's task tests the biggest patches itself,
// whose edge table, up to 24 bytes a face of the patch, the thread keeps for its next search.)
TEST(SelfIntersections, MemoryAFace) {
    const TriangleMesh s = inkline::hilbert_ordered(inkline::make_sphere({0, 0, 0}, 1, 256, 128));  // 65 024 faces
    const inkline::MeshTopology t = inkline::build_topology(s);
    const double faces = double(t.face_count());
    const auto peak_a_face = [&](const auto& search) {
        const std::size_t before = heap::live.load();
        heap::peak.store(before);
        const inkline::SelfIntersections si = search();
        EXPECT_EQ(si.flagged, 0u);
        return double(heap::peak.load() - before) / faces;
    };
    const double early = peak_a_face([&] {
        inkline::EarlySelfIntersections search({s.positions.data(), s.triangles.data(), s.triangles.size(), s.positions.size()}, 2);
        return search.finish(t);
    });
    const double plain = peak_a_face([&] { return inkline::self_intersections(t, 2); });
    std::printf("[self-intersections] peak heap a face: started early %.1f bytes, on the topology %.1f\n", early, plain);
    EXPECT_LT(early, 117.0);
    EXPECT_LT(plain, 117.0);
}
