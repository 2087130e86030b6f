#include "features/features.hpp"

#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/predicates.hpp"

namespace inkline {

bool face_is_front(const MeshTopology& mesh, std::uint32_t face, const Camera& camera) {
    const auto& v = mesh.faces[face];
    const glm::dvec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    return orient_eye(camera, a, b, c) > 0;
}

Features extract_features(const MeshTopology& mesh, const Camera& camera, const FeatureOptions& options) {
    Features out;
    const std::size_t nf = mesh.face_count(), ne = mesh.edge_count(), nv = mesh.vertex_count();
    out.face_front.resize(nf);
    // Float filter: with n = cross(b - a, c - a) rounded (each component within 4 eps of its
    // permanent p), dot(n, eye) - dot(n, a) errs by less than 16 eps (dot(p, |eye|) + dot(p, |a|)),
    // plus an absolute term for products in the subnormal range; for an orthographic camera the
    // eye term is dot(n, -forward) alone. Undecided faces go to the exact predicate.
    constexpr double kEps = 1.1102230246251565e-16;
    const bool ortho = camera.is_ortho();
    const glm::dvec3 eye = ortho ? -camera.forward() : camera.eye();
    const glm::dvec3 aeye = glm::abs(eye);
    for (std::uint32_t f = 0; f < nf; ++f) {
        const MeshTopology::FacePlane& q = mesh.face_planes[f];
        const double det = glm::dot(q.n, eye) - (ortho ? 0.0 : q.k);
        const double bound = 16.0 * kEps * (glm::dot(q.p, aeye) + (ortho ? 0.0 : q.pa)) + 0x1p-1060;
        out.face_front[f] = det > bound ? 1 : det < -bound ? 0 : (face_is_front(mesh, f, camera) ? 1 : 0);
    }

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
