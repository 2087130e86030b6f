#include "features/features.hpp"

#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

namespace inkline {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 cgal(const glm::dvec3& p) { return {p.x, p.y, p.z}; }

// Sign of det[b - a, c - a, w] for double inputs, exactly. A floating-point evaluation decides
// when its value exceeds a forward error bound (36 units in the last place of the permanent,
// several times the worst case of the 2 subtractions, 2 products and 5 additions per term, plus
// an absolute term for products that fall into the subnormal range, where the relative bound
// fails: each of the 12 products then errs by up to 2^-1075, scaled by |w| for the first);
// otherwise the determinant is recomputed in exact rational arithmetic.
int sign_det_edges_dir(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& w) {
    const glm::dvec3 e = b - a, g = c - a;
    const double t0 = e.y * g.z * w.x, t1 = e.z * g.y * w.x, t2 = e.z * g.x * w.y, t3 = e.x * g.z * w.y,
                 t4 = e.x * g.y * w.z, t5 = e.y * g.x * w.z;
    const double det = (t0 - t1) + (t2 - t3) + (t4 - t5);
    const double perm = std::abs(t0) + std::abs(t1) + std::abs(t2) + std::abs(t3) + std::abs(t4) + std::abs(t5);
    const double underflow = 0x1p-1066 * (1.0 + std::abs(w.x) + std::abs(w.y) + std::abs(w.z));
    const double bound = 36.0 * 1.1102230246251565e-16 * perm + underflow;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    using Q = CGAL::Exact_rational;
    const Q ex = Q(b.x) - Q(a.x), ey = Q(b.y) - Q(a.y), ez = Q(b.z) - Q(a.z);
    const Q gx = Q(c.x) - Q(a.x), gy = Q(c.y) - Q(a.y), gz = Q(c.z) - Q(a.z);
    const Q d = (ey * gz - ez * gy) * Q(w.x) + (ez * gx - ex * gz) * Q(w.y) + (ex * gy - ey * gx) * Q(w.z);
    return CGAL::sign(d);
}
}  // namespace

bool face_is_front(const MeshTopology& mesh, std::uint32_t face, const Camera& camera) {
    const auto& v = mesh.faces[face];
    const glm::dvec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    if (camera.is_ortho()) return sign_det_edges_dir(a, b, c, -camera.forward()) > 0;
    return CGAL::orientation(cgal(a), cgal(b), cgal(c), cgal(camera.eye())) == CGAL::POSITIVE;
}

Features extract_features(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options) {
    Features out;
    const std::size_t nf = mesh.face_count(), ne = mesh.edge_count(), nv = mesh.vertex_count();
    out.face_front.resize(nf);
    for (std::uint32_t f = 0; f < nf; ++f) out.face_front[f] = face_is_front(mesh, f, camera) ? 1 : 0;

    out.edge_kind.assign(ne, kNoKind);
    for (std::uint32_t e = 0; e < ne; ++e) {
        const auto [f0, f1] = mesh.edge_face[e];
        if (f1 == kNoFace) {
            out.edge_kind[e] = std::uint8_t(LineKind::Border);
            out.border_edges.push_back(e);
        } else if (out.face_front[f0] != out.face_front[f1]) {
            out.edge_kind[e] = std::uint8_t(LineKind::Silhouette);
            out.silhouette_edges.push_back(e);
        } else if (mesh.is_crease(e)) {
            out.edge_kind[e] = std::uint8_t(LineKind::Crease);
            out.crease_edges.push_back(e);
        }
    }

    // Cusps (Definition 3), over the vertices of silhouette edges.
    std::vector<std::uint8_t> cusp(nv, 0);
    for (std::uint32_t e : out.silhouette_edges) {
        for (std::uint32_t v : mesh.edge_vertex[e]) {
            if (cusp[v]) continue;
            int sil = 0, front = 0;
            bool border = false;
            for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
                const std::uint32_t g = mesh.vertex_edges[k];
                if (out.edge_kind[g] == std::uint8_t(LineKind::Silhouette)) {
                    ++sil;
                    front += mesh.is_convex(g) ? 1 : 0;
                }
                border |= mesh.is_border(g);
            }
            CuspCase c = CuspCase::None;
            if (sil > 2) c = CuspCase::ManySilhouettes;
            else if (border) c = CuspCase::BorderEdge;
            else if (sil == 2 && front == 1) c = CuspCase::FrontBackMeet;
            if (c != CuspCase::None) {
                cusp[v] = 1;
                out.cusp_vertices.push_back(v);
                out.cusp_cases.push_back(c);
            }
        }
    }

    // Chaining. A vertex breaks chains where the number of feature edges (of every kind, drawn or
    // not) is not two, where the two differ in kind, or at a cusp.
    auto is_break = [&](std::uint32_t v) {
        if (cusp[v]) return true;
        int deg = 0;
        std::uint8_t kind = kNoKind;
        bool mixed = false;
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint8_t kk = out.edge_kind[mesh.vertex_edges[k]];
            if (kk == kNoKind) continue;
            if (deg++ > 0 && kk != kind) mixed = true;
            kind = kk;
        }
        return deg != 2 || mixed;
    };
    auto other_feature_edge = [&](std::uint32_t v, std::uint32_t e) {
        for (std::uint32_t k = mesh.vertex_edge_begin[v]; k < mesh.vertex_edge_begin[v + 1]; ++k) {
            const std::uint32_t g = mesh.vertex_edges[k];
            if (g != e && out.edge_kind[g] != kNoKind) return g;
        }
        return e;
    };
    std::vector<std::uint8_t> used(ne, 0);
    auto walk = [&](std::uint32_t start_v, std::uint32_t start_e) {
        FeatureCurve c;
        c.kind = LineKind(out.edge_kind[start_e]);
        c.vertices.push_back(start_v);
        std::uint32_t v = start_v, e = start_e;
        while (true) {
            used[e] = 1;
            c.edges.push_back(e);
            v = mesh.edge_vertex[e][0] == v ? mesh.edge_vertex[e][1] : mesh.edge_vertex[e][0];
            c.vertices.push_back(v);
            if (v == start_v) {  // a loop; closed only if it may continue through its start
                c.closed = !is_break(v);
                break;
            }
            if (is_break(v)) break;
            e = other_feature_edge(v, e);
            if (used[e]) break;
        }
        out.curves.push_back(std::move(c));
    };
    const std::vector<std::uint32_t>* lists[3] = {&out.silhouette_edges, &out.border_edges, &out.crease_edges};
    for (const auto* list : lists) {
        for (std::uint32_t e : *list) {
            if (used[e] || !options.wants(LineKind(out.edge_kind[e]))) continue;
            for (std::uint32_t v : mesh.edge_vertex[e])
                if (!used[e] && is_break(v)) walk(v, e);
        }
    }
    for (const auto* list : lists)  // what is left are closed loops without a break
        for (std::uint32_t e : *list)
            if (!used[e] && options.wants(LineKind(out.edge_kind[e]))) walk(mesh.edge_vertex[e][0], e);
    return out;
}

}  // namespace inkline
