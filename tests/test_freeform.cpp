// Freeform surfaces and Elber's line art (src/freeform/): exact evaluation against finite
// differences and known curvatures, the .bpt reader, tessellation into the mesh pipeline, uniform
// coverage, stroke growth, cone coverings against the paper's Table 1, cone culling against a
// brute-force scan, stroke visibility against analytic ray tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include <glm/geometric.hpp>

#include "core/error.hpp"
#include "freeform/cones.hpp"
#include "freeform/lineart.hpp"
#include "freeform/strokes.hpp"
#include "freeform/surface.hpp"
#include "freeform/tessellate.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"

using namespace inkline;
using namespace inkline::freeform;

namespace {

const std::string kTeapot = std::string(INKLINE_EXAMPLES_DIR) + "/teapot.bpt";
const std::string kWavy = std::string(INKLINE_EXAMPLES_DIR) + "/wavy_torus.json";

double rel(const glm::dvec3& a, const glm::dvec3& b, double scale) { return glm::length(a - b) / scale; }

// Central differences of eval() against the exact partials, at interior random parameters.
void expect_partials(const Surface& s, int n, double tol) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(0.05, 0.95);
    const double h = 1e-5;
    for (int k = 0; k < n; ++k) {
        const double u = s.u_range[0] + U(rng) * (s.u_range[1] - s.u_range[0]);
        const double v = s.v_range[0] + U(rng) * (s.v_range[1] - s.v_range[0]);
        const SurfacePoint p = s.eval(u, v);
        const double scale = 1.0 + glm::length(p.su) + glm::length(p.sv);
        const SurfacePoint pu0 = s.eval(u - h, v), pu1 = s.eval(u + h, v), pv0 = s.eval(u, v - h), pv1 = s.eval(u, v + h);
        EXPECT_LT(rel(p.su, (pu1.p - pu0.p) / (2 * h), scale), tol) << s.name() << " S_u at " << u << "," << v;
        EXPECT_LT(rel(p.sv, (pv1.p - pv0.p) / (2 * h), scale), tol) << s.name() << " S_v";
        EXPECT_LT(rel(p.suu, (pu1.su - pu0.su) / (2 * h), scale), tol) << s.name() << " S_uu";
        EXPECT_LT(rel(p.suv, (pv1.su - pv0.su) / (2 * h), scale), tol) << s.name() << " S_uv";
        EXPECT_LT(rel(p.suv, (pu1.sv - pu0.sv) / (2 * h), scale), tol) << s.name() << " S_vu";
        EXPECT_LT(rel(p.svv, (pv1.sv - pv0.sv) / (2 * h), scale), tol) << s.name() << " S_vv";
    }
}

// Normal curvature along a parameter direction by finite differences of positions only.
double fd_normal_curvature(const Surface& s, glm::dvec2 uv, glm::dvec2 d) {
    const double h = 1e-4;
    const glm::dvec3 a = s.eval(uv.x - h * d.x, uv.y - h * d.y).p, b = s.eval(uv.x, uv.y).p,
                     c = s.eval(uv.x + h * d.x, uv.y + h * d.y).p;
    const glm::dvec3 c1 = (c - a) / (2 * h), c2 = (c - 2.0 * b + a) / (h * h);
    return glm::dot(c2, s.normal(uv.x, uv.y)) / glm::dot(c1, c1);
}

}  // namespace

TEST(FreeformSurface, BezierPartialsMatchFiniteDifferences) {
    const SurfaceList teapot = load_bpt(kTeapot);
    ASSERT_EQ(teapot.size(), 32u);
    for (const auto& s : teapot) expect_partials(*s, 5, 1e-6);
}

TEST(FreeformSurface, PrimitivePartialsMatchFiniteDifferences) {
    expect_partials(Sphere({1, 2, 3}, 2.0), 20, 1e-6);
    expect_partials(Torus({0, 0, 0}, 2.0, 0.5), 20, 1e-6);
    expect_partials(Torus({0, 1, 0}, 1.0, 0.38, 0.3, 6), 20, 1e-6);
}

TEST(FreeformSurface, BezierInterpolatesCornersAndIsExactOnAPlane) {
    const SurfaceList teapot = load_bpt(kTeapot);
    const auto& b = dynamic_cast<const BezierPatch&>(*teapot[5]);
    EXPECT_EQ(b.eval(0, 0).p, b.control_points()[0]);
    EXPECT_EQ(b.eval(1, 1).p, b.control_points()[15]);
    // A bilinear patch on the plane z = 0 spanned evenly: S = (u, v, 0), flat.
    BezierPatch flat(1, 1, {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}});
    const Curvature c = flat.curvature(0.3, 0.6);
    ASSERT_TRUE(c.valid);
    EXPECT_NEAR(c.k1, 0.0, 1e-15);
    EXPECT_NEAR(c.k2, 0.0, 1e-15);
    EXPECT_NEAR(c.n.z, 1.0, 1e-15);
}

TEST(FreeformSurface, SphereCurvatureIsMinusOneOverR) {
    const Sphere s({1, -1, 2}, 2.5);
    for (double u : {0.3, 1.0, 2.0, 2.9})
        for (double v : {0.0, 1.0, 4.0}) {
            const Curvature c = s.curvature(u, v);
            ASSERT_TRUE(c.valid);
            EXPECT_NEAR(c.k1, -1 / 2.5, 1e-12);
            EXPECT_NEAR(c.k2, -1 / 2.5, 1e-12);
            // Outward unit normal.
            EXPECT_NEAR(glm::dot(c.n, (s.eval(u, v).p - s.center) / 2.5), 1.0, 1e-12);
            EXPECT_NEAR(glm::dot(c.d1, c.d2), 0.0, 1e-12);
        }
    EXPECT_FALSE(s.curvature(0.0, 1.0).valid);  // the pole: S_u x S_v = 0
}

TEST(FreeformSurface, TorusCurvatureMatchesKnownFormulas) {
    const double R = 2.0, r = 0.5;
    const Torus t({0, 0, 0}, R, r);
    for (double u : {0.1, 1.7, 4.0})
        for (double v : {0.2, 1.4, 2.5, 3.3, 5.0}) {
            const Curvature c = t.curvature(u, v);
            ASSERT_TRUE(c.valid);
            // Outward normal: the tube's curvature is -1/r, the ring's -cos v / (R + r cos v).
            const double kt = -1.0 / r, kr = -std::cos(v) / (R + r * std::cos(v));
            EXPECT_NEAR(c.k1, std::max(kt, kr), 1e-12);
            EXPECT_NEAR(c.k2, std::min(kt, kr), 1e-12);
            // The tube's direction is the meridian, S_v (u constant).
            const glm::dvec2 tube = kt < kr ? c.uv2 : c.uv1;
            EXPECT_NEAR(tube.x, 0.0, 1e-9);
            const glm::dvec3 p = t.eval(u, v).p, axis_pt = R * glm::dvec3(std::cos(u), std::sin(u), 0);
            EXPECT_NEAR(glm::dot(c.n, (p - axis_pt) / r), 1.0, 1e-12);
        }
}

TEST(FreeformSurface, PrincipalCurvaturesAreExtremeNormalCurvatures) {
    // Wavy torus and a teapot patch: k1, k2 equal the normal curvatures along their own directions
    // (finite differences of positions) and bound those of every other direction.
    const SurfaceList teapot = load_bpt(kTeapot);
    const Torus wavy({0, 0, 0}, 1.0, 0.38, 0.3, 6);
    std::vector<const Surface*> list{&wavy, teapot[4].get(), teapot[13].get()};
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(0.1, 0.9);
    for (const Surface* s : list)
        for (int k = 0; k < 10; ++k) {
            const glm::dvec2 uv(s->u_range[0] + U(rng) * (s->u_range[1] - s->u_range[0]),
                                s->v_range[0] + U(rng) * (s->v_range[1] - s->v_range[0]));
            const Curvature c = s->curvature(uv.x, uv.y);
            ASSERT_TRUE(c.valid);
            const double scale = 1.0 + std::abs(c.k1) + std::abs(c.k2);
            EXPECT_NEAR(fd_normal_curvature(*s, uv, c.uv1), c.k1, 1e-4 * scale) << s->name();
            EXPECT_NEAR(fd_normal_curvature(*s, uv, c.uv2), c.k2, 1e-4 * scale) << s->name();
            for (double a = 0; a < M_PI; a += 0.3) {
                const double kn = fd_normal_curvature(*s, uv, {std::cos(a), std::sin(a)});
                EXPECT_LE(kn, c.k1 + 1e-4 * scale);
                EXPECT_GE(kn, c.k2 - 1e-4 * scale);
            }
        }
}

TEST(FreeformSurface, NurbsSphereIsExact) {
    // examples/nurbs_sphere.json: the classic rational quadratic sphere (9 x 5 control points).
    SurfaceList list = load_surfaces(std::string(INKLINE_EXAMPLES_DIR) + "/nurbs_sphere.json");
    ASSERT_EQ(list.size(), 1u);
    const Surface& s = *list[0];
    EXPECT_EQ(s.name(), "nurbs");
    expect_partials(s, 20, 1e-6);
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> U(0.01, 0.99);
    for (int k = 0; k < 200; ++k) {
        const double u = U(rng), v = U(rng);
        const SurfacePoint p = s.eval(u, v);
        EXPECT_NEAR(glm::length(p.p), 1.0, 1e-14);
        const Curvature c = s.curvature(u, v);
        ASSERT_TRUE(c.valid);
        EXPECT_NEAR(c.k1, -1.0, 1e-9);
        EXPECT_NEAR(c.k2, -1.0, 1e-9);
        EXPECT_NEAR(glm::dot(c.n, p.p), 1.0, 1e-12);  // outward
    }
    EXPECT_NEAR(glm::length(s.eval(1.0, 1.0).p), 1.0, 1e-14);  // the domain's end evaluates
    EXPECT_NEAR(total_area(list), 4 * M_PI, 1e-3);
    // Tessellated, welded at the poles and the seam: a closed sphere.
    const Tessellation t = tessellate(list, {}, "nurbs_sphere.json");
    EXPECT_TRUE(build_topology(t.mesh).closed);
}

TEST(FreeformSurface, BezierAsNurbsIsTheSameSurface) {
    const SurfaceList teapot = load_bpt(kTeapot);
    const auto& b = dynamic_cast<const BezierPatch&>(*teapot[9]);
    const std::vector<double> K{0, 0, 0, 0, 1, 1, 1, 1};
    NurbsSurface n(3, 3, K, K, 4, 4, b.control_points(), std::vector<double>(16, 1.0));
    for (double u : {0.0, 0.2, 0.7, 1.0})
        for (double v : {0.0, 0.45, 1.0}) {
            const SurfacePoint a = b.eval(u, v), c = n.eval(u, v);
            EXPECT_LT(glm::length(a.p - c.p), 1e-13);
            EXPECT_LT(glm::length(a.su - c.su), 1e-12);
            EXPECT_LT(glm::length(a.svv - c.svv), 1e-11);
            EXPECT_LT(glm::length(a.suv - c.suv), 1e-11);
        }
    EXPECT_THROW(NurbsSurface(3, 3, {0, 0, 0, 0, 1, 1, 0.5, 1}, K, 4, 4, b.control_points(), std::vector<double>(16, 1.0)), Error);
    EXPECT_THROW(NurbsSurface(3, 3, K, K, 4, 4, b.control_points(), std::vector<double>(16, 0.0)), Error);
    EXPECT_THROW(parse_surfaces_json(R"({"surfaces": [{"type": "nurbs", "degree": [1, 1], "count": [2, 2],
        "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[0,1,0],[1,0,0]]}]})", "x.json"), Error);
    const SurfaceList ok = parse_surfaces_json(R"({"surfaces": [{"type": "nurbs", "degree": [1, 1], "count": [2, 2],
        "knots_u": [0, 0, 1, 1], "knots_v": [0, 0, 1, 1], "points": [[0,0,0],[0,1,0],[1,0,0],[1,1,0,2]]}]})", "x.json");
    EXPECT_EQ(ok.size(), 1u);
}

TEST(FreeformSurface, BptReaderRefusesMalformedInput) {
    auto msg = [](const std::string& text) {
        try {
            parse_bpt(text, "bad.bpt");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(msg("").find("bad.bpt: expected the number of patches"), std::string::npos);
    EXPECT_NE(msg("1\n3 3\n0 0 0\n").find("patch 1: expected 16 control points, got 1"), std::string::npos);
    EXPECT_NE(msg("1\n0 3\n").find("degrees must be between 1 and 15"), std::string::npos);
    std::string ok = "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n1 1 0\n";
    EXPECT_EQ(msg(ok), "accepted");
    EXPECT_NE(msg(ok + "7\n").find("unexpected data"), std::string::npos);
    EXPECT_NE(msg("1\n1 1\n0 0 0\n0 1 0\n1 0 x\n1 1 0\n").find("control point 3 is not three numbers"), std::string::npos);
    EXPECT_NE(msg("1\n1 1\n0 0 0\n0 1 0\n1 0 nan\n1 1 0\n").find("NaN"), std::string::npos);
    EXPECT_THROW(load_bpt("/nonexistent/x.bpt"), Error);
}

TEST(FreeformSurface, JsonReaderBuildsPrimitivesAndRefusesBadOnes) {
    const SurfaceList w = load_surfaces(kWavy);
    ASSERT_EQ(w.size(), 1u);
    EXPECT_EQ(w[0]->name(), "wavy_torus");
    const SurfaceList s = parse_surfaces_json(
        R"({"surfaces": [{"type": "sphere", "radius": 2}, {"type": "bezier", "degree": [1, 1],
            "points": [[0,0,0],[0,1,0],[1,0,0],[1,1,0]]}], "transparent": [1]})", "x.json");
    ASSERT_EQ(s.size(), 2u);
    EXPECT_FALSE(s[0]->transparent);
    EXPECT_TRUE(s[1]->transparent);
    EXPECT_THROW(parse_surfaces_json(R"({"surfaces": [{"type": "cube"}]})", "x.json"), Error);
    EXPECT_THROW(parse_surfaces_json(R"({"surfaces": [{"type": "sphere", "radius": -1}]})", "x.json"), Error);
    EXPECT_THROW(parse_surfaces_json(R"({"surfaces": [{"type": "torus", "R": 1, "r": 2}]})", "x.json"), Error);
    EXPECT_THROW(parse_surfaces_json("{", "x.json"), Error);
}

TEST(FreeformTessellation, TeapotWeldsIntoTheMeshPipeline) {
    SurfaceList teapot = load_bpt(kTeapot);
    const Tessellation t = tessellate(teapot, {}, "teapot.bpt");
    EXPECT_GT(t.welded, 0u);
    EXPECT_GT(t.dropped, 0u);  // collapsed cells at the lid's, the bottom's poles
    EXPECT_EQ(t.mesh.triangles.size() + t.dropped, 32u * 16 * 16 * 2);
    // Normals point outward (Newell's patches come inward: all 32 are turned): away from the axis
    // on the body (patches 4-11 in Newell's order) and on the outside of the rim's rolled lip
    // (0-3, u = 0.9; its inside, u = 0.1, faces the axis), up on the lid (24-27) and the knob's
    // top (20-23, u = 0.1), down on the bottom (28-31), sideways on the handle (12-15).
    EXPECT_EQ(t.flipped_surfaces, 32u);
    for (std::size_t s = 0; s < 32; ++s) {
        auto radial = [&](double u) {
            const glm::dvec3 p = teapot[s]->eval(u, 0.5).p;
            return glm::dot(teapot[s]->normal(u, 0.5), glm::normalize(glm::dvec3(p.x, p.y, 0)));
        };
        const double nz = teapot[s]->normal(0.5, 0.5).z;
        if (s < 4) {
            EXPECT_GT(radial(0.9), 0.5) << "patch " << s;
            EXPECT_LT(radial(0.1), -0.5) << "patch " << s;
        } else if (s < 12) {
            EXPECT_GT(radial(0.5), 0.5) << "patch " << s;
        } else if (s < 16) {
            const glm::dvec3 p = teapot[s]->eval(0.5, 0.5).p;
            EXPECT_GT(teapot[s]->normal(0.5, 0.5).y * p.y, 0.0) << "patch " << s;
        } else if (s >= 20 && s < 24) {
            EXPECT_GT(teapot[s]->normal(0.1, 0.5).z, 0.9) << "patch " << s;
        } else if (s >= 24 && s < 28) {
            EXPECT_GT(nz, 0.9) << "patch " << s;
        } else if (s >= 28) {
            EXPECT_LT(nz, -0.9) << "patch " << s;
        }
    }
    // Every surface's normal agrees with the orientation of its triangles.
    Model model(t.mesh);
    std::uint32_t f0, f1;
    for (std::size_t s = 0; s < 32; ++s) {
        const glm::dvec2 uv(0.37, 0.61);
        const glm::dvec3 p = t.locate(teapot, s, uv, f0, f1);
        ASSERT_NE(f0, UINT32_MAX);
        EXPECT_GT(glm::dot(model.topology().face_normal(f0), teapot[s]->normal(uv.x, uv.y)), 0.9) << "patch " << s;
        EXPECT_LT(glm::length(p - teapot[s]->eval(uv.x, uv.y).p), 0.01);  // chordal error of a 16x16 grid
    }
    // Silhouettes and borders of the teapot through the unchanged pipeline.
    const View v = render_view(model, test::framed_camera(model.topology().bounds, 512));
    std::size_t sil = 0, border = 0;
    for (const auto& p : v.drawing.pieces) {
        sil += p.kind == LineKind::Silhouette && p.qi == 0;
        border += p.kind == LineKind::Border && p.qi == 0;
    }
    EXPECT_GT(sil, 0u);
    EXPECT_GT(border, 0u);  // the spout's open tip
}

TEST(FreeformTessellation, ClosedPrimitivesAreClosedAndOutward) {
    SurfaceList list;
    list.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1.0));
    list.push_back(std::make_unique<Torus>(glm::dvec3(4, 0, 0), 1.0, 0.38, 0.3, 6));
    const Tessellation t = tessellate(list, {}, "primitives");
    const MeshTopology topo = build_topology(t.mesh);
    EXPECT_TRUE(topo.closed);
    EXPECT_EQ(list[0]->sign, 1.0);
    EXPECT_EQ(list[1]->sign, 1.0);
    EXPECT_EQ(t.flipped_surfaces, 0u);
}

// Valid but huge input: the grids' size is checked before anything is evaluated, so 40,000
// patches (11.6 M grid points at 16 segments) or a NURBS of 256 x 256 knot spans (4097^2 grid
// points) are refused at once with one line naming the file, instead of gigabytes of mesh.
TEST(FreeformTessellation, RefusesGridsOfMillionsOfPointsBeforeEvaluating) {
    std::string bpt = "40000\n";
    for (int k = 0; k < 40000; ++k) {  // disjoint squares
        const std::string x0 = std::to_string(k), x1 = std::to_string(k) + ".5";
        bpt += "1 1\n" + x0 + " 0 0\n" + x0 + " 1 0\n" + x1 + " 0 0\n" + x1 + " 1 0\n";
    }
    SurfaceList patches = parse_bpt(bpt, "many.bpt");
    ASSERT_EQ(patches.size(), 40000u);
    std::string json = R"({"surfaces": [{"type": "nurbs", "degree": [1, 1], "count": [257, 257], "knots_u": [0)";
    std::string knots;
    for (int i = 0; i <= 257; ++i) knots += ", " + std::to_string(i);
    json += knots + R"(], "knots_v": [0)" + knots + R"(], "points": [)";
    for (int i = 0; i < 257 * 257; ++i) json += (i ? ",[" : "[") + std::to_string(i % 257) + "," + std::to_string(i / 257) + ",0]";
    json += "]}]}";
    SurfaceList nurbs = parse_surfaces_json(json, "fine.json");
    for (auto* list : {&patches, &nurbs}) {
        const std::string file = list == &patches ? "many.bpt" : "fine.json";
        try {
            tessellate(*list, {}, file);
            ADD_FAILURE() << file << " accepted";
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << m;
            EXPECT_NE(m.find("more than 9000000 grid points"), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    }
    // A lower resolution brings the patches under the limit (40,000 x 9 points).
    EXPECT_EQ(tessellate(patches, {2, 8}, "many.bpt").mesh.triangles.size(), 40000u * 8);
}

// Surfaces of absurd scale: a sphere of radius 1e300 has an infinite area, which made every
// share of the coverage NaN (cast to a count: undefined behaviour); one of radius 1e-300, or a
// patch whose corners lie on a line, has faces without a usable normal, whose NaN ray made Embree
// abort in the orientation vote. Found with the bpt/surfaces fuzz checks; the inputs are replayed
// by FuzzRegressions.BezierPatches and FuzzRegressions.SurfacesJson.
TEST(FreeformCoverage, InfiniteAreaGivesNoPointsAndDegenerateFacesNoVote) {
    SurfaceList huge;
    huge.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1e300));
    EXPECT_TRUE(cover(huge, 10, 1).empty());
    SurfaceList line = parse_bpt("1\n1 1\n0 0 0\n1 0 0\n2 0 0\n3 0 0\n", "line.bpt");
    const Tessellation t = tessellate(line, {2, 8}, "line.bpt");  // a flat strip: kept, orientation as given
    EXPECT_EQ(t.mesh.triangles.size(), 8u);
    EXPECT_EQ(line[0]->sign, 1.0);
    SurfaceList tiny;
    tiny.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1e-300));
    try {
        tessellate(tiny, {2, 8}, "tiny.json");
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("tiny.json: ", 0), 0u) << e.what();
    }
}

// Welding counts cells from the bounding box's corner: a torus centred 8.9e23 from the origin
// (found by fuzz/run.sh surfaces; fuzz/regressions/surfaces-far-center) overflowed the 64-bit
// cell index (undefined behaviour); one at 1e6 welds exactly like the one at the origin.
TEST(FreeformTessellation, FarFromTheOriginWeldsTheSame) {
    auto torus_at = [](glm::dvec3 c) {
        SurfaceList l;
        l.push_back(std::make_unique<Torus>(c, 1.0, 0.38, 0.3, 6));
        return l;
    };
    SurfaceList near = torus_at(glm::dvec3(0)), far = torus_at({0, 0, 1e6}), farther = torus_at({0, 0, 8.9e23});
    const Tessellation a = tessellate(near, {2, 16}, "near.json"), b = tessellate(far, {2, 16}, "far.json");
    EXPECT_EQ(a.mesh.positions.size(), b.mesh.positions.size());
    EXPECT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
    EXPECT_EQ(a.welded, b.welded);
    try {  // all of it within one rounding step: refused by the mesh checks, or collapsed
        tessellate(farther, {2, 16}, "farther.json");
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("farther.json: ", 0), 0u) << e.what();
    }
    SurfaceList huge;
    huge.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1e300));
    EXPECT_THROW(tessellate(huge, {2, 8}, "huge.json"), Error);
}

TEST(FreeformCoverage, SphereHasEqualCountsInEqualAreas) {
    SurfaceList list;
    list.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1.0));
    const std::size_t r = 40000;
    const auto pts = cover(list, r, 11);
    EXPECT_NEAR(double(pts.size()), double(r), 0.01 * r);
    // Archimedes: slabs of equal height have equal area; so do sectors of longitude.
    std::vector<int> slab(10, 0), sector(8, 0);
    for (const auto& s : pts) {
        const glm::dvec3 p = list[0]->eval(s.uv.x, s.uv.y).p;
        slab[std::min(9, int((p.z + 1.0) / 0.2))]++;
        sector[std::min(7, int((std::atan2(p.y, p.x) + M_PI) / (M_PI / 4)))]++;
    }
    for (int c : slab) EXPECT_NEAR(c, pts.size() / 10.0, 0.05 * pts.size() / 10.0);
    for (int c : sector) EXPECT_NEAR(c, pts.size() / 8.0, 0.05 * pts.size() / 8.0);
    // Deterministic for a seed, different for another.
    const auto again = cover(list, r, 11), other = cover(list, r, 12);
    ASSERT_EQ(again.size(), pts.size());
    EXPECT_EQ(again[123].uv, pts[123].uv);
    EXPECT_NE(other[123].uv, pts[123].uv);
}

TEST(FreeformCoverage, TorusOuterHalfGetsItsShareOfArea) {
    // Area element r (R + r cos v): the outer half (cos v > 0) holds (pi R + 2 r) / (2 pi R).
    SurfaceList list;
    const double R = 1.0, r = 0.6;
    list.push_back(std::make_unique<Torus>(glm::dvec3(0), R, r));
    const auto pts = cover(list, 50000, 5);
    std::size_t outer = 0;
    for (const auto& s : pts) outer += std::cos(s.uv.y) > 0;
    EXPECT_NEAR(double(outer) / pts.size(), (M_PI * R + 2 * r) / (2 * M_PI * R), 0.01);
    EXPECT_NEAR(total_area(list), 4 * M_PI * M_PI * R * r, 1e-3 * 4 * M_PI * M_PI * R * r);
}

TEST(FreeformCoverage, TeapotPointsPerAreaAreUniformOverCells) {
    // Points per unit area over many 3D cells, against the tessellation's area in each cell.
    SurfaceList teapot = load_bpt(kTeapot);
    const Tessellation t = tessellate(teapot, {64, 128}, "teapot.bpt");
    const std::size_t r = 100000;
    const auto pts = cover(teapot, r, 1);
    const double cell = 0.75;
    auto key = [&](const glm::dvec3& p) {
        return std::make_tuple(int(std::floor(p.x / cell)), int(std::floor(p.y / cell)), int(std::floor(p.z / cell)));
    };
    std::map<std::tuple<int, int, int>, double> area, count;
    double total = 0.0;
    for (const auto& tr : t.mesh.triangles) {
        const glm::dvec3 a = t.mesh.positions[tr[0]], b = t.mesh.positions[tr[1]], c = t.mesh.positions[tr[2]];
        const double A = 0.5 * glm::length(glm::cross(b - a, c - a));
        area[key((a + b + c) / 3.0)] += A;
        total += A;
    }
    for (const auto& s : pts) count[key(teapot[s.surface]->eval(s.uv.x, s.uv.y).p)] += 1;
    int checked = 0;
    for (const auto& [k, A] : area) {
        const double expected = double(pts.size()) * A / total;
        if (expected < 400) continue;  // cells the surface barely touches
        ++checked;
        EXPECT_NEAR(count[k], expected, 0.1 * expected);
    }
    EXPECT_GT(checked, 20);
}

TEST(FreeformStrokes, StayOnTheSurfaceAndWithinTheLimits) {
    SurfaceList teapot = load_bpt(kTeapot);
    tessellate(teapot, {}, "teapot.bpt");  // outward signs
    const auto pts = cover(teapot, 600, 3);
    for (StrokeField f : {StrokeField::Iso, StrokeField::Curvature, StrokeField::Isophote}) {
        StrokeOptions o;
        o.field = f;
        o.length = 0.4;
        o.isophote_direction = glm::normalize(glm::dvec3(1, 0.6, 1.4));
        const auto strokes = grow_strokes(teapot, pts, o);
        EXPECT_GT(strokes.size(), pts.size() * 9 / 10);
        std::size_t long_ones = 0;
        for (const Stroke& st : strokes) {
            const Surface& s = *teapot[st.surface];
            EXPECT_LE(st.length(), o.length * 1.0001);
            long_ones += st.length() > 0.9 * o.length;
            for (std::size_t k = 0; k < st.points.size(); ++k) {
                EXPECT_LT(glm::length(st.points[k] - s.eval(st.uv[k].x, st.uv[k].y).p), 1e-12);
                EXPECT_GE(st.uv[k].x, 0.0);
                EXPECT_LE(st.uv[k].x, 1.0);
                EXPECT_GE(st.uv[k].y, 0.0);
                EXPECT_LE(st.uv[k].y, 1.0);
            }
            // A short stroke ended at the patch boundary or at a singularity of the field.
            if (f == StrokeField::Iso && st.length() < 0.99 * o.length / 2) {
                const glm::dvec2 a = st.uv.front(), b = st.uv.back();
                auto on_edge = [](glm::dvec2 p) { return p.x == 0 || p.x == 1 || p.y == 0 || p.y == 1; };
                EXPECT_TRUE(on_edge(a) || on_edge(b));
            }
            // The field: iso strokes keep one parameter, isophotes keep N . D.
            if (f == StrokeField::Iso) {
                const bool iso_u = st.uv.front().x == st.uv.back().x, iso_v = st.uv.front().y == st.uv.back().y;
                EXPECT_TRUE(iso_u || iso_v);
            }
            if (f == StrokeField::Isophote) {
                for (std::size_t k = 0; k < st.points.size(); ++k)
                    EXPECT_NEAR(glm::dot(s.normal(st.uv[k].x, st.uv[k].y), o.isophote_direction),
                                glm::dot(st.normal, o.isophote_direction), 0.02);
            }
        }
        EXPECT_GT(long_ones, strokes.size() / 3);
    }
}

TEST(FreeformStrokes, PrescribedDirectionFollowsItsProjection) {
    // On a sphere around the origin, the field "+z projected onto the tangent plane" is the
    // meridians: every stroke keeps its longitude.
    SurfaceList list;
    list.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1.0));
    StrokeOptions o;
    o.field = StrokeField::Direction;
    o.direction = {0, 0, 1};
    o.length = 0.5;
    const auto strokes = grow_strokes(list, cover(list, 300, 4), o);
    ASSERT_GT(strokes.size(), 280u);
    for (const Stroke& st : strokes) {
        EXPECT_GT(st.length(), 0.2);
        for (const auto& uv : st.uv) EXPECT_NEAR(std::remainder(uv.y - st.seed_uv.y, 2 * M_PI), 0.0, 1e-6);
    }
}

TEST(FreeformCoverage, MeshPointsFollowTriangleArea) {
    // A fine UV sphere: its triangles are far from equal in area; counts per equal-area z slab are.
    SurfaceList list;
    list.push_back(std::make_unique<Sphere>(glm::dvec3(0), 1.0));
    const Tessellation t = tessellate(list, {16, 256}, "sphere");
    const auto pts = cover_mesh(t.mesh.positions, t.mesh.triangles, 40000, 3);
    EXPECT_NEAR(double(pts.size()), 40000.0, 400.0);
    std::vector<int> slab(10, 0);
    for (const auto& s : pts) {
        const auto& tr = t.mesh.triangles[s.face];
        // Inside its triangle: the barycentric weights of the point are non-negative.
        const glm::dvec3 a = t.mesh.positions[tr[0]], b = t.mesh.positions[tr[1]], c = t.mesh.positions[tr[2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        EXPECT_GE(glm::dot(glm::cross(b - a, s.point - a), n), -1e-12);
        EXPECT_GE(glm::dot(glm::cross(c - b, s.point - b), n), -1e-12);
        EXPECT_GE(glm::dot(glm::cross(a - c, s.point - c), n), -1e-12);
        slab[std::min(9, int((s.point.z + 1.0) / 0.2))]++;
    }
    for (int c : slab) EXPECT_NEAR(c, pts.size() / 10.0, 0.05 * pts.size() / 10.0);
}

TEST(FreeformStrokes, LinesOfCurvatureOnATorusAreParallelsAndMeridians) {
    SurfaceList list;
    list.push_back(std::make_unique<Torus>(glm::dvec3(0), 2.0, 0.5));
    const auto pts = cover(list, 200, 9);
    StrokeOptions o;
    o.field = StrokeField::Curvature;
    o.length = 1.0;
    const auto strokes = grow_strokes(list, pts, o);
    ASSERT_GT(strokes.size(), 190u);
    for (const Stroke& st : strokes) {
        bool u_const = true, v_const = true;
        for (const auto& uv : st.uv) {
            u_const &= std::abs(std::remainder(uv.x - st.seed_uv.x, 2 * M_PI)) < 1e-6;
            v_const &= std::abs(std::remainder(uv.y - st.seed_uv.y, 2 * M_PI)) < 1e-6;
        }
        EXPECT_TRUE(u_const || v_const);
        EXPECT_NEAR(st.length(), o.length, 1e-9);  // no boundary on a torus: the limit stops it
    }
}

TEST(FreeformCones, CoveringAnglesAgainstThePapersTable) {
    // Table 1 of the paper (optimal coverings after Hardin, Sloane and Smith).
    const std::vector<std::pair<int, double>> table{{4, 70.5287794}, {20, 29.6230958}, {50, 18.3000226},
                                                    {100, 12.9360973}, {130, 11.3165625}};
    std::mt19937_64 rng(5);
    std::normal_distribution<double> N(0.0, 1.0);
    for (const auto& [m, paper] : table) {
        const auto axes = cone_axes(m);
        ASSERT_EQ(axes.size(), std::size_t(m));
        const double alpha = covering_angle(axes);
        const double deg = alpha * 180 / M_PI;
        // Never better than the optimum; ours within 2% of it (measured 0.0%, 1.4%, 0.4%, 1.1%,
        // 1.4%: a local optimisation, the paper's are Hardin-Sloane-Smith's best known), the
        // tetrahedron (m = 4) exactly. The sampled estimate equals the Delaunay circumradius.
        EXPECT_GE(deg, paper - 1e-3) << "m = " << m;
        EXPECT_LE(deg, paper * 1.02) << "m = " << m;
        EXPECT_NEAR(alpha, hull_covering_angle(axes), 1e-9) << "m = " << m;
        if (m == 4) {
            EXPECT_NEAR(deg, paper, 1e-3);
        }
        // Every direction is within alpha of an axis (independent random directions).
        for (int k = 0; k < 20000; ++k) {
            const glm::dvec3 d = glm::normalize(glm::dvec3(N(rng), N(rng), N(rng)));
            double best = -1;
            for (const auto& a : axes) best = std::max(best, glm::dot(a, d));
            ASSERT_GE(best, std::cos(alpha) - 1e-12) << "m = " << m;
        }
        std::printf("m = %d: covering angle %.4f deg (paper %.4f), redundancy %.4f\n", m, deg, paper,
                    m * (1 - std::cos(alpha)) / 2);
    }
}

TEST(FreeformCones, BucketsHoldEveryNormalOnceOrRedundantly) {
    const auto normals = fibonacci_sphere(20000);
    const auto axes = cone_axes(50);
    const double alpha = covering_angle(axes);
    ConeBuckets red(axes, alpha, normals, normals, BucketMode::Redundant);
    ConeBuckets exc(axes, alpha, normals, normals, BucketMode::Exclusive);
    std::vector<int> in_red(normals.size(), 0), in_exc(normals.size(), 0);
    for (std::size_t l = 0; l < axes.size(); ++l) {
        for (auto i : red.bucket(l)) {
            ++in_red[i];
            EXPECT_GE(glm::dot(normals[i], axes[l]), std::cos(alpha) - 1e-12);
        }
        for (auto i : exc.bucket(l)) ++in_exc[i];
        EXPECT_LE(red.radius(l), alpha + 1e-12);
    }
    for (std::size_t i = 0; i < normals.size(); ++i) {
        EXPECT_GE(in_red[i], 1);
        EXPECT_EQ(in_exc[i], 1);
    }
    // Redundancy of uniform normals: close to the caps' total area over the sphere's (eq. 3).
    const double expected = 50 * (1 - std::cos(alpha)) / 2;
    EXPECT_NEAR(double(red.entries()) / normals.size(), expected, 0.02 * expected);
    EXPECT_EQ(exc.entries(), normals.size());
}

TEST(FreeformCones, CullingNeverDropsAStrokeTheShaderDraws) {
    // Stroke normals of the teapot and of a sphere; random views, lights and shaders; both bucket
    // modes; closed and open: the cones visited give exactly the strokes of a scan of all strokes.
    SurfaceList teapot = load_bpt(kTeapot);
    tessellate(teapot, {}, "teapot.bpt");
    std::vector<glm::dvec3> normals, seeds;
    for (const auto& s : cover(teapot, 20000, 2)) {
        const SurfacePoint p = teapot[s.surface]->eval(s.uv.x, s.uv.y);
        const glm::dvec3 n = unit_normal(p, teapot[s.surface]->sign);
        if (glm::length(n) < 0.5) continue;
        normals.push_back(n);
        seeds.push_back(p.p);
    }
    std::mt19937_64 rng(17);
    std::normal_distribution<double> N(0.0, 1.0);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto dir = [&] { return glm::normalize(glm::dvec3(N(rng), N(rng), N(rng))); };
    std::size_t culled = 0, visited = 0;
    for (int m : {20, 50, 130}) {
        const auto axes = cone_axes(m);
        const double alpha = covering_angle(axes);
        for (BucketMode mode : {BucketMode::Redundant, BucketMode::Exclusive}) {
            ConeBuckets b(axes, alpha, normals, seeds, mode);
            for (int k = 0; k < 30; ++k) {
                Shader sh;
                sh.kind = ShaderKind(k % 3);
                sh.lights = {dir(), dir()};
                sh.c = 1 + 3 * U(rng);
                sh.tau_dif = 0.5 * U(rng);
                sh.d = 1 + 6 * U(rng);
                sh.tau_sil = 0.6 * U(rng);
                const bool ortho = k % 2;
                const glm::dvec3 eye = glm::dvec3(0.2, 0, 1.5) + (ortho ? 20.0 : 4.0 + 10 * U(rng)) * dir();
                const ViewQuery q = make_query(eye, glm::normalize(glm::dvec3(0.2, 0, 1.5) - eye), ortho,
                                               glm::dvec3(0.2, 0, 1.5), 3.5, k % 4 < 2);
                SelectStats st;
                auto fast = b.select(q, sh, true, &st);
                auto slow = select_all(normals, seeds, q, sh);
                auto uncut = b.select(q, sh, false);
                auto order = [](const Selected& x, const Selected& y) { return x.stroke < y.stroke; };
                std::sort(fast.begin(), fast.end(), order);
                std::sort(uncut.begin(), uncut.end(), order);
                ASSERT_EQ(fast.size(), slow.size()) << "m " << m << " view " << k;
                ASSERT_EQ(uncut.size(), slow.size());
                for (std::size_t i = 0; i < slow.size(); ++i) {
                    EXPECT_EQ(fast[i].stroke, slow[i].stroke);
                    EXPECT_EQ(fast[i].psi, slow[i].psi);
                }
                culled += st.cones_culled_back + st.cones_culled_shader;
                visited += st.cones_visited;
                // Drawn once per frame although a stroke sits in several buckets.
                std::set<std::uint32_t> unique;
                for (const auto& s : fast) unique.insert(s.stroke);
                EXPECT_EQ(unique.size(), fast.size());
            }
        }
    }
    EXPECT_GT(culled, visited / 4);  // culling does cull
}

TEST(FreeformLineArt, StrokeVisibilityMatchesAnalyticRayTests) {
    // Two unit spheres, one in front of the other as seen from the eye; the ray service's layer
    // count at points of the tessellation against exact ray/sphere intersections. The front sphere
    // transparent: it hides nothing any more.
    for (bool transparent : {false, true}) {
        SurfaceList list;
        list.push_back(std::make_unique<Sphere>(glm::dvec3(0, 0, 0), 1.0));
        list.push_back(std::make_unique<Sphere>(glm::dvec3(0.6, 0.3, 2.5), 1.0));
        list[1]->transparent = transparent;
        LineArtOptions o;
        o.points = 100;
        o.tessellation.primitive_segments = 256;
        LineArt art(std::move(list), o, "spheres");
        const Camera cam = Camera::perspective({0.5, 0.4, 9}, {0, 0, 0}, {0, 1, 0}, 30, 512, 512);
        std::mt19937_64 rng(8);
        std::uniform_real_distribution<double> U(0.02, 0.98);
        int agree = 0, total = 0, hidden = 0;
        for (int k = 0; k < 2000; ++k) {
            const std::uint32_t s = k % 2;
            const Surface& S = *art.surfaces()[s];
            const glm::dvec2 uv(S.u_range[0] + U(rng) * (S.u_range[1] - S.u_range[0]),
                                S.v_range[0] + U(rng) * (S.v_range[1] - S.v_range[0]));
            const glm::dvec3 p = S.eval(uv.x, uv.y).p;
            int expected = 0;
            double margin = 1e9;  // distance of the line of sight from a tangency: skip near-ties
            for (std::uint32_t o2 = 0; o2 < 2; ++o2) {
                const auto& sp = dynamic_cast<const Sphere&>(*art.surfaces()[o2]);
                if (o2 == 1 && transparent) continue;
                const glm::dvec3 e = cam.eye(), d = p - e;
                const double len = glm::length(d);
                const double a = glm::dot(d, d), b = 2 * glm::dot(d, e - sp.center),
                             c = glm::dot(e - sp.center, e - sp.center) - sp.radius * sp.radius;
                const double disc = b * b - 4 * a * c;
                if (disc <= 0) continue;
                for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)}) {
                    const double dist = std::abs(1 - t) * len;  // from the point, along the sight line
                    if (o2 == s && dist < 1e-6) continue;        // the point itself
                    margin = std::min(margin, dist);
                    if (t > 0 && t < 1) ++expected;
                }
                margin = std::min(margin, std::sqrt(disc) / (2 * a) * len);  // grazing the sphere
            }
            if (margin < 0.02) continue;  // within the tessellation's chordal error of a tie
            ++total;
            const int got = art.layers_at(cam, s, uv);
            agree += got == expected;
            hidden += expected > 0;
            EXPECT_EQ(got, expected) << "surface " << s << " uv " << uv.x << "," << uv.y;
        }
        EXPECT_GT(total, 1000);
        EXPECT_GT(hidden, 300);
        EXPECT_EQ(agree, total);
    }
}

TEST(FreeformLineArt, DrawsPortionsOfSelectedStrokesAndClipsHiddenOnes) {
    LineArtOptions o;
    o.points = 3000;
    LineArt art(load_surfaces(kTeapot), o, "teapot.bpt");
    EXPECT_GT(art.stats().strokes, 2900u);
    const Camera cam = Camera::perspective({6, -8, 5}, {0, 0, 1.2}, {0, 0, 1}, 30, 800, 800);
    DrawOptions d;
    d.shader.kind = ShaderKind::Silhouette;
    DrawStats with, without;
    const auto vis = art.draw(cam, d, &with);
    d.visibility = false;
    const auto all = art.draw(cam, d, &without);
    EXPECT_EQ(with.selected, without.selected);
    EXPECT_GT(with.selected, 100u);
    auto length = [](const std::vector<Piece>& ps, int qi) {
        double l = 0;
        for (const auto& p : ps)
            if (p.qi == qi)
                for (std::size_t k = 1; k < p.points.size(); ++k) l += glm::length(p.points[k] - p.points[k - 1]);
        return l;
    };
    const double visible = length(vis, 0), hidden = length(vis, 1) + length(vis, 2) + length(vis, 3);
    EXPECT_GT(hidden, 0.0);  // the handle and spout hide parts of the body, the body parts of them
    EXPECT_NEAR(visible + hidden, length(all, 0), 0.05 * length(all, 0));  // clipping only splits
    for (const auto& p : vis) EXPECT_EQ(p.kind, LineKind::Freeform);
    // A shorter portion for a weaker shader value: the diffuse shader with a high threshold draws less.
    d.shader.kind = ShaderKind::Diffuse;
    d.shader.tau_dif = 0.0;
    const double full = length(art.draw(cam, d), 0);
    d.shader.tau_dif = 0.5;
    const double part = length(art.draw(cam, d), 0);
    EXPECT_LT(part, 0.7 * full);
    EXPECT_GT(part, 0.0);
}

// ---- The command line: inkline render SURFACES --strokes=... ----------------------------------

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include "cli_util.hpp"

namespace {
namespace fs = std::filesystem;

using CliRun = inkline_test::Result;
using inkline_test::slurp;

fs::path scratch_dir() { return inkline_test::scratch("inkline_ff_"); }

CliRun inkline_run(const std::string& args, const fs::path& dir) { return inkline_test::run_inkline("", "render " + args, dir); }
}  // namespace

TEST(FreeformCli, TeapotStrokesAndSilhouettesToJsonAndSvg) {
    const fs::path d = scratch_dir();
    const std::string cam = " --up=0,0,1 --eye=7,-9,5.5 --target=0.2,0,1.4 --size=600x600";
    for (const char* kind : {"iso", "curvature", "isophote"}) {
        const CliRun r = inkline_run(kTeapot + " -o " + (d / "t.json").string() + cam + " --strokes=" + kind +
                                      " --points=1500 --cones=20 --shader=combined",
                                  d);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.out.find("freeform: "), std::string::npos);
        const auto j = nlohmann::json::parse(slurp(d / "t.json"));
        std::map<std::string, int> kinds;
        for (const auto& p : j["polylines"]) {
            kinds[p["kind"].get<std::string>()]++;
            for (const auto& q : p["points"]) {
                EXPECT_GT(q[0].get<double>(), 0.0);
                EXPECT_LT(q[0].get<double>(), 600.0);
            }
        }
        EXPECT_GT(kinds["freeform"], 300) << kind;
        EXPECT_GT(kinds["silhouette"], 10) << kind;
        EXPECT_GT(kinds["border"], 0) << kind;  // the spout's tip, the rim's opening
    }
    const CliRun r = inkline_run(kTeapot + " -o " + (d / "t.svg").string() + cam + " --strokes=iso --points=500", d);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(slurp(d / "t.svg").find("freeform-visible"), std::string::npos);
    // Without --strokes: the tessellation's lines only.
    const CliRun plain = inkline_run(kTeapot + " -o " + (d / "p.json").string() + cam, d);
    ASSERT_EQ(plain.code, 0) << plain.err;
    EXPECT_EQ(slurp(d / "p.json").find("\"freeform\""), std::string::npos);
}

TEST(FreeformCli, BadInputIsOneLineNamingTheProblem) {
    const fs::path d = scratch_dir();
    // A value a line-art flag refuses is a usage error, as for every other flag: exit 2, one line.
    const std::pair<std::string, std::string> bad_values[] = {
        {" --strokes=spiral", "inkline: --strokes: unknown stroke kind 'spiral'"},
        {" --strokes=iso --shader=phong", "inkline: --shader: unknown shader 'phong'"},
        {" --strokes=iso --cones=0", "inkline: --cones: expected an integer from 1 to 100000\n"},
        {" --strokes=iso --tau-dif=3", "inkline: --tau-dif: expected a number in [0, 1]\n"},
        {" --strokes=iso --light=0,0,0", "inkline: --light: expected a non-zero direction, got '0,0,0'\n"},
        {" --strokes=iso --points=abc", "inkline: --points: expected a number, got 'abc'\n"},
        {" --cones=20", "inkline: --strokes: line-art flags given without --strokes\n"},
    };
    CliRun r;
    for (const auto& [flags, message] : bad_values) {
        r = inkline_run(kTeapot + " -o " + (d / "a.svg").string() + flags, d);
        EXPECT_EQ(r.code, 2) << flags;
        EXPECT_EQ(r.err.rfind(message, 0), 0u) << flags << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << flags;
    }
    r = inkline_run(kTeapot + " -o " + (d / "a.svg").string() + " --subdivide=1", d);
    EXPECT_EQ(r.code, 2);  // a flag that does not go with the model: a usage error
    EXPECT_NE(r.err.find("--subdivide: not for surface models"), std::string::npos) << r.err;
    std::ofstream(d / "bad.bpt") << "2\n3 3\n0 0 0\n";
    r = inkline_run((d / "bad.bpt").string() + " -o " + (d / "a.svg").string(), d);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("bad.bpt: patch 1: expected 16 control points, got 1"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
    r = inkline_run(test::mesh_path("fandisk") + " -o " + (d / "a.svg").string() + " --strokes=iso", d);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("need a .bpt or .json surface model"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(d / "a.svg"));
}
