// The self-intersection search (self_intersections.hpp) started before the topology exists, so
// that it runs beside the topology's construction: it needs only the faces and their corners,
// which build_topology keeps as they are (the same face numbers, corners and positions). Model::load uses it when it may use more threads
// (LoadOptions::threads); the result is the same as self_intersections(topology, threads).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <glm/vec3.hpp>

#include "model/self_intersections.hpp"

namespace inkline {

// The arrays the search reads: face_count triangles of corner indices into vertex_count positions
// (read by the constructor only: it copies them).
struct SearchInput {
    const glm::dvec3* positions = nullptr;
    const std::array<std::uint32_t, 3>* faces = nullptr;
    std::size_t face_count = 0;
    std::size_t vertex_count = 0;
};

class EarlySelfIntersections {
public:
    // Starts the search on a thread of its own (and up to threads - 2 more, as the search's size
    // allows).
    EarlySelfIntersections(const SearchInput& input, int threads);
    ~EarlySelfIntersections();  // waits for the search's threads (a load that failed meanwhile)
    EarlySelfIntersections(const EarlySelfIntersections&) = delete;
    EarlySelfIntersections& operator=(const EarlySelfIntersections&) = delete;
    // Takes the search's remaining tasks on the calling thread, waits for the others, and gives
    // the result on `mesh`, whose faces and positions are the ones given. Once only.
    SelfIntersections finish(const MeshTopology& mesh);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace inkline
