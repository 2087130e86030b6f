// Feature stage: exact facing (grazing views, perspective and orthographic), silhouette / border /
// crease classification, chaining into curves, and the three cusp cases, on meshes with known
// answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <CGAL/Exact_rational.h>
#include <glm/geometric.hpp>

#include "features/features.hpp"
#include "model/primitives.hpp"
#include "model/topology.hpp"

using inkline::Camera;
using inkline::CuspCase;
using inkline::Features;
using inkline::LineKind;
using inkline::MeshTopology;
using inkline::TriangleMesh;

namespace {

constexpr std::uint8_t kSil = std::uint8_t(LineKind::Silhouette);
constexpr std::uint8_t kBorder = std::uint8_t(LineKind::Border);
constexpr std::uint8_t kCrease = std::uint8_t(LineKind::Crease);

MeshTopology topology(TriangleMesh m, double crease = 40.0) {
    inkline::validate_mesh(m, "test mesh");
    return inkline::build_topology(m, crease);
}

MeshTopology one_triangle(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    TriangleMesh m;
    m.positions = {a, b, c};
    m.triangles = {{0, 1, 2}};
    return topology(m);
}

Camera persp(glm::dvec3 eye, glm::dvec3 target = {0, 0, 0}, glm::dvec3 up = {0, 1, 0}) {
    return Camera::perspective(eye, target, up, 40.0, 400, 300);
}
Camera ortho(glm::dvec3 eye, glm::dvec3 target = {0, 0, 0}, glm::dvec3 up = {0, 1, 0}) {
    return Camera::orthographic(eye, target, up, 4.0, 400, 300);
}

// Exact sign of det[b - a, c - a, w] in rationals: the reference for facing.
int exact_sign(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 w) {
    using Q = CGAL::Exact_rational;
    const Q ex = Q(b.x) - Q(a.x), ey = Q(b.y) - Q(a.y), ez = Q(b.z) - Q(a.z);
    const Q gx = Q(c.x) - Q(a.x), gy = Q(c.y) - Q(a.y), gz = Q(c.z) - Q(a.z);
    const Q d = (ey * gz - ez * gy) * Q(w.x) + (ez * gx - ex * gz) * Q(w.y) + (ex * gy - ey * gx) * Q(w.z);
    return CGAL::sign(d);
}
// Perspective: the eye on the positive side of the oriented plane (a, b, c).
int exact_side(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 eye) {
    using Q = CGAL::Exact_rational;
    const Q ex = Q(b.x) - Q(a.x), ey = Q(b.y) - Q(a.y), ez = Q(b.z) - Q(a.z);
    const Q gx = Q(c.x) - Q(a.x), gy = Q(c.y) - Q(a.y), gz = Q(c.z) - Q(a.z);
    const Q px = Q(eye.x) - Q(a.x), py = Q(eye.y) - Q(a.y), pz = Q(eye.z) - Q(a.z);
    const Q d = (ey * gz - ez * gy) * px + (ez * gx - ex * gz) * py + (ex * gy - ey * gx) * pz;
    return CGAL::sign(d);
}

double up_next(double x) { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
double down_next(double x) { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

// ---------------------------------------------------------------------------------------------
// Independent checks of a feature extraction against the definitions in features.hpp.

// Kind of every edge and the per-kind lists, from face_front.
void expect_classification(const MeshTopology& m, const Camera& cam, const Features& f) {
    ASSERT_EQ(f.face_front.size(), m.face_count());
    ASSERT_EQ(f.edge_kind.size(), m.edge_count());
    for (std::uint32_t i = 0; i < m.face_count(); ++i)
        EXPECT_EQ(f.face_front[i], inkline::face_is_front(m, i, cam) ? 1 : 0) << "face " << i;
    std::vector<std::uint32_t> sil, border, crease;
    for (std::uint32_t e = 0; e < m.edge_count(); ++e) {
        const auto [f0, f1] = m.edge_face[e];
        std::uint8_t want = inkline::kNoKind;
        if (f1 == inkline::kNoFace) want = kBorder;
        else if (f.face_front[f0] != f.face_front[f1]) want = kSil;  // silhouette overrides crease
        else if (m.is_crease(e)) want = kCrease;
        EXPECT_EQ(f.edge_kind[e], want) << "edge " << e;
        if (want == kSil) sil.push_back(e);
        if (want == kBorder) border.push_back(e);
        if (want == kCrease) crease.push_back(e);
    }
    auto sorted = [](std::vector<std::uint32_t> v) {
        std::sort(v.begin(), v.end());
        return v;
    };
    EXPECT_EQ(sorted(f.silhouette_edges), sil);
    EXPECT_EQ(sorted(f.border_edges), border);
    EXPECT_EQ(sorted(f.crease_edges), crease);
}

std::vector<std::uint32_t> incident_of_kind(const MeshTopology& m, const Features& f, std::uint32_t v,
                                            std::uint8_t kind) {
    std::vector<std::uint32_t> out;
    for (auto k = m.vertex_edge_begin[v]; k < m.vertex_edge_begin[v + 1]; ++k)
        if (f.edge_kind[m.vertex_edges[k]] == kind) out.push_back(m.vertex_edges[k]);
    return out;
}

// Cusps: exactly the vertices of silhouette edges that match one of the three cases, with the
// case given by the definitions (ManySilhouettes first, then BorderEdge, then FrontBackMeet).
std::map<std::uint32_t, CuspCase> expected_cusps(const MeshTopology& m, const Features& f) {
    std::map<std::uint32_t, CuspCase> out;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
        const auto sil = incident_of_kind(m, f, v, kSil);
        if (sil.empty()) continue;
        int front = 0;
        for (auto e : sil) front += m.is_convex(e) ? 1 : 0;
        bool border = false;
        for (auto k = m.vertex_edge_begin[v]; k < m.vertex_edge_begin[v + 1]; ++k)
            border |= m.is_border(m.vertex_edges[k]);
        if (sil.size() > 2) out[v] = CuspCase::ManySilhouettes;
        else if (border) out[v] = CuspCase::BorderEdge;
        else if (sil.size() == 2 && front == 1) out[v] = CuspCase::FrontBackMeet;
    }
    return out;
}

std::map<std::uint32_t, CuspCase> reported_cusps(const Features& f) {
    EXPECT_EQ(f.cusp_vertices.size(), f.cusp_cases.size());
    std::map<std::uint32_t, CuspCase> out;
    for (std::size_t i = 0; i < f.cusp_vertices.size(); ++i) {
        EXPECT_TRUE(out.emplace(f.cusp_vertices[i], f.cusp_cases[i]).second)
            << "cusp vertex " << f.cusp_vertices[i] << " reported twice";
        EXPECT_NE(f.cusp_cases[i], CuspCase::None);
    }
    return out;
}

int feature_degree(const MeshTopology& m, const Features& f, std::uint32_t v, bool* mixed = nullptr) {
    int deg = 0;
    std::set<std::uint8_t> kinds;
    for (auto k = m.vertex_edge_begin[v]; k < m.vertex_edge_begin[v + 1]; ++k) {
        const auto kk = f.edge_kind[m.vertex_edges[k]];
        if (kk == inkline::kNoKind) continue;
        ++deg;
        kinds.insert(kk);
    }
    if (mixed) *mixed = kinds.size() > 1;
    return deg;
}

// Chaining: each curve is a path (or cycle) of edges of its kind; every edge of a wanted kind is in
// exactly one curve and no other edge is; curves pass only through plain vertices (two feature
// edges of one kind, no cusp) and open curves end at junctions, cusps or kind changes.
void expect_chains(const MeshTopology& m, const Features& f, const inkline::FeatureOptions& opt = {}) {
    const auto cusps = reported_cusps(f);
    auto is_break = [&](std::uint32_t v) {
        bool mixed = false;
        const int deg = feature_degree(m, f, v, &mixed);
        return deg != 2 || mixed || cusps.count(v) > 0;
    };
    std::vector<int> used(m.edge_count(), 0);
    for (std::size_t c = 0; c < f.curves.size(); ++c) {
        const auto& cv = f.curves[c];
        SCOPED_TRACE("curve " + std::to_string(c));
        ASSERT_FALSE(cv.edges.empty());
        ASSERT_EQ(cv.vertices.size(), cv.edges.size() + 1);
        EXPECT_TRUE(opt.wants(cv.kind));
        for (std::size_t i = 0; i < cv.edges.size(); ++i) {
            const auto e = cv.edges[i];
            ASSERT_LT(e, m.edge_count());
            ++used[e];
            EXPECT_EQ(f.edge_kind[e], std::uint8_t(cv.kind)) << "edge " << e;
            const std::set<std::uint32_t> ends = {m.edge_vertex[e][0], m.edge_vertex[e][1]};
            EXPECT_EQ(ends, (std::set<std::uint32_t>{cv.vertices[i], cv.vertices[i + 1]})) << "edge " << e;
        }
        // closed: a loop whose start is an ordinary vertex; a loop from a junction back to it is open
        EXPECT_EQ(cv.closed, cv.vertices.front() == cv.vertices.back() && !is_break(cv.vertices.front()));
        for (std::size_t i = 1; i + 1 < cv.vertices.size(); ++i)
            EXPECT_FALSE(is_break(cv.vertices[i])) << "curve runs through junction " << cv.vertices[i];
        if (!cv.closed) {
            EXPECT_TRUE(is_break(cv.vertices.front())) << "open curve starts at plain vertex " << cv.vertices.front();
            EXPECT_TRUE(is_break(cv.vertices.back())) << "open curve ends at plain vertex " << cv.vertices.back();
        }
    }
    for (std::uint32_t e = 0; e < m.edge_count(); ++e) {
        const bool wanted = f.edge_kind[e] != inkline::kNoKind && opt.wants(LineKind(f.edge_kind[e]));
        EXPECT_EQ(used[e], wanted ? 1 : 0) << "edge " << e << " kind " << int(f.edge_kind[e]);
    }
}

void expect_consistent(const MeshTopology& m, const Camera& cam, const Features& f,
                       const inkline::FeatureOptions& opt = {}) {
    expect_classification(m, cam, f);
    EXPECT_EQ(reported_cusps(f), expected_cusps(m, f));
    expect_chains(m, f, opt);
}

std::size_t count_kind(const Features& f, LineKind k) {
    return std::size_t(std::count_if(f.curves.begin(), f.curves.end(),
                                     [&](const inkline::FeatureCurve& c) { return c.kind == k; }));
}

}  // namespace

// =============================================================================================
// Facing

TEST(FaceIsFront, SignConventionPerspective) {
    // Counter-clockwise seen from +z: outward normal +z.
    const MeshTopology t = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_GT(t.face_normal(0).z, 0.0);
    EXPECT_TRUE(inkline::face_is_front(t, 0, persp({0.2, 0.2, 5})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({0.2, 0.2, -5})));
    // Only the side of the eye matters, not where the camera looks.
    EXPECT_TRUE(inkline::face_is_front(t, 0, persp({30, -20, 0.5}, {60, -40, 0.5})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({30, -20, -0.5}, {0, 0, 10})));
}

TEST(FaceIsFront, SignConventionOrthographic) {
    const MeshTopology t = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    EXPECT_TRUE(inkline::face_is_front(t, 0, ortho({0, 0, 5})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, ortho({0, 0, -5})));
    // Orthographic: only the direction matters, not the side of the plane the eye is on.
    EXPECT_TRUE(inkline::face_is_front(t, 0, ortho({0, 0, -5}, {0, 0, -10})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, ortho({0, 0, 5}, {0, 0, 10})));
}

TEST(FaceIsFront, BoxFacesPointOutward) {
    const MeshTopology box = topology(inkline::make_box({-1, -1, -1}, {1, 1, 1}));
    for (const glm::dvec3 dir : {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0),
                                 glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1)}) {
        const glm::dvec3 up = dir.y != 0 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        for (const Camera& cam : {persp(10.0 * dir, {0, 0, 0}, up), ortho(10.0 * dir, {0, 0, 0}, up)}) {
            int front = 0;
            for (std::uint32_t f = 0; f < box.face_count(); ++f) {
                const bool is_front = inkline::face_is_front(box, f, cam);
                front += is_front;
                // Front exactly when the outward normal points to the eye; the four sides seen
                // edge-on (ortho) or from behind their planes (perspective) are not front.
                EXPECT_EQ(is_front, glm::dot(box.face_normal(f), dir) > 0.5) << "face " << f;
            }
            EXPECT_EQ(front, 2);
        }
    }
}

TEST(FaceIsFront, EyeInThePlanePerspective) {
    // Plane z = 0.1 (the double nearest 0.1): the eye exactly in it is not front; the next double
    // above is front, the next below is back, even far away where a naive determinant would round.
    const double z = 0.1;
    const MeshTopology t = one_triangle({0, 0, z}, {1, 0, z}, {0, 1, z});
    for (const double far : {0.0, 3.0, 1e8, 1e15, 1e150}) {
        SCOPED_TRACE(far);
        const glm::dvec3 e(far + 0.5, -far, z);
        EXPECT_FALSE(inkline::face_is_front(t, 0, persp(e, {0, 0, 0}, {0, 0, 1})));
        EXPECT_TRUE(inkline::face_is_front(t, 0, persp({e.x, e.y, up_next(z)}, {0, 0, 0}, {0, 0, 1})));
        EXPECT_FALSE(inkline::face_is_front(t, 0, persp({e.x, e.y, down_next(z)}, {0, 0, 0}, {0, 0, 1})));
    }
    // The smallest steps off the plane z = 0.
    const MeshTopology t0 = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    const double tiny = std::numeric_limits<double>::denorm_min();
    EXPECT_FALSE(inkline::face_is_front(t0, 0, persp({5, 3, 0}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_TRUE(inkline::face_is_front(t0, 0, persp({5, 3, tiny}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_FALSE(inkline::face_is_front(t0, 0, persp({5, 3, -tiny}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_TRUE(inkline::face_is_front(t0, 0, persp({5, 3, 1e-300}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_FALSE(inkline::face_is_front(t0, 0, persp({5, 3, -1e-300}, {0, 0, 0}, {0, 0, 1})));
}

TEST(FaceIsFront, EyeInASkewPlanePerspective) {
    // Plane x + y + z = 3 through (3,0,0), (0,3,0), (0,0,3), normal (1,1,1). Eyes on it with huge
    // coordinates, then one unit in the last place off it.
    const MeshTopology t = one_triangle({3, 0, 0}, {0, 3, 0}, {0, 0, 3});
    const double big = 1e15;  // ulp(1e15) = 0.125
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({big, -big, 3})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({0.375, 0.125, 2.5})));
    EXPECT_TRUE(inkline::face_is_front(t, 0, persp({big, -big, up_next(3)})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({big, -big, down_next(3)})));
    EXPECT_TRUE(inkline::face_is_front(t, 0, persp({big + 0.125, -big, 3})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({big, -big - 0.125, 3})));
    EXPECT_TRUE(inkline::face_is_front(t, 0, persp({up_next(0.375), 0.125, 2.5})));
    EXPECT_FALSE(inkline::face_is_front(t, 0, persp({0.375, down_next(0.125), 2.5})));
}

TEST(FaceIsFront, ViewDirectionInThePlaneOrthographic) {
    const MeshTopology t = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    // Looking along -x, exactly in the plane z = 0: not front (and not back either: the face is
    // edge-on, so both sides agree it is "not front").
    const Camera edge_on = ortho({5, 0, 0}, {0, 0, 0}, {0, 0, 1});
    EXPECT_EQ(edge_on.forward(), glm::dvec3(-1, 0, 0));
    EXPECT_FALSE(inkline::face_is_front(t, 0, edge_on));
    // Tilted by the smallest amounts: the sign follows the tilt of the stored view direction.
    for (const double tilt : {1e-300, std::numeric_limits<double>::denorm_min(), 1e-17, 0x1p-1060}) {
        SCOPED_TRACE(tilt);
        const Camera above = ortho({1, 0, tilt}, {0, 0, 0}, {0, 0, 1});
        const Camera below = ortho({1, 0, -tilt}, {0, 0, 0}, {0, 0, 1});
        ASSERT_LT(above.forward().z, 0.0);  // looking slightly down: sees the +z side
        ASSERT_GT(below.forward().z, 0.0);
        EXPECT_TRUE(inkline::face_is_front(t, 0, above));
        EXPECT_FALSE(inkline::face_is_front(t, 0, below));
    }
    // A view direction in a skew plane: face in x + y + z = 3 seen along (1, -1, 0).
    const MeshTopology s = one_triangle({3, 0, 0}, {0, 3, 0}, {0, 0, 3});
    EXPECT_FALSE(inkline::face_is_front(s, 0, ortho({1, -1, 0}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_FALSE(inkline::face_is_front(s, 0, ortho({-1, 1, 0}, {0, 0, 0}, {0, 0, 1})));
    EXPECT_TRUE(inkline::face_is_front(s, 0, ortho({1, 1, 1}, {0, 0, 0}, {0, 0, 1})));
}

TEST(FaceIsFront, RandomGrazingEyesMatchExactArithmetic) {
    // Eyes computed to lie on the plane of a random triangle (so within rounding of it), then
    // nudged by a few units in the last place; scales from subnormal-prone to huge.
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int on_plane = 0, checked = 0, wrong = 0;
    // Perspective facing depends on the eye only; look anywhere that makes a valid frame.
    auto look_from = [](glm::dvec3 eye) {
        const double reach = std::max({1.0, std::abs(eye.x), std::abs(eye.y), std::abs(eye.z)});
        return persp(eye, eye + reach * glm::dvec3(0.3, -0.2, 0.9), glm::dvec3(0, 1, 0));
    };
    for (const double scale : {0x1p-520, 1e-150, 1e-3, 1.0, 1e6, 1e150}) {
        for (int it = 0; it < 3000; ++it) {
            const glm::dvec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng)), c(U(rng), U(rng), U(rng));
            const glm::dvec3 A = a * scale, B = b * scale, C = c * scale;
            const MeshTopology t = one_triangle(A, B, C);
            const double s = 4 * U(rng), r = 4 * U(rng);
            glm::dvec3 eye = A + s * (B - A) + r * (C - A);
            const int k = int(rng() % 3), steps = int(rng() % 5) - 2;
            for (int i = 0; i < std::abs(steps); ++i) eye[k] = steps > 0 ? up_next(eye[k]) : down_next(eye[k]);
            if (eye == A) continue;
            const int want = exact_side(A, B, C, eye);
            on_plane += want == 0;
            if (inkline::face_is_front(t, 0, look_from(eye)) != (want > 0) && ++wrong <= 5)
                ADD_FAILURE() << "perspective, scale " << scale << " it " << it << ": exact sign " << want;
            ++checked;
        }
    }
    EXPECT_GT(checked, 17900);
    // Lattice triangles and eyes that are exact combinations of their corners: exactly on the
    // plane (not front) unless nudged.
    std::uniform_int_distribution<int> I(-1000, 1000), S(-32, 32);
    int lattice_checked = 0;
    for (const int exponent : {-1000, -30, 0, 40, 400}) {
        for (int it = 0; it < 2000; ++it) {
            auto lattice = [&] { return std::ldexp(1.0, exponent) * glm::dvec3(I(rng), I(rng), I(rng)); };
            const glm::dvec3 A = lattice(), B = lattice(), C = lattice();
            const MeshTopology t = one_triangle(A, B, C);
            glm::dvec3 eye = A + (S(rng) / 8.0) * (B - A) + (S(rng) / 8.0) * (C - A);  // exact
            const int k = int(rng() % 3), steps = int(rng() % 3) - 1;
            if (steps) eye[k] = steps > 0 ? up_next(eye[k]) : down_next(eye[k]);
            if (eye == A) continue;
            const int want = exact_side(A, B, C, eye);
            on_plane += want == 0;
            if (inkline::face_is_front(t, 0, look_from(eye)) != (want > 0) && ++wrong <= 5)
                ADD_FAILURE() << "lattice, exponent " << exponent << " it " << it << ": exact sign " << want;
            ++lattice_checked;
        }
    }
    EXPECT_GT(lattice_checked, 9900);
    EXPECT_GT(on_plane, 2000);  // a third of the lattice eyes lie exactly on the plane
    // Orthographic: random triangles and view directions; the reference uses the stored forward.
    int ortho_checked = 0;
    for (const double scale : {0x1p-538, 0x1p-536, 0x1p-534, 0x1p-500, 1e-150, 1.0, 1e150}) {
        for (int it = 0; it < 4000; ++it) {
            const glm::dvec3 A(0.0), B = scale * glm::dvec3(U(rng), U(rng), U(rng)),
                                     C = scale * glm::dvec3(U(rng), U(rng), U(rng));
            const MeshTopology t = one_triangle(A, B, C);
            glm::dvec3 d(U(rng), U(rng), U(rng));
            if (it % 2) {  // nearly in the plane of the face
                const glm::dvec3 n = glm::cross(B / scale, C / scale);
                d -= glm::dot(d, n) / glm::dot(n, n) * n;
            }
            try {
                const Camera cam = Camera::orthographic(-d, {0, 0, 0}, {0.3, 0.5, 0.7}, 1.0, 10, 10);
                const int want = exact_sign(A, B, C, -cam.forward());
                if (inkline::face_is_front(t, 0, cam) != (want > 0) && ++wrong <= 5)
                    ADD_FAILURE() << "orthographic, scale " << scale << " it " << it << ": exact sign " << want;
                ++ortho_checked;
            } catch (const std::invalid_argument&) {
            }
        }
    }
    EXPECT_GT(ortho_checked, 27000);
    EXPECT_EQ(wrong, 0) << "facing decisions that differ from exact arithmetic";
}

// =============================================================================================
// Classification and chaining

TEST(ExtractFeatures, SphereHasOneClosedSilhouette) {
    const MeshTopology s = topology(inkline::make_sphere({0, 0, 0}, 1.0, 32, 16));
    for (const glm::dvec3 eye : {glm::dvec3(3.1, 1.7, 4.3), glm::dvec3(2, -3, 1), glm::dvec3(-4, 0.3, -2)}) {
        SCOPED_TRACE(eye.x);
        for (const Camera& cam : {persp(eye), ortho(eye)}) {
            const Features f = extract_features(s, cam);
            expect_consistent(s, cam, f);
            EXPECT_TRUE(f.border_edges.empty());
            EXPECT_TRUE(f.crease_edges.empty());
            EXPECT_TRUE(f.cusp_vertices.empty());  // convex: every silhouette edge front-facing
            EXPECT_GT(f.silhouette_edges.size(), 20u);
            ASSERT_EQ(f.curves.size(), 1u);
            const auto& c = f.curves[0];
            EXPECT_EQ(c.kind, LineKind::Silhouette);
            EXPECT_TRUE(c.closed);
            EXPECT_EQ(c.vertices.front(), c.vertices.back());
            EXPECT_EQ(c.edges.size(), f.silhouette_edges.size());
            for (auto e : f.silhouette_edges) {
                EXPECT_TRUE(s.is_convex(e));
                EXPECT_NE(f.face_front[s.edge_face[e][0]], f.face_front[s.edge_face[e][1]]);
            }
            // Front faces are those facing the eye: roughly half the sphere.
            const auto front = [&] { const auto all = f.face_front.all(); return std::count(all.begin(), all.end(), 1); }();
            EXPECT_GT(front, long(s.face_count()) / 4);
            EXPECT_LT(front, long(s.face_count()) * 3 / 4);
        }
    }
}

TEST(ExtractFeatures, BoxFromACorner) {
    const MeshTopology box = topology(inkline::make_box({-1, -1, -1}, {1, 1, 1}));
    const Camera cam = persp({3, 4, 5});
    const Features f = extract_features(box, cam);
    expect_consistent(box, cam, f);
    // Three sides face the eye; their outline is a hexagon of six box edges (creases, but
    // classified as silhouettes); the other six box edges are creases: three at the near corner
    // (1,1,1), three at the hidden far corner (-1,-1,-1).
    EXPECT_EQ([&] { const auto all = f.face_front.all(); return std::count(all.begin(), all.end(), 1); }(), 6);
    ASSERT_EQ(f.silhouette_edges.size(), 6u);
    EXPECT_EQ(f.crease_edges.size(), 6u);
    EXPECT_TRUE(f.border_edges.empty());
    EXPECT_TRUE(f.cusp_vertices.empty());
    std::map<std::uint32_t, int> degree;
    for (auto e : f.silhouette_edges) {
        EXPECT_TRUE(box.is_crease(e));
        ++degree[box.edge_vertex[e][0]];
        ++degree[box.edge_vertex[e][1]];
    }
    EXPECT_EQ(degree.size(), 6u);  // one closed loop through six vertices
    for (const auto& [v, d] : degree) {
        EXPECT_EQ(d, 2) << v;
        const glm::dvec3 p = box.positions[v];
        EXPECT_FALSE(p == glm::dvec3(1, 1, 1) || p == glm::dvec3(-1, -1, -1));
    }
    for (auto e : f.crease_edges) {
        const glm::dvec3 p = box.positions[box.edge_vertex[e][0]], q = box.positions[box.edge_vertex[e][1]];
        const bool near = p == glm::dvec3(1, 1, 1) || q == glm::dvec3(1, 1, 1);
        const bool far = p == glm::dvec3(-1, -1, -1) || q == glm::dvec3(-1, -1, -1);
        EXPECT_TRUE(near != far) << e;
    }
    // Every hexagon vertex joins two silhouette edges and one crease: a junction. So are the
    // corners where three creases meet. Every curve is a single edge.
    EXPECT_EQ(count_kind(f, LineKind::Silhouette), 6u);
    EXPECT_EQ(count_kind(f, LineKind::Crease), 6u);
    EXPECT_EQ(f.curves.size(), 12u);
    int ends_at_near_corner = 0;
    for (const auto& c : f.curves) {
        EXPECT_EQ(c.edges.size(), 1u);
        EXPECT_FALSE(c.closed);
        for (auto v : {c.vertices.front(), c.vertices.back()})
            ends_at_near_corner += box.positions[v] == glm::dvec3(1, 1, 1);
    }
    EXPECT_EQ(ends_at_near_corner, 3);

    // Without creases the hexagon is one closed silhouette curve of six edges.
    MeshTopology smooth = box;
    smooth.set_crease_angle(100.0);
    const Features g = extract_features(smooth, cam);
    expect_consistent(smooth, cam, g);
    EXPECT_TRUE(g.crease_edges.empty());
    ASSERT_EQ(g.curves.size(), 1u);
    EXPECT_TRUE(g.curves[0].closed);
    EXPECT_EQ(g.curves[0].edges.size(), 6u);
    EXPECT_EQ(g.curves[0].vertices.size(), 7u);
}

TEST(ExtractFeatures, BoxSeenAlongAnAxisOrthographic) {
    // Looking straight down -z: the four sides are edge-on (not front), so only the top square
    // separates front from not-front; the bottom square and the verticals are creases.
    const MeshTopology box = topology(inkline::make_box({-1, -1, -1}, {1, 1, 1}));
    const Camera cam = ortho({0, 0, 10});
    const Features f = extract_features(box, cam);
    expect_consistent(box, cam, f);
    EXPECT_EQ([&] { const auto all = f.face_front.all(); return std::count(all.begin(), all.end(), 1); }(), 2);
    ASSERT_EQ(f.silhouette_edges.size(), 4u);
    for (auto e : f.silhouette_edges) {
        EXPECT_EQ(box.positions[box.edge_vertex[e][0]].z, 1.0);
        EXPECT_EQ(box.positions[box.edge_vertex[e][1]].z, 1.0);
    }
    EXPECT_EQ(f.crease_edges.size(), 8u);
}

TEST(ExtractFeatures, SheetBorderIsOneClosedCurve) {
    for (int n : {1, 3, 6}) {
        const MeshTopology sheet = topology(inkline::make_sheet(1.0, 0.0, n));
        // From above (front), from below (back), and from within its plane (edge-on).
        for (const glm::dvec3 eye : {glm::dvec3(0.3, 5, 0.2), glm::dvec3(0.3, -5, 0.2), glm::dvec3(5, 0, 3)}) {
            SCOPED_TRACE(std::to_string(n) + " eye.y " + std::to_string(eye.y));
            const Camera cam = persp(eye, {0, 0, 0}, eye.y == 0 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
            const Features f = extract_features(sheet, cam);
            expect_consistent(sheet, cam, f);
            const auto front = [&] { const auto all = f.face_front.all(); return std::count(all.begin(), all.end(), 1); }();
            EXPECT_EQ(front, eye.y > 0 ? long(sheet.face_count()) : 0L);
            EXPECT_TRUE(f.silhouette_edges.empty());
            EXPECT_TRUE(f.crease_edges.empty());
            EXPECT_TRUE(f.cusp_vertices.empty());
            EXPECT_EQ(f.border_edges.size(), std::size_t(4 * n));
            ASSERT_EQ(f.curves.size(), 1u);
            EXPECT_EQ(f.curves[0].kind, LineKind::Border);
            EXPECT_TRUE(f.curves[0].closed);
            EXPECT_EQ(f.curves[0].edges.size(), std::size_t(4 * n));
            EXPECT_EQ(f.curves[0].vertices.front(), f.curves[0].vertices.back());
        }
    }
}

TEST(ExtractFeatures, KindsSwitchOffChaining) {
    const MeshTopology box = topology(inkline::make_box({-1, -1, -1}, {1, 1, 1}));
    const Camera cam = persp({3, 4, 5});
    for (int off = 0; off < inkline::kLineKindCount; ++off) {
        inkline::FeatureOptions opt;
        opt.kinds[off] = false;
        const Features f = extract_features(box, cam, opt);
        expect_consistent(box, cam, f, opt);
        // Classification is unchanged; only the curves of that kind are gone. The junctions still
        // count the switched-off kind, so the remaining curves are the same single edges.
        EXPECT_EQ(f.silhouette_edges.size(), 6u);
        EXPECT_EQ(f.crease_edges.size(), 6u);
        EXPECT_EQ(count_kind(f, LineKind(off)), 0u);
        const std::size_t want = off == int(LineKind::Border) ? 12u : 6u;
        EXPECT_EQ(f.curves.size(), want);
        for (const auto& c : f.curves) EXPECT_EQ(c.edges.size(), 1u);
    }
    inkline::FeatureOptions none;
    for (auto& k : none.kinds) k = false;
    const Features f = extract_features(box, cam, none);
    EXPECT_TRUE(f.curves.empty());
    EXPECT_EQ(f.silhouette_edges.size(), 6u);
}

// =============================================================================================
// Cusps

TEST(Cusps, TorusFrontBackMeet) {
    // A torus seen from close by at a grazing elevation: its silhouette crosses the saddle-shaped
    // inner half, where front- (convex) and back-facing (concave) silhouette edges meet.
    const MeshTopology torus = topology(inkline::make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.4, 48, 24));
    int total = 0;
    for (const glm::dvec3 eye : {glm::dvec3(0.31, 0.05, 1.8), glm::dvec3(0.31, 0.2, 2.5),
                                 glm::dvec3(0.31, 1.0, 4.0), glm::dvec3(0.31, 0.4, 2.5)}) {
        SCOPED_TRACE(eye.y);
        const Camera cam = persp(eye);
        const Features f = extract_features(torus, cam);
        expect_consistent(torus, cam, f);
        EXPECT_TRUE(f.border_edges.empty());
        int front_back = 0, many = 0;
        for (std::size_t i = 0; i < f.cusp_vertices.size(); ++i) {
            const auto v = f.cusp_vertices[i];
            const auto sil = incident_of_kind(torus, f, v, kSil);
            if (f.cusp_cases[i] == CuspCase::FrontBackMeet) {
                ++front_back;
                ASSERT_EQ(sil.size(), 2u) << v;
                EXPECT_NE(torus.is_convex(sil[0]), torus.is_convex(sil[1])) << v;
            } else {
                EXPECT_EQ(f.cusp_cases[i], CuspCase::ManySilhouettes);
                EXPECT_GT(sil.size(), 2u);
                ++many;
            }
        }
        EXPECT_GT(front_back, 0);
        // Along each closed silhouette loop the front/back class changes an even number of times,
        // so without junctions the cusps come in pairs.
        if (many == 0) {
            EXPECT_EQ(front_back % 2, 0);
        }
        total += front_back;
        // Silhouette curves end exactly at cusps (no borders or creases on a smooth torus): each
        // open silhouette curve has cusps at both ends.
        std::set<std::uint32_t> cusps(f.cusp_vertices.begin(), f.cusp_vertices.end());
        for (const auto& c : f.curves)
            if (!c.closed) {
                EXPECT_TRUE(cusps.count(c.vertices.front()));
                EXPECT_TRUE(cusps.count(c.vertices.back()));
            }
    }
    EXPECT_GT(total, 10);
    // Seen from far above the axis, the silhouettes are the outer and inner equators: convex and
    // concave loops with no cusp.
    const Camera top = ortho({0, 10, 0}, {0, 0, 0}, {0, 0, 1});
    const Features f = extract_features(torus, top);
    expect_consistent(torus, top, f);
    EXPECT_TRUE(f.cusp_vertices.empty());
    ASSERT_EQ(f.curves.size(), 2u);
    EXPECT_TRUE(f.curves[0].closed && f.curves[1].closed);
}

namespace {
// The upper half (y >= 0) of a UV sphere: an open dome with its rim on the equator.
TriangleMesh dome(int slices, int stacks) {
    const TriangleMesh s = inkline::make_sphere({0, 0, 0}, 1.0, slices, stacks);
    TriangleMesh m;
    std::map<std::uint32_t, std::uint32_t> remap;
    for (const auto& t : s.triangles) {
        const double y = (s.positions[t[0]].y + s.positions[t[1]].y + s.positions[t[2]].y) / 3;
        if (y <= 0) continue;
        std::array<std::uint32_t, 3> u;
        for (int k = 0; k < 3; ++k) {
            auto [it, inserted] = remap.try_emplace(t[k], std::uint32_t(m.positions.size()));
            if (inserted) m.positions.push_back(s.positions[t[k]]);
            u[k] = it->second;
        }
        m.triangles.push_back(u);
    }
    return m;
}
}  // namespace

TEST(Cusps, BorderEdgeWhereSilhouetteMeetsTheRim) {
    const MeshTopology d = topology(dome(32, 16));
    ASSERT_FALSE(d.closed);
    for (const glm::dvec3 eye : {glm::dvec3(4, 0.5, 1.3), glm::dvec3(-3, 1.5, 2)}) {
        SCOPED_TRACE(eye.x);
        const Camera cam = persp(eye);
        const Features f = extract_features(d, cam);
        expect_consistent(d, cam, f);
        EXPECT_EQ(f.border_edges.size(), 32u);
        int border_cusps = 0;
        for (std::size_t i = 0; i < f.cusp_vertices.size(); ++i) {
            const auto v = f.cusp_vertices[i];
            ASSERT_EQ(f.cusp_cases[i], CuspCase::BorderEdge) << v;
            ++border_cusps;
            EXPECT_NEAR(d.positions[v].y, 0.0, 1e-12);  // on the rim
            EXPECT_FALSE(incident_of_kind(d, f, v, kSil).empty());
            EXPECT_EQ(incident_of_kind(d, f, v, kBorder).size(), 2u);
        }
        // The silhouette arc runs over the dome from one side of the rim to the other.
        EXPECT_GE(border_cusps, 2);
        EXPECT_GE(count_kind(f, LineKind::Silhouette), 1u);
        for (const auto& c : f.curves) EXPECT_FALSE(c.closed);  // every curve is cut at the cusps
    }
}

namespace {
// Monkey saddle: a fan of six triangles around the origin, rim corners alternately up and down.
TriangleMesh monkey_saddle() {
    TriangleMesh m;
    m.positions.push_back({0, 0, 0});
    for (int k = 0; k < 6; ++k) {
        const double a = M_PI / 3 * k;
        m.positions.push_back({std::cos(a), std::sin(a), k % 2 ? -1.0 : 1.0});
    }
    for (std::uint32_t k = 0; k < 6; ++k) m.triangles.push_back({0, 1 + k, 1 + (k + 1) % 6});
    return m;
}
}  // namespace

TEST(Cusps, ManySilhouettesAtAMonkeySaddle) {
    // Seen from the side along +x, the six faces around the centre are back, front, back, back,
    // front, back: four spokes separate front from back. (No crease threshold: the folds between
    // faces are steep, and the two spokes that are not silhouettes would be creases.)
    const MeshTopology s = topology(monkey_saddle(), 180.0);
    for (const Camera& cam : {persp({10, 0, 1}, {0, 0, 0}, {0, 0, 1}), ortho({10, 0, 1}, {0, 0, 0}, {0, 0, 1})}) {
        const Features f = extract_features(s, cam);
        expect_consistent(s, cam, f);
        EXPECT_EQ(f.face_front.all(),
                  (std::vector<std::uint8_t>{0, 1, 0, 0, 1, 0}));
        ASSERT_EQ(f.silhouette_edges.size(), 4u);
        EXPECT_EQ(f.border_edges.size(), 6u);
        const auto cusps = reported_cusps(f);
        ASSERT_TRUE(cusps.count(0));
        EXPECT_EQ(cusps.at(0), CuspCase::ManySilhouettes);
        // The rim ends of the four silhouette spokes (rim vertices 1, 2, 4, 5) touch borders.
        EXPECT_EQ(cusps, (std::map<std::uint32_t, CuspCase>{{0, CuspCase::ManySilhouettes},
                                                             {2, CuspCase::BorderEdge},
                                                             {3, CuspCase::BorderEdge},
                                                             {5, CuspCase::BorderEdge},
                                                             {6, CuspCase::BorderEdge}}));
        // Four one-edge silhouettes and the rim cut at the four cusps into 1 + 2 + 1 + 2 edges.
        EXPECT_EQ(count_kind(f, LineKind::Silhouette), 4u);
        std::multiset<std::size_t> rim;
        for (const auto& c : f.curves) {
            if (c.kind == LineKind::Silhouette) EXPECT_EQ(c.edges.size(), 1u);
            else rim.insert(c.edges.size());
        }
        EXPECT_EQ(rim, (std::multiset<std::size_t>{1, 1, 2, 2}));
        // Border chaining off: only the four silhouettes remain.
        inkline::FeatureOptions opt;
        opt.kinds[int(LineKind::Border)] = false;
        const Features g = extract_features(s, cam, opt);
        expect_consistent(s, cam, g, opt);
        EXPECT_EQ(g.curves.size(), 4u);
    }
    // With the default 40-degree threshold the other two spokes (rim vertices 0 and 3) are creases:
    // every rim vertex is then a junction and the rim falls apart into six single edges.
    const MeshTopology c = topology(monkey_saddle());
    const Camera cam = persp({10, 0, 1}, {0, 0, 0}, {0, 0, 1});
    const Features f = extract_features(c, cam);
    expect_consistent(c, cam, f);
    EXPECT_EQ(f.silhouette_edges.size(), 4u);
    ASSERT_EQ(f.crease_edges.size(), 2u);
    for (auto e : f.crease_edges) {
        const auto v = c.edge_vertex[e][0] == 0 ? c.edge_vertex[e][1] : c.edge_vertex[e][0];
        EXPECT_TRUE(v == 1 || v == 4) << v;
    }
    EXPECT_EQ(count_kind(f, LineKind::Border), 6u);
    EXPECT_EQ(count_kind(f, LineKind::Crease), 2u);
    EXPECT_EQ(f.curves.size(), 12u);
}

// Curves are views into their list's flat arrays: a copy of a view's features keeps its own
// curves when the original's storage is reused by the next view (and a moved list keeps them).
TEST(CurveList, CopiesAndMovesKeepTheirCurves) {
    const MeshTopology torus = topology(inkline::make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.4, 48, 24));
    const Camera a = persp({0.31, 0.2, 2.5}), b = persp({2.0, 1.5, 0.3});
    auto snapshot = [](const Features& f) {
        std::vector<std::tuple<int, bool, std::vector<std::uint32_t>, std::vector<std::uint32_t>>> out;
        for (const auto& c : f.curves)
            out.emplace_back(int(c.kind), c.closed, std::vector<std::uint32_t>(c.vertices.begin(), c.vertices.end()),
                             std::vector<std::uint32_t>(c.edges.begin(), c.edges.end()));
        return out;
    };
    const auto want_a = snapshot(extract_features(torus, a)), want_b = snapshot(extract_features(torus, b));
    ASSERT_GT(want_a.size(), 1u);
    ASSERT_NE(want_a, want_b);
    inkline::SilhouetteFinder finder(torus);
    Features f;
    finder.find(a, {}, f);
    const Features copy = f;  // copy construction
    Features assigned;
    assigned = f;  // copy assignment
    finder.find(b, {}, f);  // the original's arrays now hold view b
    EXPECT_EQ(snapshot(f), want_b);
    EXPECT_EQ(snapshot(copy), want_a);
    EXPECT_EQ(snapshot(assigned), want_a);
    for (const auto& c : copy.curves) {  // the views point into the copy's own arrays
        ASSERT_FALSE(c.edges.empty());
        EXPECT_EQ(c.vertices.size(), c.edges.size() + 1);
    }
    const Features moved = std::move(f);
    EXPECT_EQ(snapshot(moved), want_b);
}

// edges_of(c0, c1): the edges of curves [c0, c1) one after another, for every range of a view with
// many curves (build_pieces reads ahead in it across curves), and empty for an empty range.
TEST(CurveList, EdgesOfARangeAreTheCurvesEdgesInOrder) {
    const MeshTopology torus = topology(inkline::make_torus({0, 0, 0}, {0, 1, 0}, 1.0, 0.4, 48, 24));
    const Features f = extract_features(torus, persp({2.0, 1.5, 0.3}));
    const std::size_t n = f.curves.size();
    ASSERT_GT(n, 3u);
    for (std::size_t c0 = 0; c0 <= n; ++c0)
        for (std::size_t c1 = c0; c1 <= n; ++c1) {
            std::vector<std::uint32_t> want;
            for (std::size_t c = c0; c < c1; ++c)
                want.insert(want.end(), f.curves[c].edges.begin(), f.curves[c].edges.end());
            const std::span<const std::uint32_t> got = f.curves.edges_of(c0, c1);
            ASSERT_EQ(std::vector<std::uint32_t>(got.begin(), got.end()), want) << c0 << " " << c1;
        }
}
