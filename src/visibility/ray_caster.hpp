// Ray-test service: counts the layers of surface crossed by a segment (Appel's QI).
// Built once per mesh, lazily, only when a view needs ray tests. Embree (single precision,
// coordinates relative to the model's centre, the ray started near the model) proposes faces;
// each is decided by CGAL's exact segment/triangle predicate in double coordinates, together
// with the faces next to it that single precision may have confused with it and the faces around
// the segment's end edge (see count_layers in ray_caster.cpp).
#pragma once

#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "model/topology.hpp"

namespace inkline {

class RayCaster {
public:
    explicit RayCaster(const MeshTopology& mesh);
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

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
