// Where the progressive mesh's per-frame ray-test index goes (issue 44): along a PmSession's path,
// each frame's adapted mesh is indexed again by its parts, each timed in wall and all-threads CPU
// ms: Embree's device, the geometry's upload, the tree's build at Embree's build qualities
// (medium, as RayCaster; low; low in a dynamic scene), RayCaster's per-face tables (the faces
// around each vertex, the degenerate faces) and RayCaster's constructor whole. Not a test.
//
//   ray_index_profile [MESH] [PX] [--path=dolly|orbit|dolly-in] [--frames=N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <embree3/rtcore.h>

#include "bench_models.hpp"
#include "core/clock.hpp"
#include "detail/progressive_mesh_session.hpp"

using namespace inkline;

namespace {

struct Cost {
    std::vector<double> wall, cpu;
    void add(const std::function<void()>& f) {
        const double w0 = wall_seconds(), c0 = process_cpu_seconds();
        f();
        cpu.push_back((process_cpu_seconds() - c0) * 1e3);
        wall.push_back((wall_seconds() - w0) * 1e3);
    }
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

Camera path_camera(const MeshTopology& t, const std::string& path, int k, int frames) {
    const Camera framed = Camera::framing(t.bounds, 1024, 1024);
    const glm::dvec3 c = t.bounds.center();
    if (path == "dolly-in") {
        const double fov = 30.0, D = t.bounds.half_diagonal() / std::sin(fov * M_PI / 360.0);
        const glm::dvec3 dir = glm::normalize(glm::dvec3(1.0, 0.6, 1.4));
        const double s = 1.5 - 0.9 * double(k) / double(std::max(1, frames - 1));
        return Camera::perspective(c + s * D * dir, c, {0, 1, 0}, fov, 1024, 1024);
    }
    const double times = path == "dolly" ? std::pow(1.01, k) : 1.0, a = path == "orbit" ? k * M_PI / 180.0 : 0.0;
    const glm::dvec3 d = framed.eye() - c;
    const glm::dvec3 turned{std::cos(a) * d.x + std::sin(a) * d.z, d.y, -std::sin(a) * d.x + std::cos(a) * d.z};
    return Camera::perspective(c + times * turned, c, framed.up(), framed.fov_deg(), 1024, 1024);
}

// A scene of the mesh on `device` with the given flags and quality; committed when `commit`.
RTCScene upload(RTCDevice device, const MeshTopology& m, RTCSceneFlags flags, RTCBuildQuality quality) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, flags);
    rtcSetSceneBuildQuality(scene, quality);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertex_count()));
    const glm::dvec3 o = m.bounds.center();
    for (std::size_t i = 0; i < m.vertex_count(); ++i)
        for (int k = 0; k < 3; ++k) v[3 * i + k] = float(m.positions[i][k] - o[k]);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.face_count()));
    for (std::size_t f = 0; f < m.face_count(); ++f)
        for (int k = 0; k < 3; ++k) idx[3 * f + k] = m.faces[f][k];
    rtcSetGeometryBuildQuality(g, quality);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    return scene;
}

// A two-level scene: one geometry per block of `block` consecutive faces (refit quality).
RTCScene upload_blocks(RTCDevice device, const MeshTopology& m, RTCSceneFlags flags, std::size_t block) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTCSceneFlags(flags | RTC_SCENE_FLAG_DYNAMIC));
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    const glm::dvec3 o = m.bounds.center();
    for (std::size_t b = 0; b < m.face_count(); b += block) {
        const std::size_t n = std::min(block, m.face_count() - b);
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
        for (std::size_t f = 0; f < n; ++f)
            for (int c = 0; c < 3; ++c) {
                idx[3 * f + c] = unsigned(3 * f + c);
                for (int k = 0; k < 3; ++k) v[9 * f + 3 * c + k] = float(m.positions[m.faces[b + f][c]][k] - o[k]);
            }
        rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_REFIT);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcReleaseGeometry(g);
    }
    return scene;
}

struct Reject {
    RTCIntersectContext ctx;
    std::size_t hits = 0;
};
void reject(const RTCFilterFunctionNArguments* args) {
    reinterpret_cast<Reject*>(args->context)->hits++;
    args->valid[0] = 0;
}
// Rays from the eye to every 20th vertex, every hit reported (as RayCaster's): their hits.
std::size_t cast(RTCScene s, const MeshTopology& m, const Camera& cam) {
    Reject r;
    rtcInitIntersectContext(&r.ctx);
    r.ctx.filter = reject;
    const glm::dvec3 o = m.bounds.center(), e = cam.eye() - o;
    for (std::size_t w = 0; w < m.vertex_count(); w += 20) {
        const glm::dvec3 d = m.positions[w] - o - e;
        RTCRayHit rh{};
        rh.ray.org_x = float(e.x), rh.ray.org_y = float(e.y), rh.ray.org_z = float(e.z);
        rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
        rh.ray.tfar = 1.0001f;
        rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(s, &r.ctx, &rh);
    }
    return r.hits;
}

}  // namespace

int main(int argc, char** argv) {
    std::string name = "armadillo", path = "orbit";
    double px = 3.0;
    int frames = 20, positional = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--path=", 0) == 0)
            path = a.substr(7);
        else if (a.rfind("--frames=", 0) == 0)
            frames = std::max(1, std::atoi(a.c_str() + 9));
        else if (positional++ == 0)
            name = a;
        else
            px = std::atof(a.c_str());
    }
    const Model* model = bench_model_for(name, "ray_index_profile");
    if (!model) return 1;
    const ProgressiveMesh pm(model->topology());
    ViewOptions o;
    o.exact_hidden = false;
    o.surface.suggestive = true;
    o.features.kinds[int(LineKind::Crease)] = false;
    PmSession session(pm, o, PmViewOptions::for_path(*model, px));
    session.settle(path_camera(model->topology(), path, 0, frames));
    RTCDevice device = rtcNewDevice(nullptr);
    const auto robust = RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    const auto dynamic = RTCSceneFlags(robust | RTC_SCENE_FLAG_DYNAMIC);
    Cost dev, up, medium, low, dyn_low, tables, degenerate, whole, blocks256, blocks1024;
    Cost cast_medium, cast_low, cast_dyn_low, cast_blocks256, cast_blocks1024;
    std::size_t rays = 0;
    std::size_t faces = 0;
    for (int k = 1; k <= frames; ++k) {
        session.render(path_camera(model->topology(), path, k, frames), 1.0 / 25.0);
        const MeshTopology& m = session.adapted().topology();
        faces += m.face_count();
        dev.add([] { rtcReleaseDevice(rtcNewDevice(nullptr)); });
        RTCScene s = nullptr;
        up.add([&] { s = upload(device, m, robust, RTC_BUILD_QUALITY_MEDIUM); });
        rtcReleaseScene(s);
        const Camera cam = path_camera(model->topology(), path, k, frames);
        rays = (m.vertex_count() + 19) / 20;
        const std::pair<Cost*, Cost*> kinds[] = {{&medium, &cast_medium}, {&low, &cast_low}, {&dyn_low, &cast_dyn_low},
                                                 {&blocks256, &cast_blocks256}, {&blocks1024, &cast_blocks1024}};
        for (int i = 0; i < 5; ++i) {
            kinds[i].first->add([&] {
                s = i == 0   ? upload(device, m, robust, RTC_BUILD_QUALITY_MEDIUM)
                    : i == 1 ? upload(device, m, robust, RTC_BUILD_QUALITY_LOW)
                    : i == 2 ? upload(device, m, dynamic, RTC_BUILD_QUALITY_LOW)
                             : upload_blocks(device, m, robust, i == 3 ? 256 : 1024);
                rtcCommitScene(s);
            });
            kinds[i].second->add([&] { cast(s, m, cam); });
            rtcReleaseScene(s);
        }
        tables.add([&] {
            std::vector<std::uint32_t> begin(m.vertex_count() + 1, 0), vf;
            for (const auto& f : m.faces)
                for (std::uint32_t w : f) ++begin[w + 1];
            for (std::size_t w = 0; w < m.vertex_count(); ++w) begin[w + 1] += begin[w];
            vf.resize(begin.back());
            std::vector<std::uint32_t> fill(begin.begin(), begin.end() - 1);
            for (std::uint32_t f = 0; f < m.face_count(); ++f)
                for (std::uint32_t w : m.faces[f]) vf[fill[w]++] = f;
        });
        degenerate.add([&] {
            using P = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
            std::vector<std::uint8_t> d(m.face_count());
            auto p = [&](std::uint32_t w) { return P(m.positions[w].x, m.positions[w].y, m.positions[w].z); };
            for (std::uint32_t f = 0; f < m.face_count(); ++f)
                d[f] = CGAL::collinear(p(m.faces[f][0]), p(m.faces[f][1]), p(m.faces[f][2]));
        });
        whole.add([&] { RayCaster r(m); });
    }
    rtcReleaseDevice(device);
    std::printf("%s %g px, %s, %d frames, %.0f faces a frame, %zu rays (eye to vertices, all hits); median ms wall / all-threads CPU\n",
                name.c_str(), px, path.c_str(), frames, double(faces) / frames, rays);
    const std::pair<const char*, Cost*> rows[] = {
        {"new device", &dev},          {"upload (no build)", &up}, {"upload + build medium", &medium},
        {"upload + build low", &low},  {"upload + build low, dynamic scene", &dyn_low},
        {"upload + build, blocks of 256 faces (refit quality), dynamic scene", &blocks256},
        {"upload + build, blocks of 1024 faces", &blocks1024},
        {"rays: medium", &cast_medium}, {"rays: low", &cast_low}, {"rays: low dynamic", &cast_dyn_low},
        {"rays: blocks of 256", &cast_blocks256}, {"rays: blocks of 1024", &cast_blocks1024},
        {"faces around vertices", &tables}, {"degenerate faces", &degenerate}, {"RayCaster whole", &whole}};
    for (const auto& [label, c] : rows)
        std::printf("| %s | %.2f | %.2f |\n", label, median(c->wall), median(c->cpu));
    return 0;
}
