// Ray-test service: counts the layers of surface crossed by a segment (Appel's QI).
// Built once per mesh, lazily, only when a view needs ray tests. Embree (single precision,
// coordinates relative to the model's centre) finds candidate hits; hits close to either end
// of the segment, where single precision cannot decide, are re-decided by CGAL's exact
// segment/triangle predicate in double coordinates.
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

    // Number of distinct faces, other than skip0/skip1 (kNoFace to skip none), that the open
    // segment from `from` to `to` crosses. Thread-safe.
    int count_layers(const glm::dvec3& from, const glm::dvec3& to, std::uint32_t skip0,
                     std::uint32_t skip1) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
