// The frame on N threads (docs/threads.md): the work split among threads and merged in part order,
// so every thread count draws exactly what one thread draws, bit for bit.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "core/worker_thread.hpp"
#include "model/subdivide.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"

namespace inkline {
namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every piece equal: kind, curve, QI, object, every point's bits, every span.
void expect_same_pieces(const std::vector<Piece>& a, const std::vector<std::vector<EdgeSpan>>& as,
                        const std::vector<Piece>& b, const std::vector<std::vector<EdgeSpan>>& bs, const std::string& at) {
    ASSERT_EQ(a.size(), b.size()) << at;
    ASSERT_EQ(as.size(), bs.size()) << at;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string where = at + " piece " + std::to_string(i);
        ASSERT_EQ(a[i].kind, b[i].kind) << where;
        ASSERT_EQ(a[i].curve, b[i].curve) << where;
        ASSERT_EQ(a[i].qi, b[i].qi) << where;
        ASSERT_EQ(a[i].object, b[i].object) << where;
        ASSERT_EQ(a[i].points.size(), b[i].points.size()) << where;
        for (std::size_t k = 0; k < a[i].points.size(); ++k)
            ASSERT_TRUE(same_bits(a[i].points[k].x, b[i].points[k].x) && same_bits(a[i].points[k].y, b[i].points[k].y))
                << where << " point " << k;
        ASSERT_EQ(as[i].size(), bs[i].size()) << where;
        for (std::size_t k = 0; k < as[i].size(); ++k)
            ASSERT_TRUE(as[i][k].edge == bs[i][k].edge && same_bits(as[i][k].s0, bs[i][k].s0) &&
                        same_bits(as[i][k].s1, bs[i][k].s1))
                << where << " span " << k;
    }
}

TEST(WorkerTeam, RunsEveryPartOnceAndRethrowsTheFirstPartsError) {
    WorkerTeam team;
    for (int parts : {1, 2, 3, 8, 5}) {  // (grows, then runs on fewer of its workers)
        std::vector<int> runs(static_cast<std::size_t>(parts), 0);  // (each part its own element)
        team.run(parts, [&](int i) { ++runs[std::size_t(i)]; });
        for (int i = 0; i < parts; ++i) EXPECT_EQ(runs[std::size_t(i)], 1) << parts << " parts, part " << i;
    }
    // Parts 2 and 5 throw: part 2's error comes out (part order), after every part has run.
    std::atomic<int> ran{0};
    try {
        team.run(6, [&](int i) {
            ++ran;
            if (i == 2 || i == 5) throw std::runtime_error("part " + std::to_string(i));
        });
        ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "part 2");
    }
    EXPECT_EQ(ran.load(), 6);
}

// The same graph: crossing count, occluders, pieces, links, link crossings, curve ends.
void expect_same_graph(const PieceGraph& many, const PieceGraph& one, const std::string& at) {
    EXPECT_EQ(many.curves.crossings, one.curves.crossings) << at;
    EXPECT_EQ(many.occluders.size(), one.occluders.size()) << at;
    EXPECT_EQ(many.extreme_vertices, one.extreme_vertices) << at;
    EXPECT_EQ(many.immersive, one.immersive) << at;
    expect_same_pieces(many.curves.pieces, many.curves.spans, one.curves.pieces, one.curves.spans, at);
    ASSERT_EQ(many.links.size(), one.links.size()) << at;
    for (std::size_t i = 0; i < one.links.size(); ++i)
        ASSERT_TRUE(many.links[i].before == one.links[i].before && many.links[i].after == one.links[i].after)
            << at << " link " << i;
    ASSERT_EQ(many.link_crossings.size(), one.link_crossings.size()) << at;
    for (std::size_t i = 0; i < one.link_crossings.size(); ++i) {
        const auto &x = many.link_crossings[i], &y = one.link_crossings[i];
        ASSERT_TRUE(x.link == y.link && x.occluder == y.occluder && x.occluder_edge == y.occluder_edge &&
                    same_bits(x.t, y.t) && same_bits(x.occluder_s, y.occluder_s))
            << at << " link crossing " << i;
    }
    ASSERT_EQ(many.ends.size(), one.ends.size()) << at;
    for (std::size_t i = 0; i < one.ends.size(); ++i)
        ASSERT_TRUE(many.ends[i].piece == one.ends[i].piece && many.ends[i].vertex == one.ends[i].vertex &&
                    many.ends[i].edge == one.ends[i].edge)
            << at << " end " << i;
}

// build_pieces with every view split (parallel_edges 0: ranges of any size) among 2, 3 and 8
// threads gives one thread's graph: pieces, links, link crossings, curve ends, crossing count.
TEST(Threads, BuildPiecesOnManyThreadsEqualsOne) {
    std::size_t views = 0;
    for (const char* name : {"armadillo", "bunny00", "knot1", "fandisk"}) {
        const Model model = Model::load(test::mesh_path(name));
        const MeshTopology& mesh = model.topology();
        std::mt19937 rng(5u);
        for (int k = 0; k < 4; ++k) {
            Camera cam = test::framed_then_random(k, rng, mesh.bounds, 0.3, 1.2);
            cam.set_near(default_near(mesh));
            const Features f = extract_features(mesh, cam);
            PieceGraph one;
            build_pieces(one, mesh, f, cam, &model.self_intersections().cuts, 1, 0);
            for (int threads : {2, 3, 8}) {
                const std::string at = std::string(name) + " view " + std::to_string(k) + ", " +
                                       std::to_string(threads) + " threads";
                PieceGraph many;
                for (int again = 0; again < 2; ++again)  // (the second build into recycled storage)
                    build_pieces(many, mesh, f, cam, &model.self_intersections().cuts, threads, 0);
                expect_same_graph(many, one, at);
            }
            ++views;
        }
    }
    EXPECT_EQ(views, 16u);
}

// The occluders started ahead on the helper thread (start_occluders, as a session on two threads
// does while it chains the curves) give one thread's graph; started for another view (other
// features and camera), or dropped, build_pieces makes them again: one thread's graph still.
TEST(Threads, OccludersStartedAheadGiveTheSameGraph) {
    for (const char* name : {"armadillo", "bunny00", "knot1"}) {
        const Model model = Model::load(test::mesh_path(name));
        const MeshTopology& mesh = model.topology();
        const auto* cuts = &model.self_intersections().cuts;
        std::mt19937 rng(9u);
        Camera other = test::framed_then_random(1, rng, mesh.bounds, 0.3, 1.2);
        other.set_near(default_near(mesh));
        const Features f_other = extract_features(mesh, other);
        PieceGraph ahead, stale;
        for (int k = 0; k < 3; ++k) {
            Camera cam = test::framed_then_random(k, rng, mesh.bounds, 0.3, 1.2);
            cam.set_near(default_near(mesh));
            const Features f = extract_features(mesh, cam);
            PieceGraph one;
            build_pieces(one, mesh, f, cam, cuts, 1, 0);
            const std::string at = std::string(name) + " view " + std::to_string(k);
            for (int threads : {1, 2, 3}) {
                start_occluders(ahead, mesh, f, cam);
                build_pieces(ahead, mesh, f, cam, cuts, threads, 0);
                expect_same_graph(ahead, one, at + ", started ahead, " + std::to_string(threads) + " threads");
            }
            start_occluders(stale, mesh, f_other, other);
            build_pieces(stale, mesh, f, cam, cuts, 2, 0);
            expect_same_graph(stale, one, at + ", started for another view");
            start_occluders(stale, mesh, f, cam);
            stale.drop_started_occluders();  // (as a session does before its next view's features)
            build_pieces(stale, mesh, f, cam, cuts, 2, 0);
            expect_same_graph(stale, one, at + ", started, then dropped");
        }
    }
}

// Whole frames (exhaustive finder, Appel visibility; visible lines with walks, and exact hidden
// QI) along a few cameras, one session per thread count (storage recycled from view to view):
// 2, 3 and 8 threads draw exactly what one thread draws, and count the same crossings, clusters,
// walks and ray tests.
void expect_frames_equal_one_thread(const Model& model, const std::string& name, int cameras,
                                    std::size_t* most_crossings = nullptr, std::size_t* most_walks = nullptr) {
    const MeshTopology& mesh = model.topology();
    for (bool exact_hidden : {false, true}) {
        std::vector<ViewSession> sessions;
        for (int threads : {1, 2, 3, 8}) {
            ViewOptions o;
            o.exact_hidden = exact_hidden;
            o.threads = threads;
            sessions.emplace_back(model, o);
        }
        std::mt19937 rng(17u);
        for (int k = 0; k < cameras; ++k) {
            const Camera cam = test::framed_then_random(k, rng, mesh.bounds);
            const View& one = sessions[0].render(cam);
            const DrawingStats& s1 = one.drawing.stats;
            if (most_crossings) *most_crossings = std::max(*most_crossings, s1.crossings);
            if (most_walks) *most_walks = std::max(*most_walks, s1.walks);
            for (std::size_t t = 1; t < sessions.size(); ++t) {
                const View& many = sessions[t].render(cam);
                const std::string at = name + " camera " + std::to_string(k) + (exact_hidden ? " hidden" : " visible") +
                                       ", session " + std::to_string(t);
                const DrawingStats& s = many.drawing.stats;
                EXPECT_EQ(s.silhouette_edges, s1.silhouette_edges) << at;
                EXPECT_EQ(s.crossings, s1.crossings) << at;
                EXPECT_EQ(s.clusters, s1.clusters) << at;
                EXPECT_EQ(s.walks, s1.walks) << at;
                EXPECT_EQ(s.ray_tests, s1.ray_tests) << at;
                expect_same_pieces(many.drawing.pieces, many.spans, one.drawing.pieces, one.spans, at);
            }
        }
    }
}

TEST(Threads, FramesEqualOneThreadOnSampleMeshes) {
    for (const char* name : {"armadillo", "bunny00", "elephant.off", "ChineseDragon-10kv", "knot1", "fandisk", "3torus"}) {
        const Model model = Model::load(test::mesh_path(name));
        expect_frames_equal_one_thread(model, name, 4);
    }
}

// A large model (armadillo subdivided twice, 832 k triangles), so that every split stage runs on
// all 8 threads: its framed view has enough curve edges for 8 ranges of pieces (2000 edges a
// range), crossings and curve ends for 8 parts each (1000 a part), and walks for 8 threads (4 a
// thread); those sizes pinned.
TEST(Threads, FramesOfALargeModelEqualOneThread) {
    const Model model = Model::load(test::mesh_path("armadillo"), 40.0, 2);
    std::size_t most_crossings = 0, most_walks = 0;
    expect_frames_equal_one_thread(model, "armadillo@2", 3, &most_crossings, &most_walks);
    EXPECT_EQ(most_crossings, 8852u);  // (8 parts of crossings: 1000 a part)
    EXPECT_EQ(most_walks, 66u);  // (8 threads of walks: 4 a thread)
}

// The flag, once defined for every command: 0, negative, too many, fractions and words are usage
// errors (exit 2) with one line naming the flag; nothing is drawn.
TEST(Threads, BadValuesOfTheFlagAreUsageErrors) {
    const std::filesystem::path err = std::filesystem::temp_directory_path() / "inkline_test_threads_err.txt";
    const std::string mesh = test::mesh_path("knot1");
    const std::string range = "inkline: --threads: expected an integer from 1 to 256\n";
    const struct {
        std::string args, message;
    } cases[] = {
        {"render " + mesh + " --threads=0 -o /nonexistent/x.svg", range},
        {"render " + mesh + " --threads=-2 -o /nonexistent/x.svg", range},
        {"render " + mesh + " --threads=257 -o /nonexistent/x.svg", range},
        {"render " + mesh + " --threads=1000000000 -o /nonexistent/x.svg", range},
        {"render " + mesh + " --threads=2.5 -o /nonexistent/x.svg", range},
        {"render " + mesh + " --threads=many -o /nonexistent/x.svg", "inkline: --threads: expected a number, got 'many'\n"},
        {"view " + mesh + " --threads=0", range},
        {"bench " + mesh + " --threads=-1", range},
    };
    for (const auto& c : cases) {
        const int status = std::system((std::string(INKLINE_BINARY) + " " + c.args + " > /dev/null 2> " + err.string()).c_str());
        ASSERT_TRUE(WIFEXITED(status)) << c.args;
        EXPECT_EQ(WEXITSTATUS(status), 2) << c.args;
        std::ostringstream text;
        text << std::ifstream(err).rdbuf();
        EXPECT_EQ(text.str(), c.message) << c.args;
    }
    std::filesystem::remove(err);
}

}  // namespace
}  // namespace inkline
