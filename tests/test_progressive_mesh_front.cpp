// The progressive mesh's incremental front (src/detail/progressive_mesh_front.hpp): it converges
// to the criterion of seed 000's section 3.1, stops changing at a fixed camera, stays a manifold
// of the input's topology along a dolly and an orbit, and lands near the from-scratch mesh; the
// geomorphs of section 3.2 move no vertex by a jump.
#include <gtest/gtest.h>

#include <map>

#include "detail/progressive_mesh_front.hpp"
#include "detail/progressive_mesh_session.hpp"
#include "detail/temporal_smoothing.hpp"
#include "model/mesh_io.hpp"
#include "model/reorder.hpp"
#include "progressive_mesh_fixtures.hpp"
#include "test_data.hpp"

using namespace inkline;

namespace {

using test::armadillo_pm;
using test::bounds_of;
using test::euler_characteristic;
using test::geomorphs_at_3px;
using test::target_px;

// The framed camera moved `times` the framed distance from the centre and turned `yaw_deg` about
// the vertical axis through it.
Camera dolly_orbit(const Bounds3& box, double times, double yaw_deg) {
    const Camera framed = test::framed_camera(box);
    const glm::dvec3 c = box.center(), d = framed.eye() - c;
    const double a = yaw_deg * M_PI / 180.0;
    const glm::dvec3 turned{std::cos(a) * d.x + std::sin(a) * d.z, d.y, -std::sin(a) * d.x + std::cos(a) * d.z};
    return Camera::perspective(c + times * turned, c, framed.up(), framed.fov_deg(), 1024, 1024);
}

// Updates until a frame makes no operation; the number of frames it took.
int converge(AdaptiveFront& front, const Camera& cam, const DetailCriterion& c, int most = 50) {
    for (int frame = 1; frame <= most; ++frame) {
        const FrontStats s = front.update(cam, c);
        if (s.splits + s.collapses == 0) return frame;
    }
    return most + 1;
}

struct BandCount {
    std::size_t vertices = 0, above = 0, below = 0;
};
BandCount band(const AdaptiveFront& front, const Camera& cam, const DetailCriterion& c) {
    BandCount b;
    std::vector<std::uint32_t> from;
    front.mesh(&from);
    for (std::uint32_t v : from) {
        const double a = front.image_area_of(v, cam);
        ++b.vertices;
        b.above += a > c.split * c.target_area_px;
        b.below += a < c.collapse * c.target_area_px;
    }
    return b;
}

}  // namespace

TEST(AdaptiveFront, StartsAsTheInput) {
    const ProgressiveMesh& pm = armadillo_pm();
    AdaptiveFront front(pm);
    const TriangleMesh m = front.mesh();
    EXPECT_EQ(m.positions, pm.input().positions);
    EXPECT_EQ(m.triangles, pm.input().triangles);
}

TEST(AdaptiveFront, ConvergesIntoTheBandAndStops) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    const DetailCriterion c = target_px(4.0);
    AdaptiveFront front(pm);
    const int frames = converge(front, cam, c);
    // Measured: the second frame makes nothing (operations are driven by a worklist within a frame;
    // the second frame only finds what became legal after the worklist ran dry).
    EXPECT_LE(frames, 3);
    for (int k = 0; k < 5; ++k) {  // at a fixed camera nothing changes any more
        const FrontStats s = front.update(cam, c);
        EXPECT_EQ(s.splits + s.collapses, 0u) << k;
    }
}

TEST(AdaptiveFront, DollyAndOrbitKeepAManifold) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    AdaptiveFront front(pm);
    const long chi = euler_characteristic(pm.input());
    for (int k = 0; k <= 60; ++k) {
        const double t = k / 60.0;
        const Camera cam = k <= 30 ? dolly_orbit(box, std::pow(8.0, t * 2), 0.0) : dolly_orbit(box, 8.0 / std::pow(8.0, (t - 0.5) * 2), (t - 0.5) * 720);
        const FrontStats s = front.update(cam, c);
        TriangleMesh m = front.mesh();
        ASSERT_EQ(euler_characteristic(m), chi) << k;
        ASSERT_NO_THROW(validate_mesh(m, "front")) << k;
        ASSERT_EQ(m.faces_reoriented, 0u) << k;
        if (k % 10 == 0) std::printf("frame %d: %zu triangles, %zu splits, %zu collapses, %.2f ms\n", k, s.triangles, s.splits, s.collapses, s.seconds * 1e3);
    }
}

// The band after convergence, vertex by vertex, with the reason for each one outside it.
TEST(AdaptiveFront, OutsideTheBandOnlyAtTheLimitsOrGuarded) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    for (double px : {3.0, 6.0}) {
        const DetailCriterion c = target_px(px);
        AdaptiveFront front(pm);
        converge(front, cam, c);
        std::vector<std::uint32_t> from;
        front.mesh(&from);
        std::size_t above_bottom = 0, above_guarded = 0, below_top = 0, below_blocked = 0;
        for (std::uint32_t v : from) {
            const double a = front.image_area_of(v, cam);
            if (a > c.split * c.target_area_px) ++(front.at_bottom(v) ? above_bottom : above_guarded);
            if (a < c.collapse * c.target_area_px) ++(front.at_top(v) ? below_top : below_blocked);
        }
        std::printf("%g px: %zu vertices; above t_s T: %zu at the bottom, %zu guarded; below t_c T: %zu at the top, "
                    "%zu blocked\n", px, from.size(), above_bottom, above_guarded, below_top, below_blocked);
        // Above t_s T only at the hierarchy's bottom: every split that was asked for was made (at
        // 3 px the framed armadillo's own triangles are mostly larger than the band: 13038 of
        // 25579 vertices). Below t_c T: collapses blocked by Hoppe's tree order (a child's
        // collapse illegal), the link condition, a turned face or the band guard on a neighbour:
        // measured 417 of 25579 at 3 px, 874 of 10860 at 6 px; adapt() leaves 452 of 21379 at 4 px.
        EXPECT_EQ(above_guarded, 0u) << px;
        EXPECT_LT(below_blocked * 10, from.size()) << px;
        EXPECT_GT(above_bottom + below_top + below_blocked, 0u) << px;  // (the count is not empty by accident)
    }
}

// Along a slow dolly the front follows the view; at the end it is compared with a front converged
// there from the input and with ProgressiveMesh::adapt (the from-scratch replay).
TEST(AdaptiveFront, IncrementalLandsNearFromScratch) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    AdaptiveFront moving(pm);
    for (int k = 0; k <= 70; ++k) moving.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c);
    const Camera last = dolly_orbit(box, std::pow(1.01, 70), 0.0);
    converge(moving, last, c);
    AdaptiveFront fresh(pm);
    converge(fresh, last, c);
    const std::size_t replay = pm.adapt(last, c).triangles.size();
    const BandCount bm = band(moving, last, c), bf = band(fresh, last, c);
    std::printf("2x: incremental %zu triangles (%zu above, %zu below), fresh %zu (%zu above, %zu below), replay %zu\n",
                moving.active_faces(), bm.above, bm.below, fresh.active_faces(), bf.above, bf.below, replay);
    // Not the same mesh: the band admits many fixed points and the path picks one (the header
    // says why). Measured: 22768 triangles incremental, 21192 fresh, 21240 replayed; 7 vertices
    // above t_s T in each, 1118 / 853 below t_c T. Bound: within 10 % of both in size, and as
    // many above the band (both only at the hierarchy's bottom). (With kept integer ring sums:
    // 22 768, 21 186 and 21 240; 1 122 / 850 below.)
    EXPECT_NEAR(double(moving.active_faces()), double(fresh.active_faces()), 0.1 * double(fresh.active_faces()));
    EXPECT_NEAR(double(moving.active_faces()), double(replay), 0.1 * double(replay));
    EXPECT_EQ(bm.above, bf.above);
    EXPECT_LT(bm.below * 10, bm.vertices);
}

// The window's slider at a fixed camera: the target grows from 2 to 6 px, collapses run as
// geomorphs. Every frame: a vertex kept moves at most its share of the way to its parent (the
// speed times the frame, at most max_speedup / seconds); a vertex leaves from within that share of its parent's place;
// a vertex arrives at its parent's place (each by at most that share too). Then the morphs end and the mesh stops changing.
TEST(AdaptiveFront, GeomorphsMoveNoVertexByAJump) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    const GeomorphOptions g{.enabled = true, .seconds = 0.5, .max_speedup = 8.0};
    AdaptiveFront front(pm, g);
    for (int k = 0; k < 20; ++k) front.update(cam, target_px(2.0), 10.0);  // converge, morphs done at once
    ASSERT_EQ(front.morphs_running(), 0u);
    const double dt = 1.0 / 25.0, share = g.max_speedup * dt / g.seconds;  // at most 0.64 of the way a frame
    const auto& p = pm.input().positions;
    std::vector<std::uint32_t> parent(p.size(), UINT32_MAX);  // each removed vertex's kept one
    for (std::size_t i = 0; i < pm.collapses(); ++i) parent[pm.removed_vertex()[i]] = pm.kept_vertex()[i];
    const auto parent_of = [&](std::uint32_t v) { return parent[v]; };
    std::vector<std::uint32_t> before_ids, now_ids;
    TriangleMesh before = front.mesh(&before_ids);
    std::map<std::uint32_t, glm::dvec3> shown_before;
    for (std::size_t j = 0; j < before_ids.size(); ++j) shown_before[before_ids[j]] = before.positions[j];
    double largest = 0.0;
    std::size_t arrived = 0, left = 0;
    int frame = 0;
    for (; frame < 200; ++frame) {
        const DetailCriterion c = target_px(frame < 30 ? 2.0 + 4.0 * frame / 30.0 : 6.0);  // the slider moved
        const FrontStats s = front.update(cam, c, dt);
        largest = std::max(largest, s.largest_move_px);
        const TriangleMesh now = front.mesh(&now_ids);
        std::map<std::uint32_t, glm::dvec3> shown_now;
        for (std::size_t j = 0; j < now_ids.size(); ++j) shown_now[now_ids[j]] = now.positions[j];
        for (const auto& [v, q] : shown_now) {
            const auto was = shown_before.find(v);
            const std::uint32_t k = parent_of(v);
            if (was == shown_before.end()) {  // arrived by a split: at its parent
                ++arrived;
                ASSERT_NE(k, UINT32_MAX);
                EXPECT_LE(glm::length(cam.project(q) - cam.project(shown_before.at(k))),
                          share * glm::length(cam.project(p[v]) - cam.project(p[k])) + 1e-9) << v;
                continue;
            }
            const double step = glm::length(cam.project(q) - cam.project(was->second));
            if (step > 0.0) {
                ASSERT_NE(k, UINT32_MAX) << v;
                // Exact in the world: at most `share` of the way a frame. In the image, perspective
                // stretches the part of the way nearer the eye: 1 % allowed for it.
                EXPECT_LE(glm::length(q - was->second), share * glm::length(p[v] - p[k]) * (1 + 1e-12)) << v;
                EXPECT_LE(step, 1.01 * share * glm::length(cam.project(p[v]) - cam.project(p[k])) + 1e-9) << v;
            }
        }
        for (const auto& [v, q] : shown_before)
            if (!shown_now.count(v)) {  // left by a collapse: its last step onto its parent
                ++left;
                const std::uint32_t k = parent_of(v);
                EXPECT_LE(glm::length(cam.project(q) - cam.project(p[k])),
                          share * glm::length(cam.project(p[v]) - cam.project(p[k])) + 1e-9) << v;
            }
        shown_before = std::move(shown_now);
        if (frame > 30 && s.morphs_running == 0 && s.splits + s.collapses + s.morphs_started == 0) break;
    }
    std::printf("slider 2 -> 6 px: %zu vertices left, %zu arrived, largest move %.2f px a frame, still after %d frames\n",
                left, arrived, largest, frame);
    EXPECT_GT(left, 1000u);  // (the slider did coarsen the mesh)
    EXPECT_LT(frame, 200);   // the morphs ended and nothing started any more: no cycle
}

// A collapse refused because a morph locks its parent is not tried again each frame (it is
// stamped), yet it happens once that morph ends: when the front is still (no morph, no operation)
// nothing was left waiting, which 70 more frames, past every stamp's backstop (64), confirm.
TEST(AdaptiveFront, CollapseBlockedByAMorphHappensWhenTheMorphEnds) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    AdaptiveFront front(pm, GeomorphOptions{.enabled = true, .seconds = 0.5, .max_speedup = 8.0});
    for (int k = 0; k < 20; ++k) front.update(cam, target_px(2.0), 10.0);  // converged, morphs done
    ASSERT_EQ(front.morphs_running(), 0u);
    const DetailCriterion c = target_px(6.0);
    const double dt = 1.0 / 25.0;
    front.update(cam, c, dt);  // collapses start as morphs: their rings are locked
    std::vector<std::uint32_t> parent(pm.input().positions.size(), UINT32_MAX), blocked;
    for (std::size_t i = 0; i < pm.collapses(); ++i) parent[pm.removed_vertex()[i]] = pm.kept_vertex()[i];
    for (std::uint32_t v = 0; v < parent.size(); ++v)
        if (front.is_active(v) && !front.is_locked(v) && parent[v] != UINT32_MAX && front.is_active(parent[v]) &&
            front.is_locked(parent[v]) && front.image_area_of(v, cam) < c.collapse * c.target_area_px)
            blocked.push_back(v);
    int frame = 1;
    for (; frame < 300; ++frame) {
        const FrontStats s = front.update(cam, c, dt);
        if (s.morphs_running + s.splits + s.collapses + s.morphs_started == 0) break;
    }
    std::size_t collapsed = 0;
    for (std::uint32_t v : blocked) collapsed += !front.is_active(v);
    std::printf("%zu collapses waited on a parent's lock, %zu made; still after %d frames\n", blocked.size(),
                collapsed, frame);
    EXPECT_GT(blocked.size(), 1000u);  // (the case is common: the test can see the stamps at work)
    // The front is still as soon as without the stamps (89 frames then); had the blocked collapses
    // waited for their backstop instead of the morphs' end, 194.
    EXPECT_LT(frame, 120);
    // (the others ended inside the band as their neighbours coarsened, or the band guard refuses
    // them: as many as without the stamps, 1426 then)
    EXPECT_GT(collapsed, blocked.size() * 2 / 3);
    std::size_t later = 0;
    for (int k = 0; k < 70; ++k) {
        const FrontStats s = front.update(cam, c, dt);
        later += s.splits + s.collapses + s.morphs_started;
    }
    EXPECT_EQ(later, 0u);  // no refused collapse was left waiting for its backstop
}

// The adapted mesh along a path, pinned: speed work on the front's rules, areas and link test
// must not change a single operation. A slow dolly out (1 % a frame, 1x -> 4x) with geomorphs,
// then back in without; the hash covers every frame's operation counts and the final mesh (its
// triangles and shown positions, bit for bit). Pinned again when ring areas became kept integer
// sums (AreaUnits: areas rounded to a unit, so ring means moved in their last bits and some
// decisions with them; 67 890 operations against 67 907, 8 624 + 48 148 triangles at the ends).
TEST(AdaptiveFront, AdaptedMeshAlongADollyIsPinned) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a, 64 bits
    const auto mix = [&](const void* data, std::size_t bytes) {
        for (std::size_t j = 0; j < bytes; ++j) hash = (hash ^ static_cast<const unsigned char*>(data)[j]) * 1099511628211ull;
    };
    const auto mix_mesh = [&](const TriangleMesh& m) {
        mix(m.positions.data(), m.positions.size() * sizeof(m.positions[0]));
        mix(m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]));
    };
    std::size_t operations = 0;
    AdaptiveFront morphing(pm, GeomorphOptions{.enabled = true, .seconds = 0.5, .max_speedup = 8.0});
    for (int k = 0; k <= 140; ++k) {
        const FrontStats s = morphing.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0);
        const std::size_t counts[4] = {s.splits, s.collapses, s.morphs_started, s.morphs_running};
        mix(counts, sizeof counts);
        operations += s.splits + s.collapses;
        if (k % 35 == 0) mix_mesh(morphing.mesh());
    }
    AdaptiveFront plain(pm);
    for (int k = 140; k >= 0; k -= 2) {
        const FrontStats s = plain.update(dolly_orbit(box, std::pow(1.01, k), 10.0), c);
        const std::size_t counts[2] = {s.splits, s.collapses};
        mix(counts, sizeof counts);
        operations += s.splits + s.collapses;
    }
    mix_mesh(plain.mesh());
    std::printf("%zu operations, %zu + %zu triangles at the ends, hash %016llx\n", operations, morphing.active_faces(),
                plain.active_faces(), static_cast<unsigned long long>(hash));
    EXPECT_GT(operations, 10000u);  // (the path does adapt the mesh)
    EXPECT_EQ(hash, 0x893ba452fa19f96bull);
}

// Each vertex's ring area is kept as a running sum that the faces changed by an operation update
// (AreaUnits: fixed-point integers). Along a slow dolly out with geomorphs and the default budget
// and back in (collapses, then splits; morphs running at the checks), every active vertex's kept
// sum and face count equal a fresh sum over its ring, and the area the criterion reads equals one
// measured from the front's mesh alone (its triangles in their corner order, the input's
// positions): exactly, whatever the history. (Seen failing with a face's area change not added to
// its corners' sums.)
TEST(AdaptiveFront, KeptRingSumsAreFreshSums) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    AdaptiveFront front(pm, GeomorphOptions{.enabled = true, .seconds = 0.5, .max_speedup = 8.0});
    const AreaUnits& units = front.area_units();
    const auto& p = pm.input().positions;
    const auto check = [&](int k) {
        ASSERT_EQ(front.ring_sums_differing(), 0u) << k;
        std::vector<std::uint32_t> ids;
        const TriangleMesh m = front.mesh(&ids);
        std::vector<std::int64_t> sum(ids.size(), 0);
        std::vector<std::uint32_t> faces(ids.size(), 0);
        for (const auto& t : m.triangles) {
            const glm::dvec3 a = p[ids[t[0]]], b = p[ids[t[1]]], d = p[ids[t[2]]];
            const std::int64_t q = units.of(0.5 * glm::length(glm::cross(b - a, d - a)));
            for (const std::uint32_t v : t) sum[v] += q, ++faces[v];
        }
        std::size_t differing = 0;
        for (std::size_t v = 0; v < ids.size(); ++v) differing += front.ring_area_of(ids[v]) != units.mean(sum[v], faces[v]);
        ASSERT_EQ(differing, 0u) << k;
    };
    std::size_t operations = 0, running = 0;
    for (int k = 0; k <= 140; ++k) {
        const FrontStats s =
            front.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0, FrontBudget::following_lag());
        operations += s.morphs_started + s.splits + s.collapses;
        if (k % 35 == 0) {
            running += s.morphs_running;
            check(k);
        }
    }
    std::size_t splits = 0;
    for (int k = 140; k >= 0; k -= 2) {
        const FrontStats s =
            front.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0, FrontBudget::following_lag());
        operations += s.morphs_started + s.splits + s.collapses;
        splits += s.splits;
        if (k % 35 == 0) {
            running += s.morphs_running;
            check(k);
        }
    }
    std::printf("%zu operations (%zu splits), %zu morphs running at the checks\n", operations, splits, running);
    EXPECT_GT(splits, 10000u);  // (the path refines as well as coarsens)
    EXPECT_GT(running, 100u);   // (checked with morphs in flight)
}

// Ring neighbours' records stay near each other in their pools (an operation reads a ring's
// records: near, they share cache lines and pages), after a slow dolly out with geomorphs and the
// default budget (coarsening: records leave) and back in (refining: records come back). Counted
// over the adapted mesh's edges: the share whose two vertex records, and over pairs of faces
// sharing a corner the share whose face records, lie within 128 slots (4 KiB) of each other.
struct RecordNearness {
    double vertices = 0.0, faces = 0.0;
};
RecordNearness records_near(const AdaptiveFront& front) {
    std::vector<std::uint32_t> vertex_id, face_id;
    const TriangleMesh m = front.mesh(&vertex_id, &face_id);
    const auto near = [](std::uint32_t a, std::uint32_t b) { return (a > b ? a - b : b - a) <= 128; };
    std::size_t edges = 0, near_edges = 0;
    std::vector<std::vector<std::uint32_t>> faces_at(m.positions.size());
    for (std::size_t f = 0; f < m.triangles.size(); ++f)
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t a = m.triangles[f][j], b = m.triangles[f][(j + 1) % 3];
            ++edges;
            near_edges += near(front.vertex_record(vertex_id[a]), front.vertex_record(vertex_id[b]));
            faces_at[a].push_back(front.face_record(face_id[f]));
        }
    std::size_t pairs = 0, near_pairs = 0;
    for (const auto& ring : faces_at)
        for (std::size_t i = 0; i < ring.size(); ++i)
            for (std::size_t j = i + 1; j < ring.size(); ++j) {
                ++pairs;
                near_pairs += near(ring[i], ring[j]);
            }
    return {double(near_edges) / double(edges), double(near_pairs) / double(pairs)};
}

TEST(AdaptiveFront, RingRecordsStayNearInTheirPools) {
    // (in Hilbert order, as a Model's mesh: the records start near their neighbours')
    const ProgressiveMesh pm(hilbert_ordered(load_mesh(test::mesh_path("armadillo"))));
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    AdaptiveFront front(pm, GeomorphOptions{.enabled = true, .seconds = 0.5, .max_speedup = 8.0});
    const RecordNearness start = records_near(front);  // (the input's order)
    std::size_t operations = 0;
    for (int k = 0; k <= 140; ++k)
        operations += front.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0, FrontBudget::following_lag())
                          .morphs_started;
    const RecordNearness out = records_near(front);
    for (int k = 140; k >= 40; --k)
        operations += front.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0, FrontBudget::following_lag())
                          .morphs_started;
    const RecordNearness back = records_near(front);
    std::printf("%zu geomorphs; ring records within 128 slots: vertices %.3f -> %.3f -> %.3f, faces %.3f -> %.3f -> "
                "%.3f\n",
                operations, start.vertices, out.vertices, back.vertices, start.faces, out.faces, back.faces);
    EXPECT_GT(operations, 20000u);  // (the path does move records in and out)
    // Near as the input's order left them (0.89 and 0.87) within a tenth: 0.87, 0.87, 0.84, 0.79.
    // Moving the front's last vertex record into each removed one's place, and giving a split the
    // face slot freed last, left 0.16 and 0.01 of the vertex pairs near, and 0.84 and 0.12 of the
    // face pairs (seen failing so: the faces' pool scatters only on the way back in).
    EXPECT_GT(out.vertices, 0.75);
    EXPECT_GT(back.vertices, 0.75);
    EXPECT_GT(out.faces, 0.7);
    EXPECT_GT(back.faces, 0.7);
}

// The collapses not made whose kept vertex is v (Hoppe's tree order: v's own collapse waits for
// them), from the front's public state: a collapse is made when its removed vertex is inactive.
std::vector<std::uint32_t> children_waiting(const ProgressiveMesh& pm, const AdaptiveFront& front) {
    std::vector<std::uint32_t> waiting(pm.input().positions.size(), 0);
    for (std::size_t i = 0; i < pm.collapses(); ++i)
        if (front.is_active(pm.removed_vertex()[i])) ++waiting[pm.kept_vertex()[i]];
    return waiting;
}

// The operation budget (FrontBudget::fixed, VDPM's regulation): a frame
// makes at most that many operations, taking the vertices furthest out of the band first.
// A fresh front at 4 px (every vertex at the hierarchy's bottom, none stamped): the scan's
// candidates are the vertices below t_c T with a parent and no child collapse left to make; one
// frame with a budget of 300 makes 300 collapses, each of a vertex ranked among those tried
// first, the rest deferred.
TEST(AdaptiveFront, BudgetTakesTheLargestDiscrepancyFirst) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    const DetailCriterion c = target_px(4.0);
    AdaptiveFront front(pm);
    std::vector<std::uint32_t> ids;
    front.mesh(&ids);
    const std::vector<std::uint32_t> waiting = children_waiting(pm, front);
    std::vector<std::pair<double, std::uint32_t>> candidates;  // (t_c T / A_img, vertex)
    for (std::uint32_t v : ids) {
        const double a = front.image_area_of(v, cam);
        if (!front.at_top(v) && waiting[v] == 0 && a < c.collapse * c.target_area_px)
            candidates.push_back({c.collapse * c.target_area_px / a, v});
    }
    std::sort(candidates.rbegin(), candidates.rend());
    const std::size_t budget = 300;
    const FrontStats s = front.update(cam, c, 0.0, FrontBudget::fixed(budget));
    std::vector<double> made;  // the discrepancies of the vertices collapsed
    for (const auto& [d, v] : candidates)
        if (!front.is_active(v)) made.push_back(d);
    std::printf("%zu candidates, %zu tried, %zu collapsed, %zu deferred; discrepancy collapsed %.2f..%.2f, median %.2f\n",
                candidates.size(), s.tried, s.collapses, s.deferred, made.empty() ? 0.0 : made.back(),
                made.empty() ? 0.0 : made.front(), candidates[candidates.size() / 2].first);
    EXPECT_EQ(s.collapses, budget);
    EXPECT_EQ(made.size(), budget);
    ASSERT_GT(candidates.size(), 4 * budget);  // (the budget binds: most are deferred)
    // The scan ranks what this test ranks (its depths from float positions: a near tie may swap).
    EXPECT_NEAR(double(s.ranked), double(candidates.size()), 2.0);
    ASSERT_GE(s.tried, budget);
    const double last_tried = candidates[std::min(s.tried, candidates.size()) - 1].first;
    EXPECT_GE(made.back(), last_tried * (1 - 1e-5));  // every collapse among the first tried
    // (in scan order they would have been spread over all the candidates)
    EXPECT_GT(made.back(), candidates[candidates.size() / 2].first);
    const FrontStats again = front.update(cam, c, 0.0, FrontBudget::fixed(budget));  // the deferred ones come next
    EXPECT_EQ(again.collapses, budget);
}

// A budgeted frame does not rank the collapses waiting on their children (Hoppe's tree order:
// they cannot be made yet): it stamps them as an unbudgeted frame's refusal does, so the scan
// skips them until a child's collapse changes their ring, and what it defers is the backlog
// itself. A fresh front at 4 px, a budget of 300 a frame at a fixed camera: each frame ranks
// (tries or defers) exactly the vertices below t_c T whose collapse is ready, not the thousands
// waiting, and counts every deferred one as backlog.
TEST(AdaptiveFront, BudgetedFrameSkipsCollapsesWaitingOnTheirChildren) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    const DetailCriterion c = target_px(4.0);
    AdaptiveFront front(pm);
    for (int frame = 1; frame <= 3; ++frame) {
        std::vector<std::uint32_t> ids;
        front.mesh(&ids);
        const std::vector<std::uint32_t> waiting = children_waiting(pm, front);
        std::size_t ready = 0, waits = 0;
        for (std::uint32_t v : ids)
            if (!front.at_top(v) && front.image_area_of(v, cam) < c.collapse * c.target_area_px)
                ++(waiting[v] == 0 ? ready : waits);
        const FrontStats s = front.update(cam, c, 0.0, FrontBudget::fixed(300));
        std::printf("frame %d: %zu ready, %zu waiting on their children; %zu ranked, %zu tried, %zu deferred, backlog %zu\n",
                    frame, ready, waits, s.ranked, s.tried, s.deferred, s.backlog);
        ASSERT_GT(waits, 1000u) << frame;  // (the count below would tell them apart)
        EXPECT_EQ(s.collapses, 300u) << frame;
        // (the scan's depths are from float positions: a near tie at the band's edge may differ;
        // ranking the waiting ones too, as before, gave 9 542 in frame 1)
        EXPECT_NEAR(double(s.ranked), double(ready), 2.0) << frame;
        // Every ranked candidate left untried is backlog (the budget binds in the ranking, which
        // comes before the vertices this frame's collapses queued).
        EXPECT_GE(s.backlog, s.ranked - s.tried) << frame;
        EXPECT_LE(s.backlog, s.deferred) << frame;
    }
}

// With a budget the front still converges into the band at a fixed camera (in more frames) and
// then stops changing; every frame within the budget.
TEST(AdaptiveFront, BudgetedFrontConvergesIntoTheBandAndStops) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Camera cam = test::framed_camera(bounds_of(pm.input()));
    const DetailCriterion c = target_px(6.0);
    const std::size_t budget = 500;
    AdaptiveFront front(pm);
    int frames = 1;
    for (; frames <= 200; ++frames) {
        const FrontStats s = front.update(cam, c, 0.0, FrontBudget::fixed(budget));
        ASSERT_LE(s.splits + s.collapses, budget) << frames;
        if (s.splits + s.collapses == 0 && s.deferred == 0) break;
    }
    std::printf("converged in %d frames\n", frames);
    // From 25579 vertices to about 10 900 at 6 px: some 14 700 collapses, so at least 30 frames
    // at 500 (measured 30; without the budget 2-3).
    EXPECT_GE(frames, 30);
    EXPECT_LE(frames, 40);
    for (int k = 0; k < 5; ++k) {
        const FrontStats s = front.update(cam, c, 0.0, FrontBudget::fixed(budget));
        EXPECT_EQ(s.splits + s.collapses + s.deferred, 0u) << k;
    }
    std::vector<std::uint32_t> from;
    front.mesh(&from);
    std::size_t above_guarded = 0, below_blocked = 0;
    for (std::uint32_t v : from) {
        const double a = front.image_area_of(v, cam);
        above_guarded += a > c.split * c.target_area_px && !front.at_bottom(v);
        below_blocked += a < c.collapse * c.target_area_px && !front.at_top(v);
    }
    EXPECT_EQ(above_guarded, 0u);  // the criterion of OutsideTheBandOnlyAtTheLimitsOrGuarded
    EXPECT_LT(below_blocked * 10, from.size());
}

// The slow dolly of AdaptedMeshAlongADollyIsPinned with geomorphs and a budget of 300 a frame
// (the path asks for up to about 550: starts and ends): the budget holds every frame (geomorphs ending count against it),
// work is deferred on the way, and at the last view held still the front catches up, then stops
// inside the band. The budgeted meshes are pinned by their own hash (the unbudgeted path's hash
// above is unchanged: the budget is another schedule of the same operations, not a new rule).
TEST(AdaptiveFront, BudgetedDollyWithGeomorphsCatchesUpAndIsPinned) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    const std::size_t budget = 300;
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a, 64 bits
    const auto mix = [&](const void* data, std::size_t bytes) {
        for (std::size_t j = 0; j < bytes; ++j) hash = (hash ^ static_cast<const unsigned char*>(data)[j]) * 1099511628211ull;
    };
    AdaptiveFront front(pm, GeomorphOptions{.enabled = true, .seconds = 0.5, .max_speedup = 8.0});
    std::size_t deferring = 0;
    for (int k = 0; k <= 140; ++k) {
        const FrontStats s = front.update(dolly_orbit(box, std::pow(1.01, k), 0.0), c, 1.0 / 25.0, FrontBudget::fixed(budget));
        if (k > 0) {  // (frame 0 starts at the input: morphs only start there)
            ASSERT_LE(s.morphs_started + std::min(s.morphs_ended, budget), budget) << k;
        }
        deferring += s.deferred > 0;
        const std::size_t counts[5] = {s.splits, s.collapses, s.morphs_started, s.morphs_running, s.deferred};
        mix(counts, sizeof counts);
        if (k % 35 == 0) {
            const TriangleMesh m = front.mesh();
            mix(m.positions.data(), m.positions.size() * sizeof(m.positions[0]));
            mix(m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]));
        }
    }
    const Camera last = dolly_orbit(box, std::pow(1.01, 140), 0.0);
    int frame = 1;
    for (; frame < 300; ++frame) {
        const FrontStats s = front.update(last, c, 1.0 / 25.0, FrontBudget::fixed(budget));
        if (s.deferred + s.morphs_running + s.splits + s.collapses + s.morphs_started == 0) break;
    }
    const BandCount b = band(front, last, c);
    std::printf("%zu of 141 frames deferred work; still %d frames after the last view; %zu triangles, %zu above, "
                "%zu below; hash %016llx\n", deferring, frame, front.active_faces(), b.above, b.below,
                static_cast<unsigned long long>(hash));
    EXPECT_GT(deferring, 10u);  // (the budget binds on this path: 116 frames)
    // Caught up, morphs ended, nothing more: measured 78 frames (53 without the budget: chains of
    // collapses, each waiting for its children's morphs, take that long either way).
    EXPECT_LT(frame, 100);
    std::vector<std::uint32_t> from;
    front.mesh(&from);
    for (std::uint32_t v : from) {
        if (front.image_area_of(v, last) > c.split * c.target_area_px) {
            EXPECT_TRUE(front.at_bottom(v)) << v;
        }
    }
    EXPECT_LT(b.below * 10, b.vertices);  // (measured 260 of about 2 700 below t_c T; 258 without the budget)
    EXPECT_EQ(hash, 0x9dbd9fa0b5c04684ull);
}

// FrontBudget's rule: base operations a frame, plus the last frame's backlog over catch_up_frames,
// at most `most`; a fixed budget is base = most; none is no budget.
TEST(AdaptiveFront, FrontBudgetRule) {
    const FrontBudget lag{200, 4, 400};
    EXPECT_EQ(lag.for_backlog(0), 200u);
    EXPECT_EQ(lag.for_backlog(3), 200u);   // (3 / 4 rounds down)
    EXPECT_EQ(lag.for_backlog(403), 300u);
    EXPECT_EQ(lag.for_backlog(800), 400u);
    EXPECT_EQ(lag.for_backlog(100000), 400u);
    EXPECT_EQ(FrontBudget::fixed(300).for_backlog(100000), 300u);
    EXPECT_EQ(FrontBudget::none().for_backlog(100000), SIZE_MAX);
    EXPECT_EQ((FrontBudget{200, 0, 400}.for_backlog(50)), 250u);  // (no catch-up frames taken as 1)
    // A cap on top of a rule: the rule within it; on none, a fixed budget.
    EXPECT_EQ(lag.capped(300).for_backlog(0), 200u);
    EXPECT_EQ(lag.capped(300).for_backlog(800), 300u);
    EXPECT_EQ(lag.capped(100).for_backlog(0), 100u);
    EXPECT_EQ(FrontBudget::none().capped(300).for_backlog(100000), 300u);
}

// The slow dolly of AdaptedMeshAlongADollyIsPinned with geomorphs and a budget that follows the
// lag (200 a frame plus a quarter of the backlog, at most 400; the path asks for up to about 550
// a frame, starts and ends): every frame's budget is the rule's for the last frame's backlog and
// holds; the front stays near the unbudgeted one where a fixed budget of 200 (the rule's base)
// falls far behind; at the last view held still the backlog is 0 within a few frames. The meshes
// are pinned by their own hash.
TEST(AdaptiveFront, LagFollowingBudgetHoldsAndCatchesUp) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    const DetailCriterion c = target_px(3.0);
    const GeomorphOptions morphs{.enabled = true, .seconds = 0.5, .max_speedup = 8.0};
    const FrontBudget rule{200, 4, 400};
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a, 64 bits
    const auto mix = [&](const void* data, std::size_t bytes) {
        for (std::size_t j = 0; j < bytes; ++j) hash = (hash ^ static_cast<const unsigned char*>(data)[j]) * 1099511628211ull;
    };
    AdaptiveFront lag(pm, morphs), fixed(pm, morphs), free(pm, morphs);
    std::size_t deferring = 0, raised = 0, most_excess = 0, most_excess_fixed = 0, backlog = 0, laid_out = 0;
    for (int k = 0; k <= 140; ++k) {
        const Camera cam = dolly_orbit(box, std::pow(1.01, k), 0.0);
        const FrontStats s = lag.update(cam, c, 1.0 / 25.0, rule);
        const FrontStats f = fixed.update(cam, c, 1.0 / 25.0, FrontBudget::fixed(rule.base));
        free.update(cam, c, 1.0 / 25.0);
        ASSERT_EQ(s.budget, rule.for_backlog(backlog)) << k;
        ASSERT_EQ(f.budget, rule.base) << k;
        if (k > 0) {  // (frame 0 starts at the input: morphs only start there)
            // (a pool laid out again is paid from the budget, as the ended morphs' collapses are)
            ASSERT_LE(s.morphs_started + s.splits + std::min(s.morphs_ended + s.layout_operations, s.budget), s.budget)
                << k;
        }
        laid_out += s.layout_operations > 0;
        backlog = s.backlog;
        ASSERT_LE(s.backlog, s.deferred) << k;
        deferring += s.deferred > 0;
        raised += s.budget > rule.base;
        if (k > 0) {
            most_excess = std::max(most_excess, s.triangles - std::min(s.triangles, free.active_faces()));
            most_excess_fixed = std::max(most_excess_fixed, f.triangles - std::min(f.triangles, free.active_faces()));
        }
        const std::size_t counts[6] = {s.splits, s.collapses, s.morphs_started, s.morphs_running, s.deferred, s.backlog};
        mix(counts, sizeof counts);
        if (k % 35 == 0) {
            const TriangleMesh m = lag.mesh();
            mix(m.positions.data(), m.positions.size() * sizeof(m.positions[0]));
            mix(m.triangles.data(), m.triangles.size() * sizeof(m.triangles[0]));
        }
    }
    const std::size_t end_lag = lag.active_faces(), end_fixed = fixed.active_faces(), end_free = free.active_faces();
    const Camera last = dolly_orbit(box, std::pow(1.01, 140), 0.0);
    int caught_up = 0;
    for (; caught_up < 100 && lag.backlog() > 0; ++caught_up) lag.update(last, c, 1.0 / 25.0, rule);
    std::printf("%zu frames deferred work, %zu with a raised budget; triangles at the end %zu (fixed %zu, none %zu); "
                "most excess over none %zu (fixed %zu); backlog 0 after %d frames held still; %zu layouts paid; hash %016llx\n",
                deferring, raised, end_lag, end_fixed, end_free, most_excess, most_excess_fixed, caught_up, laid_out,
                static_cast<unsigned long long>(hash));
    // Measured: 118 frames deferring, 118 raised; at the end 9 670 triangles against 8 624
    // unbudgeted (the cap of 400 is below this path's demand until its last frames) and 25 580 with
    // the fixed 200; the largest excess 3 756 against 17 454; the backlog 0 at once; 17 frames
    // paid for a pool's layout.
    EXPECT_GT(raised, 10u);  // (the rule raises the budget on this path)
    EXPECT_GT(laid_out, 0u);  // (so the budget check above saw a layout paid)
    EXPECT_LT(most_excess * 3, most_excess_fixed);
    EXPECT_LT(end_lag, end_free + end_free / 8);  // within 12.5 % of the unbudgeted front at the end
    EXPECT_GT(end_fixed, 2 * end_free);  // (the fixed base lags: the test's contrast)
    EXPECT_LE(caught_up, 3);
    EXPECT_EQ(hash, 0x7e2fd92cfd21f7caull);
}

// PmSession: settle (a window's first view) converges with no budget; a frame after it takes
// the session's budget (PmViewOptions::budget, here a fixed 50).
TEST(AdaptiveFront, SessionSettlesWholeAndBudgetsItsFrames) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    ViewOptions options;
    options.features.kinds[int(LineKind::Crease)] = false;
    PmViewOptions o = geomorphs_at_3px();
    o.budget = FrontBudget::fixed(50);
    PmSession session(pm, options, o);
    session.settle(dolly_orbit(box, 1.5, 0.0));
    // Settled as an unbudgeted front converges: measured 995 of 18 407 vertices below t_c T (a
    // settle within 50 operations a frame, 64 frames at most, would leave thousands of the ~7 000
    // collapses undone) and 2 above t_s T off the hierarchy's bottom (splits refused by the
    // split's guards, as without a budget).
    const DetailCriterion c = target_px(3.0);
    std::vector<std::uint32_t> from;
    session.front().mesh(&from);
    std::size_t above = 0, below = 0;
    for (std::uint32_t v : from) {
        const double a = session.front().image_area_of(v, dolly_orbit(box, 1.5, 0.0));
        above += a > c.split * c.target_area_px && !session.front().at_bottom(v);
        below += a < c.collapse * c.target_area_px && !session.front().at_top(v);
    }
    std::printf("settled: %zu vertices, %zu above, %zu below\n", from.size(), above, below);
    EXPECT_LT(above * 1000, from.size());
    EXPECT_LT(below * 10, from.size());
    EXPECT_EQ(session.front().morphs_running(), 0u);
    session.render(dolly_orbit(box, 2.0, 0.0), 1.0 / 25.0);  // far enough out for thousands of collapses
    const FrontStats& s = session.stats();
    std::printf("%zu started, %zu ended, %zu deferred\n", s.morphs_started, s.morphs_ended, s.deferred);
    EXPECT_EQ(s.morphs_started, 50u);
    EXPECT_GT(s.deferred, 1000u);
}

// A session's frames take its budget rule (PmViewOptions::budget; by default the one that follows
// the lag): the first frame after settle has no backlog, so its budget is the base; a jump that
// leaves thousands of collapses raises the next frame's by a quarter of the backlog, up to the cap.
TEST(AdaptiveFront, SessionFramesTakeTheLagFollowingBudget) {
    const ProgressiveMesh& pm = armadillo_pm();
    const Bounds3 box = bounds_of(pm.input());
    ViewOptions options;
    options.features.kinds[int(LineKind::Crease)] = false;
    PmViewOptions o = geomorphs_at_3px();
    const FrontBudget rule = FrontBudget::following_lag();
    EXPECT_EQ(o.budget.base, rule.base);  // (the default)
    EXPECT_EQ(o.budget.catch_up_frames, rule.catch_up_frames);
    EXPECT_EQ(o.budget.most, rule.most);
    PmSession session(pm, options, o);
    session.settle(dolly_orbit(box, 1.5, 0.0));
    session.render(dolly_orbit(box, 2.5, 0.0), 1.0 / 25.0);
    const FrontStats first = session.stats();
    session.render(dolly_orbit(box, 2.5, 0.0), 1.0 / 25.0);
    const FrontStats second = session.stats();
    std::printf("budgets %zu, %zu; started %zu, %zu; backlog %zu, %zu\n", first.budget, second.budget,
                first.morphs_started, second.morphs_started, first.backlog, second.backlog);
    EXPECT_EQ(first.budget, rule.base);
    EXPECT_EQ(first.morphs_started, rule.base);
    EXPECT_GT(first.backlog, 4 * (rule.most - rule.base));  // (enough to raise the next budget to the cap)
    EXPECT_EQ(second.budget, rule.for_backlog(first.backlog));
    EXPECT_EQ(second.budget, rule.most);
}

TEST(TemporalSmoothing, WeightOfTheSeedsExample) {
    EXPECT_NEAR(smoothing_weight(0.8, 25.0, 0.9), 0.1087, 5e-5);  // n = 20: 1 - 0.1^(1/20)
    EXPECT_EQ(smoothing_weight(0.8, 1.0, 0.9), 1.0);             // under a frame: no smoothing
}

TEST(TemporalSmoothing, ReachesAlphaOfTheWayAfterNFrames) {
    TemporalSmoother s;
    const double w = smoothing_weight(0.8, 25.0, 0.9);
    const std::vector<std::uint32_t> ids{7};
    ViewCurvature v{{0.0f}, {0.0f}, {0.0f}};
    s.blend(v, ids, w);  // first sight: the value as it is
    EXPECT_EQ(v.kr[0], 0.0f);
    for (int frame = 1; frame <= 20; ++frame) {
        v = ViewCurvature{{1.0f}, {2.0f}, {-4.0f}};  // the target, fixed
        s.blend(v, ids, w);
        if (frame == 19) {
            EXPECT_LT(v.kr[0], 0.9f * 2.0f);
        }
    }
    EXPECT_NEAR(v.ndotv[0], 0.9f, 1e-5f);
    EXPECT_NEAR(v.kr[0], 0.9f * 2.0f, 1e-5f);
    EXPECT_NEAR(v.dwkr[0], 0.9f * -4.0f, 1e-5f);
    // A vertex unseen for a frame starts again from its value (its old state was another shape's).
    s.blend(v, {8}, w);
    v = ViewCurvature{{0.5f}, {0.5f}, {0.5f}};
    s.blend(v, ids, w);
    EXPECT_EQ(v.kr[0], 0.5f);
}
