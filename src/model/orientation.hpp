// Orientation seams of non-orientable surfaces (a Moebius strip, a Klein bottle immersion).
// Takes a MeshTopology whose edges are built; gives the edges where the faces' windings disagree
// (kEdgeSeam, MeshTopology::seam_list) and the few facts the per-view stages need about them.
//
// Tolerant loading orients each connected part by propagation from a seed face (mesh_io.cpp); on
// a surface that cannot be oriented the propagation meets itself with the opposite winding along
// a curve of edges: the seam. The faces keep the windings the propagation gave them, so on a seam
// edge both faces traverse the edge the same way: the surface is continuous there, but one face's
// normal is the negative of the continuous surface's. Every per-view test that compares the two
// faces of an edge therefore reads the comparison flipped on a seam edge: a seam edge is a
// silhouette exactly where its two faces have the same facing (docs/loading.md).
#pragma once

#include <cstdint>

#include "model/topology.hpp"

namespace inkline {

// Flags the seam edges (kEdgeSeam; both faces traverse the edge from edge_vertex[0] to [1]) and
// lists them in edge order in seam_list, before the angles between face normals, which are then
// taken with the second normal negated on a seam edge. (build_topology marks the same edges while
// it makes them; the adapted topology, which keeps its edges, calls this.)
void mark_orientation_seams(MeshTopology& t);

// Whether the two faces of interior edge e lie on opposite sides of the eye's view (a silhouette),
// from their facing bits: the facings differ, or agree on a seam edge.
inline bool silhouette_from_facing(const MeshTopology& t, std::uint32_t e, bool front0, bool front1) {
    return (front0 != front1) != t.is_seam(e);
}

// Face f's facing relative to the winding of edge e's first face (edge_face[e][0]): its own facing,
// negated when f is the second face of a seam edge. (Convexity, kEdgeConvex, is relative to that
// first face's winding on every edge.)
inline bool facing_relative_to_first(const MeshTopology& t, std::uint32_t e, std::uint32_t f, bool front) {
    return t.is_seam(e) && f != t.edge_face[e][0] ? !front : front;
}

// Calls out(f) for each face f around vertex v once: the faces of v's edges that leave v along
// them in their own winding (on a seam edge both faces leave v, or neither, by its direction).
template <class Out>
void for_each_face_around(const MeshTopology& t, std::uint32_t v, Out&& out) {
    for (std::uint32_t k = t.vertex_edge_begin[v]; k < t.vertex_edge_begin[v + 1]; ++k) {
        const std::uint32_t g = t.vertex_edges[k];
        const bool from_v = t.edge_vertex[g][0] == v;
        if (t.is_seam(g)) {
            if (from_v) out(t.edge_face[g][0]), out(t.edge_face[g][1]);
            continue;
        }
        const std::uint32_t f = from_v ? t.edge_face[g][0] : t.edge_face[g][1];
        if (f != kNoFace) out(f);
    }
}

// Whether vertex v is an end of a seam edge (every ring there mixes the two windings).
bool on_orientation_seam(const MeshTopology& t, std::uint32_t v);

}  // namespace inkline
