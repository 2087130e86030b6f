// The progressive mesh's adapted meshes as MeshTopology, frame after frame: exactly what
// build_topology makes of each (the same edges in the same order, flags, angles, planes), with the
// arrays' storage kept from frame to frame; for every interior edge whose two faces have the
// same corners at the same positions as in the last frame, the angle between their normals and the
// convexity (an exact orientation test) carried over instead of computed again, and for every
// corner between faces whose corners did not change, its mate (the corner across its edge).
//
// Takes each frame's mesh with its vertices' and faces' input indices (both increasing: the front's
// meshes keep input order, so a face is matched to the last frame's by one merge, with no map sized
// by the input) and the last frame's topology (alive during the call); gives the new topology.
#pragma once

#include <cstdint>
#include <vector>

#include "model/topology.hpp"

namespace inkline {

class AdaptedTopology {
public:
    // Fills `out` (its storage reused) from `mesh` (its arrays taken); `last`: the last frame's
    // topology, whose vertices and faces had the ids of the last call (null: none).
    void build(MeshTopology& out, TriangleMesh&& mesh, const std::vector<std::uint32_t>& vertex_id,
               const std::vector<std::uint32_t>& face_id, double crease_degrees, const MeshTopology* last);
    // Interior edges of the last build whose angle and convexity were carried over.
    std::size_t carried_edges() const { return carried_; }
    // Corners of the last build whose mate (the corner across their edge, or none) was carried over.
    std::size_t carried_mates() const { return carried_mates_; }

private:
    std::vector<std::uint32_t> vertex_id_, face_id_, last_vertex_id_, last_face_id_;  // per mesh
    std::vector<std::uint32_t> last_face_;  // per face: the same face in the last mesh, if unchanged
    // Per face: the last mesh's face of the same id and corners (positions aside); per face of
    // the last mesh, the other way round.
    std::vector<std::uint32_t> same_corners_, last_same_corners_;
    std::vector<std::uint32_t> corner_edge_, last_mate_;  // per corner; the last mesh's mates
    bool last_mates_paired_ = false;  // every last mate mutual (no edge of three corners or more)
    std::vector<std::uint8_t> dirty_;  // per vertex: a corner of a face whose corners changed
    std::vector<std::pair<std::uint64_t, std::uint32_t>> unsettled_;  // (edge, corner) to group
    std::vector<glm::dvec3> normal_;
    std::size_t carried_ = 0, carried_mates_ = 0;

    void match_faces(const MeshTopology& t, const MeshTopology* last);
    void find_mates(const MeshTopology& t, const MeshTopology* last);
    void make_edges(MeshTopology& t);
    void angles_and_flags(MeshTopology& t, const MeshTopology* last);
    void remember();
};

}  // namespace inkline
