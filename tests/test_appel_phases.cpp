// The phases of the fast visibility (visibility/appel_phases.hpp), each on its own: hand-made
// state where the phase reads only the propagation's arrays, small real meshes where it reads
// the view. Every expected value is derived in a comment.
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "model/primitives.hpp"
#include "model/topology.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"
#include "visibility/appel_phases.hpp"

namespace inkline {
namespace {

MeshTopology topology(TriangleMesh m) {
    validate_mesh(m, "test mesh");
    return build_topology(m, 40.0);
}


// One view of a mesh, its pieces built, ready for the phases.
struct Scene {
    MeshTopology mesh;
    Camera cam;
    Features f;
    PieceGraph graph;
    std::unique_ptr<RayCaster> caster;
    std::function<const RayCaster&()> rays = [this]() -> const RayCaster& {
        if (!caster) caster = std::make_unique<RayCaster>(mesh);
        return *caster;
    };
    AppelOptions options;
    Scene(TriangleMesh m, const Camera& c) : mesh(topology(std::move(m))), cam(c), f(extract_features(mesh, cam)) {
        build_pieces(graph, mesh, f, cam);
    }
    AppelPropagation propagation() { return AppelPropagation(mesh, cam, f.face_front, rays, graph, options); }
};

// The box [-1, 1]^3 from (3, 4, 5) (ExtractFeatures.BoxFromACorner): twelve one-edge curves, no
// crossings, so twelve pieces; they end at the eight corners.
Scene box_from_a_corner() {
    return Scene(make_box({-1, -1, -1}, {1, 1, 1}), Camera::perspective({3, 4, 5}, {0, 0, 0}, {0, 1, 0}, 40.0, 400, 300));
}

bool touches_far_corner(const Scene& s, std::uint32_t piece) {
    const std::uint32_t e = s.graph.curves.spans[piece].front().edge;
    for (std::uint32_t v : s.mesh.edge_vertex[e])
        if (s.mesh.positions[v] == glm::dvec3(-1, -1, -1)) return true;
    return false;
}

// Hand-made state for the phases that read only the propagation's arrays: `np` pieces, no vertex
// nodes, every piece its own cluster unless set otherwise.
struct HandMade {
    Scene scene = box_from_a_corner();  // (only for the references the type holds)
    AppelPropagation a = scene.propagation();
    explicit HandMade(std::uint32_t np, std::vector<PieceGraph::Link> links = {}) {
        a.np = a.nn = np;
        a.graph.links = std::move(links);
        a.comp.resize(np);
        a.off.assign(np, 0);
        for (std::uint32_t p = 0; p < np; ++p) a.comp[p] = p;
        a.nc = np;
        a.state.assign(np, AppelPropagation::kBound);
        a.base.assign(np, 0);
    }
};

TEST(OffsetForest, OffsetsAlongUnionsAndContradictions) {
    OffsetForest f(4);
    EXPECT_TRUE(f.unite(0, 1, 2));   // v1 = v0 + 2
    EXPECT_TRUE(f.unite(2, 1, -1));  // v1 = v2 - 1: v2 = v0 + 3
    int o0, o2, o3;
    const std::uint32_t r0 = f.find(0, o0), r2 = f.find(2, o2), r3 = f.find(3, o3);
    EXPECT_EQ(r0, r2);
    EXPECT_EQ(o2 - o0, 3);
    EXPECT_NE(r3, r0);
    EXPECT_EQ(o3, 0);
    EXPECT_TRUE(f.unite(0, 2, 3));   // what is known already
    EXPECT_FALSE(f.unite(2, 0, 3));  // v0 = v2 + 3 contradicts v2 = v0 + 3
}

// Links 0 -> 1 (+2) and 1 -> 2 (-1): values v0, v0 + 2, v0 + 1 in one cluster, whose lower bound
// puts its least value at 0: QI 0, 2, 1. Piece 3 is alone: QI 0. A third link 2 -> 0 with change 0
// contradicts v2 = v0 + 1: the cluster is inconsistent.
TEST(AppelPhases, UniteAlongCurvesAndFormClusters) {
    for (const bool contradiction : {false, true}) {
        HandMade h(4, {{0, 1}, {1, 2}});
        AppelPropagation& a = h.a;
        a.link_delta = {2, -1};
        if (contradiction) a.graph.links.push_back({2, 0}), a.link_delta.push_back(0);
        a.forest.reset(4);
        a.bad.assign(4, 0);
        a.pierced.assign(4, 0);
        a.unite_along_curves();
        a.form_clusters();
        ASSERT_EQ(a.nc, 2u);
        EXPECT_EQ(a.st.clusters, 2u);
        EXPECT_EQ(a.comp, (std::vector<std::uint32_t>{0, 0, 0, 1}));
        EXPECT_EQ(a.value(0), 0);
        EXPECT_EQ(a.value(1), 2);
        EXPECT_EQ(a.value(2), 1);
        EXPECT_EQ(a.value(3), 0);
        EXPECT_EQ(a.state[0], contradiction ? AppelPropagation::kInconsistent : AppelPropagation::kBound);
        EXPECT_EQ(a.state[1], AppelPropagation::kBound);
    }
}

// A link across a pierced piece is not united: pieces 0 and 1 stay apart, and 1's cluster is
// inconsistent (counted).
TEST(AppelPhases, PiercedPiecesTakeNoPartInPropagation) {
    HandMade h(2, {{0, 1}});
    AppelPropagation& a = h.a;
    a.link_delta = {2};
    a.forest.reset(2);
    a.bad.assign(2, 0);
    a.pierced = {0, 1};
    a.unite_along_curves();
    a.form_clusters();
    EXPECT_EQ(a.nc, 2u);
    EXPECT_EQ(a.state[a.comp[0]], AppelPropagation::kBound);
    EXPECT_EQ(a.state[a.comp[1]], AppelPropagation::kInconsistent);
    EXPECT_EQ(a.st.pierced, 1u);
}

// The flags of the box's faces: the pieces on an edge of a flagged face are pierced (the box's
// faces are triangles; face 0 has three edges, each of which a piece may lie on).
TEST(AppelPhases, MarkPiercedFindsThePiecesOnFlaggedFaces) {
    Scene s = box_from_a_corner();
    std::vector<std::uint8_t> flags(s.mesh.face_count(), 0);
    flags[0] = 1;
    s.options.pierced_faces = &flags;
    ASSERT_EQ(s.graph.curves.pieces.size(), 12u);
    AppelPropagation a = s.propagation();
    a.mark_pierced();
    ASSERT_EQ(a.pierced.size(), 12u);
    for (std::uint32_t p = 0; p < 12; ++p) {
        const auto [f0, f1] = s.mesh.edge_face[s.graph.curves.spans[p].front().edge];
        EXPECT_EQ(a.pierced[p], f0 == 0 || f1 == 0) << p;
    }
}

// The box from a corner, through the phases to the clusters: the twelve pieces and eight corner
// nodes are one cluster (every curve ends at corners where others end; no crossing changes QI).
// At a hexagon corner, the crease toward the far corner (-1,-1,-1) runs behind the two front
// faces there, one of which hides it: local occlusion 1. So the three far creases have QI 1,
// the other nine pieces (six silhouettes, three near creases) QI 0. The bounding-box rule fixes
// the cluster (its extreme corners are visible, value 0), and parity holds (silhouettes of a
// convex box: even).
TEST(AppelPhases, BoxFromACornerIsOneClusterFixedByTheBoundingBox) {
    Scene s = box_from_a_corner();
    ASSERT_EQ(s.graph.curves.pieces.size(), 12u);
    ASSERT_TRUE(s.mesh.closed);
    AppelPropagation a = s.propagation();
    a.order_vertex_nodes();
    EXPECT_EQ(a.verts.size(), 8u);
    EXPECT_EQ(a.nn, 20u);
    a.mark_pierced();
    a.crossing_deltas();
    EXPECT_TRUE(a.occluding.empty());
    a.unite_along_curves();
    a.unite_at_vertices();
    a.form_clusters();
    ASSERT_EQ(a.nc, 1u);
    EXPECT_EQ(a.state[0], AppelPropagation::kBound);
    for (std::uint32_t p = 0; p < 12; ++p) EXPECT_EQ(a.value(p), touches_far_corner(s, p) ? 1 : 0) << p;
    a.apply_bounding_box_rule();
    EXPECT_EQ(a.state[0], AppelPropagation::kFixed);
    EXPECT_EQ(a.st.clusters_bbox, 1u);
    a.apply_parity();
    EXPECT_TRUE(a.parity);
    EXPECT_EQ(a.state[0], AppelPropagation::kFixed);
    for (std::uint32_t p = 0; p < 12; ++p) EXPECT_EQ(a.value(p), touches_far_corner(s, p) ? 1 : 0) << p;
}

// fix: the first fix decides a cluster; a second with another value makes it inconsistent.
TEST(AppelPhases, FixedTwiceDifferentlyIsInconsistent) {
    HandMade h(2);
    AppelPropagation& a = h.a;
    a.comp = {0, 0};
    a.off = {0, 1};
    a.nc = 1;
    a.fix(1, 3);  // value(1) = 3: base 2
    EXPECT_EQ(a.state[0], AppelPropagation::kFixed);
    EXPECT_EQ(a.base[0], 2);
    a.fix(0, 2);  // value(0) = 2: the same base
    EXPECT_EQ(a.state[0], AppelPropagation::kFixed);
    a.fix(0, 0);  // value(0) = 0: another
    EXPECT_EQ(a.state[0], AppelPropagation::kInconsistent);
    EXPECT_EQ(a.st.clusters_bbox, 1u);
}

// Parity on the (closed, convex) box: a silhouette piece at offset 1 in a bounded cluster of base
// 0 has value 1, odd: the base is raised to 1 (value 2). In a fixed cluster the same is a
// contradiction. A crease piece constrains nothing.
TEST(AppelPhases, ParityRaisesBoundedAndContradictsFixed) {
    Scene s = box_from_a_corner();
    std::uint32_t sil = UINT32_MAX, crease = UINT32_MAX;
    for (std::uint32_t p = 0; p < 12; ++p) (s.graph.curves.pieces[p].kind == LineKind::Silhouette ? sil : crease) = p;
    ASSERT_NE(sil, UINT32_MAX);
    ASSERT_NE(crease, UINT32_MAX);
    for (const auto first : {AppelPropagation::kBound, AppelPropagation::kFixed}) {
        AppelPropagation a = s.propagation();
        a.np = a.nn = 12;
        a.comp.assign(12, 1);  // every piece in cluster 1 (at offset 0, base 0: even) ...
        a.off.assign(12, 0);
        a.comp[sil] = 0, a.off[sil] = 1;  // ... but the silhouette's
        a.comp[crease] = 2, a.off[crease] = 1;  // and the crease's (odd, unconstrained)
        a.nc = 3;
        a.state = {std::uint8_t(first), AppelPropagation::kBound, AppelPropagation::kBound};
        a.base = {0, 0, 0};
        a.apply_parity();
        EXPECT_TRUE(a.parity);
        if (first == AppelPropagation::kBound) {
            EXPECT_EQ(a.base[0], 1);
            EXPECT_EQ(a.value(sil), 2);
        } else {
            EXPECT_EQ(a.state[0], AppelPropagation::kInconsistent);
        }
        EXPECT_EQ(a.state[1], AppelPropagation::kBound);
        EXPECT_EQ(a.base[1], 0);
        EXPECT_EQ(a.base[2], 0);
    }
}

// Piece 0 (cluster 0, fixed at QI 3) occludes link 0 (pieces 1 -> 2, cluster 1, bounded, values 0
// and 1): both sides must reach 3, so the cluster rises by 3 (values 3, 4). With parity the
// raise is rounded up to even: 4 (values 4, 5).
TEST(AppelPhases, RaiseByConstraints) {
    for (const bool parity : {false, true}) {
        HandMade h(3, {{1, 2}});
        AppelPropagation& a = h.a;
        a.comp = {0, 1, 1};
        a.off = {0, 0, 1};
        a.nc = 2;
        a.state = {AppelPropagation::kFixed, AppelPropagation::kBound};
        a.base = {3, 0};
        a.parity = parity;
        a.constraints = {{0, 0}};
        a.raise_by_constraints();
        EXPECT_EQ(a.base[0], 3);
        EXPECT_EQ(a.base[1], parity ? 4 : 3);
    }
}

// Piece 0 (cluster 0, bounded, base 0) occludes link 0 (pieces 1 -> 2, cluster 1, fixed): its QI
// there is at most the lower of the link's values. Values 0 and 2, no parity: upper bound 0 =
// the lower bound: fixed at 0. Values 1 and 3 with parity (step 2): upper bound 1 < 0 + 2: fixed
// at 0. Values 1 and 3 without parity: 1 >= 0 + 1 leaves two values: still bounded. Base 2 under
// an upper bound of 1: inconsistent.
TEST(AppelPhases, BoundAbove) {
    struct Case {
        int fixed_base, bound_base;
        bool parity;
        std::uint8_t state;
        std::size_t bounded;
    };
    for (const Case c : {Case{0, 0, false, AppelPropagation::kFixed, 1}, Case{1, 0, true, AppelPropagation::kFixed, 1},
                         Case{1, 0, false, AppelPropagation::kBound, 0},
                         Case{1, 2, false, AppelPropagation::kInconsistent, 0}}) {
        HandMade h(3, {{1, 2}});
        AppelPropagation& a = h.a;
        a.comp = {0, 1, 1};
        a.off = {0, 0, 2};
        a.nc = 2;
        a.state = {AppelPropagation::kBound, AppelPropagation::kFixed};
        a.base = {c.bound_base, c.fixed_base};
        a.parity = c.parity;
        a.constraints = {{0, 0}};
        a.open_upper_bounds();
        EXPECT_EQ(a.open.size(), 1u);
        a.bound_above();
        EXPECT_EQ(a.state[0], c.state) << c.fixed_base << " " << c.bound_base << " " << c.parity;
        EXPECT_EQ(a.st.clusters_bounded, c.bounded);
        EXPECT_EQ(a.base[0], c.bound_base);
    }
}

// Runs the phases of `a` up to (not including) the walks.
void propagate(AppelPropagation& a) {
    a.order_vertex_nodes();
    a.mark_pierced();
    a.crossing_deltas();
    a.unite_along_curves();
    a.unite_at_vertices();
    a.form_clusters();
    a.apply_bounding_box_rule();
    a.apply_parity();
    a.match_occluders();
    a.raise_by_constraints();
    a.open_upper_bounds();
    a.bound_above();
    a.survey_bounded();
}

// Figure 2 (c), the branch in front (test_appel.cpp: Figure2.BranchInFront), visible lines only:
// the clusters left bounded with a piece at QI 0 are walked; each walk proves its point visible
// (fixing its cluster) or hidden (raising it), so none is left for a ray test. Without walks the
// same clusters take a ray test each, and every piece is visible or hidden as the walks found.
TEST(AppelPhases, WalksDecideWhatRayTestsWouldOtherwise) {
    const Camera cam = Camera::perspective({0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 35, 800, 800);
    Scene s(test::bumped_sphere({0.5, 0.0, 1.0}, 0.4, 0.35), cam);
    s.options.exact_hidden = false;
    AppelPropagation a = s.propagation();
    propagate(a);
    std::size_t walkable = 0;
    for (std::size_t c = 0; c < a.nc; ++c) walkable += a.state[c] == AppelPropagation::kBound && a.zero[c] != UINT32_MAX;
    EXPECT_GE(walkable, 1u);
    a.walk();
    EXPECT_EQ(a.st.walks, walkable);
    a.ray_test_rest();
    EXPECT_EQ(a.st.ray_tests, 0u);
    a.settle();
    std::vector<bool> walked_visible;
    for (const Piece& p : s.graph.curves.pieces) walked_visible.push_back(p.qi == 0);

    s.options.walk = false;
    AppelPropagation b = s.propagation();
    propagate(b);
    b.walk();
    EXPECT_EQ(b.st.walks, 0u);
    b.ray_test_rest();
    EXPECT_EQ(b.st.ray_tests, walkable);
    b.settle();
    for (std::size_t p = 0; p < walked_visible.size(); ++p) EXPECT_EQ(s.graph.curves.pieces[p].qi == 0, walked_visible[p]) << p;
}

// settle: a piece whose value is below 0 proves its cluster's offsets wrong: every piece of that
// cluster takes a ray test (the box's piece 0 is visible: QI 0 by the ray); the others keep their
// values.
TEST(AppelPhases, SettleSendsNegativeClustersToTheReference) {
    HandMade h(12);
    AppelPropagation& a = h.a;
    a.comp.assign(12, 1);
    a.comp[0] = 0;
    a.nc = 2;
    a.state = {AppelPropagation::kFixed, AppelPropagation::kFixed};
    a.base = {-2, 5};
    a.settle();
    EXPECT_EQ(a.state[0], AppelPropagation::kInconsistent);
    EXPECT_EQ(a.st.inconsistent, 1u);
    EXPECT_EQ(a.st.ray_tests, 1u);
    EXPECT_EQ(a.graph.curves.pieces[0].qi, touches_far_corner(h.scene, 0) ? 1 : 0);
    for (std::uint32_t p = 1; p < 12; ++p) EXPECT_EQ(a.graph.curves.pieces[p].qi, 5);
}

// run() is the phases in order: the same QI as assign_qi_appel, on the box (far creases 1).
TEST(AppelPhases, RunGivesTheBoxItsQi) {
    Scene s = box_from_a_corner();
    const AppelStats st = s.propagation().run();
    EXPECT_EQ(st.clusters, 1u);
    EXPECT_EQ(st.ray_tests, 0u);
    EXPECT_EQ(st.walks, 0u);
    for (std::uint32_t p = 0; p < 12; ++p) EXPECT_EQ(s.graph.curves.pieces[p].qi, touches_far_corner(s, p) ? 1 : 0) << p;
}

}  // namespace
}  // namespace inkline
