// Ray-test service: counts the layers of surface crossed by a segment (Appel's QI).
// Built once per mesh, lazily, only when a view needs ray tests. Embree (single precision,
// coordinates relative to the model's centre, the ray started near the model) proposes faces;
// each is decided by CGAL's exact segment/triangle predicate in double coordinates, together
// with the faces next to it that single precision may have confused with it and the faces around
// the segment's end edge (see count_layers in ray_caster.cpp). The faces around a vertex and the
// faces across an edge are read from the mesh's topology: the index keeps no per-face table
// (but for a mesh with an edge of three faces or more, whose edges do not list every face).
//
// Two kinds of index: a mesh's own (one Embree tree, built once), and an index kept across meshes
// that are each a subset of one input's faces (the progressive mesh's adapted meshes, a new mesh
// a frame): its faces are held in blocks of consecutive input faces, one Embree geometry each, in
// a two-level scene, and a new mesh rebuilds only the blocks whose faces changed and refits those
// whose faces only moved (the input being in a spatially coherent order, a block is compact).
// Both decide every ray exactly; the index only proposes faces.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "model/topology.hpp"

namespace inkline {

class RayCaster {
public:
    explicit RayCaster(const MeshTopology& mesh);
    // An index of subsets of one input's faces (see above), empty until `reindex`;
    // `block_faces` input faces a block.
    struct SubsetOptions {
        // (Small enough that a frame's changes leave most blocks alone, large enough that the top
        // level over the blocks stays cheap: measured in docs/progressive_mesh.md.)
        std::size_t block_faces = 256;
        // Blocks whose faces only moved are refitted (Embree's refit build quality: the block's
        // tree kept, its boxes grown to the new triangles); otherwise rebuilt at low quality.
        bool refit = true;
    };
    explicit RayCaster(const SubsetOptions& options);
    ~RayCaster();
    RayCaster(const RayCaster&) = delete;
    RayCaster& operator=(const RayCaster&) = delete;

    // Number of layers of surface, other than faces skip0/skip1 (kNoFace to skip none), that the
    // segment from `from` to `to` crosses: the faces it meets, where two that share an edge and
    // face `from` the same way count once (it passes through their edge). Thread-safe.
    int count_layers(const glm::dvec3& from, const glm::dvec3& to, std::uint32_t skip0,
                     std::uint32_t skip1) const;

    // The mesh's positions moved (same connectivity, MeshTopology::refresh_geometry done): the
    // index is refitted to them (Embree's refit build quality: the tree's structure is kept and
    // its boxes grown to the new triangles, much cheaper than a new build), the degenerate faces
    // and the ray-start sphere follow. Not thread-safe against count_layers.
    void refit();

    // Subset index: from now on the index is of `mesh`, whose face f is input face face_id[f] and
    // vertex v input vertex vertex_id[v] (face ids increasing; `mesh` must outlive its use here).
    // A block (block_faces consecutive input faces) whose faces are the last mesh's, with the same
    // corners (input vertices) at the same single-precision positions, is kept; one whose faces
    // only moved is refitted; any other is built anew. Coordinates are taken relative to the mesh's
    // box, as in the mesh's own index, so the faces proposed are that index's and every count is
    // the same. Not thread-safe against count_layers.
    struct ReindexStats {
        std::size_t blocks = 0, kept = 0, refitted = 0, rebuilt = 0, removed = 0;
    };
    ReindexStats reindex(const MeshTopology& mesh, const std::vector<std::uint32_t>& vertex_id,
                         const std::vector<std::uint32_t>& face_id);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
