// build_pieces into a recycled PieceGraph (the storage of earlier views reused, as ViewSession and
// the benchmarks run it) gives exactly what a fresh build gives, view after view: more pieces, then
// fewer, another mesh in between, one or two threads; and the pipeline's session views equal
// render_view's.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <latch>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/predicates.hpp"
#include "core/worker_thread.hpp"
#include "pipeline.hpp"
#include "random_camera.hpp"
#include "test_data.hpp"
#include "visibility/appel.hpp"
#include "visibility/crossings.hpp"

namespace inkline {
namespace {

// The stages' second halves (build_pieces, the fast method's ends and walks) run on a worker kept
// from view to view: both halves run, the worker's on one thread of its own every time, and an
// exception of either half comes out only after both are done (the halves share the caller's locals).
TEST(WorkerThread, ForkJoinRunsBothHalvesOnOneKeptThread) {
    WorkerThread w;
    std::thread::id first{}, second{};
    int here = 0, there = 0;
    w.fork_join([&] { ++there, first = std::this_thread::get_id(); }, [&] { ++here; });
    w.fork_join([&] { ++there, second = std::this_thread::get_id(); }, [&] { ++here; });
    EXPECT_EQ(here, 2);
    EXPECT_EQ(there, 2);
    EXPECT_NE(first, std::this_thread::get_id());
    EXPECT_EQ(first, second);

    EXPECT_THROW(w.fork_join([] { throw std::runtime_error("there"); }, [&] { ++here; }), std::runtime_error);
    EXPECT_EQ(here, 3);
    std::atomic<bool> finished{false};
    EXPECT_THROW(w.fork_join(
                     [&] {
                         std::this_thread::sleep_for(std::chrono::milliseconds(20));
                         finished = true;
                     },
                     [] { throw std::runtime_error("here"); }),
                 std::runtime_error);
    EXPECT_TRUE(finished);  // (the worker's half was waited for)
    w.fork_join([&] { ++there; }, [] {});  // still usable
    EXPECT_EQ(there, 3);
}

bool same_spans(const std::vector<EdgeSpan>& a, const std::vector<EdgeSpan>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].edge != b[i].edge || a[i].s0 != b[i].s0 || a[i].s1 != b[i].s1) return false;
    return true;
}

bool same_piece(const Piece& a, const Piece& b) {
    return a.kind == b.kind && a.qi == b.qi && a.curve == b.curve && a.points == b.points;
}

// Every field of the two graphs (pieces with their QI, spans, links, crossings, ends, occluders).
void expect_same_graph(const PieceGraph& a, const PieceGraph& b, const std::string& at) {
    ASSERT_EQ(a.curves.pieces.size(), b.curves.pieces.size()) << at;
    ASSERT_EQ(a.curves.spans.size(), b.curves.spans.size()) << at;
    EXPECT_EQ(a.curves.crossings, b.curves.crossings) << at;
    for (std::size_t p = 0; p < a.curves.pieces.size(); ++p) {
        ASSERT_TRUE(same_piece(a.curves.pieces[p], b.curves.pieces[p])) << at << " piece " << p;
        ASSERT_TRUE(same_spans(a.curves.spans[p], b.curves.spans[p])) << at << " piece " << p;
    }
    ASSERT_EQ(a.links.size(), b.links.size()) << at;
    for (std::size_t l = 0; l < a.links.size(); ++l)
        ASSERT_TRUE(a.links[l].before == b.links[l].before && a.links[l].after == b.links[l].after) << at;
    ASSERT_EQ(a.link_crossings.size(), b.link_crossings.size()) << at;
    for (std::size_t c = 0; c < a.link_crossings.size(); ++c) {
        const auto &x = a.link_crossings[c], &y = b.link_crossings[c];
        ASSERT_TRUE(x.link == y.link && x.occluder == y.occluder && x.seg == y.seg && x.t == y.t && x.c1 == y.c1 &&
                    x.c2 == y.c2 && x.occluder_edge == y.occluder_edge && x.occluder_s == y.occluder_s &&
                    x.delta == y.delta)
            << at << " crossing " << c;
    }
    ASSERT_EQ(a.ends.size(), b.ends.size()) << at;
    for (std::size_t e = 0; e < a.ends.size(); ++e)
        ASSERT_TRUE(a.ends[e].piece == b.ends[e].piece && a.ends[e].vertex == b.ends[e].vertex &&
                    a.ends[e].edge == b.ends[e].edge)
            << at;
    ASSERT_EQ(a.occluders.size(), b.occluders.size()) << at;
    for (std::size_t k = 0; k < a.occluders.size(); ++k)
        ASSERT_TRUE(a.occluders[k].a == b.occluders[k].a && a.occluders[k].b == b.occluders[k].b &&
                    a.occluders[k].edge == b.occluders[k].edge && a.occluders[k].slack == b.occluders[k].slack)
            << at;
    EXPECT_EQ(a.extreme_vertices, b.extreme_vertices) << at;
    EXPECT_EQ(a.immersive, b.immersive) << at;
    EXPECT_EQ(a.image_size, b.image_size) << at;
}

// The model's lazy parts (the ray-test index, the self-intersections) are built once when two
// threads ask for them at the same time, as the preview window's two sessions may: both get the
// same object, and both use it (a second build would replace, and free, what the first thread got).
TEST(Model, LazyPartsAreBuiltOnceWhenTwoThreadsAskAtOnce) {
    for (int round = 0; round < 3; ++round) {
        const Model bunny = Model::load(test::mesh_path("bunny00"));
        const glm::dvec3 far = bunny.topology().bounds.center() + 10.0 * glm::dvec3(bunny.topology().bounds.half_diagonal());
        std::latch start(2);
        const RayCaster* rays[2] = {nullptr, nullptr};
        const SelfIntersections* si[2] = {nullptr, nullptr};
        int layers[2] = {-1, -1};
        const auto ask = [&](int k) {
            start.arrive_and_wait();
            rays[k] = &bunny.rays();
            si[k] = &bunny.self_intersections();
            layers[k] = rays[k]->count_layers(far, bunny.topology().bounds.center(), kNoFace, kNoFace);
        };
        std::thread other(ask, 1);
        ask(0);
        other.join();
        EXPECT_EQ(rays[0], rays[1]);
        EXPECT_EQ(si[0], si[1]);
        EXPECT_EQ(layers[0], layers[1]);
        EXPECT_GE(layers[0], 1);  // (the segment ends inside the closed surface)
    }
}

TEST(BuildPieces, RecycledGraphEqualsFreshBuilds) {
    const Model armadillo = Model::load(test::mesh_path("armadillo"));
    const Model bunny = Model::load(test::mesh_path("bunny00"));
    std::mt19937 rng(5u);
    PieceGraph recycled;  // one graph through every view
    std::size_t previous = 0, fewer = 0, more = 0, walks = 0;
    for (int k = 0; k < 12; ++k) {
        const Model& model = k == 5 ? bunny : armadillo;  // (another vertex count in between)
        const MeshTopology& mesh = model.topology();
        const SelfIntersections& si = model.self_intersections();
        Camera cam = test::framed_then_random(k, rng, mesh.bounds, 0.3, 1.2);
        cam.set_near(default_near(mesh));
        const Features f = extract_features(mesh, cam);
        const int threads = k % 3 == 2 ? 2 : 1;  // (two threads: the second range's slots swapped in)
        const std::string at = "view " + std::to_string(k);
        PieceGraph fresh = build_pieces(mesh, f, cam, &si.cuts, threads, 0);
        build_pieces(recycled, mesh, f, cam, &si.cuts, threads, 0);
        expect_same_graph(fresh, recycled, at + " (pieces)");
        // The QI by propagation on each (walks use the occluder grid, rebuilt for the view).
        auto rays = [&]() -> const RayCaster& { return model.rays(); };
        const AppelStats s1 = assign_qi_appel(mesh, cam, f.face_front, rays, fresh, {false, &si.faces, true, 1});
        const AppelStats s2 = assign_qi_appel(mesh, cam, f.face_front, rays, recycled, {false, &si.faces, true, 1});
        EXPECT_EQ(s1.walks, s2.walks) << at;
        EXPECT_EQ(s1.ray_tests, s2.ray_tests) << at;
        EXPECT_EQ(s1.clusters, s2.clusters) << at;
        expect_same_graph(fresh, recycled, at + " (QI)");
        const std::size_t n = fresh.curves.pieces.size();
        if (k > 0) (n < previous ? fewer : more) += 1;
        previous = n;
        walks += s1.walks;
    }
    // The sequence had views with fewer pieces than the one before, and with more.
    EXPECT_GT(fewer, 0u);
    EXPECT_GT(more, 0u);
    EXPECT_GT(walks, 0u);
}

// Silhouette-against-silhouette pairs tested once for both segments (mirror_pairs, the default)
// give exactly the graph of testing each pair on its own: every piece, split parameter, link
// crossing (with where it lies on the occluder) and crossing count, bit for bit. Random views of
// several meshes, perspective and orthographic, the near plane through the model in some (curve
// segments clipped: not mirrored), one thread or two (pairs across the ranges: not mirrored), with
// the self-intersection cuts.
TEST(BuildPieces, MirroredSilhouettePairsGiveTheSameGraph) {
    std::size_t views = 0, silhouette_crossings = 0;
    for (const char* name : {"armadillo", "bunny00", "knot1", "elephant", "fandisk"}) {
        const Model model = Model::load(test::mesh_path(name));
        const MeshTopology& mesh = model.topology();
        const SelfIntersections& si = model.self_intersections();
        std::mt19937 rng(23u);
        for (int k = 0; k < 12; ++k) {
            Camera cam = test::framed_then_random(k, rng, mesh.bounds, 0.3, 1.2);
            if (k % 4 == 3) {  // (orthographic, from the same eye)
                const double R = mesh.bounds.half_diagonal();
                cam = Camera::orthographic(cam.eye(), mesh.bounds.center(), std::abs(cam.forward().y) > 0.95
                                           ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0), 2.2 * R, 1024, 1024);
            }
            cam.set_near(k % 3 == 1 ? std::max(cam.depth(mesh.bounds.center()), default_near(mesh)) : default_near(mesh));
            const Features f = extract_features(mesh, cam);
            const int threads = k % 2 ? 2 : 1;
            const std::string at = std::string(name) + " view " + std::to_string(k);
            PieceGraph mirrored, each;
            build_pieces(mirrored, mesh, f, cam, &si.cuts, threads, 0, true);
            build_pieces(each, mesh, f, cam, &si.cuts, threads, 0, false);
            expect_same_graph(mirrored, each, at);
            // (crossings of a silhouette piece with a silhouette occluder: the pairs mirrored)
            std::vector<std::uint32_t> sil(f.silhouette_edges.begin(), f.silhouette_edges.end());
            std::sort(sil.begin(), sil.end());
            for (const auto& c : mirrored.link_crossings)
                silhouette_crossings += mirrored.curves.pieces[mirrored.links[c.link].before].kind == LineKind::Silhouette &&
                                        std::binary_search(sil.begin(), sil.end(), c.occluder_edge);
            ++views;
        }
    }
    EXPECT_EQ(views, 60u);
    EXPECT_GT(silhouette_crossings, 10000u);
}

// Every piece's stretch is its mesh edge's part clipped to the camera's near plane, in travel
// order: the image points are the projections of the span's ends on the edge, and no end lies in
// front of the near plane, and consecutive spans meet on the surface. With the near plane through the model (curves clipped there while the
// occluders, clipped only at the default near plane, are not) and without; silhouette edges
// are walked in either direction along their curves.
TEST(BuildPieces, PiecesAreTheirEdgesClippedAndProjected) {
    const Model armadillo = Model::load(test::mesh_path("armadillo"));
    const MeshTopology& mesh = armadillo.topology();
    std::mt19937 rng(11u);
    std::size_t clipped = 0, spans = 0;
    for (int k = 0; k < 8; ++k) {
        Camera cam = test::framed_then_random(k, rng, mesh.bounds, 0.3, 1.2);
        cam.set_near(k % 2 ? std::max(cam.depth(mesh.bounds.center()), default_near(mesh)) : default_near(mesh));
        const Features f = extract_features(mesh, cam);
        const PieceGraph g = build_pieces(mesh, f, cam, nullptr, k % 4 == 3 ? 2 : 1, 0);
        for (std::size_t p = 0; p < g.curves.pieces.size(); ++p) {
            const Piece& piece = g.curves.pieces[p];
            const auto& sp = g.curves.spans[p];
            ASSERT_EQ(piece.points.size(), sp.size() + 1);
            glm::dvec3 last_end(0.0);
            for (std::size_t i = 0; i < sp.size(); ++i) {
                const auto [v0, v1] = mesh.edge_vertex[sp[i].edge];
                const glm::dvec3 E0 = mesh.positions[v0], E1 = mesh.positions[v1];
                const glm::dvec3 start = E0 + sp[i].s0 * (E1 - E0);
                if (i > 0) {
                    ASSERT_LE(glm::length(start - last_end), 1e-9 * mesh.bounds.half_diagonal())
                        << "view " << k << " piece " << p << " span " << i;
                }
                last_end = E0 + sp[i].s1 * (E1 - E0);
                // In travel order: along the edge from the curve's vertex before it.
                const FeatureCurve& curve = f.curves[piece.curve];
                const auto at = std::find(curve.edges.begin(), curve.edges.end(), sp[i].edge);
                ASSERT_NE(at, curve.edges.end());
                const bool forward = curve.vertices[std::size_t(at - curve.edges.begin())] == v0;
                ASSERT_TRUE(forward ? sp[i].s0 <= sp[i].s1 : sp[i].s0 >= sp[i].s1)
                    << "view " << k << " piece " << p << " span " << i;
                for (int end = 0; end < 2; ++end) {
                    const double s = end ? sp[i].s1 : sp[i].s0;
                    const glm::dvec3 X = E0 + s * (E1 - E0);
                    const double z = cam.depth(X);
                    ASSERT_GE(z, cam.near_distance() * (1.0 - 1e-9)) << "view " << k << " piece " << p;
                    if (std::abs(z - cam.near_distance()) <= 1e-9 * cam.near_distance()) ++clipped;
                    const glm::dvec2 x = cam.project(X), q = piece.points[i + end];
                    const double tol = 1e-7 * (1.0 + std::abs(x.x) + std::abs(x.y));
                    ASSERT_NEAR(q.x, x.x, tol) << "view " << k << " piece " << p << " span " << i;
                    ASSERT_NEAR(q.y, x.y, tol) << "view " << k << " piece " << p << " span " << i;
                }
                ++spans;
            }
        }
    }
    EXPECT_GT(clipped, 0u);  // (the near plane cut curves)
    EXPECT_GT(spans, 10000u);
}

// A ViewSession along a camera path (the graph and the drawing's storage swapped from view to
// view) gives the drawing render_view gives, also with hidden lines' exact QI, and when the
// silhouettes are chained only for propagation and then dropped (fandisk's creases drawn).
TEST(ViewSession, RecycledViewsEqualRenderView) {
    const Model armadillo = Model::load(test::mesh_path("armadillo"));
    const Model fandisk = Model::load(test::mesh_path("fandisk"));
    for (int variant = 0; variant < 3; ++variant) {
        const Model& model = variant == 2 ? fandisk : armadillo;
        ViewOptions o;
        o.exact_hidden = variant == 1;
        if (variant == 2) o.features.kinds[int(LineKind::Silhouette)] = false;
        ViewSession session(model, o);
        std::mt19937 rng(9u);
        std::size_t previous = 0, fewer = 0;
        for (int k = 0; k < 6; ++k) {
            const Camera cam = test::framed_then_random(k, rng, model.topology().bounds, 0.3, 1.2);
            const std::string at = "variant " + std::to_string(variant) + " view " + std::to_string(k);
            const View fresh = render_view(model, cam, o);
            const View& v = session.render(cam);
            ASSERT_EQ(v.drawing.pieces.size(), fresh.drawing.pieces.size()) << at;
            ASSERT_EQ(v.spans.size(), fresh.spans.size()) << at;
            for (std::size_t p = 0; p < v.drawing.pieces.size(); ++p) {
                ASSERT_TRUE(same_piece(v.drawing.pieces[p], fresh.drawing.pieces[p])) << at << " piece " << p;
                ASSERT_TRUE(same_spans(v.spans[p], fresh.spans[p])) << at << " piece " << p;
            }
            EXPECT_EQ(v.drawing.stats.pieces, fresh.drawing.stats.pieces) << at;
            EXPECT_EQ(v.drawing.stats.crossings, fresh.drawing.stats.crossings) << at;
            EXPECT_EQ(v.drawing.stats.walks, fresh.drawing.stats.walks) << at;
            EXPECT_EQ(v.drawing.stats.ray_tests, fresh.drawing.stats.ray_tests) << at;
            if (variant != 2) {
                if (k > 0 && fresh.drawing.pieces.size() < previous) ++fewer;
                previous = fresh.drawing.pieces.size();
            } else {
                EXPECT_GT(v.drawing.pieces.size(), 0u) << at;
                for (const Piece& p : v.drawing.pieces) ASSERT_NE(p.kind, LineKind::Silhouette) << at;
            }
        }
        if (variant != 2) {
            EXPECT_GT(fewer, 0u) << "variant " << variant;
        }
    }
}

}  // namespace
}  // namespace inkline
