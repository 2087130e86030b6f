#include "visibility/ray_caster.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

// Embree's ray runs this fraction of the segment past its end, so that a face just in front of
// the end point that single precision (relative error ~6e-8 of the model size) puts behind it is
// still proposed; every proposal is decided exactly anyway.
constexpr float kPastEnd = 1e-4f;

struct HitCollector {
    RTCIntersectContext ctx;  // must be first: Embree hands this pointer back to the filter
    std::uint32_t skip0, skip1;
    std::vector<std::uint32_t>* hits;
};

void collect(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<HitCollector*>(args->context);
    const std::uint32_t prim = RTCHitN_primID(args->hit, args->N, 0);
    args->valid[0] = 0;  // reject, so that traversal goes on and reports every face
    if (prim == c->skip0 || prim == c->skip1) return;
    c->hits->push_back(prim);
}
// The segment as Embree's ray, in coordinates relative to the model's centre. Embree's errors
// grow with the distance of the ray origin from the model (single precision): from a far eye they
// exceed 1e-4 of the model size. The ray therefore starts where the segment enters the sphere of
// twice the model's half diagonal (all geometry lies within one); nothing is lost before that
// point. False when the segment never comes near the model (no ray).
bool embree_ray(const glm::dvec3& origin, double radius, const glm::dvec3& from, const glm::dvec3& to, RTCRayHit& rh) {
    glm::dvec3 o = from - origin, d = to - from;
    const double rho = 2.0 * radius, oo = glm::dot(o, o);
    if (oo > rho * rho) {
        const double dd = glm::dot(d, d), od = glm::dot(o, d), disc = od * od - dd * (oo - rho * rho);
        const double t0 = disc >= 0.0 && dd > 0.0 ? (-od - std::sqrt(disc)) / dd : 2.0;
        if (t0 > 1.0) return false;
        if (t0 > 0.0) {
            o += t0 * d;
            d *= 1.0 - t0;
        }
    }
    rh = RTCRayHit{};
    rh.ray.org_x = float(o.x);
    rh.ray.org_y = float(o.y);
    rh.ray.org_z = float(o.z);
    rh.ray.dir_x = float(d.x);
    rh.ray.dir_y = float(d.y);
    rh.ray.dir_z = float(d.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = 1.0f + kPastEnd;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return true;
}
}  // namespace

struct RayCaster::Impl {
    const MeshTopology& mesh;
    glm::dvec3 origin;
    double radius;
    std::vector<std::uint32_t> vertex_face_begin, vertex_faces;  // vertex -> incident faces
    std::vector<std::uint8_t> degenerate;                        // per face: zero area (never crossed)
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;  // owned by the scene
    bool refittable = false;         // the geometry's build quality is Embree's refit
    // Vertices into the Embree buffer (relative to `origin`) and the degenerate faces.
    void load_vertices(float* v);
    void find_degenerate();
    explicit Impl(const MeshTopology& m) : mesh(m), origin(m.bounds.center()), radius(m.bounds.half_diagonal()) {}
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {
// One count_layers: the faces looked at, each decided once, exactly (CGAL's segment/triangle
// predicate); its facing found when needed. Storage per thread, reused from test to test.
struct LayerCount {
    struct Decided {
        std::uint32_t face;
        bool crossed;
        int facing;  // orientation of the segment's start against the face; 2 until computed
    };
    const MeshTopology& mesh;
    const std::vector<std::uint32_t>& vertex_face_begin;
    const std::vector<std::uint32_t>& vertex_faces;
    const std::vector<std::uint8_t>& degenerate;
    std::uint32_t skip0, skip1;
    K::Segment_3 seg;
    K::Point_3 start;
    std::vector<std::uint32_t>& cand;   // the faces Embree reported, sorted, once each
    std::vector<Decided>& seen;
    std::vector<std::uint32_t>& queue;  // crossed faces whose neighbours are still to be looked at

    K::Point_3 corner(std::uint32_t face, int k) const { return cgal(mesh.positions[mesh.faces[face][k]]); }
    // The index in `seen` of `face`, decided on first sight.
    std::size_t decide(std::uint32_t face) {
        for (std::size_t i = 0; i < seen.size(); ++i)
            if (seen[i].face == face) return i;
        const bool x = !degenerate[face] && CGAL::do_intersect(seg, K::Triangle_3(corner(face, 0), corner(face, 1), corner(face, 2)));
        seen.push_back({face, x, 2});
        return seen.size() - 1;
    }
    int facing_of(std::uint32_t face) const { return int(CGAL::orientation(corner(face, 0), corner(face, 1), corner(face, 2), start)); }
    int facing(std::size_t i) {
        if (seen[i].facing == 2) seen[i].facing = facing_of(seen[i].face);
        return seen[i].facing;
    }
    // Decides the faces around vertex w (but skip0, skip1); those newly found crossed are queued.
    void look_around(std::uint32_t w) {
        for (std::uint32_t k = vertex_face_begin[w]; k < vertex_face_begin[w + 1]; ++k) {
            const std::uint32_t g = vertex_faces[k];
            if (g == skip0 || g == skip1) continue;
            const std::size_t n = seen.size(), j = decide(g);
            if (j == n && seen[j].crossed) queue.push_back(g);
        }
    }
    void look_around_end_edge();
    void follow_queue();
    int merge_layers();
};

// Queues the reported faces, and decides the faces around the curve edge's vertices (those skip0
// shares with skip1; all of skip0's, on a border). Two faces that share no vertex (a point where
// two surfaces cross: an intersection curve) have the segment's end inside both: the faces around
// all their corners, since one next to either can pass between the eye and the end arbitrarily
// close to it, where the ray, stopped short of the end, does not reach (mannequin-devil.off).
void LayerCount::look_around_end_edge() {
    queue.assign(cand.begin(), cand.end());
    if (skip0 == kNoFace) return;
    auto shared = [&](std::uint32_t w) {
        return std::find(mesh.faces[skip1].begin(), mesh.faces[skip1].end(), w) != mesh.faces[skip1].end();
    };
    const bool apart = skip1 != kNoFace && std::none_of(mesh.faces[skip0].begin(), mesh.faces[skip0].end(), shared);
    for (std::uint32_t w : mesh.faces[skip0])
        if (skip1 == kNoFace || apart || shared(w)) look_around(w);
    if (apart)
        for (std::uint32_t w : mesh.faces[skip1]) look_around(w);
}

// A reported face that is not crossed: single precision put the line of sight on the wrong side
// of one of its edges or corners, and the exact segment may cross a face around one of its
// vertices instead. A crossed face: the faces around its vertices, where the surface may fold back
// over the line of sight (a silhouette between them) and be crossed again; single precision misses
// such a face where the line grazes it (mannequin-devil.off: a fan folding about a vertex, the
// line crossing two of its faces nearly edge-on and not the one between them), so the whole rings
// are looked at, not only the faces across its edges.
void LayerCount::follow_queue() {
    while (!queue.empty()) {
        const std::uint32_t face = queue.back();
        queue.pop_back();
        const std::size_t i = decide(face);
        if (!seen[i].crossed && !std::binary_search(cand.begin(), cand.end(), face)) continue;
        for (std::uint32_t w : mesh.faces[face]) look_around(w);
    }
}

// Two crossed faces that share an edge and face the segment's start the same way are one layer:
// seen from there they lie on opposite sides of the plane through the start and the shared edge,
// so a line of sight meets both only on that edge. Faces folding over a shared silhouette edge
// can both be crossed and stay apart. The layers: the crossed faces, so merged. (The same way
// relative to the continuous surface: on an orientation seam, whose faces' windings differ,
// opposite facings.)
int LayerCount::merge_layers() {
    thread_local std::vector<std::size_t> crossed;
    crossed.clear();
    for (std::size_t i = 0; i < seen.size(); ++i)
        if (seen[i].crossed) crossed.push_back(i);
    auto shared_edge = [&](std::uint32_t a, std::uint32_t b) {  // UINT32_MAX: none
        const auto& fe = mesh.face_edges[a];
        for (int k = 0; k < 3; ++k)
            if (fe.face[k] == b) return fe.edge[k];
        return UINT32_MAX;
    };
    int layers = int(crossed.size());
    thread_local std::vector<std::uint32_t> parent;
    parent.resize(crossed.size());
    for (std::uint32_t i = 0; i < crossed.size(); ++i) parent[i] = i;
    auto root = [&](std::uint32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    for (std::uint32_t i = 0; i < crossed.size(); ++i)
        for (std::uint32_t j = i + 1; j < crossed.size(); ++j) {
            const std::uint32_t e = shared_edge(seen[crossed[i]].face, seen[crossed[j]].face);
            if (e == UINT32_MAX) continue;
            const int si = facing(crossed[i]), sj = facing(crossed[j]);
            if (si == int(CGAL::COPLANAR) || si != (mesh.is_seam(e) ? -sj : sj)) continue;
            const std::uint32_t ri = root(i), rj = root(j);
            if (ri != rj) {
                parent[ri] = rj;
                --layers;
            }
        }
    return layers;
}
}  // namespace

RayCaster::RayCaster(const MeshTopology& mesh) : impl_(std::make_unique<Impl>(mesh)) {
    Impl& m = *impl_;
    m.device = rtcNewDevice(nullptr);
    if (!m.device) throw std::runtime_error("Embree: cannot create a device");
    m.scene = rtcNewScene(m.device);
    rtcSetSceneFlags(m.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    RTCGeometry geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertex_count()));
    m.load_vertices(v);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.face_count()));
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) idx[3 * f + k] = mesh.faces[f][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(m.scene, geom);
    rtcReleaseGeometry(geom);
    m.geometry = geom;
    rtcCommitScene(m.scene);

    m.vertex_face_begin.assign(mesh.vertex_count() + 1, 0);
    for (const auto& f : mesh.faces)
        for (std::uint32_t w : f) ++m.vertex_face_begin[w + 1];
    for (std::size_t w = 0; w < mesh.vertex_count(); ++w) m.vertex_face_begin[w + 1] += m.vertex_face_begin[w];
    m.vertex_faces.resize(m.vertex_face_begin.back());
    std::vector<std::uint32_t> fill(m.vertex_face_begin.begin(), m.vertex_face_begin.end() - 1);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f)
        for (std::uint32_t w : mesh.faces[f]) m.vertex_faces[fill[w]++] = f;
    m.find_degenerate();
}

void RayCaster::Impl::load_vertices(float* v) {
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        const glm::dvec3 p = mesh.positions[i] - origin;
        v[3 * i] = float(p.x);
        v[3 * i + 1] = float(p.y);
        v[3 * i + 2] = float(p.z);
    }
}

void RayCaster::Impl::find_degenerate() {
    degenerate.resize(mesh.face_count());
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const auto& t = mesh.faces[f];
        degenerate[f] = CGAL::collinear(cgal(mesh.positions[t[0]]), cgal(mesh.positions[t[1]]), cgal(mesh.positions[t[2]]));
    }
}

void RayCaster::refit() {
    Impl& m = *impl_;
    if (!m.refittable) {  // the first refit builds the tree anew, later ones refit it
        // (Embree refits a geometry's tree only in a dynamic scene of low build quality, a
        // two-level structure: 1 ms instead of 11 for armadillo's 52 k triangles.)
        rtcSetSceneFlags(m.scene, RTCSceneFlags(rtcGetSceneFlags(m.scene) | RTC_SCENE_FLAG_DYNAMIC));
        rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_LOW);
        rtcSetGeometryBuildQuality(m.geometry, RTC_BUILD_QUALITY_REFIT);
        m.refittable = true;
    }
    m.load_vertices(static_cast<float*>(rtcGetGeometryBufferData(m.geometry, RTC_BUFFER_TYPE_VERTEX, 0)));
    rtcUpdateGeometryBuffer(m.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(m.geometry);
    rtcCommitScene(m.scene);
    // The origin stays (the buffer is relative to it); the sphere that rays start on must still
    // hold the whole model.
    m.radius = glm::length(m.mesh.bounds.center() - m.origin) + m.mesh.bounds.half_diagonal();
    m.find_degenerate();
}

RayCaster::~RayCaster() = default;

// Embree only proposes faces; every face counted is decided by CGAL's exact segment/triangle
// predicate. Single precision can put the line of sight on the wrong side of a face's edge or
// corner, so the faces looked at are: every face Embree reports, the faces around the vertices
// of a reported face that turns out not to be crossed, the neighbours folding back over a crossed
// face's edges (a silhouette between them), and the faces around the curve edge's vertices
// (those shared by skip0 and skip1): these reach the segment's end and, seen from the eye, can
// lie arbitrarily close to the line of sight, e.g. with an edge nearly in line with the curve
// edge, which image-space crossings ignore because it shares a vertex with the curve.
int RayCaster::count_layers(const glm::dvec3& from, const glm::dvec3& to, std::uint32_t skip0,
                            std::uint32_t skip1) const {
    const Impl& m = *impl_;
    thread_local std::vector<std::uint32_t> cand, queue;
    thread_local std::vector<LayerCount::Decided> seen;
    cand.clear();
    seen.clear();
    HitCollector c;
    rtcInitIntersectContext(&c.ctx);
    c.ctx.filter = collect;
    c.skip0 = skip0;
    c.skip1 = skip1;
    c.hits = &cand;
    RTCRayHit rh;
    if (embree_ray(m.origin, m.radius, from, to, rh)) rtcIntersect1(m.scene, &c.ctx, &rh);
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());

    LayerCount count{m.mesh, m.vertex_face_begin, m.vertex_faces, m.degenerate, skip0, skip1,
                     K::Segment_3(cgal(from), cgal(to)), cgal(from), cand, seen, queue};
    count.look_around_end_edge();
    count.follow_queue();
    return count.merge_layers();
}

}  // namespace inkline
