// Intersection lines (model/intersection_curves.hpp, visibility/surface_visibility.hpp): the curves
// where two surfaces cross, their shape, their QI against the ray reference and a brute-force count
// that skips the curve's two own faces, and the command's kind, layer and default.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "gltf_writer.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "random_camera.hpp"
#include "test_data.hpp"

namespace {

using inkline::IntersectionCurves;
using inkline::LineKind;
using inkline::Model;
using inkline::TriangleMesh;
namespace fs = std::filesystem;

// A unit sphere (64 x 32) and a box whose bottom face, the plane z = 0.8, cuts the sphere's cap off
// inside it: x and y in [-0.8, 0.8] reach past the circle of radius sqrt(1 - 0.8^2) = 0.6 where the
// plane meets the sphere, and the box's sides (|x| = 0.8 or |y| = 0.8 with z >= 0.8) lie outside
// the sphere (x^2 + z^2 >= 1.28). So the surfaces cross along that one circle, and nowhere else.
constexpr double kPlaneZ = 0.8, kCircleRadius = 0.6;
TriangleMesh sphere_and_box() {
    TriangleMesh m = inkline::merge_meshes(inkline::make_sphere({0, 0, 0}, 1.0, 64, 32),
                                           inkline::make_box({-0.8, -0.8, kPlaneZ}, {0.8, 0.8, 2.0}));
    m.face_object.assign(m.triangles.size(), 0);
    std::fill(m.face_object.end() - 12, m.face_object.end(), 1u);  // the box's 12 triangles
    m.object_names = {"Ball", "Box"};
    return m;
}

double polyline_length(const IntersectionCurves& c, const IntersectionCurves::Curve& curve) {
    double l = 0.0;
    for (std::uint32_t i = curve.begin + 1; i < curve.end; ++i) l += glm::length(c.points[i] - c.points[i - 1]);
    return l;
}

TEST(IntersectionCurves, BoxPushedIntoSphereGivesTheCircle) {
    const Model model(sphere_and_box());
    const IntersectionCurves& c = model.intersection_curves();
    ASSERT_EQ(c.curves.size(), 1u);
    const auto& curve = c.curves[0];
    EXPECT_TRUE(curve.closed);
    EXPECT_FALSE(curve.meets_other);
    EXPECT_EQ(c.points[curve.begin], c.points[curve.end - 1]);
    // The sphere's faces lie inside the unit sphere, their corners on it: a point of the curve is
    // at most the faces' sag inside it (1 - cos of half a face's diagonal angle, about 0.0024 for
    // 64 x 32), so its radius in the plane lies in [sqrt((1 - 0.0024)^2 - 0.64), 0.6].
    const double sag = 1.0 - std::cos(0.5 * std::hypot(2 * M_PI / 64, M_PI / 32));
    const double r_min = std::sqrt((1 - sag) * (1 - sag) - kPlaneZ * kPlaneZ);
    for (std::uint32_t i = curve.begin; i < curve.end; ++i) {
        const glm::dvec3& p = c.points[i];
        EXPECT_NEAR(p.z, kPlaneZ, 1e-12) << i;
        const double r = std::hypot(p.x, p.y);
        EXPECT_GE(r, r_min) << i;
        EXPECT_LE(r, kCircleRadius + 1e-12) << i;
    }
    // Its length: at most the circle's, at least that of the smallest circle above less what 92
    // chords cut off (under 0.1 %).
    const double length = polyline_length(c, curve);
    EXPECT_LE(length, 2 * M_PI * kCircleRadius);
    EXPECT_GE(length, 0.999 * 2 * M_PI * r_min);
    // One segment per sphere face the plane cuts, each on a sphere face (slot 0, object 0, the
    // surface of the first segment) and a box face (slot 1): the slots stay on their surfaces.
    const auto& topo = model.topology();
    std::size_t segments = 0;
    for (std::uint32_t i = curve.begin; i + 1 < curve.end; ++i, ++segments) {
        const auto [f, g] = c.segment_faces[i];
        EXPECT_EQ(topo.face_object[f], topo.face_object[c.segment_faces[curve.begin][0]]) << i;
        EXPECT_NE(topo.face_object[f], topo.face_object[g]) << i;
    }
    EXPECT_EQ(segments, 92u);  // pinned (this tessellation): a segment per crossed pair of faces
    EXPECT_EQ(c.segment_faces[curve.end - 1][0], inkline::kNoFace);
    EXPECT_EQ(c.coplanar_pairs, 0u);
}

TEST(IntersectionCurves, SurfacesThatDoNotCrossGiveNone) {
    EXPECT_TRUE(Model(inkline::make_sphere({0, 0, 0}, 1.0, 32, 16)).intersection_curves().curves.empty());
    // Two objects apart, and a box on a box (faces lie on one another: no crossing to draw).
    EXPECT_TRUE(Model(inkline::merge_meshes(inkline::make_sphere({0, 0, 0}, 1.0, 32, 16),
                                            inkline::make_box({2, 2, 2}, {3, 3, 3})))
                    .intersection_curves()
                    .curves.empty());
    const Model stacked(inkline::merge_meshes(inkline::make_box({0, 0, 0}, {1, 1, 1}),
                                              inkline::make_box({0.25, 0.25, 1}, {0.75, 0.75, 2})));
    EXPECT_TRUE(stacked.intersection_curves().curves.empty());
    // The top box's bottom (2 triangles) on the lower one's top (2): 4 coplanar pairs.
    EXPECT_EQ(stacked.intersection_curves().coplanar_pairs, 4u);
    const Model bunny = Model::load(inkline::test::mesh_path("bunny00.off"));
    EXPECT_TRUE(bunny.intersection_curves().curves.empty());
}

// Two tori about one centre, their rings at right angles (around z and around y): the rings meet
// at (+-1, 0, 0), where the thin tube passes through the thick one, in and out: four closed
// curves, none meeting another.
TriangleMesh crossed_tori(int major, int minor) {
    return inkline::merge_meshes(inkline::make_torus({0, 0, 0}, {0, 0, 1}, 1.0, 0.3, major, minor),
                                  inkline::make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.15, major, minor));
}

TEST(IntersectionCurves, CrossedTori) {
    const Model m(crossed_tori(64, 24));
    const IntersectionCurves& c = m.intersection_curves();
    ASSERT_EQ(c.curves.size(), 4u);
    for (const auto& curve : c.curves) {
        EXPECT_TRUE(curve.closed);
        EXPECT_FALSE(curve.meets_other);
        // Each loop goes round the thin tube: about its circumference 2 pi 0.15 (0.94), a little
        // more where it leans over the thick tube's curved surface.
        EXPECT_GT(polyline_length(c, curve), 0.9);
        EXPECT_LT(polyline_length(c, curve), 1.2);
    }
}

// A sheet (the plane y = 0.5, grid lines every 1 in x and z) through a box [-0.5, 1] x [0, 1] x
// [-0.5, 0.5]: the box's side x = 1 holds sheet edges (the grid line x = 1), the sheet's faces on
// both sides of it, and the diagonal of that side passes through a sheet vertex; the crossing is
// still the one rectangle, 1.5 by 1, closed.
TEST(IntersectionCurves, CrossingAlongEdgesAndThroughVertices) {
    const Model m(inkline::merge_meshes(inkline::make_sheet(2.0, 0.5, 4), inkline::make_box({-0.5, 0, -0.5}, {1, 1, 0.5})));
    const IntersectionCurves& c = m.intersection_curves();
    ASSERT_EQ(c.curves.size(), 1u);
    EXPECT_TRUE(c.curves[0].closed);
    EXPECT_NEAR(polyline_length(c, c.curves[0]), 5.0, 1e-12);
    for (std::uint32_t i = c.curves[0].begin; i < c.curves[0].end; ++i) EXPECT_NEAR(c.points[i].y, 0.5, 1e-15);
    // Touching is not crossing: the sheet laid on the box's top draws nothing.
    const Model on_top(inkline::merge_meshes(inkline::make_sheet(2.0, 1.0, 4), inkline::make_box({-0.5, 0, -0.5}, {1, 1, 0.5})));
    EXPECT_TRUE(on_top.intersection_curves().curves.empty());
}

// Nothing is computed for a view that does not draw intersection lines; once asked for, the
// curves are built once and every view reads the same.
TEST(IntersectionCurves, BuiltOnlyWhenDrawnAndOnce) {
    const Model model(sphere_and_box());
    const inkline::Camera cam = inkline::Camera::perspective({3, 2, 5}, {0, 0, 0.5}, {0, 1, 0}, 35, 600, 600);
    inkline::View plain = inkline::render_view(model, cam);
    EXPECT_EQ(plain.intersections, nullptr);
    EXPECT_EQ(model.intersection_curves_if_computed(), nullptr);
    for (const auto& p : plain.drawing.pieces) EXPECT_NE(p.kind, LineKind::Intersection);
    inkline::ViewOptions o;
    o.features.intersection = true;
    const inkline::View a = inkline::render_view(model, cam, o);
    const inkline::View b = inkline::render_view(model, cam, o);
    ASSERT_NE(a.intersections, nullptr);
    EXPECT_EQ(a.intersections, b.intersections);
    EXPECT_EQ(a.intersections, model.intersection_curves_if_computed());
    EXPECT_EQ(a.drawing.stats.intersection_curves, 1u);
    EXPECT_GT(std::count_if(a.drawing.pieces.begin(), a.drawing.pieces.end(),
                            [](const auto& p) { return p.kind == LineKind::Intersection; }),
              0);
}

// Layers of surface between the eye and p, by brute force over every face but the two p lies on
// (exact segment/triangle predicate): the QI an intersection point must get.
int brute_force_qi(const inkline::MeshTopology& t, const glm::dvec3& eye, const glm::dvec3& p, std::uint32_t f,
                   std::uint32_t g) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    const auto P = [&](const glm::dvec3& v) { return K::Point_3(v.x, v.y, v.z); };
    const K::Segment_3 ray(P(eye), P(p));
    int n = 0;
    for (std::uint32_t h = 0; h < t.face_count(); ++h) {
        if (h == f || h == g) continue;
        const auto& c = t.faces[h];
        n += CGAL::do_intersect(ray, K::Triangle_3(P(t.positions[c[0]]), P(t.positions[c[1]]), P(t.positions[c[2]])));
    }
    return n;
}

double distance_to_polyline(const glm::dvec2& q, const std::vector<glm::dvec2>& pts) {
    double best = 1e300;
    for (std::size_t i = 1; i < pts.size(); ++i) {
        const glm::dvec2 d = pts[i] - pts[i - 1];
        const double dd = glm::dot(d, d);
        const double s = dd > 0 ? std::clamp(glm::dot(q - pts[i - 1], d) / dd, 0.0, 1.0) : 0.0;
        best = std::min(best, glm::length(q - (pts[i - 1] + s * d)));
    }
    return best;
}

double image_length(const inkline::Piece& p) {
    double l = 0.0;
    for (std::size_t i = 1; i < p.points.size(); ++i) l += glm::length(p.points[i] - p.points[i - 1]);
    return l;
}

// Per view: propagation gives the same intersection pieces and QI as the ray reference, and at
// sample points of the curves (segment middles) the drawn QI is the brute-force count.
void expect_exact_visibility(const Model& model, const std::vector<inkline::Camera>& cams, std::size_t& checked,
                             std::size_t& hidden) {
    const IntersectionCurves& c = model.intersection_curves();
    for (std::size_t k = 0; k < cams.size(); ++k) {
        const inkline::Camera& cam = cams[k];
        inkline::ViewOptions fast, ref;
        fast.features.intersection = ref.features.intersection = true;
        ref.visibility = inkline::VisibilityMethod::Rays;
        const inkline::View a = inkline::render_view(model, cam, fast), b = inkline::render_view(model, cam, ref);
        std::vector<const inkline::Piece*> pa, pb;
        for (const auto& p : a.drawing.pieces)
            if (p.kind == LineKind::Intersection) pa.push_back(&p);
        for (const auto& p : b.drawing.pieces)
            if (p.kind == LineKind::Intersection) pb.push_back(&p);
        ASSERT_EQ(pa.size(), pb.size()) << "view " << k;
        for (std::size_t i = 0; i < pa.size(); ++i) {
            ASSERT_EQ(pa[i]->points, pb[i]->points) << "view " << k << " piece " << i;
            // As in test_surface_view: on a piece much shorter than a pixel the reference's probe
            // point, constructed inside it, can round past its end and answer for the neighbour.
            if (image_length(*pa[i]) < 0.01) continue;
            EXPECT_EQ(pa[i]->qi, pb[i]->qi) << "view " << k << " piece " << i;
        }
        for (const auto& curve : c.curves)
            for (std::uint32_t i = curve.begin; i + 1 < curve.end; i += 2) {
                const glm::dvec3 m = 0.5 * (c.points[i] + c.points[i + 1]);
                if (cam.depth(m) <= cam.near_distance()) continue;
                const glm::dvec2 q = cam.project(m);
                // The piece through q: nearest, and no piece of another QI near it (not at a cut).
                double best = 1e300, other = 1e300;
                int qi = -1;
                for (const auto* p : pa) {
                    const double d = distance_to_polyline(q, p->points);
                    if (d < best) {
                        if (qi >= 0 && p->qi != qi) other = std::min(other, best);
                        best = d, qi = p->qi;
                    } else if (p->qi != qi) other = std::min(other, d);
                }
                if (best > 1e-6 || other < 0.5) continue;
                EXPECT_EQ(qi, brute_force_qi(model.topology(), cam.ray_origin(m), m, c.segment_faces[i][0],
                                             c.segment_faces[i][1]))
                    << "view " << k << " point " << i;
                ++checked;
                hidden += qi > 0;
            }
    }
}

TEST(IntersectionVisibility, BoxInSphereAgreesWithTheReference) {
    const Model model(sphere_and_box());
    std::mt19937 rng(11);
    std::vector<inkline::Camera> cams = {
        // From above: the circle lies under the box's top face (one layer) all round.
        inkline::Camera::perspective({0, 0, 5}, {0, 0, 0.8}, {0, 1, 0}, 30, 600, 600),
        // From below: behind the sphere's lower half (one layer).
        inkline::Camera::perspective({0, 0.1, -5}, {0, 0, 0.8}, {0, 1, 0}, 30, 600, 600),
        // From the side, below the plane: the near half of the circle in view, the far half behind
        // the sphere.
        inkline::Camera::perspective({4, 0.5, 0.2}, {0, 0, 0.8}, {0, 0, 1}, 30, 600, 600)};
    for (int k = 0; k < 5; ++k) cams.push_back(inkline::random_camera(rng, model.topology().bounds));
    std::size_t checked = 0, hidden = 0;
    expect_exact_visibility(model, cams, checked, hidden);
    // Pinned (these views): samples checked against the brute-force count, and how many hidden.
    EXPECT_EQ(checked, 368u);
    EXPECT_EQ(hidden, 339u);
    // From above every piece is hidden by exactly the box's top.
    inkline::ViewOptions o;
    o.features.intersection = true;
    std::size_t from_above = 0;
    for (const auto& p : inkline::render_view(model, cams[0], o).drawing.pieces) {
        if (p.kind != LineKind::Intersection) continue;
        EXPECT_EQ(p.qi, 1);
        ++from_above;
    }
    EXPECT_GT(from_above, 0u);
}

TEST(IntersectionVisibility, CrossedToriAgreeWithTheReference) {
    const Model model(crossed_tori(48, 16));
    std::mt19937 rng(5);
    std::vector<inkline::Camera> cams;
    for (int k = 0; k < 6; ++k) cams.push_back(inkline::random_camera(rng, model.topology().bounds));
    std::size_t checked = 0, hidden = 0;
    expect_exact_visibility(model, cams, checked, hidden);
    EXPECT_EQ(checked, 562u);  // pinned, as above
    EXPECT_EQ(hidden, 443u);
}

// Sample meshes that pass through themselves: bones.off (its bones pushed into one another: closed
// loops), cow.off (open curves too: folds that start at a shared vertex) and mannequin-devil.off
// (curves that meet, at triple points: those take the reference). Counts pinned; visibility as above.
TEST(IntersectionVisibility, SelfIntersectingSampleMeshes) {
    struct Case {
        const char* name;
        std::size_t curves, closed, meeting;
    };
    for (const Case& k : {Case{"bones.off", 20, 20, 0}, Case{"cow.off", 6, 1, 0},
                          Case{"mannequin-devil.off", 61, 40, 24}}) {
        const Model model = Model::load(inkline::test::mesh_path(k.name));
        const IntersectionCurves& c = model.intersection_curves();
        std::size_t closed = 0, meeting = 0;
        for (const auto& curve : c.curves) closed += curve.closed, meeting += curve.meets_other;
        EXPECT_EQ(c.curves.size(), k.curves) << k.name;
        EXPECT_EQ(closed, k.closed) << k.name;
        EXPECT_EQ(meeting, k.meeting) << k.name;
        std::mt19937 rng(3);
        std::vector<inkline::Camera> cams;
        for (int v = 0; v < 3; ++v) cams.push_back(inkline::test::framed_then_random(v, rng, model.topology().bounds));
        std::size_t checked = 0, hidden = 0;
        // (Every piece as the reference. One piece of mannequin-devil, third view, 1.2 px next to
        // a fold, once differed: the reference missed a face its ray grazes, in a fan folding
        // about a vertex; RayCaster now looks around the vertices of every crossed face.)
        expect_exact_visibility(model, cams, checked, hidden);
        EXPECT_GT(checked, 20u) << k.name;
        std::printf("[intersections] %s: %zu samples checked, %zu hidden\n", k.name, checked, hidden);
    }
}

// The command: a glTF scene of the two objects draws intersection lines by default (several
// objects), in their own SVG layer and JSON kind; --lines without it draws none.
TEST(IntersectionCli, DefaultForScenesLayerAndKind) {
    const fs::path d = inkline_test::scratch("inkline_test_intersections_");
    inkline_test::Gltf g;
    const int ball = g.add_mesh(inkline::make_sphere({0, 0, 0}, 1.0, 64, 32), "ball");
    const int box = g.add_mesh(inkline::make_box({-0.8, -0.8, kPlaneZ}, {0.8, 0.8, 2.0}), "box");
    const std::string scene = g.save(d, "pressed", {g.add_node({{"name", "Ball"}, {"mesh", ball}}),
                                                    g.add_node({{"name", "Box"}, {"mesh", box}})});
    const std::string cam = " --eye=4,0.5,0.2 --target=0,0,0.8 --up=0,0,1 --size=400x400 --hidden";
    auto r = inkline_test::run_inkline("", "render " + scene + cam + " -o " + (d / "a.json").string(), d);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(inkline_test::slurp(d / "a.json"));
    std::size_t visible = 0, hidden = 0;
    for (const auto& p : j["polylines"])
        if (p["kind"] == "intersection") {
            if (p["qi"] == 0) ++visible;
            else ++hidden;
        }
    EXPECT_GT(visible, 0u);
    EXPECT_GT(hidden, 0u);
    r = inkline_test::run_inkline("", "render " + scene + cam + " -o " + (d / "a.svg").string(), d);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string svg = inkline_test::slurp(d / "a.svg");
    EXPECT_NE(svg.find("id=\"intersection-visible\""), std::string::npos);
    EXPECT_NE(svg.find("id=\"intersection-hidden-qi1\""), std::string::npos);
    r = inkline_test::run_inkline("", "render " + scene + cam + " --lines=silhouette,crease -o " + (d / "b.json").string(), d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(inkline_test::slurp(d / "b.json").find("\"intersection\""), std::string::npos);
    // A single mesh: off unless asked for.
    const std::string off = inkline::test::mesh_path("bunny00.off");
    r = inkline_test::run_inkline("", "render " + off + " --lines=silhouette,intersection -o " + (d / "c.json").string(), d);
    EXPECT_EQ(r.code, 0) << r.err;
    r = inkline_test::run_inkline("", "render " + off + " --lines=silhouette,intersect -o " + (d / "c.json").string(), d);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("intersection"), std::string::npos) << r.err;
}

}  // namespace
