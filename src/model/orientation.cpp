#include "model/orientation.hpp"

namespace inkline {

void mark_orientation_seams(MeshTopology& t) {
    t.seam_list.clear();
    for (std::uint32_t e = 0; e < t.edge_count(); ++e) {
        const std::uint32_t f1 = t.edge_face[e][1];
        if (f1 == kNoFace) continue;
        // f1 traverses e the same way as f0 (from edge_vertex[0] to [1]) exactly on a seam.
        const auto& c = t.faces[f1];
        const std::uint32_t a = t.edge_vertex[e][0], b = t.edge_vertex[e][1];
        const bool same = (c[0] == a && c[1] == b) || (c[1] == a && c[2] == b) || (c[2] == a && c[0] == b);
        if (!same) continue;
        t.edge_flags[e] |= kEdgeSeam;
        t.seam_list.push_back(e);
    }
}

bool on_orientation_seam(const MeshTopology& t, std::uint32_t v) {
    for (std::uint32_t k = t.vertex_edge_begin[v]; k < t.vertex_edge_begin[v + 1]; ++k)
        if (t.is_seam(t.vertex_edges[k])) return true;
    return false;
}

}  // namespace inkline
