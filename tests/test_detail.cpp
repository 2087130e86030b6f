// Detail control, multi-scale method (src/detail/): the levels, the blend, and the line density
// along a dolly (issue 43's checks). Geometry only: no timings.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

#include "detail/multiscale.hpp"
#include "detail/multiscale_cache.hpp"
#include "detail/progressive_mesh_cache.hpp"
#include "model/mesh_io.hpp"
#include "cli_util.hpp"
#include "model/primitives.hpp"
#include "test_data.hpp"

namespace inkline {
namespace {

ViewOptions suggestive_view() {
    ViewOptions o;
    o.features.kinds[int(LineKind::Crease)] = false;
    o.surface.suggestive = true;
    return o;
}

// Models and their levels, built once per test program (the pre-process takes a second or two).
struct Built {
    std::unique_ptr<Model> model;
    MultiscaleLevels levels;
};
const Built& built(const std::string& name) {
    static std::map<std::string, Built> cache;
    auto it = cache.find(name);
    if (it == cache.end()) {
        Built b;
        b.model = std::make_unique<Model>(Model::load(test::mesh_path(name)));
        b.levels = build_multiscale_levels(*b.model);
        it = cache.emplace(name, std::move(b)).first;
    }
    return it->second;
}

TEST(MultiscaleLevels, ArmadilloFourLevelsWithinTheSeedsMemory) {
    const Built& b = built("armadillo");
    const MultiscaleLevels& L = b.levels;
    EXPECT_EQ(L.levels, 4);
    EXPECT_TRUE(L.note.empty());
    EXPECT_EQ(L.vertices, 26002u);
    // Shortest edge first down to a base mesh: all but a handful of the vertices go (a closed
    // genus-0 surface ends at a tetrahedron-like base; here at 7 vertices).
    EXPECT_EQ(L.collapses, 25995u);
    // 49 bytes a vertex a level for the three smoothed levels (the seed: 52).
    EXPECT_EQ(L.bytes(), 49u * 3u * 26002u);
}

TEST(MultiscaleLevels, InputIsLevelZeroExactly) {
    const Built& b = built("armadillo");
    EXPECT_EQ(level_positions(*b.model, b.levels, 0), b.model->topology().positions);
    // A view whose every vertex is at level 0 (a target far below one edge's projection) draws
    // exactly what the plain pipeline draws: same positions, same quantities, same pieces.
    const Camera cam = test::framed_camera(b.model->topology().bounds);
    MultiscaleSession s(*b.model, b.levels, suggestive_view(), {.target_px = 1e-3});
    const View& detail = s.render(cam);
    for (float l : s.vertex_levels()) ASSERT_EQ(l, 0.0f);
    EXPECT_EQ(s.blended().topology().positions, b.model->topology().positions);
    const View plain = render_view(*b.model, cam, suggestive_view());
    ASSERT_EQ(detail.drawing.pieces.size(), plain.drawing.pieces.size());
    for (std::size_t i = 0; i < plain.drawing.pieces.size(); ++i) {
        EXPECT_EQ(detail.drawing.pieces[i].qi, plain.drawing.pieces[i].qi);
        EXPECT_EQ(detail.drawing.pieces[i].points, plain.drawing.pieces[i].points);
    }
}

TEST(MultiscaleLevels, AllDetailRebuildsTheInput) {
    // r = 1: every vertex split adds its detail back, so the rebuilt level is the input (to the
    // float the levels are stored in): the detail coefficients invert the prediction exactly.
    const Built& b = built("bunny00");
    const MultiscaleLevels L = build_multiscale_levels(*b.model, {.levels = 2, .ratio = 1.0});
    ASSERT_EQ(L.levels, 2);
    const auto& p0 = b.model->topology().positions;
    const auto p1 = level_positions(*b.model, L, 1);
    const double tolerance = 1e-6 * b.model->topology().bounds.half_diagonal();
    double worst = 0.0;
    for (std::size_t v = 0; v < p0.size(); ++v) worst = std::max(worst, glm::length(p1[v] - p0[v]));
    EXPECT_LE(worst, tolerance);
    // r = 3/4 moves them: level 1 is smoothed.
    double moved = 0.0;
    const auto q1 = level_positions(*b.model, b.levels, 1);
    for (std::size_t v = 0; v < p0.size(); ++v) moved = std::max(moved, glm::length(q1[v] - p0[v]));
    EXPECT_GT(moved, 100.0 * tolerance);
}

TEST(MultiscaleLevels, EveryLevelKeepsTheConnectivityUnfolded) {
    const Built& b = built("armadillo");
    const MeshTopology& m0 = b.model->topology();
    for (int k = 1; k < b.levels.levels; ++k) {
        TriangleMesh t;
        t.positions = level_positions(*b.model, b.levels, k);
        t.triangles = m0.faces;
        const MeshTopology mk = build_topology(std::move(t));
        EXPECT_EQ(mk.edge_vertex, m0.edge_vertex) << "level " << k;
        EXPECT_EQ(mk.edge_face, m0.edge_face) << "level " << k;
        // No face of a smoothed level collapsed, and almost none turned over against its input face.
        std::size_t flat = 0, flipped = 0;
        for (std::uint32_t f = 0; f < m0.face_count(); ++f) {
            const glm::dvec3 n = mk.face_normal(f);
            flat += n == glm::dvec3(0.0);
            flipped += glm::dot(n, m0.face_normal(f)) < 0.0;
        }
        EXPECT_EQ(flat, 0u) << "level " << k;
        EXPECT_LE(flipped, m0.face_count() / 500) << "level " << k;  // (measured 2, 9, 58 of 52 000)
    }
}

TEST(MultiscaleLevels, SmoothedLevelsLoseTheSmallBumps) {
    // Median |k1| over armadillo: every smoothed level well below M0's (measured 0.130 for M0, then
    // 0.094, 0.099, 0.114). Not monotone, and the mean rises (0.19, 0.22, 0.37, 0.76): the umbrella
    // smoothing thins the claws, ears and fingers (k1 = 1/radius grows) and folds a few faces,
    // whose curvatures dominate the mean. docs/detail.md lists this as a known shortfall.
    const MultiscaleLevels& L = built("armadillo").levels;
    ASSERT_EQ(L.median_abs_k1.size(), 4u);
    for (int k = 1; k < 4; ++k) EXPECT_LT(L.median_abs_k1[std::size_t(k)], 0.9 * L.median_abs_k1[0]) << "level " << k;
    EXPECT_NEAR(L.median_abs_k1[1], 0.0940, 0.0005);
    EXPECT_NEAR(L.median_abs_k1[3], 0.1144, 0.0005);
}

// The second-order functional (GSS's, uniform weights; --detail-fairing=second-order, with its 8
// relaxation and 32 tangential sweeps a level): M0 is the input, every level keeps the
// connectivity, level k keeps the detail of exactly the first r^k n splits (level 2 at r equals
// level 1 at r^2), and at the seed's r = 3/4 the smoothed levels lose the small bumps without the
// umbrella's folds: mean |k1| of M3 0.149 against M0's 0.187 on armadillo (the umbrella's: 0.76),
// 18.7 against 20.6 on bunny; folded faces 3, 2, 4 (the umbrella's at r = 1/2: 2, 9, 58).
TEST(MultiscaleLevels, SecondOrderKeepsTheShape) {
    const Built& b = built("armadillo");
    MultiscaleOptions o{.ratio = 0.75, .fairing = MultiscaleFairing::SecondOrder, .sweeps = 8, .tangential_sweeps = 32};
    const MultiscaleLevels L = build_multiscale_levels(*b.model, o);
    ASSERT_EQ(L.levels, 4);
    EXPECT_EQ(level_positions(*b.model, L, 0), b.model->topology().positions);
    const MeshTopology& m0 = b.model->topology();
    std::vector<std::size_t> flipped;
    for (int k = 1; k < L.levels; ++k) {
        TriangleMesh t;
        t.positions = level_positions(*b.model, L, k);
        t.triangles = m0.faces;
        const MeshTopology mk = build_topology(std::move(t));
        EXPECT_EQ(mk.edge_vertex, m0.edge_vertex) << "level " << k;
        EXPECT_EQ(mk.edge_face, m0.edge_face) << "level " << k;
        std::size_t n = 0;
        for (std::uint32_t f = 0; f < m0.face_count(); ++f) n += glm::dot(mk.face_normal(f), m0.face_normal(f)) < 0.0;
        flipped.push_back(n);
    }
    EXPECT_EQ(flipped, (std::vector<std::size_t>{3, 2, 4}));
    EXPECT_NEAR(L.mean_abs_k1[3], 0.1491, 0.0005);
    EXPECT_LT(L.mean_abs_k1[3], 0.85 * L.mean_abs_k1[0]);
    EXPECT_NEAR(L.median_abs_k1[3], 0.0932, 0.0005);
    EXPECT_LT(L.median_abs_k1[3], 0.75 * L.median_abs_k1[0]);
    const MultiscaleLevels bunny = build_multiscale_levels(*built("bunny00").model, o);
    EXPECT_NEAR(bunny.mean_abs_k1[3], 18.68, 0.05);
    EXPECT_LT(bunny.mean_abs_k1[3], 0.92 * bunny.mean_abs_k1[0]);
    // The r^k n rule: level 2 at r = 0.75 is level 1 at r = 0.5625, to the bit.
    o.levels = 2;
    o.ratio = 0.5625;
    const MultiscaleLevels one = build_multiscale_levels(*b.model, o);
    EXPECT_EQ(level_positions(*b.model, one, 1), level_positions(*b.model, L, 2));
    // The umbrella folds more at M3 (measured 2, 9, 58 at r = 1/2).
    std::size_t umbrella_m3 = 0;
    const auto p3 = level_positions(*b.model, b.levels, 3);
    for (std::uint32_t f = 0; f < m0.face_count(); ++f) {
        const auto& v = m0.faces[f];
        umbrella_m3 += glm::dot(glm::cross(p3[v[1]] - p3[v[0]], p3[v[2]] - p3[v[0]]), m0.face_normal(f)) < 0.0;
    }
    EXPECT_EQ(umbrella_m3, 58u);
}

// The model renumbered: vertices and faces in a random order, each face starting at a random
// corner (the same surface, another file). new_of_old maps the model's vertices to the copy's.
struct Renumbered {
    std::unique_ptr<Model> model;
    std::vector<std::uint32_t> new_of_old;
};
Renumbered renumbered(const MeshTopology& m, std::uint32_t seed) {
    std::mt19937 rng(seed);
    Renumbered r;
    r.new_of_old.resize(m.vertex_count());
    std::iota(r.new_of_old.begin(), r.new_of_old.end(), 0u);
    std::shuffle(r.new_of_old.begin(), r.new_of_old.end(), rng);
    TriangleMesh t;
    t.positions.resize(m.vertex_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v) t.positions[r.new_of_old[v]] = m.positions[v];
    for (const auto& f : m.faces) {
        const std::uint32_t k = std::uint32_t(rng() % 3);
        t.triangles.push_back({r.new_of_old[f[k]], r.new_of_old[f[(k + 1) % 3]], r.new_of_old[f[(k + 2) % 3]]});
    }
    std::shuffle(t.triangles.begin(), t.triangles.end(), rng);
    r.model = std::make_unique<Model>(std::move(t));
    return r;
}

// The levels follow the surface, not the file's numbering: which edge collapses first and which of
// its ends goes are decided by positions, so a renumbered armadillo gets the same levels vertex for
// vertex. The umbrella and second-order levels to the bit (every sum adds in an order fixed by the
// positions). The thin-guarded ones to 1e-6 of the model's size: their sparse solver orders its
// elimination by the numbering and Embree's thickness rays start from normals summed in face order,
// so the doubles differ in their last bits, and a level stores floats, whose step is 6e-8 of the
// coordinates: a last-bit difference can round to the neighbouring float (measured: 6.7e-8).
TEST(MultiscaleLevels, LevelsDoNotDependOnTheNumbering) {
    const Built& b = built("armadillo");
    const Renumbered r = renumbered(b.model->topology(), 46);
    const double size = b.model->topology().bounds.half_diagonal();
    const MultiscaleOptions second{.ratio = 0.75, .fairing = MultiscaleFairing::SecondOrder, .sweeps = 8, .tangential_sweeps = 32};
    const std::pair<const char*, MultiscaleOptions> settings[] = {
        {"umbrella", {}}, {"second-order", second}, {"thin-guarded", thin_guarded({})}};
    for (const auto& [name, options] : settings) {
        const MultiscaleLevels L = build_multiscale_levels(*b.model, options);
        const MultiscaleLevels R = build_multiscale_levels(*r.model, options);
        ASSERT_EQ(R.levels, L.levels) << name;
        EXPECT_EQ(R.collapses, L.collapses) << name;
        double worst = 0.0;
        for (int k = 1; k < L.levels; ++k)
            for (std::size_t v = 0; v < L.vertices; ++v)
                worst = std::max(worst, double(glm::length(R.position[R.at(k, r.new_of_old[v])] - L.position[L.at(k, v)])));
        std::printf("%s: worst difference %.3g of the size\n", name, worst / size);
        if (options.smoothing > 0.0)
            EXPECT_LE(worst, 1e-6 * size) << name;
        else
            EXPECT_EQ(worst, 0.0) << name;
    }
}

// A tetrahedron: nothing can be collapsed (each collapse would leave a non-manifold two faces).
TEST(MultiscaleLevels, TinyMeshGetsOnlyTheInputAndSaysSo) {
    TriangleMesh t;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    t.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const Model model(t);
    const MultiscaleLevels L = build_multiscale_levels(model);
    EXPECT_EQ(L.levels, 1);
    EXPECT_NE(L.note.find("only the input level"), std::string::npos) << L.note;
    EXPECT_NE(L.note.find("too small"), std::string::npos) << L.note;
    const Camera cam = test::framed_camera(model.topology().bounds);
    MultiscaleSession s(model, L, ViewOptions{}, {.target_px = 50.0});
    const View& v = s.render(cam);
    EXPECT_EQ(v.drawing.pieces.size(), render_view(model, cam).drawing.pieces.size());
}

// The progress of the pre-process: one call a step (the model's curvature, the simplification,
// each smoothed level), in order, the last at the total, also when fewer levels are built.
TEST(MultiscaleLevels, ProgressCountsEachStepOnce) {
    for (const std::string name : {"elephant", "tetrahedron"}) {
        const Model model = Model::load(test::mesh_path(name));
        std::vector<std::pair<int, int>> calls;
        MultiscaleOptions options;
        options.progress = [&calls](int done, int total) { calls.emplace_back(done, total); };
        const MultiscaleLevels L = build_multiscale_levels(model, options);
        ASSERT_FALSE(calls.empty()) << name;
        for (std::size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].second, 5) << name;
        for (std::size_t i = 1; i < calls.size(); ++i) EXPECT_GT(calls[i].first, calls[i - 1].first) << name;
        EXPECT_EQ(calls.back().first, 5) << name;
        EXPECT_EQ(calls.size(), L.levels == 4 ? 5u : 3u) << name;
    }
}

TEST(MultiscaleLevels, BordersEverywhereStillDraw) {
    // A strip of 2 x 40 vertices: every vertex on the border. Collapses along the border may go,
    // the rest cannot: the levels the mesh allows, and a drawing either way.
    TriangleMesh t;
    for (int i = 0; i < 40; ++i) t.positions.push_back({double(i), 0.0, 0.1 * std::sin(i)}), t.positions.push_back({double(i), 1.0, 0.0});
    for (std::uint32_t i = 0; i + 1 < 40; ++i) {
        t.triangles.push_back({2 * i, 2 * i + 2, 2 * i + 1});
        t.triangles.push_back({2 * i + 1, 2 * i + 2, 2 * i + 3});
    }
    const Model model(t);
    const MultiscaleLevels L = build_multiscale_levels(model);
    EXPECT_EQ(L.levels == 1, !L.note.empty());
    const Camera cam = test::framed_camera(model.topology().bounds);
    MultiscaleSession s(model, L, ViewOptions{}, {.target_px = 50.0});
    EXPECT_GT(s.render(cam).drawing.pieces.size(), 0u);
}

TEST(MultiscaleLevels, NonManifoldVertexGetsOnlyTheInput) {
    // Two tetrahedra sharing one vertex: a valid drawing input (every edge has two faces), but
    // OpenMesh's half-edge structure refuses the second fan there.
    TriangleMesh t;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
    t.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 5, 4}, {0, 4, 6}, {0, 6, 5}, {4, 5, 6}};
    const Model model(t);
    const MultiscaleLevels L = build_multiscale_levels(model);
    EXPECT_EQ(L.levels, 1);
    EXPECT_NE(L.note.find("non-manifold"), std::string::npos) << L.note;
}

TEST(MultiscaleView, LevelsFollowDistance) {
    const Built& b = built("armadillo");
    const MeshTopology& m = b.model->topology();
    const Camera near = test::framed_camera(m.bounds);
    // T such that L projects to T at the model's centre: l = log2(d / d_centre) per vertex.
    const double d = glm::length(near.eye() - m.bounds.center());
    const double target = b.levels.feature_size * near.focal() / d;
    std::vector<float> levels;
    multiscale_vertex_levels(*b.model, b.levels, near, {.target_px = target}, levels);
    for (std::size_t v = 0; v < m.vertex_count(); v += 997) {
        const double expect = std::clamp(std::log2(glm::length(near.eye() - m.positions[v]) / d), 0.0, 3.0);
        EXPECT_NEAR(levels[v], expect, 1e-5);
    }
    // 4x farther: about level 2; orthographic: one level everywhere.
    const Camera far = Camera::perspective(m.bounds.center() + 4.0 * (near.eye() - m.bounds.center()), m.bounds.center(),
                                           {0, 1, 0}, 30.0, 1024, 1024);
    multiscale_vertex_levels(*b.model, b.levels, far, {.target_px = target}, levels);
    EXPECT_NEAR(levels[0], 2.0, 0.1);
    const Camera ortho = Camera::orthographic(near.eye(), m.bounds.center(), {0, 1, 0}, 400.0, 1024, 1024);
    multiscale_vertex_levels(*b.model, b.levels, ortho, {.target_px = 8.0}, levels);
    const float l = float(std::log2(8.0 / (b.levels.feature_size * 1024.0 / 400.0)));
    for (std::size_t v = 0; v < m.vertex_count(); v += 997) EXPECT_FLOAT_EQ(levels[v], std::clamp(l, 0.0f, 3.0f));
}

// The target per object (--detail-object) and with depth (--detail-depth): two spheres, objects
// "A" and "B"; B's own target 4x A's puts B two levels finer; E = -1 puts every vertex at the
// centre's level, E = 1 doubles the level's growth with distance.
TEST(MultiscaleView, TargetPerObjectAndWithDepth) {
    TriangleMesh a = make_sphere({-2, 0, 0}, 1.0, 32, 16), b = make_sphere({2, 0, 0}, 1.0, 32, 16);
    TriangleMesh t = a;
    const auto offset = std::uint32_t(a.positions.size());
    t.positions.insert(t.positions.end(), b.positions.begin(), b.positions.end());
    for (auto f : b.triangles) t.triangles.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
    t.face_object.assign(a.triangles.size(), 0);
    t.face_object.resize(t.triangles.size(), 1);
    t.object_names = {"A", "B"};
    const Model model(t);
    const MeshTopology& m = model.topology();
    MultiscaleLevels L;
    L.levels = 8;
    L.feature_size = 0.002;  // (every level between 2 and 6: none clamped)
    const Camera cam = Camera::perspective({0, 3, 12}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800);
    const double d0 = L.feature_size * cam.focal() / 2.0;  // T = 2 px: level log2(d / d0)
    std::vector<float> levels;
    multiscale_vertex_levels(model, L, cam, {.target_px = 2.0, .object_target_px = {{"B", 8.0}}}, levels);
    for (std::size_t v = 0; v < m.vertex_count(); v += 7) {
        const double base = std::log2(glm::length(cam.eye() - m.positions[v]) / d0);
        ASSERT_GT(base, 1.0);
        EXPECT_NEAR(levels[v], v < offset ? base : base + 2.0, 1e-5) << v;
    }
    EXPECT_EQ(unknown_detail_objects(m, {.object_target_px = {{"B", 8.0}, {"C", 1.0}, {"D", 1.0}}}), "'C', 'D'");
    const double log_ref = std::log2(glm::length(cam.eye() - m.bounds.center()));
    multiscale_vertex_levels(model, L, cam, {.target_px = 2.0, .depth_exponent = -1.0}, levels);
    for (std::size_t v = 0; v < m.vertex_count(); v += 7) EXPECT_NEAR(levels[v], log_ref - std::log2(d0), 1e-5) << v;
    multiscale_vertex_levels(model, L, cam, {.target_px = 2.0, .depth_exponent = 1.0}, levels);
    for (std::size_t v = 0; v < m.vertex_count(); v += 7) {
        const double log_d = std::log2(glm::length(cam.eye() - m.positions[v]));
        EXPECT_NEAR(levels[v], 2.0 * log_d - log_ref - std::log2(d0), 1e-5) << v;
    }
}

// Issue 43's density check: along a dolly from the framed view to 8x farther, visible line length
// per unit of the model's image area grows with distance (an outline's length shrinks like 1/d,
// the area like 1/d^2: a fixed drawing's density grows 8x); with detail control the fine lines
// go, so its growth is at most half of the plain drawing's, while at the start the two agree
// within 10 % of length. T: L's projection at the model's centre in the framed view (level 0
// there at the start, level 3 at 8x).
void check_density(const std::string& name, double most, const MultiscaleLevels* levels = nullptr) {
    const Built& b = built(name);
    const MultiscaleLevels& L = levels ? *levels : b.levels;
    const MeshTopology& m = b.model->topology();
    const int size = 1024;
    const Camera framed = test::framed_camera(m.bounds, size);
    const double target = L.feature_size * framed.focal() / glm::length(framed.eye() - m.bounds.center());
    MultiscaleSession s(*b.model, L, suggestive_view(), {.target_px = target});
    ViewSession plain(*b.model, suggestive_view());
    const test::DollyDensity g = test::dolly_density(
        m.bounds, framed, [&](const Camera& cam) { return test::visible_length_px(plain.render(cam).drawing); },
        [&](const Camera& cam) { return test::visible_length_px(s.render(cam).drawing); });
    EXPECT_NEAR(g.detail_start, g.plain_start, 0.1 * g.plain_start) << name << ": at the start";
    const double growth_plain = g.plain_growth, growth_detail = g.detail_growth;
    std::printf("%s: density growth 1x -> 8x: plain %.2f, detail %.2f\n", name.c_str(), growth_plain, growth_detail);
    EXPECT_GT(growth_plain, 4.0) << name;
    EXPECT_LE(growth_detail, most * growth_plain) << name;
}

TEST(MultiscaleDensity, Armadillo) { check_density("armadillo", 0.5); }
TEST(MultiscaleDensity, Elephant) { check_density("elephant", 0.5); }
// The implicit post-pass that spares thin parts (MultiscaleOptions::smoothing, thin_guard: level k
// solved from (W + t_k L^2) x = p, t_k = 4 * 16^(k - 1), each vertex's reach at most a tenth of
// the shape's thickness there) on the second-order levels at the seed's r = 3/4 meets both of
// issue 43's checks on armadillo: M3's mean |k1| 0.782 of M0's (the issue: well below; <= 0.8 here)
// and the density growth 0.45 of plain (<= 0.5). (On bunny and elephant it does not: 0.59 and
// 0.78 of plain, docs/detail.md; the default stays.)
TEST(MultiscaleDensity, ThinGuardedLevelsMeetBothChecksOnArmadillo) {
    const Built& b = built("armadillo");
    const MultiscaleLevels L = build_multiscale_levels(*b.model, thin_guarded({}));  // --detail-smoothing=thin-guarded
    ASSERT_EQ(L.levels, 4);
    EXPECT_EQ(level_positions(*b.model, L, 0), b.model->topology().positions);
    EXPECT_LE(L.mean_abs_k1[3], 0.8 * L.mean_abs_k1[0]);
    EXPECT_NEAR(L.mean_abs_k1[3], 0.1461, 0.0005);
    check_density("armadillo", 0.5, &L);
}

// The bunny's drawing at 8x is little more than its outline, whose density grows 8x like any fixed
// drawing's; with the levels independent of the numbering (quadric-error ends, 4 umbrella sweeps)
// it meets half too: measured 3.57 against 7.33 (0.487; the levels before them: 0.51).
TEST(MultiscaleDensity, Bunny) { check_density("bunny00", 0.5); }

// The command: flags checked before any work (usage errors, exit 2, one line naming the flag);
// --detail draws and reports its levels; a mesh without smoothed levels warns and still draws.
TEST(MultiscaleCli, FlagsAndWarnings) {
    using inkline_test::run_inkline;
    const auto dir = inkline_test::scratch("detail_");
    const std::string bunny = test::mesh_path("bunny00") + " -o " + (dir / "b.json").string();
    const struct {
        std::string args, words;
    } bad[] = {
        {"--detail=0", "--detail: expected a target size in pixels"},
        {"--detail=-3", "--detail: expected a target size in pixels"},
        {"--detail=4 --levels=1", "--levels"},
        {"--detail=4 --levels=9", "--levels"},
        {"--levels=3", "--levels needs --detail=PX"},
        {"--detail-ratio=0.5", "--detail-ratio needs --detail=PX"},
        {"--detail=4 --detail-ratio=1", "--detail-ratio: expected a ratio in (0, 1)"},
        {"--detail=4 --detail-method=spiral", "--detail-method: unknown method 'spiral' (expected multiscale or pm)"},
        {"--detail=4 --detail-depth=5", "--detail-depth: expected an exponent in [-1, 4]"},
        {"--detail=4 --detail-depth=-1.5", "--detail-depth: expected an exponent in [-1, 4]"},
        {"--detail-object=a=3", "--detail-object needs --detail=PX"},
        {"--detail=4 --detail-object=a", "--detail-object: expected NAME=PX"},
        {"--detail=4 --detail-object=a=0", "--detail-object: expected a target size in pixels"},
        {"--detail=4 --detail-object=Head=3", "has no object named 'Head'"},
        {"--detail=4 --cache=", "--cache: expected a folder"},
        {"--detail=4 --detail-method=pm --detail-fairing=second-order", "are for --detail-method=multiscale"},
        {"--detail-smoothing=thin-guarded", "--detail-smoothing needs --detail=PX"},
        {"--detail=4 --detail-smoothing=gauss", "--detail-smoothing: unknown smoothing 'gauss' (expected none or thin-guarded)"},
    };
    for (const auto& b : bad) {
        const auto r = run_inkline("", "render " + bunny + " " + b.args, dir);
        EXPECT_EQ(r.code, 2) << b.args;
        EXPECT_NE(r.err.find(b.words), std::string::npos) << b.args << ": " << r.err;
    }
    // The window refuses before it opens what it cannot honour (it used to ignore them).
    for (const auto& [args, words] : {std::pair<std::string, std::string>{"--detail=4 --detail-object=a=3", "render and bench only"},
                                      {"--detail=4 --detail-method=pm --detail-smoothing=thin-guarded",
                                       "are for --detail-method=multiscale"}}) {
        const auto r = run_inkline("", "view " + test::mesh_path("bunny00") + " " + args, dir);
        EXPECT_EQ(r.code, 2) << args;
        EXPECT_NE(r.err.find(words), std::string::npos) << args << ": " << r.err;
    }
    const auto ok = run_inkline("", "render " + bunny + " --detail=5 --levels=3", dir);
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_NE(ok.out.find("detail: multiscale, target 5 px, 3 levels"), std::string::npos) << ok.out;
    const std::string elephant = test::mesh_path("elephant") + " -o " + (dir / "e.json").string();
    const auto guarded = run_inkline("", "render " + elephant + " --detail=5 --detail-smoothing=thin-guarded", dir);
    EXPECT_EQ(guarded.code, 0) << guarded.err;
    EXPECT_NE(guarded.out.find("detail: multiscale, target 5 px, 4 levels, thin-guarded smoothing"), std::string::npos)
        << guarded.out;
    // Two tetrahedra sharing a vertex: drawn, with one warning line naming the file.
    const auto off = dir / "bowtie.off";
    std::ofstream(off) << "OFF\n7 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n-1 0 0\n0 -1 0\n0 0 -1\n"
                          "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 5 4\n3 0 4 6\n3 0 6 5\n3 4 5 6\n";
    const auto warned = run_inkline("", "render " + off.string() + " --detail=5 -o " + (dir / "t.json").string(), dir);
    EXPECT_EQ(warned.code, 0) << warned.err;
    EXPECT_NE(warned.err.find("warning: " + off.string() + ": only the input level"), std::string::npos) << warned.err;
    EXPECT_EQ(std::count(warned.err.begin(), warned.err.end(), '\n'), 1) << warned.err;  // (not OpenMesh's own too)
}

// --cache: the levels written once, read back identical; a changed option is another file; a
// corrupt, truncated or stale file is detected, rebuilt and rewritten; no temporary file stays.
void expect_same_levels(const MultiscaleLevels& a, const MultiscaleLevels& b) {
    EXPECT_EQ(a.levels, b.levels);
    EXPECT_EQ(a.ratio, b.ratio);
    EXPECT_EQ(a.feature_size, b.feature_size);
    EXPECT_EQ(a.collapses, b.collapses);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.normal_oct, b.normal_oct);
    EXPECT_EQ(a.dir1_angle, b.dir1_angle);
    EXPECT_EQ(a.k1, b.k1);
    EXPECT_EQ(a.k2, b.k2);
    EXPECT_EQ(a.dcurv, b.dcurv);
    EXPECT_EQ(a.valid, b.valid);
    EXPECT_EQ(a.mean_abs_k1, b.mean_abs_k1);
    EXPECT_EQ(a.levels_self_intersect, b.levels_self_intersect);
}

// Damages a cache file as a crash, a full disk or another version would: a flipped byte in the
// middle, the last 100 bytes cut, emptied, or (`rewrite_stale`) rewritten whole for another key.
void damage_cache_file(const std::string& path, const std::string& what, const std::function<void()>& rewrite_stale) {
    const auto size = std::filesystem::file_size(path);
    if (what == "flip") {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(std::streamoff(size / 2));
        const char c = char(f.get());
        f.seekp(std::streamoff(size / 2));
        f.put(char(c ^ 0x10));
    }
    if (what == "truncate") std::filesystem::resize_file(path, size - 100);
    if (what == "empty") std::filesystem::resize_file(path, 0);
    if (what == "stale") rewrite_stale();
}
const char* const kCacheDamage[] = {"flip", "truncate", "empty", "stale"};
// The words a damaged file's warning must hold.
std::string cache_problem_words(const std::string& what) {
    return what == "stale" ? "stale" : what == "empty" ? "truncated" : "checksum";
}

TEST(MultiscaleCache, WrittenOnceReadBackRebuiltWhenBad) {
    const std::string path = test::mesh_path("elephant");
    const Model model = Model::load(path);
    const auto dir = inkline_test::scratch("detail_cache_");
    const std::string folder = (dir / "levels").string();  // made by the first write
    const MultiscaleOptions options;
    const CachedLevels first = cached_multiscale_levels(model, path, "v", options, folder);
    ASSERT_EQ(first.outcome, CacheOutcome::Built) << first.problem;
    expect_same_levels(first.levels, build_multiscale_levels(model, options));
    const CachedLevels again = cached_multiscale_levels(model, path, "v", options, folder);
    ASSERT_EQ(again.outcome, CacheOutcome::Loaded) << again.problem;
    EXPECT_EQ(again.path, first.path);
    expect_same_levels(again.levels, first.levels);
    // Another ratio, fairing or loader variant: another file, built.
    EXPECT_EQ(cached_multiscale_levels(model, path, "v", {.ratio = 0.75}, folder).outcome, CacheOutcome::Built);
    EXPECT_EQ(cached_multiscale_levels(model, path, "w", options, folder).outcome, CacheOutcome::Built);
    EXPECT_EQ(cached_multiscale_levels(model, path, "v", {.fairing = MultiscaleFairing::SecondOrder}, folder).outcome,
              CacheOutcome::Built);
    // The implicit post-pass's parameters are in the key too (each its own file); the same ones again are read.
    const MultiscaleOptions smoothed{.smoothing = 0.5};
    EXPECT_EQ(cached_multiscale_levels(model, path, "v", smoothed, folder).outcome, CacheOutcome::Built);
    EXPECT_EQ(cached_multiscale_levels(model, path, "v", {.smoothing = 0.5, .smoothing_order = 1}, folder).outcome,
              CacheOutcome::Built);
    EXPECT_EQ(cached_multiscale_levels(model, path, "v", {.smoothing = 0.5, .thin_guard = 0.1}, folder).outcome,
              CacheOutcome::Built);
    const CachedLevels smoothed_again = cached_multiscale_levels(model, path, "v", smoothed, folder);
    EXPECT_EQ(smoothed_again.outcome, CacheOutcome::Loaded);
    expect_same_levels(smoothed_again.levels, build_multiscale_levels(model, smoothed));
    for (const std::string what : kCacheDamage) {
        damage_cache_file(first.path, what, [&] { write_levels_file(first.path, 12345, first.levels); });  // another key
        const CachedLevels bad = cached_multiscale_levels(model, path, "v", options, folder);
        EXPECT_EQ(bad.outcome, CacheOutcome::Rebuilt) << what;
        EXPECT_NE(bad.problem.find(first.path), std::string::npos) << what << ": " << bad.problem;
        EXPECT_NE(bad.problem.find(cache_problem_words(what)), std::string::npos) << what << ": " << bad.problem;
        expect_same_levels(bad.levels, first.levels);
        EXPECT_EQ(cached_multiscale_levels(model, path, "v", options, folder).outcome, CacheOutcome::Loaded) << what;
    }
    // Seven files (two options, a variant, a fairing and three post-passes besides the first), no
    // temporary ones.
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(folder)) {
        ++files;
        EXPECT_EQ(e.path().extension(), ".levels") << e.path();
    }
    EXPECT_EQ(files, 7u);
}

// A --cache command's round (`args` without -o): the first run builds and writes the file (its
// report says so), the second reads it (no warning) and draws the same lines; with every file in
// the cache cut to 100 bytes, a run warns once (a checksum) and draws the same again.
void check_cache_round(const std::string& args, const std::filesystem::path& dir, const std::string& cache) {
    using inkline_test::run_inkline;
    const auto built = run_inkline("", args + " -o " + (dir / "a.json").string(), dir);
    ASSERT_EQ(built.code, 0) << built.err;
    EXPECT_NE(built.out.find("(built, cached as " + cache), std::string::npos) << built.out;
    const auto read = run_inkline("", args + " -o " + (dir / "b.json").string(), dir);
    ASSERT_EQ(read.code, 0) << read.err;
    EXPECT_NE(read.out.find("(read from " + cache), std::string::npos) << read.out;
    EXPECT_EQ(read.err, "");
    const auto polylines = [](const std::filesystem::path& p) {
        std::ifstream in(p);
        const std::string j((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return j.substr(j.find("\"polylines\""));
    };
    EXPECT_EQ(polylines(dir / "a.json"), polylines(dir / "b.json"));
    for (const auto& e : std::filesystem::directory_iterator(cache)) std::filesystem::resize_file(e.path(), 100);
    const auto rebuilt = run_inkline("", args + " -o " + (dir / "c.json").string(), dir);
    ASSERT_EQ(rebuilt.code, 0) << rebuilt.err;
    EXPECT_EQ(std::count(rebuilt.err.begin(), rebuilt.err.end(), '\n'), 1) << rebuilt.err;
    EXPECT_NE(rebuilt.err.find("inkline: warning: --cache: " + cache), std::string::npos) << rebuilt.err;
    EXPECT_NE(rebuilt.err.find("checksum"), std::string::npos) << rebuilt.err;
    EXPECT_EQ(polylines(dir / "a.json"), polylines(dir / "c.json"));
}

// The command: --cache needs --detail; the second run reads the levels; a corrupt file gives one
// warning line and the same drawing.
TEST(MultiscaleCache, Command) {
    using inkline_test::run_inkline;
    const auto dir = inkline_test::scratch("detail_cache_cli_");
    const std::string cache = (dir / "c").string();
    const std::string elephant = test::mesh_path("elephant");
    const auto bad = run_inkline("", "render " + elephant + " --cache=" + cache + " -o " + (dir / "x.json").string(), dir);
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.err.find("--cache needs --detail=PX"), std::string::npos) << bad.err;
    check_cache_round("render " + elephant + " --detail=8 --cache=" + cache, dir, cache);
}

// The progressive mesh's hierarchy in the cache: the same collapse sequence read back as built,
// another loader variant another file, a damaged or stale file rebuilt with its problem named, and
// a file whose records name vertices the mesh lacks refused (its checksum valid).
TEST(ProgressiveMeshCache, WrittenOnceReadBackRebuiltWhenBad) {
    const std::string path = test::mesh_path("elephant");
    const Model model = Model::load(path);
    const MeshTopology& t = model.topology();
    const auto dir = inkline_test::scratch("pm_cache_");
    const std::string folder = (dir / "pm").string();  // made by the first write
    const CachedHierarchy first = cached_progressive_mesh(t, path, "v", folder);
    ASSERT_EQ(first.outcome, CacheOutcome::Built) << first.problem;
    const ProgressiveMesh built(t);
    ASSERT_GT(built.collapses(), 2700u);
    EXPECT_EQ(first.pm->removed_vertex(), built.removed_vertex());
    EXPECT_EQ(first.pm->kept_vertex(), built.kept_vertex());
    const CachedHierarchy again = cached_progressive_mesh(t, path, "v", folder);
    ASSERT_EQ(again.outcome, CacheOutcome::Loaded) << again.problem;
    EXPECT_EQ(again.path, first.path);
    EXPECT_EQ(again.pm->removed_vertex(), built.removed_vertex());
    EXPECT_EQ(again.pm->kept_vertex(), built.kept_vertex());
    EXPECT_EQ(&again.pm->input().positions, &t.positions);  // (over the model's arrays, no copy)
    EXPECT_EQ(cached_progressive_mesh(t, path, "w", folder).outcome, CacheOutcome::Built);
    for (const std::string what : kCacheDamage) {
        damage_cache_file(first.path, what, [&] { write_hierarchy_file(first.path, 12345, t.vertex_count(), built); });
        const CachedHierarchy bad = cached_progressive_mesh(t, path, "v", folder);
        EXPECT_EQ(bad.outcome, CacheOutcome::Rebuilt) << what;
        EXPECT_NE(bad.problem.find(first.path), std::string::npos) << what << ": " << bad.problem;
        EXPECT_NE(bad.problem.find(cache_problem_words(what)), std::string::npos) << what << ": " << bad.problem;
        EXPECT_EQ(bad.pm->removed_vertex(), built.removed_vertex()) << what;
        EXPECT_EQ(cached_progressive_mesh(t, path, "v", folder).outcome, CacheOutcome::Loaded) << what;
    }
    // A valid file of the right key whose records come from a larger mesh: refused as corrupt.
    const ProgressiveMesh larger(load_mesh(test::mesh_path("fandisk")));  // (6 475 vertices against 2 775)
    std::vector<std::uint32_t> removed, kept;
    std::string problem;
    const std::string odd = (dir / "odd.pm").string();
    write_hierarchy_file(odd, 7, t.vertex_count(), larger);
    EXPECT_FALSE(read_hierarchy_file(odd, 7, t.vertex_count(), removed, kept, problem));
    EXPECT_NE(problem.find("corrupt"), std::string::npos) << problem;
    EXPECT_THROW(ProgressiveMesh(t, larger.removed_vertex(), larger.kept_vertex(), 0.0), std::invalid_argument);
    EXPECT_THROW(ProgressiveMesh(t, {1, 2}, {3}, 0.0), std::invalid_argument);
    // Three files (two variants; the odd one is outside the folder), no temporary ones.
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(folder)) {
        ++files;
        EXPECT_EQ(e.path().extension(), ".pm") << e.path();
    }
    EXPECT_EQ(files, 2u);
}

// The command with --detail-method=pm: the second run reads the hierarchy and draws the same; a
// corrupt file gives one warning line and the same drawing.
TEST(ProgressiveMeshCache, Command) {
    const auto dir = inkline_test::scratch("pm_cache_cli_");
    const std::string cache = (dir / "c").string();
    check_cache_round("render " + test::mesh_path("elephant") + " --detail=6 --detail-method=pm --cache=" + cache, dir,
                      cache);
}

// Issue 43's temporal coherence: along a slow dolly (1 % of the distance a frame) no line pops in
// or out in one frame at full length. The previous drawing is scaled about the image centre by
// the dolly's zoom (exact at the target's depth) before the two are compared; a pop is a visible
// piece of at least 20 px of which less than a tenth lies within 2 px of the other drawing's lines.
struct NearMask {
    int w, h;
    std::vector<std::uint8_t> near;
    NearMask(const Drawing& d, int width, int height, double scale, double reach)
        : w(width), h(height), near(std::size_t(w) * std::size_t(h), 0) {
        const glm::dvec2 centre(0.5 * w, 0.5 * h);
        const int r = int(std::ceil(reach));
        for (const Piece& p : d.pieces) {
            if (p.qi != 0) continue;
            for (std::size_t i = 1; i < p.points.size(); ++i) {
                const glm::dvec2 a = centre + scale * (p.points[i - 1] - centre), b = centre + scale * (p.points[i] - centre);
                const int n = std::max(1, int(std::ceil(2.0 * glm::length(b - a))));
                for (int k = 0; k <= n; ++k) {
                    const glm::dvec2 q = a + (b - a) * (double(k) / double(n));
                    for (int dy = -r; dy <= r; ++dy)
                        for (int dx = -r; dx <= r; ++dx) {
                            const int x = int(std::floor(q.x)) + dx, y = int(std::floor(q.y)) + dy;
                            if (x >= 0 && y >= 0 && x < w && y < h) near[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 1;
                        }
                }
            }
        }
    }
    bool covers(glm::dvec2 q) const {
        const int x = int(std::floor(q.x)), y = int(std::floor(q.y));
        return x >= 0 && y >= 0 && x < w && y < h && near[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    }
};

// Pieces of `d` (at least `min_px` long) of which less than a tenth is covered by `other`.
int popped_pieces(const Drawing& d, const NearMask& other, double min_px) {
    int popped = 0;
    for (const Piece& p : d.pieces) {
        if (p.qi != 0) continue;
        double length = 0.0, covered = 0.0;
        for (std::size_t i = 1; i < p.points.size(); ++i) {
            const double l = glm::length(p.points[i] - p.points[i - 1]);
            length += l;
            if (other.covers(0.5 * (p.points[i] + p.points[i - 1]))) covered += l;
        }
        popped += length >= min_px && covered < 0.1 * length;
    }
    return popped;
}

TEST(MultiscaleCoherence, SlowDollyPopsNoLine) {
    const Built& b = built("armadillo");
    const MeshTopology& m = b.model->topology();
    const Camera framed = test::framed_camera(m.bounds);
    const double target = b.levels.feature_size * framed.focal() / glm::length(framed.eye() - m.bounds.center());
    MultiscaleSession s(*b.model, b.levels, suggestive_view(), {.target_px = target});
    const glm::dvec3 c = m.bounds.center(), offset = framed.eye() - c;
    std::unique_ptr<Drawing> previous;
    int pops = 0;
    for (int i = 0; i <= 20; ++i) {  // from 2x, where every vertex blends between levels 0 .. 2
        const double factor = 2.0 * std::pow(1.01, i);
        const Camera cam = Camera::perspective(c + factor * offset, c, {0, 1, 0}, 30.0, 1024, 1024);
        auto now = std::make_unique<Drawing>(s.render(cam).drawing);
        if (previous) {
            // (each drawing compared with the other brought to its scale)
            const NearMask before(*previous, 1024, 1024, 1.0 / 1.01, 2.0), after(*now, 1024, 1024, 1.01, 2.0);
            pops += popped_pieces(*now, before, 20.0) + popped_pieces(*previous, after, 20.0);
        }
        previous = std::move(now);
    }
    EXPECT_EQ(pops, 0);
}

// --detail with a sequence (--frames --orbit, on two jobs): the levels built once for the run,
// and each frame is the drawing a single render with that frame's camera makes.
TEST(MultiscaleCli, OrbitFramesWithDetail) {
    using inkline_test::run_inkline;
    const auto dir = inkline_test::scratch("detail_orbit_");
    const std::string elephant = test::mesh_path("elephant");
    const auto run = run_inkline("", "render " + elephant + " --detail=8 --frames=3 --orbit --jobs=2 --verbose -o " +
                                         (dir / "f_%d.json").string(), dir);
    ASSERT_EQ(run.code, 0) << run.err;
    std::vector<std::string> cameras;
    for (std::size_t at = run.out.find("\ncamera: "); at != std::string::npos; at = run.out.find("\ncamera: ", at + 1)) {
        const std::size_t end = run.out.find('\n', at + 1);
        cameras.push_back(run.out.substr(at + 9, end - at - 9));
    }
    ASSERT_EQ(cameras.size(), 4u) << run.out;  // three frames and the run's summary
    std::size_t detail_lines = 0;
    for (std::size_t at = run.out.find("detail: multiscale"); at != std::string::npos; at = run.out.find("detail: multiscale", at + 1))
        ++detail_lines;
    EXPECT_EQ(detail_lines, 3u) << run.out;
    const auto slurp = [](const std::filesystem::path& p) {
        std::ifstream in(p);
        const std::string j((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return j.substr(std::min(j.size(), j.find("\"polylines\"")));
    };
    const auto single = run_inkline("", "render " + elephant + " --detail=8 " + cameras[2] + " -o " +
                                            (dir / "single.json").string(), dir);
    ASSERT_EQ(single.code, 0) << single.err;
    EXPECT_EQ(slurp(dir / "f_2.json"), slurp(dir / "single.json"));
    EXPECT_NE(slurp(dir / "f_0.json"), slurp(dir / "f_2.json"));
    // Several models with --detail: refused before any work, as before.
    const auto two = run_inkline("", "render " + elephant + " " + test::mesh_path("bunny00") + " --detail=8 -o " + (dir / "m/").string(), dir);
    EXPECT_EQ(two.code, 2);
    EXPECT_NE(two.err.find("--detail: one model a run"), std::string::npos) << two.err;
}

}  // namespace
}  // namespace inkline
