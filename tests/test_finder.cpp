// The randomized seed-and-seek finder (Markosian et al. 97, section 4.1) against the exhaustive
// one: identical at fraction 1, only true silhouettes ever, whole curves traced, frame coherence
// on a static camera, deterministic runs, and a floor on the recall of silhouette length.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <tuple>

#include <glm/geometric.hpp>

#include "model/primitives.hpp"
#include "model/reorder.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"

namespace inkline {
namespace {

const char* kMeshes[] = {"fandisk", "bunny00", "armadillo", "elephant", "ChineseDragon-10kv", "knot1"};

const Model& mesh_model(const std::string& name) {
    static std::map<std::string, Model> cache;
    auto it = cache.find(name);
    if (it == cache.end()) {
        const std::string path = test::mesh_path(name);
        if (!std::filesystem::exists(path)) throw std::runtime_error(path + " missing: run scripts/setup.sh");
        it = cache.emplace(name, Model::load(path)).first;
    }
    return it->second;
}

std::vector<Camera> cameras(const Bounds3& box) {
    std::vector<Camera> out{test::framed_camera(box)};
    const glm::dvec3 c = box.center();
    const double d = 3.0 * box.half_diagonal();
    out.push_back(Camera::perspective(c + glm::dvec3(-d, 0.3 * d, -0.5 * d), c, {0, 1, 0}, 35, 800, 600));
    out.push_back(Camera::orthographic(c + glm::dvec3(0.2 * d, d, 0.4 * d), c, {0, 0, 1}, 2.2 * box.half_diagonal(), 640, 640));
    return out;
}

// A UV sphere scaled and moved far from the origin (the filters' extremes), and its cameras plus
// one with the eye in the plane of face 5 up to rounding (on the line through two of its corners).
Model scaled_sphere(int slices, int stacks, double scale, double offset) {
    TriangleMesh s = make_sphere({0, 0, 0}, 1.0, slices, stacks);
    for (auto& p : s.positions) p = p * scale + glm::dvec3(offset, -offset, 0.5 * offset);
    return Model(s);
}
std::vector<Camera> cameras_with_grazing(const MeshTopology& t) {
    std::vector<Camera> cams = cameras(t.bounds);
    const auto& f5 = t.faces[5];
    const glm::dvec3 a = t.positions[f5[0]], b = t.positions[f5[1]];
    cams.push_back(Camera::perspective(a + 3.0 * (a - b), t.bounds.center(), {0, 1, 0}, 40, 256, 256));
    return cams;
}

std::vector<std::uint32_t> sorted(std::vector<std::uint32_t> v) {
    std::sort(v.begin(), v.end());
    return v;
}

// Curves as sorted edge lists with their kind and closedness, in sorted order (start vertices and
// list order depend on the order edges were found in).
std::vector<std::tuple<int, bool, std::vector<std::uint32_t>>> canonical_curves(const Features& f) {
    std::vector<std::tuple<int, bool, std::vector<std::uint32_t>>> out;
    for (const auto& c : f.curves) out.emplace_back(int(c.kind), c.closed, sorted({c.edges.begin(), c.edges.end()}));
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::pair<std::uint32_t, int>> canonical_cusps(const Features& f) {
    std::vector<std::pair<std::uint32_t, int>> out;
    for (std::size_t i = 0; i < f.cusp_vertices.size(); ++i) out.emplace_back(f.cusp_vertices[i], int(f.cusp_cases[i]));
    std::sort(out.begin(), out.end());
    return out;
}

// The same lists in the same order and the same chains, vertex for vertex (a finder that
// follows the exhaustive one exactly: the drawing is then the same, piece for piece).
void expect_identical(const Features& a, const Features& b) {
    EXPECT_EQ(a.silhouette_edges, b.silhouette_edges);
    EXPECT_EQ(a.border_edges, b.border_edges);
    EXPECT_EQ(a.crease_edges, b.crease_edges);
    EXPECT_EQ(a.cusp_vertices, b.cusp_vertices);
    ASSERT_EQ(a.curves.size(), b.curves.size());
    for (std::size_t i = 0; i < a.curves.size(); ++i) {
        EXPECT_EQ(a.curves[i].kind, b.curves[i].kind) << i;
        EXPECT_EQ(a.curves[i].closed, b.curves[i].closed) << i;
        EXPECT_TRUE(std::equal(a.curves[i].vertices.begin(), a.curves[i].vertices.end(), b.curves[i].vertices.begin(),
                               b.curves[i].vertices.end())) << i;
    }
}

void expect_same(const Features& a, const Features& b) {
    EXPECT_EQ(sorted(a.silhouette_edges), sorted(b.silhouette_edges));
    EXPECT_EQ(a.border_edges, b.border_edges);
    EXPECT_EQ(a.crease_edges, b.crease_edges);
    EXPECT_EQ(canonical_cusps(a), canonical_cusps(b));
    EXPECT_EQ(canonical_curves(a), canonical_curves(b));
}

FinderOptions randomized(double fraction, bool coherence = false, std::uint64_t seed = 7) {
    FinderOptions o;
    o.kind = FinderKind::Randomized;
    o.fraction = fraction;
    o.coherence = coherence;
    o.seed = seed;
    return o;
}

TEST(Finder, FractionOneEqualsExhaustive) {
    for (const char* name : kMeshes) {
        const Model& m = mesh_model(name);
        for (const Camera& cam : cameras(m.topology().bounds)) {
            SCOPED_TRACE(name);
            const Features ex = extract_features(m.topology(), cam);
            Features rf;
            SilhouetteFinder(m.topology(), randomized(1.0)).find(cam, {}, rf);
            expect_same(ex, rf);
            EXPECT_FALSE(ex.silhouette_edges.empty());
        }
    }
}

// The exhaustive scan split over threads gives the same edges in the same order (and the same
// curves) as on one thread. armadillo@1 so that both passes are actually split.
TEST(Finder, ExhaustiveThreadsSameResult) {
    static const Model sub = Model::load(test::mesh_path("armadillo"), 40.0, 1);
    for (const Model* m : {&sub, &mesh_model("bunny00")}) {
        for (const Camera& cam : cameras(m->topology().bounds)) {
            Features one, two;
            SilhouetteFinder(m->topology()).find(cam, {}, one);
            FinderOptions o;
            o.threads = 2;
            SilhouetteFinder(m->topology(), o).find(cam, {}, two);
            EXPECT_EQ(one.silhouette_edges, two.silhouette_edges);
            EXPECT_FALSE(one.silhouette_edges.empty());
            expect_same(one, two);
        }
    }
}

// Everything the randomized finder reports is a silhouette edge, and what it finds is closed
// under adjacency: every silhouette edge at a vertex of a found one is found.
TEST(Finder, OnlyTrueSilhouettesAndWholeCurves) {
    for (const char* name : kMeshes) {
        const Model& m = mesh_model(name);
        const MeshTopology& t = m.topology();
        for (const Camera& cam : cameras(t.bounds)) {
            SCOPED_TRACE(name);
            const Features ex = extract_features(t, cam);
            std::vector<std::uint8_t> is_sil(t.edge_count(), 0);
            for (auto e : ex.silhouette_edges) is_sil[e] = 1;
            Features rf;
            SilhouetteFinder(t, randomized(0.01)).find(cam, {}, rf);
            std::vector<std::uint8_t> found(t.edge_count(), 0);
            for (auto e : rf.silhouette_edges) {
                EXPECT_TRUE(is_sil[e]) << "edge " << e;
                EXPECT_FALSE(found[e]) << "edge " << e << " reported twice";
                found[e] = 1;
            }
            for (auto e : rf.silhouette_edges)
                for (auto v : t.edge_vertex[e])
                    for (auto k = t.vertex_edge_begin[v]; k < t.vertex_edge_begin[v + 1]; ++k)
                        EXPECT_EQ(found[t.vertex_edges[k]], is_sil[t.vertex_edges[k]]) << "edge " << t.vertex_edges[k];
            // Facing agrees with the exact predicate on every face the finder decided.
            for (std::uint32_t f = 0; f < t.face_count(); f += 97)
                EXPECT_EQ(rf.face_front[f], face_is_front(t, f, cam) ? 1 : 0) << "face " << f;
        }
    }
}

TEST(Finder, StaticCameraCoherence) {
    // A second frame from the same camera keeps every silhouette edge of the first; on a torus,
    // where the first frame finds everything, the two frames are equal.
    const Model torus(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 96, 48));
    for (const Model* m : {&torus, &mesh_model("armadillo"), &mesh_model("bunny00")}) {
        const Camera cam = test::framed_camera(m->topology().bounds);
        SilhouetteFinder finder(m->topology(), randomized(0.01, true));
        Features a, b;
        finder.find(cam, {}, a);
        const auto first = sorted(a.silhouette_edges);
        finder.find(cam, {}, b);
        const auto second = sorted(b.silhouette_edges);
        EXPECT_TRUE(std::includes(second.begin(), second.end(), first.begin(), first.end()));
        if (m == &torus) {
            EXPECT_EQ(first, sorted(extract_features(m->topology(), cam).silhouette_edges));
            expect_same(a, b);
        }
        // Storage reused across views gives the same answer as a fresh one.
        Features fresh;
        SilhouetteFinder again(m->topology(), randomized(0.01, true));
        again.find(cam, {}, fresh);
        again.find(cam, {}, fresh);
        expect_same(b, fresh);
    }
}

TEST(Finder, DeterministicSeed) {
    const Model& m = mesh_model("armadillo");
    const Bounds3 box = m.topology().bounds;
    std::vector<std::vector<std::uint32_t>> runs[2];
    for (auto& run : runs) {
        SilhouetteFinder finder(m.topology(), randomized(0.005, true, 42));
        Features f;
        for (int i = 0; i < 4; ++i) {
            const double az = 0.1 * i;
            const glm::dvec3 dir(std::sin(az), 0.3, std::cos(az));
            finder.find(Camera::perspective(box.center() + 3.0 * box.half_diagonal() * dir, box.center(), {0, 1, 0}, 30, 512, 512), {}, f);
            run.push_back(f.silhouette_edges);  // in the order found
        }
    }
    EXPECT_EQ(runs[0], runs[1]);
    // Another seed draws other edges.
    SilhouetteFinder other(m.topology(), randomized(0.005, true, 43));
    Features f;
    const glm::dvec3 dir(0, 0.3, 1);
    other.find(Camera::perspective(box.center() + 3.0 * box.half_diagonal() * dir, box.center(), {0, 1, 0}, 30, 512, 512), {}, f);
    EXPECT_NE(f.silhouette_edges, runs[0][0]);
}

// A correctness floor, not a speed test: one frame, no previous view, default fraction.
TEST(Finder, RecallFloorOnDefaultViews) {
    for (const char* name : kMeshes) {
        const Model& m = mesh_model(name);
        const Camera cam = test::framed_camera(m.topology().bounds);
        const Features ex = extract_features(m.topology(), cam);
        FinderOptions o;
        o.kind = FinderKind::Randomized;
        Features rf;
        SilhouetteFinder(m.topology(), o).find(cam, {}, rf);
        const double recall = edges_length(m.topology(), rf.silhouette_edges) / edges_length(m.topology(), ex.silhouette_edges);
        EXPECT_GE(recall, 0.95) << name;
        std::printf("%s: recall %.4f at fraction %g (%zu of %zu silhouette edges)\n", name, recall, o.fraction,
                    rf.silhouette_edges.size(), ex.silhouette_edges.size());
    }
}

// Along a slow orbit with coherence and no random draws at all, silhouettes are followed from
// frame to frame by checking the previous edges and seeking from the lost ones.
TEST(Finder, CoherenceAloneFollowsAnOrbit) {
    const Model torus(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 96, 48));
    const Bounds3 box = torus.topology().bounds;
    auto cam = [&](int i) {
        const double az = 0.02 * i;
        const glm::dvec3 dir(std::sin(az), 0.5, std::cos(az));
        return Camera::perspective(box.center() + 3.0 * box.half_diagonal() * dir, box.center(), {0, 1, 0}, 30, 512, 512);
    };
    // Without draws and without a previous view nothing is found: what follows is coherence's work.
    Features g;
    SilhouetteFinder(torus.topology(), randomized(0.0, true)).find(cam(0), {}, g);
    EXPECT_TRUE(g.silhouette_edges.empty());
    SilhouetteFinder cont(torus.topology(), randomized(1.0, true));
    Features h;
    cont.find(cam(0), {}, h);  // the first frame with every edge examined
    cont.set_fraction(0.0);    // then no draws at all
    double worst = 1.0;
    for (int i = 1; i <= 20; ++i) {
        cont.find(cam(i), {}, h);
        const Features ex = extract_features(torus.topology(), cam(i));
        worst = std::min(worst, edges_length(torus.topology(), h.silhouette_edges) /
                                    edges_length(torus.topology(), ex.silhouette_edges));
    }
    EXPECT_GE(worst, 0.999);
}

// With coherence from an exhaustive first view, every later view is the exhaustive answer exactly
// (the band holds every face that can turn): along an orbit (band kept and rebuilt), after a jump,
// for an orthographic camera, and back to perspective. Draws are off, so nothing else could help.
TEST(Finder, CoherenceFromExhaustiveFirstViewIsExact) {
    const Model torus(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 96, 48));
    for (const Model* m : {&torus, &mesh_model("armadillo"), &mesh_model("fandisk")}) {
        const Bounds3 box = m->topology().bounds;
        const glm::dvec3 c = box.center();
        const double d = 3.0 * box.half_diagonal();
        std::vector<Camera> path;
        for (int i = 0; i < 24; ++i) {
            const double az = 0.3 + 0.0175 * i;  // 1 degree per view
            path.push_back(Camera::perspective(c + d * glm::dvec3(std::sin(az), 0.4, std::cos(az)), c, {0, 1, 0}, 30, 640, 480));
        }
        for (int i = 22; i >= 16; --i) path.push_back(path[std::size_t(i)]);  // back (the band was built ahead)
        for (int i = 0; i < 6; ++i) path.push_back(path[std::size_t(16 + (i % 2))]);  // to and fro
        path.push_back(Camera::perspective(c + d * glm::dvec3(-0.8, -0.3, 0.5), c, {0, 1, 0}, 30, 640, 480));  // a jump
        for (int i = 0; i < 4; ++i)
            path.push_back(Camera::orthographic(c + d * glm::dvec3(0.3 + 0.01 * i, 1.0, 0.4), c, {0, 0, 1},
                                                2.2 * box.half_diagonal(), 640, 640));
        path.push_back(path.front());
        FinderOptions o = randomized(0.0, true);
        o.first_full = true;
        SilhouetteFinder finder(m->topology(), o);
        Features f;
        std::size_t rebuilt = 0;
        for (std::size_t i = 0; i < path.size(); ++i) {
            SCOPED_TRACE(testing::Message() << "view " << i);
            finder.find(path[i], {}, f);
            const Features ex = extract_features(m->topology(), path[i]);
            ASSERT_FALSE(ex.silhouette_edges.empty());
            expect_identical(ex, f);
            // The facing the visibility stage reads: carried on as a full view, every face exact.
            EXPECT_TRUE(f.face_front.full());
            EXPECT_EQ(f.face_front.all(), ex.face_front.all());
            rebuilt += f.stats.band_rebuilt;
        }
        EXPECT_GE(rebuilt, 3u);                  // the orbit's first, the jump, the camera kind
        EXPECT_LT(rebuilt, path.size() - 2);     // and the band kept across orbit views
    }
}

// A view that does not follow the previous one (after reset(): an exhaustive first view again)
// in the middle of a band that is still valid for the eyes around it: the views after it are
// exact (the band's faces that turned across that view are not taken from the view before it).
TEST(Finder, CoherenceAfterAViewWithoutFollowIsExact) {
    const Model torus(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 96, 48));
    for (const Model* m : {&torus, &mesh_model("armadillo")}) {
        const Bounds3 box = m->topology().bounds;
        const glm::dvec3 c = box.center();
        const double d = 3.0 * box.half_diagonal();
        FinderOptions o = randomized(0.0, true);
        o.first_full = true;
        o.band_steps = 16.0;  // a wide band: it outlives the reset
        SilhouetteFinder finder(m->topology(), o);
        Features f;
        std::size_t turned_across = 0;
        for (int i = 0; i < 16; ++i) {
            SCOPED_TRACE(testing::Message() << "view " << i);
            if (i == 6) finder.reset();
            const double az = 0.3 + 0.0175 * i;  // 1 degree per view
            const Camera cam =
                Camera::perspective(c + d * glm::dvec3(std::sin(az), 0.4, std::cos(az)), c, {0, 1, 0}, 30, 640, 480);
            finder.find(cam, {}, f);
            const Features ex = extract_features(m->topology(), cam);
            expect_identical(ex, f);
            if (i == 7) {
                EXPECT_TRUE(f.stats.band_rebuilt);
                turned_across += f.stats.faces_turned;
            }
        }
        EXPECT_GT(turned_across, 0u);
    }
}

// The carried facing where the float filter cannot decide: a far, scaled sphere, the eye moving
// into the plane of a face (decided only by the exact predicate) and out again, small steps
// (faces turn one by one), and faces read in between (undecided faces resolved and cached for one
// camera, then carried to the next). Every face's facing equals a fresh exhaustive view's.
TEST(Finder, CoherenceCarriesTheFacingThroughUndecidedFaces) {
    for (double scale : {1e-3, 1.0, 1e4}) {
        SCOPED_TRACE(testing::Message() << "scale " << scale);
        const Model m = scaled_sphere(48, 24, scale, 3.0 * scale);
        const MeshTopology& t = m.topology();
        const auto& f5 = t.faces[5];
        const glm::dvec3 a = t.positions[f5[0]], b = t.positions[f5[1]], c = t.bounds.center();
        std::vector<Camera> path;
        for (int i = -3; i <= 3; ++i) {  // through the plane of face 5 (i == 0: in it, up to rounding)
            const glm::dvec3 off = double(i) * 1e-3 * scale * glm::dvec3(0.3, 0.7, -0.2);
            path.push_back(Camera::perspective(a + 3.0 * (a - b) + off, c, {0, 1, 0}, 40, 256, 256));
        }
        path.push_back(Camera::orthographic(c + glm::dvec3(0.2, 1.0, 0.4) * (4.0 * scale), c, {0, 0, 1}, 2.5 * scale, 256, 256));
        path.push_back(path[3]);
        FinderOptions o = randomized(0.0, true);
        o.first_full = true;
        SilhouetteFinder finder(t, o);
        Features f;
        for (std::size_t i = 0; i < path.size(); ++i) {
            SCOPED_TRACE(testing::Message() << "view " << i);
            finder.find(path[i], {}, f);
            const Features ex = extract_features(t, path[i]);
            expect_identical(ex, f);
            EXPECT_TRUE(f.face_front.full());
            EXPECT_EQ(f.face_front.all(), ex.face_front.all());
            // Read every other face now (caching the undecided ones for this camera only).
            for (std::uint32_t x = 0; x < t.face_count(); x += 2) (void)f.face_front[x];
        }
    }
}

}  // namespace
}  // namespace inkline

namespace inkline {
namespace {

// The float filter in front of the exact facing predicate: full and lazy views agree with the
// exact predicate on every face, at extreme scales and offsets, and with the eye exactly in the
// plane of faces (where only the exact predicate can decide).
TEST(Facing, FloatFilterAgreesWithExactPredicate) {
    for (double scale : {1e-6, 1.0, 1e6})
        for (double offset : {0.0, 1e6}) {
            const Model m = scaled_sphere(24, 12, scale, offset);
            const MeshTopology& t = m.topology();
            const std::vector<Camera> cams = cameras_with_grazing(t);
            for (const Camera& cam : cams) {
                SCOPED_TRACE(testing::Message() << "scale " << scale << " offset " << offset);
                FaceFacing full, lazy;
                full.begin_full(t, cam);
                lazy.begin_lazy(t, cam);
                for (std::uint32_t f = 0; f < t.face_count(); ++f) {
                    const std::uint8_t want = face_is_front(t, f, cam) ? 1 : 0;
                    EXPECT_EQ(full[f], want) << "face " << f;
                    EXPECT_EQ(lazy[f], want) << "face " << f;
                }
                // The grazing camera leaves faces to the exact predicate (the filter said "undecided").
                if (&cam == &cams.back()) {
                    EXPECT_GT(lazy.exact_tests(), 0u);
                }
            }
        }
}

}  // namespace
}  // namespace inkline

namespace inkline {
namespace {

// The faces whose float distance to the filter's eye is not above limit (NaN planes included),
// one at a time: what a band of that limit holds.
std::vector<std::uint32_t> within(const MeshTopology& t, const FacingFilter& filter, float limit) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t f = 0; f < t.face_count(); ++f)
        if (!(std::abs(filter.signed_distance(t.facing[f])) > limit)) out.push_back(f);
    return out;
}

// Face blocks (FaceBlocks): a full view that decides whole blocks from their plane ranges gives
// byte for byte the states of the plain pass, with blocks decided as a whole (fewer planes
// read) on a smooth mesh; the band search gives the same faces; at extreme scales and offsets,
// and for a grazing eye in the plane of a face.
TEST(Facing, BlocksGiveTheSameStatesAndBand) {
    std::size_t skipped = 0, exact_outside = 0;
    for (double scale : {1e-6, 1.0, 1e6})
        for (double offset : {0.0, 1e6}) {
            const Model m = scaled_sphere(96, 48, scale, offset);
            const MeshTopology& t = m.topology();
            FaceBlocks blocks;
            blocks.build(t);
            ASSERT_TRUE(blocks.built_for(t));
            EXPECT_FALSE(blocks.has_edges());
            blocks.build_edges();
            ASSERT_TRUE(blocks.has_edges());
            const std::vector<Camera> cams = cameras_with_grazing(t);
            for (const Camera& cam : cams) {
                SCOPED_TRACE(testing::Message() << "scale " << scale << " offset " << offset);
                FaceFacing plain, blocked;
                plain.begin_full(t, cam);
                blocked.begin_full(t, cam, 1, &blocks);
                const std::size_t nf = t.face_count();
                EXPECT_TRUE(std::equal(plain.states(), plain.states() + nf, blocked.states()));
                EXPECT_EQ(plain.planes_read(), nf);
                EXPECT_LE(blocked.planes_read(), nf);
                EXPECT_EQ(blocked.block_states().size(), blocks.size());
                skipped += nf - blocked.planes_read();
                FacingFilter filter;
                filter.bind(t, cam);
                for (float limit : {0.0f, 0.01f * float(scale), 0.3f * float(scale)}) {
                    const std::vector<std::uint32_t> all = within(t, filter, limit);
                    // The band as a rebuild selects it (FacingBand::select, AVX2 and portable,
                    // with and without blocks): those faces, each one's plane in the rows bit for
                    // bit (NaN planes included), the same front bits outside the band with and
                    // without blocks, every plane read without blocks. Each band is selected over
                    // a wider one first, so that it writes over longer rows, and with the bits
                    // left by it inverted, so that every bit outside the band must be written.
                    std::vector<std::uint64_t> bits[2][2];  // [blocks][simd]
                    std::size_t read = 0;
                    for (int with_blocks : {0, 1})
                        for (int simd : {0, 1}) {
                            const FaceBlocks* b = with_blocks ? &blocks : nullptr;
                            std::vector<std::uint64_t>& w = bits[with_blocks][simd];
                            w.assign(nf / 64 + 1, 0);
                            FacingBand band;
                            band.select(t, filter, 4.0f * limit + 0.5f * float(scale), b, w.data(), simd == 1);
                            for (auto& x : w) x = ~x;
                            const std::size_t r = band.select(t, filter, limit, b, w.data(), simd == 1);
                            if (with_blocks) {
                                EXPECT_LE(r, nf);
                                if (simd) {
                                    EXPECT_EQ(r, read);
                                }
                                read = r;
                            } else {
                                EXPECT_EQ(r, nf);
                            }
                            ASSERT_EQ(band.size(), all.size());
                            for (std::size_t i = 0; i < all.size(); ++i) {
                                ASSERT_EQ(band.face(i), all[i]);
                                const MeshTopology::FacingPlane p = band.plane(i);
                                ASSERT_EQ(std::memcmp(&p, &t.facing[all[i]], sizeof(p)), 0) << "face " << all[i];
                            }
                        }
                    const std::vector<std::uint64_t>& plain_bits = bits[0][0];
                    const std::vector<std::uint64_t>& block_bits = bits[1][1];
                    std::vector<std::uint8_t> in_band(nf, 0);
                    for (std::uint32_t f : all) in_band[f] = 1;
                    for (std::uint32_t f = 0; f < nf; ++f) {
                        if (in_band[f]) continue;
                        const bool a = (plain_bits[f >> 6] >> (f & 63)) & 1, b = (block_bits[f >> 6] >> (f & 63)) & 1;
                        ASSERT_EQ(a, b) << "face " << f << " limit " << limit;
                        ASSERT_EQ(a, bool((bits[0][1][f >> 6] >> (f & 63)) & 1)) << "face " << f;
                        ASSERT_EQ(a, bool((bits[1][0][f >> 6] >> (f & 63)) & 1)) << "face " << f;
                        if (limit >= filter.bound) {
                            ASSERT_EQ(a, face_is_front(t, f, cam)) << "face " << f;
                            ++exact_outside;
                        }
                    }
                }
            }
        }
    EXPECT_GT(skipped, 0u);  // blocks were decided as a whole
    EXPECT_GT(exact_outside, 10000u);  // front bits outside the band compared with the exact facing
}

// The band's per-view states (FacingBand::states, AVX2 and portable): each band face's front
// bit is the filter's "front" now and no other bit changes (none without bits); the positions to
// check are those where the two views' filter states differ or the current one is undecided. Bands of every
// density (sparse and dense words, lengths not a multiple of 8), at extreme scales and offsets,
// with a grazing eye and an untrusted (NaN) plane; one band (faces 110 to 130) ends with the
// untrusted face, so that a position after the last full group of 8 is checked in every view.
TEST(Facing, BandStatesMatchTheFilter) {
    std::mt19937_64 rng(11);
    std::size_t checked = 0, fronts = 0;
    for (double scale : {1e-6, 1.0, 1e6})
        for (double offset : {0.0, 1e6}) {
            Model m = scaled_sphere(96, 48, scale, offset);
            MeshTopology& t = m.topology();
            t.facing[130].nz = NAN;
            const std::size_t nf = t.face_count();
            const std::vector<Camera> cams = cameras_with_grazing(t);
            for (double keep : {0.03, 0.5, 1.0, 0.0}) {
                std::vector<std::uint32_t> faces;
                for (std::uint32_t f = 0; f < nf; ++f)
                    if (keep > 0.0 ? std::uniform_real_distribution<double>(0, 1)(rng) < keep : f >= 110 && f <= 130)
                        faces.push_back(f);
                if (faces.size() % 8 == 0) faces.pop_back();
                if (keep == 0.0) {
                    ASSERT_EQ(faces.size() % 8, 5u);
                }
                FacingBand band;
                band.assign(t, faces);
                ASSERT_EQ(band.size(), faces.size());
                for (std::size_t a = 0; a < cams.size(); ++a)
                    for (std::size_t b = 0; b < cams.size(); ++b) {
                        FacingFilter now, before;
                        now.bind(t, cams[a]);
                        before.bind(t, cams[b]);
                        std::vector<std::uint64_t> preset(nf / 64 + 1);
                        for (auto& w : preset) w = rng();
                        std::vector<std::uint64_t> bits[2] = {preset, preset};
                        std::vector<std::uint32_t> check[2];
                        for (int simd : {0, 1}) band.states(now, before, bits[simd].data(), check[simd], simd == 1);
                        EXPECT_EQ(bits[0], bits[1]);
                        EXPECT_EQ(check[0], check[1]);
                        std::vector<std::uint32_t> want;
                        std::vector<std::uint64_t> want_bits = preset;
                        for (std::size_t i = 0; i < faces.size(); ++i) {
                            const std::uint32_t f = faces[i];
                            ASSERT_EQ(band.face(i), f);
                            const std::uint8_t sa = now(t.facing[f]), sb = before(t.facing[f]);
                            const std::uint64_t bit = std::uint64_t(1) << (f & 63);
                            want_bits[f >> 6] = sa == FaceFacing::kFront ? want_bits[f >> 6] | bit : want_bits[f >> 6] & ~bit;
                            if (sa != sb || sa == FaceFacing::kUnknown) want.push_back(std::uint32_t(i));
                            fronts += sa == FaceFacing::kFront;
                        }
                        ASSERT_EQ(bits[1], want_bits);
                        ASSERT_EQ(check[1], want);
                        // Without bits: the same positions to check, no bit written.
                        for (int simd : {0, 1}) {
                            std::vector<std::uint32_t> only;
                            band.states(now, before, nullptr, only, simd == 1);
                            ASSERT_EQ(only, want);
                        }
                        checked += want.size();
                    }
            }
        }
    EXPECT_GT(checked, 1000u);  // positions to check, and front faces, did occur
    EXPECT_GT(fronts, 1000u);
}

// A block holding an untrusted (NaN) plane is never decided as a whole: that face goes to the
// exact predicate, as in the plain pass.
TEST(Facing, BlocksWithAnUntrustedPlane) {
    Model m(make_sphere({0, 0, 0}, 1.0, 96, 48));
    MeshTopology& t = m.topology();
    const std::uint32_t bad = 3 * FaceBlocks::kFaces + 5;
    t.facing[bad].nx = NAN;
    FaceBlocks blocks;
    blocks.build(t);
    for (const Camera& cam : cameras(t.bounds)) {
        FaceFacing plain, blocked;
        plain.begin_full(t, cam);
        blocked.begin_full(t, cam, 1, &blocks);
        EXPECT_EQ(blocked.block_states()[3], FaceFacing::kUnknown);
        EXPECT_TRUE(std::equal(plain.states(), plain.states() + t.face_count(), blocked.states()));
        EXPECT_EQ(blocked[bad], face_is_front(t, bad, cam) ? 1 : 0);
        EXPECT_LT(blocked.planes_read(), t.face_count());
    }
}

// The facing pass that builds the blocks as it goes (FaceFacing::begin_full_building, the coherent
// finder's first view) gives the states, block states and planes read of begin_full with blocks
// built beforehand, and blocks that decide as those do (block states for other views, the bands
// and front bits of FacingBand::select): face counts that fill the blocks or not (a last block of a few
// faces), extreme scales and offsets, a grazing eye, an untrusted (NaN) plane in the second chunk.
TEST(Facing, BuildingPassGivesTheSameStatesAndBlocks) {
    std::size_t compared = 0;
    for (const auto& [slices, stacks] : {std::pair{96, 48}, std::pair{131, 67}, std::pair{7, 5}})
        for (double scale : {1e-6, 1.0, 1e6})
            for (double offset : {0.0, 1e6})
                for (bool nan : {false, true}) {
                    Model m = scaled_sphere(slices, stacks, scale, offset);
                    MeshTopology& t = m.topology();
                    const std::size_t nf = t.face_count();
                    const std::uint32_t bad = std::uint32_t(std::min<std::size_t>(nf - 1, 64 * FaceBlocks::kFaces + 9));
                    if (nan) t.facing[bad].ny = NAN;
                    FaceBlocks before;
                    before.build(t);
                    const std::vector<Camera> cams = cameras_with_grazing(t);
                    for (const Camera& cam : cams) {
                        SCOPED_TRACE(testing::Message() << slices << "x" << stacks << " scale " << scale << " offset "
                                                        << offset << " nan " << nan);
                        FaceBlocks built;
                        FaceFacing plain, fused;
                        plain.begin_full(t, cam, 1, &before);
                        fused.begin_full_building(t, cam, built);
                        ASSERT_TRUE(built.built_for(t));
                        ASSERT_EQ(built.size(), before.size());
                        EXPECT_TRUE(std::equal(plain.states(), plain.states() + nf + FaceFacing::kPad, fused.states()));
                        EXPECT_EQ(plain.block_states(), fused.block_states());
                        EXPECT_EQ(plain.planes_read(), fused.planes_read());
                        EXPECT_TRUE(fused.full());
                        for (std::uint32_t f = 0; f < nf; f += 7) ASSERT_EQ(fused[f], face_is_front(t, f, cam) ? 1 : 0);
                        if (nan) {  // the untrusted plane's block is never decided as a whole
                            EXPECT_EQ(fused.block_states()[bad / FaceBlocks::kFaces], FaceFacing::kUnknown);
                            EXPECT_EQ(fused[bad], face_is_front(t, bad, cam) ? 1 : 0);
                        }
                        for (const Camera& other : cams) {
                            FacingFilter filter;
                            filter.bind(t, other);
                            std::vector<std::uint8_t> a(before.size()), b(built.size());
                            before.classify(0, before.size(), filter, a.data());
                            built.classify(0, built.size(), filter, b.data());
                            EXPECT_EQ(a, b);
                            for (float limit : {0.0f, 0.01f * float(scale), 0.3f * float(scale)}) {
                                FacingBand fa, fb;
                                std::vector<std::uint64_t> ba(nf / 64 + 1, 0), bb(nf / 64 + 1, 0);
                                EXPECT_EQ(fa.select(t, filter, limit, &before, ba.data()),
                                          fb.select(t, filter, limit, &built, bb.data()));
                                ASSERT_EQ(fa.size(), fb.size());
                                for (std::size_t i = 0; i < fa.size(); ++i) ASSERT_EQ(fa.face(i), fb.face(i));
                                EXPECT_EQ(ba, bb);
                                ++compared;
                            }
                        }
                    }
                }
    EXPECT_GT(compared, 500u);
}

// Block states four at a time (FaceBlocks::classify over a range) equal those one at a time, for
// every start and length modulo four, at extreme scales and offsets, a grazing eye, a block with
// an untrusted (NaN) plane and an eye out of float range (every block undecided).
TEST(Facing, BlockStatesFourAtATime) {
    std::size_t decided = 0, total = 0;
    for (double scale : {1e-6, 1.0, 1e6})
        for (double offset : {0.0, 1e6}) {
            Model m = scaled_sphere(96, 48, scale, offset);
            MeshTopology& t = m.topology();
            t.facing[2 * FaceBlocks::kFaces + 7].ny = NAN;
            FaceBlocks blocks;
            blocks.build(t);
            std::vector<Camera> cams = cameras_with_grazing(t);
            cams.push_back(Camera::perspective(t.bounds.center() + glm::dvec3(1e39, 0, 0), t.bounds.center(), {0, 1, 0}, 30, 64, 64));
            for (const Camera& cam : cams) {
                FacingFilter filter;
                filter.bind(t, cam);
                for (std::size_t b0 : {0, 1, 2, 3})
                    for (std::size_t cut : {0, 1, 2, 3}) {
                        const std::size_t b1 = blocks.size() - cut;
                        std::vector<std::uint8_t> got(b1 - b0, 9);
                        blocks.classify(b0, b1, filter, got.data());
                        for (std::size_t b = b0; b < b1; ++b) {
                            ASSERT_EQ(got[b - b0], blocks.classify(b, filter)) << "block " << b;
                            decided += got[b - b0] != FaceFacing::kUnknown;
                            ++total;
                        }
                    }
                EXPECT_EQ(blocks.classify(2, filter), FaceFacing::kUnknown);
                // Bounds just at a block's widened range: undecided, as one at a time.
                for (std::size_t b = 4; b + 4 <= blocks.size(); b += 5) {
                    double lo, hi;
                    blocks.distance_range(b, filter, lo, hi);
                    if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
                    for (double edge : {lo, -hi}) {
                        FacingFilter f = filter;
                        f.bound = std::nextafter(float(edge), INFINITY);
                        if (!(f.bound > 0.0f)) continue;
                        std::uint8_t got[4];
                        blocks.classify(b, b + 4, f, got);
                        ASSERT_EQ(got[0], blocks.classify(b, f));
                        EXPECT_EQ(got[0], FaceFacing::kUnknown);
                        ++total;
                    }
                }
            }
        }
    EXPECT_GT(decided, 0u);
    EXPECT_LT(decided, total);
}

// The exhaustive finder with blocks (from its second view) against the one without, along a
// path: the same silhouette edges in the same order, every view, and fewer edges read.
// Block states against a limit (FaceBlocks::classify_within, four a step: FacingBand::select's test)
// equal the one-at-a-time test of distance_range against +-limit, for limits from zero to beyond
// every distance, every start and length modulo four, an untrusted (NaN) plane and limits just at
// a block's range.
TEST(Facing, BlockStatesWithinALimit) {
    std::size_t front = 0, back = 0, unknown = 0;
    for (double scale : {1e-6, 1.0, 1e6}) {
        Model m = scaled_sphere(96, 48, scale, 0.0);
        MeshTopology& t = m.topology();
        t.facing[2 * FaceBlocks::kFaces + 7].ny = NAN;
        FaceBlocks blocks;
        blocks.build(t);
        for (const Camera& cam : cameras_with_grazing(t)) {
            FacingFilter filter;
            filter.bind(t, cam);
            auto one = [&](std::size_t b, double limit) {
                double lo, hi;
                blocks.distance_range(b, filter, lo, hi);
                return lo > limit ? FaceFacing::kFront : hi < -limit ? FaceFacing::kBack : FaceFacing::kUnknown;
            };
            std::vector<double> limits = {0.0, double(filter.bound), 0.01 * scale, 0.3 * scale, 100.0 * scale};
            for (std::size_t b = 5; b + 4 <= blocks.size(); b += 37) {
                double lo, hi;
                blocks.distance_range(b, filter, lo, hi);
                for (double x : {lo, hi, -lo, -hi})
                    if (std::isfinite(x) && x > 0.0) limits.push_back(x), limits.push_back(std::nextafter(x, -1.0));
            }
            for (double limit : limits)
                for (std::size_t b0 : {0, 1, 2, 3}) {
                    const std::size_t b1 = blocks.size() - b0;
                    std::vector<std::uint8_t> got(b1 - b0, 9);
                    blocks.classify_within(b0, b1, filter, limit, got.data());
                    for (std::size_t b = b0; b < b1; ++b) {
                        const std::uint8_t want = one(b, limit);
                        ASSERT_EQ(got[b - b0], want) << "block " << b << " limit " << limit;
                        front += want == FaceFacing::kFront, back += want == FaceFacing::kBack, unknown += want == FaceFacing::kUnknown;
                    }
                    if (b0 <= 2) {
                        EXPECT_EQ(got[2 - b0], FaceFacing::kUnknown);  // the untrusted plane's block
                    }
                }
        }
    }
    EXPECT_GT(front, 0u);
    EXPECT_GT(back, 0u);
    EXPECT_GT(unknown, 0u);
}

TEST(Finder, ExhaustiveBlocksSameResult) {
    const Model torus(hilbert_ordered(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 192, 96)));
    for (const Model* m : {&torus, &mesh_model("armadillo"), &mesh_model("fandisk"), &mesh_model("bunny00")}) {
        std::vector<Camera> path = cameras(m->topology().bounds);
        path.push_back(path.front());
        FinderOptions plain_opt;
        plain_opt.blocks = false;
        plain_opt.edge_windows = false;
        SilhouetteFinder with(m->topology()), without(m->topology(), plain_opt);
        Features a, b;
        std::size_t read = 0, edges = 0;
        for (std::size_t i = 0; i < path.size(); ++i) {
            SCOPED_TRACE(testing::Message() << "view " << i);
            with.find(path[i], {}, a);
            without.find(path[i], {}, b);
            EXPECT_EQ(a.silhouette_edges, b.silhouette_edges);
            expect_same(a, b);
            EXPECT_EQ(b.stats.edges_read, m->topology().edge_count());
            if (i > 0) read += a.stats.edges_read, edges += m->topology().edge_count();
        }
        EXPECT_LT(read, edges);
    }
}

// The same with the facing pass and the edge scan split over threads (parts of whole blocks).
TEST(Finder, ExhaustiveBlocksThreadsSameResult) {
    Model sub = Model::load(test::mesh_path("armadillo"), 40.0, 1);  // 208 k faces: threads run
    const MeshTopology& t = sub.topology();
    std::vector<Camera> path = cameras(t.bounds);
    path.push_back(path.front());
    FinderOptions threaded, plain;
    threaded.threads = 3;
    plain.blocks = false;
    plain.edge_windows = false;
    SilhouetteFinder with(t, threaded), without(t, plain);
    Features a, b;
    std::size_t read = 0;
    for (std::size_t i = 0; i < path.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "view " << i);
        with.find(path[i], {}, a);
        without.find(path[i], {}, b);
        EXPECT_EQ(a.silhouette_edges, b.silhouette_edges);
        EXPECT_TRUE(std::equal(a.face_front.states(), a.face_front.states() + t.face_count(), b.face_front.states()));
        if (i > 0) read += a.stats.planes_read;
    }
    EXPECT_LT(read, (path.size() - 1) * t.face_count());
}

// The gather-free edge layout (BlockEdges) against a plain scan of every edge: candidates are
// the interior edges whose faces' states differ or include an undecided face (those flagged
// kCheck), in edge order; from the AVX-512 kernel (where the CPU has it) and the portable loop,
// whole or split in parts of blocks.
std::vector<std::uint32_t> plain_candidates(const MeshTopology& t, const std::uint8_t* st) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
        const auto [f0, f1] = t.edge_face[e];
        if (f1 == kNoFace) continue;
        const std::uint8_t a = st[f0], b = st[f1];
        const bool undecided = a == FaceFacing::kUnknown || b == FaceFacing::kUnknown;
        if (a != b || undecided) out.push_back(e | (undecided ? BlockEdges::kCheck : 0));
    }
    return out;
}

void expect_block_edges_match(const MeshTopology& t, const BlockEdges& be, const std::uint8_t* st) {
    const std::vector<std::uint32_t> want = plain_candidates(t, st);
    const auto none = [](std::uint32_t) { return false; };
    const std::uint32_t nb = std::uint32_t(be.size());
    for (bool simd : {true, false}) {
        SCOPED_TRACE(simd ? "simd" : "portable");
        std::vector<std::uint32_t> got, parts;
        be.scan(st, 0, nb, none, got, simd);
        EXPECT_EQ(got, want);
        for (std::uint32_t b = 0; b < nb; b += 7) be.scan(st, b, std::min(nb, b + 7), none, parts, simd);
        EXPECT_EQ(parts, want);
    }
}

TEST(Facing, BlockEdgesMatchThePlainScan) {
    const Model torus(hilbert_ordered(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.35, 192, 96)));
    const Model sphere = scaled_sphere(96, 48, 1e6, 1e6);
    const Model sheet(make_sheet(1.0, 0.0, 40));  // borders; coplanar faces (edge-on from +x: undecided)
    std::size_t escapes = 0, candidates = 0, checked = 0;
    for (const Model* m : {&torus, &sphere, &sheet, &mesh_model("armadillo"), &mesh_model("fandisk"),
                           &mesh_model("bunny00"), &mesh_model("knot1"), &mesh_model("elephant")}) {
        const MeshTopology& t = m->topology();
        BlockEdges be;
        ASSERT_TRUE(be.build(t));
        ASSERT_TRUE(be.built_for(t));
        EXPECT_EQ(be.size(), (t.face_count() + BlockEdges::kFaces - 1) / BlockEdges::kFaces);
        escapes += be.escapes();
        std::vector<Camera> cams = cameras_with_grazing(t);
        const glm::dvec3 c = t.bounds.center();  // axis-aligned orthographic views (coplanar faces edge-on)
        cams.push_back(Camera::orthographic(c + glm::dvec3(0, 0, 5), c, {0, 1, 0}, 3.0 * t.bounds.half_diagonal(), 256, 256));
        cams.push_back(Camera::orthographic(c + glm::dvec3(5, 0, 0), c, {0, 1, 0}, 3.0 * t.bounds.half_diagonal(), 256, 256));
        for (const Camera& cam : cams) {
            FaceFacing facing;
            facing.begin_full(t, cam);
            expect_block_edges_match(t, be, facing.states());
            for (std::uint32_t e : plain_candidates(t, facing.states())) ++candidates, checked += (e & BlockEdges::kCheck) != 0;
        }
        // Synthetic states with many undecided faces (each state at random; the padding as in a view).
        std::mt19937 rng(5);
        std::vector<std::uint8_t> st(t.face_count() + FaceFacing::kPad, FaceFacing::kSentinel);
        for (int round = 0; round < 3; ++round) {
            for (std::size_t f = 0; f < t.face_count(); ++f) {
                const std::uint32_t r = rng() % 100;
                st[f] = r < 10 ? FaceFacing::kUnknown : round == 0 ? (r < 55 ? FaceFacing::kFront : FaceFacing::kBack)
                                                                   : std::uint8_t(r % 2 ? FaceFacing::kFront : FaceFacing::kBack);
                if (round == 2 && r >= 10) st[f] = FaceFacing::kFront;  // uniform but for the undecided
            }
            expect_block_edges_match(t, be, st.data());
        }
    }
    EXPECT_GT(escapes, 0u);
    EXPECT_GT(candidates, 0u);
    EXPECT_GT(checked, 0u);
}

// The exhaustive finder with the layout (from its second view) against the plain scan where
// faces are left to the exact predicate: extreme scales and offsets, a grazing eye, a sheet seen
// edge-on (orthographic, every face undecided by the filter): the same silhouette edges in the
// same order, the same states and the same exact tests.
TEST(Finder, ExhaustiveWindowsSameResultWithUndecidedFaces) {
    std::vector<Model> models;
    for (double scale : {1e-6, 1e6})
        for (double offset : {0.0, 1e6}) models.push_back(scaled_sphere(96, 48, scale, offset));
    models.emplace_back(make_sheet(1.0, 0.0, 40));
    std::size_t exact = 0;
    for (const Model& m : models) {
        const MeshTopology& t = m.topology();
        std::vector<Camera> cams = cameras_with_grazing(t);
        const glm::dvec3 c = t.bounds.center();
        cams.push_back(Camera::orthographic(c + glm::dvec3(5, 0, 0), c, {0, 1, 0}, 3.0 * t.bounds.half_diagonal(), 256, 256));
        FinderOptions plain;
        plain.blocks = false;
        plain.edge_windows = false;
        SilhouetteFinder with(t), without(t, plain);
        Features a, b;
        for (int round = 0; round < 2; ++round)  // (the layout is used from the second view)
            for (const Camera& cam : cams) {
                with.find(cam, {}, a);
                without.find(cam, {}, b);
                EXPECT_EQ(a.silhouette_edges, b.silhouette_edges);
                EXPECT_TRUE(std::equal(a.face_front.states(), a.face_front.states() + t.face_count(), b.face_front.states()));
                EXPECT_EQ(a.stats.exact_facing_tests, b.stats.exact_facing_tests);
                expect_same(a, b);
                exact += a.stats.exact_facing_tests;
            }
    }
    EXPECT_GT(exact, 0u);
}

// Skipped blocks give no candidates; a mesh whose edges are not numbered by their first corner
// gets no layout.
TEST(Facing, BlockEdgesSkipAndRefuse) {
    const MeshTopology& t = mesh_model("bunny00").topology();
    BlockEdges be;
    ASSERT_TRUE(be.build(t));
    FaceFacing facing;
    facing.begin_full(t, test::framed_camera(t.bounds, 512));
    std::vector<std::uint32_t> odd, all;
    be.scan(facing.states(), 0, std::uint32_t(be.size()), [](std::uint32_t b) { return b % 2 == 0; }, odd);
    for (std::uint32_t e : plain_candidates(t, facing.states()))
        if ((t.edge_face[e & ~BlockEdges::kCheck][0] / BlockEdges::kFaces) % 2 == 1) all.push_back(e);
    EXPECT_EQ(odd, all);
    EXPECT_FALSE(odd.empty());
    MeshTopology swapped = t;
    std::swap(swapped.edge_face[10], swapped.edge_face[200]);
    BlockEdges bad;
    EXPECT_FALSE(bad.build(swapped));
    EXPECT_FALSE(bad.built_for(swapped));
    EXPECT_EQ(bad.size(), 0u);
}

// Band rebuilds with blocks find the same band as without (coherence from an exhaustive view).
// Following exactly on a smooth subdivided mesh (armadillo@1, 208 k faces: thin silhouettes,
// many faces turning per view) at a quarter degree per view, with the eye brought into the plane
// of a face (grazing: the filters cannot decide it, the exact checks do), then an orthographic
// stretch: every view equals the exhaustive finder's, and the band is both kept and rebuilt
// (the front bits of the faces outside it come from the rebuilds).
TEST(Finder, CoherenceFollowsASubdividedMeshExactly) {
    const std::string path = test::mesh_path("armadillo");
    ASSERT_TRUE(std::filesystem::exists(path));
    const Model m = Model::load(path, 40.0, 1);
    const MeshTopology& t = m.topology();
    const Bounds3 box = t.bounds;
    const glm::dvec3 c = box.center();
    const double d = 3.0 * box.half_diagonal();
    std::vector<Camera> path_cams;
    for (int i = 0; i < 40; ++i) {
        const double az = 0.3 + 0.25 * M_PI / 180.0 * i;
        path_cams.push_back(Camera::perspective(c + d * glm::dvec3(std::sin(az), 0.4, std::cos(az)), c, {0, 1, 0}, 30, 640, 480));
    }
    // Grazing: the eye on the line through two corners of a face, and two small steps from there.
    const auto& f = t.faces[t.face_count() / 3];
    const glm::dvec3 a = t.positions[f[0]], b = t.positions[f[1]];
    const glm::dvec3 graze = a + (d / glm::length(a - b)) * (a - b);
    for (int i = 0; i < 3; ++i)
        path_cams.push_back(Camera::perspective(graze + 1e-4 * d * double(i) * glm::dvec3(0, 1, 0), c, {0, 1, 0}, 30, 640, 480));
    for (int i = 0; i < 6; ++i)
        path_cams.push_back(Camera::orthographic(c + d * glm::dvec3(0.3 + 0.004 * i, 1.0, 0.4), c, {0, 0, 1},
                                                 2.2 * box.half_diagonal(), 640, 640));
    FinderOptions o = randomized(0.0, true);
    o.first_full = true;
    SilhouetteFinder finder(t, o);
    Features got;
    std::size_t rebuilt = 0, kept = 0, turned = 0;
    for (std::size_t i = 0; i < path_cams.size(); ++i) {
        SCOPED_TRACE(testing::Message() << "view " << i);
        finder.find(path_cams[i], {}, got);
        const Features ex = extract_features(t, path_cams[i]);
        ASSERT_FALSE(ex.silhouette_edges.empty());
        ASSERT_EQ(got.silhouette_edges, ex.silhouette_edges);  // in the same (edge) order
        for (std::uint32_t e : got.silhouette_edges) ASSERT_EQ(got.edge_kind[e], ex.edge_kind[e]) << "edge " << e;
        expect_identical(ex, got);
        if (i > 0) {
            rebuilt += got.stats.band_rebuilt;
            kept += !got.stats.band_rebuilt;
            turned += got.stats.faces_turned;
        }
    }
    EXPECT_GE(rebuilt, 4u);  // along the orbit, at the graze, at the camera kind
    EXPECT_GE(kept, 20u);
    EXPECT_GT(turned, 1000u);
}

// A coherent view that follows its own previous view keeps that view's edge kinds and rewrites
// only those of the edges of faces that turned; every edge's kind must still be the exhaustive
// finder's (no silhouette mark left on an edge that stopped being one, creases unmarked when they
// become silhouettes and marked again after). Also with the views written alternately into two
// Features, and into a new one midway (the marks cannot be kept there).
TEST(Finder, CoherenceKeepsEveryEdgeKindExact) {
    const std::string path = test::mesh_path("fandisk");
    ASSERT_TRUE(std::filesystem::exists(path));
    const Model m = Model::load(path, 40.0, 1);
    const MeshTopology& t = m.topology();
    ASSERT_FALSE(t.crease_list.empty());
    const glm::dvec3 c = t.bounds.center();
    const double d = 3.0 * t.bounds.half_diagonal();
    FinderOptions o = randomized(0.0, true);
    o.first_full = true;
    SilhouetteFinder same(t, o), alternate(t, o);
    Features a, b[2];
    std::size_t turned = 0, crease_changes = 0;
    std::vector<std::uint32_t> last_creases;
    for (int i = 0; i < 60; ++i) {
        SCOPED_TRACE(testing::Message() << "view " << i);
        const double az = 0.2 + 0.01 * i;
        const Camera cam = Camera::perspective(c + d * glm::dvec3(std::sin(az), 0.5, std::cos(az)), c, {0, 1, 0}, 30, 640, 480);
        const Features ex = extract_features(t, cam);
        same.find(cam, {}, a);
        EXPECT_EQ(a.edge_kind, ex.edge_kind);
        expect_identical(ex, a);
        if (i == 30) b[1] = Features{};  // a new Features midway
        Features& out = b[i % 2];
        alternate.find(cam, {}, out);
        EXPECT_EQ(out.edge_kind, ex.edge_kind);
        expect_identical(ex, out);
        if (i > 0) turned += a.stats.faces_turned;
        crease_changes += ex.crease_edges != last_creases;
        last_creases = ex.crease_edges;
    }
    EXPECT_GT(turned, 500u);
    EXPECT_GT(crease_changes, 3u);  // creases became silhouettes and stopped being ones along the way
}

// A Features shared by two coherent finders: the second's view, with as many silhouette edges
// (a view turned by the sphere's symmetry), must not pass for the first's marks when the first
// finds into it again (the marks are stamped per view, not recognized by the Features' address).
TEST(Finder, CoherenceKeepsNoOtherFindersMarks) {
    const Model m(make_sphere({0, 0, 0}, 1.0, 8, 6));  // 8-fold symmetric about y
    const MeshTopology& t = m.topology();
    FinderOptions o = randomized(0.0, true);
    o.first_full = true;
    SilhouetteFinder a(t, o), b(t, o);
    auto cam = [](double az) {
        return Camera::perspective(4.0 * glm::dvec3(std::sin(az), 0.3, std::cos(az)), {0, 0, 0}, {0, 1, 0}, 30, 640, 480);
    };
    const double az0 = 0.2, turn = 2.0 * M_PI / 8.0;
    Features out;
    a.find(cam(az0), {}, out);
    b.find(cam(az0 + turn), {}, out);
    ASSERT_EQ(out.silhouette_edges.size(), extract_features(t, cam(az0)).silhouette_edges.size());
    ASSERT_NE(out.silhouette_edges, extract_features(t, cam(az0)).silhouette_edges);
    for (double step : {0.002, 0.004}) {
        a.find(cam(az0 + step), {}, out);
        const Features ex = extract_features(t, cam(az0 + step));
        EXPECT_EQ(out.edge_kind, ex.edge_kind) << step;
        expect_identical(ex, out);
    }
    // A copy of a finder's output keeps its stamp: following into it is exact too.
    Features copy = out;
    a.find(cam(az0 + 0.006), {}, copy);
    EXPECT_EQ(copy.edge_kind, extract_features(t, cam(az0 + 0.006)).edge_kind);
}

TEST(Finder, CoherenceBandSameWithBlocks) {
    const Model& m = mesh_model("armadillo");
    const Bounds3 box = m.topology().bounds;
    const glm::dvec3 c = box.center();
    const double d = 3.0 * box.half_diagonal();
    FinderOptions o = randomized(0.0, true);
    o.first_full = true;
    FinderOptions p = o;
    p.blocks = false;
    SilhouetteFinder with(m.topology(), o), without(m.topology(), p);
    Features a, b;
    for (int i = 0; i < 20; ++i) {
        const double az = 0.3 + 0.0175 * i;
        const Camera cam = Camera::perspective(c + d * glm::dvec3(std::sin(az), 0.4, std::cos(az)), c, {0, 1, 0}, 30, 640, 480);
        with.find(cam, {}, a);
        without.find(cam, {}, b);
        EXPECT_EQ(a.stats.band_faces, b.stats.band_faces);
        EXPECT_EQ(a.stats.band_rebuilt, b.stats.band_rebuilt);
        EXPECT_EQ(a.silhouette_edges, b.silhouette_edges);
    }
}

}  // namespace
}  // namespace inkline
