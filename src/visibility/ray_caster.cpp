#include "visibility/ray_caster.hpp"

#include <algorithm>
#include <array>
#include <atomic>
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
    const std::uint32_t* geometry_first;  // per geometry: the mesh's face of its primitive 0
    std::vector<std::uint32_t>* hits;
};

void collect(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<HitCollector*>(args->context);
    const std::uint32_t face = c->geometry_first[RTCHitN_geomID(args->hit, args->N, 0)] +
                               RTCHitN_primID(args->hit, args->N, 0);
    args->valid[0] = 0;  // reject, so that traversal goes on and reports every face
    if (face == c->skip0 || face == c->skip1) return;
    c->hits->push_back(face);
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

// A subset index's block: the input faces [b * block_faces, (b + 1) * block_faces) that the
// mesh has, as one Embree geometry (geometry ID b) of their triangles' corners, three a face (so
// that a block's buffers need no vertex numbering), and per face its input face and corners'
// input vertices, to tell what changed.
struct SubsetBlock {
    RTCGeometry geometry = nullptr;  // null: no face of the block in the mesh
    std::vector<std::array<std::uint32_t, 4>> key;
};

struct RayCaster::Impl {
    const MeshTopology* mesh;
    glm::dvec3 origin;
    double radius;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    RTCGeometry geometry = nullptr;  // a mesh's own index: its one geometry (owned by the scene)
    bool refittable = false;         // the geometry's build quality is Embree's refit
    std::vector<std::uint32_t> geometry_first{0};  // per geometry ID: the mesh's face of its primitive 0
    // Per face: 0 not yet known, 1 has an area, 2 zero area (never crossed); found on a face's
    // first test, so a mesh's index costs nothing per face (a frame with thousands of ray tests
    // would test each face many times over).
    mutable std::unique_ptr<std::atomic<std::uint8_t>[]> degenerate;
    std::size_t degenerate_capacity = 0;
    void forget_degenerate();
    // The faces around each vertex: read from the topology's edges when every face's corner is on
    // its edges' lists (each edge of at most two faces); else (an edge of three faces or more,
    // whose edge_face holds two) from this table, made for the mesh.
    std::vector<std::uint32_t> vertex_face_begin, vertex_faces;
    void list_vertex_faces();
    // A subset index's blocks and options.
    std::vector<SubsetBlock> blocks;
    SubsetOptions subset;
    // `reindex`'s list of a block's faces, kept so a frame allocates nothing for it (a rebuilt
    // block swaps its old list in).
    std::vector<std::array<std::uint32_t, 4>> scratch_key;
    // Vertices into the Embree buffer (relative to `origin`).
    void load_vertices(float* v);
    RTCGeometry new_block(std::size_t faces) const;
    void fill_block(float* v, std::size_t first, std::size_t faces) const;
    bool block_moved(const SubsetBlock& b, std::size_t first) const;
    Impl(const MeshTopology* m, const glm::dvec3& o, double r) : mesh(m), origin(o), radius(r) {}
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
    const std::vector<std::uint32_t>& vertex_face_begin;  // (Impl's; empty: the edges)
    const std::vector<std::uint32_t>& vertex_faces;
    std::atomic<std::uint8_t>* degenerate;  // (Impl::degenerate)
    std::uint32_t skip0, skip1;
    K::Segment_3 seg;
    K::Point_3 start;
    std::vector<std::uint32_t>& cand;   // the faces Embree reported, sorted, once each
    std::vector<Decided>& seen;
    std::vector<std::uint32_t>& queue;  // crossed faces whose neighbours are still to be looked at

    K::Point_3 corner(std::uint32_t face, int k) const { return cgal(mesh.positions[mesh.faces[face][k]]); }
    // The index in `seen` of `face`, decided on first sight (a face of zero area is never crossed).
    std::size_t decide(std::uint32_t face) {
        for (std::size_t i = 0; i < seen.size(); ++i)
            if (seen[i].face == face) return i;
        const K::Point_3 a = corner(face, 0), b = corner(face, 1), c = corner(face, 2);
        std::uint8_t zero_area = degenerate[face].load(std::memory_order_relaxed);
        if (zero_area == 0) {  // (threads that race here store the same value)
            zero_area = CGAL::collinear(a, b, c) ? 2 : 1;
            degenerate[face].store(zero_area, std::memory_order_relaxed);
        }
        const bool x = zero_area == 1 && CGAL::do_intersect(seg, K::Triangle_3(a, b, c));
        seen.push_back({face, x, 2});
        return seen.size() - 1;
    }
    int facing_of(std::uint32_t face) const { return int(CGAL::orientation(corner(face, 0), corner(face, 1), corner(face, 2), start)); }
    int facing(std::size_t i) {
        if (seen[i].facing == 2) seen[i].facing = facing_of(seen[i].face);
        return seen[i].facing;
    }
    // Decides the faces around vertex w (but skip0, skip1), the faces of its edges (each face
    // met twice: decided once); those newly found crossed are queued.
    void look_around(std::uint32_t w) {
        auto look = [&](std::uint32_t g) {
            if (g == kNoFace || g == skip0 || g == skip1) return;
            const std::size_t n = seen.size(), j = decide(g);
            if (j == n && seen[j].crossed) queue.push_back(g);
        };
        if (!vertex_face_begin.empty()) {
            for (std::uint32_t k = vertex_face_begin[w]; k < vertex_face_begin[w + 1]; ++k) look(vertex_faces[k]);
            return;
        }
        for (std::uint32_t k = mesh.vertex_edge_begin[w]; k < mesh.vertex_edge_begin[w + 1]; ++k)
            for (const std::uint32_t g : mesh.edge_face[mesh.vertex_edges[k]]) look(g);
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

RayCaster::RayCaster(const MeshTopology& mesh)
    : impl_(std::make_unique<Impl>(&mesh, mesh.bounds.center(), mesh.bounds.half_diagonal())) {
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
    m.forget_degenerate();
    m.list_vertex_faces();
}

void RayCaster::Impl::list_vertex_faces() {
    vertex_face_begin.clear();
    vertex_faces.clear();
    std::size_t listed = 0;  // corners on their edges' lists
    for (const auto& ef : mesh->edge_face) listed += (ef[0] != kNoFace) + (ef[1] != kNoFace);
    if (listed == 3 * mesh->face_count()) return;
    vertex_face_begin.assign(mesh->vertex_count() + 1, 0);
    for (const auto& f : mesh->faces)
        for (const std::uint32_t w : f) ++vertex_face_begin[w + 1];
    for (std::size_t w = 0; w < mesh->vertex_count(); ++w) vertex_face_begin[w + 1] += vertex_face_begin[w];
    vertex_faces.resize(vertex_face_begin.back());
    std::vector<std::uint32_t> fill(vertex_face_begin.begin(), vertex_face_begin.end() - 1);
    for (std::uint32_t f = 0; f < mesh->face_count(); ++f)
        for (const std::uint32_t w : mesh->faces[f]) vertex_faces[fill[w]++] = f;
}

void RayCaster::Impl::forget_degenerate() {
    const std::size_t n = mesh->face_count();
    if (n > degenerate_capacity) {
        degenerate = std::make_unique<std::atomic<std::uint8_t>[]>(n);
        degenerate_capacity = n;
    }
    for (std::size_t f = 0; f < n; ++f) degenerate[f].store(0, std::memory_order_relaxed);
}

void RayCaster::Impl::load_vertices(float* v) {
    for (std::size_t i = 0; i < mesh->vertex_count(); ++i) {
        const glm::dvec3 p = mesh->positions[i] - origin;
        v[3 * i] = float(p.x);
        v[3 * i + 1] = float(p.y);
        v[3 * i + 2] = float(p.z);
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
    m.radius = glm::length(m.mesh->bounds.center() - m.origin) + m.mesh->bounds.half_diagonal();
    m.forget_degenerate();
}

RayCaster::RayCaster(const SubsetOptions& options) : impl_(std::make_unique<Impl>(nullptr, glm::dvec3(0.0), 0.0)) {
    Impl& m = *impl_;
    m.subset = options;
    m.subset.block_faces = std::max<std::size_t>(1, options.block_faces);
    m.device = rtcNewDevice(nullptr);
    if (!m.device) throw std::runtime_error("Embree: cannot create a device");
    m.scene = rtcNewScene(m.device);
    // Dynamic, low quality: the top level over the blocks is rebuilt at each commit (cheap: one
    // box a block), a block's own tree only when the block was committed.
    rtcSetSceneFlags(m.scene, RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                            RTC_SCENE_FLAG_DYNAMIC));
    rtcSetSceneBuildQuality(m.scene, RTC_BUILD_QUALITY_LOW);
    rtcCommitScene(m.scene);
    m.geometry_first.clear();
}

// A block's geometry for `faces` faces: its corners three a face, in order (index 3f + k).
RTCGeometry RayCaster::Impl::new_block(std::size_t faces) const {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * faces);
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), faces));
    for (std::size_t i = 0; i < 3 * faces; ++i) idx[i] = unsigned(i);
    rtcSetGeometryBuildQuality(g, subset.refit ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_LOW);
    return g;
}

// The corners of the mesh's faces [first, first + faces) into a block's vertex buffer.
void RayCaster::Impl::fill_block(float* v, std::size_t first, std::size_t faces) const {
    for (std::size_t f = 0; f < faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p = mesh->positions[mesh->faces[first + f][k]] - origin;
            float* q = v + 9 * f + 3 * k;
            q[0] = float(p.x), q[1] = float(p.y), q[2] = float(p.z);
        }
}

// Whether a block whose faces are the mesh's [first, ...) holds other single-precision corners.
bool RayCaster::Impl::block_moved(const SubsetBlock& b, std::size_t first) const {
    const auto* v = static_cast<const float*>(rtcGetGeometryBufferData(b.geometry, RTC_BUFFER_TYPE_VERTEX, 0));
    for (std::size_t f = 0; f < b.key.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p = mesh->positions[mesh->faces[first + f][k]] - origin;
            const float* q = v + 9 * f + 3 * k;
            if (q[0] != float(p.x) || q[1] != float(p.y) || q[2] != float(p.z)) return true;
        }
    return false;
}

RayCaster::ReindexStats RayCaster::reindex(const MeshTopology& mesh, const std::vector<std::uint32_t>& vertex_id,
                                           const std::vector<std::uint32_t>& face_id) {
    Impl& m = *impl_;
    m.mesh = &mesh;
    // The mesh's own frame, as its own index takes it: the blocks' corners and the rays are then
    // the same single-precision numbers as in a new index of the mesh, so Embree proposes the same
    // faces. (When the mesh's box moves, every block moves with it and is refitted.)
    m.origin = mesh.bounds.center();
    m.radius = mesh.bounds.half_diagonal();
    m.forget_degenerate();
    m.list_vertex_faces();
    const std::size_t bf = m.subset.block_faces, nf = mesh.face_count();
    const std::size_t nblocks = nf ? face_id[nf - 1] / bf + 1 : 0;
    if (m.blocks.size() < nblocks) m.blocks.resize(nblocks);
    m.geometry_first.resize(m.blocks.size());
    ReindexStats stats;
    bool changed = false;
    std::vector<std::array<std::uint32_t, 4>>& key = m.scratch_key;
    std::size_t f = 0;
    for (std::uint32_t b = 0; b < m.blocks.size(); ++b) {
        SubsetBlock& block = m.blocks[b];
        const std::size_t first = f;
        key.clear();
        for (; f < nf && face_id[f] / bf == b; ++f) {
            const auto& t = mesh.faces[f];
            key.push_back({face_id[f], vertex_id[t[0]], vertex_id[t[1]], vertex_id[t[2]]});
        }
        m.geometry_first[b] = std::uint32_t(first);
        if (key.empty()) {
            if (block.geometry) {
                rtcDetachGeometry(m.scene, b);
                block = SubsetBlock{};
                ++stats.removed;
                changed = true;
            }
            continue;
        }
        ++stats.blocks;
        if (block.geometry && key == block.key) {
            if (!m.block_moved(block, first)) {
                ++stats.kept;
                continue;
            }
            m.fill_block(static_cast<float*>(rtcGetGeometryBufferData(block.geometry, RTC_BUFFER_TYPE_VERTEX, 0)), first,
                         key.size());
            rtcUpdateGeometryBuffer(block.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
            rtcCommitGeometry(block.geometry);
            ++stats.refitted;
            changed = true;
            continue;
        }
        if (block.geometry) rtcDetachGeometry(m.scene, b);
        RTCGeometry g = m.new_block(key.size());
        m.fill_block(static_cast<float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0)), first, key.size());
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(m.scene, g, b);
        rtcReleaseGeometry(g);
        block.geometry = g;
        block.key.swap(key);
        ++stats.rebuilt;
        changed = true;
    }
    if (changed) rtcCommitScene(m.scene);
    return stats;
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
    c.geometry_first = m.geometry_first.data();
    c.hits = &cand;
    RTCRayHit rh;
    if (embree_ray(m.origin, m.radius, from, to, rh)) rtcIntersect1(m.scene, &c.ctx, &rh);
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());

    LayerCount count{*m.mesh, m.vertex_face_begin, m.vertex_faces, m.degenerate.get(), skip0, skip1,
                     K::Segment_3(cgal(from), cgal(to)), cgal(from), cand, seen, queue};
    count.look_around_end_edge();
    count.follow_queue();
    return count.merge_layers();
}

}  // namespace inkline
