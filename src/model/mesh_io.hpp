// Model loading: strict parsers (OBJ, OFF, PLY, STL; ASCII and binary) into a validated triangle soup.
// Takes a file path; gives positions and consistently oriented triangles, or throws
// inkline::Error("<file>: <problem>") for anything the pipeline cannot draw correctly.
// Loading is tolerant by default: what exported models commonly get wrong is repaired and counted
// (LoadReport); LoadOptions::strict refuses those files instead, as inkline did before.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "model/load_progress.hpp"

namespace inkline {

// The repairs made while loading, each counted (zero: none needed). warnings() gives one line per
// kind of repair made, for the command to print.
struct LoadReport {
    std::size_t vertices_welded = 0;         // vertices merged into an earlier one at the same position
    std::size_t faces_dropped = 0;           // degenerate input faces (a repeated corner, zero area) and
                                             // duplicates (the three corners of an earlier face)
    std::size_t nonmanifold_edges_cut = 0;   // edges of more than two faces, cut so each sheet has a border there
    std::size_t vertices_split = 0;          // vertex copies those cuts made
    std::size_t components_reoriented = 0;   // connected parts whose faces disagreed in orientation
    std::size_t nonorientable_parts = 0;     // connected parts that cannot be oriented (Moebius strip ...)
    std::size_t orientation_seam_edges = 0;  // their edges where the faces' windings disagree (kEdgeSeam)
    std::size_t cameras_dropped = 0;         // a scene's cameras that cannot make a view (zero field of view ...)
    std::string first_camera_problem;        // why the first of them could not
    bool any() const {
        return vertices_welded + faces_dropped + nonmanifold_edges_cut + components_reoriented + cameras_dropped +
                   orientation_seam_edges > 0;
    }
    std::vector<std::string> warnings(const std::string& where) const;  // "<where>: <repair>" lines
};

struct LoadOptions {
    // Load as before the repairs existed: nothing welded (but STL corners, as always), degenerate
    // faces, non-manifold edges and non-orientable surfaces refused. Re-orientation happens in
    // both modes; tolerant loading leaves orientation seams where it cannot (model/orientation.hpp).
    bool strict = false;
    // Called as the load advances (model/load_progress.hpp), from the loading thread; none when
    // empty. Model::load makes the last call (done) once the topology is built.
    LoadProgressCallback progress = {};
    // Threads Model::load may use beside the calling one's (its Hilbert sorts, the
    // self-intersection search it starts early): 1, the calling thread only.
    int threads = 1;
};

struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::size_t polygons_triangulated = 0;  // input faces with more than 3 corners
    std::size_t faces_reoriented = 0;       // faces flipped to make orientation consistent
    LoadReport repairs;
    // Scenes of several objects: per triangle the index of its object in object_names. Empty for a
    // single-object mesh; kept in step with `triangles` by every repair and reordering.
    std::vector<std::uint32_t> face_object;
    std::vector<std::string> object_names;
    // The corner pairing of `triangles` (CornerMates::mate below) as the repairs found it, carried
    // through the Hilbert order so that build_topology need not pair the corners again. Trusted only
    // while `triangles` still hash to corner_mates_of (triangles_key): code that changes the
    // triangles without updating it just makes the topology pair them again.
    std::vector<std::uint32_t> corner_mates;
    std::uint64_t corner_mates_of = 0;
};

// A hash of the triangles' corners (what corner_mates depends on).
std::uint64_t triangles_key(const std::vector<std::array<std::uint32_t, 3>>& triangles);

// Reads a mesh file, welds vertices at the same position (seams split by UVs or normals; not in
// strict mode), then checks or repairs it (repair_mesh). Refuses (inkline::Error naming the file) in every mode:
// unreadable/unknown-format/malformed files, NaN or infinite coordinates, no faces (a point
// cloud), out-of-range indices. Strict mode also refuses faces with repeated vertex indices,
// non-manifold edges and non-orientable surfaces; tolerant mode drops and cuts them, and orients
// a non-orientable part except across an orientation seam (model/orientation.hpp).
TriangleMesh load_mesh(const std::string& path, const LoadOptions& options = {});

// load_mesh that starts `ahead` (model/reorder.hpp: the Hilbert orders made on a thread of their
// own) once the vertices are welded and the indices checked, and announces to it any change the
// repairs then make (Model::load: the order beside the repairs).
class HilbertOrderAhead;
TriangleMesh load_mesh(const std::string& path, const LoadOptions& options, HilbertOrderAhead* ahead);

// What load_mesh does after parsing, for triangles built elsewhere (the scene loader): welds
// vertices at the same position (tolerant mode; a scene's objects each on their own), then drops
// degenerate faces (a repeated corner; zero area on edges closed without it; the same three points
// as an earlier face), cuts non-manifold edges (the vertices on them split per fan of faces joined
// by manifold edges, so each sheet meets the edge as its own border; a sheet that still shares the
// edge after that is detached), and orients every connected part consistently (closed parts
// outward). Strict: refuses instead of dropping and cutting. Counts go to mesh.repairs.
void repair_mesh(TriangleMesh& mesh, const std::string& where, const LoadOptions& options = {});

// The strict validation for meshes built in memory (no welding); `where` names the source in
// errors. Polygons are not accepted here (triangles only); orientation is made consistent (a
// non-orientable surface is refused).
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
