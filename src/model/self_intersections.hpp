// Faces that intersect other faces of the mesh (not just at shared edges or vertices): where a
// curve passes through a face, its QI changes without any image-space event, so the fast
// visibility must not propagate across such curves.
#pragma once
#include <cstdint>
#include <vector>

#include "model/topology.hpp"

namespace inkline {

// Per face: 1 if it intersects another face (exact predicates). Candidate pairs come from CGAL's
// box_self_intersection_d on float boxes rounded outward (32 bytes per face, twice: CGAL copies
// them); the pair test is the case analysis of CGAL's Polygon_mesh_processing::self_intersections,
// written here because that function needs the mesh copied into a CGAL::Surface_mesh first (about
// 80 bytes per face more, the peak of a 3 M-triangle model; docs/memory.md). test_model checks
// that both give the same faces.
std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh);

}  // namespace inkline
