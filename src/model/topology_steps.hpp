// Three of build_topology's steps (model/topology.hpp), for a builder that keeps what did not change
// between meshes (detail/adapted_topology.hpp): takes a MeshTopology with positions and faces
// (and, for edge_convexity, its edges); gives what build_topology would put there.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "model/topology.hpp"

namespace inkline {

// The bounds, facing origin, radius and float facing planes, from the positions.
void compute_bounds_and_facing(MeshTopology& t);
// angle[i] = float(std::acos(cosine[i])) for i < n, exactly (the angles between face normals),
// faster: two at a time where glibc's vector math is available.
void angles_of_cosines(const double* cosine, std::size_t n, float* angle);
// An interior edge's kEdgeConvex, kEdgeConcave or neither (exact predicate).
std::uint8_t edge_convexity(const MeshTopology& t, std::uint32_t e);
// Each vertex's edges (vertex_edge_begin, vertex_edges) from the edges' vertices; `cursor` is
// working storage (kept by a caller that builds many meshes).
void fill_vertex_edges(MeshTopology& t, std::vector<std::uint32_t>& cursor);

}  // namespace inkline
