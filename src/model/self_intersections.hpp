// Faces that intersect other faces of the mesh (not just at shared edges or vertices): where a
// curve passes through a face, its QI changes without any image-space event, so the fast
// visibility must not propagate across such curves.
#pragma once
#include <cstdint>
#include <vector>

#include "model/topology.hpp"

namespace inkline {

// Per face: 1 if it intersects another face (CGAL Polygon_mesh_processing, exact predicates).
std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh);

}  // namespace inkline
