#include "detail/adapted_topology.hpp"

#include <algorithm>
#include <cmath>

#include "core/sorted_ids.hpp"
#include "model/orientation.hpp"
#include "model/topology_steps.hpp"

namespace inkline {
namespace {
constexpr std::uint32_t kNone = UINT32_MAX;
}  // namespace

// Per face, the last mesh's face of the same id when its corners are the same vertices in the same
// order at the same positions (its normal, and the angle and convexity of an edge between two such
// faces, are then the same).
void AdaptedTopology::match_faces(const MeshTopology& t, const MeshTopology* last) {
    const std::size_t nf = t.face_count();
    last_face_.assign(nf, kNone);
    if (!last) return;
    match_increasing_ids(face_id_, last_face_id_, &last_face_, nullptr);  // (both in input order: one merge)
    for (std::uint32_t f = 0; f < nf; ++f) {
        const std::uint32_t q = last_face_[f];
        if (q == kNone) continue;
        bool same = true;
        for (int j = 0; j < 3 && same; ++j) {
            const std::uint32_t v = t.faces[f][j], w = last->faces[q][j];
            same = vertex_id_[v] == last_vertex_id_[w] && t.positions[v] == last->positions[w];
        }
        if (!same) last_face_[f] = kNone;
    }
}

// build_topology's edges: numbered in the order of their first traversal, face 0 the first
// traversal's, face 1 the other; the faces across each corner's edge.
void AdaptedTopology::make_edges(MeshTopology& t) {
    const std::size_t nf = t.face_count(), nc = 3 * nf;
    std::size_t ne = 0;
    {
        CornerMates mates = corner_mates(t.faces, t.vertex_count());
        corner_edge_.swap(mates.mate);
        for (std::uint32_t c = 0; c < nc; ++c) ne += corner_edge_[c] == kNoCorner || corner_edge_[c] > c;
    }
    t.face_edges.resize(nf);
    for (std::uint32_t c = 0; c < nc; ++c)
        t.face_edges[c / 3].face[c % 3] = corner_edge_[c] == kNoCorner ? kNoFace : corner_edge_[c] / 3;
    t.edge_vertex.clear();
    t.edge_face.clear();
    t.edge_vertex.reserve(ne);
    t.edge_face.reserve(ne);
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t f = c / 3, mate = corner_edge_[c];
        if (mate == kNoCorner || mate > c) {
            corner_edge_[c] = std::uint32_t(t.edge_vertex.size());
            t.edge_vertex.push_back({t.faces[f][c % 3], t.faces[f][(c % 3 + 1) % 3]});
            t.edge_face.push_back({f, kNoFace});
        } else {
            corner_edge_[c] = corner_edge_[mate];
            t.edge_face[corner_edge_[c]][1] = f;
        }
        t.face_edges[f].edge[c % 3] = corner_edge_[c];
    }
}

// build_topology's angles between face normals and convexity flags, carried from the last mesh's
// edge where both faces are unchanged (and neither edge is a seam), then creases and borders.
void AdaptedTopology::angles_and_flags(MeshTopology& t, const MeshTopology* last) {
    const std::size_t ne = t.edge_count(), nf = t.face_count();
    t.edge_normal_angle.assign(ne, 0.0f);
    t.edge_flags.assign(ne, 0);
    t.border_list.clear();
    t.closed = true;
    normal_.resize(nf);
    for (std::uint32_t f = 0; f < nf; ++f) normal_[f] = t.face_normal(f);  // (kept whole: cheap next to the rest)
    mark_orientation_seams(t);
    carried_ = 0;
    for (std::uint32_t e = 0; e < ne; ++e) {
        const auto [f0, f1] = t.edge_face[e];
        if (f1 == kNoFace) {
            t.edge_flags[e] = kEdgeBorder;
            t.border_list.push_back(e);
            t.closed = false;
            continue;
        }
        const std::uint32_t q0 = last_face_[f0], q1 = last_face_[f1];
        if (q0 != kNone && q1 != kNone && !t.is_seam(e)) {
            // The last mesh's edge between the same two faces, at the same corner of face 0.
            const int k = t.faces[f0][0] == t.edge_vertex[e][0] ? 0 : t.faces[f0][1] == t.edge_vertex[e][0] ? 1 : 2;
            const std::uint32_t le = last->face_edges[q0].edge[k];
            if (last->edge_face[le][0] == q0 && last->edge_face[le][1] == q1 && !last->is_seam(le)) {
                t.edge_normal_angle[e] = last->edge_normal_angle[le];
                t.edge_flags[e] |= std::uint8_t(last->edge_flags[le] & (kEdgeConvex | kEdgeConcave));
                ++carried_;
                continue;
            }
        }
        const double sign = t.is_seam(e) ? -1.0 : 1.0;
        const double c = std::clamp(sign * glm::dot(normal_[f0], normal_[f1]), -1.0, 1.0);
        t.edge_normal_angle[e] = float(std::acos(c));
        t.edge_flags[e] |= edge_convexity(t, e);
    }
}

void AdaptedTopology::build(MeshTopology& t, TriangleMesh&& mesh, const std::vector<std::uint32_t>& vertex_id,
                            const std::vector<std::uint32_t>& face_id, double crease_degrees, const MeshTopology* last) {
    vertex_id_.assign(vertex_id.begin(), vertex_id.end());
    face_id_.assign(face_id.begin(), face_id.end());
    t.positions.swap(mesh.positions);
    t.faces.swap(mesh.triangles);
    t.face_object.swap(mesh.face_object);
    t.object_names.swap(mesh.object_names);
    compute_bounds_and_facing(t);
    match_faces(t, last);
    make_edges(t);
    angles_and_flags(t, last);
    t.set_crease_angle(crease_degrees);
    fill_vertex_edges(t, corner_edge_);  // (corner_edge_ as the fill cursors)
    remember();
}

// This mesh's ids become the last ones.
void AdaptedTopology::remember() {
    last_vertex_id_.swap(vertex_id_);
    last_face_id_.swap(face_id_);
}

}  // namespace inkline
