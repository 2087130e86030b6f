// Surface lines (suggestive contours, smooth contours, ridges, valleys) in the pipeline: their
// visibility by propagation against the ray reference, the curvature computed only when asked
// for, and the drawing's invariance to the model's scale.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "random_camera.hpp"

namespace inkline {
namespace {

std::string mesh_path(const std::string& name) { return std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off"; }

bool is_surface_kind(LineKind k) {
    return k == LineKind::Suggestive || k == LineKind::SmoothContour || k == LineKind::Ridge || k == LineKind::Valley;
}

ViewOptions all_surface_lines(VisibilityMethod method) {
    ViewOptions o;
    o.visibility = method;
    o.surface.suggestive = o.surface.smooth_contour = o.surface.ridge = o.surface.valley = true;
    return o;
}

double polyline_length(const Piece& p) {
    double l = 0.0;
    for (std::size_t i = 1; i < p.points.size(); ++i) l += glm::length(p.points[i] - p.points[i - 1]);
    return l;
}

// Propagation along each curve gives every surface piece the QI of a ray test at that piece, on
// real meshes from many cameras (near ones too, where the near plane cuts curves).
class SurfaceVisibility : public ::testing::TestWithParam<const char*> {};

TEST_P(SurfaceVisibility, PropagationAgreesWithRays) {
    const std::string path = mesh_path(GetParam());
    const Model model = Model::load(path);
    std::mt19937 rng(7);
    std::size_t compared = 0, hidden = 0;
    for (int view = 0; view < 8; ++view) {
        const Camera cam = random_camera(rng, model.topology().bounds, view < 2 ? 0.3 : 0.7);
        const View fast = render_view(model, cam, all_surface_lines(VisibilityMethod::Appel));
        const View ref = render_view(model, cam, all_surface_lines(VisibilityMethod::Rays));
        std::vector<const Piece*> a, b;
        for (const Piece& p : fast.drawing.pieces)
            if (is_surface_kind(p.kind)) a.push_back(&p);
        for (const Piece& p : ref.drawing.pieces)
            if (is_surface_kind(p.kind)) b.push_back(&p);
        ASSERT_EQ(a.size(), b.size()) << "view " << view;
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_EQ(a[i]->points, b[i]->points) << "view " << view << " piece " << i;
            // The reference probes a piece at a point constructed inside it; on a piece much
            // shorter than a pixel (two crossings a hair apart) rounding can put that point past
            // its end, so the ray answers for the neighbour: those are not compared. (Smooth
            // contours lie beside the polygonal silhouette and cross it often: many such pieces.)
            if (polyline_length(*a[i]) < 0.01) continue;
            EXPECT_EQ(a[i]->qi, b[i]->qi) << "view " << view << " piece " << i << " of curve " << a[i]->curve;
            hidden += b[i]->qi > 0;
            ++compared;
        }
        // Propagation makes at most one ray test per run of a curve in front of the near plane.
        EXPECT_LE(fast.drawing.stats.surface_ray_tests, ref.drawing.stats.surface_ray_tests);
    }
    EXPECT_GT(compared, 100u) << "too few surface pieces to compare";
    EXPECT_GT(hidden, 10u) << "no hidden surface pieces: the comparison would not test propagation";
}

INSTANTIATE_TEST_SUITE_P(Meshes, SurfaceVisibility, ::testing::Values("bunny00", "armadillo", "elephant", "knot1"),
                         [](const auto& info) { return std::string(info.param); });

TEST(SurfaceLines, ComputedOnlyWhenAskedFor) {
    const Model model(make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.4, 48, 24));
    const Camera cam = Camera::framing(model.topology().bounds, 512, 512);
    const View plain = render_view(model, cam);
    EXPECT_EQ(model.curvature_if_computed(), nullptr);
    EXPECT_EQ(plain.drawing.stats.surface_curves, 0u);
    ViewOptions o;
    o.surface.suggestive = true;
    const View with = render_view(model, cam, o);
    EXPECT_NE(model.curvature_if_computed(), nullptr);
    // The framing camera looks down on the torus at about 20 degrees: its inner part shows
    // suggestive contours.
    EXPECT_GT(with.drawing.stats.surface_curves, 0u);
    std::size_t suggestive = 0;
    for (const Piece& p : with.drawing.pieces) suggestive += p.kind == LineKind::Suggestive;
    EXPECT_GT(suggestive, 0u);
    // The feature curves are the same pieces as without them.
    std::size_t features = 0;
    for (const Piece& p : with.drawing.pieces) features += !is_surface_kind(p.kind);
    EXPECT_EQ(features, plain.drawing.pieces.size());
}

// Scaling the model (and the camera with it) by 1e-4 or 1e4 draws the same lines in pixels:
// the thresholds are relative to the model's feature size.
TEST(SurfaceLines, SameDrawingAtAnyScale) {
    TriangleMesh base = load_mesh(mesh_path("bunny00"));
    const Bounds3 box = Model(base).topology().bounds;
    auto drawing_at = [&](double scale) {
        TriangleMesh m = base;
        for (auto& p : m.positions) p *= scale;
        const Model model(std::move(m));
        Bounds3 b{box.lo * scale, box.hi * scale};
        ViewOptions o;
        o.surface.suggestive = true;
        return render_view(model, Camera::framing(b, 800, 800), o).drawing;
    };
    const Drawing one = drawing_at(1.0);
    double length_one = 0.0;
    std::size_t n_one = 0;
    for (const Piece& p : one.pieces)
        if (p.kind == LineKind::Suggestive && p.qi == 0) length_one += polyline_length(p), ++n_one;
    ASSERT_GT(length_one, 200.0);
    for (double scale : {1e-4, 1e4}) {
        const Drawing d = drawing_at(scale);
        double length = 0.0;
        for (const Piece& p : d.pieces) {
            for (const auto& q : p.points) ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
            if (p.kind == LineKind::Suggestive && p.qi == 0) length += polyline_length(p);
        }
        // Float curvature at another scale rounds differently: a few points move by a hair.
        EXPECT_NEAR(length, length_one, 0.01 * length_one) << "scale " << scale;
    }
}

// A vertex whose curvature cannot be estimated (an isolated triangle's corners have one face
// each, a zero-area face) is counted, draws nothing, and the rest is drawn.
TEST(SurfaceLines, UnestimatedVerticesAreCountedAndTheRestDrawn) {
    TriangleMesh m = make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.4, 48, 24);
    const std::uint32_t n = std::uint32_t(m.positions.size());
    m.positions.push_back({3.0, 0.0, 0.0});
    m.positions.push_back({3.1, 0.0, 0.0});
    m.positions.push_back({3.0, 0.1, 0.0});
    m.triangles.push_back({n, n + 1, n + 2});
    const Model model(std::move(m));
    ViewOptions o;
    o.surface.suggestive = true;
    const View v = render_view(model, Camera::framing(model.topology().bounds, 512, 512), o);
    EXPECT_GE(v.drawing.stats.curvature_invalid_vertices, 3u);
    EXPECT_GT(v.drawing.stats.surface_curves, 0u);
    for (const Piece& p : v.drawing.pieces)
        for (const auto& q : p.points) ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
}

// On a mesh with a border no surface line runs along the border: no segment joins two points
// that both lie on border edges.
TEST(SurfaceLines, NoLineAlongABorder) {
    const Model model = Model::load(mesh_path("elephant-with-holes"));
    std::mt19937 rng(3);
    for (int view = 0; view < 4; ++view) {
        const View v = render_view(model, random_camera(rng, model.topology().bounds),
                                   all_surface_lines(VisibilityMethod::Appel));
        const SurfaceCurves& s = v.surface;
        ASSERT_GT(s.curves.size(), 0u);
        for (const auto& c : s.curves)
            for (std::uint32_t i = c.begin; i + 1 < c.end; ++i) {
                const std::uint32_t e0 = s.point_edge[i], e1 = s.point_edge[i + 1];
                const bool b0 = e0 != UINT32_MAX && model.topology().is_border(e0);
                const bool b1 = e1 != UINT32_MAX && model.topology().is_border(e1);
                EXPECT_FALSE(b0 && b1) << "view " << view << ": a segment along the border";
            }
    }
}

}  // namespace
}  // namespace inkline
