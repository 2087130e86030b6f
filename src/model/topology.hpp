// MeshTopology: the flat, read-only arrays that every per-view stage reads (DESIGN.md step 1).
// Takes a validated TriangleMesh (moved in, so the model is held once); gives vertices, faces, edges with both faces, face planes,
// the angle between face normals, convexity, crease and border flags, vertex->edge adjacency.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.hpp"
#include "model/mesh_io.hpp"

namespace inkline {

inline constexpr std::uint32_t kNoFace = UINT32_MAX;

enum EdgeFlag : std::uint8_t {
    kEdgeBorder = 1,   // one incident face
    kEdgeCrease = 2,   // normal angle above the crease threshold
    kEdgeConvex = 4,   // surface convex along the edge (exact orientation test): a silhouette
                       // here is front-facing in the Markosian et al. sense (footnote 4)
    kEdgeConcave = 8,  // strictly concave; neither flag: coplanar faces
    kEdgeSeam = 16,    // orientation seam of a non-orientable surface: both faces traverse the edge
                       // the same way (model/orientation.hpp); convexity is relative to face 0
};

struct MeshTopology {
    // Vertices and faces (faces consistently oriented, closed parts outward; on a non-orientable
    // part, consistently except across its seam edges: kEdgeSeam).
    std::vector<glm::dvec3> positions;
    std::vector<std::array<std::uint32_t, 3>> faces;
    // Per face, the edge of each corner k, (faces[k], faces[k+1]), and the face across it
    // (kNoFace on a border), in one 24-byte record: a step from a face to its neighbours (a walk,
    // the faces that turned between two views) reads one or two cache lines, not one per edge of
    // edge_face. (12 bytes per triangle more than the edges alone: docs/memory.md.)
    struct FaceEdges {
        std::array<std::uint32_t, 3> edge;
        std::array<std::uint32_t, 3> face;
    };
    std::vector<FaceEdges> face_edges;
    // Unit normal of face f (zero for a degenerate face), computed from the corners: nothing per
    // face is stored for it (the model's memory is the topology; see docs/memory.md).
    glm::dvec3 face_normal(std::uint32_t f) const;
    // Float facing planes, 16 bytes per face (one load for a lazy test, and the full scan reads
    // one stream instead of four: bench/results/model.md), for the exhaustive scan and the per-face test
    // (features/facing.hpp): unit normal and offset d = dot(n, a - facing_origin), so that
    // dot(n, eye - facing_origin) - d is the eye's signed distance to the plane. A face whose float
    // plane is not within 2^-21 (per normal component) of its exact one (slivers, zero area) holds
    // NaN and always takes the exact test.
    struct alignas(16) FacingPlane {
        float nx, ny, nz, d;
    };
    std::vector<FacingPlane> facing;
    glm::dvec3 facing_origin{0.0};  // centre of the bounding box
    double facing_radius = 0.0;     // max over vertices of |v - facing_origin|_1


    // Edges (structure of arrays). edge_face[e][0] traverses edge_vertex[e][0] -> [1].
    std::vector<std::array<std::uint32_t, 2>> edge_vertex;
    std::vector<std::array<std::uint32_t, 2>> edge_face;  // [1] == kNoFace on borders
    std::vector<float> edge_normal_angle;  // angle between the two face normals, radians;
                                           // also the randomized sampling weight (pi - dihedral)
    std::vector<std::uint8_t> edge_flags;  // EdgeFlag bits
    std::vector<std::uint32_t> border_list;  // border edges, in order
    std::vector<std::uint32_t> crease_list;  // crease edges (set_crease_angle), in order
    std::vector<std::uint32_t> seam_list;    // orientation seam edges (kEdgeSeam), in order; empty
                                             // for an orientable mesh (per-view code tests that first)

    // Vertex -> incident edges, compressed rows.
    std::vector<std::uint32_t> vertex_edge_begin;  // size V+1
    std::vector<std::uint32_t> vertex_edges;

    // Scenes of several objects (TriangleMesh::face_object): each face's object and the objects'
    // names; empty for a single mesh.
    std::vector<std::uint32_t> face_object;
    std::vector<std::string> object_names;

    Bounds3 bounds;
    bool closed = false;        // no border edge
    double crease_degrees = 40.0;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t face_count() const { return faces.size(); }
    std::size_t edge_count() const { return edge_vertex.size(); }
    bool is_border(std::uint32_t e) const { return edge_flags[e] & kEdgeBorder; }
    bool is_crease(std::uint32_t e) const { return edge_flags[e] & kEdgeCrease; }
    bool is_convex(std::uint32_t e) const { return edge_flags[e] & kEdgeConvex; }
    bool is_seam(std::uint32_t e) const { return edge_flags[e] & kEdgeSeam; }

    // Re-flags creases for another threshold (angle between face normals, degrees).
    void set_crease_angle(double degrees);
    // After `positions` moved (same connectivity: a smoothed copy of the shape, detail/): the
    // bounds, facing planes and convexity flags follow them, exactly as build_topology makes them.
    // The angles between face normals and the crease flags are kept (the creases stay those of the
    // shape the topology was built from).
    void refresh_geometry();
};

MeshTopology build_topology(TriangleMesh mesh, double crease_degrees = 40.0);
// The same in place, for a caller that has other threads read the positions and faces while the
// rest is built (Model::load's self-intersection search): `t` holds the mesh's positions and
// faces already (moved out of `mesh`, whose other fields are used as build_topology uses them),
// and keeps them as they are, in the same buffers; the rest of `t` is made.
void build_topology_on(MeshTopology& t, TriangleMesh mesh, double crease_degrees = 40.0);

}  // namespace inkline
