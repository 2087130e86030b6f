#include "visibility/appel.hpp"
#include "visibility/appel_phases.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <climits>
#include <cstring>
#include <functional>
#include <future>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "core/clock.hpp"
#include "core/predicates.hpp"
#include "model/orientation.hpp"
#include "visibility/fast_orient.hpp"

namespace inkline {
namespace {

glm::dvec3 third_vertex(const MeshTopology& mesh, std::uint32_t face, std::uint32_t edge) {
    const auto& f = mesh.faces[face];
    const auto& ev = mesh.edge_vertex[edge];
    for (std::uint32_t v : f)
        if (v != ev[0] && v != ev[1]) return mesh.positions[v];
    return mesh.positions[f[0]];
}

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Exact sign of the orientation of (a, b, c): positive when c is left of the directed line a -> b.
int orient2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) { return orient2_fast(a, b, c); }

// orient_eye (exact, with an inlined float filter).
int eye_side(const Camera& camera, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return orient_eye_fast(camera, a, b, c);
}

// Sorts keys (high 32 bits: the sort key, below 2^bits; low 32 bits: increasing in input order)
// by their high bits, stably: the same order as std::sort on the whole keys, by LSD radix passes.
void sort_keys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& tmp, int bits) {
    if (keys.size() < 256) {
        std::sort(keys.begin(), keys.end());
        return;
    }
    constexpr int kDigit = 11;
    tmp.resize(keys.size());
    std::vector<std::uint32_t> count(std::size_t(1) << kDigit);
    for (int shift = 32; shift < 32 + bits; shift += kDigit) {
        std::fill(count.begin(), count.end(), 0u);
        for (const std::uint64_t k : keys) ++count[(k >> shift) & ((1u << kDigit) - 1)];
        std::uint32_t sum = 0;
        for (auto& c : count) {
            const std::uint32_t n = c;
            c = sum;
            sum += n;
        }
        for (const std::uint64_t k : keys) tmp[count[(k >> shift) & ((1u << kDigit) - 1)]++] = k;
        keys.swap(tmp);
    }
}
int bit_width(std::size_t n) {
    int b = 0;
    while (n >> b) ++b;
    return b;
}

// A set of mesh edges, one bit each.
class EdgeMarks {
public:
    explicit EdgeMarks(std::size_t n) : bits_(n / 64 + 1, 0) {}
    void set(std::uint32_t e) { bits_[e >> 6] |= std::uint64_t(1) << (e & 63); }
    bool test(std::uint32_t e) const { return bits_[e >> 6] >> (e & 63) & 1; }
    void clear() { std::fill(bits_.begin(), bits_.end(), 0); }

private:
    std::vector<std::uint64_t> bits_;
};

// A cross product p x q kept for exact sign tests of x . (p x q) = det[x, p, q]: the products'
// magnitudes give the forward error bound of orient3_fast (the same evaluation with the rows
// cyclically permuted: the bound does not depend on which row is outside the cross product).
struct Cross {
    glm::dvec3 c{0.0};     // p x q, rounded
    glm::dvec3 perm{0.0};  // |p.y q.z| + |p.z q.y|, |p.z q.x| + |p.x q.z|, |p.x q.y| + |p.y q.x|
};
inline Cross cross_of(const glm::dvec3& p, const glm::dvec3& q) {
    const double m0 = p.y * q.z, m1 = p.z * q.y, m2 = p.z * q.x, m3 = p.x * q.z, m4 = p.x * q.y, m5 = p.y * q.x;
    return {{m0 - m1, m2 - m3, m4 - m5},
            {std::abs(m0) + std::abs(m1), std::abs(m2) + std::abs(m3), std::abs(m4) + std::abs(m5)}};
}
// Sign of x . (p x q) where the float evaluation decides (orient3_fast's bound), 2 otherwise.
inline int filtered_sign(const glm::dvec3& x, const Cross& k) {
    const double det = x.x * k.c.x + x.y * k.c.y + x.z * k.c.z;
    const double perm = std::abs(x.x) * k.perm.x + std::abs(x.y) * k.perm.y + std::abs(x.z) * k.perm.z;
    const double bound = 16.0 * 1.1102230246251565e-16 * perm + 0x1p-1022 * (1.0 + std::abs(x.x) + std::abs(x.y) + std::abs(x.z));
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return 2;
}

// Two doubles per step (GCC/Clang vector extensions: SSE2 on x86-64, the baseline; plain code
// elsewhere). Lanes compute exactly what the scalar expressions would, operation by operation.
using V2 = double __attribute__((vector_size(16)));
using V2i = decltype(V2{} < V2{});  // the lanes of a comparison: 64-bit integers, -1 or 0
inline V2 load2(const double* p) {
    V2 r;
    std::memcpy(&r, p, sizeof r);
    return r;
}
inline void store2(double* p, V2 x) { std::memcpy(p, &x, sizeof x); }
inline V2 splat(double x) { return V2{x, x}; }
inline V2 vabs(V2 x) { return (V2)((V2i)x & (V2i{} + LLONG_MAX)); }

// The faces around a vertex v, each with its facing, its other corners A, B in the face's order
// (v, A, B), and orient_eye(v, A, B) (1 for a front face; 0: seen exactly edge-on).
// Perspective views also keep A - v and B - v (rounded, with their magnitudes and the absolute
// term of the filter's bound for each) and the cross product n = (A - v) x (B - v): the three
// tests of local_occlusion are then one dot product each (see there). These are kept field by
// field for pairs of faces (faces 2p and 2p + 1: block p, each field two doubles; the count padded
// to even), so that two faces are tested per step.
struct Ring {
    // The perspective fields (in each block of `data`).
    enum Field {
        kAx, kAy, kAz, kBx, kBy, kBz,  // a = A - v, b = B - v
        kAax, kAay, kAaz, kAbx, kAby, kAbz,  // |a|, |b|
        kTinyA, kTinyB,  // the bound's absolute terms (filtered_sign) for x = a, x = b
        kNx, kNy, kNz, kPx, kPy, kPz,  // n = a x b: Cross::c, Cross::perm
        kFront, kEye,  // 1 front, -1 not; orient_eye(v, A, B)
        kFields
    };
    std::size_t size = 0;
    bool fast = false;  // perspective: the fields are set
    glm::dvec3 to_eye{0.0};  // E - v
    std::vector<std::uint32_t> face;
    std::vector<std::uint32_t> front;  // 1: front (not a char type: stores to it then alias nothing)
    std::vector<int> eye;
    std::vector<const glm::dvec3*> A, B;
    std::vector<double> data;
    std::size_t cap = 0;
    static constexpr std::size_t kBlock = 2 * kFields;
    // Field k of faces i, i + 1 (i even): data[(i / 2) kBlock + 2 k], the next.
    // Room for n faces (storage reused from ring to ring).
    void reserve(std::size_t n) {
        if (n <= cap && n <= face.size()) return;
        const std::size_t c = std::max<std::size_t>(16, (n + 1) & ~std::size_t(1)) * 2;
        face.resize(c), front.resize(c), eye.resize(c), A.resize(c), B.resize(c);
        data.assign(c / 2 * kBlock, 0.0);
        cap = c;
    }
    bool any_edge_on() const { return std::find(eye.begin(), eye.begin() + std::ptrdiff_t(size), 0) != eye.begin() + std::ptrdiff_t(size); }
};
// |x| per component (std::abs: without branches, unlike glm::abs, whose sign tests of data are
// mispredicted).
inline glm::dvec3 abs3(const glm::dvec3& x) { return {std::abs(x.x), std::abs(x.y), std::abs(x.z)}; }
// filtered_sign's absolute term for the row x outside the cross product, from |x|.
inline double tiny_term(const glm::dvec3& abs_x) { return 0x1p-1022 * (1.0 + abs_x.x + abs_x.y + abs_x.z); }
// Prefetches (no effect on results) what ring_of reads for the vertices verts[g + d] ahead of the
// one at verts[g], one level of its chain of dependent loads per distance (vertex -> its edges ->
// their faces -> the faces' corners -> their positions): the rings' vertices are scattered over a
// large mesh, and each level's addresses come from the level before, which ring_of would
// otherwise wait for one load at a time. Each level reads only what the level before prefetched
// two steps earlier.
inline void prefetch_rings(const MeshTopology& mesh, const std::vector<std::uint32_t>& verts, std::size_t g) {
    const std::size_t n = verts.size();
    if (g + 8 < n) {
        const std::uint32_t v = verts[g + 8];
        __builtin_prefetch(&mesh.vertex_edge_begin[v]);
        __builtin_prefetch(&mesh.positions[v]);
    }
    if (g + 6 < n) {
        const std::uint32_t v = verts[g + 6];
        const std::uint32_t b = mesh.vertex_edge_begin[v], e = mesh.vertex_edge_begin[v + 1];
        __builtin_prefetch(&mesh.vertex_edges[b]);
        __builtin_prefetch(&mesh.vertex_edges[e - 1]);
    }
    if (g + 4 < n) {
        const std::uint32_t v = verts[g + 4];
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint32_t e = mesh.vertex_edges[k];
            __builtin_prefetch(&mesh.edge_vertex[e]);
            __builtin_prefetch(&mesh.edge_face[e]);
        }
    }
    if (g + 2 < n) {
        const std::uint32_t v = verts[g + 2];
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint32_t e = mesh.vertex_edges[k];
            const std::uint32_t f = mesh.edge_vertex[e][0] == v ? mesh.edge_face[e][0] : mesh.edge_face[e][1];
            if (f != kNoFace) __builtin_prefetch(&mesh.faces[f]);
        }
    }
    if (g + 1 < n) {
        const std::uint32_t v = verts[g + 1];
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint32_t e = mesh.vertex_edges[k];
            const std::uint32_t f = mesh.edge_vertex[e][0] == v ? mesh.edge_face[e][0] : mesh.edge_face[e][1];
            if (f == kNoFace) continue;
            // the corner after v in the face (the one before is the corner after v in another face)
            const auto& c = mesh.faces[f];
            __builtin_prefetch(&mesh.positions[c[0] == v ? c[1] : c[1] == v ? c[2] : c[0]]);
        }
    }
}

void ring_of(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front, std::uint32_t v,
             Ring& ring) {
    const bool fast = !camera.is_ortho();
    ring.size = 0;
    ring.fast = fast;
    const glm::dvec3 V = mesh.positions[v];  // (a copy: not read again after each store)
    const std::uint32_t k0 = mesh.vertex_edge_begin[v], k1 = mesh.vertex_edge_begin[v + 1];
    ring.reserve(k1 - k0 + 1);
    std::size_t n = 0;
    // (The arrays' addresses in locals: the stores below would otherwise make the compiler load
    // them again for every face.)
    const std::uint32_t* const vertex_edges = mesh.vertex_edges.data();
    const auto* const edge_vertex = mesh.edge_vertex.data();
    const auto* const edge_face = mesh.edge_face.data();
    const auto* const faces = mesh.faces.data();
    const glm::dvec3* const positions = mesh.positions.data();
    std::uint32_t* const ring_face = ring.face.data();
    std::uint32_t* const ring_front = ring.front.data();
    int* const ring_eye = ring.eye.data();
    const glm::dvec3** const ring_A = ring.A.data();
    const glm::dvec3** const ring_B = ring.B.data();
    double* const ring_data = ring.data.data();
    // On a non-orientable mesh, the faces around v from for_each_face_around (a seam edge may give
    // two faces or none), as a list the loop below reads; else the loop finds them itself.
    thread_local std::vector<std::uint32_t> seam_ring;
    const bool seams = !mesh.seam_list.empty();
    if (seams) {
        seam_ring.clear();
        for_each_face_around(mesh, v, [&](std::uint32_t f) { seam_ring.push_back(f); });
    }
    const std::uint32_t n_ring = seams ? std::uint32_t(seam_ring.size()) : k1 - k0;
    for (std::uint32_t k = 0; k < n_ring; ++k) {
        std::uint32_t f;
        if (seams) {
            f = seam_ring[k];
        } else {
            const std::uint32_t g = vertex_edges[k0 + k];
            // each face around v once: the one traversing g away from v
            f = edge_vertex[g][0] == v ? edge_face[g][0] : edge_face[g][1];
            if (f == kNoFace) continue;
        }
        const auto& c = faces[f];
        const int i = c[0] == v ? 0 : c[1] == v ? 1 : 2;
        const bool front = face_front[f];
        const glm::dvec3 *A = &positions[c[(i + 1) % 3]], *B = &positions[c[(i + 2) % 3]];
        ring_face[n] = f, ring_front[n] = front, ring_eye[n] = 1, ring_A[n] = A, ring_B[n] = B;
        if (fast) {
            double* const d = ring_data + (n >> 1) * Ring::kBlock + (n & 1);
            d[2 * Ring::kAx] = A->x - V.x, d[2 * Ring::kAy] = A->y - V.y, d[2 * Ring::kAz] = A->z - V.z;
            d[2 * Ring::kBx] = B->x - V.x, d[2 * Ring::kBy] = B->y - V.y, d[2 * Ring::kBz] = B->z - V.z;
            d[2 * Ring::kFront] = front ? 1.0 : -1.0;
        } else if (!front) {
            ring_eye[n] = orient_eye_fast(camera, V, *A, *B);
        }
        ++n;
    }
    ring.size = n;
    if (!ring.fast) return;
    ring.to_eye = camera.eye() - V;
    if (n & 1)  // the padding face: zero offsets (the filters cannot decide it; never read further)
        for (int k = Ring::kAx; k <= Ring::kBz; ++k) ring_data[(n >> 1) * Ring::kBlock + 2 * std::size_t(k) + 1] = 0.0;
    // Per face, two at a time: |a|, |b|, the absolute terms, n = a x b (cross_of), and the filtered
    // sign of orient_eye(V, A, B) = sign (E - V) . n (filtered_sign), the same operations in the
    // same order as the scalar functions.
    const glm::dvec3 te = ring.to_eye, ate = abs3(te);
    constexpr double kRel = 16.0 * 1.1102230246251565e-16;
    const V2 tx = splat(te.x), ty = splat(te.y), tz = splat(te.z), atx = splat(ate.x), aty = splat(ate.y), atz = splat(ate.z);
    const V2 eye_tiny = splat(0x1p-1022 * (1.0 + ate.x + ate.y + ate.z));
    const V2 rel = splat(kRel), tiny = splat(0x1p-1022), one = splat(1.0);
    double* const blocks = ring.data.data();
    for (std::size_t i = 0; i < n; i += 2) {
        double* const blk = blocks + (i >> 1) * Ring::kBlock;
        auto at = [&](Ring::Field k) { return blk + 2 * k; };
        const V2 ax = load2(at(Ring::kAx)), ay = load2(at(Ring::kAy)), az = load2(at(Ring::kAz));
        const V2 bx = load2(at(Ring::kBx)), by = load2(at(Ring::kBy)), bz = load2(at(Ring::kBz));
        const V2 aax = vabs(ax), aay = vabs(ay), aaz = vabs(az), abx = vabs(bx), aby = vabs(by), abz = vabs(bz);
        store2(at(Ring::kAax), aax), store2(at(Ring::kAay), aay), store2(at(Ring::kAaz), aaz);
        store2(at(Ring::kAbx), abx), store2(at(Ring::kAby), aby), store2(at(Ring::kAbz), abz);
        store2(at(Ring::kTinyA), tiny * (one + aax + aay + aaz));
        store2(at(Ring::kTinyB), tiny * (one + abx + aby + abz));
        const V2 m0 = ay * bz, m1 = az * by, m2 = az * bx, m3 = ax * bz, m4 = ax * by, m5 = ay * bx;
        const V2 nx = m0 - m1, ny = m2 - m3, nz = m4 - m5;
        const V2 px = vabs(m0) + vabs(m1), py = vabs(m2) + vabs(m3), pz = vabs(m4) + vabs(m5);
        store2(at(Ring::kNx), nx), store2(at(Ring::kNy), ny), store2(at(Ring::kNz), nz);
        store2(at(Ring::kPx), px), store2(at(Ring::kPy), py), store2(at(Ring::kPz), pz);
        const V2 det = tx * nx + ty * ny + tz * nz;
        const V2 bound = rel * (atx * px + aty * py + atz * pz) + eye_tiny;
        const V2i s = (det < -bound) - (det > bound);  // 1, -1, or 0: undecided
        for (std::size_t l = 0; l < 2; ++l) {
            const std::size_t j = i + l;
            if (j == n) {
                at(Ring::kEye)[l] = 0.0;  // (the padding face)
                break;
            }
            if (!ring_front[j]) {
                const int e = int(s[l]);
                ring_eye[j] = e != 0 ? e : orient3(V, *ring_A[j], *ring_B[j], camera.eye());
            }
            at(Ring::kEye)[l] = double(ring_eye[j]);
        }
    }
}

// Whether ring face j hides the points of edge (V, W) near V: the eye and those points on opposite
// sides of the face's plane (the eye's side is the face's facing, known), and the line of sight
// through them inside the face's corner at V: W seen between the planes (eye, V, A) and
// (eye, V, B), on the side of the other corner of each. The first is the face's facing,
// orient_eye(V, A, B): 1 for a front face; a face not in front may still hold the eye in its
// plane (0: it hides nothing). The second is its opposite, orient_eye(V, B, A).
bool face_hides(const Camera& camera, const Ring& ring, std::size_t j, const glm::dvec3& V, const glm::dvec3& W) {
    const glm::dvec3 &A = *ring.A[j], &B = *ring.B[j];
    const bool front = ring.front[j];
    const int edge_side = orient3_fast(V, A, B, W);  // (V, A, B): the face's corners in its order
    if (edge_side == 0 || (edge_side > 0) == front) return false;
    const int ba = ring.eye[j];
    if (ba == 0) return false;
    return eye_side(camera, V, A, W) == ba && eye_side(camera, V, B, W) == -ba;
}

// local_occlusion (appel.hpp) with the ring of faces around v.
// Perspective: the three tests of a face (with W the far end of the curve's edge, E the eye) are
//   orient3(V, A, B, W) = sign det[W - V, A - V, B - V] = sign (W - V) . n,   n = (A - V) x (B - V),
//   orient3(V, A, W, E) = sign det[A - V, W - V, E - V] = sign (A - V) . m,   m = (W - V) x (E - V),
//   orient3(V, B, W, E) = sign (B - V) . m,
// n per ring face, m per curve end (one cross product, where the wedge tests had one per corner),
// then one dot product per test, each decided by the float filter (filtered_sign's bound: the
// bound of orient3_fast on these same rounded differences from V, whose rows are here in another
// cyclic order, which changes neither the determinant nor the bound) or else by the exact orient3
// on the same points (face_hides). So each sign is the exact one and the count is the same. The
// three tests of two faces at a time are evaluated at once, without branches (the outcome of each
// is data, hard to predict); a face where a filter cannot decide takes face_hides, exact.
int local_occlusion(const MeshTopology& mesh, const Camera& camera, Ring& ring, std::uint32_t v, std::uint32_t edge) {
    const auto& ev = mesh.edge_vertex[edge];
    const std::uint32_t f0 = mesh.edge_face[edge][0], f1 = mesh.edge_face[edge][1];
    const glm::dvec3& V = mesh.positions[v];
    const glm::dvec3& W = mesh.positions[ev[0] == v ? ev[1] : ev[0]];
    const std::size_t n = ring.size;
    int count = 0;
    if (!ring.fast) {
        for (std::size_t j = 0; j < n; ++j)
            if (ring.face[j] != f0 && ring.face[j] != f1) count += face_hides(camera, ring, j, V, W);
        return count;
    }
    const glm::dvec3 w = W - V, aw = abs3(w);
    const Cross m = cross_of(w, ring.to_eye);
    constexpr double kRel = 16.0 * 1.1102230246251565e-16;  // filtered_sign's relative bound
    const V2 mx = splat(m.c.x), my = splat(m.c.y), mz = splat(m.c.z);
    const V2 qx = splat(m.perm.x), qy = splat(m.perm.y), qz = splat(m.perm.z);
    const V2 wx = splat(w.x), wy = splat(w.y), wz = splat(w.z), awx = splat(aw.x), awy = splat(aw.y), awz = splat(aw.z);
    const V2 rel = splat(kRel), tiny_w = splat(tiny_term(aw)), zero = splat(0.0);
    const double* const blocks = ring.data.data();
    const std::uint32_t* const ring_face = ring.face.data();
    // Faces [c, c + 64) at a time: bit j - c of `hidden` (decided, hiding), `undecided`.
    // The edge's own faces (f0, f1: W is a corner A or B of theirs) are never decided (so they
    // never count): for them w = W - V is bitwise the same rounded difference as a (or b), so the exact
    // determinants det[w, a, b] and det[a, w, E - V] (or det[b, w, E - V]) of these rounded
    // values are 0, and a filter's bound is at least the error of its float value: |dn| > bn and
    // |da| > ba (or |db| > bb) fail. They are skipped where the undecided faces are.
    for (std::size_t c = 0; c < n; c += 64) {
        const std::size_t c1 = std::min(n, c + 64);
        std::uint64_t hidden = 0, undecided = 0;
        for (std::size_t i = c; i < c1; i += 2) {
            const double* const blk = blocks + (i >> 1) * Ring::kBlock;
            auto at = [&](Ring::Field k) { return load2(blk + 2 * k); };
            const V2 da = at(Ring::kAx) * mx + at(Ring::kAy) * my + at(Ring::kAz) * mz;
            const V2 db = at(Ring::kBx) * mx + at(Ring::kBy) * my + at(Ring::kBz) * mz;
            const V2 dn = wx * at(Ring::kNx) + wy * at(Ring::kNy) + wz * at(Ring::kNz);
            const V2 ba = rel * (at(Ring::kAax) * qx + at(Ring::kAay) * qy + at(Ring::kAaz) * qz) + at(Ring::kTinyA);
            const V2 bb = rel * (at(Ring::kAbx) * qx + at(Ring::kAby) * qy + at(Ring::kAbz) * qz) + at(Ring::kTinyB);
            const V2 bn = rel * (awx * at(Ring::kPx) + awy * at(Ring::kPy) + awz * at(Ring::kPz)) + tiny_w;
            const V2i decided = (vabs(da) > ba) & (vabs(db) > bb) & (vabs(dn) > bn);
            // All three signs decided (none is 0): the face hides the edge when W is behind its plane
            // (the side opposite its facing: dn . front < 0), and inside its corner (sides eye, -eye
            // of its two edges at V: da . eye > 0, db . eye < 0; none with eye 0). Products with
            // +-1 and 0: exact.
            const V2 e = at(Ring::kEye);
            const V2i hides = (dn * at(Ring::kFront) < zero) & (da * e > zero) & (db * e < zero);
            const V2i lane_bit = {1, 2};
            const V2i h = hides & decided & lane_bit, u = ~decided & lane_bit;
            hidden |= std::uint64_t(h[0] | h[1]) << (i - c);
            undecided |= std::uint64_t(u[0] | u[1]) << (i - c);
        }
        // (the padding face's bit, undecided, is past n: masked off)
        const std::uint64_t live = c1 - c == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << (c1 - c)) - 1;
        count += std::popcount(hidden);
        for (std::uint64_t rest = undecided & live; rest != 0; rest &= rest - 1) {
            const std::size_t j = c + std::size_t(std::countr_zero(rest));
            if (ring_face[j] != f0 && ring_face[j] != f1) count += face_hides(camera, ring, j, V, W);
        }
    }
    return count;
}


// The image turned (by exact sign changes and a swap of the axes) so that the walk's path runs
// from u toward -x: every test on the path is then a comparison with u.y, or an orientation in
// these coordinates.
// (Dir: the turn, a template argument: the walk's inner loop turns every vertex it meets.)
template <int Dir>
struct PathFrame {
    static constexpr int dir = Dir;  // 0: toward min x, 1: max x, 2: min y, 3: max y (in the image)
    // The sign of the turned frame's orientations relative to the image's.
    static constexpr int det() { return dir == 0 || dir == 3 ? 1 : -1; }
    glm::dvec2 operator()(glm::dvec2 p) const {
        if constexpr (dir == 0) return p;
        else if constexpr (dir == 1) return {-p.x, p.y};
        else if constexpr (dir == 2) return {p.y, p.x};
        else return {-p.y, p.x};
    }
};

// Section 4.4: is the point U (P in 3D, u in the image) hidden by a layer of surface enclosing it?
// Every layer over u, followed from u along a straight path out of the occluders' box `box`
// (min x, max x, min y, max y; the path goes to the nearest side), ends at a silhouette or border
// crossing that path. From each such crossing V, walk the surface branches of the occluder back
// along the path, face by face, in the image; a branch that reaches u is depth-tested against U
// (exact orientation); a branch that folds (silhouette) or ends (border) on the way is not the
// layer over u. The path is axis-parallel, so whether a projected vertex lies above or below it is
// an exact comparison; where the path meets an edge, before or after u, is an exact orientation.
// Degenerate paths (through a vertex, u on an edge) fail: the caller then makes a ray test.
// (One walk along the path in direction Dir. cross_path and follow_branch are inlined into
// walk_to; walk_faces, the inner loop, is kept out of line: inlined too, it made the compiler
// stop inlining the vertex images' lookup in the loop, which then cost more instructions.)
template <int Dir>
struct PathWalk {
    const MeshTopology& mesh;
    const Camera& camera;
    const FaceFacing& face_front;
    const VertexImages& proj;
    const glm::dvec3& P;
    std::uint32_t own_edge;
    PathFrame<Dir> T;
    glm::dvec2 ut;  // u in the turned frame
    struct Crossed {
        double d;  // how far from u along the path (in float: only an order)
        std::uint32_t k;
        glm::dvec2 a, b;  // the occluder in the turned frame, a below the path
    };

    // The occluders crossing the path before u (other than U's own edge), into `crossed`;
    // Failed where one touches the path's line degenerately.
    [[gnu::always_inline]] inline Walk cross_path(const PieceGraph& g, const Segment2& path, std::vector<Crossed>& crossed) const {
        const glm::dvec2 ut = this->ut;  // (a local: crossed's stores could otherwise be the field)
        Walk result = Walk::Visible;
        g.occluder_grid().candidates(path, [&](std::uint32_t k) {
            if (result != Walk::Visible) return;
            const Segment2& o = g.occluders[k];
            if (o.edge == own_edge) return;
            // Does the occluder cross the path (the half-line y = u.y, x < u.x, in the turned frame)?
            glm::dvec2 a = T(o.a), b = T(o.b);
            if ((a.y > ut.y && b.y > ut.y) || (a.y < ut.y && b.y < ut.y)) return;
            if (a.y == ut.y || b.y == ut.y) {  // an end on the path's line: degenerate unless beyond u
                if ((a.y == ut.y && a.x <= ut.x) || (b.y == ut.y && b.x <= ut.x)) result = Walk::Failed;
                else if (a.y == b.y) result = Walk::Failed;  // on the line, both ends beyond u: cannot happen
                return;
            }
            if (a.y > b.y) std::swap(a, b);  // a below the path, b above
            const int su = path_side_fast(a, b, ut);  // < 0: u right of a -> b, the crossing before u
            if (su == 0) {
                result = Walk::Failed;
                return;
            }
            if (su > 0) return;
            // Where (in float: only an order) the path meets the occluder, away from u.
            crossed.push_back({ut.x - (a.x + (ut.y - a.y) / (b.y - a.y) * (b.x - a.x)), k, a, b});
        });
        return result;
    }

    // The branch of face f of the occluder (edge `edge`, crossing the path between a and b),
    // walked toward u if it lies on u's side of the occluder's image: Occluded when it reaches u
    // in front of U, Visible when it does not (ends, folds, or is U's own layer).
    [[gnu::always_inline]] inline Walk follow_branch(std::uint32_t f, std::uint32_t edge, glm::dvec2 a, glm::dvec2 b) const {
        const auto& fv = mesh.faces[f];
        const auto& fe = mesh.face_edges[f].edge;
        const int i_in = fe[0] == edge ? 0 : fe[1] == edge ? 1 : 2;
        const glm::dvec2 ut = this->ut;
        const int st = orient2(a, b, T(proj(fv[(i_in + 2) % 3])));
        if (st == 0) return Walk::Failed;
        if (st != -1) return Walk::Visible;  // (on the other side of the occluder)
        // Walk from the crossing toward u over the faces: the path enters each face by one
        // edge and leaves by one of the other two, the one joining the third corner to the
        // entry corner on the other side of the path.
        // The branch keeps its facing (it ends at folds): faces facing the same way have
        // images of the same orientation (front-facing: clockwise in the image, whose y axis
        // points down), so that the path goes on across each edge; rounding may flip a face
        // seen nearly edge-on: then give up. The images of the entry edge's ends carry over
        // from face to face.
        const bool front = face_front[f];
        const glm::dvec2 pa = T(proj(fv[i_in])), pb = T(proj(fv[(i_in + 1) % 3]));
        // Whether the entry edge's ends lie strictly on either side of the path's line (they
        // are a and b unless the occluder was clipped): then so do every exit edge's ends (the
        // third corner, strictly off the line, and the entry corner across it), as
        // path_side_fast requires; otherwise orient2 decides every step of this branch.
        const bool straddles = (pa.y < ut.y && pb.y > ut.y) || (pa.y > ut.y && pb.y < ut.y);
        return walk_faces(f, i_in, fv[i_in], pa, pb, front, straddles);
    }

    // The branch's faces from `face`, entered by its edge (corner entry, corner entry + 1) whose
    // ends are va (image pa) and the other one (pb), to u or to where the layer ends or folds.
    // The step is written with few data-dependent branches (which way the path leaves a face is
    // as good as random): each choice below is a select of values that are all computed, and
    // every test is the same exact predicate as a plain evaluation would make (see the comments),
    // so the walk takes the same faces and gives the same result.
    [[gnu::noinline]] Walk walk_faces(std::uint32_t face, int entry, std::uint32_t va, glm::dvec2 pa, glm::dvec2 pb,
                                                 bool front, bool straddles) const {
        // (The fields as locals: the step's stores (a vertex image made on first use by proj, a
        // facing decided on first read) could otherwise be this walk's fields for the compiler,
        // which would read them again at every step.)
        const glm::dvec2 ut = this->ut;
        const MeshTopology& mesh = this->mesh;
        const Camera& camera = this->camera;
        const FaceFacing& face_front = this->face_front;
        const VertexImages& proj = this->proj;
        const glm::dvec3& P = this->P;
        const std::uint32_t own_edge = this->own_edge;
        int want = front ? -T.det() : T.det();
        const bool seams = !mesh.seam_list.empty();
        const auto& own_faces = mesh.edge_face[own_edge];
        static constexpr int kNext[5] = {1, 2, 0, 1, 2};  // kNext[i] = (i + 1) % 3 for i < 5
        for (std::size_t guard = 0, face_count = mesh.face_count(); guard < face_count; ++guard) {
            const auto& c = mesh.faces[face];
            const auto& fe = mesh.face_edges[face];
            const int e1 = kNext[entry], e2 = kNext[entry + 1];
            const std::uint32_t v0 = c[entry], v1 = c[e1], v2 = c[e2];
            const std::uint32_t g1 = fe.face[e1], g2 = fe.face[e2];  // across either exit edge
            // The entry edge's ends are va and the other one, in either order (v0 is one of them).
            const bool same = v0 == va;
            const glm::dvec2 p0 = same ? pa : pb, p1 = same ? pb : pa, p2 = T(proj(v2));
            {
                // (The faces after this one, across either exit edge, fetched while the exit
                // is decided: on a large mesh the next step's reads then need not wait.)
                const std::uint32_t n1 = g1 == kNoFace ? face : g1, n2 = g2 == kNoFace ? face : g2;
                __builtin_prefetch(&mesh.faces[n1]);
                __builtin_prefetch(&mesh.face_edges[n1]);
                __builtin_prefetch(&mesh.faces[n2]);
                __builtin_prefetch(&mesh.face_edges[n2]);
            }
            if (p2.y == ut.y) return Walk::Failed;  // the path through a vertex
            if (orient2(p0, p1, p2) != want) return Walk::Failed;
            // The exit edge (q0, q1) joins the third corner p2 to the entry corner across the path.
            const bool via1 = (p1.y > ut.y) != (p2.y > ut.y);  // exit (p1, p2), else (p2, p0)
            const glm::dvec2 q0 = via1 ? p1 : p2, q1 = via1 ? p2 : p0;
            const std::uint32_t exit = fe.edge[via1 ? e1 : e2];
            // Where the path meets it, before or after u: the orientation of (lower end, upper
            // end, u), the ends swapped when q0.y > q1.y. orient2 is exact, so swapping its first
            // two points exactly negates it: the sign with (q0, q1) in their order, negated then.
            // (path_side_fast: comparisons decide it where both ends lie before u, or after it.)
            const int se = straddles ? path_side_fast(q0, q1, ut) : (q0.y > q1.y ? -1 : 1) * orient2(q0, q1, ut);
            if (se == 0)  // u on U's own edge, from one of its faces: U's layer; or u on another edge
                return exit == own_edge ? Walk::Visible : Walk::Failed;
            if (se > 0) {
                // The path reaches u inside this face: the depth test decides. U's own faces
                // are U's layer, not in front of it (P, rounded onto the edge, cannot be
                // tested against their planes).
                if (face == own_faces[0] || face == own_faces[1]) return Walk::Visible;
                const glm::dvec3 &A = mesh.positions[c[0]], &B = mesh.positions[c[1]], &C = mesh.positions[c[2]];
                const int eye = orient_eye_fast(camera, A, B, C), pt = orient3_fast(A, B, C, P);
                if (eye == 0 || pt == 0) return Walk::Failed;
                return eye != pt ? Walk::Occluded : Walk::Visible;
            }
            const std::uint32_t next = via1 ? g1 : g2;
            if (next == kNoFace) return Walk::Visible;  // the layer ends before u
            face = next;                                // the other face of the exit edge
            // Across an orientation seam the winding flips: so do the facing bit and the image
            // orientation of the same layer.
            if (seams && mesh.is_seam(exit)) front = !front, want = -want;
            if (bool(face_front[face]) != front) return Walk::Visible;  // or folds
            // The exit edge's corner in the next face (the three edges of a face differ).
            const auto& ne = mesh.face_edges[face].edge;
            entry = int(ne[1] == exit) + 2 * int(ne[2] == exit);
            va = via1 ? v1 : v2;
            pa = q0, pb = q1;
        }
        return Walk::Visible;
    }
};

template <int Dir>
Walk walk_to(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front, const PieceGraph& g,
             const VertexImages& proj, const glm::dvec3& P, glm::dvec2 u, std::uint32_t own_edge, const double box[4]) {
    const PathFrame<Dir> T;
    const PathWalk<Dir> walk{mesh, camera, face_front, proj, P, own_edge, T, T(u)};
    const glm::dvec2 end = Dir < 2 ? glm::dvec2(box[Dir], u.y) : glm::dvec2(u.x, box[Dir]);
    const Segment2 path{u, end, UINT32_MAX - 5, UINT32_MAX - 6, own_edge};
    using Crossed = typename PathWalk<Dir>::Crossed;
    thread_local std::vector<Crossed> crossed;  // (reused from walk to walk)
    crossed.clear();
    if (const Walk w = walk.cross_path(g, path, crossed); w != Walk::Visible) return w;
    // The branches from the nearest crossings first: they are the shortest, and one layer found
    // in front of U ends the walk.
    std::sort(crossed.begin(), crossed.end(), [](const Crossed& x, const Crossed& y) { return x.d < y.d; });
    for (const Crossed& x : crossed) {
        const std::uint32_t edge = g.occluders[x.k].edge;
        for (std::uint32_t f : mesh.edge_face[edge]) {
            if (f == kNoFace) continue;
            if (const Walk w = walk.follow_branch(f, edge, x.a, x.b); w != Walk::Visible) return w;
        }
    }
    return Walk::Visible;
}

// walk_to along the path to the nearest side of the box.
Walk walk_to(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front, const PieceGraph& g,
             const VertexImages& proj, const glm::dvec3& P, glm::dvec2 u, std::uint32_t own_edge, const double box[4]) {
    const double dist[4] = {u.x - box[0], box[1] - u.x, u.y - box[2], box[3] - u.y};
    switch (int(std::min_element(dist, dist + 4) - dist)) {
        case 0: return walk_to<0>(mesh, camera, face_front, g, proj, P, u, own_edge, box);
        case 1: return walk_to<1>(mesh, camera, face_front, g, proj, P, u, own_edge, box);
        case 2: return walk_to<2>(mesh, camera, face_front, g, proj, P, u, own_edge, box);
        default: return walk_to<3>(mesh, camera, face_front, g, proj, P, u, own_edge, box);
    }
}

}  // namespace

int local_occlusion(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                    std::uint32_t v, std::uint32_t edge) {
    Ring ring;
    ring_of(mesh, camera, face_front, v, ring);
    return local_occlusion(mesh, camera, ring, v, edge);
}

namespace {
// crossing_delta with the view's facing, if known (a front face needs no orientation test).
int occluder_delta(const MeshTopology& mesh, const Camera& camera, const FaceFacing* face_front, std::uint32_t occluder,
                   const glm::dvec3& c1, const glm::dvec3& c2) {
    const glm::dvec3& O1 = mesh.positions[mesh.edge_vertex[occluder][0]];
    const glm::dvec3& O2 = mesh.positions[mesh.edge_vertex[occluder][1]];
    // The occluder's line meets the line of sight at O, the curve at C. With P a plane through the
    // occluder and one curve end (not in the plane of the eye and the occluder), O lies between the
    // eye and C exactly when the eye and C are on opposite sides of P.
    int s1 = orient_eye_fast(camera, O1, O2, c1), s2 = orient_eye_fast(camera, O1, O2, c2);
    bool in_front;
    if (s1 != 0) {
        const int c = orient3_fast(O1, O2, c1, c2);
        in_front = c != 0 && s1 == -c;
    } else {
        const int c = orient3_fast(O1, O2, c2, c1);
        in_front = c != 0 && s2 == -c;
    }
    if (!in_front) return 0;
    // The curve enters the side of the occluder's image where its face(s) lie: more layers.
    // (edge_face[0] traverses the edge from edge_vertex[0] to [1]: this is its orientation.)
    const std::uint32_t f0 = mesh.edge_face[occluder][0];
    const int face_side = face_front && (*face_front)[f0] ? 1 : orient_eye_fast(camera, O1, O2, third_vertex(mesh, f0, occluder));
    const int after = s2 != 0 ? s2 : -s1;
    const int k = mesh.edge_face[occluder][1] == kNoFace ? 1 : 2;
    return after == face_side ? k : -k;
}
}  // namespace

int crossing_delta(const MeshTopology& mesh, const Camera& camera, std::uint32_t occluder, const glm::dvec3& c1,
                   const glm::dvec3& c2) {
    return occluder_delta(mesh, camera, nullptr, occluder, c1, c2);
}

AppelPropagation::AppelPropagation(const MeshTopology& mesh_, const Camera& camera_, const FaceFacing& face_front_,
                                   const std::function<const RayCaster&()>& ray_index_, PieceGraph& graph_,
                                   const AppelOptions& options_)
    : mesh(mesh_), camera(camera_), face_front(face_front_), ray_index(ray_index_), graph(graph_), options(options_),
      np(std::uint32_t(graph_.curves.pieces.size())), threads(std::clamp(options_.threads, 1, 1024)) {}

int AppelPropagation::ray_qi(std::uint32_t p) {
    if (!rays) rays = &ray_index();
    ++st.ray_tests;
    const auto t = StageClock::now();
    const int qi = qi_by_ray(mesh, camera, *rays, graph.curves.pieces[p], graph.curves.spans[p]);
    st.seconds_ray_tests += seconds_since(t);
    return qi;
}

AppelStats AppelPropagation::run() {
    if (graph.immersive) {
        ray_test_all();
        return st;
    }
    order_vertex_nodes();
    mark_pierced();
    crossing_deltas();
    unite_along_curves();
    // (The unions at vertices and the clusters beside the bounding-box rule's pass over the
    // spans, which needs neither: the same steps as one after the other.)
    std::vector<int> end_occlusion;
    local_occlusion_at_ends(end_occlusion);
    bounding_box_rule_beside([&] {
        unite_ends(end_occlusion);
        form_clusters();
    });
    apply_parity();
    // (The serial phases from here to the walks overlap the grid's build on a worker; joined
    // before anything else runs there, and before leaving, whatever is thrown.)
    struct JoinGrid {
        std::future<void>& f;
        ~JoinGrid() {
            if (f.valid()) f.wait();
        }
    } join_grid{grid_ready};
    start_occluder_grid();
    match_occluders();
    raise_by_constraints();
    open_upper_bounds();
    bound_above();
    survey_bounded();
    walk();
    ray_test_rest();
    settle();
    return st;
}

void AppelPropagation::ray_test_all() {
    for (std::uint32_t p = 0; p < np; ++p) graph.curves.pieces[p].qi = ray_qi(p);
}

void AppelPropagation::order_vertex_nodes() {
    const auto& ends = graph.ends;
    end_order.resize(ends.size());
    for (std::size_t i = 0; i < ends.size(); ++i) end_order[i] = std::uint64_t(ends[i].vertex) << 32 | i;
    sort_keys(end_order, sort_tmp, bit_width(mesh.vertex_count()));
    verts.clear();
    verts.reserve(ends.size());
    for (const std::uint64_t k : end_order)
        if (verts.empty() || verts.back() != std::uint32_t(k >> 32)) verts.push_back(std::uint32_t(k >> 32));
    nn = np + std::uint32_t(verts.size());
    forest.reset(nn);
    bad.assign(nn, 0);
}

std::uint32_t AppelPropagation::vertex_node(std::uint32_t v) const {
    return np + std::uint32_t(std::lower_bound(verts.begin(), verts.end(), v) - verts.begin());
}

void AppelPropagation::mark_pierced() {
    pierced.assign(np, 0);
    if (!options.pierced_faces) return;
    const auto& pf = *options.pierced_faces;
    const auto& spans = graph.curves.spans;
    for (std::uint32_t p = 0; p < np; ++p)
        for (const EdgeSpan& s : spans[p]) {
            const auto [f0, f1] = mesh.edge_face[s.edge];
            if (pf[f0] || (f1 != kNoFace && pf[f1])) pierced[p] = 1;
        }
}

namespace {
// occluder_delta of crossings [i0, i1). (The occluders' edges are scattered over the mesh: their
// vertices and faces, then the vertices' positions and the first face's facing, are prefetched a
// few crossings ahead, in two levels; no effect on results.)
inline void crossing_deltas_of(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                               std::vector<PieceGraph::LinkCrossing>& lcs, std::size_t i0, std::size_t i1) {
    for (std::size_t i = i0; i < i1; ++i) {
        if (i + 16 < i1) {
            const std::uint32_t e = lcs[i + 16].occluder_edge;
            __builtin_prefetch(&mesh.edge_vertex[e]);
            __builtin_prefetch(&mesh.edge_face[e]);
        }
        if (i + 8 < i1) {
            const std::uint32_t e = lcs[i + 8].occluder_edge;
            const auto& ev = mesh.edge_vertex[e];
            __builtin_prefetch(&mesh.positions[ev[0]]);
            __builtin_prefetch(&mesh.positions[ev[1]]);
            __builtin_prefetch(face_front.states() + mesh.edge_face[e][0]);  // (its first face's facing)
        }
        auto& c = lcs[i];
        c.delta = occluder_delta(mesh, camera, &face_front, c.occluder_edge, c.c1, c.c2);
    }
}
}  // namespace

void AppelPropagation::crossing_deltas() {
    link_delta.assign(graph.links.size(), 0);
    occluding.clear();
    auto& lcs = graph.link_crossings;
    const std::size_t n = lcs.size();
    // (Split from 2000 crossings, at least 1000 a part: bench/results/visibility.md, eighteenth
    // session; each crossing's change is its own, so the parts are any ranges.)
    if (threads > 1 && n >= 2000) {
        const int parts = int(std::min<std::size_t>(std::size_t(threads), n / 1000));
        face_front.set_shared(true);  // (a lazy view's facing is read by every thread)
        graph.team().run(parts, [&](int i) {
            crossing_deltas_of(mesh, camera, face_front, lcs, n * std::size_t(i) / std::size_t(parts),
                               n * std::size_t(i + 1) / std::size_t(parts));
        });
        face_front.set_shared(false);
    } else {
        crossing_deltas_of(mesh, camera, face_front, lcs, 0, n);
    }
    for (const auto& c : lcs) {
        link_delta[c.link] += c.delta;
        if (c.delta != 0) occluding.push_back({c.occluder_edge, c.link, c.occluder_s});
    }
}

void AppelPropagation::unite_along_curves() {
    for (std::size_t l = 0; l < graph.links.size(); ++l) {
        const auto [b, a] = graph.links[l];
        if (pierced[b] || pierced[a]) continue;
        if (!forest.unite(b, a, link_delta[l])) bad[a] = 1;
    }
}

namespace {
constexpr int kEdgeOn = INT32_MIN, kSkipped = INT32_MIN + 1;  // local_occlusion_of_ends' markers

// The local occlusion of ends end_order[i0, i1) (whole vertex groups) into occlusion[i0, i1):
// kEdgeOn at a vertex with a face seen edge-on, kSkipped for a pierced piece's end.
void local_occlusion_of_ends(const AppelPropagation& a, std::vector<int>& occlusion, std::size_t i0, std::size_t i1) {
    const auto& end_order = a.end_order;
    const auto& verts = a.verts;
    Ring ring;
    // (verts[g] is the vertex of the group at i)
    std::size_t g = i0 < i1 ? std::size_t(std::lower_bound(verts.begin(), verts.end(), std::uint32_t(end_order[i0] >> 32)) - verts.begin()) : 0;
    for (std::size_t i = i0; i < i1; ++g) {
        const std::uint32_t v = std::uint32_t(end_order[i] >> 32);
        std::size_t j = i;
        while (j < i1 && std::uint32_t(end_order[j] >> 32) == v) ++j;
        prefetch_rings(a.mesh, verts, g);
        ring_of(a.mesh, a.camera, a.face_front, v, ring);
        const bool edge_on = ring.any_edge_on();
        for (; i < j; ++i) {
            const auto& e = a.graph.ends[std::uint32_t(end_order[i])];
            occlusion[i] = edge_on ? kEdgeOn : a.pierced[e.piece] ? kSkipped : local_occlusion(a.mesh, a.camera, ring, v, e.edge);
        }
    }
}
}  // namespace

void AppelPropagation::unite_at_vertices() {
    std::vector<int> end_occlusion;
    local_occlusion_at_ends(end_occlusion);
    unite_ends(end_occlusion);
}

void AppelPropagation::local_occlusion_at_ends(std::vector<int>& end_occlusion) const {
    end_occlusion.resize(end_order.size());
    const std::size_t ne = end_order.size();
    if (threads > 1 && ne >= 2000) {
        // Parts of about 1000 ends at least, each starting at a vertex's first end.
        const int parts = int(std::min<std::size_t>(std::size_t(threads), ne / 1000));
        std::vector<std::size_t> cut(std::size_t(parts) + 1, ne);
        cut[0] = 0;
        for (int i = 1; i < parts; ++i) {
            std::size_t c = std::max(cut[std::size_t(i - 1)], ne * std::size_t(i) / std::size_t(parts));
            while (c < ne && c > 0 && (end_order[c] >> 32) == (end_order[c - 1] >> 32)) ++c;
            cut[std::size_t(i)] = c;
        }
        face_front.set_shared(true);  // (a lazy view's facing is read by every thread)
        graph.team().run(parts, [&](int i) {
            local_occlusion_of_ends(*this, end_occlusion, cut[std::size_t(i)], cut[std::size_t(i) + 1]);
        });
        face_front.set_shared(false);
    } else {
        local_occlusion_of_ends(*this, end_occlusion, 0, end_order.size());
    }
}

void AppelPropagation::unite_ends(const std::vector<int>& end_occlusion) {
    for (std::size_t i = 0, node = np; i < end_order.size(); ++node) {
        const std::uint32_t v = std::uint32_t(end_order[i] >> 32);
        for (; i < end_order.size() && std::uint32_t(end_order[i] >> 32) == v; ++i) {
            const auto& e = graph.ends[std::uint32_t(end_order[i])];
            if (end_occlusion[i] == kEdgeOn) pierced[e.piece] = 1;
            if (pierced[e.piece]) continue;
            if (!forest.unite(std::uint32_t(node), e.piece, end_occlusion[i])) bad[e.piece] = 1;
        }
    }
}

void AppelPropagation::form_clusters() {
    comp.resize(nn);
    off.resize(nn);
    std::vector<std::uint32_t> root_comp(nn, UINT32_MAX);
    for (std::uint32_t x = 0; x < nn; ++x) {
        const std::uint32_t r = forest.find(x, off[x]);
        if (root_comp[r] == UINT32_MAX) root_comp[r] = std::uint32_t(st.clusters++);
        comp[x] = root_comp[r];
    }
    nc = st.clusters;
    state.assign(nc, kBound);
    base.assign(nc, 0);
    std::vector<int> min_off(nc, 1 << 30);
    for (std::uint32_t x = 0; x < nn; ++x) {
        min_off[comp[x]] = std::min(min_off[comp[x]], off[x]);
        if (bad[x]) state[comp[x]] = kInconsistent;
    }
    for (std::size_t c = 0; c < nc; ++c) base[c] = -min_off[c];  // lower bound: no QI below 0
    for (std::uint32_t p = 0; p < np; ++p)
        if (pierced[p]) {
            state[comp[p]] = kInconsistent;
            ++st.pierced;
        }
}

void AppelPropagation::fix(std::uint32_t node, int qi) {
    const std::uint32_t c = comp[node];
    if (state[c] == kInconsistent) return;
    if (state[c] == kFixed && base[c] != qi - off[node]) {
        state[c] = kInconsistent;
        return;
    }
    if (state[c] != kFixed) ++st.clusters_bbox;
    state[c] = kFixed;
    base[c] = qi - off[node];
}

void AppelPropagation::apply_bounding_box_rule() { bounding_box_rule_beside([] {}); }

void AppelPropagation::bounding_box_rule_beside(const std::function<void()>& beside) {
    // (Extreme vertices inside curves: the pieces with a span reaching them, found in one pass
    // over the spans, with the edges around those vertices marked. Those at curve ends are fixed
    // after the pass: fix() reads the clusters, which `beside` may be forming.)
    std::vector<std::uint32_t> inner_extremes, end_extremes;
    for (std::uint32_t v : graph.extreme_vertices) {
        if (v == UINT32_MAX) continue;
        if (std::binary_search(verts.begin(), verts.end(), v)) end_extremes.push_back(v);
        else inner_extremes.push_back(v);
    }
    on_edge.clear();
    by_edge.clear();
    EdgeMarks extreme_edges(mesh.edge_count()), occluder_edges(mesh.edge_count());
    for (std::uint32_t v : inner_extremes)
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k)
            extreme_edges.set(mesh.vertex_edges[k]);
    for (const Occluding& c : occluding) occluder_edges.set(c.edge);
    const auto& spans = graph.curves.spans;
    // The pass over pieces [p0, p1): their stretches on occluder edges, and the pieces to fix.
    struct Found {
        std::vector<EdgePiece> on_edge;
        std::vector<std::uint32_t> edges, fixes;
    };
    auto pass = [&](std::uint32_t p0, std::uint32_t p1, Found& f) {
        for (std::uint32_t p = p0; p < p1; ++p) {
            if (p + 4 < p1) __builtin_prefetch(spans[p + 4].data());  // (each piece's spans: their own block)
            for (const EdgeSpan& s : spans[p]) {
                if (occluder_edges.test(s.edge)) {
                    f.edges.push_back(s.edge);
                    f.on_edge.push_back({p, std::min(s.s0, s.s1), std::max(s.s0, s.s1)});
                }
                if (!extreme_edges.test(s.edge)) continue;
                const auto& ev = mesh.edge_vertex[s.edge];
                for (std::uint32_t v : inner_extremes)
                    if ((ev[0] == v && std::min(s.s0, s.s1) <= 0.0) || (ev[1] == v && std::max(s.s0, s.s1) >= 1.0))
                        f.fixes.push_back(p);
            }
        }
    };
    // (A large view's pieces split among the threads, 2000 a part at least; the parts' findings
    // then taken in piece order, as one pass would make them. The calling thread runs `beside`
    // first and takes half a part: kBesideShare, measured on armadillo@2, where beside (the
    // unions at vertices and the clusters) costs about half of the pass's part on two threads.)
    const int parts = threads > 1 && np >= 4000 ? int(std::min<std::uint32_t>(std::uint32_t(threads), np / 2000)) : 1;
    std::vector<Found> found(static_cast<std::size_t>(parts));
    if (parts > 1) {
        constexpr double kBesideShare = 0.5;  // of an equal part
        const double first = kBesideShare / (double(parts) - 1.0 + kBesideShare);
        auto cut = [&](int i) {
            if (i == 0) return std::uint32_t(0);
            if (i == parts) return np;
            const double share = first + (1.0 - first) * double(i - 1) / double(parts - 1);
            return std::min(np, std::uint32_t(double(np) * share));
        };
        graph.team().run(parts, [&](int i) {
            if (i == 0) beside();
            pass(cut(i), cut(i + 1), found[std::size_t(i)]);
        });
    } else {
        beside();
        pass(0, np, found[0]);
    }
    for (std::uint32_t v : end_extremes) fix(vertex_node(v), 0);
    for (const Found& f : found) {
        for (std::size_t k = 0; k < f.on_edge.size(); ++k) {
            by_edge.push_back(std::uint64_t(f.edges[k]) << 32 | on_edge.size());
            on_edge.push_back(f.on_edge[k]);
        }
        for (std::uint32_t p : f.fixes) fix(p, 0);
    }
}

void AppelPropagation::apply_parity() {
    // (Flags are scanned up to the first one set.)
    const bool pierced_any = options.pierced_faces &&
                             std::any_of(options.pierced_faces->begin(), options.pierced_faces->end(),
                                         [](std::uint8_t x) { return x != 0; });
    // (A closed non-orientable surface bounds no solid: no parity; one in R^3 also pierces itself.)
    parity = mesh.closed && !pierced_any && mesh.seam_list.empty();
    if (!parity) return;
    const auto& pieces = graph.curves.pieces;
    const auto& spans = graph.curves.spans;
    // Per silhouette piece, the parity of base it wants (-1: not a silhouette); a large view's
    // pieces split among the threads (2000 a part at least), then read in piece order.
    std::vector<std::int8_t>& piece_want = parity_of_piece;
    piece_want.resize(np);
    auto wants = [&](std::uint32_t p0, std::uint32_t p1) {
        for (std::uint32_t p = p0; p < p1; ++p) {
            // (each piece's spans are their own block, and its edge's flags are scattered: both
            // prefetched, in two levels; no effect on results)
            if (p + 8 < p1) __builtin_prefetch(spans[p + 8].data());
            if (p + 4 < p1) __builtin_prefetch(&mesh.edge_flags[spans[p + 4].front().edge]);
            if (pieces[p].kind != LineKind::Silhouette) {
                piece_want[p] = -1;
                continue;
            }
            const int par = (mesh.is_convex(spans[p].front().edge) ? 0 : 1);
            piece_want[p] = std::int8_t(((par - off[p]) % 2 + 2) % 2);
        }
    };
    const int parts = threads > 1 && np >= 4000 ? int(std::min<std::uint32_t>(std::uint32_t(threads), np / 2000)) : 1;
    if (parts > 1)
        graph.team().run(parts, [&](int i) {
            wants(std::uint32_t(std::uint64_t(np) * std::uint64_t(i) / std::uint64_t(parts)),
                  std::uint32_t(std::uint64_t(np) * std::uint64_t(i + 1) / std::uint64_t(parts)));
        });
    else
        wants(0, np);
    std::vector<std::int8_t> want(nc, -1);  // parity of base wanted, -1 unknown
    for (std::uint32_t p = 0; p < np; ++p) {
        const std::int8_t w = piece_want[p];
        if (w < 0) continue;
        const std::uint32_t c = comp[p];
        if (want[c] < 0) want[c] = w;
        else if (want[c] != w) state[c] = kInconsistent;
    }
    for (std::size_t c = 0; c < nc; ++c)
        if (want[c] >= 0 && ((base[c] % 2 + 2) % 2) != want[c]) {
            if (state[c] == kFixed) state[c] = kInconsistent;
            else if (state[c] == kBound) base[c] += 1;
        }
}

void AppelPropagation::start_occluder_grid() {
    // (Only where walks are likely worth a second thread: a large view, split stages on. A view
    // that then makes no walk has built it for nothing, on the worker's time only.)
    if (threads > 1 && options.walk && graph.occluders.size() >= 4000) {
        const PieceGraph& g = graph;
        grid_ready = graph.team().first_worker().post([&g] { g.occluder_grid(); });
    }
}

void AppelPropagation::match_occluders() {
    // (The spans on occluder edges, sorted by edge as 64-bit keys: edge, then the span's index;
    // the crossings by occluder edge: edge, then the index among `occluding`, increasing with the
    // crossing's index.)
    sort_keys(by_edge, sort_tmp, bit_width(mesh.edge_count()));
    std::vector<std::uint64_t> lc_by_edge(occluding.size());
    for (std::size_t i = 0; i < occluding.size(); ++i) lc_by_edge[i] = std::uint64_t(occluding[i].edge) << 32 | i;
    sort_keys(lc_by_edge, sort_tmp, bit_width(mesh.edge_count()));
    std::vector<std::uint32_t> occluder_piece(occluding.size(), UINT32_MAX);
    std::size_t j = 0;
    for (const std::uint64_t key : lc_by_edge) {
        const std::uint32_t edge = std::uint32_t(key >> 32);
        while (j < by_edge.size() && std::uint32_t(by_edge[j] >> 32) < edge) ++j;
        const double s = occluding[std::uint32_t(key)].s;
        const EdgePiece* best = nullptr;
        double best_d = 1e300;
        for (std::size_t k = j; k < by_edge.size() && std::uint32_t(by_edge[k] >> 32) == edge; ++k) {
            const EdgePiece& x = on_edge[std::uint32_t(by_edge[k])];
            const double d = s < x.s0 ? x.s0 - s : s > x.s1 ? s - x.s1 : 0.0;
            if (!best || d < best_d || (d == best_d && (x.s0 < best->s0 || (x.s0 == best->s0 && x.piece < best->piece))))
                best_d = d, best = &x;
        }
        if (best) occluder_piece[std::uint32_t(key)] = best->piece;
    }
    // (A link's two pieces are in one cluster, unless one lies on a pierced face: then the link
    // was not united, and that piece's cluster is inconsistent.)
    constraints.clear();
    for (std::size_t i = 0; i < occluding.size(); ++i) {
        const std::uint32_t op = occluder_piece[i], link = occluding[i].link;
        if (op == UINT32_MAX) continue;
        if (comp[op] == comp[graph.links[link].before] && comp[op] == comp[graph.links[link].after]) continue;
        constraints.push_back({op, link});
    }
}

void AppelPropagation::raise_by_constraints() {
    for (std::size_t round = 0, changed = 1; changed && round < nc + 2; ++round) {
        changed = 0;
        for (const auto& [op, l] : constraints) {
            // An inconsistent cluster's values mean nothing (they depend on the order of union).
            if (state[comp[op]] == kInconsistent) continue;
            const int n = value(op);
            for (const std::uint32_t x : {graph.links[l].before, graph.links[l].after}) {
                const std::uint32_t c = comp[x];
                // (a side in the occluder's own cluster rises with it: no constraint)
                if (state[c] != kBound || c == comp[op]) continue;
                const int m = value(x);
                if (m >= n) continue;
                int raise = n - m;
                if (parity) raise += raise % 2;
                base[c] += raise;
                changed = 1;
            }
        }
    }
}

void AppelPropagation::open_upper_bounds() {
    upper.assign(nc, INT_MAX);
    open.clear();
    touched.clear();
    for (const auto& [op, l] : constraints)
        if (state[comp[op]] == kBound && comp[graph.links[l].after] == comp[graph.links[l].before]) open.push_back({op, l});
}

void AppelPropagation::bound_above() {
    // (Only the open constraints are read, dropped as their clusters are decided; the clusters
    // bounded in a round are listed too.)
    const int step = parity ? 2 : 1;
    for (bool changed = true; changed;) {
        changed = false;
        std::size_t kept = 0;
        for (const auto& [op, l] : open) {
            const std::uint32_t c = comp[op], d = comp[graph.links[l].before];
            if (state[c] != kBound) continue;  // (decided: dropped)
            open[kept++] = {op, l};
            if (state[d] != kFixed) continue;
            const int m = std::min(value(graph.links[l].before), value(graph.links[l].after));
            if (upper[c] == INT_MAX) touched.push_back(c);
            upper[c] = std::min(upper[c], m - off[op]);
        }
        open.resize(kept);
        for (const std::uint32_t c : touched) {
            if (upper[c] < base[c] + step) {
                state[c] = upper[c] >= base[c] ? kFixed : kInconsistent;
                st.clusters_bounded += state[c] == kFixed;
                changed = true;
            }
            upper[c] = INT_MAX;
        }
        touched.clear();
    }
}

namespace {
double piece_length(const Piece& piece) {
    double len = 0.0;
    const auto& pts = piece.points;
    for (std::size_t i = 1; i < pts.size(); ++i) len += glm::length(pts[i] - pts[i - 1]);
    return len;
}
}  // namespace

void AppelPropagation::survey_bounded() {
    has_piece.assign(nc, 0);
    min_piece.assign(nc, 1 << 30);
    zero.assign(nc, UINT32_MAX);
    std::vector<double> zero_len(nc, -1.0);
    for (std::uint32_t p = 0; p < np; ++p) {
        const std::uint32_t c = comp[p];
        if (state[c] != kBound) continue;
        has_piece[c] = 1;
        min_piece[c] = std::min(min_piece[c], value(p));
        if (value(p) != 0) continue;
        const double len = piece_length(graph.curves.pieces[p]);
        if (len > zero_len[c]) zero_len[c] = len, zero[c] = p;
    }
}

void AppelPropagation::walk() {
    double box[4] = {1e300, -1e300, 1e300, -1e300};
    for (const Segment2& o : graph.occluders) {
        box[0] = std::min({box[0], o.a.x, o.b.x});
        box[1] = std::max({box[1], o.a.x, o.b.x});
        box[2] = std::min({box[2], o.a.y, o.b.y});
        box[3] = std::max({box[3], o.a.y, o.b.y});
    }
    box[0] -= 1.0, box[1] += 1.0, box[2] -= 1.0, box[3] += 1.0;
    std::vector<std::uint32_t> walkers;
    for (std::size_t c = 0; c < nc && options.walk; ++c)
        if (state[c] == kBound && zero[c] != UINT32_MAX) walkers.push_back(std::uint32_t(c));
    std::vector<Walk> walked(walkers.size());
    auto walk_one = [&](std::size_t w, const VertexImages& proj) {
        const std::uint32_t p = zero[walkers[w]];
        const PieceProbe q = probe_point(mesh, camera, graph.curves.pieces[p], graph.curves.spans[p]);
        walked[w] = walk_to(mesh, camera, face_front, graph, proj, q.P, q.p, q.edge, box);
    };
    const auto t_walks = StageClock::now();
    if (grid_ready.valid()) grid_ready.get();  // (start_occluder_grid's build done: its errors here)
    if (!walkers.empty()) graph.occluder_grid();  // (built here, before any thread reads it)
    if (threads > 1 && walkers.size() >= 8) {
        // (at least 4 walks a thread; each walk's result is its own, whichever thread takes it)
        const int parts = int(std::min<std::size_t>(std::size_t(threads), walkers.size() / 4));
        auto& own = graph.walk_images;  // (the other threads' vertex images)
        if (own.size() < std::size_t(parts - 1)) own.resize(std::size_t(parts - 1));
        for (int i = 0; i + 1 < parts; ++i) own[std::size_t(i)].reset(mesh, camera);
        std::atomic<std::size_t> next{0};
        face_front.set_shared(true);
        graph.team().run(parts, [&](int i) {
            const VertexImages& proj = i == 0 ? graph.images : own[std::size_t(i - 1)];
            for (std::size_t w; (w = next.fetch_add(1, std::memory_order_relaxed)) < walkers.size();) walk_one(w, proj);
        });
        face_front.set_shared(false);
    } else {
        for (std::size_t w = 0; w < walkers.size(); ++w) walk_one(w, graph.images);
    }
    if (!walkers.empty()) st.seconds_walks = seconds_since(t_walks);
    for (std::size_t wi = 0; wi < walkers.size(); ++wi) {
        const std::uint32_t c = walkers[wi];
        ++st.walks;
        const Walk w = walked[wi];
        if (w == Walk::Visible) {
            state[c] = kFixed;  // value(p) == 0 already
        } else if (w == Walk::Occluded) {
            const int raise = parity ? 2 : 1;  // QI(U) >= 1, parity kept
            base[c] += raise;
            min_piece[c] += raise;
        }
    }
    if (!walkers.empty() && !open.empty()) bound_above();
}

void AppelPropagation::ray_test_rest() {
    std::vector<std::uint8_t> needs_ray(nc, 0);
    bool any_ray = false;
    for (std::size_t c = 0; c < nc; ++c) {
        if (state[c] != kBound || !has_piece[c]) continue;
        if (min_piece[c] > 0) {
            ++st.clusters_occluded;
            if (!options.exact_hidden) continue;
        }
        needs_ray[c] = 1, any_ray = true;
    }
    if (!any_ray) return;
    std::vector<std::uint32_t> rep(nc, UINT32_MAX);  // the longest piece (the first of equals)
    std::vector<double> rep_len(nc, -1.0);
    for (std::uint32_t p = 0; p < np; ++p) {
        const std::uint32_t c = comp[p];
        if (!needs_ray[c]) continue;
        const double len = piece_length(graph.curves.pieces[p]);
        if (len > rep_len[c]) rep_len[c] = len, rep[c] = p;
    }
    for (std::size_t c = 0; c < nc; ++c) {
        if (!needs_ray[c]) continue;
        const std::uint32_t p = rep[c];
        base[c] = ray_qi(p) - off[p];
        state[c] = kFixed;
    }
}

void AppelPropagation::settle() {
    // (A large view's pieces split among the threads, 2000 a part at least, in one pass: each
    // part sets the QI of its pieces in consistent clusters and lists the pieces left to a ray
    // test and the clusters it finds negative. The ray tests are made here in piece order, as one
    // pass makes them; a negative cluster (rare: a non-generic view) sends all its pieces to
    // them, listed again from every piece.)
    const int parts = threads > 1 && np >= 4000 ? int(std::min<std::uint32_t>(std::uint32_t(threads), np / 2000)) : 1;
    struct Found {
        std::vector<std::uint32_t> to_ray, negative;
    };
    std::vector<Found> found(static_cast<std::size_t>(parts));
    auto& pieces = graph.curves.pieces;
    auto pass = [&](std::uint32_t p0, std::uint32_t p1, Found& f) {
        for (std::uint32_t p = p0; p < p1; ++p) {
            if (state[comp[p]] == kInconsistent) {
                f.to_ray.push_back(p);
                continue;
            }
            if (value(p) < 0) f.negative.push_back(comp[p]);
            pieces[p].qi = value(p);
        }
    };
    auto from = [&](int i) { return std::uint32_t(std::uint64_t(np) * std::uint64_t(i) / std::uint64_t(parts)); };
    if (parts > 1) graph.team().run(parts, [&](int i) { pass(from(i), from(i + 1), found[std::size_t(i)]); });
    else pass(0, np, found[0]);
    bool any_negative = false;
    for (const Found& f : found)
        for (std::uint32_t c : f.negative) state[c] = kInconsistent, any_negative = true;
    if (any_negative) {
        for (std::uint32_t p = 0; p < np; ++p)
            if (state[comp[p]] == kInconsistent) pieces[p].qi = ray_qi(p);
    } else {
        for (const Found& f : found)
            for (std::uint32_t p : f.to_ray) pieces[p].qi = ray_qi(p);
    }
    for (std::size_t c = 0; c < nc; ++c) st.inconsistent += state[c] == kInconsistent;
}

AppelStats assign_qi_appel(const MeshTopology& mesh, const Camera& camera, const FaceFacing& face_front,
                           const std::function<const RayCaster&()>& ray_index, PieceGraph& graph,
                           const AppelOptions& options) {
    return AppelPropagation(mesh, camera, face_front, ray_index, graph, options).run();
}

}  // namespace inkline
