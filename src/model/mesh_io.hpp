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

}  // namespace inkline
