// Memory order of a mesh: vertices and faces along a Hilbert curve (CGAL's hilbert_sort), so that
// neighbours on the surface are neighbours in memory. Per-view passes that follow the surface
// (silhouette tracing, chaining, walks) then touch a few cache lines instead of the whole mesh.
// Takes a TriangleMesh; gives the same mesh (same orientation, same corners order per face)
// with renumbered vertices and faces. With threads > 1 the vertices' and faces' sorts run on two
// threads (the same orders).
#pragma once

#include <cstdint>

#include "model/mesh_io.hpp"

namespace inkline {

TriangleMesh hilbert_ordered(TriangleMesh mesh, int threads = 1);

// The same mesh numbered at random (vertices, faces, and each face's corners rotated: the same
// orientation), from `seed`. For checks that a drawing does not depend on the numbering.
TriangleMesh shuffled_numbering(TriangleMesh mesh, std::uint32_t seed);

}  // namespace inkline
