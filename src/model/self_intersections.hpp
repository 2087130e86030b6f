// Faces that intersect other faces of the mesh (not just at shared edges or vertices): where a
// curve passes through a face, its QI changes without any image-space event, so the fast
// visibility must not propagate across such curves, and both methods cut curves there.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "model/topology.hpp"

namespace inkline {

// A point where a mesh edge meets a face other than its own: parameter s along the edge (0 at
// edge_vertex[edge][0], 1 at [1]).
struct EdgeCut {
    std::uint32_t edge;
    double s;
    bool operator<(const EdgeCut& o) const { return edge != o.edge ? edge < o.edge : s < o.s; }
};

struct SelfIntersections {
    std::vector<std::uint8_t> faces;  // per face: 1 if it intersects another face
    std::size_t flagged = 0;          // faces set in `faces`
    // Sorted by edge, then s: where edges pass through other faces, and the ends of the stretches
    // where an edge lies on another face (touching or coincident surfaces). Empty for an embedded
    // surface; a few per intersecting pair otherwise (16 bytes each).
    std::vector<EdgeCut> cuts;
    // Every intersecting pair of faces (f, g), as the search met them (8 bytes each): the
    // intersection lines start from these (model/intersection_curves.hpp), without a second search.
    std::vector<std::array<std::uint32_t, 2>> pairs;
};

// Per face: 1 if it intersects another face (exact predicates). Candidate pairs come from a box
// hierarchy on float boxes rounded outward (CGAL's box_self_intersection_d lists the intersecting
// pairs in its order when there are some); the pair test is the case analysis of CGAL's Polygon_mesh_processing::self_intersections,
// written here because that function needs the mesh copied into a CGAL::Surface_mesh first (about
// 80 bytes per face more, the peak of a 3 M-triangle model; docs/memory.md). test_model checks
// that both give the same faces. The box search runs on up to `threads` threads (the same result
// for any count).
std::vector<std::uint8_t> self_intersecting_faces(const MeshTopology& mesh, int threads = 1);

// Which pairs of faces the search tests. By default a patch of faces that certainly cannot
// intersect itself (its normals within a cone under 90 degrees, its boundary's projection along
// the cone's axis a simple polygon: Volino and Thalmann's test, decided with exact predicates) is
// skipped whole; kEveryBoxPair tests every pair whose boxes meet (the same result, slower: the
// tests' reference).
enum class PatchTest { kEmbeddedPatchesSkipped, kEveryBoxPair };

// How the cuts are made. By default the cases that filters settle without a construction go first
// (an edge whose ends are strictly on one side of the face; an edge with one end at a corner of the
// face, or at its position, and the other strictly off its plane: the cut is that end or none);
// kCgalOnly gives every edge and face to CGAL's intersection (the same cuts, slower: the tests'
// reference).
enum class CutConstruction { kFilteredFirst, kCgalOnly };

// The same faces, and where their edges meet the other faces of each intersecting pair (exact
// predicates decide which edges meet which faces; the points are constructions, rounded).
SelfIntersections self_intersections(const MeshTopology& mesh, int threads = 1,
                                     PatchTest patch_test = PatchTest::kEmbeddedPatchesSkipped,
                                     CutConstruction cuts = CutConstruction::kFilteredFirst);

// The same from candidate pairs of faces, for a mesh known to intersect itself only in some of
// them (e.g. a mesh embedded but for a few moved vertices: the pairs of each face with a moved
// corner and the faces whose boxes meet its own; detail/moving_self_intersections.hpp). Each
// candidate pair (f != g, each pair once, in either order) is tested exactly as the search above
// tests it, and the faces of `suspects` and of the pairs are checked for degeneracy. Gives what
// self_intersections gives when the mesh's intersecting pairs are all among the candidates and
// its degenerate faces all among those faces: flags and cuts bit for bit (the same cut
// constructions on the same mesh), the pairs the same set, sorted, (f, g) with f < g.
SelfIntersections self_intersections_among(const MeshTopology& mesh, const std::vector<std::uint32_t>& suspects,
                                           const std::vector<std::array<std::uint32_t, 2>>& candidates);

}  // namespace inkline
