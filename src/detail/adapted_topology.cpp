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
// (Also the matches by corners alone, positions aside: same_corners_, last_same_corners_.)
void AdaptedTopology::match_faces(const MeshTopology& t, const MeshTopology* last) {
    const std::size_t nf = t.face_count();
    last_face_.assign(nf, kNone);
    same_corners_.assign(nf, kNone);
    if (!last) return;
    match_increasing_ids(face_id_, last_face_id_, &last_face_, nullptr);  // (both in input order: one merge)
    last_same_corners_.assign(last->face_count(), kNone);
    for (std::uint32_t f = 0; f < nf; ++f) {
        const std::uint32_t q = last_face_[f];
        if (q == kNone) continue;
        bool corners = true, positions = true;
        for (int j = 0; j < 3 && corners; ++j) {
            const std::uint32_t v = t.faces[f][j], w = last->faces[q][j];
            corners = vertex_id_[v] == last_vertex_id_[w];
            positions = positions && t.positions[v] == last->positions[w];
        }
        if (corners) same_corners_[f] = q, last_same_corners_[q] = f;
        if (!corners || !positions) last_face_[f] = kNone;
    }
}

// corner_mates' result (each corner's mate: kNoCorner alone on its edge, else for a group the
// first corner's the last, the others' the first), into corner_edge_. A corner of a face whose
// corners did not change keeps its last mate, mapped to this mesh, when the edge cannot have
// gained or lost a corner: its mate's face did not change either, or it was alone, and one of its
// ends is on no changed face (a new corner on the edge would be a changed face's, with both ends
// on it). The other corners are grouped by edge among themselves, which holds every corner of
// their edges. The last mesh must have had no edge of three corners or more (else all anew).
void AdaptedTopology::find_mates(const MeshTopology& t, const MeshTopology* last) {
    const std::size_t nf = t.face_count(), nc = 3 * nf;
    carried_mates_ = 0;
    if (!last || !last_mates_paired_ || last_mate_.size() != 3 * last->face_count()) {
        CornerMates mates = corner_mates(t.faces, t.vertex_count());
        corner_edge_.swap(mates.mate);
        return;
    }
    dirty_.assign(t.vertex_count(), 0);
    for (std::uint32_t f = 0; f < nf; ++f)
        if (same_corners_[f] == kNone)
            for (const std::uint32_t v : t.faces[f]) dirty_[v] = 1;
    corner_edge_.assign(nc, kNoCorner);
    unsettled_.clear();
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t f = c / 3, k = c % 3, a = t.faces[f][k], b = t.faces[f][(k + 1) % 3], q = same_corners_[f];
        if (q != kNone && !(dirty_[a] && dirty_[b])) {
            const std::uint32_t lm = last_mate_[3 * q + k];
            const std::uint32_t fm = lm == kNoCorner ? kNone : last_same_corners_[lm / 3];
            if (lm == kNoCorner || fm != kNone) {
                corner_edge_[c] = lm == kNoCorner ? kNoCorner : 3 * fm + lm % 3;
                ++carried_mates_;
                continue;
            }
        }
        unsettled_.push_back({(std::uint64_t(std::min(a, b)) << 32) | std::max(a, b), c});
    }
    if (unsettled_.size() > nc / 4) {  // (then one pass over every corner costs less than the sort)
        CornerMates mates = corner_mates(t.faces, t.vertex_count());
        corner_edge_.swap(mates.mate);
        carried_mates_ = 0;
        return;
    }
    std::sort(unsettled_.begin(), unsettled_.end());
    for (std::size_t g0 = 0; g0 < unsettled_.size();) {
        std::size_t g1 = g0 + 1;
        while (g1 < unsettled_.size() && unsettled_[g1].first == unsettled_[g0].first) ++g1;
        if (g1 - g0 > 1) {
            const std::uint32_t first = unsettled_[g0].second;
            corner_edge_[first] = unsettled_[g1 - 1].second;
            for (std::size_t i = g0 + 1; i < g1; ++i) corner_edge_[unsettled_[i].second] = first;
        }
        g0 = g1;
    }
}

// build_topology's edges: numbered in the order of their first traversal, face 0 the first
// traversal's, face 1 the other; the faces across each corner's edge.
// (corner_edge_ holds the mates: find_mates; they are kept as the last ones.)
void AdaptedTopology::make_edges(MeshTopology& t) {
    const std::size_t nf = t.face_count(), nc = 3 * nf;
    std::size_t ne = 0;
    last_mates_paired_ = true;
    for (std::uint32_t c = 0; c < nc; ++c) {
        const std::uint32_t m = corner_edge_[c];
        ne += m == kNoCorner || m > c;
        last_mates_paired_ = last_mates_paired_ && (m == kNoCorner || corner_edge_[m] == c);
    }
    last_mate_.assign(corner_edge_.begin(), corner_edge_.end());
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
    find_mates(t, last);
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
