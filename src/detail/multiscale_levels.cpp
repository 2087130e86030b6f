// The multi-scale pre-process: simplification with detail coefficients, then the smoothed levels
// rebuilt by vertex splits (multiscale.hpp; Guskov, Sweldens, Schroder 1999 as seed 001 uses it).
//
// Two fairing functionals (MultiscaleFairing). The umbrella (membrane) energy: the minimizer for
// one vertex, its neighbours fixed, is their centroid. GSS's second-order one with uniform
// parameter weights: the sum over interior edges of |p_a + p_b - p_i - p_j|^2, edge (i, j) with
// the opposite vertices a, b of its two faces (the jump of the gradient across the edge, zero
// where the surface is flat); its minimizer for one vertex x is the mean of the 2n targets its n
// edges and n ring edges give: 3/2 of its ring's centroid minus 1/2 of the centroid of the
// vertices across its ring edges. That reproduces quadratics on a regular mesh, so it does not
// shrink a curved surface as the umbrella does, but it also smooths much less per relaxation
// (bench/results/multiscale.md).
#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <queue>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <glm/geometric.hpp>

#include "core/clock.hpp"
#include "detail/multiscale.hpp"
#include "detail/multiscale_smoothing.hpp"
#include "detail/octahedral.hpp"
#include "model/self_intersections.hpp"

namespace inkline {

namespace {

struct OmTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
    VertexAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Status);
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<OmTraits>;

// The collapses in order. Each is a stencil of blocks [vertex, ring count, outer count, ring...,
// outer...]: first the removed vertex, then each vertex of its ring; ring and outer are the
// vertices the fairing predictor reads (`predict`). Per block one detail coefficient: actual
// minus predicted.
struct CollapseRecord {
    std::vector<std::uint32_t> begin{0};   // per collapse, into `blocks`; one more at the end
    std::vector<std::uint32_t> blocks;
    std::vector<std::uint32_t> detail_begin{0};  // per collapse, into `detail`
    std::vector<glm::dvec3> detail;
    // Every vertex's stencil on the input mesh (the final sweeps over the levels).
    std::vector<std::uint32_t> fine_blocks;
    std::size_t count() const { return begin.size() - 1; }
};

// Each vertex's place in the lexicographic order of the input positions (x, then y, then z; equal
// positions by index): the simplification and the sweeps decide by it wherever today's numbering
// would decide, so that the levels do not depend on how the file numbers vertices and faces.
std::vector<std::uint32_t> position_ranks(const std::vector<glm::dvec3>& positions) {
    std::vector<std::uint32_t> order(positions.size());
    for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v;
    std::ranges::sort(order, [&positions](std::uint32_t a, std::uint32_t b) {
        const glm::dvec3 &p = positions[a], &q = positions[b];
        if (p.x != q.x) return p.x < q.x;
        if (p.y != q.y) return p.y < q.y;
        if (p.z != q.z) return p.z < q.z;
        return a < b;
    });
    std::vector<std::uint32_t> rank(positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
    return rank;
}

// x's outgoing halfedge to its neighbour of least rank: sums over a ring that start there (the
// circulator from it) add in the same order whatever the numbering.
OmMesh::HalfedgeHandle ring_start(const OmMesh& m, OmMesh::VertexHandle x, const std::vector<std::uint32_t>& rank) {
    OmMesh::HalfedgeHandle start;
    std::uint32_t least = ~0u;
    for (auto h : m.voh_range(x))
        if (const std::uint32_t r = rank[std::size_t(m.to_vertex_handle(h).idx())]; r < least) least = r, start = h;
    return start;
}

// The predictor's stencil of x on mesh m, appended to `out` as one block: its neighbours and, for
// the second-order functional, the vertices across its ring edges (the flaps). Where a flap is
// missing (a border near) the umbrella stands in: the neighbours' centroid, along a border only
// the two border neighbours (so that borders are smoothed along themselves).
void predictors(const OmMesh& m, OmMesh::VertexHandle x, bool second_order, const std::vector<std::uint32_t>& rank,
                std::vector<std::uint32_t>& out) {
    const std::size_t at = out.size();
    out.push_back(std::uint32_t(x.idx()));
    out.push_back(0);
    out.push_back(0);
    const bool border = m.is_boundary(x);
    const auto start = ring_start(m, x, rank);
    if (!start.is_valid()) {  // an isolated vertex: no predictors
        out[at + 1] = 0;
        return;
    }
    for (auto h : m.voh_range(start))
        if (!border || m.is_boundary(m.edge_handle(h))) out.push_back(std::uint32_t(m.to_vertex_handle(h).idx()));
    const std::uint32_t ring = std::uint32_t(out.size() - at - 3);
    out[at + 1] = ring;
    if (!second_order || border || ring < 3) return;
    for (auto h : m.voh_range(start)) {
        const auto across = m.opposite_halfedge_handle(m.next_halfedge_handle(h));  // the ring edge's other side
        if (m.is_boundary(across)) {  // no flap there: the umbrella
            out.resize(at + 3 + ring);
            return;
        }
        out.push_back(std::uint32_t(m.to_vertex_handle(m.next_halfedge_handle(across)).idx()));
    }
    out[at + 2] = ring;
}

std::uint32_t block_size(const std::vector<std::uint32_t>& blocks, std::uint32_t b) {
    return 3 + blocks[b + 1] + blocks[b + 2];
}

// The fairing functional's minimizer for the block at b, positions by `at(vertex)`.
template <class At>
glm::dvec3 predict(const std::vector<std::uint32_t>& blocks, std::uint32_t b, const At& at) {
    const std::uint32_t ring = blocks[b + 1], outer = blocks[b + 2];
    if (ring == 0) return at(blocks[b]);
    glm::dvec3 sum_ring(0.0), sum_outer(0.0);
    for (std::uint32_t i = 0; i < ring; ++i) sum_ring += at(blocks[b + 3 + i]);
    const glm::dvec3 centroid = sum_ring / double(ring);
    if (outer == 0) return centroid;
    for (std::uint32_t i = 0; i < outer; ++i) sum_outer += at(blocks[b + 3 + ring + i]);
    return 1.5 * centroid - 0.5 * (sum_outer / double(outer));
}

[[maybe_unused]] glm::dvec3 point(const OmMesh& m, std::uint32_t v) {
    const auto& p = m.point(OmMesh::VertexHandle(int(v)));
    return {p[0], p[1], p[2]};
}

// Records the stencil of the collapse of halfedge h (its from-vertex removed) before it happens.
void record_stencil(const OmMesh& m, OmMesh::HalfedgeHandle h, bool second_order, const std::vector<std::uint32_t>& rank,
                    CollapseRecord& r) {
    const auto v0 = m.from_vertex_handle(h);
    predictors(m, v0, second_order, rank, r.blocks);
    for (auto w : m.vv_range(v0)) predictors(m, w, second_order, rank, r.blocks);
    r.begin.push_back(std::uint32_t(r.blocks.size()));
}

// After the collapse recorded last: GSS's analysis. The ring is relaxed on the coarse mesh
// (each vertex moved `relax` of the way to its fairing minimizer there: the coarser meshes are
// low-pass filtered), and each stencil vertex's detail is its position minus the position the
// synthesis predicts from the relaxed ring (synthesize: the new vertex at its minimizer, then each
// ring vertex `spread` of the way to its own), so that adding the details back rebuilds the finer
// mesh. `smooth` holds the current level's positions (the mesh's own points stay the input's: the
// simplification's choices do not depend on the smoothing).
void analyse_collapse(const OmMesh& m, CollapseRecord& r, const MultiscaleOptions& o, const std::vector<std::uint32_t>& rank,
                      std::vector<glm::dvec3>& smooth, std::vector<std::uint32_t>& scratch_ids,
                      std::vector<glm::dvec3>& coarse, std::vector<glm::dvec3>& original) {
    const std::size_t j = r.count() - 1;
    const std::uint32_t first = r.begin[j], end = r.begin[j + 1];
    const std::uint32_t v = r.blocks[first];
    const std::uint32_t ring_first = first + block_size(r.blocks, first);
    const auto next = [&r](std::uint32_t b) { return b + block_size(r.blocks, b); };
    original.clear();
    for (std::uint32_t b = ring_first; b < end; b = next(b)) original.push_back(smooth[r.blocks[b]]);
    const auto at_smooth = [&smooth](std::uint32_t u) { return smooth[u]; };
    // A step toward the minimizer, and optionally Taubin's step back (lambda|mu: less shrinking).
    const bool second_order = o.fairing == MultiscaleFairing::SecondOrder;
    for (const double factor : {o.relax, o.shrink_back}) {
        if (factor == 0.0) continue;
        coarse.clear();
        for (std::uint32_t b = ring_first; b < end; b = next(b)) {
            const std::uint32_t w = r.blocks[b];
            scratch_ids.clear();
            predictors(m, OmMesh::VertexHandle(int(w)), second_order, rank, scratch_ids);  // on the coarse mesh
            coarse.push_back(smooth[w] + factor * (predict(scratch_ids, 0, at_smooth) - smooth[w]));
        }
        std::size_t k = 0;
        for (std::uint32_t b = ring_first; b < end; b = next(b)) smooth[r.blocks[b]] = coarse[k++];
    }
    if (o.relax == 0.0 && o.shrink_back == 0.0) coarse = original;
    {  // the details are measured from the positions before the relaxation
        std::size_t k = 0;
        for (std::uint32_t b = ring_first; b < end; b = next(b)) smooth[r.blocks[b]] = original[k++];
    }
    // The value synthesis sees at vertex u when it predicts the ring: v's own, the relaxed ring's,
    // or the unchanged rest.
    const auto seen = [&](std::uint32_t u) {
        if (u == v) return smooth[v];
        std::size_t k = 0;
        for (std::uint32_t b = ring_first; b < end; b = next(b), ++k)
            if (r.blocks[b] == u) return coarse[k];
        return smooth[u];
    };
    for (std::uint32_t b = first; b < end; b = next(b)) {
        const std::uint32_t x = r.blocks[b];
        const glm::dvec3 minimizer = predict(r.blocks, b, seen);
        const glm::dvec3 predicted = b == first ? minimizer : seen(x) + o.spread * (minimizer - seen(x));
        r.detail.push_back(smooth[x] - predicted);
    }
    r.detail_begin.push_back(std::uint32_t(r.detail.size()));
    std::size_t k = 0;
    for (std::uint32_t b = ring_first; b < end; b = next(b)) smooth[r.blocks[b]] = coarse[k++];
}

// The rules of OpenMesh's BaseDecimaterT::is_collapse_legal (topology, borders), and no face
// around the removed vertex turning by more than 60 degrees or collapsing (ModNormalFlippingT's
// test): the coarse meshes fold nowhere.
bool collapse_allowed(OmMesh& m, OmMesh::HalfedgeHandle h) {  // (is_collapse_ok is not const)
    if (!m.is_collapse_ok(h)) return false;
    const auto v0 = m.from_vertex_handle(h), v1 = m.to_vertex_handle(h);
    const auto o = m.opposite_halfedge_handle(h);
    const auto vl = m.face_handle(h).is_valid() ? m.to_vertex_handle(m.next_halfedge_handle(h)) : OmMesh::VertexHandle();
    const auto vr = m.face_handle(o).is_valid() ? m.to_vertex_handle(m.next_halfedge_handle(o)) : OmMesh::VertexHandle();
    if (vl.is_valid() && vr.is_valid() && m.find_halfedge(vl, vr).is_valid() && m.valence(vl) == 3 && m.valence(vr) == 3)
        return false;
    if (m.is_boundary(v0) && (!m.is_boundary(v1) || (vl.is_valid() && vr.is_valid()))) return false;
    if (m.cw_rotated_halfedge_handle(m.cw_rotated_halfedge_handle(h)) == h) return false;
    // Each face's normal from v0's corner (the same sums whatever corner the face starts at).
    const OmMesh::Point p0 = m.point(v0), q = m.point(v1);
    for (auto g : m.voh_range(v0)) {
        if (!m.face_handle(g).is_valid()) continue;
        const auto b = m.to_vertex_handle(g), c = m.to_vertex_handle(m.next_halfedge_handle(g));
        if (b == v1 || c == v1) continue;  // removed by the collapse
        const OmMesh::Point pb = m.point(b), pc = m.point(c);
        const auto n0 = (pb - p0) % (pc - p0), n1 = (pb - q) % (pc - q);
        const double l0 = n0.norm(), l1 = n1.norm();
        if (!(l1 > 0.0) || (n0 | n1) < 0.5 * l0 * l1) return false;
    }
    return true;
}

// A queued edge: shortest first, equal lengths by the ranks of its ends (`key`: the lesser rank in
// the high half), so that the order of collapses follows the positions, not the numbering.
struct Candidate {
    double length2;
    std::uint64_t key;
    std::uint32_t edge, version;
    bool operator>(const Candidate& o) const { return length2 != o.length2 ? length2 > o.length2 : key > o.key; }
};

// Garland and Heckbert's quadric error: per vertex the sum of its faces' planes' squared distances
// (area-weighted), a collapse's cost the merged quadric at the kept end.
struct Quadric {
    double q[10] = {};  // xx xy xz xw yy yz yw zz zw ww
    void add_plane(const glm::dvec3& n, double d, double w) {
        const double a[4] = {n.x, n.y, n.z, d};
        int k = 0;
        for (int i = 0; i < 4; ++i)
            for (int j = i; j < 4; ++j) q[k++] += w * a[i] * a[j];
    }
    void add(const Quadric& o) {
        for (int k = 0; k < 10; ++k) q[k] += o.q[k];
    }
    double at(const glm::dvec3& p) const {
        const double x = p.x, y = p.y, z = p.z;
        return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z +
               2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
    }
};

glm::dvec3 at(const OmMesh& m, OmMesh::VertexHandle v) {
    const auto& p = m.point(v);
    return {p[0], p[1], p[2]};
}

// Per vertex the quadric of its faces, each face's plane from its corner of least rank, summed
// around the vertex from its neighbour of least rank (the same bits whatever the numbering).
std::vector<Quadric> vertex_quadrics(const OmMesh& m, const std::vector<std::uint32_t>& rank) {
    std::vector<Quadric> out(m.n_vertices());
    for (auto v : m.vertices()) {
        const auto start = ring_start(m, v, rank);
        if (!start.is_valid()) continue;
        for (auto h : m.voh_range(start)) {
            if (!m.face_handle(h).is_valid()) continue;
            OmMesh::VertexHandle c[3] = {v, m.to_vertex_handle(h), m.to_vertex_handle(m.next_halfedge_handle(h))};
            const int first = int(std::min_element(c, c + 3, [&rank](auto a, auto b) {
                                      return rank[std::size_t(a.idx())] < rank[std::size_t(b.idx())];
                                  }) - c);
            const glm::dvec3 p0 = at(m, c[first]), p1 = at(m, c[(first + 1) % 3]), p2 = at(m, c[(first + 2) % 3]);
            const glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
            const double twice_area = glm::length(n);
            if (!(twice_area > 0.0)) continue;
            const glm::dvec3 u = n / twice_area;
            out[std::size_t(v.idx())].add_plane(u, -glm::dot(u, p0), 0.5 * twice_area);
        }
    }
    return out;
}

// The collapse of edge e: which end goes. Of the allowed directions the one of least quadric error
// (the kept end the one the merged quadric finds nearer to the faces both ends had: a corner or a
// ridge is kept, a vertex on a flat stretch goes); errors equal within rounding by rank (the end of
// lesser rank goes). Invalid when neither direction is allowed. (Measured against keeping the end
// whose faces turn least, the flatter end by angle defect or umbrella, the end nearer the merged
// ring's centroid, and the opposite of each: this one folds the fewest faces and keeps the most
// margin on test_detail's bounds; docs/detail.md.)
OmMesh::HalfedgeHandle choose_collapse(OmMesh& m, OmMesh::EdgeHandle e, const std::vector<std::uint32_t>& rank,
                                       const std::vector<Quadric>& quadric) {
    OmMesh::HalfedgeHandle h[2] = {m.halfedge_handle(e, 0), m.halfedge_handle(e, 1)};
    if (rank[std::size_t(m.from_vertex_handle(h[1]).idx())] < rank[std::size_t(m.from_vertex_handle(h[0]).idx())])
        std::swap(h[0], h[1]);
    Quadric q = quadric[std::size_t(m.from_vertex_handle(h[0]).idx())];
    q.add(quadric[std::size_t(m.to_vertex_handle(h[0]).idx())]);
    const glm::dvec3 a = at(m, m.from_vertex_handle(h[0])), b = at(m, m.to_vertex_handle(h[0]));
    // Errors are area times squared distance: rounding's share is about 1e-16 of the faces' area
    // (the quadric's trace) times the edge's squared length.
    const double tie = 1e-9 * (q.q[0] + q.q[4] + q.q[7]) * glm::dot(b - a, b - a);
    if (q.at(a) < q.at(b) - tie) std::swap(h[0], h[1]);  // keeping a (removing b) costs less
    if (collapse_allowed(m, h[0])) return h[0];
    return collapse_allowed(m, h[1]) ? h[1] : OmMesh::HalfedgeHandle();
}

// Simplifies a copy of the mesh with OpenMesh's collapses, shortest edge first (so that the mesh
// has about uniform edge lengths at every stage, as the seed's r assumes; equal lengths by the
// ends' ranks), the removed end by choose_collapse, until no edge may collapse. A lazy heap of edges, re-queued when they touch a collapse: OpenMesh's DecimaterT
// re-tests every outgoing halfedge of every ring vertex after each collapse, which made it most of
// the pre-process (bench/results/multiscale.md). False when OpenMesh refuses a face.
bool simplify(const MeshTopology& mesh, const MultiscaleOptions& options, CollapseRecord& record,
              std::vector<glm::dvec3>& smooth, std::string& why) {
    OmMesh m;
    std::vector<OmMesh::VertexHandle> vh;
    vh.reserve(mesh.vertex_count());
    for (const auto& p : mesh.positions) vh.push_back(m.add_vertex({p.x, p.y, p.z}));
    // OpenMesh prints its own line for a refused face; the caller's warning says it once.
    struct Quiet {
        bool was = ::omerr().is_enabled();
        Quiet() { ::omerr().disable(); }
        ~Quiet() { if (was) ::omerr().enable(); }
    } quiet;
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const auto& t = mesh.faces[f];
        if (!m.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) {
            why = "face " + std::to_string(f) + " has a vertex shared by separate fans (non-manifold), which "
                  "edge collapses cannot handle";
            return false;
        }
    }
    const std::size_t n = mesh.vertex_count();
    const std::vector<std::uint32_t> rank = position_ranks(mesh.positions);
    const bool second_order = options.fairing == MultiscaleFairing::SecondOrder;
    if (options.sweeps > 0 || options.tangential_sweeps > 0) {  // the sweeps' order: by rank
        std::vector<std::uint32_t> order(n);
        for (std::uint32_t v = 0; v < n; ++v) order[rank[v]] = v;
        for (std::uint32_t v : order) predictors(m, OmMesh::VertexHandle(int(v)), second_order, rank, record.fine_blocks);
    }
    std::vector<Quadric> quadric = vertex_quadrics(m, rank);
    record.begin.reserve(n + 1);
    record.detail_begin.reserve(n + 1);
    record.blocks.reserve(7 * 16 * n);
    record.detail.reserve(7 * n);
    std::vector<std::uint32_t> version(m.n_edges(), 0);
    std::vector<std::uint8_t> refused(m.n_edges(), 0);  // popped and not allowed: may be later
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue;
    auto push = [&](OmMesh::EdgeHandle e) {
        const auto h = m.halfedge_handle(e, 0);
        const auto a = m.from_vertex_handle(h), b = m.to_vertex_handle(h);
        const double l2 = (m.point(b) - m.point(a)).sqrnorm();
        const auto [lo, hi] = std::minmax(rank[std::size_t(a.idx())], rank[std::size_t(b.idx())]);
        queue.push({l2, std::uint64_t(lo) << 32 | hi, std::uint32_t(e.idx()), ++version[std::size_t(e.idx())]});
    };
    for (auto e : m.edges()) push(e);
    std::vector<OmMesh::VertexHandle> moved;
    std::vector<std::uint32_t> ids;
    std::vector<glm::dvec3> coarse, original;
    smooth = mesh.positions;
    while (!queue.empty()) {
        const Candidate c = queue.top();
        queue.pop();
        const OmMesh::EdgeHandle e(int(c.edge));
        if (c.version != version[c.edge] || m.status(e).deleted()) continue;
        const OmMesh::HalfedgeHandle h = choose_collapse(m, e, rank, quadric);
        if (!h.is_valid()) {  // queued again when a collapse next to it may allow it
            refused[c.edge] = 1;
            continue;
        }
        const auto v0 = m.from_vertex_handle(h), v1 = m.to_vertex_handle(h);
        record_stencil(m, h, second_order, rank, record);
        moved.clear();  // v0's edges that become v1's: the only ones whose length changes
        for (auto w : m.vv_range(v0))
            if (w != v1 && !m.find_halfedge(v1, w).is_valid()) moved.push_back(w);
        m.collapse(h);
        quadric[std::size_t(v1.idx())].add(quadric[std::size_t(v0.idx())]);
        analyse_collapse(m, record, options, rank, smooth, ids, coarse, original);
        for (auto w : moved) {
            const auto k = m.edge_handle(m.find_halfedge(v1, w));
            refused[std::size_t(k.idx())] = 0;
            push(k);
        }
        // Refused edges next to the collapse may be allowed now.
        for (auto f : m.vf_range(v1))
            for (auto fe : m.fe_range(f))
                if (refused[std::size_t(fe.idx())]) {
                    refused[std::size_t(fe.idx())] = 0;
                    push(fe);
                }
    }
    return true;
}

// Rebuilds by vertex splits (the collapses in reverse), each placing the new vertex and relaxing
// its ring at their predicted positions, plus the detail for the first `with_detail` splits.
void synthesize(const CollapseRecord& r, double spread, std::size_t with_detail, std::vector<glm::dvec3>& pos,
                std::vector<glm::dvec3>& ring) {
    const std::size_t n = r.count();
    const auto at_pos = [&pos](std::uint32_t u) { return pos[u]; };
    for (std::size_t s = 0; s < n; ++s) {
        const std::size_t j = n - 1 - s;
        const bool add = s < with_detail;
        const std::uint32_t first = r.begin[j], end = r.begin[j + 1];
        std::size_t d = r.detail_begin[j];
        const auto detail = [&] { return add ? r.detail[d] : glm::dvec3(0.0); };
        // The new vertex first (its ring sees it), at its minimizer.
        pos[r.blocks[first]] = predict(r.blocks, first, at_pos) + detail();
        // Then the ring all at once, each `spread` of the way to its minimizer from the others'
        // positions before the split.
        ring.clear();
        const std::uint32_t ring_first = first + block_size(r.blocks, first);
        for (std::uint32_t b = ring_first; b < end; b += block_size(r.blocks, b)) {
            ++d;
            const glm::dvec3& x = pos[r.blocks[b]];
            ring.push_back(x + spread * (predict(r.blocks, b, at_pos) - x) + detail());
        }
        std::size_t k = 0;
        for (std::uint32_t b = ring_first; b < end; b += block_size(r.blocks, b)) pos[r.blocks[b]] = ring[k++];
    }
}

// Relaxation sweeps over the whole level (Gauss-Seidel, each vertex `spread` of the way to its
// minimizer): what the vertex splits without detail leave of high frequencies (spikes at thin
// tips, folds) goes.
void relax_level(const CollapseRecord& r, double spread, int sweeps, std::vector<glm::dvec3>& pos) {
    const auto at_pos = [&pos](std::uint32_t u) { return pos[u]; };
    for (int i = 0; i < sweeps; ++i)
        for (std::uint32_t b = 0; b < r.fine_blocks.size(); b += block_size(r.fine_blocks, b)) {
            glm::dvec3& x = pos[r.fine_blocks[b]];
            x += spread * (predict(r.fine_blocks, b, at_pos) - x);
        }
}

// Tangential relaxation: each interior vertex half way to its ring's centroid within the plane
// of the ring's vector area. The shape stays (to first order); the slivers that the splits
// without detail leave open up, whose curvature estimates were the tail of the levels' |k1|.
void tangential_level(const CollapseRecord& r, int sweeps, std::vector<glm::dvec3>& pos) {
    for (int i = 0; i < sweeps; ++i)
        for (std::uint32_t b = 0; b < r.fine_blocks.size(); b += block_size(r.fine_blocks, b)) {
            const std::uint32_t ring = r.fine_blocks[b + 1];
            if (ring < 3) continue;  // borders stay
            glm::dvec3 c(0.0), area(0.0);
            for (std::uint32_t k = 0; k < ring; ++k) {
                c += pos[r.fine_blocks[b + 3 + k]];
                area += glm::cross(pos[r.fine_blocks[b + 3 + k]], pos[r.fine_blocks[b + 3 + (k + 1) % ring]]);
            }
            c /= double(ring);
            const double a2 = glm::dot(area, area);
            if (!(a2 > 0.0)) continue;
            glm::dvec3& x = pos[r.fine_blocks[b]];
            const glm::dvec3 d = c - x;
            x += 0.5 * (d - area * (glm::dot(d, area) / a2));
        }
}

// Mean and median of |k1| over the valid vertices.
std::pair<double, double> abs_k1(const CurvatureField& field) {
    std::vector<float> a;
    a.reserve(field.size());
    for (std::size_t v = 0; v < field.size(); ++v)
        if (field.valid[v]) a.push_back(std::fabs(field.k1[v]));
    if (a.empty()) return {0.0, 0.0};
    double sum = 0.0;
    for (float x : a) sum += double(x);
    std::nth_element(a.begin(), a.begin() + std::ptrdiff_t(a.size() / 2), a.end());
    return {sum / double(a.size()), double(a[a.size() / 2])};
}

void store_level(MultiscaleLevels& out, int k, const std::vector<glm::dvec3>& pos, const CurvatureField& field) {
    for (std::size_t v = 0; v < out.vertices; ++v) {
        const std::size_t i = out.at(k, v);
        out.position[i] = glm::vec3(pos[v]);
        out.normal_oct[i] = octahedral_encode(field.normal[v]);
        out.dir1_angle[i] = angle_in_frame(octahedral_decode(out.normal_oct[i]), field.dir1[v]);
        out.k1[i] = field.k1[v];
        out.k2[i] = field.k2[v];
        out.dcurv[i] = field.dcurv[v];
        out.valid[i] = field.valid[v];
    }
}

double mean_edge_length(const MeshTopology& mesh) {
    double sum = 0.0;
    for (const auto& e : mesh.edge_vertex) sum += glm::length(mesh.positions[e[1]] - mesh.positions[e[0]]);
    return mesh.edge_count() ? sum / double(mesh.edge_count()) : 0.0;
}

}  // namespace

std::size_t MultiscaleLevels::bytes() const {
    return position.size() * sizeof(glm::vec3) + normal_oct.size() * sizeof(glm::vec2) +
           dir1_angle.size() * sizeof(float) + (k1.size() + k2.size()) * sizeof(float) +
           dcurv.size() * sizeof(std::array<float, 4>) + valid.size();
}

glm::vec3 MultiscaleLevels::normal(int k, std::size_t v) const { return octahedral_decode(normal_oct[at(k, v)]); }

glm::vec3 MultiscaleLevels::dir1(int k, std::size_t v) const {
    const std::size_t i = at(k, v);
    return direction_in_frame(octahedral_decode(normal_oct[i]), dir1_angle[i]);
}

MultiscaleLevels build_multiscale_levels(const Model& model, const MultiscaleOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const MeshTopology& mesh = model.topology();
    MultiscaleLevels out;
    out.ratio = options.ratio;
    out.vertices = mesh.vertex_count();
    out.feature_size = mean_edge_length(mesh);
    // (the model's own curvature and self-intersections, which a plain render computes too)
    int steps = 0;
    const int total_steps = options.build_steps();
    const auto step_done = [&] {
        if (options.progress) options.progress(++steps, total_steps);
    };
    const auto [mean0, median0] = abs_k1(model.curvature());
    out.mean_abs_k1.push_back(mean0);
    out.median_abs_k1.push_back(median0);
    const bool input_self_intersects = model.self_intersections().flagged > 0;
    out.seconds_model = seconds_since(t0);
    step_done();
    CollapseRecord record;
    std::vector<glm::dvec3> base;  // the smoothed base mesh's positions, where synthesis starts
    std::string why;
    const bool simplified = options.levels > 1 && simplify(mesh, options, record, base, why);
    out.collapses = record.count();
    out.base_vertices = out.vertices - out.collapses;
    if (options.levels > 1 && simplified && 2 * out.collapses < out.vertices)
        why = "only " + std::to_string(out.collapses) + " of its " + std::to_string(out.vertices) +
              " vertices can be removed by edge collapses (too small, or borders everywhere), so smoothed levels "
              "would smooth parts of it only";
    if (options.levels > 1 && !why.empty()) out.note = "only the input level: " + why;
    out.levels = options.levels > 1 && why.empty() ? options.levels : 1;
    step_done();

    const std::size_t stored = std::size_t(out.levels - 1) * out.vertices;
    out.position.resize(stored);
    out.normal_oct.resize(stored);
    out.dir1_angle.resize(stored);
    out.k1.resize(stored);
    out.k2.resize(stored);
    out.dcurv.resize(stored);
    out.valid.resize(stored);
    MeshTopology scratch;  // the level's positions with the model's connectivity, for the curvature
    if (out.levels > 1) scratch = mesh;
    out.levels_self_intersect = out.levels > 1 && input_self_intersects;
    std::vector<glm::dvec3> ring;
    std::unique_ptr<LevelSmoother> smoother;
    if (out.levels > 1 && options.smoothing > 0.0) smoother = std::make_unique<LevelSmoother>(mesh);
    const std::vector<double> thickness =
        smoother && options.thin_guard > 0.0 ? smoother->thickness(mesh.positions) : std::vector<double>();
    std::vector<double> anchor;
    for (int k = 1; k < out.levels; ++k) {
        const auto with_detail = std::size_t(std::floor(std::pow(out.ratio, k) * double(out.collapses)));
        scratch.positions = base;
        synthesize(record, options.spread, with_detail, scratch.positions, ring);
        if (with_detail < out.collapses) {  // (a level with every detail is the input: nothing to smooth)
            relax_level(record, options.spread, options.sweeps, scratch.positions);
            tangential_level(record, options.tangential_sweeps, scratch.positions);
        }
        if (smoother) {
            const double t = options.smoothing * std::pow(options.smoothing_growth, k - 1);
            anchor.clear();
            if (options.thin_guard > 0.0) {  // reach min(sigma_k, thin_guard tau): t / w = t (thin_guard tau / sigma_k)^(2 order)
                const double reach = out.feature_size * std::pow(t, 0.5 / options.smoothing_order);
                anchor.resize(out.vertices);
                for (std::size_t v = 0; v < out.vertices; ++v)
                    anchor[v] = std::max(1.0, std::pow(reach / (options.thin_guard * thickness[v]), 2.0 * options.smoothing_order));
            }
            smoother->smooth(t, options.smoothing_order, anchor, scratch.positions);
        }
        const CurvatureField field = estimate_curvature(scratch);
        store_level(out, k, scratch.positions, field);
        const auto [mean, median] = abs_k1(field);
        out.mean_abs_k1.push_back(mean);
        out.median_abs_k1.push_back(median);
        // Only the smoothest level is searched (a second each at 200 k faces): the levels between
        // it and the input smooth less, and a view that finds the blend self-intersecting where
        // neither does would need a search per view (docs/detail.md).
        if (!out.levels_self_intersect && k == out.levels - 1) {
            scratch.refresh_geometry();
            const std::vector<std::uint8_t> pierced = self_intersecting_faces(scratch);
            out.levels_self_intersect = std::ranges::any_of(pierced, [](std::uint8_t f) { return f != 0; });
        }
        step_done();
    }
    if (options.progress && steps < total_steps) options.progress(total_steps, total_steps);  // fewer levels built
    out.seconds = seconds_since(t0);
    return out;
}

std::vector<glm::dvec3> level_positions(const Model& model, const MultiscaleLevels& levels, int k) {
    if (k <= 0) return model.topology().positions;
    std::vector<glm::dvec3> out(levels.vertices);
    for (std::size_t v = 0; v < levels.vertices; ++v) out[v] = glm::dvec3(levels.position[levels.at(k, v)]);
    return out;
}

MultiscaleOptions thin_guarded(MultiscaleOptions o, bool keep_ratio, bool keep_fairing) {
    if (!keep_ratio) o.ratio = 0.75;
    if (!keep_fairing) o.fairing = MultiscaleFairing::SecondOrder;
    if (o.fairing == MultiscaleFairing::SecondOrder) o.sweeps = 8, o.tangential_sweeps = 32;
    o.smoothing = 4.0;
    o.smoothing_growth = 16.0;
    o.smoothing_order = 2;
    o.thin_guard = 0.1;
    return o;
}

}  // namespace inkline
