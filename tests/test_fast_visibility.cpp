// The fast visibility (--visibility=fast, fast_visibility.hpp) against the exact method (appel):
// one error bound for every scene and mesh, the 0.5 % of visible length (missing + extra,
// 1 px; line_difference.hpp), from many cameras; the views it must hand to the exact method; and
// the command's refusals.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "random_camera.hpp"
#include "test_data.hpp"
#include "visibility/depth_buffer.hpp"
#include "visibility/line_difference.hpp"

namespace {

using namespace inkline;

constexpr double kBound = 0.005;  // share of the exact drawing's visible length that may differ

TriangleMesh merged(std::initializer_list<TriangleMesh> parts) {
    TriangleMesh m;
    for (const TriangleMesh& p : parts) {
        const auto base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), p.positions.begin(), p.positions.end());
        for (auto t : p.triangles) m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    return m;
}

struct Compared {
    LineDifference d;
    std::string fast_method;  // the drawing's stats.visibility
};

Compared compare(const Model& model, const Camera& camera, int buffer_px = FastVisibilityOptions{}.buffer_px) {
    ViewOptions o;
    o.exact_hidden = false;
    const View exact = render_view(model, camera, o);
    o.visibility = VisibilityMethod::Fast;
    o.fast.buffer_px = buffer_px;
    const View fast = render_view(model, camera, o);
    return {visible_difference(exact.drawing, fast.drawing), fast.drawing.stats.visibility};
}

// The scenes of the visibility oracle tests (test_visibility.cpp): spheres, tori, a sheet with a
// border, a box's creases; perspective and orthographic.
TEST(FastVisibility, OracleScenesWithinTheBound) {
    const TriangleMesh torus = make_torus({0, 0, 0}, {0, 0, 1}, 2.0, 0.5, 192, 96);
    const Model sphere_torus(merged({torus, make_sphere({1.6, 0.3, 2.5}, 1.0, 128, 64)}));
    const Model linked(merged({torus, make_torus({2.0, 0, 0}, {0, 1, 0}, 2.0, 0.5, 192, 96)}));
    const Model sheet(merged({make_sheet(1.5, 0.0, 24), make_sphere({0.8, -1.2, 0.3}, 0.9, 128, 64)}));
    const Model box(make_box({-1, -1, -1}, {1, 1, 1}));
    struct Case {
        const char* name;
        const Model* model;
        Camera camera;
    };
    const Case cases[] = {
        {"sphere before torus", &sphere_torus, Camera::perspective({0, 0, 12}, {0, 0, 0}, {0, 1, 0}, 35, 800, 800)},
        {"sphere before torus, ortho", &sphere_torus, Camera::orthographic({0, 0, 12}, {0, 0, 0}, {0, 1, 0}, 7.0, 800, 800)},
        {"linked tori", &linked, Camera::perspective({0, 0, 14}, {1, 0, 0}, {0, 1, 0}, 40, 800, 800)},
        {"linked tori, behind", &linked, Camera::perspective({0, 0, -14}, {1, 0, 0}, {0, 1, 0}, 40, 800, 800)},
        {"linked tori, oblique", &linked, Camera::perspective({6, 5, 9}, {1, 0, 0}, {0, 1, 0}, 40, 800, 800)},
        {"sheet over sphere", &sheet, Camera::perspective({3, 6, 8}, {0.3, -0.5, 0}, {0, 1, 0}, 40, 800, 800)},
        {"sheet edge-on", &sheet, Camera::perspective({9, 0.01, 0.5}, {0, -0.5, 0}, {0, 1, 0}, 40, 800, 800)},
        {"box", &box, Camera::perspective({4, 3, 5}, {0, 0, 0}, {0, 1, 0}, 40, 800, 800)},
    };
    for (const Case& c : cases) {
        const Compared r = compare(*c.model, c.camera);
        EXPECT_EQ(r.fast_method, "fast") << c.name;
        EXPECT_GT(r.d.reference_px, 100.0) << c.name;
        EXPECT_LE(r.d.missing_px + r.d.extra_px, kBound * r.d.reference_px)
            << c.name << ": missing " << r.d.missing_px << " extra " << r.d.extra_px << " of " << r.d.reference_px;
    }
}

// Geometry at the eye: a depth buffer cannot stand for it; the exact method takes the view, and
// the drawing is the exact one.
TEST(FastVisibility, CameraInsideGeometryTakesTheExactMethod) {
    const Model model(merged({make_box({-2, -2, -2}, {2, 2, 2}), make_sphere({0.7, 0.7, -0.5}, 0.5, 128, 64)}));
    // The walls around the eye cross the near plane (test_visibility.cpp's CameraInsideBox).
    const Camera cam = Camera::perspective({0, 0, 1}, {0.4, 0.4, -2}, {0, 1, 0}, 90, 800, 800);
    const Compared r = compare(model, cam);
    EXPECT_EQ(r.fast_method, "appel");
    EXPECT_EQ(r.d.missing_px + r.d.extra_px, 0.0);
    EXPECT_GT(r.d.reference_px, 100.0);
}

// The six meshes of the issue from many cameras: random ones (some near: the model overflows
// the image), orthographic ones and views along the axes (grazing: fandisk's flat faces edge-on).
class FastSixMeshes : public testing::TestWithParam<const char*> {};

TEST_P(FastSixMeshes, WithinTheBoundFromManyCameras) {
    const Model model = Model::load(test::mesh_path(GetParam()));
    const Bounds3& box = model.topology().bounds;
    const double R = box.half_diagonal();
    std::mt19937 rng(20261206u);
    std::vector<Camera> cams;
    for (int k = 0; k < 6; ++k) cams.push_back(random_camera(rng, box));
    for (int k = 0; k < 2; ++k) cams.push_back(random_camera(rng, box, 0.45, 0.1));  // near
    for (int k = 0; k < 2; ++k) {
        const Camera c = random_camera(rng, box);
        cams.push_back(Camera::orthographic(c.eye(), c.target(), c.up(), 2.2 * R, 1024, 1024));
    }
    for (const glm::dvec3 axis : {glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 0)})
        cams.push_back(Camera::perspective(box.center() + 4.0 * R * axis, box.center(),
                                           axis.y != 0.0 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0), 30, 1024, 1024));
    double reference = 0.0, differing = 0.0;
    for (std::size_t k = 0; k < cams.size(); ++k) {
        const Compared r = compare(model, cams[k]);
        reference += r.d.reference_px;
        differing += r.d.missing_px + r.d.extra_px;
        std::printf("[fast] %s camera %zu (%s): missing %.1f extra %.1f of %.0f px\n", GetParam(), k,
                    r.fast_method.c_str(), r.d.missing_px, r.d.extra_px, r.d.reference_px);
    }
    std::printf("[fast] %s: %.3f %% of %.0f px differ\n", GetParam(), 100.0 * differing / reference, reference);
    EXPECT_LE(differing, kBound * reference) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Meshes, FastSixMeshes,
                         testing::Values("fandisk", "bunny00", "knot1", "armadillo", "elephant", "ChineseDragon-10kv"),
                         [](const testing::TestParamInfo<const char*>& i) {
                             std::string s = i.param;
                             for (char& c : s)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return s;
                         });

// The depth buffer's fill (depth_raster.hpp): the AVX2 kernel writes exactly what the scalar
// kernel writes, key and face of every pixel, padding included, in scenes that reach the buffer's
// border, with a face larger than the image, at tiny and huge coordinates, and orthographic.
struct Filled {
    std::vector<float> keys;
    std::vector<std::uint32_t> faces;
    int width = 0, height = 0, stride = 0;
    std::size_t drawn = 0;
};

Filled fill(const MeshTopology& mesh, const Camera& camera, int buffer_px, RasterKernel kernel) {
    DepthBuffer b;
    b.set_kernel(kernel);
    b.reset(camera, buffer_px, {0.0, 0.0}, {double(camera.width()), double(camera.height())});
    EXPECT_TRUE(b.draw(mesh, nullptr));
    return {b.keys(), b.faces(), b.width(), b.height(), b.stride(), b.faces_drawn()};
}

TriangleMesh scaled(TriangleMesh m, double s) {
    for (auto& p : m.positions) p *= s;
    return m;
}

// The pixels each face owns (kNoFace: none), of the buffer's width x height.
std::vector<std::uint32_t> owners(const Filled& f) {
    std::vector<std::uint32_t> out;
    for (int j = 0; j < f.height; ++j)
        for (int i = 0; i < f.width; ++i) out.push_back(f.faces[std::size_t(j) * f.stride + i]);
    return out;
}

TEST(DepthRaster, VectorKernelWritesWhatTheScalarOneWrites) {
    const RasterKernel avx2 = raster_kernel_avx2();
    if (!avx2) GTEST_SKIP() << "no AVX2 kernel on this machine";
    const TriangleMesh spheres = merged({make_sphere({0, 0, 0}, 1.0, 96, 48), make_sphere({0.9, 0.4, 1.2}, 0.5, 64, 32),
                                         make_box({-3, -3, -1.5}, {3, 3, -1.2})});
    struct Case {
        const char* name;
        double scale;
        Camera camera;
        int buffer_px;
    };
    const Case cases[] = {
        {"framed", 1.0, Camera::perspective({0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 40, 640, 480), 384},
        // The box's faces are larger than the image and leave it on every side.
        {"beyond the border", 1.0, Camera::perspective({0.3, 0.2, 2.6}, {0.3, 0.2, 0}, {0, 1, 0}, 50, 300, 200), 301},
        {"tiny", 1e-6, Camera::perspective({0, 0, 6e-6}, {0, 0, 0}, {0, 1, 0}, 40, 640, 480), 384},
        {"huge", 1e6, Camera::perspective({0, 0, 6e6}, {0, 0, 0}, {0, 1, 0}, 40, 640, 480), 384},
        {"orthographic", 1.0, Camera::orthographic({2, 1, 6}, {0, 0, 0}, {0, 1, 0}, 3.0, 500, 500), 257},
    };
    for (const Case& c : cases) {
        const MeshTopology mesh = Model(scaled(spheres, c.scale)).topology();
        const Filled s = fill(mesh, c.camera, c.buffer_px, &raster_faces_scalar);
        const Filled v = fill(mesh, c.camera, c.buffer_px, avx2);
        EXPECT_EQ(s.stride % 8, 0) << c.name;
        EXPECT_EQ(s.drawn, mesh.face_count()) << c.name;
        EXPECT_EQ(v.drawn, s.drawn) << c.name;
        EXPECT_TRUE(s.keys == v.keys) << c.name;
        EXPECT_TRUE(s.faces == v.faces) << c.name;
        std::size_t covered = 0;
        for (std::uint32_t f : owners(s)) covered += f != kNoFace;
        EXPECT_GT(covered, std::size_t(s.width * s.height) / 10) << c.name;
        // Nothing written past the buffer's width (the vector kernel's padding lanes).
        for (int j = 0; j < s.height; ++j)
            for (int i = s.width; i < s.stride; ++i) EXPECT_EQ(v.faces[std::size_t(j) * v.stride + i], kNoFace) << c.name;
    }
    // Scaling the scene with its camera leaves its image alone: the same owner at every pixel.
    const Filled unit = fill(Model(scaled(spheres, 1.0)).topology(), cases[0].camera, 384, avx2);
    for (int k : {2, 3}) {
        const Filled f = fill(Model(scaled(spheres, cases[k].scale)).topology(), cases[k].camera, 384, avx2);
        const std::vector<std::uint32_t> a = owners(unit), b = owners(f);
        std::size_t differ = 0;
        for (std::size_t p = 0; p < a.size(); ++p) differ += a[p] != b[p];
        EXPECT_LE(differ, a.size() / 1000) << cases[k].name;  // centres on an edge may round either way
    }
}

// One face larger than the image covers every pixel, at its plane's depth.
TEST(DepthRaster, FaceLargerThanTheImage) {
    TriangleMesh m;
    m.positions = {{-100, -100, 0}, {100, -100, 0}, {0, 150, 0}};
    m.triangles = {{0, 1, 2}};
    const MeshTopology mesh = Model(m).topology();
    for (const Camera& cam : {Camera::perspective({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 200, 100),
                              Camera::orthographic({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 4.0, 200, 100)}) {
        for (RasterKernel k : {raster_kernel_avx2(), &raster_faces_scalar}) {
            if (!k) continue;
            DepthBuffer b;
            b.set_kernel(k);
            b.reset(cam, 64, {0.0, 0.0}, {200.0, 100.0});
            ASSERT_TRUE(b.draw(mesh, nullptr));
            ASSERT_EQ(b.width(), 64);
            ASSERT_EQ(b.height(), 32);
            for (int j = 0; j < b.height(); ++j)
                for (int i = 0; i < b.width(); ++i) {
                    ASSERT_EQ(b.face(i, j), 0u) << i << "," << j;
                    ASSERT_NEAR(b.depth(i, j), 5.0, 1e-5) << i << "," << j;
                }
        }
    }
}

// The measure itself: a drawing against itself differs by nothing; against an empty one by all
// of its visible length, as missing.
TEST(LineDifference, SelfAndEmpty) {
    const Model model(make_box({-1, -1, -1}, {1, 1, 1}));
    const View v = render_view(model, Camera::perspective({4, 3, 5}, {0, 0, 0}, {0, 1, 0}, 40, 800, 800));
    const LineDifference self = visible_difference(v.drawing, v.drawing);
    EXPECT_EQ(self.missing_px + self.extra_px, 0.0);
    EXPECT_NEAR(self.reference_px, test::visible_length_px(v.drawing), 1e-6);
    Drawing empty;
    const LineDifference none = visible_difference(v.drawing, empty);
    EXPECT_NEAR(none.missing_px, self.reference_px, 1e-9);
    EXPECT_EQ(none.extra_px, 0.0);
    EXPECT_NEAR(none.share(), 1.0, 1e-12);
}

// The commands: fast draws visible lines only, and says so; its buffer's size is checked.
TEST(FastVisibilityCli, RefusalsAndStats) {
    using namespace inkline_test;
    const fs::path d = scratch("fast_");
    const std::string mesh = test::mesh_path("elephant");
    const std::string out = (d / "e.json").string();
    Result r = run_inkline("", "render " + mesh + " -o " + out + " --visibility=fast --quiet", d);
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(slurp(out));
    EXPECT_EQ(j["stats"]["visibility"], "fast");
    struct Bad {
        std::string args, words;
    };
    const Bad bad[] = {
        {"render " + mesh + " -o " + out + " --visibility=fast --hidden",
         "inkline: --visibility=fast draws visible lines only; --hidden needs the exact QI of hidden lines (use "
         "--visibility=appel)"},
        {"view " + mesh + " --visibility=fast --hidden",
         "inkline: --visibility=fast draws visible lines only; --hidden needs the exact QI of hidden lines (use "
         "--visibility=appel)"},
        {"render " + mesh + " -o " + out + " --visibility=fast --fast-buffer=16",
         "inkline: --fast-buffer: expected an integer from 64 to 8192"},
        {"render " + mesh + " -o " + out + " --visibility=fast --fast-buffer=big",
         "inkline: --fast-buffer: expected a number, got 'big'"},
        {"bench " + mesh + " --visibility=fast --fast-buffer=100000", "inkline: --fast-buffer: expected an integer from 64 to 8192"},
        {"render " + mesh + " -o " + out + " --fast-buffer=512",
         "inkline: --fast-buffer sizes the fast visibility's depth buffer: it needs --visibility=fast"},
        {"bench " + mesh + " --visibility=appel --fast-buffer=512",
         "inkline: --fast-buffer sizes the fast visibility's depth buffer: it needs --visibility=fast"},
        {"render " + mesh + " -o " + out + " --visibility=zbuffer",
         "inkline: --visibility: unknown method 'zbuffer' (expected appel, rays or fast)"},
    };
    for (const Bad& b : bad) {
        r = run_inkline("", b.args, d);
        EXPECT_EQ(r.code, 2) << b.args;
        EXPECT_NE(r.err.find(b.words), std::string::npos) << b.args << "\n" << r.err;
    }
}

}  // namespace
