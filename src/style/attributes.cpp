#include "style/attributes.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace inkline {

PointAttributes point_attributes(const MeshTopology& mesh, const Camera& camera, const Drawing& d,
                                 const std::vector<std::vector<EdgeSpan>>& spans, bool light_at_camera,
                                 const glm::dvec3& light) {
    PointAttributes a;
    a.depth.resize(d.pieces.size());
    a.tone.resize(d.pieces.size());
    for (std::size_t p = 0; p < d.pieces.size() && p < spans.size(); ++p) {
        const auto& S = spans[p];
        if (S.empty() || d.pieces[p].points.size() != S.size() + 1) continue;
        const auto add = [&](std::uint32_t e, double s) {
            const auto [v0, v1] = mesh.edge_vertex[e];
            const glm::dvec3 P = mesh.positions[v0] + s * (mesh.positions[v1] - mesh.positions[v0]);
            glm::dvec3 n = mesh.face_normal(mesh.edge_face[e][0]);
            if (mesh.edge_face[e][1] != kNoFace) n += mesh.face_normal(mesh.edge_face[e][1]);
            const double len = glm::length(n);
            const glm::dvec3 L = light_at_camera ? glm::normalize(camera.ray_origin(P) - P) : light;
            // At a silhouette the two faces turn opposite ways: the tone is about 0 (dark) there.
            a.depth[p].push_back(camera.depth(P));
            a.tone[p].push_back(len > 0 ? std::clamp(glm::dot(n / len, L), 0.0, 1.0) : 0.0);
        };
        add(S[0].edge, S[0].s0);
        for (const EdgeSpan& sp : S) add(sp.edge, sp.s1);
    }
    return a;
}

}  // namespace inkline
