#include "model/topology.hpp"
#include "model/topology_steps.hpp"

#include "core/predicates.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#if INKLINE_HAVE_MVEC
#include <emmintrin.h>
// glibc's vector acos of two doubles (libmvec, SSE2 calling convention; the library picks its
// best kernel for the processor), within 4 ulp of the true value.
extern "C" __m128d _ZGVbN2v_acos(__m128d);
#endif

namespace inkline {
// The vector acos takes a third to half of std::acos's time; its result a is kept when every
// double within 2^-40 |a| of it (some 4 000 ulp: the two functions differ by at most 5) rounds to
// the same float, so std::acos's rounds to it too; otherwise (about once in 2^16 angles) std::acos
// decides.
void angles_of_cosines(const double* cosine, std::size_t n, float* angle) {
    std::size_t i = 0;
#if INKLINE_HAVE_MVEC
    for (; i + 2 <= n; i += 2) {
        alignas(16) double a[2];
        _mm_store_pd(a, _ZGVbN2v_acos(_mm_loadu_pd(cosine + i)));
        for (int k = 0; k < 2; ++k) {
            const double margin = std::abs(a[k]) * 0x1p-40;
            angle[i + k] = float(a[k] - margin) == float(a[k] + margin) ? float(a[k]) : float(std::acos(cosine[i + k]));
        }
    }
#endif
    for (; i < n; ++i) angle[i] = float(std::acos(cosine[i]));
}

namespace {
// The bounds, the facing origin and radius, from the positions.
void compute_bounds_and_origin(MeshTopology& t) {
    t.bounds.lo = t.bounds.hi = t.positions.empty() ? glm::dvec3(0.0) : t.positions[0];
    for (const auto& p : t.positions) {
        t.bounds.lo = glm::min(t.bounds.lo, p);
        t.bounds.hi = glm::max(t.bounds.hi, p);
    }
    t.facing_origin = t.bounds.center();
    t.facing_radius = 0.0;
    for (const auto& p : t.positions) {
        const glm::dvec3 q = glm::abs(p - t.facing_origin);
        t.facing_radius = std::max(t.facing_radius, q.x + q.y + q.z);
    }
}

// Face f's float facing plane (t.facing_origin set), and its unit normal: MeshTopology::face_normal's
// doubles (the same arithmetic), made here rather than in a pass of their own.
//
// The plane comes from the double normal n = cross(b - a, c - a), which errs by at most 8 eps |p|
// per component (p its permanent: per component the sum of the absolute products), so the unit
// normal's direction by at most 16 sqrt(3) eps |p|_inf / |n|; with the rounding to float (2^-24)
// that must stay below 2^-21 per component, else the face is NaN and always goes to the exact
// predicate. facing.cpp derives the per-view bound from this.
MeshTopology::FacingPlane facing_plane(const MeshTopology& t, std::size_t f, glm::dvec3& normal) {
    const auto& v = t.faces[f];
    const glm::dvec3 a = t.positions[v[0]];
    const glm::dvec3 e = t.positions[v[1]] - a, g = t.positions[v[2]] - a;
    const glm::dvec3 n = glm::cross(e, g);
    const double pmax = std::max({std::abs(e.y * g.z) + std::abs(e.z * g.y), std::abs(e.z * g.x) + std::abs(e.x * g.z),
                                  std::abs(e.x * g.y) + std::abs(e.y * g.x)});
    const double len = glm::length(n);
    normal = len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
    constexpr double kEps = 1.1102230246251565e-16;
    const bool trusted =
        len > 0.0 && std::isfinite(len) && 16.0 * 1.7320508075688772 * kEps * pmax / len + 0x1p-24 + 8.0 * kEps <= 0x1p-21;
    if (!trusted) {
        const float nan = std::nanf("");
        return {nan, nan, nan, nan};
    }
    const glm::dvec3 u = n / len;
    return {float(u.x), float(u.y), float(u.z), float(glm::dot(u, a - t.facing_origin))};
}
}  // namespace

void compute_bounds_and_facing(MeshTopology& t) {
    compute_bounds_and_origin(t);
    t.facing.resize(t.faces.size());
    glm::dvec3 normal;
    for (std::size_t f = 0; f < t.faces.size(); ++f) t.facing[f] = facing_plane(t, f, normal);
}

// kEdgeConvex, kEdgeConcave or neither for interior edge e: the far corner of face 1 below the
// oriented plane of face 0 (exact predicate).
std::uint8_t edge_convexity(const MeshTopology& t, std::uint32_t e) {
    const auto [f0, f1] = t.edge_face[e];
    std::uint32_t opp = 0;
    for (auto v : t.faces[f1])
        if (v != t.edge_vertex[e][0] && v != t.edge_vertex[e][1]) opp = v;
    const auto& v0 = t.faces[f0];
    // (a float filter first: it settles nearly every edge, at a fraction of CGAL's orientation's cost)
    const int o = orient3_fast(t.positions[v0[0]], t.positions[v0[1]], t.positions[v0[2]], t.positions[opp]);
    return o < 0 ? kEdgeConvex : o > 0 ? kEdgeConcave : 0;
}

void MeshTopology::set_crease_angle(double degrees) {
    crease_degrees = degrees;
    const float threshold = float(degrees * M_PI / 180.0);
    crease_list.clear();
    for (std::uint32_t e = 0; e < edge_flags.size(); ++e) {
        edge_flags[e] &= std::uint8_t(~kEdgeCrease);
        if (!(edge_flags[e] & kEdgeBorder) && edge_normal_angle[e] > threshold) {
            edge_flags[e] |= kEdgeCrease;
            crease_list.push_back(e);
        }
    }
}

glm::dvec3 MeshTopology::face_normal(std::uint32_t f) const {
    const auto& v = faces[f];
    const glm::dvec3 n = glm::cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
    const double len = glm::length(n);
    return len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
}

void MeshTopology::refresh_geometry() {
    compute_bounds_and_facing(*this);
    for (std::uint32_t e = 0; e < edge_flags.size(); ++e) {
        if (edge_flags[e] & kEdgeBorder) continue;
        edge_flags[e] = std::uint8_t((edge_flags[e] & ~(kEdgeConvex | kEdgeConcave)) | edge_convexity(*this, e));
    }
}

MeshTopology build_topology(TriangleMesh mesh, double crease_degrees) {
    MeshTopology t;
    t.positions = std::move(mesh.positions);
    t.faces = std::move(mesh.triangles);
    build_topology_on(t, std::move(mesh), crease_degrees);
    return t;
}

void build_topology_on(MeshTopology& t, TriangleMesh mesh, double crease_degrees) {
    std::vector<std::uint32_t> known_mates;  // the loader's pairing, while it still fits the triangles
    if (mesh.corner_mates.size() == 3 * t.faces.size() && mesh.corner_mates_of == triangles_key(t.faces))
        known_mates = std::move(mesh.corner_mates);
    t.face_object = std::move(mesh.face_object);
    t.object_names = std::move(mesh.object_names);
    const std::size_t nv = t.positions.size(), nf = t.faces.size();

    compute_bounds_and_origin(t);  // (the facing planes are made below, beside the angles)

    // Edges, numbered in the order of their first traversal (face by face, corner by corner); the
    // first traversal a->b gives face 0, the last other one face 1 (the only other one in a
    // 2-manifold). corner_edge first holds each corner's mate, then, corner by corner, its edge.
    const std::size_t nc = 3 * nf;
    std::vector<std::uint32_t> corner_edge;  // corner c = 3f + k
    std::size_t ne = 0;
    {
        corner_edge = known_mates.empty() ? corner_mates(t.faces, nv).mate : std::move(known_mates);
        for (std::uint32_t c = 0; c < nc; ++c) ne += corner_edge[c] == kNoCorner || corner_edge[c] > c;
    }
    t.face_edges.resize(nf);
    t.edge_vertex.reserve(ne);
    t.edge_face.reserve(ne);
    t.edge_flags.assign(ne, 0);
    bool seams = false;
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t f = c / 3, k = c % 3, mate = corner_edge[c];
        t.face_edges[f].face[k] = mate == kNoCorner ? kNoFace : mate / 3;  // the face across: its mate's
        const std::uint32_t a = t.faces[f][k], b = t.faces[f][(k + 1) % 3];
        if (mate == kNoCorner || mate > c) {  // the first corner of its edge
            corner_edge[c] = std::uint32_t(t.edge_vertex.size());
            t.edge_vertex.push_back({a, b});
            t.edge_face.push_back({f, kNoFace});
        } else {  // its edge's first corner (mate < c) already holds the edge
            const std::uint32_t e = corner_edge[c] = corner_edge[mate];
            t.edge_face[e][1] = f;
            // An orientation seam: this face traverses the edge the same way as its first face
            // (here rather than in a pass of its own, which read every second face again).
            const bool seam = a == t.edge_vertex[e][0];
            t.edge_flags[e] = seam ? kEdgeSeam : 0;  // (the last face decides, as edge_face[e][1])
            seams |= seam;
        }
        t.face_edges[f].edge[k] = corner_edge[c];
    }
    std::vector<std::uint32_t>().swap(corner_edge);  // (freed before the arrays still to come)
    t.seam_list.clear();
    if (seams)
        for (std::uint32_t e = 0; e < ne; ++e)
            if (t.edge_flags[e] & kEdgeSeam) t.seam_list.push_back(e);
    t.edge_normal_angle.assign(ne, 0.0f);
    t.closed = true;
    // The angles need both faces' unit normals. The edges come in the order of their first faces,
    // and the Hilbert order puts most second faces a little further on: the facing planes and
    // normals are made face by face as the edges reach them, the normals kept in a window of the
    // last kWindow faces (in cache, where an array of them all was 24 bytes a face read at
    // scattered places); a second face beyond the window has its normal made again.
    constexpr std::size_t kWindow = std::size_t(1) << 14;
    std::vector<glm::dvec3> window(std::min(kWindow, nf));
    t.facing.resize(nf);
    std::size_t made = 0;  // faces [0, made) have their planes; [made - kWindow, made) their normals in `window`
    const auto make_until = [&](std::size_t end) {
        for (; made < end; ++made) t.facing[made] = facing_plane(t, made, window[made % kWindow]);
    };
    constexpr std::size_t kBlock = 256;  // edges whose cosines go to angles_of_cosines at once
    double cosine[kBlock];
    for (std::size_t block = 0; block < ne; block += kBlock) {
        const std::size_t m = std::min(kBlock, ne - block);
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t e = block + j;
            const auto [f0, f1] = t.edge_face[e];
            make_until(std::size_t(f0) + 1);
            if (f1 == kNoFace) {
                t.edge_flags[e] = kEdgeBorder;
                t.border_list.push_back(std::uint32_t(e));
                t.closed = false;
                cosine[j] = 1.0;  // (angle 0)
                continue;
            }
            // (On a seam the continuous surface's normal there is the second face's negated.)
            const double sign = t.is_seam(std::uint32_t(e)) ? -1.0 : 1.0;
            glm::dvec3 n1;
            if (f1 < f0 + kWindow) {  // (f1 > f0: the window still holds f0's normal after f1's is made)
                make_until(std::size_t(f1) + 1);
                n1 = window[f1 % kWindow];
            } else {
                n1 = t.face_normal(f1);
            }
            cosine[j] = std::clamp(sign * glm::dot(window[f0 % kWindow], n1), -1.0, 1.0);
            t.edge_flags[e] |= edge_convexity(t, std::uint32_t(e));
        }
        angles_of_cosines(cosine, m, &t.edge_normal_angle[block]);
    }
    make_until(nf);  // (faces after the last edge's first face)
    std::vector<glm::dvec3>().swap(window);
    t.set_crease_angle(crease_degrees);

    std::vector<std::uint32_t> cursor;
    fill_vertex_edges(t, cursor);
}

void fill_vertex_edges(MeshTopology& t, std::vector<std::uint32_t>& cursor) {
    const std::size_t nv = t.vertex_count();
    t.vertex_edge_begin.assign(nv + 1, 0);
    for (const auto& ev : t.edge_vertex) {
        ++t.vertex_edge_begin[ev[0] + 1];
        ++t.vertex_edge_begin[ev[1] + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) t.vertex_edge_begin[v + 1] += t.vertex_edge_begin[v];
    t.vertex_edges.resize(t.vertex_edge_begin[nv]);
    cursor.assign(t.vertex_edge_begin.begin(), t.vertex_edge_begin.end() - 1);
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
        t.vertex_edges[cursor[t.edge_vertex[e][0]]++] = e;
        t.vertex_edges[cursor[t.edge_vertex[e][1]]++] = e;
    }
}

}  // namespace inkline
