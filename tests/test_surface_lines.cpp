// Curvature lines across faces (src/curvature/): per-view quantities and extraction, first on
// surfaces of revolution whose curvature field is filled analytically (so the extraction is tested
// apart from the estimator), then on hand-made fields for the degenerate cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "curvature/curvature.hpp"
#include "model/primitives.hpp"
#include "model/topology.hpp"

using inkline::Camera;
using inkline::CurvatureField;
using inkline::LineKind;
using inkline::MeshTopology;
using inkline::SurfaceCurves;
using inkline::SurfaceLineOptions;
using inkline::ViewCurvature;

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// A profile curve (rho(t), z(t)) revolved around the z axis, with its first two derivatives.
// The outward normal is (-z', rho') / |c'| in the profile's plane.
struct Profile {
    std::function<glm::dvec2(double)> c, c1, c2;
    double t0, t1;
    bool periodic = false;  // closed profile (torus): t1 is t0 again
};

// Normal curvature of the meridian and of the parallel (positive where the surface bends away from
// the outward normal: a sphere's are 1/R).
double meridian_k(const Profile& p, double t) {
    const glm::dvec2 d1 = p.c1(t), d2 = p.c2(t);
    return (d1.y * d2.x - d1.x * d2.y) / std::pow(glm::length(d1), 3.0);
}
double parallel_k(const Profile& p, double t) { return -p.c1(t).y / (p.c(t).x * glm::length(p.c1(t))); }
// Fourth-order central difference: the curvatures are exact, their derivatives are to ~1e-12.
double derivative(const std::function<double(double)>& f, double t) {
    const double h = 1e-3;
    return (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h);
}

struct Analytic {
    MeshTopology mesh;
    CurvatureField field;
};

// The field at (t, phi). With e_m, e_p the principal (meridian, parallel) directions, Codazzi gives
// C(e1,e1,e1) = e1(k1), C(e1,e1,e2) = e2(k1), C(e1,e2,e2) = e1(k2), C(e2,e2,e2) = e2(k2), and
// nothing depends on phi, so only the derivatives along the meridian remain.
void fill_vertex(const Profile& p, double t, double phi, CurvatureField& f, std::size_t i) {
    const glm::dvec2 d1 = p.c1(t);
    const double speed = glm::length(d1);
    const glm::dvec2 T = d1 / speed, N = glm::dvec2(-d1.y, d1.x) / speed;
    const double c = std::cos(phi), s = std::sin(phi);
    const glm::dvec3 n(N.x * c, N.x * s, N.y), m(T.x * c, T.x * s, T.y), par(-s, c, 0.0);
    f.normal[i] = glm::vec3(n);
    f.valid[i] = 1;
    if (std::abs(p.c(t).x) < 1e-9) {  // on the axis: umbilic, and C vanishes by symmetry
        f.k1[i] = f.k2[i] = float(meridian_k(p, t));
        f.dir1[i] = glm::vec3(1, 0, 0);
        f.dcurv[i] = {0, 0, 0, 0};
        return;
    }
    const double km = meridian_k(p, t), kp = parallel_k(p, t);
    const double dkm = derivative([&](double x) { return meridian_k(p, x); }, t) / speed;
    const double dkp = derivative([&](double x) { return parallel_k(p, x); }, t) / speed;
    const double sigma = glm::dot(glm::cross(n, m), par) > 0 ? 1.0 : -1.0;  // cross(n, m) = sigma par
    if (km >= kp) {
        f.k1[i] = float(km), f.k2[i] = float(kp), f.dir1[i] = glm::vec3(m);
        f.dcurv[i] = {float(dkm), 0.0f, float(dkp), 0.0f};
    } else {  // dir1 = par, dir2 = cross(n, par) = -sigma m
        f.k1[i] = float(kp), f.k2[i] = float(km), f.dir1[i] = glm::vec3(par);
        f.dcurv[i] = {0.0f, float(-sigma * dkp), 0.0f, float(-sigma * dkm)};
    }
}

double median_edge(const MeshTopology& m) {
    std::vector<double> len;
    for (const auto& e : m.edge_vertex) len.push_back(glm::length(m.positions[e[0]] - m.positions[e[1]]));
    std::nth_element(len.begin(), len.begin() + std::ptrdiff_t(len.size() / 2), len.end());
    return len[len.size() / 2];
}

// `rows` steps along the profile, `cols` around the axis; a pole (rho = 0) is one vertex.
Analytic revolve(const Profile& p, int rows, int cols, double scale = 1.0) {
    inkline::TriangleMesh tm;
    std::vector<std::pair<double, double>> params;  // (t, phi) per vertex
    std::vector<std::vector<std::uint32_t>> ring;
    const int nrings = p.periodic ? rows : rows + 1;
    for (int r = 0; r < nrings; ++r) {
        const double t = p.t0 + (p.t1 - p.t0) * r / rows;
        const glm::dvec2 c = p.c(t);
        std::vector<std::uint32_t> ids;
        for (int j = 0; j < cols; ++j) {
            if (std::abs(c.x) < 1e-9 && j > 0) {
                ids.push_back(ids[0]);
                continue;
            }
            const double phi = 2 * M_PI * j / cols;
            ids.push_back(std::uint32_t(tm.positions.size()));
            tm.positions.push_back(scale * glm::dvec3(c.x * std::cos(phi), c.x * std::sin(phi), c.y));
            params.push_back({t, phi});
        }
        ring.push_back(ids);
    }
    for (int r = 0; r < rows; ++r) {  // the band from ring r to the next (the first again: torus)
        const auto& A = ring[std::size_t(r)];
        const auto& B = ring[std::size_t((r + 1) % nrings)];
        for (int j = 0; j < cols; ++j) {
            const std::size_t j1 = std::size_t((j + 1) % cols);
            const std::uint32_t a = A[std::size_t(j)], b = A[j1], c = B[std::size_t(j)], d = B[j1];
            if (a != b) tm.triangles.push_back({a, b, d});
            if (c != d) tm.triangles.push_back({a, d, c});
        }
    }
    CurvatureField f;
    const std::size_t n = tm.positions.size();
    f.normal.resize(n), f.dir1.resize(n), f.k1.resize(n), f.k2.resize(n), f.dcurv.resize(n);
    f.point_area.assign(n, 0.0f), f.valid.resize(n);
    Profile scaled = p;
    scaled.c = [&p, scale](double t) { return scale * p.c(t); };
    scaled.c1 = [&p, scale](double t) { return scale * p.c1(t); };
    scaled.c2 = [&p, scale](double t) { return scale * p.c2(t); };
    for (std::size_t i = 0; i < n; ++i) fill_vertex(scaled, params[i].first, params[i].second, f, i);
    // Orient every triangle by the analytic normal (the profile may run either way).
    for (auto& tri : tm.triangles) {
        const glm::dvec3 nrm = glm::cross(tm.positions[tri[1]] - tm.positions[tri[0]], tm.positions[tri[2]] - tm.positions[tri[0]]);
        const glm::dvec3 ref = glm::dvec3(f.normal[tri[0]] + f.normal[tri[1]] + f.normal[tri[2]]);
        if (glm::dot(nrm, ref) < 0) std::swap(tri[1], tri[2]);
    }
    inkline::validate_mesh(tm, "analytic surface");
    Analytic out{inkline::build_topology(std::move(tm)), std::move(f)};
    out.field.feature_size = median_edge(out.mesh);
    return out;
}

Profile sphere(double R) {
    return {[R](double t) { return glm::dvec2(R * std::sin(t), R * std::cos(t)); },
            [R](double t) { return glm::dvec2(R * std::cos(t), -R * std::sin(t)); },
            [R](double t) { return glm::dvec2(-R * std::sin(t), -R * std::cos(t)); }, 0.0, M_PI};
}
// Ellipsoid of revolution: equatorial radius a, polar radius b.
Profile spheroid(double a, double b) {
    return {[a, b](double t) { return glm::dvec2(a * std::sin(t), b * std::cos(t)); },
            [a, b](double t) { return glm::dvec2(a * std::cos(t), -b * std::sin(t)); },
            [a, b](double t) { return glm::dvec2(-a * std::sin(t), -b * std::cos(t)); }, 0.0, M_PI};
}
Profile torus(double R, double r) {
    return {[R, r](double t) { return glm::dvec2(R + r * std::sin(t), r * std::cos(t)); },
            [r](double t) { return glm::dvec2(r * std::cos(t), -r * std::sin(t)); },
            [r](double t) { return glm::dvec2(-r * std::sin(t), -r * std::cos(t)); }, 0.0, 2 * M_PI, true};
}
// z = height * exp(-rho^2 / (2 s^2)) over the disk rho <= extent (open: its rim is a border).
Profile bump(double s, double extent, double height = 1.0) {
    const double s2 = s * s;
    return {[=](double t) { return glm::dvec2(t, height * std::exp(-t * t / (2 * s2))); },
            [=](double t) { return glm::dvec2(1.0, -t / s2 * height * std::exp(-t * t / (2 * s2))); },
            [=](double t) { return glm::dvec2(0.0, (t * t / (s2 * s2) - 1 / s2) * height * std::exp(-t * t / (2 * s2))); },
            0.0, extent};
}

struct Lines {
    ViewCurvature view;
    SurfaceCurves curves;
};

Lines draw(const Analytic& a, const Camera& cam, const SurfaceLineOptions& opt = {}) {
    Lines l;
    inkline::compute_view_curvature(a.field, a.mesh, cam, l.view);
    inkline::extract_surface_lines(a.mesh, a.field, l.view, cam, opt, l.curves);
    return l;
}

std::size_t count_kind(const SurfaceCurves& c, LineKind k) {
    return std::size_t(std::count_if(c.curves.begin(), c.curves.end(), [k](const auto& x) { return x.kind == k; }));
}

// Unit directions spread over the sphere (Fibonacci lattice).
std::vector<glm::dvec3> directions(int n) {
    std::vector<glm::dvec3> out;
    for (int i = 0; i < n; ++i) {
        const double z = 1 - (2 * i + 1.0) / n, s = std::sqrt(1 - z * z), phi = i * M_PI * (3 - std::sqrt(5.0));
        out.push_back({s * std::cos(phi), s * std::sin(phi), z});
    }
    return out;
}

Camera looking_from(glm::dvec3 dir, double dist, bool ortho, glm::dvec3 target = glm::dvec3(0)) {
    const glm::dvec3 up = std::abs(dir.z) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    if (ortho) return Camera::orthographic(target + dist * dir, target, up, 3.0, 800, 800);
    return Camera::perspective(target + dist * dir, target, up, 30.0, 800, 800);
}

// Every structural promise of SurfaceCurves: finite points, curves of >= 2 points, a point on an
// edge lies on an edge of each face around it in its curve, closed curves close.
void expect_well_formed(const MeshTopology& m, const SurfaceCurves& c) {
    ASSERT_EQ(c.points.size(), c.point_edge.size());
    ASSERT_EQ(c.points.size(), c.segment_face.size());
    ASSERT_EQ(c.points.size(), c.strength.size());
    // A point on edge e, or at one of its vertices: face f holds it.
    auto face_has_edge = [&](std::uint32_t f, std::uint32_t e) {
        const auto& fe = m.face_edges[f].edge;
        return fe[0] == e || fe[1] == e || fe[2] == e;
    };
    auto vertex_at = [&](std::size_t i) -> std::uint32_t {
        if (c.point_edge[i] == kNone) return kNone;
        for (std::uint32_t v : m.edge_vertex[c.point_edge[i]])
            if (m.positions[v] == c.points[i]) return v;
        return kNone;
    };
    auto face_holds = [&](std::uint32_t f, std::size_t i) {
        const std::uint32_t v = vertex_at(i);
        if (v == kNone) return face_has_edge(f, c.point_edge[i]);
        const auto& fv = m.faces[f];
        return fv[0] == v || fv[1] == v || fv[2] == v;
    };
    for (const auto& cv : c.curves) {
        ASSERT_GE(cv.end - cv.begin, 2u);
        if (cv.closed) {
            EXPECT_EQ(c.points[cv.begin], c.points[cv.end - 1]);
        }
        for (std::uint32_t i = cv.begin; i < cv.end; ++i) {
            const glm::dvec3 p = c.points[i];
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
            ASSERT_TRUE(c.strength[i] >= 0.0f && c.strength[i] <= 1.0f);
            if (i + 1 < cv.end) {
                ASSERT_LT(c.segment_face[i], m.face_count());
                EXPECT_NE(c.points[i], c.points[i + 1]);  // no zero-length segment
                EXPECT_TRUE(c.point_edge[i] == kNone || face_holds(c.segment_face[i], i));
                EXPECT_TRUE(c.point_edge[i + 1] == kNone || face_holds(c.segment_face[i], i + 1));
            } else {
                EXPECT_EQ(c.segment_face[i], kNone);
            }
            // An interior point on an edge joins that edge's two faces.
            if (i > cv.begin && i + 1 < cv.end && c.point_edge[i] != kNone && vertex_at(i) == kNone) {
                const auto ef = m.edge_face[c.point_edge[i]];
                const std::uint32_t a = c.segment_face[i - 1], b = c.segment_face[i];
                EXPECT_TRUE((a == ef[0] && b == ef[1]) || (a == ef[1] && b == ef[0])) << "point " << i;
            }
        }
    }
}

// ---- Analytic fields ----------------------------------------------------------------------------

TEST(SurfaceLinesAnalytic, SphereAndSpheroidsHaveNoSuggestiveContours) {
    // k1, k2 > 0 everywhere, so kr = k1 u^2 + k2 t^2 >= 0: no zero crossing from any view.
    for (const Profile& p : {sphere(1.0), spheroid(1.0, 0.5), spheroid(0.6, 1.2)}) {
        const Analytic a = revolve(p, 40, 80);
        for (const glm::dvec3& d : directions(24))
            for (bool ortho : {false, true}) {
                const Lines l = draw(a, looking_from(d, 5.0, ortho));
                EXPECT_EQ(l.curves.curves.size(), 0u);
            }
    }
}

TEST(SurfaceLinesAnalytic, PlaneHasNone) {
    // kr = 0 at every vertex: 0 counts as positive, so no face has a sign change.
    const Analytic a = revolve(bump(1.0, 3.0, 0.0), 30, 60);
    for (const glm::dvec3& d : directions(12)) {
        SurfaceLineOptions opt;
        opt.ridge = opt.valley = true;
        EXPECT_EQ(draw(a, looking_from(d, 8.0, false), opt).curves.curves.size(), 0u);
    }
}

// Max |radius in pixels - F s / depth| of the bump's suggestive contour seen from straight above,
// where it is the circle rho = s (the profile's inflection: kr is the meridian's curvature there,
// since w is radial by symmetry, for a perspective eye on the axis too).
double bump_contour_error_px(int rows, int cols, int* curves) {
    const double s = 1.0, eye_height = 10.0;
    const Analytic a = revolve(bump(s, 3.0), rows, cols);
    const Camera cam = Camera::perspective({0, 0, eye_height}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800);
    const Lines l = draw(a, cam);
    expect_well_formed(a.mesh, l.curves);
    *curves = int(l.curves.curves.size());
    const double expected = cam.focal() * s / (eye_height - std::exp(-0.5));
    double err = 0.0;
    for (const glm::dvec3& p : l.curves.points) err = std::max(err, std::abs(glm::length(cam.project(p) - glm::dvec2(400, 400)) - expected));
    return err;
}

TEST(SurfaceLinesAnalytic, GaussianBumpFromAboveIsTheInflectionCircle) {
    int curves = 0;
    // Row counts for which no ring of vertices lies on rho = s (3 i / rows != 1).
    const double coarse = bump_contour_error_px(25, 48, &curves);
    EXPECT_EQ(curves, 1);
    const double mid = bump_contour_error_px(49, 96, &curves);
    EXPECT_EQ(curves, 1);
    const double fine = bump_contour_error_px(97, 192, &curves);
    EXPECT_EQ(curves, 1);
    // Linear interpolation between vertices: the error falls with the spacing.
    EXPECT_LT(mid, coarse);
    EXPECT_LT(fine, mid);
    EXPECT_LT(fine, 0.25);
    EXPECT_LT(coarse, 3.0);
}

TEST(SurfaceLinesAnalytic, GaussianBumpContourIsOneClosedCurve) {
    const Analytic a = revolve(bump(1.0, 3.0), 49, 96);
    const Lines l = draw(a, Camera::perspective({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800));
    ASSERT_EQ(l.curves.curves.size(), 1u);
    const auto& c = l.curves.curves[0];
    EXPECT_TRUE(c.closed);
    EXPECT_EQ(c.kind, LineKind::Suggestive);
    // The circle rho = s crosses the 96 radial edges of one ring band and 96 diagonals: one point each.
    EXPECT_EQ(c.end - c.begin, 2u * 96u + 1u);
    // Every point passes its test by the same margin (symmetry): equal strengths in (0, 1).
    for (std::uint32_t i = c.begin; i < c.end; ++i) {
        EXPECT_GT(l.curves.strength[i], 0.0f);
        EXPECT_LT(l.curves.strength[i], 1.0f);
    }
}

TEST(SurfaceLinesAnalytic, ThresholdRemovesWeakContours) {
    // Raising the threshold far above D_w kr / n.v at rho = s removes the bump's contour.
    const Analytic a = revolve(bump(1.0, 3.0), 48, 96);
    const Camera cam = Camera::perspective({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800);
    SurfaceLineOptions opt;
    opt.suggestive_threshold = 1.0;
    EXPECT_EQ(draw(a, cam, opt).curves.curves.size(), 0u);
    opt.suggestive_threshold = 0.0;
    EXPECT_EQ(draw(a, cam, opt).curves.curves.size(), 1u);
}

TEST(SurfaceLinesAnalytic, TorusHasThemOnItsInnerPartOnly) {
    const double R = 2.0, r = 0.7;
    const Analytic a = revolve(torus(R, r), 64, 128);
    // Views 60-80 degrees off the axis: the inner part's saddles show suggestive contours above
    // the default threshold (nearer the axis they are weaker than it).
    int views_with_lines = 0;
    for (double tilt_deg : {60.0, 70.0, 80.0}) {
        const double tl = tilt_deg * M_PI / 180;
        const Lines l = draw(a, looking_from({0, -std::sin(tl), std::cos(tl)}, 14.0, false));
        expect_well_formed(a.mesh, l.curves);
        // The outer half has k1, k2 > 0: kr > 0, nothing there.
        for (const glm::dvec3& p : l.curves.points) EXPECT_LT(std::hypot(p.x, p.y), R);
        views_with_lines += !l.curves.curves.empty();
    }
    EXPECT_EQ(views_with_lines, 3);
}

TEST(SurfaceLinesAnalytic, SmoothContourOfASphereIsTheTrueContour) {
    // From distance d, the contour generator of the unit sphere is the circle p . e^ = 1/d.
    for (int res : {32, 64, 128}) {
        const Analytic a = revolve(sphere(1.0), res, 2 * res);
        const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
        const double d = 4.0;
        SurfaceLineOptions opt;
        opt.suggestive = false, opt.smooth_contour = true;
        const Lines l = draw(a, looking_from(dir, d, false), opt);
        expect_well_formed(a.mesh, l.curves);
        ASSERT_EQ(l.curves.curves.size(), 1u);
        EXPECT_TRUE(l.curves.curves[0].closed);
        EXPECT_EQ(l.curves.curves[0].kind, LineKind::SmoothContour);
        double err = 0.0;
        for (const glm::dvec3& p : l.curves.points) err = std::max(err, std::abs(glm::dot(p, dir) - 1.0 / d));
        // Error of linear interpolation over an edge of length ~pi/res: O(h^2).
        EXPECT_LT(err, 6.0 / (res * res)) << res;
    }
}

TEST(SurfaceLinesAnalytic, ChainsJoinAcrossFaces) {
    const Analytic a = revolve(torus(2.0, 0.7), 48, 96);
    std::mt19937 rng(7);
    SurfaceLineOptions opt;
    opt.smooth_contour = opt.ridge = opt.valley = true;
    for (const glm::dvec3& d : directions(16)) {
        const Lines l = draw(a, looking_from(d, 12.0, rng() % 2 == 0), opt);
        expect_well_formed(a.mesh, l.curves);
        // The smooth contour of a torus seen from outside is closed loops only (no ends).
        for (const auto& c : l.curves.curves)
            EXPECT_TRUE(c.kind != LineKind::SmoothContour || c.closed);
    }
}

TEST(SurfaceLinesAnalytic, ScaledModelDrawsTheSamePixels) {
    const Camera base = looking_from(glm::normalize(glm::dvec3(0.1, -0.87, 0.5)), 14.0, false);
    const Analytic a = revolve(torus(2.0, 0.7), 48, 96);
    const Lines ref = draw(a, base);
    ASSERT_GT(ref.curves.points.size(), 20u);
    for (double scale : {1e-4, 1e4}) {
        const Analytic b = revolve(torus(2.0, 0.7), 48, 96, scale);
        const Camera cam = Camera::perspective(scale * base.eye(), scale * base.target(), base.up(), 30.0, 800, 800);
        const Lines l = draw(b, cam);
        ASSERT_EQ(l.curves.curves.size(), ref.curves.curves.size()) << scale;
        ASSERT_EQ(l.curves.points.size(), ref.curves.points.size()) << scale;
        double err = 0.0;
        for (std::size_t i = 0; i < l.curves.points.size(); ++i)
            err = std::max(err, glm::length(cam.project(l.curves.points[i]) - base.project(ref.curves.points[i])));
        EXPECT_LT(err, 1e-3) << scale;
    }
}

// rho of the extremum of the meridian curvature on the bump's concave flank (bisection on its
// derivative): the valley line of the Gaussian bump.
double bump_valley_rho(const Profile& p) {
    auto dk = [&](double t) { return derivative([&](double x) { return meridian_k(p, x); }, t); };
    double lo = 1.2, hi = 2.5;  // dk changes sign once in between
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((dk(mid) < 0) == (dk(lo) < 0) ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

TEST(SurfaceLinesAnalytic, BumpValleyIsTheCircleOfExtremeCurvature) {
    const Profile p = bump(1.0, 3.0);
    const double rho = bump_valley_rho(p);
    SurfaceLineOptions opt;
    opt.suggestive = false, opt.valley = true, opt.ridge = true;
    opt.ridge_threshold = 0.01;
    double prev = 1e9;
    for (int res : {32, 64, 128}) {
        const Analytic a = revolve(p, res, 2 * res);
        const Lines l = draw(a, looking_from(glm::normalize(glm::dvec3(0.3, 0.2, 1)), 10.0, false), opt);
        expect_well_formed(a.mesh, l.curves);
        EXPECT_EQ(count_kind(l.curves, LineKind::Valley), 1u) << res;
        double err = 0.0;
        for (const auto& c : l.curves.curves) {
            if (c.kind != LineKind::Valley) continue;
            EXPECT_TRUE(c.closed);
            for (std::uint32_t i = c.begin; i < c.end; ++i)
                err = std::max(err, std::abs(std::hypot(l.curves.points[i].x, l.curves.points[i].y) - rho));
        }
        EXPECT_LT(err, prev) << res;
        prev = err;
    }
    EXPECT_LT(prev, 0.02);
}

TEST(SurfaceLinesAnalytic, OblateSpheroidRidgeIsTheEquator) {
    // Meridian curvature a/b^2 peaks on the equator of an oblate spheroid (a > b).
    SurfaceLineOptions opt;
    opt.suggestive = false, opt.ridge = true;
    opt.ridge_threshold = 0.01;  // the default (rtsc's) is above this smooth ridge's curvature
    const Analytic a = revolve(spheroid(1.0, 0.5), 41, 80);
    const Lines l = draw(a, looking_from(glm::normalize(glm::dvec3(1, 0.5, 0.4)), 6.0, false), opt);
    expect_well_formed(a.mesh, l.curves);
    ASSERT_EQ(count_kind(l.curves, LineKind::Ridge), 1u);
    EXPECT_TRUE(l.curves.curves[0].closed);
    for (const glm::dvec3& p : l.curves.points) EXPECT_LT(std::abs(p.z), 0.5 * M_PI / 41);
}

TEST(SurfaceLinesAnalytic, BorderDrawsNoLineAlongIt) {
    // The bump's rim is a border. A line may cross it (a contour generator meeting the rim), but
    // no segment runs from a border edge to a border edge.
    SurfaceLineOptions opt;
    opt.smooth_contour = opt.ridge = opt.valley = true;
    const Analytic a = revolve(bump(1.0, 3.0), 48, 96);
    int crossing_rim = 0;
    for (const glm::dvec3& d : directions(16)) {
        const Lines l = draw(a, looking_from(d, 10.0, false), opt);
        const auto& c = l.curves;
        auto on_border = [&](std::size_t i) { return c.point_edge[i] != kNone && a.mesh.is_border(c.point_edge[i]); };
        for (const auto& cv : c.curves)
            for (std::uint32_t i = cv.begin; i < cv.end; ++i) {
                EXPECT_FALSE(i + 1 < cv.end && on_border(i) && on_border(i + 1));
                crossing_rim += on_border(i);
            }
    }
    EXPECT_GT(crossing_rim, 0);  // the case is exercised
}

// ---- Degenerate data ----------------------------------------------------------------------------

TEST(SurfaceLinesDegenerate, InvalidVerticesSilenceTheirFaces) {
    Analytic a = revolve(bump(1.0, 3.0), 48, 96);
    const Camera cam = Camera::perspective({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800);
    const Lines before = draw(a, cam);
    ASSERT_EQ(before.curves.curves.size(), 1u);
    // Invalidate (and poison) the vertices of one face the contour crosses.
    const std::uint32_t f = before.curves.segment_face[before.curves.curves[0].begin];
    for (std::uint32_t v : a.mesh.faces[f]) {
        a.field.valid[v] = 0;
        a.field.k1[v] = std::numeric_limits<float>::quiet_NaN();
        a.field.dcurv[v][0] = std::numeric_limits<float>::infinity();
    }
    SurfaceLineOptions opt;
    opt.smooth_contour = opt.ridge = opt.valley = true;
    const Lines after = draw(a, cam, opt);
    expect_well_formed(a.mesh, after.curves);
    ASSERT_EQ(count_kind(after.curves, LineKind::Suggestive), 1u);
    EXPECT_FALSE(after.curves.curves[0].closed);  // opened where the faces went silent
    for (std::uint32_t g : after.curves.segment_face) {
        if (g == kNone) continue;
        for (std::uint32_t v : a.mesh.faces[g]) EXPECT_TRUE(a.field.valid[v]);
    }
}

// A fan of six faces around vertex 0 with kr(0) = 0 and alternating signs around it: the zero set
// passes through the vertex; it must come out as curves through that one point, no zero-length
// segment, identical points from both faces of each edge.
TEST(SurfaceLinesDegenerate, ZeroAtAVertex) {
    inkline::TriangleMesh tm;
    tm.positions.push_back({0, 0, 0});
    for (int i = 0; i < 6; ++i) tm.positions.push_back({std::cos(i * M_PI / 3), std::sin(i * M_PI / 3), 0});
    for (std::uint32_t i = 0; i < 6; ++i) tm.triangles.push_back({0, 1 + i, 1 + (i + 1) % 6});
    inkline::validate_mesh(tm, "fan");
    const MeshTopology m = inkline::build_topology(std::move(tm));
    CurvatureField f;
    f.normal.assign(7, glm::vec3(0, 0, 1)), f.dir1.assign(7, glm::vec3(1, 0, 0));
    // A saddle, so the face is not flat (kr itself comes from `view` below).
    f.k1.assign(7, 1.0f), f.k2.assign(7, -1.0f), f.dcurv.assign(7, {0, 0, 0, 0});
    f.point_area.assign(7, 0.0f), f.valid.assign(7, 1), f.feature_size = 1.0;
    ViewCurvature view;
    view.ndotv.assign(7, 0.5f);
    view.dwkr.assign(7, 1.0f);
    view.kr = {0.0f, 1, 1, -1, -1, 1, -1};
    const Camera cam = Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 100, 100);
    SurfaceLineOptions opt;
    opt.suggestive_threshold = 0.0;
    SurfaceCurves out;
    inkline::extract_surface_lines(m, f, view, cam, opt, out);
    expect_well_formed(m, out);
    // Rim signs + + - - + - (vertices 1..6), centre 0 counted positive: faces (0,2,3), (0,4,5),
    // (0,5,6), (0,6,1) each join the centre to the zero on their rim edge; (0,3,4) has both zeros
    // at the centre and draws nothing. Four segments meet at the centre's one node: a junction,
    // so four open curves of two points, each starting or ending exactly at the vertex.
    std::size_t at_centre = 0;
    for (const glm::dvec3& p : out.points) at_centre += p == glm::dvec3(0, 0, 0);
    EXPECT_EQ(out.curves.size(), 4u);
    EXPECT_EQ(out.points.size(), 8u);
    EXPECT_EQ(at_centre, 4u);
    for (const auto& c : out.curves)
        for (std::uint32_t i = c.begin; i + 1 < c.end; ++i) EXPECT_NE(out.points[i], out.points[i + 1]);
}

TEST(SurfaceLinesDegenerate, MismatchedSizesDrawNothing) {
    const Analytic a = revolve(bump(1.0, 3.0), 16, 32);
    ViewCurvature view;
    SurfaceCurves out;
    out.points.push_back({1, 2, 3});
    inkline::extract_surface_lines(a.mesh, a.field, view, Camera::perspective({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 30, 100, 100),
                                   {}, out);
    EXPECT_TRUE(out.points.empty());
    EXPECT_TRUE(out.curves.empty());
}

TEST(ViewCurvature, MatchesDefinitionsOnTheSphere) {
    // Sphere R = 2: kr * sin^2 = sin^2 / R, D_w kr = 0 (C = 0, tau = 0), n.v = cos(theta).
    const Analytic a = revolve(sphere(2.0), 20, 40);
    for (bool ortho : {false, true}) {
        const Camera cam = looking_from(glm::normalize(glm::dvec3(1, 2, 3)), 9.0, ortho);
        ViewCurvature v;
        inkline::compute_view_curvature(a.field, a.mesh, cam, v);
        ASSERT_EQ(v.kr.size(), a.mesh.vertex_count());
        for (std::size_t i = 0; i < v.kr.size(); ++i) {
            const glm::dvec3 p = a.mesh.positions[i];
            const glm::dvec3 to_eye = ortho ? -cam.forward() : glm::normalize(cam.eye() - p);
            const double c = glm::dot(glm::normalize(p), to_eye);
            EXPECT_NEAR(v.ndotv[i], c, 1e-5);
            EXPECT_NEAR(v.kr[i], (1 - c * c) / 2.0, 1e-5);
            EXPECT_NEAR(v.dwkr[i], 0.0, 1e-5);
        }
    }
}

}  // namespace

// ---- End to end, with estimate_curvature ----------------------------------------------------------

namespace {

struct Estimated {
    MeshTopology mesh;
    CurvatureField field;
};

Estimated estimated(inkline::TriangleMesh tm) {
    inkline::validate_mesh(tm, "test mesh");
    Estimated e{inkline::build_topology(std::move(tm)), {}};
    e.field = inkline::estimate_curvature(e.mesh);
    return e;
}
Estimated estimated(const Analytic& a) {
    inkline::TriangleMesh tm;
    tm.positions = a.mesh.positions;
    tm.triangles = a.mesh.faces;
    return estimated(std::move(tm));
}
Estimated estimated_file(const std::string& name) {
    return estimated(inkline::load_mesh(std::string(INKLINE_DATA_DIR) + "/meshes/" + name));
}

Lines draw(const Estimated& e, const Camera& cam, const SurfaceLineOptions& opt = {}) {
    Lines l;
    inkline::compute_view_curvature(e.field, e.mesh, cam, l.view);
    inkline::extract_surface_lines(e.mesh, e.field, l.view, cam, opt, l.curves);
    return l;
}

// Drawn length in pixels of the curves of `kind`.
double length_px(const SurfaceCurves& c, const Camera& cam, LineKind kind = LineKind::Suggestive) {
    double len = 0.0;
    for (const auto& cv : c.curves) {
        if (cv.kind != kind) continue;
        for (std::uint32_t i = cv.begin; i + 1 < cv.end; ++i) len += glm::length(cam.project(c.points[i + 1]) - cam.project(c.points[i]));
    }
    return len;
}

Camera framing_from(const MeshTopology& m, glm::dvec3 dir) {
    const glm::dvec3 c = m.bounds.center();
    const double R = m.bounds.half_diagonal(), d = R / std::sin(15.0 * M_PI / 180.0);
    const glm::dvec3 up = std::abs(dir.y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    return Camera::perspective(c + d * dir, c, up, 30.0, 1024, 1024);
}

TEST(SurfaceLinesEstimated, SphereAndEllipsoidHaveNone) {
    inkline::TriangleMesh ellipsoid = inkline::make_sphere({0, 0, 0}, 1.0, 96, 48);
    for (glm::dvec3& p : ellipsoid.positions) p *= glm::dvec3(1.0, 0.6, 0.4);
    for (auto tm : {inkline::make_sphere({0, 0, 0}, 1.0, 96, 48), ellipsoid}) {
        const Estimated e = estimated(std::move(tm));
        for (const glm::dvec3& d : directions(24)) {
            const Camera cam = framing_from(e.mesh, d);
            EXPECT_EQ(draw(e, cam).curves.curves.size(), 0u);
        }
    }
}

TEST(SurfaceLinesEstimated, PlaneHasNone) {
    const Estimated e = estimated(inkline::make_sheet(1.0, 0.0, 40));
    SurfaceLineOptions opt;
    opt.ridge = opt.valley = true;
    for (const glm::dvec3& d : directions(12)) EXPECT_EQ(draw(e, framing_from(e.mesh, d), opt).curves.curves.size(), 0u);
}

TEST(SurfaceLinesEstimated, GaussianBumpFromAbove) {
    const double s = 1.0, eye_height = 10.0;
    const Camera cam = Camera::perspective({0, 0, eye_height}, {0, 0, 0}, {0, 1, 0}, 30.0, 800, 800);
    const double expected = cam.focal() * s / (eye_height - std::exp(-0.5));
    double prev = 1e9;
    for (int rows : {25, 49, 97}) {
        const Estimated e = estimated(revolve(bump(s, 3.0), rows, 2 * (rows - 1)));
        const Lines l = draw(e, cam);
        expect_well_formed(e.mesh, l.curves);
        ASSERT_EQ(l.curves.curves.size(), 1u) << rows;
        EXPECT_TRUE(l.curves.curves[0].closed);
        double err = 0.0;
        for (const glm::dvec3& p : l.curves.points)
            err = std::max(err, std::abs(glm::length(cam.project(p) - glm::dvec2(400, 400)) - expected));
        EXPECT_LT(err, prev) << rows;
        prev = err;
    }
    EXPECT_LT(prev, 0.5);
}

TEST(SurfaceLinesEstimated, TorusInnerPartOnly) {
    const double R = 2.0, r = 0.7;
    const Estimated e = estimated(inkline::make_torus({0, 0, 0}, {0, 0, 1}, R, r, 128, 64));
    for (double tilt_deg : {60.0, 70.0, 80.0}) {
        const double tl = tilt_deg * M_PI / 180;
        const Camera cam = looking_from({0, -std::sin(tl), std::cos(tl)}, 14.0, false);
        const Lines l = draw(e, cam);
        expect_well_formed(e.mesh, l.curves);
        EXPECT_GT(length_px(l.curves, cam), 20.0) << tilt_deg;
        for (const glm::dvec3& p : l.curves.points) EXPECT_LT(std::hypot(p.x, p.y), R);
    }
}

// Faces inside planar regions: every face sharing a vertex with it, or with those, has its normal
// within half a degree of its own.
std::vector<bool> planar_faces(const MeshTopology& m) {
    std::vector<std::vector<std::uint32_t>> vertex_faces(m.vertex_count());
    for (std::uint32_t f = 0; f < m.face_count(); ++f)
        for (std::uint32_t v : m.faces[f]) vertex_faces[v].push_back(f);
    std::vector<bool> planar(m.face_count());
    const double cos_tolerance = std::cos(0.5 * M_PI / 180);
    for (std::uint32_t f = 0; f < m.face_count(); ++f) {
        const glm::dvec3 n = m.face_normal(f);
        bool ok = true;
        for (std::uint32_t v : m.faces[f])
            for (std::uint32_t g : vertex_faces[v])
                for (std::uint32_t w : m.faces[g])
                    for (std::uint32_t h : vertex_faces[w]) ok = ok && glm::dot(n, m.face_normal(h)) > cos_tolerance;
        planar[f] = ok;
    }
    return planar;
}

TEST(SurfaceLinesEstimated, FandiskPlanarFacetsDrawNothing) {
    // On planar CAD facets kr is estimator noise: nothing may be drawn there, and no specks
    // (curves under 3 pixels) anywhere. Its curved blends may carry real suggestive contours; the
    // lines one or two rings off its sharp creases (estimator leak) are removed: the total is
    // pinned to this version's (9.3 k px over these 24 views; over 12 others 4.1 k with the rings,
    // 20.1 k without).
    const Estimated e = estimated_file("fandisk.off");
    const std::vector<bool> planar = planar_faces(e.mesh);
    ASSERT_GT(std::count(planar.begin(), planar.end(), true), std::ptrdiff_t(e.mesh.face_count() / 4));
    double total = 0.0;
    for (const glm::dvec3& d : directions(24)) {
        const Camera cam = framing_from(e.mesh, d);
        const Lines l = draw(e, cam);
        for (std::uint32_t f : l.curves.segment_face) EXPECT_TRUE(f == kNone || !planar[f]);
        for (const auto& cv : l.curves.curves) {
            double len = 0.0;
            for (std::uint32_t i = cv.begin; i + 1 < cv.end; ++i)
                len += glm::length(cam.project(l.curves.points[i + 1]) - cam.project(l.curves.points[i]));
            EXPECT_GE(len, 3.0);
            total += len;
        }
    }
    EXPECT_NEAR(total, 9344.6, 0.02 * 9344.6);
}

TEST(SurfaceLinesEstimated, ScaledModelDrawsTheSamePixels) {
    const Estimated ref_model = estimated_file("bunny00.off");
    const glm::dvec3 dir = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
    const Camera base = framing_from(ref_model.mesh, dir);
    const Lines ref = draw(ref_model, base);
    ASSERT_GT(ref.curves.points.size(), 100u);
    for (double scale : {1e-4, 1e4}) {
        inkline::TriangleMesh tm;
        tm.positions = ref_model.mesh.positions;
        for (glm::dvec3& p : tm.positions) p *= scale;
        tm.triangles = ref_model.mesh.faces;
        const Estimated e = estimated(std::move(tm));
        const Camera cam = Camera::perspective(scale * base.eye(), scale * base.target(), base.up(), 30.0, 1024, 1024);
        const Lines l = draw(e, cam);
        // Same drawing up to float rounding: the drawn lengths agree to 0.5 %.
        EXPECT_NEAR(length_px(l.curves, cam), length_px(ref.curves, base), 0.005 * length_px(ref.curves, base)) << scale;
    }
}

TEST(SurfaceLinesEstimated, BorderInventsNoLines) {
    // An open Gaussian bump: the estimate near the rim is one-sided, yet what is drawn near the rim
    // stays what the exact field draws there (within a few pixels of length).
    const Profile p = bump(1.0, 3.0);
    const Analytic exact = revolve(p, 49, 96);
    const Estimated e = estimated(exact);
    for (const glm::dvec3& d : directions(16)) {
        if (d.z < 0.2) continue;  // from above: the bump's face
        const Camera cam = looking_from(d, 10.0, false);
        SurfaceLineOptions opt;
        opt.smooth_contour = true;
        const Lines est = draw(e, cam, opt), ana = draw(exact, cam, opt);
        auto near_rim_length = [&](const SurfaceCurves& c) {
            double len = 0.0;
            for (const auto& cv : c.curves)
                for (std::uint32_t i = cv.begin; i + 1 < cv.end; ++i)
                    if (std::hypot(c.points[i].x, c.points[i].y) > 2.8)
                        len += glm::length(cam.project(c.points[i + 1]) - cam.project(c.points[i]));
            return len;
        };
        EXPECT_NEAR(near_rim_length(est.curves), near_rim_length(ana.curves), 5.0);
    }
}

}  // namespace
