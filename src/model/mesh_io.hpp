// Model loading: strict readers (OBJ, OFF, PLY, STL; ASCII and binary) into a validated triangle soup.
// Takes a file path; gives positions and consistently oriented triangles, or throws
// inkline::Error("<file>: <problem>") for anything the pipeline cannot draw correctly.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace inkline {

struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::size_t polygons_triangulated = 0;  // input faces with more than 3 corners
    std::size_t faces_reoriented = 0;       // faces flipped to make orientation consistent
};

// Reads and validates a mesh file. Refuses (inkline::Error naming the file):
// unreadable/unknown-format/malformed files, NaN or infinite coordinates, no faces,
// faces with out-of-range or repeated vertex indices, non-manifold edges (more than two faces:
// the Appel/Markosian visibility needs a 2-manifold), non-orientable surfaces.
TriangleMesh load_mesh(const std::string& path);

// The same validation for meshes built in memory; `where` names the source in errors.
// Polygons are not accepted here (triangles only); orientation is made consistent.
void validate_mesh(TriangleMesh& mesh, const std::string& where);

// Corners grouped by undirected edge. Corner c = 3f + k stands for the edge from corner k to
// corner k + 1 of face f; the corners of one edge form a group, ordered by index. mate[c] is
// kNoCorner for a corner alone on its edge (a border), the group's first corner for the others,
// and the group's last corner for the first (so in a 2-manifold each corner's mate is the other
// traversal of its edge). `extra` counts corners beyond two per edge (non-manifold edges) and
// `first_bad` is the edge (lower vertex << 32 | upper) whose third corner has the smallest index.
// A counting sort on the lower vertex and a sort per vertex: 8 bytes per corner while it runs,
// where a hash map took about 80 bytes per edge (docs/memory.md).
inline constexpr std::uint32_t kNoCorner = UINT32_MAX;
struct CornerMates {
    std::vector<std::uint32_t> mate;
    std::size_t extra = 0;
    std::uint64_t first_bad = 0;
};
CornerMates corner_mates(const std::vector<std::array<std::uint32_t, 3>>& triangles, std::size_t vertex_count);

}  // namespace inkline
