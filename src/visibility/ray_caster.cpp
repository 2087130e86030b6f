#include "visibility/ray_caster.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <embree3/rtcore.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

// Hits whose parameter along the segment lies within this fraction of either end are re-decided
// exactly: single-precision coordinates (relative error ~6e-8 of the model size) cannot tell a
// face touching the end point from one just in front of or behind it.
constexpr float kExactBand = 1e-4f;

struct HitCollector {
    RTCIntersectContext ctx;  // must be first: Embree hands this pointer back to the filter
    std::uint32_t skip0, skip1;
    std::vector<std::pair<float, std::uint32_t>>* hits;
};

void collect(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<HitCollector*>(args->context);
    const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, 0);
    const float t = RTCRayN_tfar(args->ray, args->N, 0);
    args->valid[0] = 0;  // reject, so that traversal goes on and reports every face
    if (prim == c->skip0 || prim == c->skip1) return;
    for (const auto& h : *c->hits)
        if (h.second == prim) return;
    c->hits->emplace_back(t, prim);
}
}  // namespace

struct RayCaster::Impl {
    const MeshTopology& mesh;
    glm::dvec3 origin;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    explicit Impl(const MeshTopology& m) : mesh(m), origin(m.bounds.center()) {}
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayCaster::RayCaster(const MeshTopology& mesh) : impl_(std::make_unique<Impl>(mesh)) {
    Impl& m = *impl_;
    m.device = rtcNewDevice(nullptr);
    if (!m.device) throw std::runtime_error("Embree: cannot create a device");
    m.scene = rtcNewScene(m.device);
    rtcSetSceneFlags(m.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertex_count()));
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        const glm::dvec3 p = mesh.positions[i] - m.origin;
        v[3 * i] = float(p.x);
        v[3 * i + 1] = float(p.y);
        v[3 * i + 2] = float(p.z);
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.face_count()));
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) idx[3 * f + k] = mesh.faces[f][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(m.scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(m.scene);
}

RayCaster::~RayCaster() = default;

int RayCaster::count_layers(const glm::dvec3& from, const glm::dvec3& to, std::uint32_t skip0,
                            std::uint32_t skip1) const {
    const Impl& m = *impl_;
    thread_local std::vector<std::pair<float, std::uint32_t>> hits;
    hits.clear();
    HitCollector c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = collect;
    c.skip0 = skip0;
    c.skip1 = skip1;
    c.hits = &hits;

    const glm::dvec3 o = from - m.origin, d = to - from;
    RTCRayHit rh{};
    rh.ray.org_x = float(o.x);
    rh.ray.org_y = float(o.y);
    rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(d.x);
    rh.ray.dir_y = float(d.y);
    rh.ray.dir_z = float(d.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = 1.0f + kExactBand;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m.scene, &c.ctx, &rh);

    int layers = 0;
    const K::Segment_3 seg(cgal(from), cgal(to));
    for (const auto& [t, prim] : hits) {
        if (t > kExactBand && t < 1.0f - kExactBand) {
            ++layers;
            continue;
        }
        const auto& f = m.mesh.faces[prim];
        const K::Triangle_3 tri(cgal(m.mesh.positions[f[0]]), cgal(m.mesh.positions[f[1]]),
                                cgal(m.mesh.positions[f[2]]));
        if (!tri.is_degenerate() && CGAL::do_intersect(seg, tri)) ++layers;
    }
    return layers;
}

}  // namespace inkline
